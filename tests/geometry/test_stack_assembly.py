"""Stacks of the paper's Table I: they build, check clean and follow the alternation rule."""

import pytest

from cad_fixtures import RIM_INPUT, TABLE_I, assembly
from springcad.geometry.checks import run_checks

HEAVY = {"S1+2xS2", "S2+3xS1", "2xS2 rim", "S2+3xS1 rim"}


def expected_joints(n, inp):
    joints, free = [], "shaft" if inp == "rim" else "rim"
    for _ in range(n - 1):
        joints.append(free)
        free = "shaft" if free == "rim" else "rim"
    return joints, free


@pytest.mark.parametrize("config", [
    pytest.param(c, marks=pytest.mark.slow) if c in HEAVY else c
    for c in [*TABLE_I, *RIM_INPUT]])
def test_table_i_stack_builds_and_checks(config):
    asm = assembly(config)
    sequence, inp = list(asm.design.stack.sequence), asm.design.stack.input
    assert (sequence, inp) == (tuple(RIM_INPUT[config]) if config in RIM_INPUT
                               else (sequence, "shaft"))
    n = len(sequence)
    joints, out = expected_joints(n, inp)
    stack = asm.design.stack
    assert list(stack.joints) == joints and stack.output == out
    # parts are named after the springs in sequence, input side first
    rings = [i for i in asm.instances if i.component.kind == "flexure_ring"]
    assert [r.name for r in rings] == [f"spring_{k + 1}_{s}" for k, s in enumerate(sequence)]
    assert [r.z_range_mm[0] for r in rings] == sorted(r.z_range_mm[0] for r in rings)
    # input and output parts follow the connection kinds
    for end, conn, ring in (("input", inp, rings[0]), ("output", out, rings[-1])):
        names = set(asm.input_names if end == "input" else asm.output_names)
        if conn == "shaft":
            assert any(nm.startswith("camshaft_") for nm in names)
            assert f"{end}_torque_shaft" in names and ring.name not in names
        else:
            assert names == {ring.name, f"{end}_rim_flange"}
    kinds = {i.component.kind for i in asm.instances}
    assert ({"bushing", "alignment_shaft"} <= kinds) == (n >= 3)
    assert ("centre_spacer" in kinds) == ("rim" in joints)
    report = run_checks(asm)
    assert not report.errors, [(c.subject, c.name, c.message) for c in report.errors]
    # the design keeps the neck web and rounds the D bore corners: no rule is broken
    assert not report.violations, [(c.subject, c.name, c.message) for c in report.violations]
    by_name = {c.name: c for c in report.checks if c.subject == "stack"}
    assert by_name["connection_sequence"].passed and by_name["alternation_rule"].passed
    gaps = [c for c in report.checks if c.name == "cam_clearance"]
    assert len(gaps) == n and all(c.passed for c in gaps)


def test_quantities_and_compound(stack_4xs1):
    by_number = stack_4xs1.quantities()
    qty = {stack_4xs1.parts[pn].name: n for pn, n in by_number.items()}
    assert qty["S1-RING"] == 4
    assert qty["S1-CAM-L4.5-H6-R"] == 2  # input and output camshafts: one part, turned over
    assert qty["DOWEL"] == 14
    comps = {c.name: c for c in stack_4xs1.design.stack.components}
    assert qty["DOWEL"] == comps["dowels_1"].count + comps["dowels_3"].count
    compound = stack_4xs1.compound()
    labels = [c.label for c in compound.children]
    assert labels == [i.name for i in stack_4xs1.instances]
    assert len(set(labels)) == len(labels)
    out_cam = stack_4xs1.instance("camshaft_3")
    assert out_cam.placement.flipped
    bb = out_cam.shape.bounding_box()
    assert (bb.min.Z, bb.max.Z) == pytest.approx(out_cam.z_range_mm, abs=1e-5)


def test_floating_camshafts_run_on_the_alignment_shaft(stack_4xs1):
    cams = [i.part for i in stack_4xs1.instances if i.component.kind == "camshaft"]
    assert {c.bore for c in cams} == {"round"}
    ends = [c for c in cams if c.hub_length]
    assert ends and all(c.drive == "hub_flat" for c in ends)
