"""Vendor drawings (SVG and PDF) a shop can quote from.

One A3 sheet per made part: the views and their dimensions
(:mod:`springcad.export.views`), a hole table, notes a shop needs (general
tolerance standard, contour tolerance, material, hardness and when the heat
treatment happens, surface finish, flatness), the release status
(:mod:`springcad.export.release`) and a title block filled from the title
block template (``templates/drawing_title_block.toml``, shipped as package
data) with the first-angle projection symbol. The shop cuts from the DXF;
the drawing is for quoting and inspection. Units: mm.
"""

from __future__ import annotations

import textwrap
import tomllib
from dataclasses import dataclass
from pathlib import Path

from springcad.data import data_path
from springcad.design.fatigue import surface_table
from springcad.design.processes import process_chain_text, process_text, processes
from springcad.export.release import UNASSESSED, ReleaseStatus
from springcad.geometry.disk import FlexureRing
from springcad.export.sheet import (FRAME_MM, LABEL_FONT, NOTE_FONT, THICK, Sheet, fmt,
                                    scale_text)

TITLE_BLOCK_NAME = "drawing_title_block.toml"
#: sheet parts this thin or thinner get the template's ``thin_sheet`` notes (mm)
THIN_SHEET_MM = 1.0
#: the right column (title block, notes, hole table, details): x from here to the frame
RIGHT_X0 = 230.0
#: highest y of any view (below the header line)
VIEWS_TOP = 262.0
#: notes: font size (pt), line pitch (mm), characters per line
NOTES_FONT = 6.0
NOTE_LINE_MM = 3.2
NOTE_WRAP = 128


def default_title_block() -> Path:
    """The title block shipped in ``springcad/data`` (identical to
    ``templates/drawing_title_block.toml``, kept so by a test); pass another path to
    :func:`load_title_block` to use your own."""
    return data_path(TITLE_BLOCK_NAME)


@dataclass(frozen=True)
class DrawingInfo:
    """What the title block needs beyond the part itself.

    ``release`` defaults to "not assessed": a drawing made outside ``springcad
    build`` is NOT FOR MANUFACTURE.
    """

    job: str
    quantity: int
    revision: str = "A"
    date: str = ""
    drawn_by: str = "springcad"
    release: ReleaseStatus = UNASSESSED


def load_title_block(path: Path | None = None) -> dict:
    """Read the title block template (TOML)."""
    path = Path(path) if path else default_title_block()
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def _finisher(info, fit: str) -> str:
    """The process that finishes a fit: the first of the part's processes (main, then
    secondary) that holds it."""
    keys = [k for k in (info.process, *info.secondary_processes)
            if k in processes() and processes()[k].can_finish(fit)]
    return process_text(keys[0]) if keys else "(no listed process holds it)"


def fields(part, info: DrawingInfo, scale: float, template: dict) -> dict:
    """The values the template's ``{field}`` placeholders take."""
    from springcad.geometry.sheet_cut import iso_fits

    p = part.info
    flat = template.get("flatness_mm", {}).get(p.kind)
    fits = iso_fits(p)
    return {"title": p.title, "part_number": p.part_number, "name": p.name,
            "material": p.material, "heat_treatment": p.heat_treatment or "none",
            "hardness": p.hardness or "as supplied",
            "heat_treatment_sequence": p.heat_treatment_sequence or "before cutting",
            "thickness": f"{fmt(p.thickness_mm)} mm", "quantity": str(info.quantity),
            "tolerance": (f"±{fmt(part.tolerance_mm)} mm" if p.cut_profile is not None
                          else "- (no DXF)"), "units": "mm",
            "revision": info.revision, "date": info.date, "scale": scale_text(scale),
            "job": info.job, "process": process_chain_text(p.process, p.secondary_processes),
            "fits": ", ".join(f"{fit} ({feature}) {_finisher(p, fit)}"
                              for feature, fit in fits.items()),
            "drawn_by": info.drawn_by, "sheet": "1/1", "standard": p.standard or "-",
            "general_tolerance": template.get("block", {}).get("general_tolerance",
                                                                "ISO 2768-mK"),
            "flatness": fmt(flat) if flat is not None else "", "projection": ""}


def process_position_mm(key: str) -> float:
    """Radius of the true-position zone of holes cut by this process (mm; 0 if unknown)."""
    p = processes().get(key)
    return p.position_tolerance_mm if p else 0.0


def _has_hole_table(part) -> bool:
    from springcad.export.views import hole_rows

    return bool(hole_rows(part.slabs[-1].region, ""))


