"""Predicted peak stress of screened disks: the design's stress model on arrays.

:func:`springcad.design.spring.design_spring` keeps the *predicted* peak of the
real geometry (:mod:`springcad.design.stress`: the Winkler-Bach curved-beam flank,
the root fillet and the tip-neck fillet, calibrated to FEA) below yield / margin,
choosing the root flare with the lowest peak. :func:`predict_peaks` evaluates the
same model on many screened disks at once, on the centreline stations of
:mod:`springcad.synthesis.shapes` (or straight flexures):

1. for each root flare of :data:`springcad.design.spring.ROOT_FLARES`, the flexure
   widths w = web-floor(scale x w_law(y) x flare(y)), with the scale that brings the
   Castigliano stiffness back onto the target (three passes, as the design);
2. nominal stress 6 F (y - r_c) / (z w^2) times the Winkler factors of the centreline
   curvature on both edges;
3. the root-fillet and neck-fillet tangent stations on each edge (fillet circle
   tangent to the edge and to the rim circle or the tip ball), the root model
   a (w / r_f)^b k^c there, the flank maximum below the root station, the neck nominal;
4. the flare with the lowest peak, a larger flare only when it gains more than
   :data:`springcad.design.spring.FLARE_GAIN`.

What it leaves out: the exact neighbour clearance of each flare (a flare whose
profile breaks it falls back to the next in the design). Agreement with the full
design is tested in ``tests/synthesis/test_synth_peak.py``. Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from springcad.design import flexure as fx
from springcad.design import stress
from springcad.design.spring import FLARE_GAIN, ROOT_FLARES
from springcad.synthesis.shapes import U, blocks, trapz_rows

#: peak regions, in the order of :class:`springcad.design.stress.StressPrediction`
REGIONS = ("flexure flank", "root fillet", "tip-neck fillet")
#: width-scale passes onto the target stiffness (the design's _with_flare makes three)
_SCALE_PASSES = 3


def web_floor_mm(width_mm, min_web_mm: float):
    """The flexure width with the tip web kept (mm): the smooth maximum of
    :meth:`springcad.design.spring.SpringDesign.width_mm` (web 1.002 x min_web_mm,
    blend 0.1 x web)."""
    web = 1.002 * min_web_mm
    return 0.5 * (width_mm + web + np.sqrt((width_mm - web) ** 2 + (0.1 * web) ** 2))


def _edge(x, y, slope, w, side):
    """Points of one flexure edge and its unit normal towards the void (rows x stations x 2)."""
    norm = np.sqrt(1.0 + slope ** 2)
    px = x + side * 0.5 * w / norm
    py = y - side * 0.5 * w * slope / norm
    tx, ty = np.gradient(px, U, axis=1), np.gradient(py, U, axis=1)
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


def _one_flare(flare, g, cal):
    """Flank, root and neck peaks (MPa), flexure area (mm^2) and ok of one root flare."""
    x, y, slope, kappa, arm, w_law, ds, yn = (g[k] for k in (
        "x", "y", "slope", "kappa", "arm", "w_law", "ds", "yn"))
    factor = fx.root_flare_factor(yn, 1.0, flare, 1.0)
    scale = np.ones((len(y), 1))
    for _ in range(_SCALE_PASSES):
        w = web_floor_mm(scale * w_law * factor, g["web"])
        c = trapz_rows(12.0 * arm ** 2 / (g["E"] * g["z"] * w ** 3) * ds, y)
        scale = scale * (c / g["c_target"])[:, None] ** (1 / 3)
    w = web_floor_mm(scale * w_law * factor, g["web"])
    nominal = 6.0 * g["load"] * arm / (g["z"] * w ** 2)
    inner, outer = stress.winkler_factors(w, kappa)
    bends_right = kappa > 0
    rc, rr, rf, rn, rb = (g[k][:, 0] for k in ("rc", "rr", "rf", "rn", "rb"))
    flank = root = neck = np.zeros(len(y))
    ok = np.ones(len(y), dtype=bool)
    for side, k_edge in ((+1, np.where(bends_right, inner, outer)),
                         (-1, np.where(bends_right, outer, inner))):
        edge = nominal * k_edge
        px, py, nx, ny = _edge(x, y, slope, w, side)
        # root fillet: centre at distance R_r - r_f from the disk centre
        j, frac, y_t, found = _root_station(np.hypot(px + rf[:, None] * nx, py + rf[:, None] * ny)
                                            - (rr - rf)[:, None], y, rc + 0.5 * (rr - rc))
        ok &= found
        nom_t, w_t, edge_t = (_interp(a, j, frac) for a in (nominal, w, edge))
        past = y >= y_t[:, None]
        window = past & (y <= (y_t + rf)[:, None])
        k_root = np.maximum(np.max(np.where(window, k_edge, 0.0), axis=1), edge_t / nom_t)
        r_edge = (nom_t * cal.root_coefficient * (w_t / rf) ** cal.root_width_exponent
                  * np.maximum(k_root, 1e-9) ** cal.root_curvature_exponent)
        f_edge = np.maximum(np.max(np.where(past, 0.0, edge), axis=1), edge_t)
        # neck fillet: tangent to the edge and to the tip ball
        jn, fn = _neck_station(np.hypot(px + rn[:, None] * nx, py + rn[:, None] * ny - rc[:, None])
                               - (rb + rn)[:, None])
        n_edge = _interp(nominal, jn, fn)
        flank, root, neck = np.maximum(flank, f_edge), np.maximum(root, r_edge), np.maximum(neck, n_edge)
    area = trapz_rows(w * ds, y)
    return cal.flank_factor * flank, root, cal.neck_factor * neck, area, scale[:, 0], ok


def predict_peaks(x, y, slope, kappa, *, rc, rr, ro, n, load, z, E, K, width_coef, rb,
                  root_fillet_mm, neck_fillet_mm, min_web_mm: float):
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
        min_web_mm: the tip web (mm).

    Returns:
        Columns ``flank_MPa``, ``root_MPa``, ``neck_MPa``, ``peak_MPa``, ``region``
        (index into :data:`REGIONS`), ``flare``, ``width_scale``, ``flexure_area_mm2``
        (one flexure, integral w ds) and ``ok`` (False: a fillet could not be placed).
    """
    cal = stress.calibration()
    m = len(rc)
    cols = {k: np.full(m, np.nan) for k in ("flank_MPa", "root_MPa", "neck_MPa", "peak_MPa",
                                           "flare", "width_scale", "flexure_area_mm2")}
    cols["region"] = np.zeros(m, dtype=np.int64)
    cols["ok"] = np.zeros(m, dtype=bool)
    flares = np.array(ROOT_FLARES)
    for b in blocks(m):
        def col(v):
            return np.asarray(v, dtype=float)[b][:, None]

        yb = y[b]
        arm = np.maximum(yb - col(rc), 0.0)
        flare_len = 2.0 * (col(ro) - col(rr))
        g = {"x": x[b], "y": yb, "slope": slope[b], "kappa": kappa[b], "arm": arm,
             "w_law": np.sqrt(col(width_coef) * arm), "ds": np.sqrt(1.0 + slope[b] ** 2),
             "yn": (yb - (col(rr) - flare_len)) / flare_len, "web": min_web_mm,
             "E": col(E), "z": col(z), "load": col(load),
             "c_target": (col(n) * col(rc) ** 2 / col(K))[:, 0],
             "rc": col(rc), "rr": col(rr), "rf": col(root_fillet_mm), "rn": col(neck_fillet_mm),
             "rb": col(rb)}
        runs = [_one_flare(f, g, cal) for f in ROOT_FLARES]
        peaks = np.column_stack([np.where(r[5], np.fmax(np.fmax(r[0], r[1]), r[2]), np.inf)
                                 for r in runs])
        best = np.min(peaks, axis=1)
        # the smallest flare within FLARE_GAIN of the lowest peak (design_spring's choice)
        pick = np.argmax(peaks <= (best * (1 + FLARE_GAIN))[:, None], axis=1)
        rows = np.arange(b.stop - b.start)
        for name, k in (("flank_MPa", 0), ("root_MPa", 1), ("neck_MPa", 2),
                        ("flexure_area_mm2", 3), ("width_scale", 4)):
            cols[name][b] = np.column_stack([r[k] for r in runs])[rows, pick]
        cols["ok"][b] = np.isfinite(best)
        picked = peaks[rows, pick]
        cols["peak_MPa"][b] = np.where(np.isfinite(picked), picked, np.nan)
        cols["flare"][b] = flares[pick]
        cols["region"][b] = np.argmax(np.column_stack(
            [cols["flank_MPa"][b], cols["root_MPa"][b], cols["neck_MPa"][b]]), axis=1)
    return cols
