"""Flexure centrelines of screened disks on arrays: the serpentine search of the design, vectorised.

:func:`springcad.design.flexure.design_serpentine` builds each trial shape (k tilt
reversals, turn sharpness a) in closed form from the tilt budget between
neighbours,

    tan(beta(r)) = lam * T(r) * h_k(u),   theta(r) = integral tan(beta) / r dr,

finds lam for the required area ratio s, holds the shape to the wire's concave
edge radius and the exact neighbour clearance, and keeps the shape with the
smallest curved-beam measure integral (kappa w/2)^2 ds / L (balanced shapes,
k >= 2, before the swept arm k = 1). The functions here repeat those steps on
blocks of disks at once, on the design's own 241 radial stations:

- :func:`serpentine_reach`: the largest area ratio any shape reaches at full tilt
  (lam = 1): the search's first test, exact;
- :func:`serpentine_centrelines`: lam of every shape that reaches s (false position
  on lam^2, to 1e-7 in the area ratio), the edge-radius and turn-back checks, the
  same measure and choice; returns the chosen centreline's stations. The exact
  neighbour clearance (which raises the clearance margin in the budget when it
  fails) is not checked: the full design of the finalists does it.

Units: mm, N, MPa, rad.
"""

from __future__ import annotations


import numpy as np

from springcad.design.flexure import SERPENTINE_SHAPES, shape_rank, trial_tilt
from springcad.design.numeric import cumtrapz_last as cumtrapz_rows
from springcad.design.numeric import trapz_last as trapz_rows

#: the radial stations of design_serpentine: u = (r - r_c) / L
U = np.linspace(0.0, 1.0, 241) ** 1.3
#: the trial shapes (k, a, balance) in design_serpentine's order (ties go to the first)
DESIGN_SHAPES = SERPENTINE_SHAPES
#: the same shapes, widest first, so the reach test of most disks stops at the first
_REACH_ORDER = tuple(sorted(DESIGN_SHAPES, key=lambda s: (s[0] != 1, -s[1], s[0],
                                                          s[2] != "root")))
#: rows per block: (rows x 241) float temporaries stay below the 128 kB at which glibc
#: mmaps; Dask workers set MALLOC_TRIM_THRESHOLD_, which freezes that threshold, and larger
#: temporaries then cost a page-fault storm (measured 6x slower)
BLOCK_ROWS = 48
#: false-position steps on lam^2 (the area ratio is nearly linear in lam^2)
_LAM_STEPS = 12
#: area-ratio tolerance of the tilt factor (the stress follows lam about linearly)
_RATIO_TOL = 1e-7


def blocks(m: int):
    """Slices of at most :data:`BLOCK_ROWS` rows covering ``range(m)``."""
    return [slice(k, min(k + BLOCK_ROWS, m)) for k in range(0, m, BLOCK_ROWS)]


class _Tilt:
    """The tilt budget of a block of disks and the area ratio of a shape at a tilt factor."""

    def __init__(self, rc, rr, n, load, z, sigma, clearance_mm, root_zone_mm):
        self.rc, self.L = rc[:, None], (rr - rc)[:, None]
        self.r = self.rc + self.L * U[None, :]
        self.c = (6.0 * load / (z * sigma))[:, None]
        self.w_r = w_r = np.sqrt(self.c * (self.r - self.rc))
        self.straight_area = trapz_rows(w_r, self.r)
        pitch = (2 * np.pi / n)[:, None]
        self.budget = np.sqrt(np.maximum((self.r * pitch / (w_r + clearance_mm)) ** 2 - 1.0, 0.0))
        q = np.clip((rr[:, None] - self.r) / root_zone_mm[:, None], 0.0, 1.0)
        self.taper = q * q * (3 - 2 * q)

    def shape(self, k: int, a: float, balance: str, rows=slice(None)):
        """tan(beta) at full tilt and theta(r) per unit tilt of shape (k, a, balance)
        (:func:`springcad.design.flexure.trial_tilt`)."""
        r, budget = self.r[rows], self.budget[rows]
        h = trial_tilt(k, a, balance, U[None, :], self.taper[rows], budget, r, self.rc[rows],
                       self.w_r[rows])
        tan_b = budget * h
        return tan_b, cumtrapz_rows(tan_b / r, r)

    def ratio(self, lam, tan_b, theta1, rows=slice(None)):
        """Area ratio of the shape at tilt factor ``lam`` (column vector)."""
        r, rc = self.r[rows], self.rc[rows]
        y = r * np.cos(lam * theta1)
        w = np.sqrt(self.c[rows] * np.maximum(y - rc, 0.0))
        return trapz_rows(w * np.sqrt(1.0 + (lam * tan_b) ** 2), r) / self.straight_area[rows]


