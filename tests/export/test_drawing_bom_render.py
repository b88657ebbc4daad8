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
    blob = "\n".join(texts)
    missing = [e for e in expected if e not in blob]
    assert not missing, f"missing {missing}"


def title_values(part):
    m = part.info
    return [m.part_number, m.title, m.material, m.heat_treatment or "none",
            f"{fmt(m.thickness_mm)} mm", "4", "mm", "C", "2031-02-03", "test-job"]


def test_ring_drawing_has_its_dimensions(ring_s1, tmp_path):
    r = ring_s1
    bc = 2 * math.hypot(*r.hole_centres[0])
    expected = [f"Ø{fmt(2 * r.outer_radius)}", f"R{fmt(r.contact_radius)} contact radius",
                f"R{fmt(r.tip_radius)} tip", f"Ø{fmt(bc)} bolt circle",
                f"{len(r.hole_centres)}× Ø{fmt(r.hole_diameter)}", fmt(r.thickness),
                f"±{fmt(r.spring.manufacturing.t_spring_mm)} mm"] + title_values(r)
    svg, pdf = drawing_texts(r, tmp_path)
    assert_all_in(expected, svg)
    assert_all_in(expected, pdf)
    assert fmt(r.thickness) in svg  # the side view's dimension is its own text


def test_cam_and_spacer_drawings(stack_4xs1, tmp_path):
    cam = stack_4xs1.part_named("S1-CAM-L4.5-H6-R")
    svg, pdf = drawing_texts(cam, tmp_path)
    expected = [f"Ø{fmt(2 * cam.tip_radius)} tooth tips", f"Ø{fmt(2 * cam.root_radius)} root",
                f"R{fmt(cam.contact_radius)} contact radius", f"Ø{fmt(cam.bore_diameter)} bore",
                fmt(cam.toothed_length), fmt(cam.hub_length)] + title_values(cam)
    assert_all_in(expected, svg)
    assert_all_in(expected, pdf)
    spacer = stack_4xs1.part_named("RIM-SPACER")
    svg, pdf = drawing_texts(spacer, tmp_path)
    expected = [f"Ø{fmt(2 * spacer.outer_radius)}", f"Ø{fmt(2 * spacer.inner_radius)}",
                f"{len(spacer.hole_centres)}× Ø{fmt(spacer.hole_diameter)}", fmt(spacer.length)]
    assert_all_in(expected + title_values(spacer), svg + pdf)


def test_title_block_comes_from_the_template(ring_s1, tmp_path):
    template = load_title_block()
    template["block"]["company"] = "ACME springs test"
    template["rows"][0]["cells"][0]["label"] = "ITEM NAME"
    svg, _ = drawing_texts(ring_s1, tmp_path, template)
    assert "ACME springs test" in svg and "ITEM NAME" in svg


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
