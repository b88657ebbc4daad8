"""Turn exact 2D profiles (:mod:`springcad.design.curves`) into build123d faces and solids.

Lines, arcs and circles become true lines and circles in the kernel; a spline
becomes a few Bezier edges of degree 8 within 0.5 um of it
(:mod:`springcad.geometry.bezier`), so the kernel's volume integral of the
solid, and that of any OCC-based CAD reading its STEP, is exact (a
single ~40-span B-spline edge per flank made it 0.2-8 % off). Units: mm.
"""

from __future__ import annotations

import math
import weakref

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline
from springcad.design.planar import find_defect
from springcad.errors import GeometryError
from springcad.geometry.bezier import spline_beziers


def _bezier_edge(ctrl):
    """build123d ``Edge`` of one planar Bezier piece (control points (n, 2), mm)."""
    import build123d as bd
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.collections import Array1_gp_Pnt
    from OCP.Geom import Geom_BezierCurve
    from OCP.gp import gp_Pnt

    poles = Array1_gp_Pnt(1, len(ctrl))
    for i, (x, y) in enumerate(ctrl):
        poles.SetValue(i + 1, gp_Pnt(float(x), float(y), 0.0))
    return bd.Edge(BRepBuilderAPI_MakeEdge(Geom_BezierCurve(poles)).Edge())


def segment_edges(seg) -> list:
    """build123d edges for a profile segment: one, or a spline's Bezier pieces."""
    if isinstance(seg, Spline) and seg.start_tangent is not None and seg.end_tangent is not None:
        pieces, _ = spline_beziers(seg)
        return [_bezier_edge(c) for c in pieces]
    return [segment_edge(seg)]


def segment_edge(seg):
    """One build123d ``Edge`` for a profile segment (a spline as one interpolating B-spline)."""
    import build123d as bd

    if isinstance(seg, Line):
        return bd.Edge.make_line((*seg.start, 0.0), (*seg.end, 0.0))
    if isinstance(seg, Circle):
        return bd.Edge.make_circle(seg.radius, bd.Plane.XY.move(bd.Location((*seg.center, 0.0))))
    if isinstance(seg, Arc):
        plane = bd.Plane.XY.move(bd.Location((*seg.center, 0.0)))
        a0, a1 = math.degrees(seg.start_angle), math.degrees(seg.end_angle)
        if a1 >= a0:
            edge = bd.Edge.make_circle(seg.radius, plane, a0, a1)
        else:
            edge = bd.Edge.make_circle(seg.radius, plane, a1, a0).reversed()
        return edge
    if isinstance(seg, Spline):
        # same chord-length parameters and end derivatives as Spline._spline, so the kernel's
        # C2 cubic interpolant is the curve the design evaluated
        u = seg.parameters()
        total = u[-1]
        tangents = None
        if seg.start_tangent is not None and seg.end_tangent is not None:
            tangents = [(seg.start_tangent[0] * total, seg.start_tangent[1] * total, 0.0),
                        (seg.end_tangent[0] * total, seg.end_tangent[1] * total, 0.0)]
        return bd.Edge.make_spline([(x, y, 0.0) for x, y in seg.points], tangents=tangents,
                                   parameters=list(u / total), scale=False)
    raise TypeError(f"unknown segment {type(seg).__name__}")


def loop_wire(loop: Loop):
    """A closed build123d ``Wire`` for a loop (endpoints snapped by the kernel)."""
    import build123d as bd

    edges = [e for s in loop.segments for e in segment_edges(s)]
    try:
        wire = bd.Wire(edges)
    except ValueError:
        wire = None
    if wire is None or not wire.is_closed:
        wire = bd.Wire.combine(edges, tol=1e-5)[0]
    if not wire.is_closed:
        raise GeometryError("profile loop does not close in the CAD kernel")
    return wire


def _loop_name(i: int) -> str:
    return "outer contour" if i == 0 else ("inner contour" if i == 1 else f"hole {i - 1}")


def _where(x: float, y: float) -> str:
    return (f"({x:.3f}, {y:.3f}) mm, r = {math.hypot(x, y):.3f} mm, "
            f"{math.degrees(math.atan2(y, x)):.1f} deg")


