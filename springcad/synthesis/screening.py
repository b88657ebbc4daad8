"""Screening: the closed-form single-disk design of many disks at once (numpy arrays).

:func:`screen_disks` follows :func:`springcad.design.search.design_spring` step
by step for disks whose contact radius is given (the synthesis enumerates r_c),
without building the exact profiles:

1. energy bound sigma^2/(6E) x the annulus r_c..R_r,max (the design's first check);
2. torque cap of load-sized tip balls (eq. 6), then N = the largest count whose
   balls and teeth fit around r_c, tried downward as the design does (or the
   given N), each with the rim rule for R_r solved by vectorised bisection (eq. 8);
3. straight limit theta_s (eq. 3); then the flexure shapes the request tries, each
   sizing the rows still open on arrays (:meth:`~springcad.design.shapes.base.FlexureShape.screen_size`,
   as the design asks the shape registry): straight flexures with the stiffness width
   law when they reach the deflection, else the serpentine factor s (eq. 4);
4. the serpentine tilt budget: the area ratio of every trial shape of
   :func:`springcad.design.flexure.design_serpentine` at full tilt (lam = 1) on the
   same radial stations. A disk passes when one shape reaches s: the exact first
   test of the serpentine search, so screening never rejects a disk that the full
   design accepts on this ground;
5. root gap for the wire and the cam web over the bore;
6. the serpentine the design would choose (:func:`~springcad.design.shapes.serpentine_screen.serpentine_centrelines`:
   the tilt factor of every shape that reaches s, the wire's concave edge radius,
   the smallest curved-beam measure) and the *predicted peak stress* of the real
   geometry with the root flare the design would choose
   (:func:`~springcad.synthesis.peak.predict_peaks`: the design's FEA-calibrated
   stress model on arrays);
7. with ``allowed_peak_MPa`` (yield / required margin): the design's stress passes.
   While the predicted peak exceeds the allowed one, the beam stress is lowered by
   allowed / peak x 0.995 and the disk screened again with the same N
   (:func:`springcad.design.search.design_spring` does this with the N the synthesis
   writes into the job), at most ``STRESS_PASSES`` designs; a disk that no pass
   brings under the allowed peak fails on ``yield_margin`` (or ``fatigue_margin``);
8. the minimum webs: a disk whose beam stiffness the tip webs hold out of the FEA
   correction's reach fails on ``web_stiffness``
   (:func:`springcad.design.resize.web_stiffness_excess`, as the design's
   :func:`~springcad.design.resize.stiffness_out_of_reach`);
9. mass from the flexure area integral w ds of that geometry plus tip balls and the
   rim annulus less the fastener holes; cam area, EDM cut length (an estimate).

What screening does not check (the exact neighbour clearance of the serpentine and
of each root flare, the fillet and cam profiles) the full design of the finalists does.
Every number used is one of :mod:`springcad.design.flexure`'s closed forms called
on arrays. Agreement with the full design is tested in
``tests/synthesis/test_synth_screening.py``. Units: N*mm, mm, rad, MPa, kg.
"""

from __future__ import annotations

import numpy as np

from springcad.design import flexure as fx
from springcad.design import shapes
from springcad.design.cam import OVERTRAVELS
from springcad.design.ring import hole_diameter_mm
from springcad.config.consistency import MIN_RIM_FRACTION, min_rim_mm
from springcad.design.hardware import rim_spacer_rim_mm
from springcad.design.contact_stress import tip_radius_window_mm
from springcad.design.resize import web_stiffness_excess
from springcad.design.sizing import STRESS_PASSES
from springcad.design.shapes.screen import ScreenRows, ScreenSizing, rim_root_radius_rows
from springcad.design.shapes.serpentine_screen import U
from springcad.synthesis.peak import predict_peaks
from springcad.units import J_PER_NMM

__all__ = ["REASONS", "cam_tooth_width_mm", "screen_disks", "screened_shapes"]

