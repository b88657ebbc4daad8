"""Small numerical kernels for the design math (numpy only).

The design step must start and finish in well under two seconds; importing
``scipy.optimize``/``scipy.interpolate`` alone costs ~1 s, so the five
things design needs are here: a bracketed scalar root, a bounded scalar
minimum, a clamped cubic spline, a cumulative trapezoid and the pairs of points closer
than a distance (``scipy.spatial`` alone costs ~0.5 s of CPU to import). Each is checked
against scipy in ``tests/test_numeric.py``.
"""

from __future__ import annotations

import math

import numpy as np


def find_root(f, a: float, b: float, xtol: float = 1e-12, maxiter: int = 200) -> float:
    """Root of ``f`` in [a, b] with f(a), f(b) of opposite sign (Illinois method).

    Regula falsi with the Illinois modification converges superlinearly and,
    unlike Newton or secant, never leaves the bracket.

    Raises:
        ValueError: f(a) and f(b) have the same sign.
    """
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if fa * fb > 0:
        raise ValueError(f"root not bracketed: f({a:g}) = {fa:g}, f({b:g}) = {fb:g}")
    side = 0
    c = a
    for _ in range(maxiter):
        c = (a * fb - b * fa) / (fb - fa)
        if not (min(a, b) < c < max(a, b)):
            c = 0.5 * (a + b)
        fc = f(c)
        if fc == 0.0 or abs(b - a) < xtol:
            return c
        if fc * fb > 0:
            b, fb = c, fc
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb *= 0.5
            side = 1
        if abs(b - a) < xtol:
            break
    return c


def minimize_bounded(f, lo: float, hi: float, xatol: float = 1e-5,
                     maxiter: int = 500) -> tuple[float, float]:
    """(x, f(x)) at the minimum of ``f`` on [lo, hi]: Brent's bounded method, step for step
    scipy's ``minimize_scalar(method="bounded")`` (the same arithmetic, so the same bits;
    ``tests/test_numeric.py``), without importing scipy.optimize (~0.5 s of CPU)."""
    sqrt_eps = math.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - math.sqrt(5.0))
    a, b = lo, hi
    fulc = a + golden_mean * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = f(x)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while np.abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = 1
        if np.abs(e) > tol1:  # a parabolic step?
            golden = 0
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = np.abs(q)
            r = e
            e = rat
            if (np.abs(p) < np.abs(0.5 * q * r)) and (p > q * (a - xf)) and (p < q * (b - xf)):
                rat = (p + 0.0) / q
                x = xf + rat
                if ((x - a) < tol2) or ((b - x) < tol2):
                    si = np.sign(xm - xf) + ((xm - xf) == 0)
                    rat = tol1 * si
            else:
                golden = 1
        if golden:  # a golden-section step
            e = a - xf if xf >= xm else b - xf
            rat = golden_mean * e
        si = np.sign(rat) + (rat == 0)
        x = xf + si * np.maximum(np.abs(rat), tol1)
        fu = f(x)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if (fu <= fnfc) or (nfc == xf):
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif (fu <= ffulc) or (fulc == xf) or (fulc == nfc):
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxiter:
            break
    return xf, fx


def cumtrapz(y, x) -> np.ndarray:
    """Cumulative trapezoid integral of y(x), starting at 0."""
    y, x = np.asarray(y, dtype=float), np.asarray(x, dtype=float)
    return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])



def trapz_last(y, x):
    """Trapezoid rule along the last axis (rows of y at once; x broadcast against y)."""
    return np.sum(0.5 * (y[..., 1:] + y[..., :-1]) * np.diff(x, axis=-1), axis=-1)


def cumtrapz_last(y, x):
    """Cumulative trapezoid along the last axis, starting at 0 (rows of y at once)."""
    steps = 0.5 * (y[..., 1:] + y[..., :-1]) * np.diff(x, axis=-1)
    return np.concatenate([np.zeros(steps.shape[:-1] + (1,)), np.cumsum(steps, axis=-1)],
                          axis=-1)

