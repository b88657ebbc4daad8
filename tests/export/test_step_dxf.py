"""STEP and DXF exports read back: same solids, same profiles."""

import re

import numpy as np
import pytest

from springcad.export.bundle import PERIMETER_RTOL
from springcad.export.dxf import (BIARC_TOL_MM, CHORD_TOL_MM, CUT_LAYER, ENTITY_STYLES,
                                  INFO_LAYER, chain_segments, loops_area_mm2, loops_length_mm,
                                  read_dxf_loops, write_dxf)
from springcad.export.step import read_step, write_assembly_step, write_part_step, write_part_stl
from springcad.geometry.base import face_area_mm2, solid_volume_mm3


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


CUT_PARTS = ["S1-RING", "S1-CAM-L4.5-H6-R", "S1-CAM-L9.4-R", "RIM-SPACER", "CENTRE-SPACER",
             "RIM-WASHER"]


def top_face(part):
    """The solid's face at its largest z: the cut profile (a hub, if any, lies below z = 0)."""
    return max(part.solid.faces(), key=lambda f: f.center().Z)


@pytest.mark.parametrize("entities", ENTITY_STYLES)
@pytest.mark.parametrize("name", CUT_PARTS)
def test_dxf_round_trip(stack_4xs1, tmp_path, name, entities):
    """Read back with ezdxf: LINE/ARC/CIRCLE (default) or one closed polyline per contour,
    no spline; the contours chain into the profile's loops; area and perimeter equal the
    solid's cut face within the chordal tolerance."""
    import ezdxf

    part = stack_4xs1.part_named(name)
    prof = part.info.cut_profile
    rep = write_dxf(prof, tmp_path / "p.dxf", part.part_number, part.info.thickness_mm,
                    entities=entities)
    assert rep.max_deviation_mm <= BIARC_TOL_MM
    doc = ezdxf.readfile(rep.path)
    assert not doc.audit().has_errors
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    assert len(doc.modelspace().query("SPLINE")) == 0
    cut = doc.modelspace().query(f'*[layer=="{CUT_LAYER}"]')
    if entities == "polyline":
        assert {e.dxftype() for e in cut} == {"LWPOLYLINE"} and all(e.closed for e in cut)
        assert len(cut) == len(prof.loops)
    else:
        assert {e.dxftype() for e in cut} <= {"LINE", "ARC", "CIRCLE"}
        assert len(cut) == rep.n_entities
    loops, _ = read_dxf_loops(rep.path)
    assert len(loops) == len(prof.loops)
    face = top_face(part)
    area, perimeter = face_area_mm2(face), sum(e.length for e in face.edges())
    assert abs(loops_area_mm2(loops) - area) <= CHORD_TOL_MM * perimeter
    assert loops_length_mm(loops) == pytest.approx(perimeter, rel=PERIMETER_RTOL)


def test_chaining_refuses_open_and_branched_contours():
    """Loose lines and arcs chain into closed loops only when every end meets one other."""
    sq = [((0, 0), (1, 0), 0.0), ((1, 0), (1, 1), 0.0), ((0, 1), (1, 1), 0.0),  # reversed
          ((0, 1), (0, 0), 0.0)]
    (loop,) = chain_segments(sq)
    assert abs(loop.area_mm2()) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="open contour"):
        chain_segments(sq[:3])
    with pytest.raises(ValueError, match="three contour ends"):
        chain_segments(sq + [((0, 0), (2, 2), 0.0)])


def _densified(p, step_mm: float) -> np.ndarray:
    """Closed polyline with points inserted so no edge is longer than ``step_mm``."""
    d = np.roll(p, -1, axis=0) - p
    n = np.maximum(1, np.ceil(np.linalg.norm(d, axis=1) / step_mm).astype(int))
    edge = np.repeat(np.arange(len(p)), n)
    t = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)  # 0 .. n_i - 1 on each edge
    return p[edge] + (t / n[edge])[:, None] * d[edge]


