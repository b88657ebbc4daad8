"""Screening: the closed-form single-disk design of many disks at once (numpy arrays).

:func:`screen_disks` follows :func:`springcad.design.spring.design_spring` step
by step for disks whose contact radius is given (the synthesis enumerates r_c),
without building the exact profiles:

1. energy bound sigma^2/(6E) x disk volume (the design's first check);
2. torque cap of load-sized tip balls (eq. 6), then N = the largest count whose
   balls and teeth fit around r_c, tried downward as the design does (or the
   given N), each with the rim rule for R_r solved by vectorised bisection (eq. 8);
3. straight limit theta_s (eq. 3); straight flexures with the stiffness width law
   when they reach the deflection, else the serpentine factor s (eq. 4);
4. the serpentine tilt budget: the area ratio of every trial shape of
   :func:`springcad.design.flexure.design_serpentine` at full tilt (lam = 1) on the
   same radial stations. A disk passes when one shape reaches s: the exact first
   test of the serpentine search, so screening never rejects a disk that the full
   design accepts on this ground; what it does not check (the exact neighbour
   clearance, fillet placement, cam tooth coverage) the full design of the
   finalists does;
5. root gap for the wire and the cam web over the bore;
6. mass from the flexure area s x (2/3) w0 L (constant-stress width; the tip web and
   the small beam-theory width correction ignored) plus tip balls and the rim
   annulus less the fastener holes; cam area, EDM cut length (an estimate).

Every number used is one of :mod:`springcad.design.flexure`'s closed forms called
on arrays. Agreement with the full design is tested in
``tests/synthesis/test_synth_screening.py``. Units: N*mm, mm, rad, MPa, kg.
"""

from __future__ import annotations

import math

import numpy as np

from springcad.design import flexure as fx
from springcad.design.cam import OVERTRAVELS
from springcad.design.ring import hole_diameter_mm
from springcad.design.spring import RIM_GAP_RATIO

#: failure codes (0 = passes), in the order the design meets them
(OK, ENERGY, TORQUE_CAP, FLEXURE_FIT, RIM_RULE, STRAIGHT, SERPENTINE, ROOT_GAP, CAM_TOOTH,
 CAM_BORE) = range(10)
REASONS = {ENERGY: "energy_bound", TORQUE_CAP: "torque_cap", FLEXURE_FIT: "flexure_fit",
           RIM_RULE: "rim_rule", STRAIGHT: "straight_limit", SERPENTINE: "serpentine_budget",
           ROOT_GAP: "root_gap",
           CAM_TOOTH: "cam_tooth", CAM_BORE: "cam_bore"}
#: the trial shapes of design_serpentine, widest first so most disks stop at the first
_SHAPES = tuple(sorted(((k, a) for k in (1, 2, 3, 4, 5, 6) for a in (1.0, 2.0, 3.0)),
                       key=lambda ka: (ka[0] != 1, -ka[1], ka[0])))
_U = np.linspace(0.0, 1.0, 241) ** 1.3


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


def _rim_residual(rr, ro, n, rc, w0_of_length):
    return ro - rr - (2 * np.pi * rr / n - w0_of_length(rr - rc)) / RIM_GAP_RATIO


def _rim_root(ro, n, rc, w0_of_length, iterations=48):
    """R_r from the rim rule by bisection on arrays; NaN where there is no bracket."""
    lo = rc * (1 + 1e-6) + 1e-6
    hi = np.array(ro, dtype=float)
    f_lo = _rim_residual(lo, ro, n, rc, w0_of_length)
    f_hi = _rim_residual(hi, ro, n, rc, w0_of_length)
    ok = (f_lo > 0) & (f_hi < 0)
    a, b = np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)
    for _ in range(iterations):
        mid = 0.5 * (a + b)
        pos = _rim_residual(mid, ro, n, rc, w0_of_length) > 0
        a, b = np.where(pos, mid, a), np.where(pos, b, mid)
    return 0.5 * (a + b)


def _trapz_rows(y, x):
    return np.sum(0.5 * (y[:, 1:] + y[:, :-1]) * np.diff(x, axis=1), axis=1)


#: rows per block of the serpentine test: (rows x 241) float temporaries stay below the
#: 128 kB at which glibc mmaps; Dask workers set MALLOC_TRIM_THRESHOLD_, which freezes that
#: threshold, and larger temporaries then cost a page-fault storm (measured 6x slower)
_BLOCK_ROWS = 48