def surface_note(spring) -> str:
    """The ring's surface note, from the surface condition its fatigue check assumes
    (``manufacturing.surface``; ``springcad/data/surface.csv``)."""
    return surface_table()[spring.material.duty.surface].drawing_note


def note_lines(part, values: dict, template: dict) -> list[str]:
    """Every note of the drawing, from the template's note lists and the part's own notes."""
    notes = template.get("notes", {})
    p = part.info
    lines = list(notes.get("general", []))
    if p.heat_treatment:
        lines += notes.get("heat_treated", {}).get(p.process, [])
    else:
        lines += notes.get("not_heat_treated", [])
    if values["fits"]:
        lines += notes.get("fits_heat_treated" if p.heat_treatment else "fits_not_heat_treated",
                           [])
    if p.cut_profile is not None:
        lines += notes.get("cut", [])
    spring = getattr(part, "spring", None)
    if isinstance(part, FlexureRing):
        # the flexures' cut faces: the note of the surface the fatigue check assumed
        lines.append(surface_note(spring))
    else:
        lines += notes.get("process", {}).get(p.process, [])
    if p.process == "wire_edm" and spring is not None:
        m = spring.manufacturing
        lines.append(f"Wire Ø{fmt(m.wire_diameter_mm)} mm or finer: the smallest inside "
                     f"radius R{fmt(m.min_inside_radius_mm)} is the wire radius + the "
                     f"{fmt(m.spark_gap_mm)} mm spark gap.")
    pos = process_position_mm(p.process)
    if pos > 0 and _has_hole_table(part):
        lines.append(f"Hole positions (hole table): true position Ø{fmt(2 * pos)} relative to "
                     "datum A, the outer diameter, and datum B, hole #1 (its angle).")
    if values["flatness"]:
        lines += notes.get("flatness", [])
    elif p.cut_profile is not None and p.thickness_mm <= THIN_SHEET_MM:
        lines += notes.get("thin_sheet", [])
    return [n.format(**values) for n in lines] + list(p.notes)


def _projection_symbol(sheet: Sheet, x: float, y: float, h: float) -> None:
    """ISO 5456-2 first-angle symbol in a cell (x, y) of height ``h``: truncated cone, its
    large end beside the end view (two circles) on the right."""
    d = 0.55 * h
    cy = y + 0.45 * h
    x0 = x + 2.0
    cone = [(x0, cy - 0.25 * d), (x0 + d, cy - 0.5 * d), (x0 + d, cy + 0.5 * d),
            (x0, cy + 0.25 * d)]
    sheet.polyline(cone, closed=True)
    c = (x0 + 2.0 * d, cy)
    for r in (0.5 * d, 0.25 * d):
        sheet.circle(c, r, style="-")
    sheet.polyline([(x0 - 1.0, cy), (c[0] + 0.5 * d + 1.0, cy)], style="-.")


def title_block(sheet: Sheet, template: dict, values: dict) -> tuple[float, float]:
    """Draw the title block at the bottom right; returns (left x, top y) in sheet mm."""
    block = template["block"]
    w, h = block["width_mm"], block["row_height_mm"]
    x0 = sheet.width - FRAME_MM - w
    top = FRAME_MM + h * len(template["rows"]) + 6.0
    sheet.rect(x0, FRAME_MM, w, top - FRAME_MM, lw=THICK)
    sheet.text(x0 + 2, top - 3, block.get("company", ""), size=NOTE_FONT, ha="left")
    y = top - 6.0
    for row in template["rows"]:
        x = x0
        for cell in row["cells"]:
            sheet.rect(x, y - h, cell["width_mm"], h)
            sheet.text(x + 1, y - 1.8, cell["label"], size=LABEL_FONT, ha="left", color="0.35")
            if cell["value"] == "{projection}":
                _projection_symbol(sheet, x + 0.5 * cell["width_mm"] - 6.0, y - h, h - 2.5)
            else:
                sheet.text(x + 1, y - h + 2.6, cell["value"].format(**values), size=NOTE_FONT,
                           ha="left")
            x += cell["width_mm"]
        y -= h
    return x0, top


def _wrap(items: list[str], width: int, bullet) -> list[str]:
    out = []
    for i, item in enumerate(items, 1):
        parts = textwrap.wrap(item, width) or [""]
        out += [f"{bullet(i)}{parts[0]}"] + [f"    {p}" for p in parts[1:]]
    return out


