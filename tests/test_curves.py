"""Exact 2D curves: closure, areas against closed forms, transforms."""

import math

import numpy as np
import pytest

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline


def d_shape(r=3.0, flat=0.8):
    h = math.acos(flat)
    arc = Arc((0.0, 0.0), r, -math.pi / 2 + h, 1.5 * math.pi - h)
    return Loop((arc, Line(arc.end, arc.start)))


def test_d_shape_area_closed_form():
    r, f = 3.0, 0.8
    h = math.acos(f)
    segment = r * r * (2 * h - math.sin(2 * h)) / 2  # circular segment cut by the flat
    assert abs(d_shape(r, f).signed_area()) == pytest.approx(math.pi * r * r - segment, rel=1e-12)


def test_profile_area_with_holes():
    outer = Loop((Circle((0, 0), 10.0),))
    hole = Loop((Circle((5, 0), 1.0),))
    assert Profile(outer, (hole, d_shape())).area_mm2() == pytest.approx(
        math.pi * 100 - math.pi - abs(d_shape().signed_area()), rel=1e-12)


def test_spline_area_converges_to_parabola_area():
    # region under y = 1 - x^2 on [-1, 1]: 4/3
    x = np.linspace(-1, 1, 41)
    spl = Spline(tuple(zip(x, 1 - x ** 2)), (1 / math.sqrt(5), 2 / math.sqrt(5)),
                 (1 / math.sqrt(5), -2 / math.sqrt(5)))
    loop = Loop((spl, Line(spl.end, spl.start)))
    assert abs(loop.signed_area(0.001)) == pytest.approx(4 / 3, rel=2e-5)


def test_open_loop_is_rejected():
    with pytest.raises(ValueError, match="not closed"):
        Loop((Line((0, 0), (1, 0)), Line((1, 0), (1, 1))))


@pytest.mark.parametrize("angle", [0.3, -2.0])
def test_rotation_and_mirror_keep_area(angle):
    loop = d_shape()
    assert loop.rotated(angle).signed_area() == pytest.approx(loop.signed_area(), rel=1e-12)
    mirrored = Loop(tuple(s.mirrored() for s in reversed(loop.segments)))
    mirrored = Loop(tuple(s.reversed() for s in mirrored.segments))
    assert mirrored.signed_area() == pytest.approx(loop.signed_area(), rel=1e-12)