def _cause(la: int, lb: int) -> str:
    """What probably went wrong when loops ``la`` and ``lb`` meet, and what to change."""
    if max(la, lb) >= 2:
        return ("a hole does not fit where it is (it cuts the rim or a flexure): use smaller "
                "fasteners (hardware.fastener_diameter_mm) or a wider rim")
    if la == lb:
        return ("the contour is self-intersecting (flexures too wide or too curved for their "
                "pitch, or a fillet that does not fit its corner): fewer flexures, a larger "
                "outer radius or a lower stiffness")
    return "the contours must stay apart: change the design"


def check_loops(profile: Profile, part: str = "part", step_mm: float = 0.02) -> None:
    """Check that no loop crosses or touches itself or another loop and that holes lie inside.

    The test is the planar toolkit's (:func:`springcad.design.planar.find_defect`)
    on the loops sampled every ``step_mm`` (a chord strays h^2 / 8R from its
    curve: well under a micrometre here), so the kernel is never asked to make
    a face from crossing contours.

    Raises:
        GeometryError: names the part, the loops, where they meet and what to change.
    """
    defect = find_defect(profile, step_mm)
    if defect is None:
        return
    la, lb = defect.loops
    where = _where(*defect.point_mm)
    if defect.kind in ("cross", "touch"):
        verb = "crosses" if defect.kind == "cross" else "touches"
        what = (f"the {_loop_name(la)} {verb} itself" if la == lb else
                f"the {_loop_name(la)} and the {_loop_name(lb)} cross" if defect.kind == "cross"
                else f"the {_loop_name(la)} touches the {_loop_name(lb)}")
        raise GeometryError(f"{part}: {what} at {where}; {_cause(la, lb)}")
    if defect.kind == "outside":
        raise GeometryError(f"{part}: the {_loop_name(la)} at {where} lies outside "
                            "the outer contour; move it inside the part")
    raise GeometryError(f"{part}: the {_loop_name(la)} at {where} lies inside the "
                        f"{_loop_name(lb)}; holes must not nest")


#: faces made from profiles still alive, by id(profile) (see :func:`profile_face`)
_FACES: dict[int, object] = {}


def _remember(profile: Profile, face) -> None:
    """Keep ``face`` for ``profile`` while the profile lives (a profile that cannot be
    referenced weakly is not kept)."""
    if id(profile) not in _FACES:  # a profile alive is kept once (its finalizer drops it)
        try:
            weakref.finalize(profile, _FACES.pop, id(profile), None)
        except TypeError:
            return
    _FACES[id(profile)] = face


def profile_face(profile: Profile, part: str = "part", check: bool = True):
    """Planar face (z = 0) with holes for a profile.

    The loops are checked first (:func:`check_loops`; ``check=False``: a profile checked
    before, e.g. the one a part's solid was made from), so crossing contours are reported
    with their place rather than as a kernel failure.

    With ``check=False``, the face made before from this very profile object (while it
    lives) is returned again: the DXF read-back's reference area is that of the face the
    part's solid was extruded from, not a second one (the ring's took ~0.5 s). Callers must
    not modify it. A checked call always makes a new face.

    Raises:
        GeometryError: the contours cross, or the kernel cannot make a valid face
            (names ``part``).
    """
    import build123d as bd

    made = None if check else _FACES.get(id(profile))
    if made is not None:
        return made
    if check:
        check_loops(profile, part)
    try:
        outer = loop_wire(profile.outer)
        inner = [loop_wire(h) for h in profile.holes]
        face = bd.Face(outer, inner)
    except GeometryError as err:
        raise GeometryError(f"{part}: {err}") from err
    except Exception as err:  # kernel failure
        raise GeometryError(f"{part}: the CAD kernel could not make the profile face ({err})") from err
    if not face.is_valid:
        raise GeometryError(f"{part}: the profile face is not valid (self-intersecting contour?)")
    _remember(profile, face)
    return face


def extrude_profile(profile: Profile, thickness_mm: float, part: str = "part", z_mm: float = 0.0):
    """Prism of a profile from z to z + thickness (mm)."""
    import build123d as bd

    face = profile_face(profile, part)
    solid = bd.Solid.extrude(face, (0, 0, thickness_mm))
    if z_mm:
        solid = solid.moved(bd.Location((0, 0, z_mm)))
    if not solid.is_valid:
        raise GeometryError(f"{part}: extruded solid is not valid")
    return solid
