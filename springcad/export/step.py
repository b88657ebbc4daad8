"""STEP and STL export of parts and of the stack assembly, and STEP read-back.

A part's STEP holds one solid whose product is named by its part number. The
assembly STEP holds each distinct part once (product = part number, with its
colour) and places it once per instance (occurrence = instance name, e.g.
``spring_2_S1``), so a CAD user sees both the bill of materials and the
stack. Lengths in mm.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from springcad.units import M_PER_MM

#: STL chordal tolerance (mm) and angular tolerance (rad): fine enough to show 0.025 mm gaps
STL_TOLERANCE_MM = 0.005
STL_ANGULAR_RAD = 0.2
#: date of a STEP header when none is given (the zip format's epoch, as in vendor.zip)
STEP_EPOCH_DATE = "1980-01-01"
_FILE_NAME_STAMP = re.compile(r"(FILE_NAME\s*\(\s*'(?:[^']|'')*'\s*,\s*')[^']*(')")
#: a negative zero as OCCT writes a real in a STEP data list: "-0." between "(" or "," and
#: "," or ")" (not "-0.5", not "-0.E+00" which OCCT does not write)
_NEGATIVE_ZERO = re.compile(r"(?<=[(,])-0\.(?=[,)])")


def set_step_date(path: Path, date: str = "") -> Path:
    """Put ``date`` (YYYY-MM-DD, midnight) in the time stamp of a STEP file's header, and
    write every zero of the data section unsigned.

    OCCT writes the clock time of the export there, so two exports of one solid
    would differ; with the build's date the file is a function of the geometry and
    the date only (vendor.zip of two builds on one day is byte-identical). OCCT also
    writes one zero coordinate as ``0.`` in one process and ``-0.`` in the next (measured:
    the torque shaft's and the cam's STEP, the assembly STEP), the same number.
    """
    path = Path(path)
    text = path.read_bytes().decode("latin-1")
    head, sep, rest = text.partition("ENDSEC;")
    rest = _NEGATIVE_ZERO.sub("0.", rest)
    stamp = f"{date or STEP_EPOCH_DATE}T00:00:00"
    new_head, n = _FILE_NAME_STAMP.subn(lambda m: m.group(1) + stamp + m.group(2), head,
                                        count=1)
    if n != 1:
        raise OSError(f"{path}: no FILE_NAME time stamp in the STEP header")
    path.write_bytes((new_head + sep + rest).encode("latin-1"))
    return path


def step_shape(solid):
    """The shape a STEP file carries for a part's solid: its extruded curve faces (the
    flanks' Bezier pieces) as B-spline surfaces, on which OCC's volume integral (FreeCAD's
    ``Volume``) is exact at its default and converges at any tolerance asked (on
    extrusion surfaces it was 8e-4 off at 1e-2); lines, circles and planes stay exact."""
    import build123d as bd
    from OCP.ShapeCustom import ShapeCustom

    return bd.Solid(ShapeCustom.ConvertToBSpline_s(solid.wrapped, True, False, False, False))


def write_part_step(part, path: Path, date: str = "") -> Path:
    """Write one part as STEP (mm), product named by its part number, dated ``date``
    (YYYY-MM-DD; :data:`STEP_EPOCH_DATE` if empty) instead of the clock time."""
    import build123d as bd

    solid = step_shape(part.solid)
    solid.label = part.part_number
    solid.color = bd.Color(*part.colour)
    bd.export_step(solid, str(path), unit=bd.Unit.MM)
    return set_step_date(path, date)


def write_part_stl(part, path: Path) -> Path:
    """Write one part as binary STL (mm), meshed to an absolute chord tolerance.

    The part's own solid keeps no mesh: a copy is triangulated (build123d's
    exporter uses a tolerance relative to the edge size, too coarse here).
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.StlAPI import StlAPI_Writer

    copy = BRepBuilderAPI_Copy(part.solid.wrapped, True, False).Shape()
    BRepMesh_IncrementalMesh(copy, STL_TOLERANCE_MM, False, STL_ANGULAR_RAD, True)
    writer = StlAPI_Writer()
    writer.ASCIIMode = False
    if not writer.Write(copy, str(path)):
        raise OSError(f"could not write the STL {path}")
    return unsigned_stl_zeros(path)


