"""Wire-EDM rules on profiles with known answers, and on the paper's ring."""

import math

import pytest

from springcad.config import ManufacturingSpec
from springcad.design.curves import Arc, Circle, Line, Loop, Profile
from springcad.geometry.edm import edm_rules

MFG = ManufacturingSpec()  # wire 0.25, spark gap 0.025 -> inside radius 0.15; slot 0.35; web 0.4


def square(half, cx=0.0, cy=0.0, ccw=True):
    p = [(cx - half, cy - half), (cx + half, cy - half), (cx + half, cy + half), (cx - half, cy + half)]
    if not ccw:
        p = p[::-1]
    return Loop(tuple(Line(p[i], p[(i + 1) % 4]) for i in range(4)))


def slot(width, length, cx=0.0, cy=0.0):
    """Obround hole along x, full-round ends (radius width/2)."""
    r, h = 0.5 * width, 0.5 * length
    return Loop((Line((cx - h, cy - r), (cx + h, cy - r)),
                 Arc((cx + h, cy), r, -math.pi / 2, math.pi / 2),
                 Line((cx + h, cy + r), (cx - h, cy + r)),
                 Arc((cx - h, cy), r, math.pi / 2, 1.5 * math.pi)))


def rules(profile, tol=0.02, describe=lambda x, y: "", mfg=None):
    return {r.rule: r for r in edm_rules(profile, mfg or MFG, tol, describe)}


def test_slight_concave_kink_is_a_note_not_a_violation():
    """A 10 deg kink leaves rho (sec 5 deg - 1) = 0.57 um uncut: below a tenth of 0.02 mm."""
    a = math.radians(10.0)
    hole = Loop((Line((0.0, 0.0), (2.0, 0.0)), Line((2.0, 0.0), (2.0 + 2 * math.cos(a), 2 * math.sin(a))),
                 Line((2.0 + 2 * math.cos(a), 2 * math.sin(a)), (0.0, 3.0)), Line((0.0, 3.0), (0.0, 0.0))))
    res = rules(Profile(square(10.0), (hole,)))["inside_corner_radius"]
    kink = [n for n in res.notes if abs(n["turn_deg"] - 10.0) < 1e-6]
    assert len(kink) == 1 and kink[0]["inside"]
    assert kink[0]["uncut_mm"] == pytest.approx(0.15 * (1 / math.cos(a / 2) - 1), rel=1e-9)
    assert not any(v["x_mm"] == pytest.approx(2.0) for v in res.violations)
    # the other three corners of this hole are sharp and real violations
    assert len(res.violations) == 3