def serpentine_reach(s_req, rc, rr, n, load, z, sigma, clearance_mm, root_zone_mm):
    """Largest area ratio any trial shape of design_serpentine reaches at full tilt (-).

    Evaluated in blocks of rows, shape by shape, only for the rows not yet known to
    reach ``s_req``.
    """
    m = len(rc)
    if m > _BLOCK_ROWS:
        return np.concatenate([
            serpentine_reach(*(a[k:k + _BLOCK_ROWS] for a in (s_req, rc, rr, n, load, z, sigma)),
                             clearance_mm, root_zone_mm[k:k + _BLOCK_ROWS])
            for k in range(0, m, _BLOCK_ROWS)])
    best = np.zeros(m)
    todo = np.ones(m, dtype=bool)
    L = rr - rc
    for k, a in _SHAPES:
        i = np.flatnonzero(todo)
        if i.size == 0:
            break
        r = rc[i, None] + L[i, None] * _U[None, :]
        c = (6.0 * load[i] / (z[i] * sigma[i]))[:, None]
        w_r = np.sqrt(c * (r - rc[i, None]))
        straight_area = _trapz_rows(w_r, r)
        pitch = (2 * np.pi / n[i])[:, None]
        budget = np.sqrt(np.maximum((r * pitch / (w_r + clearance_mm)) ** 2 - 1.0, 0.0))
        q = np.clip((rr[i, None] - r) / root_zone_mm[i, None], 0.0, 1.0)
        h = np.tanh(a * np.sin(k * np.pi * _U))[None, :] / math.tanh(a) * q * q * (3 - 2 * q)
        if k > 1:  # the balanced serpentine: reversed lobes scaled so the root lines up
            pos = _trapz_rows(budget * np.maximum(h, 0) / r, r)
            neg = _trapz_rows(budget * np.minimum(h, 0) / r, r)
            h = np.maximum(h, 0) - (pos / neg)[:, None] * np.minimum(h, 0)
            h = h / np.max(np.abs(h), axis=1, keepdims=True)
        tan_b = budget * h
        g = tan_b / r
        theta = np.concatenate([np.zeros((len(i), 1)),
                                np.cumsum(0.5 * (g[:, 1:] + g[:, :-1]) * np.diff(r, axis=1),
                                          axis=1)], axis=1)
        y = r * np.cos(theta)
        w = np.sqrt(c * np.maximum(y - rc[i, None], 0.0))
        ratio = _trapz_rows(w * np.sqrt(1.0 + tan_b ** 2), r) / straight_area
        best[i] = np.maximum(best[i], ratio)
        todo[i] = ratio < s_req[i]
    return best


def screen_disks(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, n_fixed, *,
                 min_tip_radius_mm: float, manufacturing, hardware,
                 straight_only: bool = False) -> dict[str, np.ndarray]:
    """Closed-form design of disks with given r_c; ``n_fixed < 0``: |n_fixed| fewer flexures
    than the largest count that fits (see :func:`_screen`)."""
    n_fixed = np.asarray(n_fixed, dtype=np.int64)
    args = dict(min_tip_radius_mm=min_tip_radius_mm, manufacturing=manufacturing,
                hardware=hardware, straight_only=straight_only)
    if not np.any(n_fixed < 0):
        return _screen(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, n_fixed, **args)
    first = _screen(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3,
                    np.where(n_fixed < 0, 0, n_fixed), **args)
    fewer = (n_fixed < 0) & (first["code"] == OK)
    if not np.any(fewer):
        return first
    i = np.flatnonzero(fewer)
    sub = [np.broadcast_to(np.asarray(v, dtype=float), n_fixed.shape)[i]
           for v in (K, theta, ro, z, rc, sigma, E, density_kg_per_mm3)]
    second = _screen(*sub, np.maximum(first["n"][i] + n_fixed[i], 2), **args)
    out = {k: v.copy() for k, v in first.items()}
    for k, v in second.items():
        out[k][i] = v
    return out


