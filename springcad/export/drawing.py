"""Vendor drawings (SVG and PDF): the part's profile with its key dimensions, a side
view with the thickness, a detail where features are small, notes and a title
block filled from the title block template (``templates/drawing_title_block.toml``,
shipped as package data).

The drawing is for ordering and inspection; the shop cuts from the DXF. Every
dimension value is written as text (see :func:`springcad.export.sheet.fmt`).
Units: mm.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from springcad.data import data_path
from springcad.export.release import UNASSESSED, ReleaseStatus
from springcad.export.sheet import LABEL_FONT, NOTE_FONT, THICK, THIN, Sheet, View, fit_scale, fmt, scale_text

TITLE_BLOCK_NAME = "drawing_title_block.toml"


def default_title_block() -> Path:
    """The title block shipped in ``springcad/data`` (identical to
    ``templates/drawing_title_block.toml``, kept so by a test); pass another path to
    :func:`load_title_block` to use your own."""
    return data_path(TITLE_BLOCK_NAME)
#: A3 layout (sheet mm): main view (centre, box), a second view at the top right
#: (centre, box), a side view of flat parts under the main view (centre x, base y)
MAIN_CENTRE, MAIN_BOX = (130.0, 170.0), 180.0
RIGHT_CENTRE, RIGHT_BOX = (325.0, 200.0), 100.0
BELOW = (130.0, 30.0)
PROCESS_TEXT = {"wire_edm": "wire EDM", "laser": "laser / waterjet / EDM", "turned": "turned",
                "purchased": "catalogue part"}


@dataclass(frozen=True)
class DrawingInfo:
    """What the title block needs beyond the part itself."""

    job: str
    quantity: int
    revision: str = "A"
    date: str = ""
    drawn_by: str = "springcad"
    release: ReleaseStatus = UNASSESSED


def _dim_hole_circle(sheet, v, centre, scale: float, part, start_offset: float = 0.0) -> None:
    """Bolt circle (drawn and dimensioned) and a leader "n x diameter thru" to the first hole."""
    if not part.hole_centres:
        return
    bc = math.hypot(*part.hole_centres[0])
    sheet.circle(centre, bc * scale)
    sheet.dim_diameter(centre, bc * scale, -35, f"Ø{fmt(2 * bc)} bolt circle")
    h = v(part.hole_centres[0])
    sheet.leader(h + np.array([start_offset, start_offset]), h + np.array([18.0, 14.0]),
                 f"{len(part.hole_centres)}× Ø{fmt(part.hole_diameter)} thru")


def load_title_block(path: Path | None = None) -> dict:
    """Read the title block template (TOML)."""
    path = Path(path) if path else default_title_block()
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def _fields(part, info: DrawingInfo, scale: float) -> dict:
    p = part.info
    tol = getattr(part, "tolerance_mm", None)
    return {"title": p.title, "part_number": p.part_number, "material": p.material,
            "heat_treatment": p.heat_treatment or "none", "thickness": f"{fmt(p.thickness_mm)} mm",
            "quantity": str(info.quantity), "tolerance": f"±{fmt(tol)} mm" if tol else "-",
            "units": "mm", "revision": info.revision, "date": info.date, "scale": scale_text(scale),
            "job": info.job, "process": PROCESS_TEXT.get(p.process, p.process),
            "drawn_by": info.drawn_by, "sheet": "1/1", "standard": p.standard or "-"}


def _title_block(sheet: Sheet, template: dict, fields: dict):
    block = template["block"]
    w, h = block["width_mm"], block["row_height_mm"]
    x0 = sheet.width - 10.0 - w
    y = 10.0 + h * len(template["rows"]) + 6.0
    sheet.rect(x0, 10.0, w, y - 10.0, lw=THICK)
    sheet.text(x0 + 2, y - 3, block.get("company", ""), size=NOTE_FONT, ha="left")
    y -= 6.0
    for row in template["rows"]:
        x = x0
        for cell in row["cells"]:
            sheet.rect(x, y - h, cell["width_mm"], h)
            sheet.text(x + 1, y - 1.8, cell["label"], size=LABEL_FONT, ha="left", color="0.35")
            sheet.text(x + 1, y - h + 2.6, cell["value"].format(**fields), size=NOTE_FONT, ha="left")
            x += cell["width_mm"]
        y -= h
    return x0, 10.0 + h * len(template["rows"]) + 6.0


def _release_box(sheet: Sheet, x0: float, y0: float, width: float, status: ReleaseStatus) -> float:
    """The release status above the title block: RELEASED, or NOT FOR MANUFACTURE and
    every reason. Returns the top of the box (sheet mm)."""
    import textwrap

    lines = []
    for r in status.reasons:
        parts = textwrap.wrap(r, int(width / 1.25))
        lines += [f"- {parts[0]}"] + [f"  {p}" for p in parts[1:]]
    h = 8.0 + 3.2 * len(lines)
    sheet.rect(x0, y0, width, h, lw=THICK)
    colour = "black" if status.released else "#c00000"
    sheet.text(x0 + 2, y0 + h - 4.0, status.stamp, size=11, ha="left", weight="bold",
               color=colour)
    y = y0 + h - 8.5
    for line in lines:
        sheet.text(x0 + 2, y, line, size=LABEL_FONT, ha="left")
        y -= 3.2
    return y0 + h


def _notes(sheet: Sheet, x0: float, y0: float, lines: list[str]):
    import textwrap

    y = y0 + 8.0
    wrapped = []
    for i, line in enumerate(lines, 1):
        parts = textwrap.wrap(line, 78)
        wrapped += [f"{i}. {parts[0]}"] + [f"    {p}" for p in parts[1:]]
    for line in reversed(wrapped):
        sheet.text(x0, y, line, size=NOTE_FONT, ha="left")
        y += 4.2
    sheet.text(x0, y + 1.0, "NOTES", size=NOTE_FONT, ha="left", weight="bold")


def _draw_loops(sheet: Sheet, view: View, profile, step_mm: float, lw=THICK):
    for loop in profile.loops:
        sheet.polyline(view(loop.sample(step_mm)), lw=lw, closed=True)


def _draw_clipped(sheet: Sheet, view: View, profile, window, step_mm: float):
    """Draw the loops inside a model window (xmin, ymin, xmax, ymax); a frame around it."""
    x0, y0, x1, y1 = window
    for loop in profile.loops:
        p = loop.sample(step_mm)
        keep = (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)
        q = view(p).copy()
        q[~keep] = np.nan
        sheet.ax.plot(q[:, 0], q[:, 1], "-", lw=THICK, color="black")
    a, b = view((x0, y0)), view((x1, y1))
    sheet.rect(a[0], a[1], b[0] - a[0], b[1] - a[1], lw=THIN)


def _side_view(sheet: Sheet, x: float, y: float, scale: float, steps, caption="SIDE VIEW",
               horizontal=False):
    """Side view: stacked rectangles ((length, radius, label), ...) in sheet mm.

    The first step sits on (x, y) and the next ones on top of it; each gets a
    length dimension. ``horizontal`` drops the axis line (flat parts under the
    main view). Returns the top edge (sheet mm).
    """
    z = y
    for length, radius, label in steps:
        h, w = length * scale, 2 * radius * scale
        sheet.rect(x - w / 2, z, w, h, lw=THICK)
        if label:
            sheet.dim_linear((x + w / 2, z), (x + w / 2, z + h), -7.0, label)
        z += h
    if not horizontal:
        sheet.polyline([(x, y - 4), (x, z + 4)], lw=THIN, style="-.")
    sheet.text(x, y - 5.0, caption, size=NOTE_FONT)
    return z


def _ring_views(sheet: Sheet, part):
    prof = part.info.cut_profile
    s = fit_scale(2 * part.outer_radius, MAIN_BOX)
    v = View(MAIN_CENTRE, s)
    _draw_loops(sheet, v, prof, 0.4 / s)
    c = v((0, 0))
    sheet.centre_mark(c, part.outer_radius * s + 4)
    sheet.dim_diameter(c, part.outer_radius * s, 35, f"Ø{fmt(2 * part.outer_radius)}")
    sheet.dim_radius(c, part.root_radius * s, 200, f"R{fmt(part.root_radius)} root (ref)")
    _dim_hole_circle(sheet, v, c, s, part, start_offset=0.4 * part.hole_diameter * s)
    # detail A: flexure 0 tip, ball centre at (0, r_c)
    rc, rb = part.contact_radius, part.tip_radius
    half = 2.0 * math.pi * rc / part.n_flexures * 1.2
    window = (-half, rc - 0.5 * half, half, rc + 1.2 * half)
    sd = fit_scale(max(2 * half, window[3] - window[1]), RIGHT_BOX)
    dv = View((RIGHT_CENTRE[0], RIGHT_CENTRE[1] - sd * (rc + 0.35 * half)), sd)
    _draw_clipped(sheet, dv, prof, window, 0.2 / sd)
    ball = dv((0, rc))
    sheet.centre_mark(ball, 3.0)
    a = np.linspace(math.pi / 2 - half / rc, math.pi / 2 + half / rc, 60)
    sheet.polyline(dv(np.column_stack([rc * np.cos(a), rc * np.sin(a)])), lw=THIN, style="-.")
    sheet.leader(dv((rb * math.cos(-2.4), rc + rb * math.sin(-2.4))),
                 ball + np.array([-30.0, -25.0]), f"R{fmt(rb)} tip", ha="right")
    arc_pt = (rc * math.cos(math.pi / 2 - 0.8 * half / rc), rc * math.sin(math.pi / 2 - 0.8 * half / rc))
    sheet.leader(dv(arc_pt), dv(arc_pt) + np.array([8.0, -22.0]),
                 f"R{fmt(rc)} contact radius")
    sheet.leader(dv((-rb * 0.75, rc + rb * 1.1)), ball + np.array([-30.0, 25.0]),
                 f"R{fmt(part.neck_fillet_radius)} neck fillet", ha="right")
    sheet.text(*(dv((0, window[1])) - np.array([0, 6])),
               f"DETAIL A  flexure 0 tip  {scale_text(sd)}", size=NOTE_FONT)
    sheet.leader(v((0, rc)), v((0, rc)) + np.array([25.0, 60.0]), "A")
    _side_view(sheet, BELOW[0], BELOW[1], s, [(part.thickness, part.outer_radius, fmt(part.thickness))],
               horizontal=True)
    return s


def _cam_views(sheet: Sheet, part):
    prof = part.info.cut_profile
    s = fit_scale(2 * part.tip_radius, MAIN_BOX * 0.7)
    v = View(MAIN_CENTRE, s)
    _draw_loops(sheet, v, prof, 0.3 / s)
    c = v((0, 0))
    sheet.centre_mark(c, part.tip_radius * s + 4)
    sheet.dim_diameter(c, part.tip_radius * s, 30, f"Ø{fmt(2 * part.tip_radius)} tooth tips")
    sheet.circle(c, part.root_radius * s)
    sheet.dim_diameter(c, part.root_radius * s, -30, f"Ø{fmt(2 * part.root_radius)} root")
    sheet.circle(c, part.contact_radius * s)
    sheet.dim_radius(c, part.contact_radius * s, 150, f"R{fmt(part.contact_radius)} contact radius")
    r_bore = 0.5 * part.bore_diameter
    sheet.dim_diameter(c, r_bore * s, 210, f"Ø{fmt(part.bore_diameter)} bore")
    if part.bore == "d_flat":
        flat, = prof.loop("bore").named("flat")
        y_flat = flat.start[1]
        sheet.dim_linear(c, v((0, y_flat)), 10.0, f"{fmt(abs(y_flat))} flat")
    pocket, = prof.loop("teeth").named("pocket", 0)
    sheet.leader(v(pocket.point_at(-math.pi / 2)), v(pocket.point_at(-math.pi / 2)) + np.array([30, 40]),
                 f"R{fmt(pocket.radius)} pocket (gap {fmt(part.gap)} to tip)")
    steps = []
    if part.hub_length:
        steps.append((part.hub_length, part.hub_radius, fmt(part.hub_length)))
    steps.append((part.toothed_length, part.tip_radius, fmt(part.toothed_length)))
    side_s = fit_scale(max(part.toothed_length + part.hub_length, 2 * part.tip_radius), RIGHT_BOX)
    _side_view(sheet, RIGHT_CENTRE[0], RIGHT_CENTRE[1] - 0.5 * RIGHT_BOX, side_s, steps,
               caption=f"SIDE VIEW {scale_text(side_s)} (hub below)")
    return s


def _annulus_views(sheet: Sheet, part):
    s = fit_scale(2 * part.outer_radius, MAIN_BOX)
    v = View(MAIN_CENTRE, s)
    prof = part.slabs[0].region
    _draw_loops(sheet, v, prof, 0.4 / s)
    c = v((0, 0))
    sheet.centre_mark(c, part.outer_radius * s + 4)
    sheet.dim_diameter(c, part.outer_radius * s, 35, f"Ø{fmt(2 * part.outer_radius)}")
    if part.inner_radius > 0:
        sheet.dim_diameter(c, part.inner_radius * s, 215, f"Ø{fmt(2 * part.inner_radius)}")
    _dim_hole_circle(sheet, v, c, s, part)
    _side_view(sheet, BELOW[0], BELOW[1], s, [(part.length, part.outer_radius, fmt(part.length))],
               horizontal=True)
    return s


def _shaft_views(sheet: Sheet, part):
    """Torque shaft: end view of its profile(s) and a side view with lengths."""
    top = part.slabs[-1].region
    r = max(abs(p) for p in top.outer.sample(0.5).ravel())
    s = fit_scale(2 * r, MAIN_BOX * 0.6)
    v = View(MAIN_CENTRE, s)
    _draw_loops(sheet, v, top, 0.3 / s)
    c = v((0, 0))
    sheet.centre_mark(c, r * s + 4)
    for key, value in part.info.dimensions.items():
        if "diameter" in key:
            sheet.dim_diameter(c, 0.5 * value * s, 35 if "outer" in key or "shaft" in key else 215,
                               f"Ø{fmt(value)} {key.replace(' diameter', '')}")
    steps = [(sl.length_mm, r, fmt(sl.length_mm)) for sl in part.slabs]
    side_s = fit_scale(max(part.length, 2 * r), RIGHT_BOX)
    x, y0 = RIGHT_CENTRE[0], RIGHT_CENTRE[1] - 0.5 * RIGHT_BOX
    top_z = _side_view(sheet, x, y0, side_s, steps,
                       caption=f"SIDE VIEW {scale_text(side_s)} (spring end up)")
    sheet.dim_linear((x - r * side_s, y0), (x - r * side_s, top_z), 10.0, fmt(part.length))
    return s


VIEWS = {"flexure_ring": _ring_views, "camshaft": _cam_views, "torque_shaft": _shaft_views}


def draw_part(part, info: DrawingInfo, template: dict | None = None) -> Sheet:
    """Lay out the drawing of one part on an A3 sheet.

    Returns:
        the :class:`Sheet`; its ``texts`` list holds every text written.
    """
    template = template or load_title_block()
    sheet = Sheet()
    sheet.rect(10, 10, sheet.width - 20, sheet.height - 20, lw=THICK)
    scale = VIEWS.get(part.info.kind, _annulus_views)(sheet, part)
    fields = _fields(part, info, scale)
    x0, top = _title_block(sheet, template, fields)
    top = _release_box(sheet, x0, top, template["block"]["width_mm"], info.release)
    notes = template.get("notes", {})
    lines = notes.get("general", []) + (notes.get("cut", []) if part.info.cut_profile else [])
    _notes(sheet, x0, top, [n.format(**fields) for n in lines] + list(part.info.notes))
    sheet.text(20, sheet.height - 18, f"{part.info.title}  {part.part_number}", size=11,
               ha="left", weight="bold")
    dims = "   ".join(f"{k} {fmt(v)}" for k, v in part.info.dimensions.items())
    sheet.text(20, sheet.height - 25, f"key dimensions (mm): {dims}", size=NOTE_FONT, ha="left")
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