def _distance_to_polylines(points, polylines) -> np.ndarray:
    """Distance from each point to the nearest of a set of closed polylines (mm).

    The polylines are densified to 10 um edges first, so the nearest vertices found by
    the KD-tree belong to the nearest edge.
    """
    from scipy.spatial import cKDTree

    polylines = [_densified(p, 0.01) for p in polylines]
    verts = np.vstack(polylines)
    nxt = np.concatenate([np.roll(np.arange(len(p)), -1) + off for p, off in
                          zip(polylines, np.cumsum([0] + [len(p) for p in polylines[:-1]]))])
    prv = np.concatenate([np.roll(np.arange(len(p)), 1) + off for p, off in
                          zip(polylines, np.cumsum([0] + [len(p) for p in polylines[:-1]]))])
    _, idx = cKDTree(verts).query(points, k=3)
    best = np.full(len(points), np.inf)
    for k in range(idx.shape[1]):
        i = idx[:, k]
        for j in (nxt[i], prv[i]):
            a, b = verts[i], verts[j]
            d = b - a
            t = np.clip(np.einsum("ij,ij->i", points - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
            best = np.minimum(best, np.linalg.norm(points - (a + t[:, None] * d), axis=1))
    return best


@pytest.mark.parametrize("name", ["S1-RING", "S1-CAM-L4.5-H6-R"])
def test_dxf_within_a_micrometre_of_the_design(stack_4xs1, tmp_path, name):
    """Both ways: design curve to the contour ezdxf reads, and the contour to the design.

    ezdxf turns the bulges into LINE and ARC entities (its own bulge code, not the
    writer's) and samples the arcs on the true circle to a 1 nm sagitta; the design is
    sampled every 4 um (sagitta < 1e-5 um on the smallest radius), so the measurement
    error is ~1 nm. (ezdxf's ``path`` module would approximate arcs by Bezier curves,
    9 um off on a 33.5 mm radius: not used.)
    """
    import ezdxf

    part = stack_4xs1.part_named(name)
    rep = write_dxf(part.info.cut_profile, tmp_path / "p.dxf", "X", 1.0, entities="polyline")
    doc = ezdxf.readfile(rep.path)

    def flattened(polyline) -> np.ndarray:
        """The closed polyline as points in path order (ARCs are stored counter-clockwise,
        so a clockwise segment's points are turned round to start where the last ended)."""
        end = np.array(polyline.get_points("xy")[0])
        pieces = []
        for e in polyline.virtual_entities():
            if e.dxftype() == "LINE":
                p = np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)])
            else:
                p = np.array([(v.x, v.y) for v in e.flattening(1e-6)])
            if np.linalg.norm(p[-1] - end) < np.linalg.norm(p[0] - end):
                p = p[::-1]
            assert np.linalg.norm(p[0] - end) < 1e-9  # the path is connected
            pieces.append(p[:-1])
            end = p[-1]
        return np.vstack(pieces)

    back = [flattened(e) for e in doc.modelspace().query(f'LWPOLYLINE[layer=="{CUT_LAYER}"]')]
    design = [lp.sample(0.004) for lp in part.info.cut_profile.loops]
    d_design = _distance_to_polylines(np.vstack(design), back)
    d_back = _distance_to_polylines(np.vstack(back), design)
    assert d_design.max() <= CHORD_TOL_MM
    assert d_back.max() <= CHORD_TOL_MM
    print(f"{name}: {rep.n_biarcs} biarcs, design->dxf {1e3 * d_design.max():.3f} um, "
          f"dxf->design {1e3 * d_back.max():.3f} um, writer {1e3 * rep.max_deviation_mm:.3f} um")


def test_header_extents_are_the_drawing_extents(stack_4xs1, tmp_path):
    """$EXTMIN/$EXTMAX are what ezdxf measures over every entity (not the +-1e20
    placeholders), the INFO text lies below the cut contours and names the part."""
    import ezdxf
    from ezdxf import bbox

    for name in ("S1-RING", "S1-CAM-L4.5-H6-R", "RIM-WASHER"):
        part = stack_4xs1.part_named(name)
        rep = write_dxf(part.info.cut_profile, tmp_path / "p.dxf", part.part_number, 4.5)
        doc = ezdxf.readfile(rep.path)
        msp = doc.modelspace()
        info = msp.query(f'TEXT[layer=="{INFO_LAYER}"]')
        assert part.part_number in [t.dxf.text for t in info]
        cut = bbox.extents(msp.query(f'*[layer=="{CUT_LAYER}"]'))
        everything = bbox.extents(msp)
        assert np.allclose(tuple(doc.header["$EXTMIN"])[:2], tuple(everything.extmin)[:2], atol=1e-9), name
        assert np.allclose(tuple(doc.header["$EXTMAX"])[:2], tuple(everything.extmax)[:2], atol=1e-9), name
        assert all(t.dxf.insert.y + t.dxf.height < cut.extmin.y for t in info), name
        r = part.info.cut_profile.outer.sample(0.05)
        assert cut.extmax.x == pytest.approx(r[:, 0].max(), abs=1e-3)
