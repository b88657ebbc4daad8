"""Common ground of every springcad part: z-prism slabs, the part base class, measurements.

Every part of a stack is a *z-prism* or a short pile of them: a planar region
(a :class:`~springcad.design.curves.Profile`) swept along the stack axis over
``[z0, z1]``. A part keeps that description (its :class:`Slab` list) next to
its solid, so that the checks can reason exactly in 2D (interference, EDM
rules) and the measurements can hold the solid against it (volume = sum of
slab area x length). Units: mm, mm^2, mm^3.

Part numbers
------------
A part number names one geometry, never a job's local label: it is the part
family's code and the first :data:`PN_HASH_DIGITS` hex digits of the SHA-256 of
the part's *identity* (:func:`identity_text`): family, material, heat
treatment, process, catalogue standard, general tolerance and every slab's z
range and exact contour (lines, arcs, circles, spline fit points and end
tangents, rounded to :data:`IDENTITY_DIGITS` decimals of a mm). So

* the same geometry gets the same number in every job (``RING-1A2B3C4D``
  whether the job calls the spring S1 or A, alone or in a stack);
* any change of form, fit or material (a radius, a tolerance, a heat
  treatment) gives a new number. A new number starts at revision A.

Revision rule: the revision letter (``springcad build --revision``) changes only
for documentation changes of an unchanged part number (notes, title block,
drawing layout); it never stands for a change of geometry, which would be a new
number. The job-local label a stack gives a part (``S1-RING``,
``RIM-SPACER-2``) is :attr:`PartInfo.name`: messages, the BOM and the drawing
header show it next to the number.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace

from springcad.design.cam import d_bore
from springcad.design.catalogue import g6_deviation_mm
from springcad.geometry import sklearn_deferred

with sklearn_deferred():
    from build123d import BasePartObject, Color, Solid

from springcad.design.curves import Arc, Circle, Line, Loop, Profile, Spline
from springcad.errors import GeometryError
from springcad.geometry.part_info import NamedByInfo, PartInfo, Slab  # noqa: F401  (their home before)
from springcad.geometry.profile import extrude_profile

#: display colours (RGB 0-1) by material family
COLOURS = {
    "steel": (0.62, 0.64, 0.68),
    "cam": (0.35, 0.37, 0.42),
    "aluminium": (0.80, 0.82, 0.86),
    "plastic": (0.93, 0.90, 0.78),
    "fastener": (0.78, 0.62, 0.25),
    "input": (0.20, 0.62, 0.32),
    "output": (0.82, 0.33, 0.20),
}


#: tolerance of turned, sheet and catalogue parts unless a part says otherwise (mm)
GENERAL_TOLERANCE_MM = 0.05
#: hex digits of the identity hash in a part number (32 bits: two different parts of one
#: family share a number with probability ~ n^2 / 2^33 for n part designs)
PN_HASH_DIGITS = 8
#: decimals (of a mm, of a unit tangent) to which the identity rounds coordinates:
#: 1e-6 mm, far below any tolerance, far above floating-point noise between jobs
IDENTITY_DIGITS = 6


def _num(x: float) -> str:
    return f"{round(float(x), IDENTITY_DIGITS) + 0.0:.{IDENTITY_DIGITS}f}"


def _pts(*points) -> str:
    return " ".join(_num(v) for p in points for v in p)


def _segment_text(seg) -> str:
    if isinstance(seg, Line):
        return "L " + _pts(seg.start, seg.end)
    if isinstance(seg, Circle):
        return f"C {_pts(seg.center)} {_num(seg.radius)}"
    if isinstance(seg, Arc):  # by points and sweep: angles may differ by 2 pi for one arc
        return f"A {_pts(seg.start, seg.end, seg.center)} {_num(seg.radius)} {_num(seg.sweep)}"
    if isinstance(seg, Spline):
        return f"S {_pts(*seg.points)} T {_pts(seg.start_tangent, seg.end_tangent)}"
    raise TypeError(f"unknown segment {type(seg).__name__}")


def identity_text(info: PartInfo, slabs, tolerance_mm: float) -> str:
    """Everything that makes a part what it is, as text (see the module docstring).

    Not part of it: the job-local name, the title, notes, quantity and placement.
    """
    lines = [f"code {info.code}", f"kind {info.kind}", f"material {info.material}",
             f"heat treatment {info.heat_treatment}", f"hardness {info.hardness}",
             f"heat treatment sequence {info.heat_treatment_sequence}",
             f"fits {sorted(info.fits.items())}", f"process {info.process}",
             *([f"secondary processes {' '.join(info.secondary_processes)}"]
               if info.secondary_processes else []),
             f"standard {info.standard}", *([f"stock {info.stock}"] if info.stock else []),
             f"tolerance {_num(tolerance_mm)}"]
    for sl in slabs:
        lines.append(f"slab {_num(sl.z0_mm)} {_num(sl.z1_mm)}")
        for loop in sl.region.loops:
            lines.append("loop " + "; ".join(_segment_text(seg) for seg in loop.segments))
    return "\n".join(lines)


def part_number_of(info: PartInfo, slabs, tolerance_mm: float) -> str:
    """``CODE-XXXXXXXX``: the family code and the hash of the part's identity."""
    digest = hashlib.sha256(identity_text(info, slabs, tolerance_mm).encode()).hexdigest()
    code = info.code or info.kind.upper().replace("_", "-")
    return f"{code}-{digest[:PN_HASH_DIGITS].upper()}"