#: failure codes (0 = passes), in the order the design meets them
(OK, ENERGY, TORQUE_CAP, FLEXURE_FIT, RIM_RULE, STRAIGHT, SERPENTINE, ROOT_GAP, CAM_TOOTH,
 CAM_BORE, SERP_SHAPE, ROOT_FILLET, YIELD, FATIGUE, TIP_BALLS, WEB_STIFFNESS) = range(16)
REASONS = {ENERGY: "energy_bound", TORQUE_CAP: "torque_cap", FLEXURE_FIT: "flexure_fit",
           RIM_RULE: "rim_rule", STRAIGHT: "straight_limit", SERPENTINE: "serpentine_budget",
           ROOT_GAP: "root_gap", CAM_TOOTH: "cam_tooth", CAM_BORE: "cam_bore",
           SERP_SHAPE: "serpentine_shape", ROOT_FILLET: "root_fillet", YIELD: "yield_margin",
           FATIGUE: "fatigue_margin", TIP_BALLS: "tip_ball_fit",
           WEB_STIFFNESS: "web_stiffness"}
#: failure code by reason name (a shape's screen names its failures)
CODES = {reason: code for code, reason in REASONS.items()}
def _nmax(rb, rc):
    """Eq. 6 on arrays: floor(pi hypot(r_b, r_c) / (2 r_b))."""
    return np.floor(np.pi * np.hypot(rb, rc) / (2.0 * rb)).astype(np.int64)


def cam_tooth_width_mm(rc, rho, n, theta):
    """Widest cam tooth tip over the overtravels the cam design tries (mm; < 0: none).

    The flank ends at p(psi_end) = R(psi_end) (r_c psi_end - rho, r_c) with
    psi_end = rho / r_c + f theta; the tip arc of radius |p| runs from its polar
    angle phi to pi - phi + 2 pi / N (``cam._unit``), so the tip is
    |p| (pi - 2 phi + 2 pi / N) wide.
    """
    best = np.full(np.shape(rc), -np.inf)
    for f in OVERTRAVELS:
        psi = rho / rc + f * theta
        x = rc * psi - rho
        phi = psi + np.arctan2(rc, x)
        best = np.maximum(best, np.hypot(x, rc) * (np.pi - 2 * phi + 2 * np.pi / n))
    return best


def screened_shapes(flexure: str = shapes.AUTO) -> list:
    """The shapes a ``flexure`` request tries (:func:`springcad.design.shapes.tried`) that
    have a synthesis screen, in order."""
    return [shape for shape in shapes.tried(flexure) if shape.screens]


def _spread(m: int, rows, values) -> np.ndarray:
    """A column of ``m`` NaNs with ``values`` at ``rows``."""
    out = np.full(m, np.nan)
    out[rows] = values
    return out


