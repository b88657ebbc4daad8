"""The export read-backs catch a damaged file, and hold the DXF against the very face the
part's solid was made from (issue 22: the reference face is no longer made twice)."""

import re
from pathlib import Path

import pytest

from springcad.export.bundle import WrittenFile, dxf_reference, dxf_references, roundtrip_checks
from springcad.export.dxf import write_dxf
from springcad.export.step import write_part_step
from springcad.geometry.base import face_area_mm2
from springcad.geometry.profile import profile_face


def _ring_files(stack, out: Path) -> tuple:
    """The S1 ring's STEP and DXF written into ``out/parts`` and their WrittenFile records."""
    ring = stack.part_named("S1-RING")
    pn = ring.part_number
    parts = out / "parts"
    parts.mkdir(parents=True, exist_ok=True)
    write_part_step(ring, parts / f"{pn}.step")
    write_dxf(ring.info.cut_profile, parts / f"{pn}.dxf", pn, ring.info.thickness_mm)
    return ring, [WrittenFile(f"parts/{pn}.step", "step", pn),
                  WrittenFile(f"parts/{pn}.dxf", "dxf", pn)]


def _verdicts(stack, out, files) -> dict:
    checks = roundtrip_checks(stack, out, files, references=dxf_references(stack))
    return {c.name: c.passed for c in checks}


def test_reference_face_is_the_solids_and_equals_a_new_one(s1_stack):
    """The DXF reference (area, perimeter) of a fresh face and of the remembered one agree
    to the last bit, and an unchecked call returns the remembered face itself."""
    ring = s1_stack.part_named("S1-RING")
    prof = ring.info.cut_profile
    fresh = profile_face(prof, "ring")  # a checked call always makes a new face
    assert profile_face(prof, "ring", check=False) is fresh
    area, perimeter = dxf_reference(ring)
    assert area == face_area_mm2(fresh)
    assert perimeter == sum(e.length for e in fresh.edges())


def test_intact_files_pass(s1_stack, tmp_path):
    _, files = _ring_files(s1_stack, tmp_path)
    assert _verdicts(s1_stack, tmp_path, files) == {"step_roundtrip": True,
                                                     "dxf_roundtrip": True}


def test_step_with_a_larger_rim_fails(s1_stack, tmp_path):
    """The ring's outer rim circle 1 % larger in the STEP text: the solid read back is not
    the part (bounding box, volume or validity). (A lone vertex moved off its curves is not
    a different solid to the kernel, which builds the shape from the curves: the read-back
    passes it, rightly.)"""
    ring, files = _ring_files(s1_stack, tmp_path)
    path = tmp_path / files[0].path
    text = path.read_text()
    circles = list(re.finditer(r"CIRCLE\('[^']*',#\d+,([-\d.E+]+)\)", text))
    radius = max(float(m.group(1)) for m in circles)
    assert radius == pytest.approx(ring.solid.bounding_box().max.X, abs=1e-3)
    rim = [m for m in circles if float(m.group(1)) == radius]
    for m in reversed(rim):
        grown = m.group(0).replace(m.group(1), repr(radius * 1.01))
        text = text[:m.start()] + grown + text[m.end():]
    path.write_text(text)
    assert _verdicts(s1_stack, tmp_path, files) == {"step_roundtrip": False,
                                                     "dxf_roundtrip": True}


def test_truncated_step_fails(s1_stack, tmp_path):
    """A STEP cut off halfway (a disk full, a killed writer) is a failed check, not a crash."""
    _, files = _ring_files(s1_stack, tmp_path)
    path = tmp_path / files[0].path
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    assert _verdicts(s1_stack, tmp_path, files)["step_roundtrip"] is False


@pytest.mark.parametrize("damage", ["drop an arc", "grow an arc"])
def test_damaged_dxf_fails(s1_stack, tmp_path, damage):
    """A DXF with one cut entity missing (an open contour) or one arc's radius 0.05 mm
    larger (its ends leave their neighbours': the contour no longer closes) fails its
    read-back."""
    import ezdxf

    _, files = _ring_files(s1_stack, tmp_path)
    path = tmp_path / files[1].path
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    if damage == "drop an arc":
        msp.delete_entity(msp.query("ARC")[0])
    else:
        arc = msp.query("ARC")[0]
        arc.dxf.radius += 0.05
    doc.saveas(path)
    assert _verdicts(s1_stack, tmp_path, files) == {"step_roundtrip": True,
                                                     "dxf_roundtrip": False}