def serpentine_reach(s_req, rc, rr, n, load, z, sigma, clearance_mm, root_zone_mm):
    """Largest area ratio any trial shape of design_serpentine reaches at full tilt (-).

    Evaluated in blocks of rows, shape by shape, only for the rows not yet known to
    reach ``s_req``.
    """
    best = np.zeros(len(rc))
    for b in blocks(len(rc)):
        t = _Tilt(rc[b], rr[b], n[b], load[b], z[b], sigma[b], clearance_mm, root_zone_mm[b])
        todo = np.ones(b.stop - b.start, dtype=bool)
        out = best[b]
        for k, a, balance in _REACH_ORDER:
            i = np.flatnonzero(todo)
            if i.size == 0:
                break
            tan_b, theta1 = t.shape(k, a, balance, i)
            ratio = t.ratio(1.0, tan_b, theta1, i)
            out[i] = np.maximum(out[i], ratio)
            todo[i] = ratio < s_req[b][i]
    return best


def curvature(x, y):
    """dx/dy and kappa = x'' / (1 + x'^2)^1.5 (1/mm) of curves sampled at :data:`U`, by
    finite differences (the shape choice; :func:`spline_centreline` for the stress)."""
    xu, yu = np.gradient(x, U, axis=1), np.gradient(y, U, axis=1)
    slope = xu / yu
    kappa = np.gradient(slope, U, axis=1) / yu / (1.0 + slope ** 2) ** 1.5
    return slope, kappa


#: design_serpentine stores every 4th station as a spline knot (240 = 4 x 60: the last is one)
KNOT_STEP = 4