def release_box(sheet: Sheet, x0: float, y0: float, width: float,
                status: ReleaseStatus) -> float:
    """The release status above the title block: RELEASED, or NOT FOR MANUFACTURE and every
    reason. Returns the top of the box (sheet mm)."""
    lines = _wrap(list(status.reasons) + list(status.ratings), 150, lambda i: "- ")
    h = 9.0 + 3.0 * len(lines)
    sheet.rect(x0, y0, width, h, lw=THICK)
    colour = "black" if status.released else "#c00000"
    sheet.text(x0 + 2, y0 + h - 4.2, status.stamp, size=11, ha="left", weight="bold",
               color=colour)
    y = y0 + h - 10.0
    for line in lines:
        sheet.text(x0 + 2, y, line, size=LABEL_FONT, ha="left", va="bottom")
        y -= 3.0
    return y0 + h


def notes_block(sheet: Sheet, x0: float, y0: float, lines: list[str]) -> float:
    """Numbered notes, bottom at ``y0``; returns the top (sheet mm)."""
    wrapped = _wrap(lines, NOTE_WRAP, lambda i: f"{i}. ")
    y = y0 + 2.0
    for line in reversed(wrapped):
        sheet.text(x0, y, line, size=NOTES_FONT, ha="left", va="bottom")
        y += NOTE_LINE_MM
    sheet.text(x0, y + 0.5, "NOTES", size=NOTE_FONT, ha="left", va="bottom", weight="bold")
    return y + 5.0


def header(sheet: Sheet, part, info: DrawingInfo) -> None:
    """Title line and the job's name of the part at the top; the stamp at the top right."""
    y = sheet.height - FRAME_MM - 8.0
    sheet.text(FRAME_MM + 6, y, f"{part.info.title}   {part.part_number}   REV {info.revision}",
               size=11, ha="left", weight="bold")
    sheet.text(FRAME_MM + 6, y - 7.0, f"called {part.info.name} in job {info.job}; quantity "
               f"{info.quantity}", size=NOTE_FONT, ha="left")
    if not info.release.released:
        sheet.text(sheet.width - FRAME_MM - 6, y - 2.0, info.release.stamp, size=16, ha="right",
                   weight="bold", color="#c00000")


def draw_part(part, info: DrawingInfo, template: dict | None = None) -> Sheet:
    """Lay out the drawing of one part on an A3 sheet.

    Returns:
        the :class:`~springcad.export.sheet.Sheet`; ``texts`` holds every text,
        ``dims`` the dimension list, ``conflicts`` labels that found no free place.
    """
    from springcad.export.views import choose_scale_of, hole_rows, part_views

    template = template or load_title_block()
    sheet = Sheet()
    sheet.rect(FRAME_MM, FRAME_MM, sheet.width - 2 * FRAME_MM, sheet.height - 2 * FRAME_MM,
               lw=THICK)
    header(sheet, part, info)
    values = fields(part, info, choose_scale_of(part), template)
    x0, top = title_block(sheet, template, values)
    width = template["block"]["width_mm"]
    top = release_box(sheet, x0, top, width, info.release)
    top = notes_block(sheet, x0 + 1.0, top, note_lines(part, values, template))
    rows = hole_rows(part.slabs[-1].region, part.info.fits.get("holes", ""))
    if rows:
        sheet.text(x0 + 1.0, top + len(rows) * 4.2 + 2.5, "HOLE TABLE (angles from +Y, "
                   "counter-clockwise, seen from +Z)", size=NOTE_FONT, ha="left", va="bottom",
                   weight="bold")
        sheet.table(x0 + 1.0, top + len(rows) * 4.2, rows, [14.0, 34.0, 22.0, 22.0, 28.0])
        top += len(rows) * 4.2 + 8.0
    zone = (max(RIGHT_X0, x0), top + 10.0, sheet.width - FRAME_MM - 2.0, VIEWS_TOP)
    part_views(sheet, part, zone)
    return sheet


def write_drawing(part, info: DrawingInfo, out_dir: Path, template: dict | None = None,
                  png: bool = False) -> list[Path]:
    """Write ``<part number>.svg`` and ``.pdf`` (and ``.png`` if asked) into ``out_dir``."""
    sheet = draw_part(part, info, template)
    paths = [Path(out_dir) / f"{part.part_number}.{ext}"
             for ext in ("svg", "pdf") + (("png",) if png else ())]
    sheet.save(*paths)
    sheet.fig.clear()
    return paths

