"""Two builds of one job on one day give the same bytes: no clock time in any file a shop
gets (STEP header, DXF header, PDF and SVG meta data), so ``vendor.zip`` is identical."""

import time
import zipfile

from springcad.export.bom import write_bom
from springcad.export.drawing import DrawingInfo, write_drawing
from springcad.export.dxf import write_dxf
from springcad.export.release import ReleaseStatus
from springcad.export.step import write_part_step
from springcad.export.vendor import write_vendor_bundle

RELEASE = ReleaseStatus(("FEA verification skipped (--no-verify)",))
DATE = "2026-01-02"
#: every kind of file the zip holds, each from a part quick to export (what is tested is
#: the absence of clock time, the same for every part): STEP and DXF of the cam, STEP and
#: drawing of the torque shaft
PARTS = ("S1-CAM-L4.5-H6", "TORQUE-SHAFT")
DRAWN = ("TORQUE-SHAFT",)


def _build(assembly, out):
    """The files of ``PARTS`` as ``springcad build`` writes them, then the bundle."""
    parts = out / "parts"
    parts.mkdir(parents=True)
    qty = assembly.quantities()
    for name in PARTS:
        part = assembly.part_named(name)
        pn = part.part_number
        write_part_step(part, parts / f"{pn}.step", DATE)
        if part.info.cut_profile is not None:
            write_dxf(part.info.cut_profile, parts / f"{pn}.dxf", pn, part.info.thickness_mm)
        if name in DRAWN:
            write_drawing(part, DrawingInfo("S1", qty[pn], date=DATE, release=RELEASE), parts)
    write_bom(assembly, out / "bom.csv")
    return write_vendor_bundle(assembly, out, RELEASE, "S1")


def test_vendor_zip_is_byte_identical_across_builds(s1_stack, tmp_path):
    """The second export starts more than a second later: every clock-stamped field (STEP's
    FILE_NAME to the second, DXF and SVG to the microsecond, PDF to the second) would
    differ if it were still written."""
    first = _build(s1_stack, tmp_path / "a")
    time.sleep(1.1)
    second = _build(s1_stack, tmp_path / "b")
    a, b = zipfile.ZipFile(first), zipfile.ZipFile(second)
    assert a.namelist() == b.namelist()
    kinds = {n.rsplit(".", 1)[-1] for n in a.namelist()}
    assert {"step", "dxf", "pdf", "csv", "txt"} <= kinds
    differ = [n for n in a.namelist() if a.read(n) != b.read(n)]
    assert not differ, differ
    assert first.read_bytes() == second.read_bytes()
    # the date the build gives is the one in the files
    step = next(n for n in a.namelist() if n.endswith(".step"))
    assert f"'{DATE}T00:00:00'" in a.read(step).decode("latin-1")
    # and the SVG drawings (not in the zip) are reproducible too
    for svg in (tmp_path / "a" / "parts").glob("*.svg"):
        assert svg.read_bytes() == (tmp_path / "b" / "parts" / svg.name).read_bytes(), svg.name


def test_build_date_follows_source_date_epoch(monkeypatch):
    import datetime

    import pytest

    from springcad.api.pipeline import build_date
    from springcad.errors import ConfigError

    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    assert build_date() == datetime.date.today().isoformat()
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1767312000")  # 2026-01-02 00:00:00 UTC
    assert build_date() == "2026-01-02"
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "yesterday")
    with pytest.raises(ConfigError, match="SOURCE_DATE_EPOCH.*whole seconds"):
        build_date()


def test_step_date_replaces_only_the_header_time_stamp(tmp_path):
    from springcad.export.step import set_step_date

    path = tmp_path / "x.step"
    body = "DATA;\n#1 = PRODUCT('FILE_NAME(''a'',''2020-01-01T00:00:00'')','',$);\nENDSEC;\n"
    path.write_bytes(("ISO-10303-21;\nHEADER;\nFILE_NAME('it''s','2026-11-23T12:10:50',"
                      "('Author'));\nENDSEC;\n" + body).encode())
    text = set_step_date(path, "2026-01-02").read_text()
    assert "FILE_NAME('it''s','2026-01-02T00:00:00'," in text
    assert text.endswith(body)  # the data section is untouched


#: writes the DXF of a plate with a slot and a hole (lines, arcs, a circle) to argv[1]
_DXF_SCRIPT = """
import sys
from springcad.design.curves import Arc, Circle, Line, Loop, Profile
from springcad.export.dxf import write_dxf
outer = Loop((Line((0.0, 0.0), (40.0, 0.0)), Line((40.0, 0.0), (40.0, 20.0)),
              Arc((20.0, 20.0), 20.0, 0.0, 3.141592653589793),
              Line((0.0, 20.0), (0.0, 0.0))))
write_dxf(Profile(outer, (Loop((Circle((20.0, 10.0), 3.0),)),)), sys.argv[1], "PLATE", 2.0)
"""


