"""STEP and DXF exports read back: same solids, same profiles."""

import re

import numpy as np
import pytest

from springcad.export.dxf import (CUT_LAYER, loops_area_mm2, read_dxf_loops, spline_bspline,
                                  write_dxf)
from springcad.export.step import read_step, write_assembly_step, write_part_step, write_part_stl
from springcad.geometry.base import face_area_mm2, solid_volume_mm3
from springcad.geometry.profile import profile_face


def test_every_part_step_round_trips(stack_4xs1, tmp_path):
    for pn, part in stack_4xs1.parts.items():
        path = write_part_step(part, tmp_path / f"{pn}.step")
        back = read_step(path)
        assert back.n_solids == 1 and back.valid, pn
        assert back.names == (pn,)
        v = solid_volume_mm3(part.solid)
        assert back.volume_mm3 == pytest.approx(v, rel=1e-3), pn
        bb = part.solid.bounding_box()
        assert back.bbox_min == pytest.approx((bb.min.X, bb.min.Y, bb.min.Z), abs=1e-3), pn
        assert back.bbox_max == pytest.approx((bb.max.X, bb.max.Y, bb.max.Z), abs=1e-3), pn
        assert "SI_UNIT(.MILLI.,.METRE.)" in path.read_text(), pn


def test_assembly_step_names_parts_and_instances(stack_4xs1, tmp_path):
    path = write_assembly_step(stack_4xs1, tmp_path / "assembly.step")
    text = path.read_text()
    products = re.findall(r"PRODUCT\('([^']*)'", text)
    assert set(stack_4xs1.parts) <= set(products)
    occurrences = re.findall(r"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('[^']*','([^']*)'", text)
    assert sorted(occurrences) == sorted(i.name for i in stack_4xs1.instances)
    back = read_step(path)
    assert back.n_solids == len(stack_4xs1.instances) and back.valid
    expected = sum(solid_volume_mm3(i.part.solid) for i in stack_4xs1.instances)
    assert back.volume_mm3 == pytest.approx(expected, rel=1e-3)
    z = [i.z_range_mm for i in stack_4xs1.instances]
    assert back.bbox_min[2] == pytest.approx(min(a for a, _ in z), abs=1e-3)
    assert back.bbox_max[2] == pytest.approx(max(b for _, b in z), abs=1e-3)


def test_stl_is_a_closed_binary_mesh(ring_s1, tmp_path):
    path = write_part_stl(ring_s1, tmp_path / "ring.stl")
    data = path.read_bytes()
    n = int.from_bytes(data[80:84], "little")
    assert len(data) == 84 + 50 * n and n > 1000
    tri = np.frombuffer(data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                                   ("a", "<u2")]))["v"].astype(float)
    # signed volume of the triangle soup equals the solid's within the chord tolerance
    vol = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    assert vol == pytest.approx(solid_volume_mm3(ring_s1.solid), rel=5e-4)


@pytest.mark.parametrize("pn", ["S1-RING", "S1-CAM-L4.5-H6-R", "S1-CAM-L9.5-R", "RIM-SPACER",
                                "CENTRE-SPACER", "RIM-WASHER"])
def test_dxf_round_trip(stack_4xs1, tmp_path, pn):
    import ezdxf

    part = stack_4xs1.part_named(pn)
    pn = part.part_number
    prof = part.info.cut_profile
    path = write_dxf(prof, tmp_path / f"{pn}.dxf", pn, part.info.thickness_mm)
    loops, auditor = read_dxf_loops(path)
    assert not auditor.has_errors
    assert len(loops) == len(prof.loops)
    area = face_area_mm2(profile_face(prof, pn))
    assert loops_area_mm2(loops) == pytest.approx(area, rel=1e-3)
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    kinds = {e.dxftype() for e in doc.modelspace().query(f'*[layer=="{CUT_LAYER}"]')}
    assert kinds <= {"LINE", "ARC", "CIRCLE", "SPLINE"}
    n_arcs = sum(lp.n_arcs for lp in prof.loops)
    n_dxf_arcs = len(doc.modelspace().query(f'ARC CIRCLE[layer=="{CUT_LAYER}"]'))
    assert n_dxf_arcs == n_arcs  # every arc and circle of the design stays a true arc


def test_dxf_spline_is_the_design_spline(ring_s1):
    """The written B-spline passes through the design's fit points with its end tangents."""
    from scipy.interpolate import BSpline

    seg = next(s for s in ring_s1.spring.ring.loop("flexures").segments if hasattr(s, "points"))
    knots, ctrl = spline_bspline(seg)
    b = BSpline(knots, ctrl, 3)
    u = seg.parameters()
    assert np.abs(b(u) - np.asarray(seg.points)).max() < 1e-9
    _, cs = seg._spline
    uu = np.linspace(0, u[-1], 997)
    assert np.abs(b(uu) - cs(uu)).max() < 1e-9
    d0 = b.derivative()(0.0)
    assert d0 / np.linalg.norm(d0) == pytest.approx(np.asarray(seg.start_tangent), abs=1e-9)
