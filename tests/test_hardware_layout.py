"""Stack hardware layout: typed plans, the stack height and envelope decided once."""

import dataclasses
import math

import pytest

from springcad.design import plans as pl


def all_plan_classes():
    out, todo = [], [pl.PartPlan]
    while todo:
        cls = todo.pop()
        todo += cls.__subclasses__()
        if cls.KIND and cls.__module__ == pl.__name__:
            out.append(cls)
    return out


@pytest.mark.parametrize("name", ["paper_S1", "paper_2xS2", "paper_4xS1", "paper_S2_3xS1"])
def test_height_and_places_from_the_spring_thicknesses(paper_designs, name):
    st = paper_designs[name].stack
    t = [s.thickness_mm for s in st.springs]
    gap = st.springs[0].hardware.rim_spacer_thickness_mm
    assert st.height_mm == pytest.approx(sum(t) + (len(t) - 1) * gap, abs=1e-12)
    rings = [c for c in st.components if c.kind == "flexure_ring"]
    assert [c.z_mm for c in rings] == pytest.approx(
        [sum(t[:i]) + i * gap for i in range(len(t))], abs=1e-12)
    assert [c.z_mm for c in rings] == list(st.layout.spring_z_mm)
    # every joint part fills the gap between its two springs
    for c in st.components:
        if c.kind in ("rim_spacer", "rim_washer", "centre_spacer"):
            j = c.plan.joint
            assert c.z_mm == pytest.approx(rings[j].z_mm + t[j]) and c.length_mm == gap
    # the parts that span the stack use the same height
    for c in st.components:
        if c.kind in ("bushing", "alignment_shaft"):
            assert (c.z_mm, c.length_mm) == (0.0, st.height_mm)
    r_out = max(s.outer_radius_mm for s in st.springs)
    bushing = [c.plan for c in st.components if c.kind == "bushing"]
    assert st.has_bushing == (len(t) >= 3) == bool(bushing)
    assert st.envelope_radius_mm == (bushing[0].outer_radius_mm if bushing else r_out)


def test_annular_volumes_are_the_closed_form(paper_designs):
    st = paper_designs["paper_4xS1"].stack
    for c in st.components:
        if isinstance(c.plan, pl.AnnulusPlan):
            p = c.plan
            area = math.pi * (p.outer_radius_mm ** 2 - p.inner_radius_mm ** 2) \
                - len(p.hole_centres_mm) * math.pi * p.hole_diameter_mm ** 2 / 4
            assert c.volume_mm3 == pytest.approx(area * c.length_mm, rel=1e-12), c.name


def test_plans_are_frozen_and_written_with_units(paper_designs):
    st = paper_designs["paper_4xS1"].stack
    cam = next(c for c in st.components if c.kind == "camshaft")
    with pytest.raises(dataclasses.FrozenInstanceError):
        cam.plan.hub_length_mm = 1.0
    d = cam.to_dict()
    assert d["kind"] == "camshaft" and d["dims"]["springs"] == cam.plan.springs
    assert d["dims"]["floating"] == (cam.role == "")
    for c in st.components:
        numbers = [k for k, v in c.plan.to_dict().items()
                   if isinstance(v, float) and k not in ("flat_ratio",)]
        assert all(k.endswith("_mm") for k in numbers), (c.kind, numbers)


def test_shape_key_ignores_the_place_only(paper_designs):
    st = paper_designs["paper_4xS1"].stack
    spacers = [c.plan for c in st.components if c.kind == "rim_spacer"]
    assert len(spacers) == 2 and spacers[0].joint != spacers[1].joint
    assert spacers[0].shape_key() == spacers[1].shape_key()
    wider = dataclasses.replace(spacers[0], outer_radius_mm=spacers[0].outer_radius_mm + 0.01)
    assert wider.shape_key() != spacers[0].shape_key()


def test_every_plan_kind_has_a_part_family():
    from springcad.geometry.families import FAMILIES

    kinds = {cls.KIND for cls in all_plan_classes()}
    assert kinds == set(FAMILIES)


def test_unknown_part_kind_is_a_geometry_error(paper_designs):
    from springcad.errors import GeometryError
    from springcad.geometry.families import BuildContext, PartCache, build_component

    @dataclasses.dataclass(frozen=True, kw_only=True)
    class GearPlan(pl.PartPlan):
        KIND = "gear"

    st = paper_designs["paper_S1"].stack
    comp = dataclasses.replace(st.components[0], name="gear_1", plan=GearPlan())
    with pytest.raises(GeometryError, match="gear_1: no part family for component kind 'gear'"):
        build_component(BuildContext(st.springs, PartCache()), comp)


def test_rim_spacers_are_cut_from_stocked_shim_strip(paper_designs):
    """The rim spacer's stock is the table's stainless shim strip (1.4310, stocked as thin
    as the 0.4 mm gap; 6061-T6 sheet is not stocked below ~0.8 mm): its material text,
    EN 10088-1's 7.9 g/cm^3 and its mass by hand (annulus minus the pin holes x gap)."""
    from springcad.materials import material_table

    st = paper_designs["paper_4xS1"].stack
    spacers = [c for c in st.components if c.kind == "rim_spacer"]
    assert len(spacers) == 2  # two rim joints in S1 | S1 - S1 | S1
    strip = material_table()["301_shim"]
    for c in spacers:
        p = c.plan
        assert c.material == strip.description and "1.4310" in c.material
        assert c.density_kg_per_m3 == 7900.0 and c.length_mm == 0.4
        area_mm2 = math.pi * (p.outer_radius_mm ** 2 - p.inner_radius_mm ** 2) \
            - len(p.hole_centres_mm) * math.pi * p.hole_diameter_mm ** 2 / 4
        assert c.mass_kg == pytest.approx(area_mm2 * 0.4 * 7.9e-6, rel=1e-12)
