"""The planar toolkit: point-in-region against closed forms, validity defects, sampling."""

import math

import numpy as np
import pytest

from springcad.design.curves import Arc, Circle, Feature, Line, Loop, Profile, Spline
from springcad.design.planar import (_repeat_runs, find_defect, inside_region,
                                     points_in_polygon, sample_loop)


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


def _comb(n: int, width: float, r_in: float = 10.0, r_out: float = 30.0) -> Loop:
    """An n-fold comb: each repeat a tooth from r_in out to r_out, ``width`` pitches wide
    there, and back (feature index = repeat, as the ring's flexures); wider than about a
    pitch, each tooth's tip crosses the next tooth's edge."""
    pitch = 2 * math.pi / n

    def at(r, a):
        return (r * math.cos(a), r * math.sin(a))

    segs, feats = [], []
    for k in range(n):
        a = k * pitch
        p = [at(r_in, a), at(r_out, a + 0.2 * pitch), at(r_out, a + (0.2 + width) * pitch),
             at(r_in, a + pitch)]
        segs += [Line(p[0], p[1]), Line(p[1], p[2]), Line(p[2], p[3])]
        feats += [Feature("edge", k), Feature("tip", k), Feature("edge", k)]
    return Loop(tuple(segs), tuple(feats))


@pytest.mark.parametrize("width, hole_at_deg, kind", [
    (0.3, None, None),          # a clean comb
    (1.5, None, "cross"),       # each tooth's tip runs across the next tooth's edge
    (0.3, 100.0, "cross"),      # a rim hole far from repeat 0 cuts the teeth
    (0.3, 200.0, None),         # the same hole clear of the teeth
])
def test_the_symmetric_search_finds_what_the_full_search_finds(width, hole_at_deg, kind):
    """find_defect with ``folds`` (repeat 0's neighbours, and wherever another loop comes
    near) against the full search of every sample, on a 24-fold comb inside a rim: the same
    answer, a defect between far repeats found through its copy at repeat 0, and a hole
    that cuts the teeth found wherever it lies."""
    holes = [_comb(24, width)]
    names = ["outer", "flexures"]
    if hole_at_deg is not None:
        a = math.radians(hole_at_deg)
        r = 40.0 if hole_at_deg < 180 else 45.0
        holes.append(Loop((Circle((r * math.cos(a), r * math.sin(a)), 10.5),)))
        names.append("hole:0")
    prof = Profile(Loop((Circle((0.0, 0.0), 60.0),)), tuple(holes), tuple(names))
    full = find_defect(prof, 0.05)
    symmetric = find_defect(prof, 0.05, folds={"flexures": 24})
    assert (full and full.kind) == kind
    assert (symmetric and symmetric.kind) == kind
    if kind is not None:
        assert symmetric.loops == full.loops


def test_a_loop_whose_repeats_are_not_copies_is_searched_whole():
    """The shortcut rests on the repeats being copies of repeat 0: a comb whose repeat 12
    alone is too wide is not (its segment ends are not repeat 0's turned), so it is
    searched whole and its defect found; nor is a loop whose features are not n equal
    runs."""
    clean, wide = _comb(24, 0.3), _comb(24, 1.5)
    mixed = Loop(clean.segments[:36] + wide.segments[36:39] + clean.segments[39:],
                 clean.features)
    prof = Profile(Loop((Circle((0.0, 0.0), 60.0),)), (mixed,), ("outer", "flexures"))
    assert _repeat_runs(clean, 24) == [3] * 24 and _repeat_runs(clean, 7) is None
    assert _repeat_runs(mixed, 24) is None
    assert find_defect(prof, 0.05).kind == "cross"
    assert find_defect(prof, 0.05, folds={"flexures": 24}).kind == "cross"
