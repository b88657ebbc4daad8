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
from springcad.design.catalogue import RIM_PIN_HOLE_FIT
from springcad.design.fatigue import surface_table
from springcad.design.processes import process_chain_text, process_text, processes
from springcad.export.release import UNASSESSED, ReleaseStatus
from springcad.export.sheet import (A3, FRAME_MM, LABEL_FONT, NOTE_FONT, TEXT_FONT, THICK, Sheet,
                                    fmt, scale_text)
from springcad.geometry.sheet_cut import iso_fits

TITLE_BLOCK_NAME = "drawing_title_block.toml"
#: free space between a title-block cell's label or value and the cell's edge (mm)
CELL_PAD_MM = 1.0
#: sheet parts this thin or thinner get the template's ``thin_sheet`` notes (mm)
THIN_SHEET_MM = 1.0
#: the right column (title block, notes, hole table, details): x from here to the frame
RIGHT_X0 = 230.0
#: highest y of any view (below the header line)
VIEWS_TOP = 262.0
#: one drawing page: ISO A3 landscape (mm)
PAGE = A3
#: least height (mm) of the right column's room for details and view B on sheet 1
MIN_VIEW_ZONE_MM = 100.0
#: notes: font size (pt) and line pitch (mm); lines are wrapped to the column's width
NOTES_FONT = TEXT_FONT
NOTE_LINE_MM = 4.6
#: hole table row height (mm)
TABLE_ROW_MM = 5.6
#: release reasons written out on the drawing (the rest: report.html, build.json)
RELEASE_LINES = 2
#: heading of the duty ratings in the release box: a rating is not a release reason
RATING_HEAD = "RATING (what the part is rated for; not a reason):"


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
    """The process that finishes a fit and the Ra it leaves (``"ground, Ra 0.4 um"``)."""
    key = _finisher_key(info, fit)
    if key is None:
        return "(no listed process holds it)"
    ra = FIT_RA_UM.get(key)
    return process_text(key) + (f", Ra {fmt(ra)} um" if ra is not None else "")


#: Ra (um) of a fitted feature by the process that finishes it: grinding gives Ra 0.4
#: cheaply; wire and sinker EDM Ra 0.8 with skim cuts or a finishing electrode (enough for
#: slip fits and bonded pins, review 7); a turned H9 Ra 1.6; a milled H11 on a 0.5 mm POM
#: edge the process's Ra 3.2 (a finer one is neither needed nor measurable there)
FIT_RA_UM = {"ground": 0.4, "wire_edm": 0.8, "sinker_edm": 0.8, "broached": 0.8,
             "turned": 1.6, "milled": 3.2, "laser": 3.2}


def _finisher_key(info, fit: str) -> str | None:
    """The key of the first of the part's processes (main, then secondary) that holds the fit."""
    return next((k for k in (info.process, *info.secondary_processes)
                 if k in processes() and processes()[k].can_finish(fit)), None)


def fields(part, info: DrawingInfo, scale: float, template: dict) -> dict:
    """The values the template's ``{field}`` placeholders take."""
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
            "fits": "; ".join(f"{fit} ({feature}) {_finisher(p, fit)}"
                              for feature, fit in fits.items()),
            "drawn_by": info.drawn_by, "sheet": "1/1", "standard": p.standard or "-",
            "general_tolerance": template.get("block", {}).get("general_tolerance",
                                                                "ISO 2768-mK"),
            "flatness": fmt(flat) if flat is not None else "", "projection": "",
            "flatness_where": (" on the rim (the flexures follow the ground plate)"
                               if p.kind == "flexure_ring" else ""),
            "profile": (fmt(2 * part.tolerance_mm)
                        if p.cut_profile is not None else "")}


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
    from springcad.geometry.disk import FlexureRing  # the CAD kernel: a drawing is made

    spring = getattr(part, "spring", None)
    if isinstance(part, FlexureRing):
        # the flexures' cut faces: the note of the surface the fatigue check assumed
        lines.append(surface_note(spring))
    else:
        lines += (notes.get("process_by_kind", {}).get(p.kind, {}).get(p.process)
                  or notes.get("process", {}).get(p.process, []))
    if p.process == "wire_edm" and p.thickness_mm > THIN_SHEET_MM:  # a shim: deburred only
        lines += notes.get("edges_wire_edm", [])
        if getattr(part, "bore", "") == "d_flat":
            lines += notes.get("edges_d_bore", [])
    if p.process == "wire_edm" and spring is not None:
        m = spring.manufacturing
        # the job's least inside radius, which the build's edm.inside_corner_radius rule
        # holds every contour to: the part's own smallest may be larger (R0.158 on a ring)
        lines.append(f"Wire Ø{fmt(m.wire_diameter_mm)} mm or finer: no inside radius of the "
                     f"contour is below R{fmt(m.min_inside_radius_mm)}, the wire radius + the "
                     f"{fmt(m.spark_gap_mm)} mm spark gap.")
    from springcad.export.views import hole_frames

    frames = hole_frames(part) if _has_hole_table(part) else ()
    if frames:
        lines.append(f"Hole positions (hole table, boxed: theoretically exact): position "
                     f"{frames[0][1]} to datum A, the outer diameter, and datum B, hole #1"
                     + (f"; {frames[1][1]} hole to hole (cut all holes in one setup)."
                        if len(frames) > 1 else "."))
    if p.fits.get("holes") == RIM_PIN_HOLE_FIT:
        lines.append(f"Holes {RIM_PIN_HOLE_FIT}: a slip fit over the m6 dowels, never pressed "
                     "(the dowels are bonded at assembly).")
    if values["flatness"]:
        lines += notes.get("flatness", [])
    elif p.cut_profile is not None and p.thickness_mm <= THIN_SHEET_MM:
        lines += notes.get("thin_sheet", [])
    return [n.format(**values) for n in lines] + list(p.notes)


