"""Exact 2D profile geometry: lines, arcs, circles and interpolating splines.

The design step describes every cut contour with these primitives so that the
CAD step (build123d) and the DXF writer (ezdxf) can reproduce true arcs and
splines instead of polylines. Units: mm and rad. Points are ``(x, y)`` tuples.

A :class:`Loop` is a closed chain of segments; a :class:`Profile` is one outer
loop with any number of hole loops (a planar face with holes).

Features by name: the builder of a profile names each loop (``"outer"``,
``"flexures"``, ``"hole:0"``, ``"teeth"``, ``"bore"``) and each segment of a loop
(a :class:`Feature`: kind, repeat index and side, e.g. the right root fillet of
flexure 3). Code outside the builder asks for features by name
(:meth:`Profile.loop`, :meth:`Loop.named`), never by position, so a builder can
change how many segments a feature has without moving anybody's labels.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from springcad.design.numeric import ClampedCubic

Point = tuple[float, float]

#: Two segment ends closer than this (mm) are the same point.
JOIN_TOL_MM = 1e-6


def _rot(p: Point, angle: float) -> Point:
    c, s = math.cos(angle), math.sin(angle)
    return (c * p[0] - s * p[1], s * p[0] + c * p[1])


def _mirror(p: Point) -> Point:
    """Mirror about the y axis (x -> -x)."""
    return (-p[0], p[1])


@dataclass(frozen=True)
class Line:
    """Straight segment from ``start`` to ``end`` (mm)."""

    start: Point
    end: Point

    def sample(self, max_step_mm: float = 0.05) -> np.ndarray:
        n = max(2, int(math.ceil(self.length / max_step_mm)) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        return (1 - t) * np.asarray(self.start) + t * np.asarray(self.end)

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    def reversed(self) -> "Line":
        return Line(self.end, self.start)

    def rotated(self, angle: float) -> "Line":
        return Line(_rot(self.start, angle), _rot(self.end, angle))

    def mirrored(self) -> "Line":
        return Line(_mirror(self.start), _mirror(self.end))


@dataclass(frozen=True)
class Arc:
    """Circular arc (mm, rad).

    Runs from ``start_angle`` to ``end_angle`` about ``center``; counter-clockwise
    when ``end_angle > start_angle``, clockwise otherwise. ``|sweep| < 2*pi``.
    """

    center: Point
    radius: float
    start_angle: float
    end_angle: float

    @property
    def sweep(self) -> float:
        return self.end_angle - self.start_angle

    def point_at(self, angle: float) -> Point:
        return (self.center[0] + self.radius * math.cos(angle),
                self.center[1] + self.radius * math.sin(angle))

    @property
    def start(self) -> Point:
        return self.point_at(self.start_angle)

    @property
    def end(self) -> Point:
        return self.point_at(self.end_angle)

    @property
    def mid(self) -> Point:
        return self.point_at(0.5 * (self.start_angle + self.end_angle))

    @property
    def length(self) -> float:
        return abs(self.sweep) * self.radius

    def sample(self, max_step_mm: float = 0.05) -> np.ndarray:
        n = max(3, int(math.ceil(self.length / max_step_mm)) + 1)
        a = np.linspace(self.start_angle, self.end_angle, n)
        return np.column_stack([self.center[0] + self.radius * np.cos(a),
                                self.center[1] + self.radius * np.sin(a)])

    def reversed(self) -> "Arc":
        return Arc(self.center, self.radius, self.end_angle, self.start_angle)

    def rotated(self, angle: float) -> "Arc":
        return Arc(_rot(self.center, angle), self.radius,
                   self.start_angle + angle, self.end_angle + angle)

    def mirrored(self) -> "Arc":
        return Arc(_mirror(self.center), self.radius,
                   math.pi - self.start_angle, math.pi - self.end_angle)


@dataclass(frozen=True)
class Circle:
    """Full circle (a closed loop on its own), e.g. a bolt hole (mm)."""

    center: Point
    radius: float

    @property
    def length(self) -> float:
        return 2 * math.pi * self.radius

    def sample(self, max_step_mm: float = 0.05) -> np.ndarray:
        n = max(16, int(math.ceil(self.length / max_step_mm)) + 1)
        a = np.linspace(0.0, 2 * math.pi, n)
        return np.column_stack([self.center[0] + self.radius * np.cos(a),
                                self.center[1] + self.radius * np.sin(a)])

    def rotated(self, angle: float) -> "Circle":
        return Circle(_rot(self.center, angle), self.radius)

    def mirrored(self) -> "Circle":
        return Circle(_mirror(self.center), self.radius)


@dataclass(frozen=True)
class Spline:
    """Interpolating cubic spline through ``points`` (mm).

    Parameters are the fit points and, optionally, unit tangents at both ends;
    the curve is parametrised by chord length, which is also what build123d
    (OCC ``GeomAPI_Interpolate``) and ezdxf use for fit-point splines, so the
    three agree to well under a micrometre for the densities used here.
    """

    points: tuple[Point, ...]
    start_tangent: Point | None = None
    end_tangent: Point | None = None

    @property
    def start(self) -> Point:
        return self.points[0]

    @property
    def end(self) -> Point:
        return self.points[-1]

    def parameters(self) -> np.ndarray:
        """Chord-length parameter of each fit point (mm)."""
        p = np.asarray(self.points, dtype=float)
        return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])

    @functools.cached_property
    def _spline(self):
        p = np.asarray(self.points, dtype=float)
        u = self.parameters()
        if self.start_tangent is None or self.end_tangent is None:
            raise ValueError("Spline needs both end tangents")
        # chord-length parameter: |dp/du| ~ 1, so unit tangents are the end derivatives
        return u, ClampedCubic(u, p, self.start_tangent, self.end_tangent)

    @property
    def length(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.sample(0.02), axis=0), axis=1)))

    def sample(self, max_step_mm: float = 0.05) -> np.ndarray:
        u, cs = self._spline
        n = max(len(self.points) * 4, int(math.ceil(u[-1] / max_step_mm)) + 1)
        return cs(np.linspace(0.0, u[-1], n))

    def reversed(self) -> "Spline":
        neg = lambda t: None if t is None else (-t[0], -t[1])  # noqa: E731
        return Spline(tuple(reversed(self.points)), neg(self.end_tangent), neg(self.start_tangent))

    def rotated(self, angle: float) -> "Spline":
        rt = lambda t: None if t is None else _rot(t, angle)  # noqa: E731
        c, s = math.cos(angle), math.sin(angle)  # once: _rot's numbers for every point
        return Spline(tuple((c * x - s * y, s * x + c * y) for x, y in self.points),
                      rt(self.start_tangent), rt(self.end_tangent))

    def mirrored(self) -> "Spline":
        mt = lambda t: None if t is None else _mirror(t)  # noqa: E731
        return Spline(tuple(_mirror(p) for p in self.points),
                      mt(self.start_tangent), mt(self.end_tangent))


Segment = Line | Arc | Spline


@dataclass(frozen=True)
class Feature:
    """Name of one segment of a loop.

    Attributes:
        kind: what the segment is (``"root"``, ``"edge"``, ``"neck"``, ``"ball"``,
            ``"rim"`` on a flexure ring; ``"flank"``, ``"pocket"``, ``"tip"`` on a cam;
            ``"arc"``, ``"corner"``, ``"flat"`` on a D bore ...).
        index: which repeat of the pattern it belongs to (flexure or tooth number).
        side: ``"right"``, ``"left"`` or ``""`` for a feature with no side.
    """

    kind: str
    index: int = 0
    side: str = ""

    @property
    def label(self) -> str:
        """``"kind:index"``: the boundary label the FE model uses."""
        return f"{self.kind}:{self.index}"

    def reindexed(self, shift: int) -> "Feature":
        return Feature(self.kind, self.index + shift, self.side)


def named(features: tuple[Feature, ...], segments: tuple) -> tuple[tuple, tuple[Feature, ...]]:
    """Pair up segments and their features, dropping the zero-length lines :func:`chain` drops."""
    keep = [(s, f) for s, f in zip(segments, features, strict=True)
            if not (isinstance(s, Line) and s.length < JOIN_TOL_MM)]
    return tuple(s for s, _ in keep), tuple(f for _, f in keep)


def _area_term(seg, max_step_mm: float) -> float:
    """Contribution 1/2 * integral (x dy - y dx) of one segment (mm^2)."""
    if isinstance(seg, Circle):
        return math.pi * seg.radius ** 2
    if isinstance(seg, Line):
        (x0, y0), (x1, y1) = seg.start, seg.end
        return 0.5 * (x0 * y1 - x1 * y0)
    if isinstance(seg, Arc):
        (cx, cy), r, a0, a1 = seg.center, seg.radius, seg.start_angle, seg.end_angle
        return 0.5 * (r * r * (a1 - a0) + r * (cx * (math.sin(a1) - math.sin(a0))
                                               - cy * (math.cos(a1) - math.cos(a0))))
    p = seg.sample(max_step_mm)
    return 0.5 * float(np.sum(p[:-1, 0] * p[1:, 1] - p[1:, 0] * p[:-1, 1]))


@dataclass(frozen=True)
class Loop:
    """A closed contour: a single :class:`Circle` or a chain of segments.

    Attributes:
        segments: the chain, each segment starting where the previous one ends.
        features: the name of each segment (same length), or ``()`` for an
            unnamed loop.
    """

    segments: tuple
    features: tuple[Feature, ...] = ()

    def __post_init__(self):
        segs = self.segments
        if self.features and len(self.features) != len(segs):
            raise ValueError(f"loop has {len(segs)} segments but {len(self.features)} feature names")
        if len(segs) == 1 and isinstance(segs[0], Circle):
            return
        for a, b in zip(segs, segs[1:] + segs[:1]):
            gap = math.dist(a.end, b.start)
            if gap > 1e-4:
                raise ValueError(f"loop is not closed: {type(a).__name__} ends {gap:.3g} mm "
                                 f"from the start of the next {type(b).__name__}")

    def sample(self, max_step_mm: float = 0.05) -> np.ndarray:
        """Closed polyline (first point not repeated), shape (n, 2), mm."""
        if self.is_circle:
            (circle,) = self.segments
            return circle.sample(max_step_mm)[:-1]
        return np.vstack([s.sample(max_step_mm)[:-1] for s in self.segments])

    def signed_area(self, max_step_mm: float = 0.01) -> float:
        """Enclosed area (mm^2), positive when counter-clockwise.

        Green's theorem per segment: exact for lines, arcs and circles; splines
        by their sampled polyline (error ~ step^2 x curvature).
        """
        return sum(_area_term(s, max_step_mm) for s in self.segments)

    def rotated(self, angle: float, index_shift: int = 0) -> "Loop":
        """The loop turned by ``angle`` (rad); feature indices shifted by ``index_shift``."""
        return Loop(tuple(s.rotated(angle) for s in self.segments),
                    tuple(f.reindexed(index_shift) for f in self.features))

    @property
    def is_circle(self) -> bool:
        """True for a loop that is one full circle (a round hole)."""
        match self.segments:
            case (Circle(),):
                return True
        return False

    def named(self, kind: str, index: int | None = None, side: str | None = None) -> tuple:
        """The segments whose feature matches (``None`` matches any index or side), in loop order.

        Raises:
            KeyError: the loop has no such feature.
        """
        out = tuple(s for s, f in zip(self.segments, self.features)
                    if f.kind == kind and (index is None or f.index == index)
                    and (side is None or f.side == side))
        if not out:
            raise KeyError(f"loop has no feature {kind!r}"
                           + (f" index {index}" if index is not None else "")
                           + (f" side {side!r}" if side else "")
                           + f"; it has {sorted({f.kind for f in self.features})}")
        return out

    def indices(self, index: int) -> tuple[int, ...]:
        """Positions of the segments of repeat ``index`` (for builders and labellers)."""
        return tuple(i for i, f in enumerate(self.features) if f.index == index)

    @property
    def n_arcs(self) -> int:
        return sum(isinstance(s, (Arc, Circle)) for s in self.segments)


@dataclass(frozen=True)
class Profile:
    """A planar face: one outer loop and zero or more hole loops (mm)."""

    outer: Loop
    holes: tuple[Loop, ...] = field(default_factory=tuple)
    names: tuple[str, ...] = ()
    """Name of each loop, outer first (``()`` for an unnamed profile)."""

    def __post_init__(self):
        if self.names and len(self.names) != 1 + len(self.holes):
            raise ValueError(f"profile has {1 + len(self.holes)} loops but {len(self.names)} names")

    def loop(self, name: str) -> Loop:
        """The loop called ``name``.

        Raises:
            KeyError: no loop has that name.
        """
        for n, lp in zip(self.names, self.loops):
            if n == name:
                return lp
        raise KeyError(f"profile has no loop {name!r}; it has {list(self.names)}")

    def loops_named(self, prefix: str) -> tuple[Loop, ...]:
        """Every loop whose name is ``prefix`` or starts with ``prefix:`` (e.g. all ``hole:j``)."""
        return tuple(lp for n, lp in zip(self.names, self.loops)
                     if n == prefix or n.startswith(prefix + ":"))

    def with_loops(self, prefix: str, loops: tuple[Loop, ...]) -> "Profile":
        """The profile with its ``prefix:j`` hole loops replaced by ``loops`` (named ``prefix:0..``)."""
        keep = [(n, lp) for n, lp in zip(self.names[1:], self.holes)
                if not (n == prefix or n.startswith(prefix + ":"))]
        new = [(f"{prefix}:{j}", lp) for j, lp in enumerate(loops)]
        items = keep + new
        return Profile(self.outer, tuple(lp for _, lp in items),
                       (self.names[0], *(n for n, _ in items)))

    def area_mm2(self, max_step_mm: float = 0.01) -> float:
        return abs(self.outer.signed_area(max_step_mm)) - sum(
            abs(h.signed_area(max_step_mm)) for h in self.holes)

    @property
    def loops(self) -> tuple[Loop, ...]:
        return (self.outer, *self.holes)


def chain(*groups) -> tuple:
    """Flatten segment groups into one tuple, dropping zero-length lines."""
    out = []
    for g in groups:
        for s in (g if isinstance(g, (list, tuple)) else (g,)):
            if isinstance(s, Line) and s.length < JOIN_TOL_MM:
                continue
            out.append(s)
    return tuple(out)
