"""Part numbers name geometry: one number per geometry, the same in every job."""

import pytest

from cad_fixtures import assembly, job_data
from springcad.geometry.base import identity_text, part_number_of


def identity(part) -> str:
    return identity_text(part.info, part.slabs, part.tolerance_mm)


def geometry(part) -> tuple:
    """Measured from the solid, not from the identity text: volume and bounding box."""
    from springcad.geometry.base import solid_volume_mm3

    bb = part.solid.bounding_box()
    return (round(solid_volume_mm3(part.solid), 3),
            tuple(round(v, 4) for v in (bb.min.X, bb.min.Y, bb.min.Z, bb.max.X, bb.max.Y,
                                        bb.max.Z)))


def test_numbers_are_the_family_code_and_a_hash(stack_4xs1):
    for pn, part in stack_4xs1.parts.items():
        code, digest = pn.rsplit("-", 1)
        assert code == part.info.code and len(digest) == 8 and int(digest, 16) >= 0
        assert pn == part_number_of(part.info, part.slabs, part.tolerance_mm)
    assert stack_4xs1.part_named("S1-RING").part_number.startswith("RING-")


@pytest.mark.parametrize("other", ["default", "2xS1", "S2+3xS1"])
def test_jobs_share_a_number_only_for_the_same_geometry(stack_4xs1, other):
    """The issue's collisions: S1-RING and TORQUE-SHAFT rev A were different parts in two jobs."""
    b = assembly(other)
    parts = {**{pn: [p] for pn, p in stack_4xs1.parts.items()}}
    for pn, p in b.parts.items():
        parts.setdefault(pn, []).append(p)
    shared = 0
    for pn, ps in parts.items():
        if len(ps) == 2:
            shared += 1
            assert identity(ps[0]) == identity(ps[1]), pn
            assert geometry(ps[0]) == geometry(ps[1]), pn
    # and different geometry never shares a number: identities and numbers are one to one
    all_parts = list(stack_4xs1.parts.values()) + list(b.parts.values())
    by_identity = {identity(p): p.part_number for p in all_parts}
    assert len(set(by_identity.values())) == len(by_identity)
    if other == "default":  # 72 mm / 29 flexures against 67 mm / 28: nothing in common
        for name in ("S1-RING", "TORQUE-SHAFT"):
            assert stack_4xs1.part_named(name).part_number != b.part_named(name).part_number
    if other == "2xS1":  # the same S1 spring: the same ring
        assert shared >= 1
        assert stack_4xs1.part_named("S1-RING").part_number == b.part_named("S1-RING").part_number


def test_same_geometry_same_number_whatever_the_job_calls_it(ring_s1):
    """Spring S1 renamed "A" in another job: the ring is the same part number."""
    from springcad.config import job_from_dict
    from springcad.design.job import design_job
    from springcad.geometry.disk import FlexureRing

    data = job_data(["S1"])
    data["springs"] = {"A": data["springs"]["S1"]}
    data["stack"]["sequence"] = ["A"]
    data["job"]["name"] = "renamed"
    ring = FlexureRing(design_job(job_from_dict(data)).springs["A"])
    assert ring.name == "A-RING" and ring_s1.name == "S1-RING"
    assert ring.part_number == ring_s1.part_number
    assert geometry(ring) == geometry(ring_s1)


def test_a_change_of_form_fit_or_material_is_a_new_number(ring_s1):
    import dataclasses

    base = part_number_of(ring_s1.info, ring_s1.slabs, ring_s1.tolerance_mm)
    tighter = part_number_of(ring_s1.info, ring_s1.slabs, 0.5 * ring_s1.tolerance_mm)
    other_steel = part_number_of(dataclasses.replace(ring_s1.info, material="17-4 PH H900"),
                                 ring_s1.slabs, ring_s1.tolerance_mm)
    thicker = part_number_of(ring_s1.info, (dataclasses.replace(
        ring_s1.slabs[0], z1_mm=ring_s1.slabs[0].z1_mm + 0.01),), ring_s1.tolerance_mm)
    renamed = part_number_of(dataclasses.replace(ring_s1.info, name="B-RING", title="x",
                                                 notes=("y",)), ring_s1.slabs,
                             ring_s1.tolerance_mm)
    assert len({base, tighter, other_steel, thicker}) == 4
    assert renamed == base  # name, title and notes are documentation (revision), not identity
