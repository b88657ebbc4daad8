"""Vendor drawings carry their dimensions as text; BOM and render are consistent."""

import csv
import math
import xml.etree.ElementTree as ET

import pytest

from pdftext import pdf_text
from springcad.export.bom import write_bom
from springcad.export.drawing import DrawingInfo, load_title_block, write_drawing
from springcad.export.sheet import fmt
from springcad.geometry.base import solid_volume_mm3

INFO = DrawingInfo(job="test-job", quantity=4, revision="C", date="2031-02-03")


def svg_texts(path) -> list[str]:
    root = ET.parse(path).getroot()
    return ["".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text")]


def drawing_texts(part, tmp_path, template=None):
    svg, pdf = write_drawing(part, INFO, tmp_path, template)
    return svg_texts(svg), pdf_text(pdf).splitlines()


def assert_all_in(expected, texts):
    """Every expected text is on the drawing: in one text, or (a long value the title
    block cuts and a note states in full) across the lines of a wrapped note."""
    blob = "\n".join(texts)
    joined = " ".join(" ".join(texts).split())
    missing = [e for e in expected if e not in blob and " ".join(e.split()) not in joined]
    assert not missing, f"missing {missing}"


def title_values(part):
    m = part.info
    return [m.part_number, m.title, m.material, m.heat_treatment or "none",
            f"{fmt(m.thickness_mm)} mm", "4", "mm", "C", "2031-02-03", "test-job"]


def test_ring_drawing_has_its_dimensions(ring_s1, tmp_path):
    r = ring_s1
    bc = 2 * math.hypot(*r.hole_centres[0])
    t = fmt(r.spring.manufacturing.t_spring_mm)
    expected = [f"Ø{fmt(2 * r.outer_radius)}", f"R{fmt(r.contact_radius)} ball centres",
                f"R{fmt(r.tip_radius)}", f"PCD Ø{fmt(bc)}",
                f"{len(r.hole_centres)}× Ø{fmt(r.hole_diameter)} E7 THRU",
                f"{fmt(r.thickness)} ±{t}", f"±{t} mm", "ISO 2768-mK", "48-52 HRC",
                "Heat treatment before EDM", "Ra 0.8 um", "Flatness of each face 0.02 mm",
                f"2× R{fmt(r.neck_fillet_radius)}", f"2× R{fmt(r.root_fillet_radius)}",
                "DETAIL C", "HOLE TABLE"] + title_values(r)
    svg, pdf = drawing_texts(r, tmp_path)
    assert_all_in(expected, svg)
    assert_all_in(expected, pdf)
    # one hole callout: no "thru" beside a "ream to H7" note
    blob = "\n".join(svg).lower()
    assert "ream" not in blob and blob.count("thru") == 1


def test_cam_and_spacer_drawings(stack_4xs1, tmp_path):
    cam = stack_4xs1.part_named("S1-CAM-L4.5-H6-R")
    svg, pdf = drawing_texts(cam, tmp_path)
    expected = [f"Ø{fmt(2 * cam.tip_radius)} tooth tips",
                f"R{fmt(cam.contact_radius)} pocket centres", f"Ø{fmt(cam.bore_diameter)} H7",
                fmt(cam.toothed_length + cam.hub_length), fmt(cam.toothed_length),
                f"Ø{fmt(2 * cam.hub_radius)}", "VIEW B", "DETAIL C"] + title_values(cam)
    assert_all_in(expected, svg)
    assert_all_in(expected, pdf)
    floating = stack_4xs1.part_named("S1-CAM-L9.4-R")
    svg, _ = drawing_texts(floating, tmp_path)
    assert not any("hub" in t.lower() for t in svg)  # no "(hub below)" on a cam without one
    spacer = stack_4xs1.part_named("RIM-SPACER")
    svg, pdf = drawing_texts(spacer, tmp_path)
    # wire-cut (the webs beside its clearance holes are too thin for a laser, issue 26):
    # holes toleranced by the process, no H7, no free-state flatness on a 0.5 mm sheet
    expected = [f"Ø{fmt(2 * spacer.outer_radius)}", f"Ø{fmt(2 * spacer.inner_radius)}",
                f"{len(spacer.hole_centres)}× Ø{fmt(spacer.hole_diameter)} ±0.005 THRU",
                fmt(spacer.length), "every contour and hole main cut and one skim cut", "±0.01 mm", "Stock to order: strip",
                "No free-state flatness requirement",
                "wire EDM"]
    assert_all_in(expected + title_values(spacer), svg + pdf)
    assert spacer.info.process == "wire_edm"
    assert not any("H7" in t or "Flatness of each face" in t for t in svg)
    for part in (spacer, stack_4xs1.part_named("CENTRE-SPACER")):  # notes of their own only
        svg, _ = drawing_texts(part, tmp_path)
        assert not any(w in t.lower() for t in svg for w in ("flexures", "teeth"))


def test_title_block_comes_from_the_template(ring_s1, tmp_path):
    template = load_title_block()
    template["block"]["company"] = "ACME springs test"
    template["rows"][0]["cells"][0]["label"] = "ITEM NAME"
    svg, _ = drawing_texts(ring_s1, tmp_path, template)
    assert "ACME springs test" in svg and "ITEM NAME" in svg


def test_job_name_is_whole_in_the_title_block(stack_4xs1, tmp_path):
    """The JOB cell (shop review 7: "requirements_4xS1_conservative_winner" was cut in a
    42 mm cell) has a row of its own: a 64-character name, the longest the schema allows,
    in the usual letters is whole; the sheet thickness below 0.5 mm, where ISO 2768-1 has
    no general tolerance, carries its own."""
    from springcad.export.drawing import draw_part

    job = "requirements_4xS1_conservative_winner_" + "rev_0123456789_abcdefghijk"
    assert len(job) == 64
    sheet = draw_part(stack_4xs1.part_named("RIM-SPACER"), DrawingInfo(job, 3))
    values = [t for t, (_, role) in zip(sheet.texts, sheet.sizes)
              if role == "title block value"]
    assert job in values, values
    assert "0.4 ±0.05" in sheet.texts


def test_bom_quantities_and_masses(stack_4xs1, tmp_path):
    path = write_bom(stack_4xs1, tmp_path / "bom.csv")
    rows = list(csv.DictReader(path.open()))
    assert sum(int(r["quantity"]) for r in rows) == len(stack_4xs1.instances)
    assert [r["name"] for r in rows][0] == "S1-RING"
    ring = next(r for r in rows if r["name"] == "S1-RING")
    assert ring["part_number"] == stack_4xs1.part_named("S1-RING").part_number
    assert int(ring["quantity"]) == 4 and ring["make_or_buy"] == "make"
    # ring mass against the design's own (profile area x thickness x density)
    design_mass_g = stack_4xs1.design.springs["S1"].mass_kg * 1000
    assert float(ring["mass_each_g"]) == pytest.approx(design_mass_g, rel=1e-4)
    dowel = next(r for r in rows if r["name"] == "DOWEL")
    assert dowel["make_or_buy"] == "buy" and dowel["standard"].startswith("ISO 8734")
    for r in rows:
        part = stack_4xs1.parts[r["part_number"]]
        mass = solid_volume_mm3(part.solid) * part.info.density_kg_per_m3 * 1e-6
        assert float(r["mass_total_g"]) == pytest.approx(mass * int(r["quantity"]), abs=2e-3)


@pytest.mark.slow
def test_render_shows_the_stack(stack_4xs1, tmp_path):
    import matplotlib.image as mpimg
    import numpy as np

    from springcad.export.render import render_png

    path = render_png(stack_4xs1, tmp_path / "a.png", size=(800, 600))
    img = mpimg.imread(path)[..., :3]
    assert img.shape[:2] == (600, 800)
    background = np.all(img > 0.98, axis=-1).mean()
    assert 0.2 < background < 0.95  # the stack fills part of the picture
    # the input (green) and output (orange) adapters are visible
    green = (img[..., 1] > img[..., 0] + 0.15) & (img[..., 1] > img[..., 2] + 0.15)
    orange = (img[..., 0] > img[..., 1] + 0.2) & (img[..., 0] > img[..., 2] + 0.2)
    assert green.sum() > 100 and orange.sum() > 100
    # the title keeps clear of the edges; the model fills the picture, no empty half
    ink = ~np.all(img > 0.98, axis=-1)
    assert not ink[:6].any() and not ink[:, :6].any() and not ink[:, -6:].any()
    rows = np.flatnonzero(ink[60:].any(axis=1))  # below the title band
    assert rows[-1] - rows[0] > 0.65 * img.shape[0]  # 0.69 for 4xS1 at 800 x 600
    for half in (ink[: img.shape[0] // 2], ink[img.shape[0] // 2:]):
        assert half.mean() > 0.08


@pytest.mark.parametrize("surface", ["edm_main_cut", "edm_skim_cuts", "polished", "shot_peened"])
def test_ring_surface_note_and_fatigue_factor_come_from_one_setting(ring_s1, surface):
    """manufacturing.surface sets both the ring drawing's surface note and the Marin surface
    factor of the fatigue check (issue 21: drawing and calculation describe one part)."""
    import copy
    import tomllib
    from dataclasses import replace

    from springcad.config import job_from_dict
    from springcad.design.fatigue import surface_table
    from springcad.export.drawing import fields, note_lines
    from tests.conftest import template

    data = tomllib.loads(template("paper_S1").read_text())
    data["manufacturing"]["surface"] = surface
    duty = job_from_dict(data).material.duty
    part = copy.copy(ring_s1)
    part.spring = replace(ring_s1.spring, material=replace(ring_s1.spring.material, duty=duty))
    tb = load_title_block()
    lines = note_lines(part, fields(part, INFO, 1.0, tb), tb)
    row = surface_table()[surface]
    assert row.drawing_note in lines
    others = [s.drawing_note for n, s in surface_table().items() if n != surface]
    assert not any(o in lines for o in others)
    assert part.spring.fatigue.surface_factor == row.factor
    assert part.spring.duty_check.surface_factor == row.factor
    if surface in ("polished", "shot_peened"):
        assert any("remove the recast" in line for line in lines)


def test_wire_note_states_the_limit_every_inside_radius_meets(ring_s1, cam_s1):
    """The wire note names the least inside radius (wire radius + spark gap) as a limit the
    contour keeps, not as the part's own smallest radius: the edm rule, run on the same
    cutting profile, finds every inside radius of the ring and the cam at or above it (the
    robot-joint winner's ring has R0.158 where the note used to say "the smallest inside
    radius R0.15")."""
    from springcad.export.drawing import fields, note_lines
    from springcad.geometry.edm import inside_corner_rule

    tb = load_title_block()
    for part in (ring_s1, cam_s1):
        m = part.spring.manufacturing
        wire = [ln for ln in note_lines(part, fields(part, INFO, 1.0, tb), tb)
                if ln.startswith("Wire Ø")]
        r = m.min_inside_radius_mm
        assert wire == [f"Wire Ø{m.wire_diameter_mm:g} mm or finer: no inside radius of the "
                        f"contour is below R{r:g}, the wire radius + the {m.spark_gap_mm:g} "
                        "mm spark gap."]
        assert r == pytest.approx(0.5 * m.wire_diameter_mm + m.spark_gap_mm)
        rule = inside_corner_rule(part.info.cut_profile, r, 1e-3, lambda x, y: "")
        assert not rule.violations and rule.value_mm >= r * (1 - 1e-9), rule.value_mm
