"""A drawing sheet in millimetres on a matplotlib figure, with dimension primitives.

Everything is placed in sheet millimetres (origin bottom left); a
:class:`View` maps model millimetres to the sheet at a drawing scale. Text
stays text in SVG and PDF, so the drawing can be searched and checked.
Units: mm (model and sheet), points only for line widths and font sizes.
"""

from __future__ import annotations

import math

import numpy as np

#: ISO A3 landscape (mm)
A3 = (420.0, 297.0)
#: standard drawing scales, largest first
SCALES = (20.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.2)
THICK, THIN = 0.7, 0.25  # line widths (pt)
DIM_FONT, NOTE_FONT, LABEL_FONT = 8.0, 7.0, 5.0  # font sizes (pt)


def fmt(value: float) -> str:
    """A dimension value as written on the drawing: up to 3 decimals, no trailing zeros."""
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def scale_text(scale: float) -> str:
    return f"{fmt(scale)}:1" if scale >= 1 else f"1:{fmt(1 / scale)}"


def fit_scale(extent_mm: float, box_mm: float) -> float:
    """Largest standard scale at which ``extent_mm`` fits in ``box_mm``."""
    for s in SCALES:
        if extent_mm * s <= box_mm:
            return s
    return SCALES[-1]


class View:
    """Model (x, y) mm to sheet mm: ``origin + scale * (x, y)``."""

    def __init__(self, origin, scale: float):
        self.origin = np.asarray(origin, dtype=float)
        self.scale = scale

    def __call__(self, pts) -> np.ndarray:
        return self.origin + self.scale * np.asarray(pts, dtype=float)


class Sheet:
    """A matplotlib figure whose single axes spans the sheet in millimetres."""

    def __init__(self, size_mm=A3):
        from matplotlib.figure import Figure

        self.width, self.height = size_mm
        self.fig = Figure(figsize=(self.width / 25.4, self.height / 25.4))
        self.ax = self.fig.add_axes((0, 0, 1, 1))
        self.ax.set_xlim(0, self.width)
        self.ax.set_ylim(0, self.height)
        self.ax.set_aspect("equal")
        self.ax.axis("off")
        self.texts: list[str] = []

    # ---------------------------------------------------------------- primitives
    def polyline(self, pts, lw=THICK, style="-", closed=False, color="black"):
        p = np.asarray(pts, dtype=float)
        if closed:
            p = np.vstack([p, p[:1]])
        self.ax.plot(p[:, 0], p[:, 1], style, lw=lw, color=color, solid_joinstyle="round")

    def text(self, x, y, s, size=DIM_FONT, ha="center", va="center", rotation=0.0, **kw):
        self.texts.append(s)
        self.ax.text(x, y, s, fontsize=size, ha=ha, va=va, rotation=rotation,
                     rotation_mode="anchor", family="DejaVu Sans", **kw)

    def rect(self, x, y, w, h, lw=THIN):
        self.polyline([(x, y), (x + w, y), (x + w, y + h), (x, y + h)], lw=lw, closed=True)

    def arrow(self, tail, head):
        self.ax.annotate("", xy=tuple(head), xytext=tuple(tail),
                         arrowprops=dict(arrowstyle="-|>", lw=THIN, color="black",
                                         shrinkA=0, shrinkB=0, mutation_scale=6))

    def centre_mark(self, c, size):
        c = np.asarray(c)
        for d in ((1, 0), (0, 1)):
            d = np.asarray(d) * size
            self.polyline([c - d, c + d], lw=THIN, style="-.")

    def circle(self, c, r, lw=THIN, style="-."):
        a = np.linspace(0, 2 * math.pi, 361)
        self.polyline(np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)]), lw=lw,
                      style=style)

    # ---------------------------------------------------------------- dimensions
    def dim_linear(self, p1, p2, offset, label, text_side=1.0):
        """Dimension between two sheet points, drawn ``offset`` mm to the left of p1->p2."""
        p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
        d = (p2 - p1) / np.linalg.norm(p2 - p1)
        n = np.array([-d[1], d[0]])
        a, b = p1 + offset * n, p2 + offset * n
        ext = 1.5 * np.sign(offset) * n
        self.polyline([p1, a + ext], lw=THIN)
        self.polyline([p2, b + ext], lw=THIN)
        mid = 0.5 * (a + b)
        self.arrow(mid, a)
        self.arrow(mid, b)
        angle = math.degrees(math.atan2(d[1], d[0]))
        if angle > 90 or angle <= -90:
            angle -= 180 * np.sign(angle)
        t = mid + 1.8 * text_side * np.array([-math.sin(math.radians(angle)),
                                                math.cos(math.radians(angle))])
        self.text(*t, label, rotation=angle)

    def dim_diameter(self, c, r, angle_deg, label):
        """Diameter dimension through the centre at an angle, text outside the circle."""
        c = np.asarray(c, float)
        u = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
        self.arrow(c, c + r * u)
        self.arrow(c, c - r * u)
        knee = c + (r + 6.0) * u
        self.polyline([c + r * u, knee], lw=THIN)
        end = knee + np.array([8.0 if u[0] >= 0 else -8.0, 0.0])
        self.polyline([knee, end], lw=THIN)
        self.text(end[0], end[1] + 0.5, label, ha="left" if u[0] >= 0 else "right", va="bottom")

    def dim_radius(self, c, r, angle_deg, label, inside=True):
        """Radius dimension: arrow from the centre (or from outside) to the arc."""
        c = np.asarray(c, float)
        u = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
        tip = c + r * u
        if inside:
            self.arrow(c, tip)
            start = c
        else:
            start = tip + 8.0 * u
            self.arrow(start, tip)
        knee = tip + 4.0 * u if inside else start
        self.polyline([start if inside else tip, knee], lw=THIN)
        end = knee + np.array([7.0 if u[0] >= 0 else -7.0, 0.0])
        self.polyline([knee, end], lw=THIN)
        self.text(end[0], end[1] + 0.5, label, ha="left" if u[0] >= 0 else "right", va="bottom")

    def leader(self, target, text_at, label, ha="left"):
        """Arrow from a text to a point of the part."""
        target, text_at = np.asarray(target, float), np.asarray(text_at, float)
        self.arrow(text_at, target)
        self.text(*(text_at + np.array([1.0 if ha == "left" else -1.0, 0.5])), label,
                  ha=ha, va="bottom")

    # ---------------------------------------------------------------- output
    def save(self, *paths):
        import matplotlib

        with matplotlib.rc_context({"svg.fonttype": "none", "pdf.fonttype": 42,
                                    "pdf.compression": 6}):
            for p in paths:
                self.fig.savefig(p, dpi=150 if str(p).endswith(".png") else 72)