def unsigned_stl_zeros(path: Path) -> Path:
    """Rewrite the negative zeros of a binary STL's normals and vertices as zeros (the
    same numbers: OCCT writes a zero as -0.0 in one process and 0.0 in the next, so two
    builds' files differed); other bytes are kept."""
    import numpy as np

    path = Path(path)
    data = bytearray(path.read_bytes())
    n = int.from_bytes(data[80:84], "little")
    if len(data) != 84 + 50 * n:
        raise OSError(f"{path}: not a binary STL of {n} triangles ({len(data)} bytes)")
    records = np.frombuffer(data, dtype=np.uint8, offset=84).reshape(n, 50)
    words = records[:, :48].copy().view("<u4")  # 12 float32 per triangle
    negative_zero = words == 0x80000000
    if negative_zero.any():
        words[negative_zero] = 0
        out = records.copy()
        out[:, :48] = words.view(np.uint8).reshape(n, 48)
        path.write_bytes(bytes(data[:84]) + out.tobytes())
    return path


def _quiet_occt():
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


def write_assembly_step(assembly, path: Path, date: str = "") -> Path:
    """Write the stack as a STEP assembly: parts once, placed per instance (mm), dated
    ``date`` (see :func:`write_part_step`)."""
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.STEPCAFControl import STEPCAFControl_Controller, STEPCAFControl_Writer
    from OCP.STEPControl import STEPControl_StepModelType
    from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
    from OCP.TDataStd import TDataStd_Name
    from OCP.TDocStd import TDocStd_Document
    from OCP.XCAFApp import XCAFApp_Application
    from OCP.XCAFDoc import XCAFDoc_ColorType, XCAFDoc_DocumentTool
    from OCP.XSControl import XSControl_WorkSession
    from build123d import Color

    _quiet_occt()
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    app = XCAFApp_Application.GetApplication_s()
    app.NewDocument(TCollection_ExtendedString("MDTV-XCAF"), doc)
    app.InitDocument(doc)
    XCAFDoc_DocumentTool.SetLengthUnit_s(doc, M_PER_MM)
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    colours = XCAFDoc_DocumentTool.ColorTool_s(doc.Main())
    shapes.SetAutoNaming_s(False)

    def name(label, text):
        TDataStd_Name.Set_s(label, TCollection_ExtendedString(text))

    top = shapes.NewShape()
    name(top, assembly.design.job.name)
    part_labels = {}
    for pn, part in assembly.parts.items():
        label = shapes.AddShape(step_shape(part.solid).wrapped, False)
        name(label, pn)
        colours.SetColor(label, Color(*part.colour).wrapped, XCAFDoc_ColorType.XCAFDoc_ColorGen)
        part_labels[pn] = label
    for inst in assembly.instances:
        comp = shapes.AddComponent(top, part_labels[inst.part.part_number],
                                   inst.placement.location().wrapped)
        name(comp, inst.name)
        if inst.colour != inst.part.colour:
            colours.SetColor(comp, Color(*inst.colour).wrapped, XCAFDoc_ColorType.XCAFDoc_ColorGen)
    shapes.UpdateAssemblies()

    writer = STEPCAFControl_Writer(XSControl_WorkSession(), False)
    writer.SetColorMode(True)
    writer.SetNameMode(True)
    header = APIHeaderSection_MakeHeader(writer.Writer().Model())
    if not header.IsDone():
        header = APIHeaderSection_MakeHeader(0)
        header.Apply(writer.Writer().Model())
    header.SetName(TCollection_HAsciiString(assembly.design.job.name))
    header.SetOriginatingSystem(TCollection_HAsciiString("springcad / build123d"))
    STEPCAFControl_Controller.Init_s()
    writer.Transfer(doc, STEPControl_StepModelType.STEPControl_AsIs)
    if writer.Write(str(path)) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise OSError(f"could not write the assembly STEP {path}")
    path = Path(path)
    path.write_bytes(canonical_styles(path.read_bytes().decode("latin-1")).encode("latin-1"))
    return set_step_date(path, date)


