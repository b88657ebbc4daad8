"""What holds each camshaft along the axis, as the drawings state it, against the solids.

Issue 26 / shop review 6: the package never said what keeps a camshaft in its ring. The
end camshaft's drawing names its hub end face as the face it is held by: directly by the
user's drive where a D shaft slides through the bore (the shaft is one prism, no shoulder),
or through the bottom of the torque shaft's socket, which must then touch the hub end face
in the stacked solids. A floating camshaft runs between the centre spacers beside it.
"""

import pytest
from cad_fixtures import assembly

from springcad.export.vendor import axial_location


def _axial_note(part) -> str:
    notes = [n for n in part.info.notes if n.startswith("Axial location:")]
    assert len(notes) == 1, (part.part_number, part.info.notes)
    return notes[0]


@pytest.mark.parametrize("stack", ["default", "4xS1"])
def test_every_camshaft_states_its_axial_location_and_the_solids_agree(stack):
    a = assembly(stack)
    cams = [i for i in a.instances if i.part.info.kind == "camshaft"]
    shafts = {i.role: i for i in a.instances if i.part.info.kind == "torque_shaft"}
    assert cams and shafts
    kinds = set()
    for cam in cams:
        note = _axial_note(cam.part)
        if not cam.part.hub_length:
            kinds.add("floating")
            assert "between the centre spacers" in note
            lo, hi = cam.z_range_mm
            beside = sorted(i.z_range_mm for i in a.instances
                            if i.part.info.kind == "centre_spacer")
            assert any(abs(z1 - lo) < 1e-6 for _, z1 in beside), (lo, beside)
            assert any(abs(z0 - hi) < 1e-6 for z0, _ in beside), (hi, beside)
            continue
        shaft = shafts[cam.role]
        part = shaft.part
        if part.style == "hub_socket":
            kinds.add("socket")
            assert "bottom of the torque shaft's socket" in note
            # the socket bottom (part z = stickout) and the hub's end face coincide
            bottom = shaft.placement.map_z(part.stickout, part.stickout)[0]
            hub_end = cam.placement.map_z(-cam.part.hub_length, -cam.part.hub_length)[0]
            assert bottom == pytest.approx(hub_end, abs=1e-9), (cam.name, bottom, hub_end)
        else:
            kinds.add("d_shaft")
            assert "slides in the bore and retains nothing" in note
            assert len(part.slabs) == 1  # one prism: no shoulder holds the camshaft
            assert "holding the camshaft along the axis" in " ".join(part.info.notes)
    assert kinds == ({"d_shaft"} if stack == "default" else {"socket", "floating"})


def test_vendor_readme_states_the_axial_location():
    from springcad.export.vendor import readme_text
    from springcad.export.release import ReleaseStatus

    a = assembly("default")
    text = readme_text(a, ReleaseStatus(()), "default", [], {})
    expect = axial_location(end_hubs=True, flanges=False)
    assert " ".join(text.split()).endswith(" ".join(("AXIAL LOCATION: " + expect).split()))
    assert "end camshafts (by their hub end faces" in expect


def test_axial_location_of_a_stack_with_rim_flanges():
    """Review 7 item 2.2: a stack driven at its rims has no end camshafts; the text names the
    flanges and the floating camshafts at the stack ends."""
    text = axial_location(end_hubs=False, flanges=True)
    assert "end camshafts" not in text and "hub" not in text
    assert "rim flanges (by their outer faces)" in text
    assert "camshafts at the stack ends and the alignment shaft" in text
