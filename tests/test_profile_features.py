"""Profiles carry named features: every consumer finds a segment by name, not by position."""

import math

import pytest

from springcad.design.curves import Arc, Circle, Feature, Loop, Profile


def test_ring_features_are_complete_and_ordered(paper_designs):
    s = paper_designs["paper_S1"].springs["S1"]
    ring = s.ring
    assert ring.names[:2] == ("outer", "flexures")
    assert len(ring.loops_named("hole")) == len(s.hole_centres_mm)
    flex = ring.loop("flexures")
    for i in range(s.n_flexures):
        kinds = [(f.kind, f.side) for f in flex.features if f.index == i]
        # from the right root fillet round the tip to the left root fillet, then the rim arc
        assert [k for k, _ in kinds if k != "rim"][0] == "root"
        assert ("ball", "") in kinds and ("rim", "") in kinds
        for kind in ("root", "edge", "neck"):
            assert (kind, "right") in kinds and (kind, "left") in kinds
    # flexure i is flexure 0 turned by i pitches, feature by feature
    pitch = 2 * math.pi / s.n_flexures
    b0, = flex.named("ball", 0)
    b5, = flex.named("ball", 5)
    assert b0.rotated(5 * pitch).center == pytest.approx(b5.center, abs=1e-9)
    assert b0.center == pytest.approx((0.0, s.contact_radius_mm), abs=1e-12)
    assert b0.radius == pytest.approx(s.tip_radius_mm)


def test_cam_features(paper_designs):
    s = paper_designs["paper_S1"].springs["S1"]
    teeth, bore = s.cam.loop("teeth"), s.cam.loop("bore")
    pocket, = teeth.named("pocket", 0)
    assert pocket.center == pytest.approx((0.0, s.contact_radius_mm), abs=1e-12)
    assert pocket.radius == pytest.approx(s.tip_radius_mm + s.manufacturing.w_gap_mm, abs=1e-4)
    tip, = teeth.named("tip", 3)
    assert tip.radius == pytest.approx(s.cam_tip_radius_mm)
    flat, = bore.named("flat")
    assert flat.start[1] == pytest.approx(flat.end[1])


def test_fea_labels_follow_the_names(paper_designs):
    from fea.geometry import ring_geometry, sector_geometry

    s = paper_designs["paper_S1"].springs["S1"]
    sec = sector_geometry(s)
    (labels,) = sec.labels
    assert labels.count("ball:0") == 1 and labels.count("root:0") == 2
    ball = sec.profile.outer.segments[labels.index("ball:0")]
    assert ball.center == pytest.approx((0.0, s.contact_radius_mm), abs=1e-12)
    full = ring_geometry(s)
    assert full.labels[1].count("ball:7") == 1
    assert [k for *_, k in sec.fillets_mm].count("root") == 2


def test_unknown_names_say_what_exists():
    loop = Loop((Circle((0.0, 0.0), 1.0),), (Feature("hole", 0),))
    prof = Profile(loop, (), ("outer",))
    with pytest.raises(KeyError, match="it has"):
        prof.loop("flexures")
    with pytest.raises(KeyError, match="no feature 'flat'"):
        loop.named("flat")
    with pytest.raises(ValueError, match="feature names"):
        Loop((Arc((0, 0), 1.0, 0.0, 1.0),), (Feature("a"), Feature("b")))