class SpringcadPart(NamedByInfo, BasePartObject):
    """A build123d part made of z-prism slabs, with its design values as attributes.

    Subclasses compute their slabs from the design and call this initialiser.
    The solid is built from the slabs (one extrusion each, fused), so solid and
    slab description cannot drift apart.

    Args:
        info: part metadata (:class:`PartInfo`).
        slabs: the z-prism pieces in the part frame.
        colour: RGB (0-1) for renders and the assembly STEP.
        solid: a ready solid (used by parts that are not plain prisms, e.g.
            catalogue screws); slabs then only serve the interference check.
    """

    def __init__(self, info: PartInfo, slabs: tuple[Slab, ...], colour, solid: Solid | None = None):
        self.slabs = tuple(slabs)
        self.info = replace(info, part_number=part_number_of(info, self.slabs, self.tolerance_mm))
        self.colour = tuple(colour)
        self.exact_prism = solid is None
        #: the kernel's validity of the solid when building it checked it (prism_solid
        #: raises on an invalid one), else None: the checks stage asks again only then
        self.solid_valid: bool | None = None
        self._volume_mm3: float | None = None
        if solid is None:
            solid = prism_solid(self.slabs, info.name)
            self.solid_valid = True
        solid.label = self.part_number
        super().__init__(solid)
        self.label = self.part_number
        self.color = Color(*self.colour)

    @property
    def tolerance_mm(self) -> float:
        """General tolerance of the part (mm); profile-cut parts override it."""
        return GENERAL_TOLERANCE_MM

    def describe(self, x: float, y: float) -> str:
        """Name the feature at part-frame (x, y) mm for check reports."""
        return ""

    @property
    def solid(self) -> Solid:
        """The one solid of this part."""
        return self.solids()[0]

    def volume_mm3(self) -> float:
        """The exact volume of the solid (:func:`solid_volume_mm3`, mm^3), measured once: the
        checks, the cached skeleton and the STEP read-back all hold files against it."""
        if getattr(self, "_volume_mm3", None) is None:
            self._volume_mm3 = solid_volume_mm3(self.solid)
        return self._volume_mm3

    def slab_volume_mm3(self) -> float:
        """Volume from the 2D description: sum of region area x length (mm^3)."""
        return sum(s.volume_mm3() for s in self.slabs)

    @property
    def z_range_mm(self) -> tuple[float, float]:
        return (min(s.z0_mm for s in self.slabs), max(s.z1_mm for s in self.slabs))


# ------------------------------------------------------------------ building blocks
def circle_loop(radius_mm: float, centre=(0.0, 0.0)) -> Loop:
    return Loop((Circle(tuple(centre), radius_mm),))


def annulus(r_in_mm: float, r_out_mm: float, holes: tuple[Loop, ...] = ()) -> Profile:
    """Ring region between two radii with optional extra holes; a disc when r_in = 0 (mm)."""
    inner = (circle_loop(r_in_mm),) if r_in_mm > 0 else ()
    return Profile(circle_loop(r_out_mm), (*inner, *holes))


def d_loop(radius_mm: float, flat_ratio: float, corner_radius_mm: float) -> Loop:
    """Circle of ``radius_mm`` with a flat at ``flat_ratio * radius`` below the centre.

    The same loop as the camshaft's D bore (:func:`springcad.design.cam.d_bore`),
    corners rounded by ``corner_radius_mm`` (what the wire leaves in the bore), so
    a D shaft or D hub built from it fits that bore line to line.
    """
    return d_bore(radius_mm, flat_ratio, corner_radius_mm)


def across_flat_check(diameter_mm: float, flat_ratio: float, flat_tolerance_mm: float) -> str:
    """How a shop measures the flat of a g6 D shaft or D hub, which the drawing gives from
    the axis (0/-``flat_tolerance_mm``): the size across it (flat to the far side of the
    round, a micrometer reading) is the g6 radius plus the flat's distance (mm)."""
    lo, hi = g6_deviation_mm(diameter_mm)
    r_mm, a_mm = 0.5 * diameter_mm, flat_ratio * 0.5 * diameter_mm
    return (f"Check the flat by the size across it (flat to the far side of the round): "
            f"{r_mm + 0.5 * lo + a_mm - flat_tolerance_mm:.3f}-{r_mm + 0.5 * hi + a_mm:.3f} mm "
            f"(the g6 radius {r_mm + 0.5 * lo:.3f}-{r_mm + 0.5 * hi:.3f} + the flat's "
            f"{a_mm - flat_tolerance_mm:.3f}-{a_mm:.3f} from the axis).")


