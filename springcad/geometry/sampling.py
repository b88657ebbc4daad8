"""Dense samples of exact 2D loops with tangents, signed curvature and arc length.

The checks (EDM rules, interference, cam clearance) work on these samples; the
exact curves stay the reference and the sampling step bounds the error (a chord
of length h on a radius R deviates h^2 / (8 R) from the curve). Units: mm, 1/mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline


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
        p, d1, d2 = cs(uu), cs(uu, 1), cs(uu, 2)
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


def profile_paths(profile: Profile, step_mm: float = 0.02):
    """matplotlib Paths of every loop (for point-in-region tests)."""
    from matplotlib.path import Path

    return [Path(loop.sample(step_mm)) for loop in profile.loops]


def inside_region(profile: Profile, xy: np.ndarray, step_mm: float = 0.02, paths=None) -> np.ndarray:
    """Boolean mask: which points lie in the profile's material (inside outer, outside holes)."""
    paths = paths or profile_paths(profile, step_mm)
    mask = paths[0].contains_points(xy)
    for hole in paths[1:]:
        mask &= ~hole.contains_points(xy)
    return mask