def screen_disks(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, n_fixed, *,
                 min_tip_radius_mm: float, manufacturing, hardware,
                 straight_only: bool = False, allowed_peak_MPa=None,
                 fatigue_limited=None, tip_radius_mm: float | None = None,
                 contact=None, rim_pinned=False) -> dict[str, np.ndarray]:
    """Closed-form design of disks with given r_c, with the design's stress passes.

    Args:
        K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, straight_only, tip_radius_mm:
            see :func:`_screen`.
        n_fixed: flexure count; 0: the largest that fits; < 0: |n_fixed| fewer than that.
        allowed_peak_MPa: largest predicted peak each disk may carry (MPa): yield strength
            / required margin. None: no stress passes (the first design is returned, its
            predicted peak in ``peak_stress_MPa``).
        fatigue_limited: per disk, whether the allowed peak comes from the fatigue margin
            (the failure is then ``fatigue_margin``, else ``yield_margin``).
        rim_pinned: per disk (or one bool), whether its stack pins it rim to rim: its rim
            then keeps the rim spacer's room too, as the design's
            :func:`~springcad.design.job.shared_rim_limit_mm`.
        contact: (Poisson's ratio, allowed contact von Mises MPa), scalars or per disk: the balls are
            sized for their Hertz contact at full deflection as well as bending, as the
            design's :func:`springcad.design.layout.tip_ball`; None: bending only.

    Returns:
        The columns of :func:`_screen` for the last pass, with ``derating`` (beam stress
        over ``sigma``) and ``derated_code`` (the check that failed at the lowered beam
        stress of a ``yield_margin`` failure, 0 if none).
    """
    n_fixed = np.asarray(n_fixed, dtype=np.int64)
    m = len(n_fixed)
    args = dict(min_tip_radius_mm=min_tip_radius_mm, manufacturing=manufacturing,
                hardware=hardware, straight_only=straight_only, tip_radius_mm=tip_radius_mm,
                contact=None if contact is None else
                tuple(np.broadcast_to(np.asarray(c, dtype=float), (m,)) for c in contact))
    full = [np.broadcast_to(np.asarray(v, dtype=float), (m,))
            for v in (K, theta, ro, z, rc, sigma, E, density_kg_per_mm3)]

    pinned = np.broadcast_to(np.asarray(rim_pinned, dtype=bool), (m,))

    def screen(rows, n_rows, sigma_rows, layout_only=False):
        sub = [v[rows] for v in full]
        sub[5] = sigma_rows
        rows_args = args if contact is None else {
            **args, "contact": tuple(c[rows] for c in args["contact"])}
        return _screen(*sub, n_rows, **rows_args, layout_only=layout_only,
                       rim_pinned=pinned[rows])

    everything = np.arange(m)
    n_run = n_fixed.clip(0)
    fewer = np.flatnonzero(n_fixed < 0)
    if fewer.size:
        # the largest count that fits (layout only), then |n_fixed| fewer
        first = screen(fewer, n_run[fewer], full[5][fewer], layout_only=True)
        sel = first["code"] == OK
        n_run[fewer[sel]] = np.maximum(first["n"][sel] + n_fixed[fewer[sel]], 2)
    out = screen(everything, n_run, full[5])
    out["derating"] = np.ones(m)
    out["derated_code"] = np.zeros(m, dtype=np.int64)
    if allowed_peak_MPa is None:
        return _web_room(out, full[0])
    allowed = np.broadcast_to(np.asarray(allowed_peak_MPa, dtype=float), (m,))
    stress_code = np.where(np.broadcast_to(np.asarray(
        False if fatigue_limited is None else fatigue_limited, dtype=bool), (m,)), FATIGUE, YIELD)
    # design_spring: accepted when yield / peak >= required (1 - 1e-3)
    over = (out["code"] == OK) & (out["peak_stress_MPa"] > allowed / (1 - 1e-3))
    for _ in range(STRESS_PASSES - 1):
        i = np.flatnonzero(over)
        if i.size == 0:
            break
        derating = out["derating"][i] * allowed[i] / out["peak_stress_MPa"][i] * 0.995
        again = screen(i, out["n"][i], full[5][i] * derating)
        bad = again["code"] != OK
        # no beam stress keeps the margin: the design stops with the last peak it predicted
        out["code"][i[bad]] = stress_code[i[bad]]
        out["value"][i[bad]] = out["peak_stress_MPa"][i[bad]]
        out["limit"][i[bad]] = allowed[i[bad]]
        out["derated_code"][i[bad]] = again["code"][bad]
        good = np.flatnonzero(~bad)
        _merge(out, i[good], {k: v[good] for k, v in again.items()})
        out["derating"][i[good]] = derating[good]
        over = (out["code"] == OK) & (out["peak_stress_MPa"] > allowed / (1 - 1e-3))
    i = np.flatnonzero(over)
    out["code"][i] = stress_code[i]
    out["value"][i] = out["peak_stress_MPa"][i]
    out["limit"][i] = allowed[i]
    return _web_room(out, full[0])


