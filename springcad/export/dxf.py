"""Wire-EDM cutting profiles as DXF, and reading them back.

Every loop of the cutting profile goes to layer ``CUT`` as true entities:
LINE, ARC, CIRCLE, and SPLINE for the design's interpolating splines. A
SPLINE is written by its B-spline control points and knots (the exact cubic
the design evaluates, with the same chord-length parameters and end
tangents), so no reader has to re-fit it. Units are set to mm ($INSUNITS = 4,
$MEASUREMENT = 1). Part number and units go to a non-cutting ``INFO`` layer.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from springcad.design.curves import Arc, Circle, Line, Profile, Spline

CUT_LAYER = "CUT"
INFO_LAYER = "INFO"
#: chord deviation when flattening curves on read-back (mm)
READ_SAGITTA_MM = 0.0005
#: loop ends closer than this join (mm)
JOIN_TOL_MM = 1e-5


def spline_bspline(seg: Spline):
    """(knots, control points (n, 2)) of the cubic B-spline equal to the design spline."""
    from scipy.interpolate import make_interp_spline

    u = seg.parameters()
    p = np.asarray(seg.points, dtype=float)
    # clamped end derivatives = the unit end tangents (chord-length parameter), as the design
    bc = ([(1, np.asarray(seg.start_tangent, dtype=float))],
          [(1, np.asarray(seg.end_tangent, dtype=float))])
    b = make_interp_spline(u, p, k=3, bc_type=bc)
    return np.asarray(b.t), np.asarray(b.c)


def _add_segment(msp, seg, attribs):
    if isinstance(seg, Line):
        msp.add_line(seg.start, seg.end, dxfattribs=attribs)
    elif isinstance(seg, Circle):
        msp.add_circle(seg.center, seg.radius, dxfattribs=attribs)
    elif isinstance(seg, Arc):
        a0, a1 = math.degrees(seg.start_angle), math.degrees(seg.end_angle)
        if a1 < a0:  # DXF arcs run counter-clockwise
            a0, a1 = a1, a0
        msp.add_arc(seg.center, seg.radius, a0, a1, dxfattribs=attribs)
    elif isinstance(seg, Spline):
        knots, ctrl = spline_bspline(seg)
        msp.add_open_spline([(x, y, 0.0) for x, y in ctrl], degree=3, knots=list(knots),
                            dxfattribs=attribs)
    else:
        raise TypeError(f"unknown segment {type(seg).__name__}")


def write_dxf(profile: Profile, path: Path, part_number: str, thickness_mm: float) -> Path:
    """Write a cutting profile (mm) as DXF R2010 with every loop on layer CUT."""
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new("R2010", setup=False)
    doc.units = units.MM
    doc.header["$MEASUREMENT"] = 1
    doc.header["$LUNITS"] = 2
    doc.layers.add(CUT_LAYER, color=1)
    doc.layers.add(INFO_LAYER, color=7)
    msp = doc.modelspace()
    for loop in profile.loops:
        for seg in loop.segments:
            _add_segment(msp, seg, {"layer": CUT_LAYER})
    r = max(abs(v) for v in profile.outer.sample(1.0).ravel())
    msp.add_text(f"{part_number}  t = {thickness_mm:g} mm  units: mm  layer {CUT_LAYER}: cut",
                 height=max(0.5, 0.04 * r), dxfattribs={"layer": INFO_LAYER}
                 ).set_placement((-r, -1.15 * r))
    doc.saveas(path)
    return Path(path)


def _entity_points(e) -> tuple[np.ndarray, bool]:
    """Flattened points of one entity and whether it is closed on its own."""
    kind = e.dxftype()
    if kind == "LINE":
        return np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)]), False
    if kind == "CIRCLE":
        pts = np.array([(v.x, v.y) for v in e.flattening(READ_SAGITTA_MM)])
        return pts[:-1] if np.allclose(pts[0], pts[-1]) else pts, True
    if kind in ("ARC", "SPLINE"):
        return np.array([(v.x, v.y) for v in e.flattening(READ_SAGITTA_MM)]), False
    raise ValueError(f"unexpected {kind} on layer {CUT_LAYER}")


def read_dxf_loops(path: Path) -> tuple[list[np.ndarray], object]:
    """Read the CUT layer back as closed loops of points (mm).

    Returns:
        (loops, auditor): each loop (n, 2) without the closing point; the ezdxf
        auditor of the file.

    Raises:
        ValueError: the pieces do not chain into closed loops.
    """
    import ezdxf

    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    loops, open_pieces = [], []
    for e in doc.modelspace().query(f'*[layer=="{CUT_LAYER}"]'):
        pts, closed = _entity_points(e)
        (loops if closed else open_pieces).append(pts)
    while open_pieces:
        chain = [open_pieces.pop()]
        while np.linalg.norm(chain[-1][-1] - chain[0][0]) > JOIN_TOL_MM:
            end = chain[-1][-1]
            for i, piece in enumerate(open_pieces):
                if np.linalg.norm(piece[0] - end) <= JOIN_TOL_MM:
                    chain.append(open_pieces.pop(i))
                    break
                if np.linalg.norm(piece[-1] - end) <= JOIN_TOL_MM:
                    chain.append(open_pieces.pop(i)[::-1])
                    break
            else:
                raise ValueError(f"{path}: contour open at ({end[0]:.4f}, {end[1]:.4f})")
        loops.append(np.vstack([c[:-1] for c in chain]))
    return loops, auditor


def loops_area_mm2(loops) -> float:
    """Area enclosed by the largest loop minus the others (mm^2)."""
    def shoelace(p):
        x, y = p[:, 0], p[:, 1]
        return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))

    areas = sorted((shoelace(p) for p in loops), reverse=True)
    return areas[0] - sum(areas[1:])
