"""Geometry the kernel cannot make stops with a message naming the part and the cause."""

import dataclasses
import math

import pytest

from springcad.design.curves import Arc, Circle, Loop, Profile, Spline
from springcad.errors import GeometryError
from springcad.geometry.disk import FlexureRing


def with_inner(spring, segments=None, holes=None):
    ring = spring.ring
    flexures = ring.loop("flexures")
    inner = Loop(tuple(segments), flexures.features) if segments is not None else flexures
    holes = holes or ring.loops_named("hole")
    return dataclasses.replace(spring, ring=Profile(
        ring.loop("outer"), (inner, *holes),
        ("outer", "flexures", *(f"hole:{j}" for j in range(len(holes))))))


def position(loop, kind, index=0, side=None):
    """Position in ``loop`` of the first segment of the named feature."""
    return next(i for i, f in enumerate(loop.features)
                if f.kind == kind and f.index == index and (side is None or f.side == side))


def test_hole_cutting_a_flexure(s1_design):
    s = s1_design.springs["S1"]
    holes = list(s.ring.loops_named("hole"))
    holes[0] = Loop((Circle((0.0, 20.0), 0.75),))  # on flexure 0, half way out
    with pytest.raises(GeometryError, match=r"S1-RING: the inner contour and the hole 1 cross"):
        FlexureRing(with_inner(s, holes=holes))


def test_self_intersecting_flexure(s1_design):
    s = s1_design.springs["S1"]
    segs = list(s.ring.loop("flexures").segments)
    k = position(s.ring.loop("flexures"), "edge", side="right")
    edge = segs[k]
    assert isinstance(edge, Spline)
    pts = list(edge.points)
    mid = len(pts) // 2
    x, y = pts[mid]
    pts[mid] = (x - 4.0, y)  # drag the right edge across the left one
    segs[k] = Spline(tuple(pts), edge.start_tangent, edge.end_tangent)
    with pytest.raises(GeometryError, match=r"S1-RING: the inner contour crosses itself at"):
        FlexureRing(with_inner(s, segments=segs))


def test_fillet_that_does_not_fit(s1_design):
    """A root fillet swept the long way round touches the contour it should blend."""
    s = s1_design.springs["S1"]
    segs = list(s.ring.loop("flexures").segments)
    k = position(s.ring.loop("flexures"), "root", side="right")
    a = segs[k]
    assert isinstance(a, Arc)
    segs[k] = Arc(a.center, a.radius, a.start_angle,
                  a.end_angle - math.copysign(2 * math.pi, a.sweep))
    with pytest.raises(GeometryError, match=r"S1-RING: the inner contour touches itself"):
        FlexureRing(with_inner(s, segments=segs))


def test_hole_outside_the_part(s1_design):
    s = s1_design.springs["S1"]
    holes = list(s.ring.loops_named("hole"))
    holes[0] = Loop((Circle((0.0, 40.0), 0.75),))
    with pytest.raises(GeometryError, match=r"hole 1 .* lies outside the outer contour"):
        FlexureRing(with_inner(s, holes=holes))
