"""Parametric parts against their design values and closed forms."""

import dataclasses
import math

import pytest

from springcad.errors import GeometryError
from springcad.geometry.base import face_area_mm2, mesh_volume_mm3, solid_volume_mm3
from springcad.geometry.profile import profile_face


def test_ring_keeps_design_values(ring_s1, s1_design):
    s = s1_design.springs["S1"]
    assert ring_s1.n_flexures == s.n_flexures == 28
    assert ring_s1.contact_radius == s.contact_radius_mm == 5.5
    assert ring_s1.tip_radius == s.tip_radius_mm == 0.3
    assert ring_s1.outer_radius == s.outer_radius_mm
    assert ring_s1.thickness == s.thickness_mm
    assert ring_s1.hole_diameter == s.hole_diameter_mm
    assert len(ring_s1.hole_centres) == 7


def test_ring_volume_is_profile_area_times_thickness(ring_s1):
    """Divergence-theorem volume of the solid against the kernel's exact face area x z."""
    face = profile_face(ring_s1.info.cut_profile, "ring")
    expected = face_area_mm2(face) * ring_s1.thickness
    assert solid_volume_mm3(ring_s1.solid) == pytest.approx(expected, rel=1e-6)
    # and against the design's own area (sampled exact curves)
    assert solid_volume_mm3(ring_s1.solid) == pytest.approx(
        ring_s1.spring.ring.area_mm2() * ring_s1.thickness, rel=1e-5)


@pytest.mark.slow
def test_ring_triangulated_volume_agrees(ring_s1):
    """An independent volume (fine triangulation) agrees with area x thickness. The mesh's
    chords cut the flanks by up to the deflection, so its error falls with it (flanks as
    Bezier pieces: -2.1e-4 at 3 um, -7.1e-5 at 1 um, -2.3e-5 at 0.5 um)."""
    expected = ring_s1.spring.ring.area_mm2() * ring_s1.thickness
    assert mesh_volume_mm3(ring_s1.solid, 0.001) == pytest.approx(expected, rel=1e-4)


def test_ring_topology_and_box(ring_s1):
    solid = ring_s1.solid
    assert solid.is_valid
    bb = solid.bounding_box()
    r = ring_s1.outer_radius
    assert (bb.min.X, bb.max.X, bb.min.Y, bb.max.Y) == pytest.approx((-r, r, -r, r), abs=1e-5)
    assert (bb.min.Z, bb.max.Z) == pytest.approx((0.0, ring_s1.thickness), abs=1e-5)
    kinds = [f.geom_type.name for f in solid.faces()]
    # each flexure's two spline flanks as the same number of Bezier pieces, a side face
    # each (springcad.geometry.bezier); two planar end faces
    from springcad.design.curves import Spline
    from springcad.geometry.bezier import spline_beziers

    flanks = [seg for loop in ring_s1.info.cut_profile.loops for seg in loop.segments
              if isinstance(seg, Spline)]
    assert len(flanks) == 2 * ring_s1.n_flexures
    assert kinds.count("EXTRUSION") == sum(len(spline_beziers(f)[0]) for f in flanks)
    assert kinds.count("PLANE") == 2


def test_camshaft_teeth_and_hub(cam_s1, s1_design):
    s = s1_design.springs["S1"]
    assert cam_s1.n_teeth == 28
    assert cam_s1.tip_radius == pytest.approx(s.cam_tip_radius_mm)
    assert cam_s1.hub_length == s.hardware.camshaft_hub_length_mm
    solid = cam_s1.solid
    bb = solid.bounding_box()
    # outermost material: the tooth tip arc radius (not reached on the axes exactly)
    r_max = max(math.hypot(v.X, v.Y) for v in solid.vertices())
    assert r_max == pytest.approx(cam_s1.tip_radius, abs=1e-6)
    assert (bb.min.Z, bb.max.Z) == pytest.approx((-cam_s1.hub_length, cam_s1.toothed_length), abs=1e-5)
    teeth = cam_s1.info.cut_profile.area_mm2() * cam_s1.toothed_length
    hub = cam_s1.slabs[0].region.area_mm2() * cam_s1.hub_length
    assert solid_volume_mm3(solid) == pytest.approx(teeth + hub, rel=1e-5)
    assert cam_s1.bore == "d_flat"  # no alignment shaft in a single spring
    # the turned hub stays inside the wire path at the pocket bottoms
    wire = s.manufacturing.min_inside_radius_mm
    assert cam_s1.hub_radius + 1e-9 < cam_s1.root_radius - 0.0 <= cam_s1.hub_radius + wire