def _projection_symbol(sheet: Sheet, x: float, y: float, h: float) -> None:
    """ISO 5456-2 first-angle symbol in the space (x, y) of height ``h`` under a cell's
    label: truncated cone, its large end beside the end view (two circles) on the right."""
    d = 0.9 * h
    cy = y + 0.5 * h
    x0 = x + 2.0
    cone = [(x0, cy - 0.25 * d), (x0 + d, cy - 0.5 * d), (x0 + d, cy + 0.5 * d),
            (x0, cy + 0.25 * d)]
    sheet.polyline(cone, closed=True)
    c = (x0 + 2.0 * d, cy)
    for r in (0.5 * d, 0.25 * d):
        sheet.circle(c, r, style="-")
    sheet.polyline([(x0 - 1.0, cy), (c[0] + 0.5 * d + 1.0, cy)], style="-.")


def title_block(sheet: Sheet, template: dict, values: dict, y_page: float = 0.0,
                notes: tuple[str, ...] = ()) -> tuple[float, float]:
    """Draw the title block at the bottom right of the sheet page starting at ``y_page``;
    returns (left x, top y) in sheet mm. Values are written at the notes' size; one too
    long for its cell is cut (:func:`cell_value`) and points to the note of ``notes``
    (numbered from 1) that states it in full."""
    block = template["block"]
    w, h = block["width_mm"], block["row_height_mm"]
    x0 = sheet.width - FRAME_MM - w
    bottom = y_page + FRAME_MM
    top = bottom + h * len(template["rows"]) + 6.0
    sheet.rect(x0, bottom, w, top - bottom, lw=THICK)
    sheet.text(x0 + 2, top - 3, block.get("company", ""), size=NOTE_FONT, ha="left")
    y = top - 6.0
    for row in template["rows"]:
        x = x0
        for cell in row["cells"]:
            sheet.rect(x, y - h, cell["width_mm"], h)
            label = sheet.text(x + 1, y - CELL_PAD_MM, cell["label"], size=LABEL_FONT,
                               ha="left", va="top", color="0.35", role="title block")
            if cell["value"] == "{projection}":
                _projection_symbol(sheet, x + 0.5 * cell["width_mm"] - 6.0,
                                   y - h + CELL_PAD_MM, label[1] - (y - h) - 1.5 * CELL_PAD_MM)
            else:
                value = cell_value(sheet, cell["value"].format(**values),
                                   cell["width_mm"] - 2.0, notes)
                sheet.text(x + 1, y - h + CELL_PAD_MM, value, ha="left", va="bottom",
                           role="title block value", size=NOTE_FONT)
            x += cell["width_mm"]
        y -= h
    return x0, top


#: words a cut title-block value does not end on
_DANGLING = frozenset(("and", "or", "of", "from", "with", "to", "the", "a", "/", "-"))