def _thomas(lower: list, diag: list, upper: list, rhs: list) -> list:
    """Solve the tridiagonal system (``lower[i]``, ``diag[i]``, ``upper[i]`` on row i) for each
    column of ``rhs`` (rows of equal length) by the Thomas algorithm, on Python floats (the
    same operations, in the same order, as on NumPy scalars: the same numbers, ~10x faster
    for the few-dozen-row systems of the design's splines)."""
    n = len(diag)
    c = [0.0] * n
    d = [None] * n
    c[0] = upper[0] / diag[0]
    d[0] = [r / diag[0] for r in rhs[0]]
    for i in range(1, n):
        low = lower[i]
        den = diag[i] - low * c[i - 1]
        c[i] = upper[i] / den if i < n - 1 else 0.0
        d[i] = [(r - low * dp) / den for r, dp in zip(rhs[i], d[i - 1])]
    m = [None] * n
    m[-1] = d[-1]
    for i in range(n - 2, -1, -1):
        ci = c[i]
        m[i] = [di - ci * mn for di, mn in zip(d[i], m[i + 1])]
    return m


class ClampedCubic:
    """C2 cubic spline through (x_i, y_i) with given end slopes dy/dx.

    ``y`` may be (n,) or (n, d). Same curve as
    ``scipy.interpolate.CubicSpline(x, y, bc_type=((1, s0), (1, s1)))``.
    """

    def __init__(self, x, y, start_slope, end_slope):
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        self._scalar = y.ndim == 1
        if self._scalar:
            y = y[:, None]
        s0 = np.broadcast_to(np.asarray(start_slope, dtype=float), y.shape[1:])
        s1 = np.broadcast_to(np.asarray(end_slope, dtype=float), y.shape[1:])
        n = len(x)
        h = np.diff(x)
        if np.any(h <= 0):
            raise ValueError("spline abscissae must increase")
        # tridiagonal system for the second derivatives m_i
        lower = np.zeros(n)
        diag = np.zeros(n)
        upper = np.zeros(n)
        rhs = np.zeros((n, y.shape[1]))
        dy = np.diff(y, axis=0) / h[:, None]
        diag[0], upper[0] = 2 * h[0], h[0]
        rhs[0] = 6 * (dy[0] - s0)
        diag[-1], lower[-1] = 2 * h[-1], h[-1]
        rhs[-1] = 6 * (s1 - dy[-1])
        lower[1:-1], diag[1:-1], upper[1:-1] = h[:-1], 2 * (h[:-1] + h[1:]), h[1:]
        rhs[1:-1] = 6 * (dy[1:] - dy[:-1])
        m = np.array(_thomas(lower.tolist(), diag.tolist(), upper.tolist(), rhs.tolist()))
        self.x, self.y, self.m, self.h = x, y, m, h

    def __call__(self, t, nu: int = 0):
        """Value (nu = 0), first (1) or second (2) derivative at t."""
        if nu not in (0, 1, 2):
            raise ValueError("nu must be 0, 1 or 2")
        return self.derivatives(t, (nu,))[0]

    def derivatives(self, t, orders=(0, 1, 2)) -> tuple:
        """The value and derivatives of the given ``orders`` at t, the interval lookup shared
        (each the same numbers as ``self(t, nu)``)."""
        t = np.asarray(t, dtype=float)
        i = np.clip(np.searchsorted(self.x, t, side="right") - 1, 0, len(self.x) - 2)
        h = self.h[i][..., None]
        a = (self.x[i + 1][..., None] - t[..., None]) / h
        b = (t[..., None] - self.x[i][..., None]) / h
        y0, y1 = self.y[i], self.y[i + 1]
        m0, m1 = self.m[i], self.m[i + 1]
        outs = []
        for nu in orders:
            if nu == 0:
                out = a * y0 + b * y1 + ((a ** 3 - a) * m0 + (b ** 3 - b) * m1) * h ** 2 / 6
            elif nu == 1:
                out = (y1 - y0) / h + ((1 - 3 * a ** 2) * m0 + (3 * b ** 2 - 1) * m1) * h / 6
            else:
                out = a * m0 + b * m1
            outs.append(out[..., 0] if self._scalar else out)
        return tuple(outs)


