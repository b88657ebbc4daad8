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


def find_defect(profile: Profile, step_mm: float = 0.02) -> LoopDefect | None:
    """The first reason why the profile's loops do not bound a valid face, or None.

    Works on the loops sampled every ``step_mm``: no loop may cross itself or
    another loop, no two far-apart stretches may come closer than half a step
    (a fillet swept the long way, a hole tangent to an edge), every hole must
    lie inside the outer contour and outside the other holes. Of several crossings (or
    touches) the one reported is the first in sample order (outer contour first).
    """
    pts = [loop.sample(step_mm) for loop in profile.loops]
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
    pairs = close_pairs(mid, 2.0 * half.max() + 1e-9)
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
    near = close_pairs(p0, 0.5 * step_mm)
    if len(near):
        a, b = near[:, 0], near[:, 1]
        gap_mm = np.abs(s_along[a] - s_along[b])
        gap_mm = np.minimum(gap_mm, loop_length[loop_of[a]] - gap_mm)
        touch = (loop_of[a] != loop_of[b]) | (gap_mm > _TOUCH_MIN_STEPS_APART * step_mm)
        if touch.any():
            k = int(np.flatnonzero(touch)[0])
            return LoopDefect("touch", (int(loop_of[a[k]]), int(loop_of[b[k]])),
                              tuple(float(v) for v in p0[a[k]]))
    for i, hole in enumerate(pts[1:], 1):
        where = tuple(float(v) for v in hole[0])
        if not points_in_polygon(pts[0], hole[:1])[0]:
            return LoopDefect("outside", (i, 0), where)
        for j, other in enumerate(pts[1:], 1):
            if j != i and points_in_polygon(other, hole[:1])[0]:
                return LoopDefect("nested", (i, j), where)
    return None
