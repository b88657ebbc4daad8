"""Public parametric parts for build123d users (issue 23): sc.FlexureRing, sc.Camshaft and
Build.compound, held against the design's own numbers (areas from the planar profiles,
radii, the stack's component list), not against the solids themselves."""

from __future__ import annotations

import math

import pytest

import springcad as sc
from springcad.errors import ConfigError
from tests.conftest import template

#: OCCT's volume of a z-prism of B-spline/arc profiles against the design's polygon area
#: (the profile sampled finely): measured 3.2e-6 (ring) and 1.4e-6 (cam) on paper_S1
REL_VOLUME = 2e-5


@pytest.fixture(scope="module")
def s1():
    return sc.design_job(template("paper_S1"))


def test_flexure_ring_is_the_designed_disk(s1):
    spring = s1.springs["S1"]
    ring = sc.FlexureRing(spring)
    from build123d import Part

    assert isinstance(ring, Part)
    density = spring.raw.material.material.density_kg_per_mm3
    # the design's mass (planar area of its profile x thickness x density)
    assert ring.volume == pytest.approx(spring.mass_kg / density, rel=REL_VOLUME)
    box = ring.bounding_box()
    r, z = spring.outer_radius_mm, spring.thickness_mm
    assert (box.min.X, box.min.Y, box.min.Z) == pytest.approx((-r, -r, 0.0), abs=1e-6)
    assert (box.max.X, box.max.Y, box.max.Z) == pytest.approx((r, r, z), abs=1e-6)
    assert ring.n_flexures == spring.n_flexures and ring.info.name == "S1-RING"
    # the internal design is taken as well as the API's Spring
    assert sc.FlexureRing(spring.raw).volume == pytest.approx(ring.volume, rel=1e-12)


def test_camshaft_is_the_designed_cam(s1):
    spring = s1.springs["S1"]
    raw = spring.raw
    cam = sc.Camshaft(spring)
    z = spring.thickness_mm
    assert cam.volume == pytest.approx(raw.cam_area_mm2 * z, rel=REL_VOLUME)
    box = cam.bounding_box()
    assert (box.min.Z, box.max.Z) == pytest.approx((0.0, z), abs=1e-6)
    # N tooth tips on the tip radius: the box's half width is the tip radius times the
    # cosine of the angle from the nearest tip to an axis (at most pi/N)
    half = max(box.max.X, box.max.Y, -box.min.X, -box.min.Y)
    tip, n = raw.cam_tip_radius_mm, raw.n_flexures
    assert tip * math.cos(math.pi / n) - 1e-6 <= half <= tip + 1e-6
    assert half > raw.cam_root_radius_mm
    longer = sc.Camshaft(spring, toothed_length_mm=2 * z)
    assert longer.volume == pytest.approx(2 * cam.volume, rel=1e-6)


def test_parts_refuse_what_is_not_one_spring(s1):
    with pytest.raises(ConfigError, match=r"spring.*one designed spring.*design\.springs\['S1'\]"):
        sc.FlexureRing(s1)
    with pytest.raises(ConfigError, match="spring"):
        sc.Camshaft("S1")
    with pytest.raises(ConfigError, match="toothed_length_mm"):
        sc.Camshaft(s1.springs["S1"], toothed_length_mm=-1.0)


def test_build_compound_is_the_placed_stack(s1):
    built = sc.build(s1)
    comp = built.compound()
    insts = built.assembly.instances
    assert [c.label for c in comp.children] == [i.name for i in insts]
    for child, inst in zip(comp.children, insts):
        c = inst.component
        # the design's component volumes: exact areas, except a camshaft's hub and bore
        # taken as round there (a D bore, a D flat on a hub)
        rel = 0.05 if c.kind == "camshaft" else REL_VOLUME
        assert child.volume == pytest.approx(c.volume_mm3, rel=rel), inst.name
    box = comp.bounding_box()
    comps = [i.component for i in insts]
    radius = s1.raw.stack.to_dict()["envelope_radius_mm"]
    assert (box.min.X, box.max.X) == pytest.approx((-radius, radius), abs=1e-6)
    assert box.min.Z == pytest.approx(min(c.z_mm for c in comps), abs=1e-6)
    assert box.max.Z == pytest.approx(max(c.z_mm + c.length_mm for c in comps), abs=1e-6)
