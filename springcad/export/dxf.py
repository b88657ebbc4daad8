"""Cutting profiles as DXF for CAM, and reading them back.

What a CAM system gets (the default, ``entities="lines-arcs"``):

* layer ``CUT``: every contour of the cutting profile as **LINE, ARC and CIRCLE
  entities** only, the entity set of DXF R12 that every CAM reads the same way;
  a hole is one CIRCLE (start-hole recognition finds it). Consecutive entities
  of a contour meet end to end (within 1e-9 mm). Lines, arcs and circles of the
  design are exact; the design's splines are replaced by biarcs
  (:mod:`springcad.export.biarc`) within :data:`CHORD_TOL_MM` of the design
  curve (measured at the writer, stated in the file). No SPLINE, no bulge.
* ``entities="polyline"``: every contour as **one closed LWPOLYLINE of lines and
  arcs** (bulges), one entity per contour, for CAM systems that prefer chained
  contours. (Some CAM programs apply a bulge to the wrong segment: an issue-26
  review saw dxf2gcode move the ring's balls by 0.43 mm; hence not the default.)
* ``version="R12"`` writes the same LINE/ARC/CIRCLE file as DXF R12 (AC1009) for
  the oldest readers; R12 has no ``$INSUNITS``, so the units are stated only in
  the INFO text. Default: DXF R2010 with ``$INSUNITS`` = 4 (mm) and
  ``$MEASUREMENT`` = 1.
* layer ``INFO``: part number, thickness, units and the tolerance as TEXT of
  :data:`INFO_TEXT_HEIGHT_MM` capital height, placed below the part, clear of
  every cut contour by one text height (switch the layer off, or leave it out,
  in CAM).
* ``$EXTMIN``/``$EXTMAX``: the true extents of everything in the file (the cut
  contours and the INFO text), and the view zoomed to them.
* no clock time and no random GUID in the file: one profile, one byte sequence.

Units: mm.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from springcad.design.curves import Profile
from springcad.export.biarc import BulgeLoop, arc_centre, loop_bulges
from springcad.options import DXF_VERSIONS

CUT_LAYER = "CUT"
INFO_LAYER = "INFO"
#: largest distance of the written contour from the design curve (mm): 1 um in all,
#: half of it for the biarcs so the CAD kernel's own spline fit (well under 0.5 um from
#: the design curve) stays inside the budget
CHORD_TOL_MM = 0.001
BIARC_TOL_MM = 0.5 * CHORD_TOL_MM
#: capital height of the INFO text (mm): ISO 3098's smallest usual height for notes
INFO_TEXT_HEIGHT_MM = 2.5
#: contour entity styles (see the module docstring); the first is the default
ENTITY_STYLES = ("lines-arcs", "polyline")
#: two entity ends closer than this (mm) are one point when contours are chained on reading
CHAIN_TOL_MM = 1e-6


@dataclass(frozen=True)
class DxfReport:
    """What the writer did: loops written, biarcs, the largest measured deviation (mm),
    the entity style and the number of CUT entities."""

    path: Path
    n_loops: int
    n_biarcs: int
    max_deviation_mm: float
    entities: str = ENTITY_STYLES[0]
    n_entities: int = 0


def info_lines(part_number: str, thickness_mm: float, entities: str,
               profile_length_mm: float | None = None) -> list[str]:
    """The INFO text: part number, thickness (and, when the outer contour is cut over only
    part of it, that length: an end camshaft's teeth beside its turned hub) and units, what
    the CUT layer holds, how close it is to the design (not a part tolerance: those are on
    the drawing)."""
    what = "LINE ARC CIRCLE" if entities == "lines-arcs" else "LWPOLYLINE"
    t = f"t {thickness_mm:g} mm"
    if profile_length_mm is not None and abs(profile_length_mm - thickness_mm) > 1e-9:
        t += f", outer contour over {profile_length_mm:g} mm"
    return [part_number, t, "units mm", f"CUT: {what}",
            f"within {CHORD_TOL_MM:g} mm of design", "tolerances: see drawing"]


def _info_text(msp, lines: list[str], bbox) -> None:
    """Text lines below ``bbox`` (xmin, ymin, xmax, ymax), left-aligned with it, the top
    line one text height below the lowest cut point."""
    x0, y0 = bbox[0], bbox[1]
    h = INFO_TEXT_HEIGHT_MM
    for k, line in enumerate(lines):
        msp.add_text(line, height=h, dxfattribs={"layer": INFO_LAYER}).set_placement(
            (x0, y0 - 2.0 * h - 1.6 * h * k))


@contextlib.contextmanager
def _fixed_meta_data():
    """ezdxf's fixed meta data while a document is made and saved: no creation or update
    time, no random GUIDs and no time in ezdxf's own marker, so one profile always gives
    the same bytes (vendor.zip of two builds is byte-identical). The option is
    ezdxf-global: restored afterwards."""
    import ezdxf

    before = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = before


def _sort_classes(doc) -> None:
    """Register the document's CLASS entries now, in sorted order: ezdxf adds those of the
    entity types in use in the iteration order of a set of strings, which follows the
    process's string hash (``PYTHONHASHSEED``), so two processes wrote LAYOUT and
    ACDBPLACEHOLDER in either order. Saving adds no other class (it skips registered ones)."""
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = dict(sorted(doc.classes.classes.items()))


def _is_circle(loop: BulgeLoop) -> bool:
    """Two half-circle bulges (how :func:`loop_bulges` writes a Circle)."""
    v = loop.vertices
    return len(v) == 2 and np.allclose(v[:, 2], 1.0)


def _add_lines_arcs(msp, loop: BulgeLoop) -> int:
    """One loop as LINE/ARC entities (a circle as one CIRCLE); returns the entity count.

    ARC entities run counter-clockwise from the start to the end angle, so a clockwise
    bulge segment is written with its ends swapped.
    """
    attribs = {"layer": CUT_LAYER}
    if _is_circle(loop):
        a, b = loop.vertices[:, :2]
        msp.add_circle(tuple(0.5 * (a + b)), 0.5 * float(np.linalg.norm(b - a)),
                       dxfattribs=attribs)
        return 1
    for a, b, bulge in loop.segments():
        if not bulge:
            msp.add_line(tuple(a), tuple(b), dxfattribs=attribs)
            continue
        centre, r, sweep = arc_centre(a, b, bulge)
        ang_a = math.degrees(math.atan2(a[1] - centre[1], a[0] - centre[0]))
        ang_b = math.degrees(math.atan2(b[1] - centre[1], b[0] - centre[0]))
        start, end = (ang_a, ang_b) if sweep > 0 else (ang_b, ang_a)
        msp.add_arc(tuple(centre), r, start, end, dxfattribs=attribs)
    return len(loop.vertices)


def write_dxf(profile: Profile, path: Path, part_number: str, thickness_mm: float,
              entities: str = ENTITY_STYLES[0], version: str = DXF_VERSIONS[0],
              profile_length_mm: float | None = None) -> DxfReport:
    """Write a cutting profile (mm) as DXF.

    Args:
        profile_length_mm: length over which the outer contour is cut, when less than the
            thickness (INFO text; :func:`info_lines`).
        entities: ``"lines-arcs"`` (LINE/ARC/CIRCLE, default) or ``"polyline"`` (one
            closed LWPOLYLINE with bulges per loop).
        version: ``"R2010"`` (default) or ``"R12"`` (lines-arcs only).

    Raises:
        ValueError: an unknown style or version, or a spline that cannot be matched by
            arcs within the tolerance.
    """
    import ezdxf
    from ezdxf import bbox as ezbbox
    from ezdxf import units, zoom

    if entities not in ENTITY_STYLES:
        raise ValueError(f"DXF entities {entities!r}: allowed {', '.join(ENTITY_STYLES)}")
    if version not in DXF_VERSIONS:
        raise ValueError(f"DXF version {version!r}: allowed {', '.join(DXF_VERSIONS)}")
    if version == "R12" and entities != "lines-arcs":
        raise ValueError("DXF R12 has no LWPOLYLINE: use entities='lines-arcs' with R12")
    bulged = [loop_bulges(loop, BIARC_TOL_MM) for loop in profile.loops]
    pts = profile.outer.sample(0.05)
    bbox = (*pts.min(axis=0), *pts.max(axis=0))
    with _fixed_meta_data():
        doc = _new_doc(version)
        if version != "R12":
            doc.units = units.MM
            doc.header["$MEASUREMENT"] = 1
        doc.header["$LUNITS"] = 2
        doc.layers.add(CUT_LAYER, color=1)
        doc.layers.add(INFO_LAYER, color=7)
        msp = doc.modelspace()
        n_entities = 0
        for b in bulged:
            if entities == "polyline":
                msp.add_lwpolyline(b.vertices.tolist(), format="xyb", close=True,
                                   dxfattribs={"layer": CUT_LAYER})
                n_entities += 1
            else:
                n_entities += _add_lines_arcs(msp, b)
        _info_text(msp, info_lines(part_number, thickness_mm, entities, profile_length_mm),
                   bbox)
        hull = _hull_entities(msp)
        box = ezbbox.extents(hull)
        msp.dxf.extmin, msp.dxf.extmax = box.extmin, box.extmax  # -> $EXTMIN/$EXTMAX
        view = ezbbox.extents(hull, fast=True)  # what zoom.extents(msp) measures
        zoom.center(msp, view.center, view.size)
        if version != "R12":
            _sort_classes(doc)
        doc.saveas(path)
    return DxfReport(Path(path), len(bulged), sum(b.n_biarcs for b in bulged),
                     max(b.max_deviation_mm for b in bulged), entities, n_entities)


#: entities of each side of the drawing measured first (those reaching furthest out)
_SEED_PER_SIDE = 8


def _arc_bound(cx: float, cy: float, r: float, start_deg: float, end_deg: float) -> tuple:
    """(xmin, ymin, xmax, ymax) holding an ARC (counter-clockwise from ``start_deg``) as ezdxf
    measures it, exactly or by control points (mm): ezdxf draws it as cubic Bezier
    segments of at most 90 degrees, each within the hull of its control points, which lie
    on the arc's tangents at most r 4/3 tan(phi / 4) from the segment's ends (phi its
    sweep). So: the arc's own box (its ends and the quadrant points it passes) grown by
    that much for phi = min(sweep, 90 degrees), and by 1e-9 of its size for rounding."""
    a0 = math.radians(start_deg) % math.tau
    sweep = (math.radians(end_deg) - a0) % math.tau or math.tau
    xs, ys = [cx + r * math.cos(a0), cx + r * math.cos(a0 + sweep)], \
        [cy + r * math.sin(a0), cy + r * math.sin(a0 + sweep)]
    for k in range(4):
        if (k * 0.5 * math.pi - a0) % math.tau <= sweep:
            xs.append(cx + r * math.cos(k * 0.5 * math.pi))
            ys.append(cy + r * math.sin(k * 0.5 * math.pi))
    grow = (r * 4.0 / 3.0 * math.tan(min(sweep, 0.5 * math.pi) / 4.0)
            + 1e-9 * (r + abs(cx) + abs(cy)))
    return min(xs) - grow, min(ys) - grow, max(xs) + grow, max(ys) + grow


def _hull_entities(msp) -> list:
    """The entities of ``msp`` that can reach its extents: ezdxf's exact and control-point
    bounding boxes of these are those of every entity, at a fraction of the cost.

    ezdxf measures an ARC or CIRCLE through its Bezier path (0.5 s for the default ring's
    2000 entities, twice: the exact box for $EXTMIN/$EXTMAX, the control-point box for the
    view). Each LINE lies within its end points and each ARC or CIRCLE within
    :func:`_arc_bound`; the entities reaching furthest out on each side, and every other
    kind (the INFO text), are measured, and an entity whose bound lies inside both their
    boxes cannot extend either, so it is left out."""
    from ezdxf import bbox as ezbbox

    entities = list(msp)
    bounds, bounded, other = [], [], []
    for e in entities:
        kind = e.dxftype()
        if kind == "LINE" and e.dxf.start.z == 0 and e.dxf.end.z == 0:
            (x0, y0), (x1, y1) = e.dxf.start.vec2, e.dxf.end.vec2
            bounds.append((min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)))
        elif kind in ("ARC", "CIRCLE") and e.dxf.center.z == 0 and tuple(e.dxf.extrusion) == (
                0.0, 0.0, 1.0):
            (cx, cy), r = e.dxf.center.vec2, abs(e.dxf.radius)
            bounds.append(_arc_bound(cx, cy, r, e.dxf.start_angle, e.dxf.end_angle)
                          if kind == "ARC" else _arc_bound(cx, cy, r, 0.0, 360.0))
        else:
            other.append(e)
            continue
        bounded.append(e)
    if not bounded:
        return entities
    b = np.array(bounds)
    seed = set()
    for col, sign in ((0, 1), (1, 1), (2, -1), (3, -1)):
        seed.update(np.argsort(sign * b[:, col], kind="stable")[:_SEED_PER_SIDE].tolist())
    seeds = other + [bounded[i] for i in sorted(seed)]
    exact, view = ezbbox.extents(seeds), ezbbox.extents(seeds, fast=True)
    if not (exact.has_data and view.has_data):
        return entities
    lo = np.maximum([exact.extmin.x, exact.extmin.y], [view.extmin.x, view.extmin.y])
    hi = np.minimum([exact.extmax.x, exact.extmax.y], [view.extmax.x, view.extmax.y])
    if exact.extmin.z > 0 or exact.extmax.z < 0 or view.extmin.z > 0 or view.extmax.z < 0:
        return entities  # (a 2D drawing has z = 0 throughout)
    inside = (b[:, 0] >= lo[0]) & (b[:, 1] >= lo[1]) & (b[:, 2] <= hi[0]) & (b[:, 3] <= hi[1])
    return seeds + [e for i, e in enumerate(bounded) if not inside[i] and i not in seed]


def _new_doc(version: str):
    """A new ezdxf document; for R12 without ezdxf's warning that R12 has no $INSUNITS (it
    was printed on the console of ``springcad build --dxf-version R12`` for every DXF: the
    units are in the INFO text and the vendor README)."""
    import logging

    import ezdxf

    log = logging.getLogger("ezdxf")
    level = log.level
    if version == "R12":
        log.setLevel(logging.ERROR)
    try:
        return ezdxf.new(version, setup=False)
    finally:
        log.setLevel(level)


def _entity_segments(e) -> list[tuple]:
    """``(start, end, bulge)`` of one LINE or ARC entity (mm)."""
    if e.dxftype() == "LINE":
        return [((e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y), 0.0)]
    c, r = (e.dxf.center.x, e.dxf.center.y), e.dxf.radius
    a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
    sweep = (a1 - a0) % (2 * math.pi) or 2 * math.pi
    return [((c[0] + r * math.cos(a0), c[1] + r * math.sin(a0)),
             (c[0] + r * math.cos(a1), c[1] + r * math.sin(a1)), math.tan(sweep / 4.0))]


def chain_segments(segments: list[tuple], tol_mm: float = CHAIN_TOL_MM) -> list[BulgeLoop]:
    """Closed loops from loose ``(start, end, bulge)`` segments (either direction).

    Raises:
        ValueError: a segment end meets no other end (an open contour) or three ends
            meet in one point (a branch).
    """
    from scipy.spatial import cKDTree

    if not segments:
        return []
    ends = np.array([p for a, b, _ in segments for p in (a, b)], dtype=float)  # 2k, 2k+1
    pairs = cKDTree(ends).query_pairs(tol_mm, output_type="ndarray")
    partner = np.full(len(ends), -1)
    for i, j in pairs:
        if i // 2 == j // 2:
            continue  # the two ends of one segment (a tiny segment)
        if partner[i] >= 0 or partner[j] >= 0:
            raise ValueError(f"three contour ends meet at ({ends[i][0]:.4f}, {ends[i][1]:.4f})")
        partner[i], partner[j] = j, i
    if (partner < 0).any():
        i = int(np.argmax(partner < 0))
        raise ValueError(f"open contour: an entity end at ({ends[i][0]:.4f}, "
                         f"{ends[i][1]:.4f}) meets no other")
    used = np.zeros(len(segments), bool)
    loops = []
    for first in range(len(segments)):
        if used[first]:
            continue
        verts, k, forward = [], first, True
        while not used[k]:
            used[k] = True
            a, b, bu = segments[k]
            verts.append((*a, bu) if forward else (*b, -bu))
            out_end = 2 * k + 1 if forward else 2 * k  # the end this segment leaves by
            nxt = partner[out_end]
            k, forward = nxt // 2, nxt % 2 == 0
        loops.append(BulgeLoop(np.asarray(verts, dtype=float)))
    return loops


def read_dxf_loops(path: Path) -> tuple[list[BulgeLoop], object]:
    """Read the CUT layer back as exact line-and-arc loops (either entity style).

    Returns:
        (loops, auditor): one :class:`~springcad.export.biarc.BulgeLoop` per contour
        (CIRCLE entities as two half-circle bulges); the ezdxf auditor of the file.

    Raises:
        ValueError: the CUT layer holds anything but LINE, ARC, CIRCLE and closed
            LWPOLYLINEs, or its lines and arcs do not chain into closed contours.
    """
    import ezdxf

    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    loops, loose = [], []
    for e in doc.modelspace().query(f'*[layer=="{CUT_LAYER}"]'):
        kind = e.dxftype()
        if kind == "LWPOLYLINE":
            if not e.closed:
                raise ValueError(f"{path}: open polyline on layer {CUT_LAYER}")
            loops.append(BulgeLoop(np.asarray(list(e.get_points("xyb")), dtype=float)))
        elif kind == "CIRCLE":
            (cx, cy), r = (e.dxf.center.x, e.dxf.center.y), e.dxf.radius
            loops.append(BulgeLoop(np.array([(cx + r, cy, 1.0), (cx - r, cy, 1.0)])))
        elif kind in ("LINE", "ARC"):
            loose += _entity_segments(e)
        else:
            raise ValueError(f"{path}: {kind} on layer {CUT_LAYER}; CAM needs lines, arcs "
                             "and circles only")
    try:
        loops += chain_segments(loose)
    except ValueError as err:
        raise ValueError(f"{path}: {err}") from None
    return loops, auditor


def loops_area_mm2(loops) -> float:
    """Area enclosed by the largest loop minus the others (mm^2), exact for lines and arcs."""
    areas = sorted((abs(lp.area_mm2()) for lp in loops), reverse=True)
    return areas[0] - sum(areas[1:])


def loops_length_mm(loops) -> float:
    """Total length of all contours (mm): the wire path."""
    return sum(lp.length_mm() for lp in loops)