def test_dxf_bytes_do_not_follow_the_string_hash(tmp_path):
    """ezdxf lists the CLASS entries of the entity types in use in a set's order, which
    follows each process's string hash: before the classes were sorted, two processes wrote
    LAYOUT and ACDBPLACEHOLDER in either order (measured: the default build's four DXFs).
    Six hash seeds: the chance that all six agreed by luck before was 1/32."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    files = []
    for seed in range(6):
        path = tmp_path / f"seed{seed}.dxf"
        env = {**os.environ, "PYTHONHASHSEED": str(seed),
               "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])}
        subprocess.run([sys.executable, "-c", _DXF_SCRIPT, str(path)], env=env, check=True,
                       cwd=tmp_path)
        files.append(path.read_bytes())
    assert b"ACDBPLACEHOLDER" in files[0] and b"AcDbLayout" in files[0]
    assert all(f == files[0] for f in files[1:])


def test_step_zeros_are_written_unsigned(tmp_path):
    """OCCT writes one zero as 0. or -0. from one process to the next: the data section's
    negative zeros become 0., other numbers (-0.5, 10.) stay as written."""
    from springcad.export.step import set_step_date

    path = tmp_path / "x.step"
    path.write_bytes(b"ISO-10303-21;\nHEADER;\nFILE_NAME('a','2026-11-23T12:10:50',('A'));\n"
                     b"ENDSEC;\nDATA;\n#1 = CARTESIAN_POINT('',(-0.,-0.5,-0.));\n"
                     b"#2 = DIRECTION('',(1.,-0.,-10.));\n#3 = X('-0.',-0.E+00);\nENDSEC;\n")
    text = set_step_date(path, "2026-01-02").read_text()
    assert "#1 = CARTESIAN_POINT('',(0.,-0.5,0.));" in text
    assert "#2 = DIRECTION('',(1.,0.,-10.));" in text
    assert "#3 = X('-0.',-0.E+00);" in text  # a string, and a form OCCT does not write


def test_stl_zeros_are_written_unsigned(tmp_path):
    """A binary STL's -0.0 coordinates and normals become 0.0; every other byte is kept."""
    import numpy as np

    from springcad.export.step import unsigned_stl_zeros

    tri = np.zeros(2, dtype=[("n", "<f4", 3), ("v", "<f4", 9), ("attr", "<u2")])
    tri["n"] = [[-0.0, 0.0, 1.0], [0.0, -1.0, -0.0]]
    tri["v"] = [[0, 0, -0.0, 1, 0, 0, 0, 1, 0], [-0.0, -2.5, 3, 1, -0.0, 0, 0, 1, 7]]
    tri["attr"] = [0, 0x8000]
    head = b"solid x".ljust(80, b" ") + (2).to_bytes(4, "little")
    path = tmp_path / "x.stl"
    path.write_bytes(head + tri.tobytes())
    unsigned_stl_zeros(path)
    back = np.frombuffer(path.read_bytes()[84:], dtype=tri.dtype)
    assert path.read_bytes()[:84] == head
    assert not np.signbit(back["n"][back["n"] == 0]).any()
    assert not np.signbit(back["v"][back["v"] == 0]).any()
    assert np.array_equal(back["v"], tri["v"]) and np.array_equal(back["n"], tri["n"])
    assert list(back["attr"]) == [0, 0x8000]
    assert np.signbit(back["v"][1, 1])  # -2.5 keeps its sign


def _styles(order):
    """A STEP file whose two colour representations (one with an overriding item) are
    written in ``order`` (OCCT's order follows memory addresses), numbered from #10."""
    blocks = {
        "a": ["MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION('',(@1,@5),#3)",
              "STYLED_ITEM('color',(@2),#1)", "PRESENTATION_STYLE_ASSIGNMENT((@3))",
              "FILL_AREA_STYLE_COLOUR('',@4)", "COLOUR_RGB('',0.5,0.25,0.)",
              "OVER_RIDING_STYLED_ITEM('overriding color',(@6),#1,\n  @1)",
              "PRESENTATION_STYLE_BY_CONTEXT((@7),#2)", "FILL_AREA_STYLE_COLOUR('',@4)"],
        "b": ["MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION('',(\n    @1),#3)",
              "STYLED_ITEM('color',(@2),#2)", "PRESENTATION_STYLE_ASSIGNMENT((@3))",
              "FILL_AREA_STYLE_COLOUR('',@4)", "COLOUR_RGB('',1.,1.,1.)"]}
    out, n = [], 10
    for name in order:
        rows = blocks[name]
        for k, row in enumerate(rows):
            out.append(f"#{n + k} = " + "".join(
                f"#{n + int(c)}" if p == "@" else c for p, c in zip(" " + row, row)
                if c != "@") + ";\n")
        n += len(rows)
    body = "".join(out).replace("@", "")
    return ("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1 = SHAPE('a');\n#2 = SHAPE('b');\n"
            "#3 = CONTEXT('');\n" + body + "ENDSEC;\nEND-ISO-10303-21;\n")


def test_assembly_step_styles_are_written_in_one_order():
    """OCCT writes an assembly's colour styles in an order of memory addresses (measured:
    three default builds, three orders); the file is rewritten with them in an order of their
    content, so the two orders give one text, whose colours and references are the same."""
    import re

    from springcad.export.step import canonical_styles

    ab, ba = _styles("ab"), _styles("ba")
    assert ab != ba
    one, two = canonical_styles(ab), canonical_styles(ba)
    assert one == two
    records = dict(re.findall(r"#(\d+) = (.*?);\n", one, re.S))
    assert sorted(map(int, records)) == list(range(1, 4)) + list(range(10, 23))

    def links(text):  # (kind, kind it references) of every reference
        rec = dict(re.findall(r"#(\d+) = (.*?);\n", text, re.S))
        return sorted((rec[i].split("(")[0], rec[r].split("(")[0])
                      for i in rec for r in re.findall(r"#(\d+)", rec[i]))

    assert links(one) == links(ab)
    # a styled item comes before the item overriding it; colours are shared as written
    assert one.index("= STYLED_ITEM('color',(#") < one.index("OVER_RIDING_STYLED_ITEM")
    assert one.count("COLOUR_RGB") == 2
    # a data section of another form is left as it is
    odd = ab.replace("#3 = CONTEXT('');", "#3 = CONTEXT(#12);")  # a style used elsewhere
    assert canonical_styles(odd) == odd