def cell_value(sheet: Sheet, text: str, width_mm: float, notes=()) -> str:
    """``text`` as a title-block cell of ``width_mm`` shows it at NOTE_FONT (never smaller:
    a shrunk value fell under the 2.5 mm capital height): whole, or cut after the last
    word (not inside brackets, not on "and" or the like; a name without spaces: after a
    character) that leaves room for " ... note N", N the first of ``notes`` that holds the
    whole text, else for " ..." (a job's name is whole in the header line)."""
    def fits(s: str) -> bool:
        return sheet.text_size(s, size=NOTE_FONT)[0] <= width_mm

    if not text or fits(text):
        return text
    n = next((k for k, note in enumerate(notes, 1) if text in note), None)
    tail = " ..." + (f" note {n}" if n else "")
    words = text.split(" ")
    heads = (" ".join(words[:k]).rstrip(",;/ ") for k in range(len(words) - 1, 0, -1)
             if words[k - 1] not in _DANGLING)
    cuts = [c for c in heads if c.count("(") == c.count(")")]
    cuts += [text[:k] for k in range(len(text) - 1, 0, -1)]
    return next((c + tail for c in cuts if c and fits(c + tail)), tail.strip())


def chars_per_line(sheet: Sheet, width_mm: float, size: float = NOTES_FONT) -> int:
    """How many characters of running text fit ``width_mm`` at ``size`` (measured on a
    sample line of the notes' own letters)."""
    sample = "Cut faces Ra 0.8 um: main cut and at least two skim cuts; holes E7, Ø1.5 m6 dowels."
    w, _ = sheet.text_size(sample, size=size)
    return max(20, int(len(sample) * width_mm / w))


def _wrap(items: list[str], width: int, bullet) -> list[str]:
    out = []
    for i, item in enumerate(items, 1):
        parts = textwrap.wrap(item, width, break_on_hyphens=False) or [""]
        out += [f"{bullet(i)}{parts[0]}"] + [f"    {p}" for p in parts[1:]]
    return out


def release_box(sheet: Sheet, x0: float, y0: float, width: float,
                status: ReleaseStatus) -> float:
    """The release status above the title block: RELEASED, or NOT FOR MANUFACTURE, how many
    reasons and the first of them (at the notes' size, cut after :data:`RELEASE_LINES`
    lines; every reason is in report.html and build.json), then, under a heading of their
    own (:data:`RATING_HEAD`), the duty's ratings: what the part is rated for is a fact
    of the design, not a reason it is held back, so it is never written as one of the
    reasons' bullets. Returns the top of the box (sheet mm)."""
    reasons = list(status.reasons)
    per_line = chars_per_line(sheet, width - 4.0) - 2
    lines: list[tuple[str, str]] = []  # (text, font weight)
    if reasons:
        head = (f"{len(reasons)} reason{'s' if len(reasons) > 1 else ''} (all in report.html "
                "and build.json), the first:")
        body = _wrap(reasons[:1], per_line, lambda i: "- ")
        if len(body) > RELEASE_LINES:
            body = body[:RELEASE_LINES]
            body[-1] = body[-1].rstrip()[:-2] + " ..."
        lines = [(head, "normal")] + [(b, "normal") for b in body]
    if status.ratings:
        lines += [(RATING_HEAD, "bold")] + [
            (r, "normal") for r in _wrap(list(status.ratings), per_line, lambda i: "  ")]
    h = 9.0 + NOTE_LINE_MM * len(lines)
    sheet.rect(x0, y0, width, h, lw=THICK)
    colour = "black" if status.released else "#c00000"
    sheet.text(x0 + 2, y0 + h - 4.2, status.stamp, size=11, ha="left", weight="bold",
               color=colour)
    y = y0 + h - 9.0 - NOTE_LINE_MM + 0.8
    for line, weight in lines:
        sheet.text(x0 + 2, y, line, size=NOTES_FONT, ha="left", va="bottom", weight=weight)
        y -= NOTE_LINE_MM
    return y0 + h


def notes_block(sheet: Sheet, x0: float, y0: float, lines: list[str], width: float) -> float:
    """Numbered notes ``width`` mm wide, bottom at ``y0``; returns the top (sheet mm)."""
    wrapped = _wrap(lines, chars_per_line(sheet, width) - 4, lambda i: f"{i}. ")
    y = y0 + 2.0 + NOTE_LINE_MM * len(wrapped)
    # written top down, so the SVG's text reads in the notes' order
    sheet.text(x0, y + 0.5, "NOTES", size=NOTE_FONT, ha="left", va="bottom", weight="bold")
    for k, line in enumerate(wrapped, 1):
        sheet.text(x0, y - NOTE_LINE_MM * k, line, size=NOTES_FONT, ha="left", va="bottom")
    return y + 5.0


