"""Interference of placed parts and the measured cam-to-tip gap."""

import math

import pytest

from springcad.design.hardware import Component
from springcad.design.plans import FastenerPlan, RimSpacerPlan
from springcad.geometry.interference import NEAR_MM, InterferenceChecker, cam_clearance
from springcad.geometry.spacers import RimSpacer
from springcad.geometry.stack import Instance, Placement

AL = ("aluminium", 2700.0)


def ring_part(r_in, r_out, t=1.0, pn="R"):
    return RimSpacer(pn, r_in, r_out, t, AL)


PLANS = {"rim_spacer": RimSpacerPlan(inner_radius_mm=0.0, outer_radius_mm=1.0, joint=0),
         "fastener": FastenerPlan(type="dowel", diameter_mm=1.0, length_mm=1.0,
                                  hole_centres_mm=(), joint=0)}


def place(name, part, z=0.0, x=0.0, y=0.0, kind="rim_spacer", angle=0.0):
    comp = Component(name, PLANS[kind], "al", 1, 0.0, 0.0, z, 1.0)
    return Instance(name, part, Placement(z, x, y, angle_rad=angle), comp, "", (1, 1, 1))


@pytest.fixture(scope="module")
def checker():
    return InterferenceChecker(assembly=None)


def test_radial_overlap_depth(checker):
    a = place("a", ring_part(5.0, 10.0))
    b = place("b", ring_part(9.7, 12.0, pn="R2"))
    r = checker.pair(a, b)
    assert r.relation == "overlap"
    assert r.depth_mm == pytest.approx(0.3, abs=2e-3)


def test_radial_clearance_and_contact(checker):
    a = place("a", ring_part(5.0, 10.0))
    gap = checker.pair(a, place("b", ring_part(10.05, 12.0, pn="R2")))
    assert gap.relation == "clear" and gap.clearance_mm == pytest.approx(0.05, abs=1e-6)
    touch = checker.pair(a, place("c", ring_part(10.0, 12.0, pn="R3")))
    assert touch.relation == "radial_contact"


def test_axial_contact_needs_shared_area(checker):
    a = place("a", ring_part(5.0, 10.0))
    on_top = checker.pair(a, place("b", ring_part(6.0, 8.0, pn="R2"), z=1.0))
    assert on_top.relation == "axial_contact"
    apart = checker.pair(a, place("c", ring_part(6.0, 8.0, pn="R3"), z=1.1))
    assert apart.relation == "clear"
    beside = checker.pair(a, place("d", ring_part(11.0, 12.0, pn="R4"), z=1.0))
    assert beside.relation == "clear"


def test_coincident_parts_overlap(checker):
    """Identical parts in the same place share every boundary: still an overlap."""
    part = ring_part(5.0, 10.0)
    r = checker.pair(place("a", part), place("b", part))
    assert r.relation == "overlap" and r.depth_mm > 0.005


def test_nested_part_overlaps(checker):
    """A small disc wholly inside a ring's material (no hole for it) overlaps."""
    disc = ring_part(0.0, 0.5, pn="D")
    r = checker.pair(place("a", ring_part(5.0, 10.0)), place("pin", disc, x=7.5, kind="fastener"))
    assert r.relation == "overlap"
    assert r.depth_mm == pytest.approx(min(2.0, NEAR_MM), abs=2e-3)  # deeper: reported as the bound


def test_pin_in_hole_touches(checker):
    plate = RimSpacer("P", 5.0, 10.0, 1.0, AL, hole_centres=((7.5, 0.0),), hole_diameter_mm=1.0)
    r = checker.pair(place("a", plate), place("pin", ring_part(0.0, 0.5, pn="D"), x=7.5,
                                              kind="fastener"))
    assert r.relation == "radial_contact"
    shifted = checker.pair(place("a", plate), place("pin", ring_part(0.0, 0.5, pn="D"), x=7.6,
                                                    kind="fastener"))
    assert shifted.relation == "overlap" and shifted.depth_mm == pytest.approx(0.1, abs=2e-3)


def test_stack_has_no_overlaps(stack_4xs1):
    results = InterferenceChecker(stack_4xs1).all_pairs()
    assert not [r for r in results if r.relation == "overlap"]
    rel = {(r.a, r.b): r.relation for r in results}
    assert rel[("spring_1_S1", "rim_spacer_1")] == "axial_contact"
    assert rel[("spring_1_S1", "dowels_1_1")] == "radial_contact"
    assert rel[("camshaft_2", "alignment_shaft")] == "radial_contact"
    assert rel[("spring_1_S1", "camshaft_1")] == "clear"
    assert rel[("spring_1_S1", "spring_2_S1")] == "clear"


def test_cam_gap_equals_design(s1_stack):
    res = cam_clearance(s1_stack.instance("spring_1_S1"), s1_stack.instance("camshaft_1"))
    gap = res.design_gap_mm
    assert res.kernel_min_mm == pytest.approx(gap, abs=1e-4)
    assert res.sampled_min_mm == pytest.approx(gap, abs=1e-4)
    assert len(res.kernel_by_flexure) == 2


def test_cam_gap_closes_with_rotation(s1_stack):
    """Turning the cam by psi closes the gap by r_c * psi (tangential contact normal)."""
    ring = s1_stack.instance("spring_1_S1")
    cam = s1_stack.instance("camshaft_1")
    psi = 0.002
    turned = Instance("cam", cam.part, Placement(cam.placement.z_mm, angle_rad=psi),
                      cam.component, "", cam.colour)
    res = cam_clearance(ring, turned)
    expected = res.design_gap_mm - ring.part.contact_radius * psi
    assert res.kernel_min_mm == pytest.approx(expected, abs=1.5e-3)
    assert res.sampled_min_mm == pytest.approx(res.kernel_min_mm, abs=1e-4)
    assert math.isclose(res.kernel_min_mm, expected, abs_tol=1.5e-3)
