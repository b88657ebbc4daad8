"""A drawing sheet in millimetres on a matplotlib figure: primitives, dimensions, free space.

Everything is placed in sheet millimetres (origin bottom left); a :class:`View`
maps model millimetres to the sheet at a drawing scale. Text stays text in SVG
and PDF, so the drawing can be searched and checked.

The sheet remembers every line segment and every text box it drew, so a label
can be *placed*: :meth:`Sheet.place_text` and the dimension primitives try
candidate positions and take the first whose text box keeps :data:`TEXT_GAP_MM`
from every other text, every line and the border (text boxes are measured by
the renderer, not estimated). All text is horizontal (unidirectional
dimensioning, ISO 129-1). Every dimension written is also recorded as a
:class:`Dimension`, the drawing's dimension list, which tests hold against the
solid. Units: mm (model and sheet), points only for line widths and font sizes.
"""

from __future__ import annotations

import contextlib
import functools
import math
from dataclasses import dataclass

import numpy as np

from springcad.export.sheet_hits import (NEAR_MM, boxes_overlap, grow, segments_hit_box,
                                        segments_hit_boxes)
from springcad.units import fmt_mm

#: ISO A3 landscape (mm)
A3 = (420.0, 297.0)
#: drawing frame inset from the sheet edge (mm)
FRAME_MM = 10.0
#: standard drawing scales (ISO 5455), largest first
SCALES = (50.0, 20.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1)
THICK, THIN = 0.7, 0.25  # line widths (pt)
#: font sizes (pt): every text of a drawing (dimension, note, table, title-block label and
#: value) is written at TEXT_FONT, whose capital height (DejaVu Sans: 0.729 em) is at least
#: MIN_CAP_MM, the ISO 3098-0 / ISO 129-1 least for an A3 sheet (issue 26: the title
#: block's labels were 6.5 pt, 1.67 mm)
TEXT_FONT = 10.0
DIM_FONT, NOTE_FONT, LABEL_FONT = TEXT_FONT, TEXT_FONT, TEXT_FONT
#: capital height of DejaVu Sans per point of font size (mm / pt)
CAP_MM_PER_PT = 0.729 * 25.4 / 72.0
MIN_CAP_MM = 2.5
#: the PDF core font (one of the 14 every reader has) the PDFs are written in when every
#: text is in its character set (:meth:`Sheet.core_font_suffices`)
PDF_CORE_FONT = "Helvetica"
#: free space kept around every text box (mm)
TEXT_GAP_MM = 0.6
#: arrow head length (mm)
ARROW_MM = 2.2
#: dimension text sits this far from its dimension line (mm)
DIM_TEXT_GAP_MM = 1.0
#: gap between a theoretically exact (boxed) value and its frame (mm)
TED_PAD_MM = 1.0
#: height of a tolerance frame row and side of a datum square (mm)
FRAME_ROW_MM = 6.0
#: geometric characteristic symbols drawn by Sheet.gdt_symbol
GDT_SYMBOLS = ("position", "profile", "coaxiality", "flatness")


def fmt(value: float) -> str:
    """A dimension value as written on the drawing (:func:`springcad.units.fmt_mm`)."""
    return fmt_mm(value)


def scale_text(scale: float) -> str:
    return f"{fmt(scale)}:1" if scale >= 1 else f"1:{fmt(1 / scale)}"


def fit_scale(extent_mm: float, box_mm: float) -> float:
    """Largest standard scale at which ``extent_mm`` fits in ``box_mm``."""
    for s in SCALES:
        if extent_mm * s <= box_mm:
            return s
    return SCALES[-1]


@dataclass(frozen=True)
class Dimension:
    """One dimension written on a drawing (the drawing's dimension list).

    Attributes:
        kind: "diameter", "radius", "flat" (distance of a flat from the axis),
            "length" (between two z levels), "position" (a hole centre).
        value: mm (for a position, the distance from the axis).
        label: the text as written.
        feature: what it dimensions ("outer", "bore", "hole pattern", "hub flat" ...).
        z: for a length, the two z levels of the part frame it spans (mm).
        angle_deg: for a position, the angle from +Y, counter-clockwise (deg).
    """

    kind: str
    value: float
    label: str
    feature: str = ""
    z: tuple[float, float] | None = None
    angle_deg: float | None = None


