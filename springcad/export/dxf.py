"""Wire-EDM cutting profiles as DXF for CAM, and reading them back.

What a CAM system gets:

* layer ``CUT``: every loop of the cutting profile as **one closed LWPOLYLINE
  of lines and arcs** (bulges), so one entity is one contour. Lines, arcs and
  circles of the design are exact; the design's splines are replaced by biarcs
  (:mod:`springcad.export.biarc`) within :data:`CHORD_TOL_MM` of the design
  curve (measured at the writer, stated in the file). No SPLINE, no loose pieces.
* layer ``INFO``: part number, thickness, units and the tolerance as text,
  placed inside the bounding box of the cut contours (the outline's bottom left
  corner, where a round part has no material), so the drawing extents are the
  cut extents.
* units mm (``$INSUNITS`` = 4, ``$MEASUREMENT`` = 1), DXF R2010.
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
from springcad.export.biarc import BulgeLoop, loop_bulges

CUT_LAYER = "CUT"
INFO_LAYER = "INFO"
#: largest distance of the written contour from the design curve (mm): 1 um in all,
#: half of it for the biarcs so the CAD kernel's own spline fit (well under 0.5 um from
#: the design curve) stays inside the budget
CHORD_TOL_MM = 0.001
BIARC_TOL_MM = 0.5 * CHORD_TOL_MM
#: INFO text: character width / height of the DXF standard font (ezdxf's estimate ~0.6-0.9)
_CHAR_ASPECT = 1.0


@dataclass(frozen=True)
class DxfReport:
    """What the writer did: loops written, biarcs and the largest measured deviation (mm)."""

    path: Path
    n_loops: int
    n_biarcs: int
    max_deviation_mm: float


def _info_text(msp, lines: list[str], bbox) -> None:
    """Text lines in the bottom left corner of ``bbox`` (xmin, ymin, xmax, ymax), inside it.

    The corner square of side (1 - 1/sqrt 2) x radius of a round outline holds no
    material; the lines are sized to fit a square of 0.8 x that side.
    """
    x0, y0, x1, y1 = bbox
    side = 0.8 * (1 - 1 / math.sqrt(2)) * 0.5 * min(x1 - x0, y1 - y0)
    longest = max(len(s) for s in lines)
    h = min(side / (_CHAR_ASPECT * longest), side / (1.6 * len(lines)))
    for k, line in enumerate(lines):
        msp.add_text(line, height=h, dxfattribs={"layer": INFO_LAYER}).set_placement(
            (x0 + 0.1 * side, y0 + 0.1 * side + 1.6 * h * (len(lines) - 1 - k)))


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


def write_dxf(profile: Profile, path: Path, part_number: str, thickness_mm: float) -> DxfReport:
    """Write a cutting profile (mm) as DXF R2010: one closed line-and-arc polyline per loop.

    Raises:
        ValueError: a spline cannot be matched by arcs within the tolerance.
    """
    import ezdxf
    from ezdxf import units

    bulged = [loop_bulges(loop, BIARC_TOL_MM) for loop in profile.loops]
    pts = profile.outer.sample(0.05)
    bbox = (*pts.min(axis=0), *pts.max(axis=0))
    with _fixed_meta_data():
        doc = ezdxf.new("R2010", setup=False)
        doc.units = units.MM
        doc.header["$MEASUREMENT"] = 1
        doc.header["$LUNITS"] = 2
        doc.layers.add(CUT_LAYER, color=1)
        doc.layers.add(INFO_LAYER, color=7)
        msp = doc.modelspace()
        for b in bulged:
            msp.add_lwpolyline(b.vertices.tolist(), format="xyb", close=True,
                               dxfattribs={"layer": CUT_LAYER})
        _info_text(msp, [part_number, f"t {thickness_mm:g} mm, units mm",
                         f"CUT: lines+arcs, tol {CHORD_TOL_MM:g} mm"], bbox)
        doc.saveas(path)
    return DxfReport(Path(path), len(bulged), sum(b.n_biarcs for b in bulged),
                     max(b.max_deviation_mm for b in bulged))


def read_dxf_loops(path: Path) -> tuple[list[BulgeLoop], object]:
    """Read the CUT layer back as exact line-and-arc loops.

    Returns:
        (loops, auditor): one :class:`~springcad.export.biarc.BulgeLoop` per contour;
        the ezdxf auditor of the file.

    Raises:
        ValueError: the CUT layer holds anything but closed LWPOLYLINEs (a SPLINE,
            loose lines or arcs, an open polyline).
    """
    import ezdxf

    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    loops = []
    for e in doc.modelspace().query(f'*[layer=="{CUT_LAYER}"]'):
        kind = e.dxftype()
        if kind != "LWPOLYLINE":
            raise ValueError(f"{path}: {kind} on layer {CUT_LAYER}; CAM needs closed "
                             "line-and-arc polylines only")
        if not e.closed:
            raise ValueError(f"{path}: open polyline on layer {CUT_LAYER}")
        loops.append(BulgeLoop(np.asarray(list(e.get_points("xyb")), dtype=float)))
    return loops, auditor


def loops_area_mm2(loops) -> float:
    """Area enclosed by the largest loop minus the others (mm^2), exact for lines and arcs."""
    areas = sorted((abs(lp.area_mm2()) for lp in loops), reverse=True)
    return areas[0] - sum(areas[1:])


def loops_length_mm(loops) -> float:
    """Total length of all contours (mm): the wire path."""
    return sum(lp.length_mm() for lp in loops)
