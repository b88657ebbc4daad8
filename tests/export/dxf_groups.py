"""A tiny DXF reader that shares no code with ezdxf: group-code pairs to entities.

Enough of the DXF format to read what a CAM system reads from springcad's files:
the HEADER variables and the LINE, ARC, CIRCLE, TEXT and LWPOLYLINE entities of
the ENTITIES section. Written from the DXF reference (group code on one line, its
value on the next; 0 starts an entity, 8 is the layer, 10/20 the first point,
11/21 the second, 40 a radius or text height, 50/51 arc angles in degrees
counter-clockwise, 42 an LWPOLYLINE vertex bulge, 70 bit 1 a closed polyline,
1 a text string). Units: mm, degrees in the file, rad out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Entity:
    kind: str
    layer: str = ""
    groups: list = field(default_factory=list)  # (code, value) in file order

    def first(self, code: int, default=None):
        return next((v for c, v in self.groups if c == code), default)

    def num(self, code: int) -> float:
        return float(self.first(code))


def group_pairs(text: str):
    lines = text.splitlines()
    for k in range(0, len(lines) - 1, 2):
        yield int(lines[k].strip()), lines[k + 1].strip()


def read(text: str) -> tuple[dict, list[Entity]]:
    """(header {name: [values]}, entities) of a DXF file's text."""
    header, entities = {}, []
    section, var, ent = None, None, None
    for code, value in group_pairs(text):
        if code == 0 and value == "SECTION":
            section, ent = "?", None
            continue
        if code == 2 and section == "?":
            section = value
            continue
        if code == 0 and value == "ENDSEC":
            section, ent = None, None
            continue
        if section == "HEADER":
            if code == 9:
                var = value
                header[var] = []
            elif var:
                header[var].append(value)
        elif section == "ENTITIES":
            if code == 0:
                ent = Entity(value)
                entities.append(ent)
            elif ent is not None:
                if code == 8:
                    ent.layer = value
                ent.groups.append((code, value))
    return header, entities


def arc_points(cx, cy, r, a0_rad, sweep_rad, step_mm: float) -> np.ndarray:
    n = max(2, int(math.ceil(abs(sweep_rad) * r / step_mm)) + 1)
    a = a0_rad + np.linspace(0.0, sweep_rad, n)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def bulge_points(a, b, bulge: float, step_mm: float) -> np.ndarray:
    """Points of one LWPOLYLINE segment: the bulge applies to the segment that starts at
    the vertex carrying it (DXF reference, group 42)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if bulge == 0.0:
        return np.vstack([a, b])
    sweep = 4.0 * math.atan(bulge)
    chord = b - a
    length = float(np.hypot(*chord))
    r = 0.5 * length / abs(math.sin(0.5 * sweep))
    left = np.array([-chord[1], chord[0]]) / length
    c = 0.5 * (a + b) + left * (0.5 * length / math.tan(0.5 * sweep))
    return arc_points(c[0], c[1], r, math.atan2(a[1] - c[1], a[0] - c[0]), sweep, step_mm)


def entity_points(e: Entity, step_mm: float) -> np.ndarray:
    """Points along a LINE, ARC, CIRCLE or LWPOLYLINE (mm), no further apart than step."""
    if e.kind == "LINE":
        return np.array([[e.num(10), e.num(20)], [e.num(11), e.num(21)]])
    if e.kind == "CIRCLE":
        return arc_points(e.num(10), e.num(20), e.num(40), 0.0, 2 * math.pi, step_mm)
    if e.kind == "ARC":
        a0, a1 = math.radians(e.num(50)), math.radians(e.num(51))
        sweep = (a1 - a0) % (2 * math.pi) or 2 * math.pi
        return arc_points(e.num(10), e.num(20), e.num(40), a0, sweep, step_mm)
    if e.kind == "LWPOLYLINE":
        verts, bulges = [], []
        for c, v in e.groups:
            if c == 10:
                verts.append([float(v), None])
                bulges.append(0.0)
            elif c == 20:
                verts[-1][1] = float(v)
            elif c == 42:
                bulges[-1] = float(v)
        closed = int(e.first(70, 0)) & 1
        n = len(verts)
        pieces = [bulge_points(verts[k], verts[(k + 1) % n], bulges[k], step_mm)
                  for k in range(n if closed else n - 1)]
        return np.vstack(pieces)
    raise ValueError(f"no points for {e.kind}")