def _web_room(out: dict, K) -> dict:
    """``out`` with the disks whose minimum webs hold the stiffness out of the FEA
    correction's reach failed on ``web_stiffness`` (the design's
    :func:`~springcad.design.resize.stiffness_out_of_reach`, after its stress passes)."""
    if "narrow_stiffness_Nmm_per_rad" not in out:  # layout only
        return out
    excess = web_stiffness_excess(out["stiffness_Nmm_per_rad"],
                                  out["narrow_stiffness_Nmm_per_rad"], K)
    i = np.flatnonzero((out["code"] == OK) & (excess > 1.0))
    out["code"][i] = WEB_STIFFNESS
    out["value"][i] = excess[i]
    out["limit"][i] = 1.0
    return out


def _merge(out: dict, rows, cols: dict) -> None:
    """Overwrite ``rows`` of every column of ``out`` with ``cols`` (same keys)."""
    for k, v in cols.items():
        out[k][rows] = v


def _screen(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, n_fixed, *,
            min_tip_radius_mm: float, manufacturing, hardware,
            straight_only: bool = False, layout_only: bool = False,
            tip_radius_mm: float | None = None, contact=None,
            rim_pinned=False) -> dict[str, np.ndarray]:
    """Closed-form design of disks with given r_c (arrays of equal length).

    Args:
        K: disk stiffness (N*mm/rad). theta: disk deflection (rad).
        ro, z, rc: outer radius, thickness, contact radius (mm).
        sigma, E: design stress and Young's modulus (MPa).
        density_kg_per_mm3: material density.
        n_fixed: flexure count, 0 = the largest that fits (as design_spring chooses).
        straight_only: reject disks that need serpentine flexures (``straight_limit``).
        layout_only: stop after the layout checks 1-5 (N, R_r, flexure kind; no
            centreline, stress or mass).
        tip_radius_mm: fixed tip-ball radius (mm), as the design's ``tip_radius_mm``
            (as-built balls): no ball sizing and no torque-cap rule; the tip-neck stress
            of that ball is checked by the calibrated peak prediction (step 6) instead.
            None: balls sized for the peak load, at least ``min_tip_radius_mm``.

    Returns:
        Columns: ``code`` (0 or a failure code of :data:`REASONS`), ``value`` and
        ``limit`` (the numbers of the failed check), and the design values
        ``n``, ``rr``, ``rb``, ``theta_s``, ``s``, ``w0``, ``straight``,
        ``beam_stress_MPa`` (the width law's), ``peak_stress_MPa`` (predicted, with
        ``flank_MPa``, ``root_MPa``, ``neck_MPa``, ``peak_region`` and the chosen
        ``root_flare``, ``width_scale``), ``stiffness_Nmm_per_rad`` (beam theory of the
        built widths), ``root_fillet_mm``, ``ring_area_mm2``,
        ``mass_kg``, ``cam_area_mm2``, ``cam_tip_radius_mm``, ``cam_root_radius_mm``,
        ``cut_ring_mm``, ``cut_cam_mm``.
    """
    K, theta, ro, z, rc, sigma, E = (np.asarray(v, dtype=float) for v in (K, theta, ro, z, rc, sigma, E))
    n_fixed = np.asarray(n_fixed, dtype=np.int64)
    m = len(K)
    nan = np.full(m, np.nan)
    code = np.zeros(m, dtype=np.int64)
    value, limit = nan.copy(), nan.copy()
    mfg, rw = manufacturing, manufacturing.min_inside_radius_mm
    clearance = max(mfg.min_slot_width_mm, 2 * rw)

    def ball(load, z_, sigma_, rows=slice(None)):
        """Tip-ball radius (mm) of disks with these tip loads (N): bending and, with
        ``contact``, Hertz contact at full deflection on the flank radius the ball leaves
        (the design's window, :func:`tip_radius_window_mm`); ``inf`` outside the window."""
        if tip_radius_mm is not None:
            return np.full(np.shape(load), float(tip_radius_mm))
        r = np.maximum(min_tip_radius_mm, fx.tip_ball_required_radius_mm(load, z_, sigma_))
        if contact is None:
            return r
        lo, hi = tip_radius_window_mm(load, rc[rows], mfg.w_gap_mm, theta[rows], z_, E[rows],
                                      contact[0][rows], contact[1][rows],
                                      mfg.t_spring_mm + mfg.t_shaft_mm)
        r = np.maximum(r, lo)
        return np.where(r <= hi * (1 + 1e-9), r, np.inf)

    capped = tip_radius_mm is None
    # the rim keeps room for its holes, and on a disk pinned rim to rim (the design's
    # shared_rim_limit_mm) for the rim spacer's holes and worst-case webs too
    spacer = rim_spacer_rim_mm(hardware, manufacturing) if hardware.fastener_count else 0.0
    rim_min = np.maximum(np.maximum(min_rim_mm(0.0, manufacturing, hardware),
                                    np.where(rim_pinned, spacer, 0.0)), MIN_RIM_FRACTION * ro)

    def fail(mask, c, v, lim):
        mask = mask & (code == OK)
        code[mask] = c
        value[mask] = np.broadcast_to(v, (m,))[mask]
        limit[mask] = np.broadcast_to(lim, (m,))[mask]

    # 1. energy bound (J): the annulus between the row's contact radius and the largest
    # root radius the rim allows, as the design's with that contact radius
    need = 0.5 * K * theta ** 2 * J_PER_NMM
    bound = fx.energy_bound_J_per_mm3(sigma, E) * np.pi * np.maximum(
        (ro - rim_min) ** 2 - rc ** 2, 0.0) * z
    fail(need > bound, ENERGY, need, bound)
    # 2. torque cap and flexure count
    peak = K * theta
    cap = fx.torque_cap_Nmm(rc, z, sigma)
    fail(capped & (n_fixed == 0) & (peak > cap), TORQUE_CAP, peak, cap)
    n = np.where(n_fixed > 0, n_fixed, _nmax(tip_radius_mm or min_tip_radius_mm, rc))
    rr = nan.copy()
    active = code == OK
    while np.any(active):
        i = np.flatnonzero(active)
        load = fx.tip_load_N(K[i], theta[i], n[i], rc[i])
        rb_i = ball(load, z[i], sigma[i], i)
        c_i = 6 * load / (z[i] * sigma[i])
        rr_i = np.minimum(rim_root_radius_rows(ro[i], n[i], rc[i],
                                               lambda L, c=c_i: np.sqrt(c * np.maximum(L, 0.0))),
                          ro[i] - rim_min[i])  # the rim keeps room for its holes (layout_at)
        rim_bad = np.isnan(rr_i) | (rr_i <= rc[i])
        fits = np.isfinite(rb_i) & (n[i] <= _nmax(np.where(np.isfinite(rb_i), rb_i, 1.0), rc[i]))
        sel = np.zeros(m, dtype=bool)
        sel[i[rim_bad]] = True
        fail(sel, RIM_RULE, n.astype(float), ro)
        done = ~rim_bad & fits
        rr[i[done]] = rr_i[done]
        retry = ~rim_bad & ~fits
        fixed = n_fixed[i] > 0
        sel[:] = False
        sel[i[retry & fixed]] = True
        fail(sel & capped & (peak > cap), TORQUE_CAP, peak, cap)
        fail(sel, FLEXURE_FIT, n.astype(float),
             _nmax(np.minimum(ball(fx.tip_load_N(K, theta, n, rc), z, sigma), 1e9),
                   rc).astype(float))
        free = i[retry & ~fixed]
        n[free] -= 1
        sel[:] = False
        sel[free[n[free] < 2]] = True
        if sel.any():
            # no N >= 2 fits the balls sized for its load (the torque cap passed above):
            # value 2 flexures, limit the balls that fit at N = 2 (0: no ball radius
            # carries the contact at full deflection)
            rb2 = ball(fx.tip_load_N(K, theta, np.full(m, 2), rc), z, sigma)
            fit2 = np.where(np.isfinite(rb2), _nmax(np.minimum(rb2, 1e9), rc), 0)
            fail(sel, TIP_BALLS, np.full(m, 2.0), fit2.astype(float))
        active = (code == OK) & np.isnan(rr)
    good = code == OK
    load = fx.tip_load_N(K, theta, n, rc)
    rb_req = fx.tip_ball_required_radius_mm(load, z, sigma)
    rb = ball(load, z, sigma)
    L = rr - rc
    theta_s = fx.straight_limit_rad(n, z, sigma, L, E, K, rc)
    w0 = np.sqrt(6 * load * L / (z * sigma))
    s = np.where(good, (theta / theta_s) ** 1.5, np.nan)
    coef, beam_stress = 6 * load / (z * sigma), sigma.copy()
    # 3-4. the flexure shapes the request tries, in order (straight flexures with the
    # stiffness width law where they reach the deflection, then serpentines within the
    # tilt budget): each sizes the open rows it takes, as the design's shape registry does
    rows = ScreenRows(K, theta, ro, z, rc, sigma, E, n, load, rr.copy(), theta_s.copy(),
                      ro - rim_min, clearance, rw)
    shape_of = np.full(m, -1)
    sizings = []
    for k, shape in enumerate(screened_shapes("straight" if straight_only else shapes.AUTO)):
        i = np.flatnonzero((code == OK) & (shape_of < 0))
        if i.size == 0:
            break
        size = shape.screen_size(rows.take(i))
        for reason, mask, v, lim in size.failures:
            sel = np.zeros(m, dtype=bool)
            sel[i[mask]] = True
            fail(sel, CODES[reason], _spread(m, i, v), _spread(m, i, lim))
        j, t = i[size.taken], size.taken
        shape_of[j] = k
        rr[j], theta_s[j], w0[j], s[j] = size.rr[t], size.theta_s[t], size.w0[t], size.s[t]
        coef[j], beam_stress[j] = size.width_coef[t], size.beam_stress_MPa[t]
        sizings.append((shape, j, size))
    L = rr - rc
    straight = np.isin(shape_of, [k for k, (shape, _, _) in enumerate(sizings)
                                  if shape.name == "straight"])
    fail(shape_of < 0, STRAIGHT, theta, theta_s)  # no shape the request tries reaches
    # 5. root gap and cam web
    gap = 2 * np.pi * rr / n - w0
    fail(gap <= 2 * rw, ROOT_GAP, gap, np.full(m, 2 * rw))
    tooth = cam_tooth_width_mm(rc, rb + mfg.w_gap_mm, n, theta)
    fail(tooth < mfg.min_web_mm, CAM_TOOTH, tooth, np.full(m, mfg.min_web_mm))
    cam_root = rc - (rb + mfg.w_gap_mm)
    web = cam_root - 0.5 * hardware.shaft_diameter_mm
    fail(web < mfg.min_web_mm, CAM_BORE, web, np.full(m, mfg.min_web_mm))
    if layout_only:
        return {"code": code, "value": value, "limit": limit, "n": n, "rr": rr}
    # 6. the centreline the design would build, then the predicted peak of the real geometry
    t_rim = ro - rr
    root_fillet = np.maximum(np.minimum(0.5 * t_rim, gap / 3.0), rw)
    neck_fillet = np.maximum(0.5 * rb, rw)
    x = np.zeros((m, U.size))
    y = np.where(np.isfinite(L), rc, 0.0)[:, None] + np.where(np.isfinite(L), L, 0.0)[:, None] * U
    slope, kappa = np.zeros_like(x), np.zeros_like(x)
    for shape, j, _ in sizings:
        i = j[code[j] == OK]
        if i.size == 0:
            continue
        line = shape.screen_centreline(rows.take(i), ScreenSizing(
            np.ones(i.size, dtype=bool), rr[i], theta_s[i], w0[i], s[i], coef[i],
            beam_stress[i]))
        if line is None:  # the radial straight line set above
            continue
        for reason, mask, v, lim in line.failures:
            sel = np.zeros(m, dtype=bool)
            sel[i[mask]] = True
            fail(sel, CODES[reason], _spread(m, i, v), _spread(m, i, lim))
        x[i], y[i], slope[i], kappa[i] = line.x, line.y, line.slope, line.kappa
    ok = code == OK
    pk = {k: np.full(m, np.nan) for k in ("flank_MPa", "root_MPa", "neck_MPa", "peak_MPa",
                                         "flare", "width_scale", "flexure_area_mm2",
                                         "stiffness_Nmm_per_rad", "narrow_stiffness_Nmm_per_rad")}
    pk["region"] = np.zeros(m, dtype=np.int64)
    if np.any(ok):
        i = np.flatnonzero(ok)
        res = predict_peaks(x[i], y[i], slope[i], kappa[i], rc=rc[i], rr=rr[i], ro=ro[i], n=n[i],
                            load=load[i], z=z[i], E=E[i], K=K[i], width_coef=coef[i], rb=rb[i],
                            root_fillet_mm=root_fillet[i], neck_fillet_mm=neck_fillet[i],
                            manufacturing=mfg)
        for k in pk:
            pk[k][i] = res[k]
        sel = np.zeros(m, dtype=bool)
        sel[i[~res["ok"]]] = True
        fail(sel, ROOT_FILLET, root_fillet, t_rim)
    # 7. areas, mass, cut length
    ok = code == OK
    holes = min(hardware.fastener_count, 10 ** 9) * np.ones(m)
    holes = np.minimum(holes, n)
    hole_d = hole_diameter_mm(hardware) if hardware.fastener_count else 0.0
    ring_area = (n * (pk["flexure_area_mm2"] + np.pi * rb ** 2)
                 + np.pi * (ro ** 2 - rr ** 2) - holes * np.pi * hole_d ** 2 / 4)
    cam_tip = rc + rb + mfg.w_gap_mm
    ball_share = np.clip(n * 2 * (rb + mfg.w_gap_mm) / (2 * np.pi * rc), 0.0, 1.0)
    bore = 0.5 * hardware.shaft_diameter_mm
    cam_area = (np.pi * cam_root ** 2 + np.pi * (cam_tip ** 2 - cam_root ** 2) * (1 - ball_share)
                - np.pi * bore ** 2)
    cut_ring = (n * (2 * s * L + 1.3 * np.pi * rb) + np.maximum(2 * np.pi * rr - n * w0, 0.0)
                + 2 * np.pi * ro + holes * np.pi * hole_d)
    cut_cam = 2 * np.pi * rc + n * 2 * (cam_tip - cam_root) + 2 * np.pi * bore
    return {"code": code, "value": value, "limit": limit, "n": n, "rr": rr, "rb": rb,
            "rb_req": rb_req, "theta_s": theta_s, "s": s, "w0": w0, "straight": straight,
            "beam_stress_MPa": beam_stress, "peak_stress_MPa": pk["peak_MPa"],
            "flank_MPa": pk["flank_MPa"], "root_MPa": pk["root_MPa"], "neck_MPa": pk["neck_MPa"],
            "peak_region": pk["region"], "root_flare": pk["flare"],
            "width_scale": pk["width_scale"], "stiffness_Nmm_per_rad": pk["stiffness_Nmm_per_rad"],
            "narrow_stiffness_Nmm_per_rad": pk["narrow_stiffness_Nmm_per_rad"],
            "root_fillet_mm": root_fillet,
            "ring_area_mm2": np.where(ok, ring_area, np.nan),
            "mass_kg": np.where(ok, ring_area * z * density_kg_per_mm3, np.nan),
            "cam_area_mm2": cam_area, "cam_tip_radius_mm": cam_tip, "cam_root_radius_mm": cam_root,
            "hole_diameter_mm": np.full(m, hole_d), "n_holes": holes,
            "cut_ring_mm": cut_ring, "cut_cam_mm": cut_cam}
