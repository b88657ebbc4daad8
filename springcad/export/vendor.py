"""The vendor bundle: one zip a shop can quote and make the parts from.

``vendor.zip`` in the build folder, always with the same names::

    README.txt                 release status, what to make, how many, of what
    bom.csv                    the bill of materials (every part, made and bought)
    <PN>/<PN>.step             every made part: the solid,
    <PN>/<PN>.dxf              the cutting profile (wire-EDM and sheet parts),
    <PN>/<PN>.pdf              the drawing

Entries are written in sorted order with a fixed time stamp, so a bundle of
unchanged files is byte-for-byte the same zip. Units: mm, g.
"""

from __future__ import annotations

import textwrap
import zipfile
from pathlib import Path

from springcad.export.release import ReleaseStatus
from springcad.options import DXF_VERSION

BUNDLE_NAME = "vendor.zip"
#: zip time stamp of every entry (the zip format's epoch): no build date in the bundle
_EPOCH = (1980, 1, 1, 0, 0, 0)
#: files of a made part that go into its folder
PART_KINDS = ("step", "dxf", "pdf")


#: what holds the stack along its axis (vendor README, report.html): no part of the package
#: does; the camshafts' drawings say how each is held
AXIAL_LOCATION_TITLE = "Axial location"


def axial_location(end_hubs: bool, flanges: bool) -> str:
    """What the user's housing must hold along the axis, for a stack with end camshafts
    with hubs (``end_hubs``) or rim flanges at its ends (``flanges``; then the camshafts at
    the stack ends float on the alignment shaft, their end faces flush with the end rings)."""
    held = []
    if end_hubs:
        held.append("the end camshafts (by their hub end faces, directly or through a torque "
                    "shaft's socket bottom)")
    if flanges:
        held.append("the rim flanges (by their outer faces) and, inside their bores, the "
                    "camshafts at the stack ends and the alignment shaft (by their end faces, "
                    "flush with the end rings' outer faces: nothing else holds them)")
    else:
        held.append("the rim stack (the outer faces of its first and last rims)")
    return ("No part of this package retains the stack along its axis. The user's housing "
            f"holds {' and '.join(held)} between thrust faces; inside, the centre spacers keep "
            "the camshafts apart and the rim spacers the rims. The cam teeth are as long as "
            "the rings are thick, so any axial offset of a camshaft from its ring shortens the "
            "contact line: keep the end float small.")


def assembly_axial_location(assembly) -> str:
    """:func:`axial_location` of a built stack (from its components' plans: a cached
    build's parts are not built for this)."""
    kinds = {i.component.kind for i in assembly.instances}
    hubs = any(getattr(i.component.plan, "hub_length_mm", 0.0) > 0 for i in assembly.instances
               if i.component.kind == "camshaft")
    return axial_location(hubs, "rim_flange" in kinds)


