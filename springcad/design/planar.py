"""The planar toolkit: sampling, point-in-region and validity of 2D profiles.

Every layer that reasons about a :class:`~springcad.design.curves.Profile` in
the plane uses these: the CAD kernel's face check (:mod:`springcad.geometry.profile`),
the EDM rules and interference checks, and the FE mesher's face check
(:mod:`fea.geometry`). They report plain records; each layer words them into
its own error (``GeometryError``, ``MeshingError``).

The exact curves stay the reference; the checks work on samples whose step
bounds the error (a chord of length h on a radius R deviates h^2 / (8 R) from
the curve). numpy only (the close pairs of samples from
:func:`springcad.design.numeric.close_pairs`, not scipy's KD-tree: design imports no scipy).
Units: mm, 1/mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline
from springcad.design.numeric import close_pairs

#: two samples of one loop closer than half a step count as the loop touching itself only
#: when they lie more than this many steps apart along it (else they are neighbours on the
#: curve). Measured along the loop, not in samples: a short spline is sampled far more
#: finely than the step (4 samples per fit point), and five samples of a 0.02 mm cam flank
#: are ~1 um apart
_TOUCH_MIN_STEPS_APART = 2.0


# ------------------------------------------------------------------------------ sampling
@dataclass(frozen=True)
class LoopSamples:
    """Samples of one closed loop (first point not repeated).

    Attributes:
        points: (n, 2) positions (mm).
        tangents: (n, 2) unit tangents in the loop direction.
        curvature: (n,) signed curvature, positive when the loop turns left (1/mm).
        s: (n,) arc length from the loop start (mm).
        segment: (n,) index of the segment each sample lies on.
        length: loop length (mm).
        corners: (k, 4) rows (segment index, x, y, turning angle rad) at joins
            whose tangents differ by more than 0.5 deg.
    """

    points: np.ndarray
    tangents: np.ndarray
    curvature: np.ndarray
    s: np.ndarray
    segment: np.ndarray
    length: float
    corners: np.ndarray

    @property
    def signed_area(self) -> float:
        x, y = self.points[:, 0], self.points[:, 1]
        return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _segment(seg, step: float):
    """(points, tangents, curvature) of one segment, end point excluded."""
    if isinstance(seg, Line):
        n = max(1, int(math.ceil(seg.length / step)))
        t = np.linspace(0.0, 1.0, n + 1)[:-1, None]
        p = (1 - t) * np.asarray(seg.start) + t * np.asarray(seg.end)
        d = (np.asarray(seg.end) - np.asarray(seg.start)) / seg.length
        return p, np.tile(d, (n, 1)), np.zeros(n)
    if isinstance(seg, (Arc, Circle)):
        a0, a1 = (seg.start_angle, seg.end_angle) if isinstance(seg, Arc) else (0.0, 2 * math.pi)
        n = max(2, int(math.ceil(abs(a1 - a0) * seg.radius / step)))
        a = np.linspace(a0, a1, n + 1)[:-1]
        sign = 1.0 if a1 > a0 else -1.0
        c = np.asarray(seg.center)
        p = c + seg.radius * np.column_stack([np.cos(a), np.sin(a)])
        tan = sign * np.column_stack([-np.sin(a), np.cos(a)])
        return p, tan, np.full(n, sign / seg.radius)
    if isinstance(seg, Spline):
        u, cs = seg._spline  # the design's own interpolant (chord-length parameter)
        n = max(len(seg.points) * 2, int(math.ceil(u[-1] / step)))
        uu = np.linspace(0.0, u[-1], n + 1)[:-1]
        p, d1, d2 = cs.derivatives(uu)  # one interval lookup: cs(uu, nu)'s numbers
        speed = np.linalg.norm(d1, axis=1)
        kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed ** 3
        return p, d1 / speed[:, None], kappa
    raise TypeError(f"unknown segment {type(seg).__name__}")


def _end_tangent(seg) -> np.ndarray:
    if isinstance(seg, Line):
        d = np.asarray(seg.end) - np.asarray(seg.start)
        return d / np.linalg.norm(d)
    if isinstance(seg, Arc):
        a, sign = seg.end_angle, (1.0 if seg.sweep > 0 else -1.0)
        return sign * np.array([-math.sin(a), math.cos(a)])
    if isinstance(seg, Spline):
        u, cs = seg._spline
        d = cs(u[-1], 1)
        return d / np.linalg.norm(d)
    raise TypeError(type(seg).__name__)


def sample_loop(loop: Loop, step_mm: float = 0.02) -> LoopSamples:
    """Sample a loop every ``step_mm`` (at most) along each segment."""
    pts, tans, kap, segidx = [], [], [], []
    for i, seg in enumerate(loop.segments):
        p, t, k = _segment(seg, step_mm)
        pts.append(p)
        tans.append(t)
        kap.append(k)
        segidx.append(np.full(len(p), i))
    points = np.vstack(pts)
    tangents = np.vstack(tans)
    closed = np.vstack([points, points[:1]])
    ds = np.linalg.norm(np.diff(closed, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(ds)[:-1]])
    corners = []
    segs = loop.segments
    if not isinstance(segs[0], Circle):
        starts = np.cumsum([0] + [len(p) for p in pts])[:-1]
        for i, seg in enumerate(segs):
            j = (i + 1) % len(segs)
            t_in, t_out = _end_tangent(seg), tangents[starts[j]]
            turn = math.atan2(t_in[0] * t_out[1] - t_in[1] * t_out[0], float(np.dot(t_in, t_out)))
            if abs(turn) > math.radians(0.5):
                x, y = points[starts[j]]
                corners.append((j, x, y, turn))
    return LoopSamples(points, tangents, np.concatenate(kap), s, np.concatenate(segidx),
                       float(np.sum(ds)), np.asarray(corners, dtype=float).reshape(-1, 4))


def sample_profile(profile: Profile, step_mm: float = 0.02) -> list[LoopSamples]:
    """Samples of the outer loop followed by every hole loop."""
    return [sample_loop(loop, step_mm) for loop in profile.loops]


def material_on_left(samples: LoopSamples, is_outer: bool) -> bool:
    """True when the part's material lies to the left of the loop direction."""
    ccw = samples.signed_area > 0
    return ccw if is_outer else not ccw