def test_outside_corners_may_be_sharp_inside_corners_may_not():
    plate = rules(Profile(square(10.0)))
    assert plate["inside_corner_radius"].passed
    square_hole = rules(Profile(square(10.0), (square(1.0),)))
    res = square_hole["inside_corner_radius"]
    assert not res.passed and len(res.violations) == 4
    corners = sorted((round(v["x_mm"], 6), round(v["y_mm"], 6)) for v in res.violations)
    assert corners == [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    assert all(v["value_mm"] == 0.0 for v in res.violations)


def test_slot_width_closed_form():
    res = rules(Profile(square(10.0), (slot(0.3, 4.0, cy=2.0),)))
    assert res["min_slot_width"].value_mm == pytest.approx(0.3, abs=1e-3)
    assert not res["min_slot_width"].passed
    assert all(abs(v["y_mm"] - 2.0) < 0.2 for v in res["min_slot_width"].violations)
    # full-round ends of radius 0.15 are exactly the smallest radius the wire cuts
    assert res["inside_corner_radius"].passed
    assert res["inside_corner_radius"].value_mm == pytest.approx(0.15, abs=1e-9)
    wide = rules(Profile(square(10.0), (slot(0.5, 4.0),)))
    assert wide["min_slot_width"].passed
    assert wide["min_slot_width"].value_mm == pytest.approx(0.5, abs=1e-3)


def test_web_and_hole_edge_closed_form():
    """Two holes of radius 1 with centres 2.3 apart leave a 0.3 mm ligament."""
    holes = (Loop((Circle((-1.15, 0.0), 1.0),)), Loop((Circle((1.15, 0.0), 1.0),)))
    res = rules(Profile(square(10.0), holes))
    web = res["min_web"]
    assert web.value_mm == pytest.approx(0.3, abs=1e-3)
    assert [round(v["x_mm"], 2) for v in web.violations] == [0.0]
    edge = res["hole_edge"]
    assert edge.value_mm == pytest.approx(0.3, abs=1e-4)
    assert len(edge.violations) == 2  # both holes are too close to each other
    far = rules(Profile(square(10.0), (Loop((Circle((0.0, 0.0), 1.0),)),)))
    assert far["hole_edge"].value_mm == pytest.approx(9.0, abs=1e-4)
    assert far["min_web"].passed and far["hole_edge"].passed


def test_s1_ring_against_its_design(ring_s1):
    s = ring_s1.spring
    res = rules(s.ring, s.manufacturing.t_spring_mm, ring_s1.describe)
    # the narrowest void between neighbouring flexures is the design's own clearance
    assert res["min_slot_width"].value_mm == pytest.approx(s.min_neighbour_clearance_mm, abs=2e-3)
    # the flexure is thinnest where its edges meet the neck fillets: no wider than the
    # distance between the two tangency points; the design keeps that web at
    # at least 1.002 x min_web_mm (smooth maximum), so the 0.4 mm rule holds
    flexures = s.ring.loop("flexures")
    neck = math.dist(flexures.named("edge", 0, "right")[-1].end,
                     flexures.named("edge", 0, "left")[0].start)
    web = res["min_web"]
    assert 0.9 * neck <= web.value_mm <= neck + 1e-3
    assert web.passed and 1.0 < web.value_mm / s.manufacturing.min_web_mm < 1.1
    # fillets are at least the wire radius + spark gap and tangent: no concave kinks
    corner = res["inside_corner_radius"]
    assert corner.passed and corner.value_mm == pytest.approx(s.neck_fillet_radius_mm)
    assert not [n for n in corner.notes if n["inside"]]
    assert res["hole_edge"].value_mm == pytest.approx(
        0.5 * (s.outer_radius_mm - s.root_radius_mm) - 0.5 * s.hole_diameter_mm, abs=1e-3)


def test_violation_locations_name_flexures(ring_s1):
    import dataclasses

    strict = dataclasses.replace(ring_s1.spring.manufacturing, min_web_mm=0.45)
    res = rules(ring_s1.spring.ring, describe=ring_s1.describe, mfg=strict)
    feats = [v["feature"] for v in res["min_web"].violations]
    assert sorted(feats) == sorted(f"flexure {k} tip" for k in range(ring_s1.n_flexures))
    for v in res["min_web"].violations:  # each location lies at its flexure's angle
        k = int(v["feature"].split()[1])
        expected = 90.0 + 360.0 * k / ring_s1.n_flexures
        assert abs((v["angle_deg"] - expected + 180) % 360 - 180) < 180 / ring_s1.n_flexures


def test_hole_edge_per_hole_equals_the_brute_force_minimum():
    """Each hole's edge distance (the rule now queries one tree per other loop) equals the
    smallest distance from its samples to every sample of every other loop (all pairs), and
    the reported location is the midpoint of that pair; and the closed forms of the holes'
    distances to the plate edge and to each other."""
    import numpy as np
    from scipy.spatial.distance import cdist

    from springcad.geometry.edm import CURVE_STEP_MM, hole_edge_rule

    holes = (Loop((Circle((-6.0, 0.0), 1.0),)), Loop((Circle((-3.5, 0.4), 1.2),)),
             Loop((Circle((5.0, 6.5), 2.0),)), slot(1.0, 4.0, 2.0, -5.0))
    profile = Profile(square(10.0), holes)
    got = hole_edge_rule(profile, 100.0, lambda x, y: "").violations  # every hole reported
    pts = [lp.sample(CURVE_STEP_MM) for lp in profile.loops]
    circles = [1, 2, 3]  # the slot (loop 4) is not a round hole
    assert len(got) == len(circles)
    for i, v in zip(circles, got):
        others = np.vstack([p for j, p in enumerate(pts) if j != i])
        d = cdist(pts[i], others)
        a, b = np.unravel_index(np.argmin(d), d.shape)
        assert v["value_mm"] == d[a, b]
        assert (v["x_mm"], v["y_mm"]) == tuple(0.5 * (pts[i][a] + others[b]))
    # hole 1 to hole 2: centres sqrt(2.5^2 + 0.4^2) apart; hole 3 to the plate's top edge
    assert got[0]["value_mm"] == pytest.approx(math.hypot(2.5, 0.4) - 2.2, abs=1e-3)
    assert got[2]["value_mm"] == pytest.approx(10.0 - 6.5 - 2.0, abs=1e-3)


def test_facing_pairs_in_blocks_equal_one_block(ring_s1, monkeypatch):
    """The pair search works in blocks of pairs (its arrays bounded to a few MB): blocks that
    split the ring's pairs anywhere give the same distances, midpoints and sides, bit for
    bit, as all pairs at once."""
    import numpy as np

    from springcad.geometry import edm

    monkeypatch.setattr(edm, "PAIR_BLOCK", 10 ** 9)
    whole = edm._facing_pairs(ring_s1.spring.ring, 0.8)
    monkeypatch.setattr(edm, "PAIR_BLOCK", 997)
    blocks = edm._facing_pairs(ring_s1.spring.ring, 0.8)
    assert len(whole[0]) > 10 * 997
    for a, b in zip(whole, blocks):
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    assert np.any(whole[2]) and not np.all(whole[2])  # both webs and slots among them
