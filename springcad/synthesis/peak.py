"""Predicted peak stress of screened disks: the design's stress model on arrays.

:func:`springcad.design.search.design_spring` keeps the *predicted* peak of the
real geometry (:mod:`springcad.design.stress`: the Winkler-Bach curved-beam flank,
the root fillet and the tip-neck fillet, calibrated to FEA) below yield / margin,
choosing the root flare with the lowest peak. :func:`predict_peaks` evaluates the
same model on many screened disks at once, on the centreline stations of
:mod:`springcad.design.shapes.serpentine_screen` (or straight flexures):

1. the flexure widths w = web-floor(scale x w_law(y) x flare(y)): the scale brought
   onto the target stiffness (Castigliano) in two passes without a flare, then, for each
   root flare of :data:`springcad.design.sizing.ROOT_FLARES`, three passes onto that
   stiffness, exactly as the design steps (the tip web does not scale, so where it is a
   large part of the flexure the passes stop short of the target, as the design's do);
2. nominal stress 6 F (y - r_c) / (z w^2) times the Winkler factors of the centreline
   curvature on both edges (:func:`springcad.design.stress.winkler_factors`);
3. the root-fillet and neck-fillet tangent stations on each edge (fillet circle
   tangent to the edge and to the rim circle or the tip ball), the root model
   a (w / r_f)^b k^c there, the flank maximum below the root station times the flexure
   shape's own factor and (z / w_root)^e term (straight or curved rows), the neck nominal;
   all at the target stiffness's load K theta / (N r_c), as the design
   (:func:`springcad.design.stress.tip_load_N`);
4. the flare with the lowest peak, a larger flare only when it gains more than
   :data:`springcad.design.sizing.FLARE_GAIN`.

A flare whose profile the design cannot build (neighbouring root fillets overlapping,
clearance or edge radius broken: the design falls back to the next flare) is skipped
the same way; the clearance by its perpendicular-gap estimate. Agreement with the full
design is tested in ``tests/synthesis/test_synth_peak.py``. Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from springcad.design import flexure as fx
from springcad.design import stress
from springcad.design.resize import ROOM_SCALE
from springcad.design.sizing import FLARE_GAIN, ROOT_FLARES
from springcad.design.shapes.serpentine_screen import U, blocks, trapz_rows

#: peak regions, in the order of :class:`springcad.design.stress.StressPrediction`
REGIONS = ("flexure flank", "root fillet", "tip-neck fillet")
#: width-scale passes: onto the target stiffness without a flare (_design_at), then of
#: each flare onto that stiffness (_with_flare)
_DESIGN_PASSES, _FLARE_PASSES = 2, 3


def web_floor_mm(width_mm, min_web_mm: float):
    """The flexure width with the tip web kept (mm): the smooth maximum of
    :meth:`springcad.design.spring.SpringDesign.width_mm` (web 1.002 x min_web_mm,
    blend 0.1 x web)."""
    web = 1.002 * min_web_mm
    return 0.5 * (width_mm + web + np.sqrt((width_mm - web) ** 2 + (0.1 * web) ** 2))


def _edge(x, y, slope, w, side, along=U):
    """Points of one flexure edge and its unit normal towards the void (rows x stations,
    x and y each); ``along``: the parameter of the stations (only its direction matters)."""
    norm = np.sqrt(1.0 + slope ** 2)
    px = x + side * 0.5 * w / norm
    py = y - side * 0.5 * w * slope / norm
    tx, ty = np.gradient(px, along, axis=1), np.gradient(py, along, axis=1)
    t = np.hypot(tx, ty)
    return px, py, side * ty / t, -side * tx / t


def _interp(a, j, frac):
    """a[row, j] + frac (a[row, j + 1] - a[row, j]) for each row."""
    rows = np.arange(len(a))
    return a[rows, j] + frac * (a[rows, j + 1] - a[rows, j])


def _root_station(g, y, y_min):
    """Highest crossing of g from <= 0 to > 0 (the root fillet scanned down from the rim):
    index j, fraction in [j, j + 1], station y (mm); ok False when none above ``y_min``."""
    m, p = g.shape
    below = g[:, :-1] <= 0
    j = p - 2 - np.argmax(below[:, ::-1], axis=1)
    ok = below.any(axis=1)
    rows = np.arange(m)
    g0, g1 = g[rows, j], g[rows, j + 1]
    frac = np.clip(np.where(g1 != g0, g0 / (g0 - g1), 0.0), 0.0, 1.0)
    y_t = _interp(y, j, frac)
    return j, frac, y_t, ok & (y_t >= y_min)


def _neck_station(h):
    """First crossing of h from < 0 to >= 0 from the tip: index j, fraction in [j, j + 1]."""
    m = len(h)
    above = h[:, 1:] >= 0
    j = np.argmax(above, axis=1)
    rows = np.arange(m)
    h0, h1 = h[rows, j], h[rows, j + 1]
    frac = np.clip(np.where(h1 != h0, h0 / (h0 - h1), 0.0), 0.0, 1.0)
    return j, frac


def _compliance(scale, factor, g):
    """Tip compliance of one flexure by Castigliano (mm/N) and its widths (mm):
    integral 12 (y - r_c)^2 / (E z w^3) ds by the trapezoid rule (weights precomputed)."""
    w = web_floor_mm(scale * g["w_law"] * factor, g["web"])
    return np.sum(g["castigliano"] / w ** 3, axis=1), w


def _scale_onto(scale, factor, compliance, passes, g):
    """The width scale after ``passes`` steps scale x (C / C_target)^(1/3) (K ~ scale^3
    away from the tip web), as :func:`springcad.design.sizing._design_at` and
    ``_with_flare`` step."""
    for _ in range(passes):
        scale = scale * (_compliance(scale, factor, g)[0] / compliance)[:, None] ** (1 / 3)
    return scale


def _widths(y, scale, flare, g):
    """Flexure widths at stations ``y`` (rows x k, mm) with a width scale and root flare."""
    arm = np.maximum(y - g["rc"], 0.0)
    yn = (y - (g["rr"] - g["flare_len"])) / g["flare_len"]
    return web_floor_mm(scale * np.sqrt(g["coef"] * arm) * fx.root_flare_factor(yn, 1.0, flare, 1.0),
                        g["web"])


_FINE = np.linspace(0.0, 1.0, 33)


def _neck_nominal(j, side, scale, g):
    """Nominal stress (MPa) where the neck fillet meets one edge, found between stations
    j and j + 1 on 33 points (the centreline interpolated, the widths exact)."""
    rows = np.arange(len(j))

    def between(a):
        return a[rows, j][:, None] + _FINE * (a[rows, j + 1] - a[rows, j])[:, None]

    y = between(g["y"])
    w = _widths(y, scale, g["flare"], g)
    px, py, nx, ny = _edge(between(g["x"]), y, between(g["slope"]), w, side, _FINE)
    rn, rb, rc = g["rn"], g["rb"], g["rc"]
    k, frac = _neck_station(np.hypot(px + rn * nx, py + rn * ny - rc) - (rb + rn))
    y_n = _interp(y, k, frac)[:, None]
    w_n = _widths(y_n, scale, g["flare"], g)
    return (6.0 * g["load"] * (y_n - rc) / (g["z"] * w_n ** 2))[:, 0]


def _one_flare(flare, g, cal):
    """Flank, root and neck peaks (MPa) of one root flare at the design's load, its
    flexure area (mm^2), width scale, compliance (mm/N), whether the stress model could
    place the fillets (``predicted``) and whether the profile is buildable (``buildable``:
    the neighbouring root fillets do not overlap and, for curved flexures, the clearance
    to the neighbour and the concave edge radius keep the wire's rules, as
    :func:`springcad.design.resize.with_width` and the ring profile check), and the
    compliance of flexures :data:`~springcad.design.resize.ROOM_SCALE` x as wide (mm/N).
    ``cal``: the (straight, curved) rows' :class:`~springcad.design.stress.StressCalibration`
    (the fillet and neck coefficients are shared).
    """
    x, y, slope, kappa, arm, yn = (g[k] for k in ("x", "y", "slope", "kappa", "arm", "yn"))
    straight_cal, curved_cal = cal
    factor = fx.root_flare_factor(yn, 1.0, flare, 1.0)
    g["flare"] = flare
    scale = _scale_onto(g["scale0"], factor, g["c_target"], _FLARE_PASSES, g)
    compliance, w = _compliance(scale, factor, g)
    nominal = 6.0 * g["load"] * arm / (g["z"] * w ** 2)
    rc, rr, rf, rn, rb = (g[k][:, 0] for k in ("rc", "rr", "rf", "rn", "rb"))
    flank = root = neck = np.zeros(len(y))
    loaded, w_root = np.full(len(y), -np.inf), np.ones(len(y))  # the more loaded root's width
    ok = np.ones(len(y), dtype=bool)
    rim_angle = {}
    if g["straight"]:
        # a block of straight flexures: no curvature, both edges mirror images
        sides = ((+1, np.ones_like(w)),)
    else:
        inner, outer = stress.winkler_factors(w, kappa)
        bends_right = kappa > 0
        sides = ((+1, np.where(bends_right, inner, outer)),
                 (-1, np.where(bends_right, outer, inner)))
    for side, k_edge in sides:
        edge = nominal * k_edge
        px, py, nx, ny = _edge(x, y, slope, w, side)
        # root fillet: centre at distance R_r - r_f from the disk centre
        j, frac, y_t, found = _root_station(np.hypot(px + rf[:, None] * nx, py + rf[:, None] * ny)
                                            - (rr - rf)[:, None], y, rc + 0.5 * (rr - rc))
        ok &= found
        nom_t, w_t, edge_t = (_interp(a, j, frac) for a in (nominal, w, edge))
        # where the fillet meets the rim circle: the polar angle of its centre
        rim_angle[side] = np.arctan2(_interp(py + rf[:, None] * ny, j, frac),
                                     _interp(px + rf[:, None] * nx, j, frac))
        past = y >= y_t[:, None]
        window = past & (y <= (y_t + rf)[:, None])
        k_root = np.maximum(np.max(np.where(window, k_edge, 0.0), axis=1), edge_t / nom_t)
        r_edge = (nom_t * curved_cal.root_coefficient
                  * (w_t / rf) ** curved_cal.root_width_exponent
                  * np.maximum(k_root, 1e-9) ** curved_cal.root_curvature_exponent)
        f_edge = np.maximum(np.max(np.where(past, 0.0, edge), axis=1), edge_t)
        more = nom_t * k_root > loaded
        loaded, w_root = np.where(more, nom_t * k_root, loaded), np.where(more, w_t, w_root)
        # neck fillet: tangent to the edge and to the tip ball; bracketed on the stations,
        # then solved on a fine grid inside the bracket (the width grows like the square
        # root of the arm there: a straight-line interpolation misses the nominal by 1 %)
        jn, _ = _neck_station(np.hypot(px + rn[:, None] * nx, py + rn[:, None] * ny - rc[:, None])
                              - (rb + rn)[:, None])
        n_edge = _neck_nominal(jn, side, scale, g)
        flank, root, neck = np.maximum(flank, f_edge), np.maximum(root, r_edge), np.maximum(neck, n_edge)
    # flexure outside the tip ball, plus the two root fillets (a right-angle corner each)
    area = trapz_rows(np.where(arm > g["rb"], w, 0.0) * g["ds"], y) + 2 * (1 - np.pi / 4) * rf ** 2
    # the next flexure's right fillet must start on the rim after this one's left ends
    buildable = rim_angle[+1] + g["pitch"] > rim_angle.get(-1, np.pi - rim_angle[+1])
    curved = np.any(kappa != 0, axis=1)
    if np.any(curved):
        # concave edge radius 1/|kappa| - w/2, and the gap to the neighbour above the tip
        # ball: r pitch cos(beta) - w (beta: tilt from radial; within 1 um of the exact
        # point-to-curve distance on the serpentines tried)
        edge_r = np.min(1.0 / np.maximum(np.abs(kappa), 1e-12) - 0.5 * w, axis=1)
        r = np.hypot(x, y)
        cos_b = np.abs(slope * x + y) / (r * np.sqrt(1.0 + slope ** 2))
        gap = np.where(arm > 2 * g["rb"], r * g["pitch"][:, None] * cos_b - w, np.inf)
        buildable &= ~curved | ((edge_r >= g["min_edge"]) & (np.min(gap, axis=1) >= g["min_slot"]))
    # the design's flank model per shape (straight rows: the straight flexure's, curved:
    # the serpentine's), with its thickness-over-root-width term
    f_factor = np.where(curved, curved_cal.flank_factor, straight_cal.flank_factor)
    f_exp = np.where(curved, curved_cal.flank_aspect_exponent,
                     straight_cal.flank_aspect_exponent)
    flank = f_factor * flank * (g["z"][:, 0] / w_root) ** f_exp
    narrow = _compliance(scale * ROOM_SCALE, factor, g)[0]
    return (flank, root, curved_cal.neck_factor * neck, area, scale[:, 0], compliance, ok,
            buildable, narrow)


def predict_peaks(x, y, slope, kappa, *, rc, rr, ro, n, load, z, E, K, width_coef, rb,
                  root_fillet_mm, neck_fillet_mm, manufacturing):
    """Predicted peak stress at the maximum deflection of many disks (MPa), root flare chosen.

    Args:
        x, y, slope, kappa: centreline stations (rows x 241, mm), dx/dy and curvature
            (1/mm) of the stored spline (zeros and ``rc + (rr - rc) U`` for straight).
        rc, rr, ro: contact, root and outer radius (mm). n: flexure count.
        load: tip load K theta / (N r_c) (N). z: thickness (mm). E: Young's modulus (MPa).
        K: disk stiffness (N*mm/rad), the target of the width scale.
        width_coef: width law w^2 = width_coef (y - r_c) (mm): 6 F / (z sigma) for the
            constant-stress law, w0^2 / L for straight flexures sized for stiffness.
        rb, root_fillet_mm, neck_fillet_mm: tip ball and fillet radii (mm).
        manufacturing: the wire rules (tip web, slot width, concave radius).

    Returns:
        Columns ``flank_MPa``, ``root_MPa``, ``neck_MPa``, ``peak_MPa``, ``region``
        (index into :data:`REGIONS`), ``flare``, ``width_scale``, ``flexure_area_mm2``
        (one flexure outside the tip ball, integral w ds, and its root fillets),
        ``stiffness_Nmm_per_rad`` (beam theory of the built
        widths: the tip web keeps it off ``K`` where it is a large part of the flexure),
        ``narrow_stiffness_Nmm_per_rad`` (the same with widths
        :data:`~springcad.design.resize.ROOM_SCALE` x as wide) and
        ``ok`` (False: no root flare gives a profile the design can build: a fillet
        cannot be placed, neighbouring root fillets overlap, or the flared flexures break
        the clearance or edge radius).
    """
    # the fillet coefficients are shared; the flank's are the shape's (design/stress.py)
    cal = (stress.calibration("straight"), stress.calibration("serpentine"))
    m = len(rc)
    cols = {k: np.full(m, np.nan) for k in ("flank_MPa", "root_MPa", "neck_MPa", "peak_MPa",
                                           "flare", "width_scale", "flexure_area_mm2",
                                           "stiffness_Nmm_per_rad", "narrow_stiffness_Nmm_per_rad")}
    cols["region"] = np.zeros(m, dtype=np.int64)
    cols["ok"] = np.zeros(m, dtype=bool)
    flares = np.array(ROOT_FLARES)
    # straight flexures first, so that most blocks take the straight path of _one_flare
    curved = np.any(kappa != 0, axis=1) | np.any(x != 0, axis=1)
    perm = np.argsort(curved, kind="stable")
    x, y, slope, kappa = (np.asarray(v)[perm] for v in (x, y, slope, kappa))
    curved = curved[perm]
    rc, rr, ro, n, load, z, E, K, width_coef, rb, root_fillet_mm, neck_fillet_mm = (
        np.broadcast_to(np.asarray(v, dtype=float), (m,))[perm]
        for v in (rc, rr, ro, n, load, z, E, K, width_coef, rb, root_fillet_mm, neck_fillet_mm))
    for b in blocks(m):
        def col(v):
            return np.asarray(v, dtype=float)[b][:, None]

        yb = y[b]
        arm = np.maximum(yb - col(rc), 0.0)
        flare_len = 2.0 * (col(ro) - col(rr))
        g = {"x": x[b], "y": yb, "slope": slope[b], "kappa": kappa[b], "arm": arm,
             "w_law": np.sqrt(col(width_coef) * arm), "ds": np.sqrt(1.0 + slope[b] ** 2),
             "coef": col(width_coef), "flare_len": flare_len,
             "yn": (yb - (col(rr) - flare_len)) / flare_len, "web": manufacturing.min_web_mm,
             "min_slot": manufacturing.min_slot_width_mm,
             "min_edge": manufacturing.min_inside_radius_mm,
             "pitch": 2 * np.pi / np.asarray(n, dtype=float)[b],
             "E": col(E), "z": col(z), "rc": col(rc), "rr": col(rr),
             "rf": col(root_fillet_mm), "rn": col(neck_fillet_mm), "rb": col(rb),
             "straight": not np.any(curved[b])}
        step = np.diff(yb, axis=1)
        weights = 0.5 * (np.pad(step, ((0, 0), (1, 0))) + np.pad(step, ((0, 0), (0, 1))))
        g["castigliano"] = 12.0 * arm ** 2 / (g["E"] * g["z"]) * g["ds"] * weights
        # the design: widths scaled onto K without a flare, then each flare rescaled onto
        # that flexure's stiffness and its peak predicted at the matching load
        no_flare = np.ones_like(yb)
        c_k = (col(n) * col(rc) ** 2 / col(K))[:, 0]
        g["scale0"] = _scale_onto(np.ones((len(yb), 1)), no_flare, c_k, _DESIGN_PASSES, g)
        g["c_target"] = _compliance(g["scale0"], no_flare, g)[0]
        g["load"] = col(load) * (c_k / g["c_target"])[:, None]
        runs = [_one_flare(f, g, cal) for f in ROOT_FLARES]
        peaks = np.column_stack([np.where(r[6], np.fmax(np.fmax(r[0], r[1]), r[2]), np.inf)
                                 for r in runs])
        buildable = np.column_stack([r[7] for r in runs])
        best = np.min(peaks, axis=1)
        # design_spring's order: the flares within FLARE_GAIN of the lowest peak, smallest
        # first, then the others by peak; the first whose profile is buildable
        within = peaks <= (best * (1 + FLARE_GAIN))[:, None]
        order = np.where(within, flares[None, :], 10.0 + peaks * 1e-6)
        order = np.where(buildable & np.isfinite(peaks), order, np.inf)
        pick = np.argmin(order, axis=1)
        rows = np.arange(b.stop - b.start)
        compliance = np.column_stack([r[5] for r in runs])[rows, pick]
        # stresses are linear in the load: the design's is the target stiffness's, ``load``
        # (springcad.design.stress.tip_load_N), not the built widths' beam stiffness's
        gain = np.broadcast_to(g["c_target"] / c_k, compliance.shape)
        for name, k in (("flank_MPa", 0), ("root_MPa", 1), ("neck_MPa", 2)):
            cols[name][b] = np.column_stack([r[k] for r in runs])[rows, pick] * gain
        for name, k in (("flexure_area_mm2", 3), ("width_scale", 4)):
            cols[name][b] = np.column_stack([r[k] for r in runs])[rows, pick]
        k_of = np.asarray(n, dtype=float)[b] * np.asarray(rc, dtype=float)[b] ** 2
        cols["stiffness_Nmm_per_rad"][b] = k_of / compliance
        cols["narrow_stiffness_Nmm_per_rad"][b] = k_of / np.column_stack(
            [r[8] for r in runs])[rows, pick]
        cols["ok"][b] = np.isfinite(order[rows, pick])
        picked = peaks[rows, pick] * gain
        cols["peak_MPa"][b] = np.where(np.isfinite(picked), picked, np.nan)
        cols["flare"][b] = flares[pick]
        cols["region"][b] = np.argmax(np.column_stack(
            [cols["flank_MPa"][b], cols["root_MPa"][b], cols["neck_MPa"][b]]), axis=1)
    back = np.argsort(perm)
    return {k: v[back] for k, v in cols.items()}
