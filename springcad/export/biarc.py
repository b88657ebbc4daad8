"""Loops as lines and arcs only: bulge polylines, splines replaced by biarcs.

Many wire-EDM CAM systems take lines and arcs only. A loop becomes one closed
bulge polyline (the DXF LWPOLYLINE model): vertices ``(x, y, bulge)`` where the
bulge ``tan(sweep / 4)`` of a vertex describes the segment that starts there
(0 for a line, > 0 counter-clockwise). Lines, arcs and circles of the design
are exact; a spline is replaced by *biarcs*: pairs of tangent arcs that
match the spline's points and tangents at their ends, split in two (at the
middle of the parameter range) until the largest distance from the spline to
the biarc, measured at :data:`SAMPLES_PER_PIECE` points of each piece, is
within the tolerance. The result is G1 (tangent-continuous) everywhere, as the
spline is. Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Arc, Circle, Line, Loop, Spline

#: spline points per biarc piece at which the deviation is measured
SAMPLES_PER_PIECE = 48
#: an arc whose sagitta is below this is written as a line (mm)
FLAT_SAGITTA_MM = 1e-9
#: smallest parameter interval a spline is split into (mm of chord length)
MIN_PIECE_MM = 1e-6


@dataclass(frozen=True)
class BulgeLoop:
    """A closed loop of lines and arcs.

    Attributes:
        vertices: (n, 3) array of ``(x, y, bulge)``; segment k runs from vertex k to
            vertex k + 1 (the last one back to vertex 0).
        max_deviation_mm: largest measured distance from the design curves (0 for
            loops of lines, arcs and circles only).
        n_biarcs: number of biarcs that replace the loop's splines.
    """

    vertices: np.ndarray
    max_deviation_mm: float = 0.0
    n_biarcs: int = 0

    def segments(self):
        """``(start, end, bulge)`` of every segment."""
        v = self.vertices
        for k in range(len(v)):
            yield v[k, :2], v[(k + 1) % len(v), :2], v[k, 2]

    def area_mm2(self) -> float:
        """Signed enclosed area (mm^2), exact for lines and arcs (> 0 counter-clockwise)."""
        return sum(segment_area_term(a, b, bu) for a, b, bu in self.segments())

    def length_mm(self) -> float:
        """Perimeter (mm), exact for lines and arcs."""
        return sum(segment_length(a, b, bu) for a, b, bu in self.segments())


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def bulge_from_tangent(a, b, tangent) -> float:
    """Bulge of the arc from ``a`` to ``b`` that leaves ``a`` along ``tangent``."""
    chord = np.asarray(b, float) - np.asarray(a, float)
    t = np.asarray(tangent, float)
    half_sweep = math.atan2(_cross(t, chord), float(np.dot(t, chord)))  # tangent-chord angle
    sweep = 2.0 * half_sweep
    if abs(sweep) * np.linalg.norm(chord) / 8.0 < FLAT_SAGITTA_MM:
        return 0.0
    return math.tan(sweep / 4.0)


def arc_centre(a, b, bulge: float) -> tuple[np.ndarray, float, float]:
    """(centre, radius, sweep) of the bulge arc from ``a`` to ``b`` (bulge != 0)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    sweep = 4.0 * math.atan(bulge)
    chord = b - a
    length = float(np.linalg.norm(chord))
    normal = np.array([-chord[1], chord[0]]) / length  # left of the chord
    centre = 0.5 * (a + b) + normal * (0.5 * length / math.tan(0.5 * sweep))
    return centre, 0.5 * length / abs(math.sin(0.5 * sweep)), sweep


def segment_area_term(a, b, bulge: float) -> float:
    """1/2 * integral (x dy - y dx) along one line or bulge arc (mm^2)."""
    area = 0.5 * float(_cross(np.asarray(a, float), np.asarray(b, float)))
    if bulge:
        _, r, sweep = arc_centre(a, b, bulge)
        area += 0.5 * r * r * (sweep - math.sin(sweep))  # circular segment beside the chord
    return area


def segment_length(a, b, bulge: float) -> float:
    chord = float(np.linalg.norm(np.asarray(b, float) - np.asarray(a, float)))
    if not bulge:
        return chord
    _, r, sweep = arc_centre(a, b, bulge)
    return abs(sweep) * r