def spline_centreline(x, y, end_slope):
    """x, dx/dy, d2x/dy2 at the stations of the clamped cubic x(y) the design stores.

    :class:`springcad.design.flexure.Centreline` interpolates x(y) through every
    :data:`KNOT_STEP`-th station with slope 0 at the tip and ``end_slope`` at the root
    (:class:`springcad.design.numeric.ClampedCubic`); the stress model reads its
    curvature. The same spline for many rows at once: the tridiagonal system for the
    knot second derivatives by the Thomas algorithm, vectorised over rows.
    """
    xk, yk = x[:, ::KNOT_STEP], y[:, ::KNOT_STEP]
    m, n = xk.shape
    h = np.diff(yk, axis=1)
    dy = np.diff(xk, axis=1) / h
    lower = np.concatenate([np.zeros((m, 1)), h[:, :-1], h[:, -1:]], axis=1)
    upper = np.concatenate([h[:, :1], h[:, 1:], np.zeros((m, 1))], axis=1)
    diag = np.concatenate([2 * h[:, :1], 2 * (h[:, :-1] + h[:, 1:]), 2 * h[:, -1:]], axis=1)
    rhs = np.concatenate([6 * (dy[:, :1] - 0.0), 6 * np.diff(dy, axis=1),
                          6 * (end_slope[:, None] - dy[:, -1:])], axis=1)
    c, d = np.zeros((m, n)), np.zeros((m, n))
    c[:, 0], d[:, 0] = upper[:, 0] / diag[:, 0], rhs[:, 0] / diag[:, 0]
    for i in range(1, n):
        den = diag[:, i] - lower[:, i] * c[:, i - 1]
        c[:, i] = upper[:, i] / den
        d[:, i] = (rhs[:, i] - lower[:, i] * d[:, i - 1]) / den
    mom = np.zeros((m, n))
    mom[:, -1] = d[:, -1]
    for i in range(n - 2, -1, -1):
        mom[:, i] = d[:, i] - c[:, i] * mom[:, i + 1]
    j = np.minimum(np.arange(y.shape[1]) // KNOT_STEP, n - 2)
    y0, y1, hh = yk[:, j], yk[:, j + 1], h[:, j]
    a, b = (y1 - y) / hh, (y - y0) / hh
    m0, m1 = mom[:, j], mom[:, j + 1]
    xs = a * xk[:, j] + b * xk[:, j + 1] + ((a ** 3 - a) * m0 + (b ** 3 - b) * m1) * hh ** 2 / 6
    slope = dy[:, j] + ((1 - 3 * a ** 2) * m0 + (3 * b ** 2 - 1) * m1) * hh / 6
    return xs, slope, a * m0 + b * m1


def serpentine_centrelines(s_req, rc, rr, n, load, z, sigma, clearance_mm, root_zone_mm,
                           min_edge_radius_mm):
    """The serpentine centreline design_serpentine would choose, for each disk.

    Args:
        s_req: required area ratio (-). rc, rr: contact and root radius (mm).
        n: flexure count. load: tip load (N). z: thickness (mm). sigma: beam stress (MPa).
        clearance_mm: clearance to the neighbour in the tilt budget (mm).
        root_zone_mm: length over which the tilt fades out at the root (mm).
        min_edge_radius_mm: smallest concave edge radius the wire cuts (mm).

    Returns:
        ``ok`` (a shape was found), ``x``, ``y`` (stations of the centreline, rows x 241,
        mm), ``slope`` (dx/dy) and ``kappa`` (1/mm) of the stored spline there, ``end_slope``, ``shape`` (index into :data:`DESIGN_SHAPES`, -1 if none), ``reach`` (largest
        area ratio at full tilt), ``edge_radius_mm`` (the chosen shape's smallest concave
        edge radius; without a shape, the largest among the shapes that reach s).
    """
    m = len(rc)
    out = {"ok": np.zeros(m, dtype=bool), "x": np.zeros((m, U.size)), "y": np.zeros((m, U.size)),
           "slope": np.zeros((m, U.size)), "kappa": np.zeros((m, U.size)),
           "end_slope": np.zeros(m), "shape": np.full(m, -1), "reach": np.zeros(m),
           "edge_radius_mm": np.full(m, -np.inf)}
    for b in blocks(m):
        t = _Tilt(rc[b], rr[b], n[b], load[b], z[b], sigma[b], clearance_mm, root_zone_mm[b])
        s = s_req[b][:, None]
        best_key = np.full(b.stop - b.start, np.inf)
        for idx, (k, a, balance) in enumerate(DESIGN_SHAPES):
            tan_b, theta1 = t.shape(k, a, balance)
            r1 = t.ratio(1.0, tan_b, theta1)
            out["reach"][b] = np.maximum(out["reach"][b], r1)
            i = np.flatnonzero(r1 >= s[:, 0])
            if i.size == 0:
                continue
            tb, th1, si = tan_b[i], theta1[i], s[i]
            # false position on q = lam^2 in [0, 1], f(0) = 1 - s < 0 <= f(1), Illinois: an
            # end kept twice in a row has its value halved, so both ends close in
            qa, fa = np.zeros((i.size, 1)), 1.0 - si
            qb, fb = np.ones((i.size, 1)), r1[i][:, None] - si
            last = np.zeros((i.size, 1))
            q_best, f_best = qb.copy(), fb.copy()
            for _ in range(_LAM_STEPS):
                q = np.clip(qb - fb * (qb - qa) / np.where(fb != fa, fb - fa, 1.0), 0.0, 1.0)
                f = t.ratio(np.sqrt(q), tb, th1, i)[:, None] - si
                low = f < 0
                fb = np.where(low & (last < 0), 0.5 * fb, np.where(low, fb, f))
                fa = np.where(~low & (last > 0), 0.5 * fa, np.where(low, f, fa))
                qa, qb = np.where(low, q, qa), np.where(low, qb, q)
                last = np.where(low, -1.0, 1.0)
                # a row's result must not depend on the rows it shares a block with: once
                # within tolerance it is frozen
                closer = (np.abs(f) < np.abs(f_best)) & (np.abs(f_best) >= _RATIO_TOL)
                q_best, f_best = np.where(closer, q, q_best), np.where(closer, f, f_best)
                if np.all(np.abs(f_best) < _RATIO_TOL):
                    break
            lam = np.sqrt(q_best)
            theta = lam * th1
            r = t.r[i]
            x, y = r * np.sin(theta), r * np.cos(theta)
            monotone = np.all(np.diff(y, axis=1) > 0, axis=1)
            end_slope = np.tan(theta[:, -1])
            _, slope, ddx = spline_centreline(x, np.where(monotone[:, None], y, t.r[i]), end_slope)
            kappa = ddx / (1.0 + slope ** 2) ** 1.5
            w = np.sqrt(t.c[i] * np.maximum(y - t.rc[i], 0.0))
            edge = np.min(1.0 / np.maximum(np.abs(kappa), 1e-12) - 0.5 * w, axis=1)
            measure = trapz_rows((kappa * 0.5 * w) ** 2 * np.sqrt(1.0 + slope ** 2), y) / t.L[i, 0]
            good = monotone & (edge >= min_edge_radius_mm)
            rows = np.arange(b.start, b.stop)[i]
            out["edge_radius_mm"][rows] = np.where(
                out["ok"][rows], out["edge_radius_mm"][rows],
                np.maximum(out["edge_radius_mm"][rows], np.where(monotone, edge, -np.inf)))
            key = shape_rank(balance, measure)
            better = good & (key < best_key[i])
            j = rows[better]
            best_key[i[better]] = key[better]
            out["ok"][j] = True
            out["x"][j], out["y"][j] = x[better], y[better]
            out["shape"][j] = idx
            out["edge_radius_mm"][j] = edge[better]
            out["end_slope"][j] = end_slope[better]
            out["slope"][j], out["kappa"][j] = slope[better], kappa[better]
    return out