def prism_solid(slabs, part: str) -> Solid:
    """Fuse the extrusion of every slab into one solid.

    Raises:
        GeometryError: a slab cannot be made or the result is not one valid solid.
    """
    pieces = [extrude_profile(s.region, s.length_mm, part, s.z0_mm) for s in slabs]
    solid = pieces[0]
    if len(pieces) > 1:
        try:
            fused = pieces[0].fuse(*pieces[1:]).clean()
        except Exception as err:  # kernel failure
            raise GeometryError(f"{part}: the CAD kernel could not join its sections ({err})") from err
        solids = fused.solids()
        if len(solids) != 1:
            raise GeometryError(f"{part}: its sections do not join into one solid "
                                f"({len(solids)} pieces); check the axial layout")
        solid = solids[0]
        if not solid.is_valid:  # one slab: extrude_profile checked this very solid
            raise GeometryError(f"{part}: the solid is not valid")
    return solid


# ------------------------------------------------------------------ measurements
def face_area_mm2(face) -> float:
    """Exact area of a face from the kernel (mm^2)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face.wrapped, props, 1e-9)
    return props.Mass()


def mesh_volume_mm3(shape, deflection_mm: float = 0.001) -> float:
    """Volume of the triangulated shape (mm^3); accurate but slow on large B-spline parts."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    from OCP.BRepGProp import BRepGProp
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.GProp import GProp_GProps

    copy = BRepBuilderAPI_Copy(shape.wrapped, True, False).Shape()  # keep the original's mesh
    BRepMesh_IncrementalMesh(copy, deflection_mm, False, 0.1, True)
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(copy, props, False, False, True)
    return props.Mass()


def solid_volume_mm3(shape) -> float:
    """Volume of a solid by the divergence theorem, exact for z-prismatic solids (mm^3).

    With the field F = (0, 0, z), V = sum over faces of the integral of z n_z dA.
    Side faces of a z-prism (cylinders with a z axis, extrusions along z, vertical
    planes, B-spline surfaces that are such extrusions, as a STEP export writes
    them) have n_z = 0; horizontal planar faces contribute n_z z A with the exact
    kernel area. A face of any other kind (a screw head, a tilted plane) sends the
    whole shape to :func:`mesh_volume_mm3`. The kernel's default volume integration
    was 0.2-8 % off on extruded many-span B-spline faces, which is why it is not used.
    """
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepGProp import BRepGProp
    from OCP.GeomAbs import (GeomAbs_BSplineSurface, GeomAbs_Cylinder, GeomAbs_Plane,
                             GeomAbs_SurfaceOfExtrusion)
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_REVERSED

    total = 0.0
    for face in shape.faces():
        surf = BRepAdaptor_Surface(face.wrapped)
        kind = surf.GetType()
        if kind == GeomAbs_Plane:
            n = surf.Plane().Axis().Direction()
            nz = n.Z() * (-1.0 if face.wrapped.Orientation() == TopAbs_REVERSED else 1.0)
            if abs(nz) < 1e-12:
                continue
            if abs(abs(nz) - 1.0) > 1e-9:
                return mesh_volume_mm3(shape)
            props = GProp_GProps()
            BRepGProp.SurfaceProperties_s(face.wrapped, props, 1e-9)
            total += nz * props.CentreOfMass().Z() * props.Mass()
        elif kind == GeomAbs_Cylinder:
            if abs(abs(surf.Cylinder().Axis().Direction().Z()) - 1.0) > 1e-9:
                return mesh_volume_mm3(shape)
        elif kind == GeomAbs_SurfaceOfExtrusion:
            if abs(abs(surf.Direction().Z()) - 1.0) > 1e-9:
                return mesh_volume_mm3(shape)
        elif kind == GeomAbs_BSplineSurface:
            if not _is_z_extrusion(surf.BSpline()):
                return mesh_volume_mm3(shape)
        else:
            return mesh_volume_mm3(shape)
    return total


def _is_z_extrusion(bspline, tol_mm: float = 1e-9) -> bool:
    """True if a B-spline surface is a curve extruded along z: linear in v with its two
    rows of poles differing in z only (its normal is horizontal everywhere)."""
    if bspline.VDegree() != 1 or bspline.NbVPoles() != 2 or bspline.IsVRational():
        return False
    for i in range(1, bspline.NbUPoles() + 1):
        a, b = bspline.Pole(i, 1), bspline.Pole(i, 2)
        if abs(a.X() - b.X()) > tol_mm or abs(a.Y() - b.Y()) > tol_mm:
            return False
    return True