def header(sheet: Sheet, part, info: DrawingInfo, y_page: float = 0.0) -> None:
    """Title line and the job's name of the part at the top of the sheet page starting at
    ``y_page``; the stamp at the top right."""
    y = y_page + PAGE[1] - FRAME_MM - 8.0
    sheet.text(FRAME_MM + 6, y, f"{part.info.title}   {part.part_number}   REV {info.revision}",
               size=11, ha="left", weight="bold")
    sheet.text(FRAME_MM + 6, y - 7.0, f"called {part.info.name} in job {info.job}; quantity "
               f"{info.quantity}", size=NOTE_FONT, ha="left")
    if not info.release.released:
        sheet.text(sheet.width - FRAME_MM - 6, y - 2.0, info.release.stamp, size=16, ha="right",
                   weight="bold", color="#c00000")


def _hole_table(sheet: Sheet, x: float, bottom: float, rows) -> float:
    """The hole table with its heading, bottom at ``bottom``; returns its top (sheet mm)."""
    top = bottom + 3.0 + len(rows) * TABLE_ROW_MM
    sheet.text(x, top + 2.5, "HOLE TABLE (angles from +Y, CCW, seen from +Z)", size=NOTE_FONT,
               ha="left", va="bottom", weight="bold")
    sheet.table(x, top, rows, [16.0, 48.0, 30.0, 30.0, 40.0], row_h=TABLE_ROW_MM)
    return top + 9.0


def _column_height(sheet: Sheet, notes: list[str], rows, width: float) -> float:
    """Height (mm) the notes and the hole table take in the right column."""
    lines = len(_wrap(notes, chars_per_line(sheet, width) - 4, lambda i: f"{i}. "))
    return lines * NOTE_LINE_MM + 7.0 + (len(rows) * TABLE_ROW_MM + 9.0 if rows else 0.0)


def draw_part(part, info: DrawingInfo, template: dict | None = None) -> Sheet:
    """Lay out the drawing of one part on one A3 sheet, or on two when the notes and the hole
    table at a readable size would leave the views' right column less than
    :data:`MIN_VIEW_ZONE_MM` (a part with no view there: when they do not fit). Sheet 1:
    views, release and title block; sheet 2: hole table (top left), notes and title block
    (the right column); one figure,
    sheet 2 below sheet 1, the PDF a page each.

    Returns:
        the :class:`~springcad.export.sheet.Sheet`; ``texts`` holds every text,
        ``dims`` the dimension list, ``conflicts`` labels that found no free place.
    """
    from springcad.export.views import choose_scale_of, hole_rows, part_views, uses_right_column

    template = template or load_title_block()
    values = fields(part, info, choose_scale_of(part), template)
    notes = note_lines(part, values, template)
    rows = hole_rows(part.slabs[-1].region, part.info.fits.get("holes", ""))
    width = template["block"]["width_mm"]
    probe = Sheet()
    x0, top = title_block(probe, template, values, notes=tuple(notes))
    top = release_box(probe, x0, top, width, info.release)
    room = VIEWS_TOP - (top + _column_height(probe, notes, rows, width - 2.0))
    two = room < (MIN_VIEW_ZONE_MM if uses_right_column(part) else 0.0)
    probe.fig.clear()
    pages = 2 if two else 1
    sheet = Sheet((PAGE[0], PAGE[1] * pages), bottom_mm=-(pages - 1) * PAGE[1])
    for k in range(pages):
        y_page = -k * PAGE[1]  # page 1 on top, so the SVG reads in page order
        sheet.rect(FRAME_MM, y_page + FRAME_MM, sheet.width - 2 * FRAME_MM,
                   PAGE[1] - 2 * FRAME_MM, lw=THICK)
        header(sheet, part, info, y_page)
        x0, top = title_block(sheet, template, {**values, "sheet": f"{k + 1}/2" if two
                                                else "1/1"}, y_page, tuple(notes))
        if k == 0:
            top = release_box(sheet, x0, top, width, info.release)
        if k == 1 or not two:
            top = notes_block(sheet, x0 + 1.0, top, notes, width - 2.0)
            if rows and not two:
                top = _hole_table(sheet, x0 + 1.0, top, rows)
            elif rows:  # sheet 2: the table at the top left, the whole column for the notes
                _hole_table(sheet, FRAME_MM + 10.0, y_page + VIEWS_TOP - 12.0
                            - len(rows) * TABLE_ROW_MM, rows)
        if two and k == 0:
            sheet.text(x0 + 1.0, top + 2.0, ("HOLE TABLE AND " if rows else "") + "NOTES: SHEET 2",
                       size=NOTE_FONT,
                       ha="left", va="bottom", weight="bold")
            top += 8.0
        if k == 0:
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

