"""Every exported DXF read back by a reader that is not ezdxf (tests/export/dxf_groups.py).

What a CAM system sees must be the design: both ways within the contour tolerance
(design curve to the DXF's entities and back), holes as CIRCLE entities, no SPLINE or
bulge in the default style, true header extents and INFO text a person can read.
"""

import math

import numpy as np
import pytest
from cad_fixtures import assembly
from dxf_groups import entity_points, read

from springcad.design.curves import Circle
from springcad.export.dxf import (CHORD_TOL_MM, CUT_LAYER, ENTITY_STYLES, INFO_LAYER,
                                  INFO_TEXT_HEIGHT_MM, write_dxf)

#: sample spacing along design curves and DXF arcs (mm): sagitta < 0.02 um on R0.1
STEP_MM = 0.004
STACKS = ("4xS1", "default")


def cut_parts():
    return [(s, pn) for s in STACKS for pn, p in assembly(s).parts.items()
            if p.info.cut_profile is not None]


def distance_to_paths(points: np.ndarray, paths: list[np.ndarray]) -> np.ndarray:
    """Distance (mm) from each point to the nearest of a set of open polylines.

    Each polyline is cut into pieces of at most 10 um; the 6 pieces with the nearest
    midpoints are measured exactly. A miss can only make a distance larger (the test
    stricter), never smaller.
    """
    from scipy.spatial import cKDTree

    a_list, b_list = [], []
    for p in paths:
        a, b = p[:-1], p[1:]
        n = np.maximum(1, np.ceil(np.linalg.norm(b - a, axis=1) / 0.01).astype(int))
        k = np.repeat(np.arange(len(a)), n)
        t0 = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / n[k]
        t1 = t0 + 1.0 / n[k]
        d = b[k] - a[k]
        a_list.append(a[k] + t0[:, None] * d)
        b_list.append(a[k] + t1[:, None] * d)
    a, b = np.vstack(a_list), np.vstack(b_list)
    _, idx = cKDTree(0.5 * (a + b)).query(points, k=6)
    best = np.full(len(points), np.inf)
    for j in range(idx.shape[1]):
        pa, pb = a[idx[:, j]], b[idx[:, j]]
        d = pb - pa
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-30)
        t = np.clip(np.einsum("ij,ij->i", points - pa, d) / dd, 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(points - (pa + t[:, None] * d), axis=1))
    return best


def closed(p: np.ndarray) -> np.ndarray:
    return np.vstack([p, p[:1]])


@pytest.mark.parametrize("entities", ENTITY_STYLES)
@pytest.mark.parametrize("stack,pn", cut_parts())
def test_dxf_read_by_a_second_reader_is_the_design(tmp_path, stack, pn, entities):
    part = assembly(stack).parts[pn]
    prof = part.info.cut_profile
    along = sum(sl.length_mm for sl in part.slabs if sl.region is prof)
    rep = write_dxf(prof, tmp_path / f"{pn}.dxf", pn, part.info.thickness_mm, entities=entities,
                    profile_length_mm=along)
    header, ents = read(rep.path.read_text())
    cut = [e for e in ents if e.layer == CUT_LAYER]
    kinds = {e.kind for e in cut}
    n_circles = sum(isinstance(lp.segments[0], Circle) for lp in prof.loops if lp.is_circle)
    if entities == "lines-arcs":
        assert kinds <= {"LINE", "ARC", "CIRCLE"}, kinds
        assert sum(e.kind == "CIRCLE" for e in cut) == n_circles  # every hole one CIRCLE
    else:
        assert kinds == {"LWPOLYLINE"} and len(cut) == len(prof.loops)
        assert all(int(e.first(70)) & 1 for e in cut)
    back = [entity_points(e, STEP_MM) for e in cut]
    design = [closed(lp.sample(STEP_MM)) for lp in prof.loops]
    d_design = distance_to_paths(np.vstack(design), back)
    d_back = distance_to_paths(np.vstack(back), design)
    print(f"{stack} {pn} {entities}: {len(cut)} CUT entities, design->dxf "
          f"{1e3 * d_design.max():.4f} um, dxf->design {1e3 * d_back.max():.4f} um")
    assert d_design.max() <= CHORD_TOL_MM
    assert d_back.max() <= CHORD_TOL_MM

    # header extents hold everything and are not the +-1e20 placeholders
    lo = np.array([float(v) for v in header["$EXTMIN"][:2]])
    hi = np.array([float(v) for v in header["$EXTMAX"][:2]])
    pts = np.vstack(back)
    assert np.all(lo <= pts.min(axis=0) + 1e-9) and np.all(hi >= pts.max(axis=0) - 1e-9)
    # INFO: legible, below the cut contours, inside the extents
    info = [e for e in ents if e.layer == INFO_LAYER and e.kind == "TEXT"]
    assert pn in [e.first(1) for e in info]
    # an end camshaft's teeth are cut over the toothed length only (review 7, 2.14)
    t = f"t {part.info.thickness_mm:g} mm"
    assert (t if along == part.info.thickness_mm else f"{t}, outer contour over {along:g} mm") \
        in [e.first(1) for e in info]
    for e in info:
        x, y, h = e.num(10), e.num(20), e.num(40)
        assert h >= INFO_TEXT_HEIGHT_MM >= 2.5
        assert y + h <= pts[:, 1].min() - 0.9 * h  # clear of every contour
        assert lo[1] <= y and lo[0] <= x <= hi[0]
    # nothing but the contours and the text (at most one text height per character wide)
    x_text = max(e.num(10) + len(e.first(1)) * e.num(40) for e in info)
    y_text = min(e.num(20) for e in info)
    assert hi[0] <= max(pts[:, 0].max(), x_text) and hi[1] <= pts[:, 1].max() + 1e-6
    assert lo[0] >= pts[:, 0].min() - 1e-6 and lo[1] >= y_text - INFO_TEXT_HEIGHT_MM