class View:
    """Model (x, y) mm to sheet mm: ``origin + scale * (x, y)``, x mirrored for a view
    from behind (``mirror_x``)."""

    def __init__(self, origin, scale: float, mirror_x: bool = False):
        self.origin = np.asarray(origin, dtype=float)
        self.scale = scale
        self._flip = np.array([-1.0 if mirror_x else 1.0, 1.0])

    def __call__(self, pts) -> np.ndarray:
        return self.origin + self.scale * self._flip * np.asarray(pts, dtype=float)


class Sheet:
    """A matplotlib figure whose single axes spans the sheet in millimetres.

    Attributes:
        texts: every text written, in order.
        sizes: (font size in pt, role) of every text, in the same order.
        boxes: the sheet-mm box (x0, y0, x1, y1) of every text.
        dims: the dimension list (:class:`Dimension`).
        frames: every tolerance frame row drawn (symbol key, then its cells' texts).
        conflicts: labels that found no free place (drawn at their first
            candidate); a good layout leaves it empty.
    """

    def __init__(self, size_mm=A3, bottom_mm: float = 0.0):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.width, self.height = size_mm
        self.bottom = bottom_mm  # sheet y of the figure's lower edge (< 0: pages below page 1)
        self.fig = Figure(figsize=(self.width / 25.4, self.height / 25.4))
        self._canvas = FigureCanvasAgg(self.fig)
        self._renderer = _measuring_renderer(self.fig.dpi)
        self.ax = self.fig.add_axes((0, 0, 1, 1))
        self.ax.set_xlim(0, self.width)
        self.ax.set_ylim(self.bottom, self.bottom + self.height)
        self.ax.set_aspect("equal")
        self.ax.axis("off")
        self.texts: list[str] = []
        self.sizes: list[tuple[float, str]] = []
        self.boxes: list[tuple] = []
        self.dims: list[Dimension] = []
        self.frames: list[tuple[str, ...]] = []
        self.conflicts: list[str] = []
        self._segs: list[np.ndarray] = []
        self._seg_cache: np.ndarray | None = None
        self._seg_bounds: np.ndarray | None = None

    @property
    def inner(self) -> tuple[float, float, float, float]:
        """The drawing area inside the frame (sheet mm)."""
        return (FRAME_MM, self.bottom + FRAME_MM, self.width - FRAME_MM,
                self.bottom + self.height - FRAME_MM)

    # ---------------------------------------------------------------- bookkeeping
    def _add_segments(self, p: np.ndarray) -> None:
        p = p[~np.isnan(p).any(axis=1)] if np.isnan(p).any() else p
        if len(p) > 1:
            self._segs.append(np.hstack([p[:-1], p[1:]]))
            self._seg_cache = self._seg_bounds = None

    @property
    def segments(self) -> np.ndarray:
        """Every line segment drawn so far (n, 4), sheet mm."""
        if self._seg_cache is None:
            self._seg_cache = np.vstack(self._segs) if self._segs else np.zeros((0, 4))
        return self._seg_cache

    def is_free(self, box, pad: float = TEXT_GAP_MM, lines: bool = True) -> bool:
        """Whether a text box keeps ``pad`` from every text, line and the frame."""
        x0, y0, x1, y1 = self.inner
        if box[0] < x0 + pad or box[1] < y0 + pad or box[2] > x1 - pad or box[3] > y1 - pad:
            return False
        grown = grow(box, pad)
        if any(boxes_overlap(grown, b) for b in self.boxes):
            return False
        return not (lines and self._lines_hit(grown))

    def _lines_hit(self, box) -> bool:
        """Whether a drawn segment crosses or touches ``box``: clipped only against the
        segments whose bounding box comes within :data:`NEAR_MM` of it (the others cannot
        reach it; the answer is the one clipping every segment gives)."""
        segs = self.segments
        if self._seg_bounds is None:
            self._seg_bounds = np.column_stack([np.minimum(segs[:, 0], segs[:, 2]),
                                                np.minimum(segs[:, 1], segs[:, 3]),
                                                np.maximum(segs[:, 0], segs[:, 2]),
                                                np.maximum(segs[:, 1], segs[:, 3])])
        b = self._seg_bounds
        near = ((b[:, 2] >= box[0] - NEAR_MM) & (b[:, 0] <= box[2] + NEAR_MM)
                & (b[:, 3] >= box[1] - NEAR_MM) & (b[:, 1] <= box[3] + NEAR_MM))
        return bool(segments_hit_box(segs[near], box).any())

    def path_is_free(self, pts, pad: float = 0.3) -> bool:
        """Whether a polyline (sheet mm) keeps ``pad`` from every text box."""
        p = np.asarray(pts, float)
        segs = np.hstack([p[:-1], p[1:]])
        boxes = np.asarray([grow(b, pad) for b in self.boxes], dtype=float).reshape(-1, 4)
        return not segments_hit_boxes(segs, boxes).any()

    # ---------------------------------------------------------------- primitives
    def polyline(self, pts, lw=THIN, style="-", closed=False, color="black"):
        p = np.asarray(pts, dtype=float)
        if closed:
            p = np.vstack([p, p[:1]])
        self.ax.plot(p[:, 0], p[:, 1], style, lw=lw, color=color, solid_joinstyle="round")
        self._add_segments(p)

    def _make_text(self, x, y, s, size, ha, va, **kw):
        t = self.ax.text(x, y, s, fontsize=size, ha=ha, va=va, family="DejaVu Sans", **kw)
        bb = t.get_window_extent(self._renderer)
        (a, b), (c, d) = self.ax.transData.inverted().transform([[bb.x0, bb.y0], [bb.x1, bb.y1]])
        return t, (float(a), float(b), float(c), float(d))

    def text(self, x, y, s, size=DIM_FONT, ha="center", va="center", role: str = "", **kw):
        """Write text at a fixed place (title block, notes); returns its box. ``role``
        names the texts exempt from the least text size (the title block's cells)."""
        _, box = self._make_text(x, y, s, size, ha, va, **kw)
        self.texts.append(s)
        self.sizes.append((size, role))
        self.boxes.append(box)
        return box

    def text_size(self, s, size=DIM_FONT, **kw) -> tuple[float, float]:
        """Width and height of a text (mm), measured by the renderer."""
        t, box = self._make_text(0.0, 0.0, s, size, "left", "bottom", **kw)
        t.remove()
        return box[2] - box[0], box[3] - box[1]

    def place_text(self, candidates, s, size=DIM_FONT, ha="left", va="bottom", **kw):
        """Write text at the first candidate (x, y) where it is free; returns its box."""
        first = None
        for x, y in candidates:
            t, box = self._make_text(x, y, s, size, ha, va, **kw)
            if self.is_free(box):
                self.texts.append(s)
                self.sizes.append((size, ""))
                self.boxes.append(box)
                return box
            t.remove()
            first = first or (x, y)
        self.conflicts.append(s)
        return self.text(*first, s, size=size, ha=ha, va=va, **kw)

    def rect(self, x, y, w, h, lw=THIN):
        self.polyline([(x, y), (x + w, y), (x + w, y + h), (x, y + h)], lw=lw, closed=True)

    def arrow(self, tail, head):
        """A thin line from ``tail`` with a filled arrow head at ``head``."""
        tail, head = np.asarray(tail, float), np.asarray(head, float)
        u = head - tail
        n = np.linalg.norm(u)
        u = u / n if n > 0 else np.array([1.0, 0.0])
        w = np.array([-u[1], u[0]])
        base = head - ARROW_MM * u
        tri = np.array([head, base + 0.35 * w, base - 0.35 * w])
        self.ax.fill(tri[:, 0], tri[:, 1], color="black", lw=0)
        self.polyline([tail, head])
        self._add_segments(np.vstack([tri, tri[:1]]))

    def centre_mark(self, c, size):
        c = np.asarray(c)
        for d in ((1, 0), (0, 1)):
            d = np.asarray(d) * size
            self.polyline([c - d, c + d], style="-.")

    def circle(self, c, r, lw=THIN, style="-."):
        a = np.linspace(0, 2 * math.pi, 361)
        self.polyline(np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)]), lw=lw,
                      style=style)

    # ---------------------------------------------------------------- dimensions
    def callout(self, target, label, direction, dim: Dimension | None = None,
                reach=(8.0, 13.0, 19.0, 26.0, 34.0, 44.0), turn=(0, 20, -20, 40, -40, 60, -60),
                frames=(), boxed: bool = False):
        """Leader from a point of the part to a label: arrow, knee, shoulder under the text.

        Candidate knees lie ``reach`` mm from the target along ``direction`` (sheet,
        unit vector) turned by ``turn`` degrees; the first whose text box is free and
        whose leader crosses no text is taken. The text runs away from the part.
        ``frames``: tolerance frame rows (:meth:`frames_size`) under the shoulder;
        ``boxed``: the label framed as a theoretically exact dimension (ISO 1101).
        """
        target = np.asarray(target, float)
        base = math.atan2(direction[1], direction[0])
        w, h = self.text_size(label)
        fw, fh = self.frames_size(frames)
        w_all = max(w + (1.2 if boxed else 0.0), fw)
        fallback = None
        if boxed or frames:  # bigger labels: look further for a free place
            reach = (*reach, 55.0)
            turn = (*turn, 80, -80, 100, -100, 120, -120, 150, -150, 180)
        for r in reach:
            for dt in turn:
                a = base + math.radians(dt)
                knee = target + r * np.array([math.cos(a), math.sin(a)])
                right = math.cos(a) >= -1e-9
                end = knee + np.array([w_all + 2.0 if right else -(w_all + 2.0), 0.0])
                x_left = knee[0] + 1.0 if right else knee[0] - 1.0 - w_all
                box = (x_left, knee[1] + 0.6, x_left + w, knee[1] + 0.6 + h)
                fbox = (x_left, knee[1] - 0.8 - fh, x_left + fw, knee[1] - 0.8) if frames else None
                fallback = fallback or (knee, end, box, fbox)
                own = np.array([[*target, *knee], [*knee, *end]])
                clear_of_own = not segments_hit_box(own, grow(box, 0.4)).any()
                if boxed:  # the frame around the value sits on the shoulder line
                    clear_of_own = not segments_hit_box(own[:1], grow(box, TED_PAD_MM)).any()
                frames_ok = fbox is None or (
                    self.is_free(fbox) and not segments_hit_box(own[:1], grow(fbox, 0.4)).any())
                if (self.is_free(grow(box, TED_PAD_MM) if boxed else box)
                        and self.path_is_free([target, knee, end]) and clear_of_own and frames_ok):
                    return self._draw_callout(target, knee, end, box, label, dim, frames, fbox,
                                              boxed)
        self.conflicts.append(label)
        return self._draw_callout(target, *fallback[:3], label, dim, frames, fallback[3], boxed)

    def _draw_callout(self, target, knee, end, box, label, dim, frames=(), fbox=None,
                      boxed=False):
        self.arrow(knee, target)
        self.polyline([knee, end])
        self.text(box[0], box[1], label, ha="left", va="bottom")
        if boxed:
            x0, y0, x1, y1 = grow(box, TED_PAD_MM)
            self.rect(x0, y0, x1 - x0, y1 - y0)
        if frames:
            self.draw_frames(fbox[0], fbox[3], frames)
        if dim is not None:
            self.dims.append(dim)
        return box

    # ---------------------------------------------------------------- GD&T (ISO 1101)
    def frames_size(self, rows) -> tuple[float, float]:
        """Width and height (mm) of tolerance frame rows: each row a symbol key of
        :data:`GDT_SYMBOLS` and its cells' texts (tolerance, datums)."""
        if not rows:
            return 0.0, 0.0
        width = max(FRAME_ROW_MM + sum(self.text_size(c)[0] + 2.0 for c in row[1:])
                    for row in rows)
        return width, FRAME_ROW_MM * len(rows)

    def draw_frames(self, x: float, y_top: float, rows) -> None:
        """Tolerance frames, top left at (x, y_top): a symbol cell, then one cell per text
        (two rows: a composite frame, its lower row the pattern's own tolerance). Their
        outline is kept free like a text box."""
        w, h = self.frames_size(rows)
        self.frames.extend(tuple(row) for row in rows)
        self.boxes.append((x, y_top - h, x + w, y_top))
        y = y_top
        for row in rows:
            cx = x
            self.rect(cx, y - FRAME_ROW_MM, FRAME_ROW_MM, FRAME_ROW_MM)
            self.gdt_symbol(row[0], (cx + 0.5 * FRAME_ROW_MM, y - 0.5 * FRAME_ROW_MM),
                            0.36 * FRAME_ROW_MM)
            cx += FRAME_ROW_MM
            for cell in row[1:]:
                w = self.text_size(cell)[0] + 2.0
                self.rect(cx, y - FRAME_ROW_MM, w, FRAME_ROW_MM)
                self.text(cx + 1.0, y - 0.5 * FRAME_ROW_MM, cell, ha="left")
                cx += w
            y -= FRAME_ROW_MM

    def gdt_symbol(self, key: str, c, r: float) -> None:
        """Draw a geometric characteristic symbol of radius ``r`` about ``c`` (lines, so it
        needs no font glyph): position, profile (of a surface), coaxiality, flatness."""
        c = np.asarray(c, float)
        a = np.linspace(0.0, 2.0 * math.pi, 49)
        ring = np.column_stack([np.cos(a), np.sin(a)])
        if key == "position":
            self.polyline(c + 0.75 * r * ring)
            self.polyline([c - (r, 0), c + (r, 0)])
            self.polyline([c - (0, r), c + (0, r)])
        elif key == "profile":
            half = np.column_stack([np.cos(a[:25]), np.sin(a[:25])])
            self.polyline(c + r * half - (0, 0.4 * r), closed=True)
        elif key == "coaxiality":
            self.polyline(c + r * ring)
            self.polyline(c + 0.5 * r * ring)
        elif key == "flatness":
            self.polyline(c + r * np.array([[-1.0, -0.4], [0.5, -0.4], [1.0, 0.4], [-0.5, 0.4]]),
                          closed=True)
        else:
            raise ValueError(f"GD&T symbol '{key}': not one of {GDT_SYMBOLS}")

    def datum_feature(self, target, direction, letter: str,
                      reach=(6.0, 9.0, 13.0, 18.0), turn=(0, 25, -25, 50, -50, 80, -80)) -> None:
        """Datum feature symbol (ISO 5459): a filled triangle on the feature at ``target``,
        a leader along ``direction`` (turned as needed) to a square with the letter."""
        target = np.asarray(target, float)
        base = math.atan2(direction[1], direction[0])
        side = FRAME_ROW_MM
        first = None
        for r in reach:
            for dt in turn:
                a = base + math.radians(dt)
                u = np.array([math.cos(a), math.sin(a)])
                centre = target + (r + 0.5 * side) * u
                box = (centre[0] - 0.5 * side, centre[1] - 0.5 * side,
                       centre[0] + 0.5 * side, centre[1] + 0.5 * side)
                first = first or (u, centre, box)
                if self.is_free(box) and self.path_is_free([target, target + r * u]):
                    return self._draw_datum(target, u, centre, box, letter)
        self.conflicts.append(f"datum {letter}")
        self._draw_datum(target, *first, letter)

    def _draw_datum(self, target, u, centre, box, letter) -> None:
        w = np.array([-u[1], u[0]])
        tri = np.array([target + 0.9 * w, target - 0.9 * w, target + 1.4 * u])
        self.ax.fill(tri[:, 0], tri[:, 1], color="black", lw=0)
        self._add_segments(np.vstack([tri, tri[:1]]))
        edge = centre - 0.5 * FRAME_ROW_MM * u / max(abs(u[0]), abs(u[1]))
        self.polyline([target + 1.4 * u, edge])
        self.rect(box[0], box[1], box[2] - box[0], box[3] - box[1])
        self.text(centre[0], centre[1], letter)

    def dim_linear(self, p1, p2, side: float, label: str, dim: Dimension | None = None,
                   offsets=(7.0, 12.0, 17.0, 23.0, 30.0)):
        """Horizontal or vertical dimension between sheet points p1 and p2.

        ``side`` is the direction the dimension line moves away from the points:
        +1 above / right, -1 below / left (for a vertical dimension, the x of the
        points decides "right" as +1). Arrows turn outside when the span is
        shorter than two arrow heads; the text is horizontal, beside a vertical
        dimension line and above (or beside, when it does not fit) a horizontal one.
        """
        p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
        vertical = abs(p2[0] - p1[0]) < abs(p2[1] - p1[1])
        ax = 0 if vertical else 1  # the coordinate the offset moves along
        span = abs(p2[1 - ax] - p1[1 - ax])
        w, h = self.text_size(label)
        outside = span < 2 * ARROW_MM + 1.0
        fallback = None
        for off in offsets:
            ref = (max(p1[ax], p2[ax]) if side > 0 else min(p1[ax], p2[ax])) + side * off
            a, b = p1.copy(), p2.copy()
            a[ax] = b[ax] = ref
            lo, hi = (a, b) if a[1 - ax] <= b[1 - ax] else (b, a)
            mid = 0.5 * (a + b)
            if vertical:  # beside the line, beyond the 1.5 mm overshoot of the extension lines
                tx = ref + 1.5 + DIM_TEXT_GAP_MM if side > 0 else ref - 1.5 - DIM_TEXT_GAP_MM - w
                cands = [(tx, mid[1] - 0.5 * h)]
                if outside:
                    cands += [(tx, hi[1] + ARROW_MM), (tx, lo[1] - ARROW_MM - h)]
            else:
                ty = ref + DIM_TEXT_GAP_MM if side > 0 else ref - DIM_TEXT_GAP_MM - h
                cands = [(mid[0] - 0.5 * w, ty)] if w + 2 <= span - 2 * ARROW_MM else []
                cands += [(hi[0] + ARROW_MM + 3.0, ref - 0.5 * h), (lo[0] - ARROW_MM - 3.0 - w,
                                                                     ref - 0.5 * h)]
            ext = [(p1, a + side * 1.5 * _unit(ax)), (p2, b + side * 1.5 * _unit(ax))]
            own = np.array([[*p, *q] for p, q in ext] + [[*lo, *hi]])
            if outside:
                u = (hi - lo) / max(np.linalg.norm(hi - lo), 1e-9)
                own = np.vstack([own, [[*(lo - (ARROW_MM + 3.0) * u), *lo],
                                       [*(hi + (ARROW_MM + 3.0) * u), *hi]]])
            for x, y in cands:
                box = (x, y, x + w, y + h)
                fallback = fallback or (a, b, lo, hi, ext, box)
                lines_ok = all(self.path_is_free(e) for e in ext) and self.path_is_free([lo, hi])
                clear_of_own = not segments_hit_box(own, grow(box, TEXT_GAP_MM)).any()
                if self.is_free(box) and lines_ok and clear_of_own:
                    return self._draw_linear(lo, hi, ext, box, label, outside, dim)
        self.conflicts.append(label)
        a, b, lo, hi, ext, box = fallback
        return self._draw_linear(lo, hi, ext, box, label, outside, dim)

    def _draw_linear(self, lo, hi, ext, box, label, outside, dim):
        for e in ext:
            self.polyline(e)
        if outside:
            u = (hi - lo) / max(np.linalg.norm(hi - lo), 1e-9)
            self.arrow(lo - (ARROW_MM + 3.0) * u, lo)
            self.arrow(hi + (ARROW_MM + 3.0) * u, hi)
            self.polyline([lo, hi])
        else:
            mid = 0.5 * (lo + hi)
            self.arrow(mid, lo)
            self.arrow(mid, hi)
        self.text(box[0], box[1], label, ha="left", va="bottom")
        if dim is not None:
            self.dims.append(dim)
        return box

    def table(self, x: float, y_top: float, rows: list[tuple[str, ...]], widths: list[float],
              row_h: float = 5.6, size: float = TEXT_FONT) -> float:
        """A ruled table, top left at (x, y_top); returns its bottom (sheet mm)."""
        y = y_top
        for r, row in enumerate(rows):
            cx = x
            for text, wcol in zip(row, widths):
                self.rect(cx, y - row_h, wcol, row_h)
                self.text(cx + 1.0, y - 0.5 * row_h, text, size=size, ha="left",
                          weight="bold" if r == 0 else "normal")
                cx += wcol
            y -= row_h
        return y

    # ---------------------------------------------------------------- output
    def save(self, *paths):
        """Write the sheet (SVG, PDF or PNG by suffix) without the clock time: no creation
        date in the PDF or SVG meta data and fixed SVG ids, so a drawing is a function of
        its content (the date in the title block included) and two builds give the same
        bytes. A sheet of several A3 pages stacked downwards (page 1 at the top, so the SVG
        and PNG read in page order) is one PDF page per A3 page, page 1 first."""
        import matplotlib
        from matplotlib.backends.backend_pdf import PdfPages

        no_clock = {".pdf": {"CreationDate": None}, ".svg": {"Date": None}}
        pages = max(1, round(self.height / A3[1]))
        core = self.core_font_suffices()
        with matplotlib.rc_context({"svg.fonttype": "none", "pdf.fonttype": 42,
                                    "pdf.compression": 6, "svg.hashsalt": "springcad"}):
            for p in paths:
                suffix = str(p)[-4:].lower()
                if suffix != ".pdf":
                    self.fig.savefig(p, dpi=150 if suffix == ".png" else 72,
                                     metadata=no_clock.get(suffix))
                    continue
                with _pdf_font(self.fig, core), PdfPages(p, metadata=no_clock[".pdf"]) as pdf:
                    self.fig.set_size_inches(self.width / 25.4, A3[1] / 25.4)
                    for k in range(pages):
                        top = self.bottom + self.height - k * A3[1]
                        self.ax.set_ylim(top - A3[1], top)
                        pdf.savefig(self.fig, dpi=72)
                    self.fig.set_size_inches(self.width / 25.4, self.height / 25.4)
                    self.ax.set_ylim(self.bottom, self.bottom + self.height)

    def core_font_suffices(self) -> bool:
        """Whether every text of the sheet is in the PDF core font's character set
        (:data:`PDF_CORE_FONT`, WinAnsi: ASCII, Latin-1, and among others the
        diameter sign, plus-minus, degree, micro and multiplication signs)."""
        try:
            "".join(self.texts).encode("cp1252")
        except UnicodeEncodeError:
            return False
        return True


