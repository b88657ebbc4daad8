"""Non-round holes and pockets need a process that makes them (issue 26): a blind D socket
in a hardened shaft names sinker EDM (or broaching before hardening) in the process list
and on the drawing; a D bore through a turned part is refused; and no ± hole tolerance is
tighter than the part's processes hold. The parts are the built 4xS1 and default stacks,
changed one field at a time with dataclasses.replace."""

from dataclasses import replace

import pytest
from cad_fixtures import assembly

from springcad.design.curves import Profile
from springcad.geometry.base import Slab, circle_loop, d_loop
from springcad.geometry.sheet_cut import fit_rule, internal_features, internal_profile_rule


def _socket_shaft():
    return next(p for p in assembly("4xS1").parts.values() if p.info.kind == "torque_shaft")


def test_features_by_hand():
    """4xS1 torque shaft: one blind pocket, from the stick-out's end to the inner end
    (socket depth = length - stick-out); default end camshaft: its D bore through hub and
    teeth (two slabs, one feature); the flexure ring's cut-out through."""
    shaft = _socket_shaft()
    (loop, kind, z0, z1), = internal_features(shaft.slabs)
    assert kind == "blind"
    assert (z0, z1) == pytest.approx((shaft.stickout, shaft.length))
    assert z1 - z0 == pytest.approx(shaft.socket_depth)
    cam = assembly("default").part_named("S1-CAM-L12-H6")
    feats = internal_features(cam.slabs)
    assert [(k, z0, z1) for _, k, z0, z1 in feats] == [("through", -6.0, 12.0)]
    ring = assembly("default").part_named("S1-RING")
    assert {k for _, k, _, _ in internal_features(ring.slabs)} == {"through"}


def test_sinker_edm_socket_passes_and_names_its_process():
    shaft = _socket_shaft()
    maker, res = internal_profile_rule(shaft.info, shaft.slabs, 0.15)
    assert maker == "sinker_edm" and res.passed
    assert res.value_mm == pytest.approx(0.15) and res.limit_mm == pytest.approx(0.08)
    assert "sinker EDM" in " ".join(shaft.info.notes)


@pytest.mark.parametrize("change,message", [
    (dict(secondary_processes=()), "turned cannot make it; name sinker EDM (after hardening) "
                                   "or broaching before hardening"),
    (dict(secondary_processes=("ground",)), "turned / ground cannot make it"),
    (dict(notes=("D socket: made to the drawing.",)), "made by sinker EDM, which no drawing "
                                                      "note names"),
    (dict(secondary_processes=("broached",), notes=("D socket broached.",)),
     "broached cuts soft steel only"),
])
def test_socket_without_its_process_is_refused(change, message):
    shaft = _socket_shaft()
    _, res = internal_profile_rule(replace(shaft.info, **change), shaft.slabs, 0.15)
    assert not res.passed
    assert any(message in v["feature"] for v in res.violations), res.violations


def test_broaching_before_hardening_passes():
    shaft = _socket_shaft()
    info = replace(shaft.info, secondary_processes=("broached",), notes=("D socket broached.",),
                   heat_treatment_sequence="after turning and broaching the socket")
    maker, res = internal_profile_rule(info, shaft.slabs, 0.15)
    assert maker == "broached" and res.passed


def test_sharp_socket_corner_and_through_d_bore_in_a_turned_part():
    shaft = _socket_shaft()
    r = 0.5 * shaft.outer_radius
    sharp = (Slab(0.0, 5.0, Profile(circle_loop(shaft.outer_radius))),
             Slab(5.0, 10.0, Profile(circle_loop(shaft.outer_radius), (d_loop(r, 0.8, 0.05),))))
    _, res = internal_profile_rule(shaft.info, sharp, 0.15)
    assert res.value_mm == pytest.approx(0.05, abs=2e-3)
    assert any("sinker EDM needs R0.08" in v["feature"] for v in res.violations)
    through = (Slab(0.0, 10.0, Profile(circle_loop(shaft.outer_radius),
                                       (d_loop(r, 0.8, 0.15),))),)
    info = replace(shaft.info, secondary_processes=())
    assert internal_features(through)[0][1] == "through"
    _, res = internal_profile_rule(info, through, 0.15)
    assert any("turned cannot make it" in v["feature"] for v in res.violations)
    # the same bore by wire EDM (the camshafts' D bores) is made
    maker, res = internal_profile_rule(replace(info, process="wire_edm"), through, 0.15)
    assert maker == "edm" and res.passed


def test_hole_tolerance_no_tighter_than_the_process():
    """The rim spacer's clearance holes: ±0.005 by wire EDM (skim cut) is made; the same on a
    laser-cut spacer is refused (the laser holds ±0.05)."""
    spacer = assembly("4xS1").part_named("RIM-SPACER")
    assert spacer.info.process == "wire_edm" and spacer.info.fits["holes"] == "±0.005"
    assert fit_rule(spacer.info).passed
    res = fit_rule(replace(spacer.info, process="laser"))
    assert [v["feature"] for v in res.violations] == [
        "holes ±0.005: laser cut hold ±0.05 at best"]
    assert fit_rule(replace(spacer.info, process="laser", fits={"holes": "±0.05"})).passed


def test_rim_spacer_notes_follow_the_process():
    """4xS1 (wire EDM): the web at the largest hole by hand from the plan, hole circle
    minus half of Ø1.56 + 0.005 minus the inner radius, is at least the 0.4 mm sheet
    (issue 26) and the spacers are cut as a stack; a laser spacer is cut one sheet at a
    time and says nothing of stacks."""
    import math

    spacer = assembly("4xS1").part_named("RIM-SPACER")
    hc = min(math.hypot(*c) for c in spacer.hole_centres)
    web = hc - 0.5 * (1.56 + 0.005) - spacer.inner_radius
    assert spacer.hole_diameter == 1.56 and spacer.length == 0.4
    assert web >= spacer.length - 1e-9
    text = " ".join(spacer.info.notes)
    assert "several sheets clamped as one stack" in text and "thinner" not in text
    laser = type(spacer)("X", spacer.inner_radius, spacer.outer_radius, 0.4,
                         ("aluminium", 2700.0), spacer.hole_centres, 1.68, process="laser")
    assert "one sheet at a time" in laser.info.notes[0]
    assert "stack" not in " ".join(laser.info.notes)