def test_r12_file_is_r12_with_the_same_entities(tmp_path):
    part = assembly("4xS1").part_named("S1-RING")
    rep = write_dxf(part.info.cut_profile, tmp_path / "r12.dxf", "X", 1.0, version="R12")
    header, ents = read(rep.path.read_text())
    assert header["$ACADVER"] == ["AC1009"]
    assert {e.kind for e in ents if e.layer == CUT_LAYER} <= {"LINE", "ARC", "CIRCLE"}
    with pytest.raises(ValueError, match="R12 has no LWPOLYLINE"):
        write_dxf(part.info.cut_profile, tmp_path / "x.dxf", "X", 1.0, entities="polyline",
                  version="R12")
    with pytest.raises(ValueError, match="allowed lines-arcs, polyline"):
        write_dxf(part.info.cut_profile, tmp_path / "x.dxf", "X", 1.0, entities="spline")


def test_second_reader_catches_a_misapplied_bulge():
    """The check is not blind: a bulge applied to the next segment (the dxf2gcode error
    the issue-26 review saw) is found, as it moves the contour far beyond the tolerance."""
    from dxf_groups import Entity

    sq = [(0.0, 0.0, 0.0), (10.0, 0.0, math.tan(math.pi / 8)), (10.0, 10.0, 0.0),
          (0.0, 10.0, 0.0)]
    groups = [(70, "1")]
    for x, y, b in sq:
        groups += [(10, str(x)), (20, str(y)), (42, str(b))]
    right = entity_points(Entity("LWPOLYLINE", CUT_LAYER, groups), STEP_MM)
    shifted = [(x, y, sq[k - 1][2]) for k, (x, y, _) in enumerate(sq)]
    groups = [(70, "1")] + [g for x, y, b in shifted for g in ((10, str(x)), (20, str(y)),
                                                                (42, str(b)))]
    wrong = entity_points(Entity("LWPOLYLINE", CUT_LAYER, groups), STEP_MM)
    assert distance_to_paths(wrong, [right]).max() > 1.0


def _dxf2gcode_python() -> str | None:
    """The system Python that imports dxf2gcode, or None (the test is then skipped)."""
    import shutil
    import subprocess

    py = shutil.which("python3", path="/usr/bin")
    if py is None:
        return None
    ok = subprocess.run([py, "-c", "import dxf2gcode.dxfimport.importer, PyQt5"],
                        capture_output=True).returncode == 0
    return py if ok else None


@pytest.mark.parametrize("stack,name", [("4xS1", "S1-RING"), ("4xS1", "S1-CAM-L4.5-H6-R"),
                                        ("4xS1", "RIM-SPACER"), ("4xS1", "RIM-WASHER"),
                                        ("default", "S1-RING"), ("default", "S1-CAM-L12-H6"),
                                        ("default", "CENTRE-SPACER")])