@functools.lru_cache(maxsize=None)
def _measuring_renderer(dpi: float):
    """The Agg renderer every sheet of this process measures its texts with (at ``dpi``,
    the figures' dots per inch).

    A text's size is a function of the string, its font properties and the dpi only (Agg:
    FreeType's advance widths), and matplotlib keeps the sizes it measured per renderer: one
    renderer for every sheet lets a drawing's probe sheet, its real sheet and the next
    drawings share them (the title block's labels, the notes), where a renderer per sheet
    measured each again; and a sheet no longer allocates an A3 pixel buffer to measure."""
    from matplotlib.backends.backend_agg import RendererAgg

    return RendererAgg(1, 1, dpi)


@contextlib.contextmanager
def _pdf_font(fig, core: bool):
    """Write a PDF's text in :data:`PDF_CORE_FONT`, a font every PDF reader has, with no font
    file embedded (``core``), or else in DejaVu Sans embedded as a TrueType subset.

    Subsetting and embedding DejaVu Sans took 0.3 s per PDF (fontTools), most of a
    drawing's writing time; the core font costs nothing. The layout stays the one measured
    in DejaVu Sans: Helvetica is narrower in every glyph used, so each text keeps inside
    the box the sheet placed it in; its capital height (0.718 em, 2.53 mm at
    :data:`TEXT_FONT`) is still at least :data:`MIN_CAP_MM`. SVG and PNG keep DejaVu Sans.
    """
    import matplotlib

    if not core:
        yield
        return
    texts = fig.findobj(matplotlib.text.Text)
    kept = [(t.get_fontfamily(), t.get_fontweight()) for t in texts]
    for t, (_, weight) in zip(texts, kept):
        t.set_fontfamily(PDF_CORE_FONT)
        if weight in ("normal", "regular", 400):  # the core font's regular weight is "Medium"
            t.set_fontweight("medium")
    try:
        with matplotlib.rc_context({"pdf.use14corefonts": True}):
            yield
    finally:
        for t, (family, weight) in zip(texts, kept):
            t.set_fontfamily(family)
            t.set_fontweight(weight)


def _unit(axis: int) -> np.ndarray:
    return np.array([1.0, 0.0]) if axis == 0 else np.array([0.0, 1.0])