def test_d_shaft_area_closed_form(s1_stack):
    """Torque D shaft: circle minus the segment below the flat, minus the two rounded corners."""
    from springcad.design.cam import d_bore

    shaft = s1_stack.instance("input_torque_shaft").part
    r, f = 0.5 * shaft.diameter, shaft.flat_ratio
    sharp = math.pi * r ** 2 - r ** 2 * (math.acos(f) - f * math.sqrt(1 - f ** 2))
    assert abs(d_bore(r, f).signed_area()) == pytest.approx(sharp, rel=1e-12)
    rf = s1_stack.design.springs["S1"].manufacturing.min_inside_radius_mm
    rounded = d_bore(r, f, rf)
    # two straight-straight corners of the same interior angle would lose
    # rf^2 (cot(a/2) - (pi - a)/2) each; the arc side loses a little more
    a = math.pi - math.atan2(math.sqrt(1 - f * f), f)
    lines_only = 2 * rf ** 2 * (1 / math.tan(a / 2) - (math.pi - a) / 2)
    loss = sharp - abs(rounded.signed_area())
    assert lines_only < loss < 1.2 * lines_only
    assert solid_volume_mm3(shaft.solid) == pytest.approx(
        abs(rounded.signed_area()) * shaft.length, rel=1e-6)


def test_annular_parts_closed_form(stack_4xs1):
    for name in ("rim_spacer_1", "centre_spacer_1", "rim_washer_2", "outer_bushing",
                 "alignment_shaft", "dowels_1_1"):
        part = stack_4xs1.instance(name).part
        holes = len(part.hole_centres) * math.pi * part.hole_diameter ** 2 / 4
        area = math.pi * (part.outer_radius ** 2 - part.inner_radius ** 2) - holes
        assert solid_volume_mm3(part.solid) == pytest.approx(area * part.length, rel=1e-9), name


def test_components_are_the_source_of_sizes(stack_4xs1):
    """Every placed part spans exactly its Component's axial range."""
    for inst in stack_4xs1.instances:
        c = inst.component
        z0, z1 = inst.z_range_mm
        assert (z0, z1) == pytest.approx((c.z_mm, c.z_mm + c.length_mm), abs=1e-9), inst.name


def test_shared_camshaft_needs_full_travel(s1_design):
    from springcad.geometry.disk import Camshaft

    s = s1_design.springs["S1"]
    cam = Camshaft(s, 4.5, 0.0, "round", "", 4.0, 0.8)
    cam.check_members([s])
    wide = dataclasses.replace(s, spec=dataclasses.replace(
        s.spec, max_deflection_rad=1.01 * cam.travel_rad))
    with pytest.raises(GeometryError, match="cover .* less than spring S1"):
        cam.check_members([wide])
    other = dataclasses.replace(s, n_flexures=27)
    with pytest.raises(GeometryError, match="differ in flexure count"):
        cam.check_members([other])


def test_screw_size_must_be_catalogue(s1_design):
    from springcad.geometry.fasteners import RimScrew

    with pytest.raises(GeometryError, match="fastener_diameter_mm = 1.5 is not a size"):
        RimScrew("SCREW", 1.5, 9.5, 1.6)
    screw = RimScrew("SCREW", 2.0, 9.5, 1.6)
    assert screw.solid.is_valid
    assert screw.length >= 9.5 + 1.6
