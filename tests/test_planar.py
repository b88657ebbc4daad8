"""The planar toolkit: point-in-region against closed forms, validity defects, sampling."""

import math

import numpy as np
import pytest

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline
from springcad.design.planar import (find_defect, inside_region, points_in_polygon,
                                     sample_loop)


def square(x0, y0, size):
    p = [(x0, y0), (x0 + size, y0), (x0 + size, y0 + size), (x0, y0 + size)]
    return Loop(tuple(Line(p[k], p[(k + 1) % 4]) for k in range(4)))


#: a hole whose corner (10, 5) lies on the right edge of the square(0, 0, 10)
DIAMOND = [(10.0, 5.0), (8.0, 7.0), (6.0, 5.0), (8.0, 3.0)]


def test_points_in_star_polygon_against_its_polar_form():
    """A star r(t) = 10 + 3 sin(7 t): inside iff r < r(t) at the point's angle."""
    t = np.linspace(0.0, 2 * np.pi, 4001)[:-1]
    r = 10 + 3 * np.sin(7 * t)
    poly = np.column_stack([r * np.cos(t), r * np.sin(t)])
    rng = np.random.default_rng(1)
    xy = rng.uniform(-14, 14, (20000, 2))
    a = np.arctan2(xy[:, 1], xy[:, 0])
    rho = np.hypot(xy[:, 0], xy[:, 1])
    edge = 10 + 3 * np.sin(7 * a)
    clear = np.abs(rho - edge) > 0.05  # the polyline strays < 0.01 mm from the curve
    got = points_in_polygon(poly, xy)
    assert np.array_equal(got[clear], (rho < edge)[clear])
    assert clear.sum() > 19000


def test_inside_region_of_an_annulus_with_a_hole():
    prof = Profile(Loop((Circle((0.0, 0.0), 10.0),)),
                   (Loop((Circle((0.0, 0.0), 4.0),)), Loop((Circle((7.0, 0.0), 1.0),))))
    pts = np.array([[0.0, 0.0], [5.0, 0.0], [7.0, 0.0], [7.0, 1.5], [0.0, 9.9], [0.0, 10.1]])
    assert inside_region(prof, pts).tolist() == [False, True, False, True, True, False]


def test_a_valid_profile_has_no_defect():
    prof = Profile(square(0, 0, 10), (square(2, 2, 2), Loop((Circle((7.0, 7.0), 1.0),))))
    assert find_defect(prof) is None


@pytest.mark.parametrize("holes, kind, loops", [
    ((square(8.013, 4.007, 4),), "cross", (0, 1)),         # a hole sticking out through the edge
    ((square(2, 2, 3), square(4.011, 4.007, 3)), "cross", (1, 2)),
    ((square(20, 20, 2),), "outside", (1, 0)),
    ((square(1, 1, 8), square(3, 3, 2)), "nested", (2, 1)),
    ((Loop(tuple(Line(a, b) for a, b in zip(DIAMOND, DIAMOND[1:] + DIAMOND[:1]))),),
     "touch", (0, 1)),  # a corner on the right edge
])
def test_defects_are_named(holes, kind, loops):
    d = find_defect(Profile(square(0, 0, 10), holes))
    assert d is not None and d.kind == kind
    assert tuple(sorted(d.loops)) == tuple(sorted(loops))


def test_self_crossing_loop():
    bow = [(0, 0), (4, 4), (4, 0), (0, 4)]  # a bow tie: edges 0-1 and 2-3 cross at (2, 2)
    d = find_defect(Profile(Loop(tuple(Line(bow[k], bow[(k + 1) % 4]) for k in range(4)))))
    assert d.kind == "cross" and d.loops == (0, 0)
    assert math.dist(d.point_mm, (2.0, 2.0)) < 2.0


def test_fillet_swept_the_long_way_touches_its_loop():
    """A corner fillet swept the long way round runs back along the edge it should blend."""
    c = (4.0, 1.0)
    good = Loop((Line((0, 0), (4, 0)), Arc(c, 1.0, -math.pi / 2, 0.0), Line((5, 1), (5, 5)),
                 Line((5, 5), (0, 5)), Line((0, 5), (0, 0))))
    assert find_defect(Profile(good)) is None
    bad = Loop((good.segments[0], Arc(c, 1.0, -math.pi / 2, -2 * math.pi), *good.segments[2:]))
    d = find_defect(Profile(bad))
    assert d.kind == "touch" and d.loops == (0, 0)


def test_sampled_loop_length_and_area_match_closed_forms():
    loop = Loop((Line((0, 0), (4, 0)), Arc((4.0, 2.0), 2.0, -math.pi / 2, math.pi / 2),
                 Line((4, 4), (0, 4)), Line((0, 4), (0, 0))))
    s = sample_loop(loop, 0.01)
    assert s.length == pytest.approx(12 + 2 * math.pi, rel=1e-5)
    assert s.signed_area == pytest.approx(16 + 2 * math.pi, rel=1e-5)
    on_arc = s.segment == 1
    assert np.allclose(s.curvature[on_arc], 0.5)
    # the two convex corners of the left side turn by +90 deg each
    assert sorted(np.round(np.degrees(s.corners[:, 3])).tolist()) == [90.0, 90.0]


def test_a_short_finely_sampled_flank_is_not_a_self_touch():
    """A 0.03 mm spline flank (a cam at small deflection) is sampled ~1 um apart; samples
    five apart are neighbours on the curve, not the loop touching itself. The same square
    with a fillet swept the long way is still a touch."""
    flank = Spline(tuple((4.0 + 0.03 * t, 0.004 * t * t) for t in np.linspace(0, 1, 8)),
                   (1.0, 0.0), (0.03, 0.008))
    end = flank.points[-1]
    loop = Loop((Line((0, 0), (4, 0)), flank, Line(end, (5, 5)), Line((5, 5), (0, 5)),
                 Line((0, 5), (0, 0))))
    assert len(flank.sample(0.02)) >= 30  # far finer than the step
    assert find_defect(Profile(loop)) is None