def _screen(K, theta, ro, z, rc, sigma, E, density_kg_per_mm3, n_fixed, *,
            min_tip_radius_mm: float, manufacturing, hardware,
            straight_only: bool = False) -> dict[str, np.ndarray]:
    """Closed-form design of disks with given r_c (arrays of equal length).

    Args:
        K: disk stiffness (N*mm/rad). theta: disk deflection (rad).
        ro, z, rc: outer radius, thickness, contact radius (mm).
        sigma, E: design stress and Young's modulus (MPa).
        density_kg_per_mm3: material density.
        n_fixed: flexure count, 0 = the largest that fits (as design_spring chooses).
        straight_only: reject disks that need serpentine flexures (``straight_limit``).

    Returns:
        Columns: ``code`` (0 or a failure code of :data:`REASONS`), ``value`` and
        ``limit`` (the numbers of the failed check), and the design values
        ``n``, ``rr``, ``rb``, ``theta_s``, ``s``, ``w0``, ``straight``,
        ``peak_stress_MPa``, ``ring_area_mm2``, ``mass_kg``, ``cam_area_mm2``,
        ``cam_tip_radius_mm``, ``cam_root_radius_mm``, ``cut_ring_mm``, ``cut_cam_mm``.
    """
    K, theta, ro, z, rc, sigma, E = (np.asarray(v, dtype=float) for v in (K, theta, ro, z, rc, sigma, E))
    n_fixed = np.asarray(n_fixed, dtype=np.int64)
    m = len(K)
    nan = np.full(m, np.nan)
    code = np.zeros(m, dtype=np.int64)
    value, limit = nan.copy(), nan.copy()
    mfg, rw = manufacturing, manufacturing.min_inside_radius_mm

    def fail(mask, c, v, lim):
        mask = mask & (code == OK)
        code[mask] = c
        value[mask] = np.broadcast_to(v, (m,))[mask]
        limit[mask] = np.broadcast_to(lim, (m,))[mask]

    # 1. energy bound (J)
    need = 0.5 * K * theta ** 2 * 1e-3
    bound = fx.energy_bound_J_per_mm3(sigma, E) * np.pi * ro ** 2 * z
    fail(need > bound, ENERGY, need, bound)
    # 2. torque cap and flexure count
    peak = K * theta
    cap = fx.torque_cap_Nmm(rc, z, sigma)
    fail((n_fixed == 0) & (peak > cap), TORQUE_CAP, peak, cap)
    n = np.where(n_fixed > 0, n_fixed, _nmax(min_tip_radius_mm, rc))
    rr = nan.copy()
    active = code == OK
    while np.any(active):
        i = np.flatnonzero(active)
        load = fx.tip_load_N(K[i], theta[i], n[i], rc[i])
        rb_i = np.maximum(min_tip_radius_mm, fx.tip_ball_required_radius_mm(load, z[i], sigma[i]))
        c_i = 6 * load / (z[i] * sigma[i])
        rr_i = _rim_root(ro[i], n[i], rc[i], lambda L, c=c_i: np.sqrt(c * np.maximum(L, 0.0)))
        rim_bad = np.isnan(rr_i)
        fits = n[i] <= _nmax(rb_i, rc[i])
        sel = np.zeros(m, dtype=bool)
        sel[i[rim_bad]] = True
        fail(sel, RIM_RULE, n.astype(float), ro)
        done = ~rim_bad & fits
        rr[i[done]] = rr_i[done]
        retry = ~rim_bad & ~fits
        fixed = n_fixed[i] > 0
        sel[:] = False
        sel[i[retry & fixed]] = True
        fail(sel & (peak > cap), TORQUE_CAP, peak, cap)
        fail(sel, FLEXURE_FIT, n.astype(float), _nmax(np.maximum(
            min_tip_radius_mm, fx.tip_ball_required_radius_mm(
                fx.tip_load_N(K, theta, n, rc), z, sigma)), rc).astype(float))
        free = i[retry & ~fixed]
        n[free] -= 1
        sel[:] = False
        sel[free[n[free] < 2]] = True
        fail(sel, TORQUE_CAP, peak, cap)
        active = (code == OK) & np.isnan(rr)
    good = code == OK
    load = fx.tip_load_N(K, theta, n, rc)
    rb_req = fx.tip_ball_required_radius_mm(load, z, sigma)
    rb = np.maximum(min_tip_radius_mm, rb_req)
    L = rr - rc
    theta_s = fx.straight_limit_rad(n, z, sigma, L, E, K, rc)
    # 3. straight flexures with the stiffness width law where they reach the deflection
    straight = good & (theta_s >= theta)
    w0 = np.sqrt(6 * load * L / (z * sigma))
    s = np.where(good, (theta / theta_s) ** 1.5, np.nan)
    if np.any(straight):
        i = np.flatnonzero(straight)
        coef = 8.0 * K[i] / (n[i] * rc[i] ** 2 * E[i] * z[i])
        rr_s = _rim_root(ro[i], n[i], rc[i], lambda Ls, c=coef: np.cbrt(c * Ls ** 3))
        sel = np.zeros(m, dtype=bool)
        sel[i[np.isnan(rr_s)]] = True
        fail(sel, RIM_RULE, n.astype(float), ro)
        th2 = fx.straight_limit_rad(n[i], z[i], sigma[i], rr_s - rc[i], E[i], K[i], rc[i])
        keep = ~np.isnan(rr_s) & (th2 >= theta[i])
        j = i[keep]
        rr[j], L[j], theta_s[j] = rr_s[keep], rr_s[keep] - rc[j], th2[keep]
        w0[j] = np.cbrt(coef[keep] * L[j] ** 3)
        s[j] = 1.0
        straight[:] = False
        straight[j] = True
    if straight_only:
        fail(~straight, STRAIGHT, theta, theta_s)
    # 4. serpentine tilt budget
    serp = (code == OK) & ~straight
    if np.any(serp):
        i = np.flatnonzero(serp)
        reach = serpentine_reach(s[i], rc[i], rr[i], n[i], load[i], z[i], sigma[i],
                                 max(mfg.min_slot_width_mm, 2 * rw), 2.0 * (ro[i] - rr[i]))
        sel = np.zeros(m, dtype=bool)
        sel[i[reach < s[i]]] = True
        val = np.full(m, np.nan)
        val[i] = reach
        fail(sel, SERPENTINE, s, val)
    # 5. root gap and cam web
    gap = 2 * np.pi * rr / n - w0
    fail(gap <= 2 * rw, ROOT_GAP, gap, np.full(m, 2 * rw))
    tooth = cam_tooth_width_mm(rc, rb + mfg.w_gap_mm, n, theta)
    fail(tooth < mfg.min_web_mm, CAM_TOOTH, tooth, np.full(m, mfg.min_web_mm))
    cam_root = rc - (rb + mfg.w_gap_mm)
    web = cam_root - 0.5 * hardware.shaft_diameter_mm
    fail(web < mfg.min_web_mm, CAM_BORE, web, np.full(m, mfg.min_web_mm))
    # 6. areas, mass, cut length
    peak_stress = np.where(straight, 6 * load * L / (z * w0 ** 2), sigma)
    holes = min(hardware.fastener_count, 10 ** 9) * np.ones(m)
    holes = np.minimum(holes, n)
    hole_d = hole_diameter_mm(hardware) if hardware.fastener_count else 0.0
    ring_area = (n * (s * (2.0 / 3.0) * w0 * L + np.pi * rb ** 2)
                 + np.pi * (ro ** 2 - rr ** 2) - holes * np.pi * hole_d ** 2 / 4)
    cam_tip = rc + rb + mfg.w_gap_mm
    ball_share = np.clip(n * 2 * (rb + mfg.w_gap_mm) / (2 * np.pi * rc), 0.0, 1.0)
    bore = 0.5 * hardware.shaft_diameter_mm
    cam_area = (np.pi * cam_root ** 2 + np.pi * (cam_tip ** 2 - cam_root ** 2) * (1 - ball_share)
                - np.pi * bore ** 2)
    cut_ring = (n * (2 * s * L + 1.3 * np.pi * rb) + np.maximum(2 * np.pi * rr - n * w0, 0.0)
                + 2 * np.pi * ro + holes * np.pi * hole_d)
    cut_cam = 2 * np.pi * rc + n * 2 * (cam_tip - cam_root) + 2 * np.pi * bore
    ok = code == OK
    return {"code": code, "value": value, "limit": limit, "n": n, "rr": rr, "rb": rb,
            "rb_req": rb_req, "theta_s": theta_s, "s": s, "w0": w0, "straight": straight,
            "peak_stress_MPa": peak_stress, "ring_area_mm2": np.where(ok, ring_area, np.nan),
            "mass_kg": np.where(ok, ring_area * z * density_kg_per_mm3, np.nan),
            "cam_area_mm2": cam_area, "cam_tip_radius_mm": cam_tip, "cam_root_radius_mm": cam_root,
            "hole_diameter_mm": np.full(m, hole_d), "n_holes": holes,
            "cut_ring_mm": cut_ring, "cut_cam_mm": cut_cam}