def readme_text(assembly, release: ReleaseStatus, job_name: str, bom_rows: list[dict],
                files_by_part: dict[str, list[str]], dxf_version: str = DXF_VERSION) -> str:
    """The shop's README: status first, then one block per part to make, then the buy list
    and how the parts go together. ``dxf_version``: the version the DXFs were written in."""
    lines = [f"Job: {job_name}", f"Status: {release.stamp}"]
    if not release.released:
        lines += ["", "DO NOT MANUFACTURE: these drawings are for quoting and review only.",
                  "Reasons:"] + [f"  - {r}" for r in release.reasons]
    lines += ["", "Units: mm. Each part folder holds the STEP solid, the drawing (PDF) and, for",
              "cut parts, the DXF (layer CUT: LINE, ARC and CIRCLE entities only, every hole one",
              "CIRCLE, contours closed end to end, true size; layer INFO: text, not to cut; the",
              "DXF governs the contour, the drawing the tolerances and finishes)."]
    lines += textwrap.wrap(
        f"DXF version {dxf_version} (AC1009)." if dxf_version == "R12" else
        f"DXF version {dxf_version} (AC1024); springcad build --dxf-version R12 writes R12 "
        "(AC1009) for CAM that reads nothing newer.", 80)
    lines += ["A part number names one geometry; the same number in another job is the same part.",
              "", "PARTS TO MAKE"]
    for r in bom_rows:
        if r["make_or_buy"] != "make":
            continue
        info = assembly.parts[r["part_number"]].info
        lines += ["", f"{r['part_number']}  {r['title']}",
                  f"  quantity:        {r['quantity']}",
                  f"  material:        {r['material']}",
                  f"  hardness:        {info.hardness or 'as supplied'}",
                  f"  heat treatment:  {r['heat_treatment'] or 'none'}"
                  + (f" ({info.heat_treatment_sequence})" if info.heat_treatment_sequence
                     and r["heat_treatment"] else ""),
                  f"  process:         {r['process']}",
                  f"  thickness/length: {r['thickness_or_length_mm']} mm"]
        if r["stock"]:  # what to order, wrapped under its label
            lines += textwrap.wrap(r["stock"], 80, initial_indent="  stock to order:  ",
                                   subsequent_indent=" " * 19)
        lines += [f"  files:           {', '.join(sorted(files_by_part.get(r['part_number'], [])))}"]
    buy = [r for r in bom_rows if r["make_or_buy"] == "buy"]
    if buy:
        lines += ["", "PARTS TO BUY (not made by the shop; for reference)"]
        lines += [f"  {r['quantity']} x {r['standard'] or r['title']}  ({r['part_number']})"
                  for r in buy]
        if any(r["standard"].startswith("ISO 8734") for r in buy):
            lines += ["", "ASSEMBLY: the rim dowels slide into the rims' E7 holes (a slip fit over",
                      "the m6 pins, never pressed, so no set of pins can jam); bond each pin with",
                      "an anaerobic retaining compound for slip fits (e.g. Loctite 641) applied",
                      "as the rims are stacked; it cures after the stack is closed."]
    lines += [""] + textwrap.wrap(
        f"{AXIAL_LOCATION_TITLE.upper()}: {assembly_axial_location(assembly)}", 80)
    return "\n".join(lines) + "\n"


def _dxf_version(entries: dict[str, bytes]) -> str:
    """The version the bundle's DXFs were written in, from a header's $ACADVER (AC1009 is
    R12); the default when the bundle has no DXF."""
    for name, data in entries.items():
        if name.endswith(".dxf"):
            return "R12" if b"AC1009" in data[:2000] else DXF_VERSION
    return DXF_VERSION


def _bundle_bom(text: str, rows: list[dict], files_by_part: dict[str, list[str]]) -> bytes:
    """The build's bom.csv with its ``files`` column as the bundle holds them
    (``<PN>/<PN>.step ...``; bought parts: none), every other column as written."""
    import csv
    import io

    fields = next(csv.reader(io.StringIO(text)))
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    writer.writeheader()
    for r in rows:
        pn = r["part_number"]
        writer.writerow({**r, "files": " ".join(f"{pn}/{f}"
                                                for f in sorted(files_by_part.get(pn, [])))})
    return out.getvalue().encode()


def write_vendor_bundle(assembly, out_dir: Path, release: ReleaseStatus, job_name: str) -> Path:
    """Zip a build folder's part files, BOM and a README into ``out_dir/vendor.zip``.

    Reads the files a build wrote (``parts/<PN>.*``, ``bom.csv``); returns the zip path.
    """
    import csv

    out_dir = Path(out_dir)
    bom_path = out_dir / "bom.csv"
    with open(bom_path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    entries: dict[str, bytes] = {}
    files_by_part: dict[str, list[str]] = {}
    for r in rows:
        pn = r["part_number"]
        if r["make_or_buy"] != "make":
            continue
        for kind in PART_KINDS:
            src = out_dir / "parts" / f"{pn}.{kind}"
            if src.exists():
                entries[f"{pn}/{pn}.{kind}"] = src.read_bytes()
                files_by_part.setdefault(pn, []).append(f"{pn}.{kind}")
    entries["bom.csv"] = _bundle_bom(bom_path.read_text(), rows, files_by_part)
    entries["README.txt"] = readme_text(assembly, release, job_name, rows, files_by_part,
                                        _dxf_version(entries)).encode()
    path = out_dir / BUNDLE_NAME
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name in sorted(entries):
            info = zipfile.ZipInfo(name, date_time=_EPOCH)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            zf.writestr(info, entries[name])
    return path