def test_dxf2gcode_reads_the_design(tmp_path, stack, name):
    """A real CAM program's importer (dxf2gcode) reads the default DXF within the
    contour tolerance of the design, every contour closed (the 4xS1 and the default
    package: every kind of cut part)."""
    import json
    import subprocess
    from pathlib import Path

    py = _dxf2gcode_python()
    if py is None:
        pytest.skip("dxf2gcode (Debian package) not installed")
    part = assembly(stack).part_named(name)
    prof = part.info.cut_profile
    rep = write_dxf(prof, tmp_path / "p.dxf", part.part_number, part.info.thickness_mm)
    script = Path(__file__).with_name("dxf2gcode_read.py")
    run = subprocess.run([py, str(script), str(rep.path), str(tmp_path / "p.json")],
                         capture_output=True, text=True, timeout=600,
                         env={"HOME": str(tmp_path), "PATH": "/usr/bin:/bin",
                              "QT_QPA_PLATFORM": "offscreen"})
    assert run.returncode == 0, run.stderr[-2000:]
    stats = json.loads(run.stdout.strip().splitlines()[-1])
    assert stats["contours"] == stats["closed"] == len(prof.loops), stats
    back = [np.array(p) for p in json.loads((tmp_path / "p.json").read_text())]
    design = [closed(lp.sample(STEP_MM)) for lp in prof.loops]
    d_design = distance_to_paths(np.vstack(design), back).max()
    d_back = distance_to_paths(np.vstack(back), design).max()
    print(f"dxf2gcode {name}: {stats}, design->cam {1e3 * d_design:.4f} um, "
          f"cam->design {1e3 * d_back:.4f} um")
    assert d_design <= CHORD_TOL_MM and d_back <= CHORD_TOL_MM


def test_a_build_writes_r12_on_request(tmp_path):
    """``--dxf-version R12`` (sc.export_build(dxf_version="R12")) reaches every DXF of a
    build: the part sheets written both ways, read by the group-code parser, hold the same
    CUT entities with the same numbers and the same extents, only $ACADVER differs
    (AC1024 / AC1009); the vendor README names the version it holds; a version that is not
    offered is refused naming the option."""
    import zipfile

    from springcad.errors import OptionError
    from springcad.export.bom import write_bom
    from springcad.export.bundle import export_part_sheets
    from springcad.export.release import ReleaseStatus
    from springcad.export.vendor import write_vendor_bundle
    from springcad.options import check_dxf_version

    a = assembly("default")
    info = {"job": "default", "revision": "A", "date": "", "drawn_by": "test"}
    read_back = {}
    for version in ("R2010", "R12"):
        out = tmp_path / version
        files = export_part_sheets(a, out, info, dxf_version=version)
        dxfs = sorted(out / f.path for f in files if f.path.endswith(".dxf"))
        assert len(dxfs) == 4
        read_back[version] = [read(p.read_text()) for p in dxfs]
        write_bom(a, out / "bom.csv")
        readme = zipfile.ZipFile(write_vendor_bundle(a, out, ReleaseStatus(()), "default")) \
            .read("README.txt").decode()
        assert f"DXF version {version} ({'AC1009' if version == 'R12' else 'AC1024'})" in readme
    numeric = (10, 20, 11, 21, 40, 50, 51)
    for (h_new, e_new), (h_r12, e_r12) in zip(read_back["R2010"], read_back["R12"]):
        assert (h_new["$ACADVER"], h_r12["$ACADVER"]) == (["AC1024"], ["AC1009"])
        assert h_new["$EXTMIN"] == h_r12["$EXTMIN"] and h_new["$EXTMAX"] == h_r12["$EXTMAX"]
        cut_new = [e for e in e_new if e.layer == CUT_LAYER]
        cut_r12 = [e for e in e_r12 if e.layer == CUT_LAYER]
        assert [e.kind for e in cut_new] == [e.kind for e in cut_r12]
        for x, y in zip(cut_new, cut_r12):
            assert [(c, float(v)) for c, v in x.groups if c in numeric] == \
                [(c, float(v)) for c, v in y.groups if c in numeric]
    with pytest.raises(OptionError, match=r"dxf.version = 'R14': is one of R2010, R12"):
        check_dxf_version("R14")