_RECORD = re.compile(r"#(\d+) = (.*?);\n", re.S)
_REF = re.compile(r"#(\d+)")
_STYLES_START = "MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION("


def canonical_styles(text: str) -> str:
    """A STEP file with its presentation styles (the colours: the records from the first
    ``MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION`` to the end of the data
    section) in an order of their content, numbered in that order.

    OCCT writes the styles of an assembly from a map ordered by memory addresses, so two
    processes wrote the same styles in different orders (measured: the default job's
    assembly STEP); here each representation's items are sorted, the representations sorted,
    and the records numbered depth first from them (the numbers they had, reused), so the
    file is a function of the geometry and colours. The text is returned unchanged when the
    section is not of that form (a record not reached from a representation, a number used
    outside it, numbers not consecutive).
    """
    data = text.find("\nDATA;\n")
    start = text.find(f"= {_STYLES_START}", data)
    end = text.find("ENDSEC;", start)
    if data < 0 or start < 0 or end < 0:
        return text
    start = text.rfind("\n", 0, start) + 1
    records = {int(m.group(1)): m.group(2) for m in _RECORD.finditer(text, start, end)}
    ids = sorted(records)
    if (not ids or ids != list(range(ids[0], ids[0] + len(ids)))
            or _RECORD.sub("", text[start:end]).strip()
            or any(int(r) in records for r in _REF.findall(text[data:start]))):
        return text
    inner = lambda body: [int(r) for r in _REF.findall(body) if int(r) in records]  # noqa: E731
    keys: dict[int, str] = {}

    def key(i: int) -> str:  # the record's content, its references replaced by theirs
        if i not in keys:
            keys[i] = _REF.sub(lambda m: f"{{{key(int(m.group(1)))}}}" if int(m.group(1))
                               in records else m.group(0), records[i])
        return keys[i]

    roots = [i for i in ids if records[i].startswith(_STYLES_START)]
    for i in roots:  # each representation's items (its first list) in the order of content
        body = records[i]
        lo, hi = body.index("("), body.index(")")
        listed = [int(r) for r in _REF.findall(body[lo:hi])]
        if any(r not in records for r in listed):
            return text
        # a styled item before the items that override it, each kind by content
        ordered = iter(sorted(listed, key=lambda r: (records[r].startswith("OVER_RIDING"),
                                                     key(r))))
        records[i] = body[:lo] + _REF.sub(lambda m: f"#{next(ordered)}", body[lo:hi]) + body[hi:]
    keys.clear()
    order: list[int] = []
    seen: set[int] = set()

    def visit(i: int) -> None:
        stack = [i]
        while stack:
            j = stack.pop()
            if j in seen:
                continue
            seen.add(j)
            order.append(j)
            stack.extend(reversed(inner(records[j])))

    for i in sorted(roots, key=key):
        visit(i)
    if len(order) != len(ids):
        return text
    new = {old: ids[0] + k for k, old in enumerate(order)}
    out = "".join(f"#{new[i]} = " + _REF.sub(lambda m: f"#{new[int(m.group(1))]}"
                                             if int(m.group(1)) in new else m.group(0),
                                             records[i]) + ";\n" for i in order)
    return text[:start] + out + text[end:]


@dataclass(frozen=True)
class StepReadback:
    """What a STEP file holds when read back (mm, mm^3)."""

    n_solids: int
    valid: bool
    volume_mm3: float
    bbox_min: tuple
    bbox_max: tuple
    names: tuple


def read_step(path: Path) -> StepReadback:
    """Import a STEP file and measure it (volume by :func:`solid_volume_mm3`)."""
    import build123d as bd

    from springcad.geometry.base import solid_volume_mm3

    _quiet_occt()
    shape = bd.import_step(str(path))
    solids = shape.solids()
    bb = shape.bounding_box()
    names = tuple(dict.fromkeys(re.findall(r"PRODUCT\('([^']*)'", Path(path).read_text())))
    return StepReadback(len(solids), all(s.is_valid for s in solids),
                        sum(solid_volume_mm3(s) for s in solids),
                        (bb.min.X, bb.min.Y, bb.min.Z), (bb.max.X, bb.max.Y, bb.max.Z), names)