def close_pairs(xy: np.ndarray, r_mm: float) -> np.ndarray:
    """Every pair of rows of ``xy`` at most ``r_mm`` apart, as (k, 2) indices (i < j), sorted.

    The pairs of ``scipy.spatial.cKDTree(xy).query_pairs(r_mm, output_type="ndarray")``
    (same squared-distance test), in lexicographic order instead of the tree's. Points
    are binned on a grid of cells ``r_mm`` wide: a pair that close lies in one cell or in
    two neighbouring ones, so each cell is joined with itself and four of its eight
    neighbours (the other four are the same joins seen from the other side).

    Args:
        xy: (n, 2) points (mm).
        r_mm: the largest distance of a pair (mm), > 0.
    """
    xy = np.asarray(xy, dtype=float)
    n = len(xy)
    if n < 2:
        return np.zeros((0, 2), dtype=np.intp)
    cell = np.floor((xy - xy.min(axis=0)) / r_mm).astype(np.int64)
    # one free key between columns, so that a neighbour row -1 or +1 never wraps into
    # an occupied cell of the next column
    rows = int(cell[:, 1].max()) + 2
    key = cell[:, 0] * rows + cell[:, 1]
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    x, y = xy[order, 0], xy[order, 1]   # contiguous, in cell order
    position = np.arange(n)
    found = []
    for dx, dy in ((0, 0), (0, 1), (1, -1), (1, 0), (1, 1)):
        target = sorted_key + dx * rows + dy
        lo = np.searchsorted(sorted_key, target, side="left")
        hi = np.searchsorted(sorted_key, target, side="right")
        if dx == 0 and dy == 0:
            lo = np.maximum(lo, position + 1)   # each pair of one cell once
        count = np.maximum(hi - lo, 0)
        src = np.repeat(position, count)
        dst = lo[src] + np.arange(int(count.sum())) - (np.cumsum(count) - count)[src]
        near = (x[src] - x[dst]) ** 2 + (y[src] - y[dst]) ** 2 <= r_mm * r_mm
        i, j = order[src[near]], order[dst[near]]
        found.append(np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1))
    pairs = np.concatenate(found)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def _block_boxes(xy: np.ndarray, size: int, overlap: int) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) corners of the bounding boxes of consecutive blocks of ``size`` rows of
    ``xy``, each block also holding the next ``overlap`` rows (shape (blocks, 2))."""
    count = -(-(len(xy) - overlap) // size)
    rows = np.minimum(np.arange(count)[:, None] * size + np.arange(size + overlap)[None],
                      len(xy) - 1)
    block = xy[rows]
    return block.min(axis=1), block.max(axis=1)


def min_block_distance(a: np.ndarray, b: np.ndarray, measure, size: int = 16,
                       b_overlap: int = 0) -> float:
    """Smallest ``measure(a_block, b_block)`` over consecutive blocks of ``size`` points of the
    2D sets ``a`` and ``b`` (``b``'s blocks also holding the next ``b_overlap`` points: the
    end vertex of a polyline's last segment), by branch and bound.

    ``measure`` is a distance no smaller than that of the two blocks' bounding boxes (a
    distance between their points, or between ``a``'s points and ``b``'s segments), and
    the block pairs are measured nearest box first, until the next box lies beyond the
    smallest value found (with 1e-9 relative slack for rounding). The result is the
    all-pairs minimum bit for bit (each pair is measured by the same arithmetic), for a
    small part of its cost on long, smooth curves.
    """
    a_lo, a_hi = _block_boxes(a, size, 0)
    b_lo, b_hi = _block_boxes(b, size, b_overlap)
    gap = np.maximum(np.maximum(b_lo[None] - a_hi[:, None], a_lo[:, None] - b_hi[None]), 0.0)
    lower = np.sqrt((gap ** 2).sum(-1))
    best = math.inf
    for flat in np.argsort(lower, axis=None, kind="stable"):
        if lower.flat[flat] > best * (1.0 + 1e-9) + 1e-12:
            break
        i, j = divmod(int(flat), lower.shape[1])
        best = min(best, measure(a[i * size:(i + 1) * size],
                                 b[j * size:j * size + size + b_overlap]))
    return best