# ----------------------------------------------------------------------- point in region
def points_in_polygon(polygon: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Even-odd rule: which points lie inside a closed polyline.

    Each edge is held only against the points in its y band (points sorted by
    y), so the cost grows with the points times the edges one horizontal line
    crosses, not times all edges.

    Args:
        polygon: (n, 2) closed polyline, first point not repeated (mm).
        xy: (m, 2) points (mm).

    Returns:
        (m,) booleans.
    """
    poly = np.asarray(polygon, dtype=float)
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    a, b = poly, np.roll(poly, -1, axis=0)
    # an edge counts for the points with y in [y_low, y_high): horizontal edges never count
    y_lo, y_hi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
    order = np.argsort(xy[:, 1], kind="stable")
    ys = xy[order, 1]
    first = np.searchsorted(ys, y_lo, "left")
    count = np.searchsorted(ys, y_hi, "left") - first
    edge = np.repeat(np.arange(len(a)), count)
    offset = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
    point = order[np.repeat(first, count) + offset]
    ax, ay, bx, by = a[edge, 0], a[edge, 1], b[edge, 0], b[edge, 1]
    px, py = xy[point, 0], xy[point, 1]
    x_cross = ax + (py - ay) * (bx - ax) / (by - ay)
    hits = np.bincount(point[x_cross > px], minlength=len(xy))
    return hits % 2 == 1


def region_contains(polygons, xy: np.ndarray) -> np.ndarray:
    """Which points lie in a region: inside the first polygon, outside all others.

    Args:
        polygons: closed polylines (n_i, 2), outer contour first (mm).
        xy: (m, 2) points (mm).
    """
    polygons = list(polygons)
    mask = points_in_polygon(polygons[0], xy)
    for hole in polygons[1:]:
        mask &= ~points_in_polygon(hole, xy)
    return mask


def inside_region(profile: Profile, xy: np.ndarray, step_mm: float = 0.02) -> np.ndarray:
    """Boolean mask: which points lie in the profile's material (inside outer, outside holes)."""
    return region_contains([loop.sample(step_mm) for loop in profile.loops], xy)


# ------------------------------------------------------------------------------ validity
@dataclass(frozen=True)
class LoopDefect:
    """Why a profile is not a valid face.

    Attributes:
        kind: "cross" (two loop stretches cross), "touch" (they meet without crossing),
            "outside" (a hole outside the outer contour) or "nested" (a hole in a hole).
        loops: indices in ``profile.loops`` of the two loops involved (equal when a
            loop meets itself; for "outside" the hole and 0).
        point_mm: a point at the defect (mm).
    """

    kind: str
    loops: tuple[int, int]
    point_mm: tuple[float, float]


#: repeats of an N-fold loop on either side of repeat 0 whose samples the symmetric check
#: pairs (:func:`find_defect`): the repeats are rotated copies of one curve set, so two of
#: them can meet only where repeat 0 already overlaps its neighbour
_WINDOW_REPEATS = 2


#: how far (mm) a repeat's segment ends may lie from repeat 0's turned onto them
_REPEAT_TOLERANCE_MM = 1e-9


def _repeat_runs(loop: Loop, n: int) -> list[int] | None:
    """Segment counts of the loop's repeats 0..n-1 when its segments run as n equal,
    consecutive repeats (feature indices 0, 0, .., 1, 1, .., n-1) whose segments start
    and end where repeat 0's, turned by k 2 pi / n, do; else None."""
    idx = [f.index for f in loop.features]
    if not idx or len(idx) % n or idx != [i for i in range(n) for _ in range(len(idx) // n)]:
        return None
    m = len(idx) // n
    ends = np.array([[*s.start, *s.end] for s in loop.segments]).reshape(n, m, 4)
    turns = 2.0 * math.pi * np.arange(n) / n
    c, s = np.cos(turns)[:, None], np.sin(turns)[:, None]
    first = ends[0]
    for j in (0, 2):  # segment starts, then ends
        x = c * first[None, :, j] - s * first[None, :, j + 1]
        y = s * first[None, :, j] + c * first[None, :, j + 1]
        if np.hypot(ends[:, :, j] - x, ends[:, :, j + 1] - y).max() > _REPEAT_TOLERANCE_MM:
            return None
    return [m] * n


def _symmetric_samples(loop: Loop, n: int, step_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """Samples of an n-fold loop (:func:`_repeat_runs`): repeat 0's, turned by k 2 pi / n
    for repeat k (the same set of points the solids sample, to round-off), and the repeat
    of each sample."""
    m = len(loop.segments) // n
    unit = np.vstack([s.sample(step_mm)[:-1] for s in loop.segments[:m]])
    turns = 2.0 * math.pi * np.arange(n) / n
    c, s = np.cos(turns)[:, None], np.sin(turns)[:, None]
    x = c * unit[None, :, 0] - s * unit[None, :, 1]
    y = s * unit[None, :, 0] + c * unit[None, :, 1]
    return np.stack([x.ravel(), y.ravel()], axis=1), np.repeat(np.arange(n), len(unit))


def _window(pts, repeat, symmetric_loops, profile, reach_mm: float) -> np.ndarray | None:
    """Which samples the pair search needs when loops ``symmetric_loops`` are n-fold: the
    repeats within :data:`_WINDOW_REPEATS` of repeat 0, every sample of the other loops
    (an origin-centred circle, a hole, a bore) and the n-fold samples within ``reach_mm``
    of those (a circle's radial band, a loop's box). None when nothing is symmetric."""
    if not symmetric_loops:
        return None
    keep = []
    for i, p in enumerate(pts):
        if i in symmetric_loops:
            n = symmetric_loops[i]
            k = repeat[i]
            keep.append(np.minimum(k, n - k) <= _WINDOW_REPEATS)
        else:
            keep.append(np.ones(len(p), bool))
    xs = {i: pts[i][:, 0] for i in symmetric_loops}
    ys = {i: pts[i][:, 1] for i in symmetric_loops}
    radii = {i: np.hypot(xs[i], ys[i]) for i in symmetric_loops}
    for j, loop in enumerate(profile.loops):
        if j in symmetric_loops:
            continue
        centred = loop.is_circle and math.hypot(*loop.segments[0].center) < 1e-12
        (x0, y0), (x1, y1) = pts[j].min(axis=0) - reach_mm, pts[j].max(axis=0) + reach_mm
        for i in symmetric_loops:
            if centred:
                keep[i] |= np.abs(radii[i] - loop.segments[0].radius) <= reach_mm
            else:
                keep[i] |= (xs[i] >= x0) & (xs[i] <= x1) & (ys[i] >= y0) & (ys[i] <= y1)
    return np.concatenate(keep)


def find_defect(profile: Profile, step_mm: float = 0.02,
                folds: dict[str, int] | None = None) -> LoopDefect | None:
    """The first reason why the profile's loops do not bound a valid face, or None.

    Works on the loops sampled every ``step_mm``: no loop may cross itself or
    another loop, no two far-apart stretches may come closer than half a step
    (a fillet swept the long way, a hole tangent to an edge), every hole must
    lie inside the outer contour and outside the other holes. Of several crossings (or
    touches) the one reported is the first in sample order (outer contour first).

    ``folds``: loop name -> N for loops that are N rotated repeats of one curve set
    (a ring's flexures, a cam's teeth: :func:`_repeat_runs`). Their samples are repeat
    0's turned N times, and the pairs are searched only among the repeats next to repeat 0
    and wherever another loop comes near (:func:`_window`): a defect between repeats i and
    j is the same defect turned by -i, so the answer is the full search's (to round-off),
    at a fraction of its cost on rings of many flexures. Where a loop's segments are not
    such repeats it is searched whole.
    """
    symmetric, repeat, pts = {}, {}, []
    for i, (name, loop) in enumerate(zip(profile.names or [""] * len(profile.loops),
                                         profile.loops)):
        n = (folds or {}).get(name)
        if n and n > 2 * _WINDOW_REPEATS + 1 and _repeat_runs(loop, n) is not None:
            p, repeat[i] = _symmetric_samples(loop, n, step_mm)
            symmetric[i] = n
        else:
            p = loop.sample(step_mm)
        pts.append(p)
    sizes = np.array([len(p) for p in pts])
    p0 = np.vstack(pts)
    loop_of = np.repeat(np.arange(len(pts)), sizes)
    # arc length of every sample from its loop's start, and each loop's length (mm)
    chords = [np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1) for p in pts]
    s_along = np.concatenate([np.concatenate([[0.0], np.cumsum(c)[:-1]]) for c in chords])
    loop_length = np.array([c.sum() for c in chords])
    nxt = np.concatenate([start + (np.arange(n) + 1) % n
                          for start, n in zip(np.cumsum(sizes) - sizes, sizes)])
    p1 = p0[nxt]
    mid, half = 0.5 * (p0 + p1), 0.5 * np.linalg.norm(p1 - p0, axis=1)
    # two chords that cross have midpoints closer than the longer chord
    reach_mm = 2.0 * half.max() + 1e-9
    where = _window(pts, repeat, symmetric, profile, reach_mm + step_mm)
    search = np.arange(len(p0)) if where is None else np.flatnonzero(where)

    def pairs_within(xy: np.ndarray, r_mm: float) -> np.ndarray:
        return search[close_pairs(xy[search], r_mm)]

    pairs = pairs_within(mid, reach_mm)
    a, b = pairs[:, 0], pairs[:, 1]
    adjacent = (nxt[a] == b) | (nxt[b] == a)
    a, b = a[~adjacent], b[~adjacent]

    def orient(p, q, r):
        return np.sign((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1])
                       - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))

    cross = ((orient(p0[a], p1[a], p0[b]) * orient(p0[a], p1[a], p1[b]) < 0)
             & (orient(p0[b], p1[b], p0[a]) * orient(p0[b], p1[b], p1[a]) < 0))
    if cross.any():
        k = int(np.flatnonzero(cross)[0])
        return LoopDefect("cross", (int(loop_of[a[k]]), int(loop_of[b[k]])),
                          tuple(float(v) for v in mid[a[k]]))
    near = pairs_within(p0, 0.5 * step_mm)
    if len(near):
        a, b = near[:, 0], near[:, 1]
        gap_mm = np.abs(s_along[a] - s_along[b])
        gap_mm = np.minimum(gap_mm, loop_length[loop_of[a]] - gap_mm)
        touch = (loop_of[a] != loop_of[b]) | (gap_mm > _TOUCH_MIN_STEPS_APART * step_mm)
        if touch.any():
            k = int(np.flatnonzero(touch)[0])
            return LoopDefect("touch", (int(loop_of[a[k]]), int(loop_of[b[k]])),
                              tuple(float(v) for v in p0[a[k]]))
    # each hole's first sample against every loop at once (one pass per loop, not per pair)
    firsts = np.array([p[0] for p in pts[1:]]).reshape(-1, 2)
    inside = [points_in_polygon(p, firsts) for p in pts] if len(firsts) else []
    for i in range(1, len(pts)):
        where = tuple(float(v) for v in firsts[i - 1])
        if not inside[0][i - 1]:
            return LoopDefect("outside", (i, 0), where)
        for j in range(1, len(pts)):
            if j != i and inside[j][i - 1]:
                return LoopDefect("nested", (i, j), where)
    return None