def _row_norms(v: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(v, axis=1)`` of a real (n, 2) array, the same operations without
    its argument handling (most of its time on the biarc fit's few-point calls)."""
    return np.sqrt(np.add.reduce(v * v, axis=1))


def distance_to_segment(p, a, b, bulge: float) -> np.ndarray:
    """Distance from points ``p`` (n, 2) to one line or bulge arc (mm)."""
    p = np.atleast_2d(np.asarray(p, float))
    a, b = np.asarray(a, float), np.asarray(b, float)
    ends = np.minimum(_row_norms(p - a), _row_norms(p - b))
    if not bulge:
        d = b - a
        t = np.clip(((p - a) @ d) / float(d @ d), 0.0, 1.0)
        return _row_norms(p - (a + t[:, None] * d))
    c, r, sweep = arc_centre(a, b, bulge)
    u, w = a - c, p - c
    phi = np.arctan2(_cross(u, w), w @ u) * math.copysign(1.0, sweep)
    inside = np.mod(phi, 2 * math.pi) <= abs(sweep)
    return np.where(inside, np.abs(_row_norms(w) - r), ends)


def _biarc(p0, t0, p1, t1):
    """Junction point of the equal-tangent-length biarc, or None if it degenerates."""
    v = p1 - p0
    t = t0 + t1
    a = float(t @ t) - 4.0
    bb = -2.0 * float(v @ t)
    c = float(v @ v)
    if abs(a) < 1e-12:  # parallel end tangents
        if abs(bb) < 1e-15:
            return None
        d = -c / bb
    else:
        disc = bb * bb - 4.0 * a * c
        if disc < 0:
            return None
        d = (-bb - math.sqrt(disc)) / (2.0 * a)
    if not (d > 0 and math.isfinite(d)):
        return None
    return 0.5 * ((p0 + d * t0) + (p1 - d * t1))


def spline_biarcs(seg: Spline, tol_mm: float) -> tuple[list[tuple], float, int]:
    """Biarcs of one spline within ``tol_mm``.

    Returns:
        (vertices, max deviation mm, number of biarcs): ``vertices`` are
        ``(x, y, bulge)`` from the spline start up to (not including) its end.

    Raises:
        ValueError: the spline cannot be matched within the tolerance (a piece
            would get shorter than :data:`MIN_PIECE_MM`).
    """
    u_knots, cs = seg._spline
    out, worst, count = [], 0.0, 0
    todo = [(0.0, float(u_knots[-1]))]  # parameter intervals still to match, in curve order
    while todo:
        ua, ub = todo.pop(0)
        # the ends, their tangents and the samples between in one evaluation (elementwise:
        # the numbers of separate calls)
        at = np.concatenate([[ua, ub], np.linspace(ua, ub, SAMPLES_PER_PIECE + 2)[1:-1]])
        points, tangents = cs.derivatives(at, (0, 1))
        (p0, p1), samples = points[:2], points[2:]
        t0, t1 = tangents[0], tangents[1]
        t0, t1 = t0 / np.linalg.norm(t0), t1 / np.linalg.norm(t1)
        j = _biarc(p0, t0, p1, t1)
        if j is not None:
            b0 = bulge_from_tangent(p0, j, t0)
            b1 = -bulge_from_tangent(p1, j, -t1)  # the second arc, traced backwards from p1
            dev = float(np.max(np.minimum(distance_to_segment(samples, p0, j, b0),
                                          distance_to_segment(samples, j, p1, b1))))
            if dev <= tol_mm:
                out += [(p0[0], p0[1], b0), (j[0], j[1], b1)]
                worst, count = max(worst, dev), count + 1
                continue
        if ub - ua < MIN_PIECE_MM:
            raise ValueError(f"spline from ({p0[0]:.4f}, {p0[1]:.4f}) cannot be matched by "
                             f"arcs within {tol_mm:g} mm")
        um = 0.5 * (ua + ub)
        todo[:0] = [(ua, um), (um, ub)]
    return out, worst, count


def loop_bulges(loop: Loop, tol_mm: float) -> BulgeLoop:
    """The loop as one closed bulge polyline; splines as biarcs within ``tol_mm`` (mm)."""
    verts, worst, count = [], 0.0, 0
    for seg in loop.segments:
        if isinstance(seg, Circle):
            (cx, cy), r = seg.center, seg.radius
            verts += [(cx + r, cy, 1.0), (cx - r, cy, 1.0)]  # two counter-clockwise halves
        elif isinstance(seg, Line):
            verts.append((*seg.start, 0.0))
        elif isinstance(seg, Arc):
            n = max(1, math.ceil(abs(seg.sweep) / math.pi - 1e-12))  # |sweep| <= pi per piece
            step = seg.sweep / n
            for k in range(n):
                a = seg.start_angle + k * step
                verts.append((*seg.point_at(a), math.tan(step / 4.0)))
        elif isinstance(seg, Spline):
            v, dev, nb = spline_biarcs(seg, tol_mm)
            verts += v
            worst, count = max(worst, dev), count + nb
        else:
            raise TypeError(f"unknown segment {type(seg).__name__}")
    return BulgeLoop(np.asarray(verts, dtype=float), worst, count)
