"""FE model geometry of a flexure ring: the one-flexure sector and the full ring.

Works on the exact design curves (:mod:`springcad.design.curves`), so the CAD
face that is meshed is the one the design produced, not a polyline.

Frame: flexure 0 lies along +y, its tip-ball centre at ``(0, r_c)``; the cam
pushes the tip towards -x (counter-clockwise torque about +z). The sector is
the material of flexure 0 plus the rim wedge between the radial lines through
the middles of the rim arcs on either side of it (``pi/2 -+ pi/N`` for a
flexure whose root lines up with its tip); neighbouring flexures never reach into the wedge's rim part,
and inside the root circle each flexure is a separate body, so the sector is
exactly one repeating unit of the ring, however far a serpentine flexure
wanders sideways.

Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Arc, Line, Loop, Profile
from springcad.design.planar import find_defect
from springcad.errors import MeshingError

#: flexure features whose FE boundary label carries the flexure number ("root:3");
#: the root-circle arcs between flexures are all labelled "rim"
_INDEXED = {"root", "edge", "neck", "ball"}


def _label(feature) -> str:
    return feature.label if feature.kind in _INDEXED else feature.kind


def _angle_in(arc: Arc, a: float) -> float:
    """``a`` shifted by whole turns into the angular range of ``arc`` (rad)."""
    lo, hi = sorted((arc.start_angle, arc.end_angle))
    k = math.floor((hi - a) / (2 * math.pi))
    a2 = a + 2 * math.pi * k
    if not lo - 1e-12 <= a2 <= hi + 1e-12:
        raise MeshingError(
            f"the sector side at {math.degrees(a):.3f} deg does not cut the rim arc between "
            "flexures; the root fillets reach past the half pitch")
    return a2


@dataclass(frozen=True, eq=False)
class RingGeometry:
    """What the FE model needs to know about one flexure ring (mm, rad).

    Attributes:
        profile: the face to mesh (sector or full ring), counter-clockwise outer loop.
        n_flexures: N of the ring.
        sector: True for the one-flexure sector, False for the full ring.
        outer_radius_mm, root_radius_mm, contact_radius_mm, tip_radius_mm: ring radii.
        thickness_mm: disk thickness z.
        hole_centres_mm, hole_radius_mm: rim holes present in ``profile``.
        flexure_angles_rad: polar angle of each modelled flexure's axis.
    """

    profile: Profile
    n_flexures: int
    sector: bool
    outer_radius_mm: float
    root_radius_mm: float
    contact_radius_mm: float
    tip_radius_mm: float
    thickness_mm: float
    root_fillet_radius_mm: float
    neck_fillet_radius_mm: float
    hole_centres_mm: tuple[tuple[float, float], ...]
    hole_radius_mm: float
    flexure_angles_rad: tuple[float, ...]
    centreline_mm: np.ndarray
    """Flexure-0 centreline samples from tip to root, shape (m, 2) (mm)."""
    width_mm: np.ndarray
    """Flexure width at each centreline sample, shape (m,) (mm)."""
    fillets_mm: tuple[tuple[float, float, float, str], ...]
    """Flexure-0 fillets and tip ball as (x, y, radius, kind), kind "root", "neck" or "ball"."""
    side_angles_rad: tuple[float, ...]
    """Polar angles of the sector's two cuts (right, left); ``()`` for the full ring."""
    labels: tuple[tuple[str, ...], ...]
    """Boundary label of every segment of every profile loop (outer first): "clamp"
    (outer circle), "side" (sector cut), "rim" (root circle), "hole:j", and
    "root:i", "edge:i", "neck:i", "ball:i" for flexure i."""

    @property
    def half_pitch_rad(self) -> float:
        return math.pi / self.n_flexures

    @property
    def rim_thickness_mm(self) -> float:
        return self.outer_radius_mm - self.root_radius_mm

    def contact_points_mm(self) -> np.ndarray:
        """Cam contact point on each modelled tip ball, shape (n, 2) (mm).

        The point of the ball at the contact radius on the side the cam
        pushes (+x side of flexure 0, load towards -x).
        """
        rb, rc = self.tip_radius_mm, self.contact_radius_mm
        pts = []
        for a in self.flexure_angles_rad:
            c, s = math.cos(a - math.pi / 2), math.sin(a - math.pi / 2)
            pts.append((c * rb - s * rc, s * rb + c * rc))
        return np.asarray(pts)

    def ball_centres_mm(self) -> np.ndarray:
        rc = self.contact_radius_mm
        return np.asarray([(rc * math.cos(a), rc * math.sin(a)) for a in self.flexure_angles_rad])

    @property
    def area_mm2(self) -> float:
        return self.profile.area_mm2()

    @property
    def volume_mm3(self) -> float:
        return self.area_mm2 * self.thickness_mm


def _fillets(flexures: Loop) -> tuple:
    """Every arc of flexure 0's root, neck and ball as (x, y, radius, kind) (mm)."""
    return tuple((float(s.center[0]), float(s.center[1]), float(s.radius), kind)
                 for kind in ("root", "neck", "ball") for s in flexures.named(kind, 0)
                 if isinstance(s, Arc))


def _common(design):
    y = design.contact_radius_mm + (design.root_radius_mm - design.contact_radius_mm) * \
        np.linspace(0.0, 1.0, 400) ** 2
    x, _, _ = design.centreline.evaluate(y)
    fillets = _fillets(design.ring.loop("flexures"))
    return dict(centreline_mm=np.column_stack([x, y]), width_mm=np.asarray(design.width_mm(y)),
                fillets_mm=fillets,
                n_flexures=design.n_flexures, outer_radius_mm=design.outer_radius_mm,
                root_radius_mm=design.root_radius_mm, contact_radius_mm=design.contact_radius_mm,
                tip_radius_mm=design.tip_radius_mm, thickness_mm=design.thickness_mm,
                root_fillet_radius_mm=design.root_fillet_radius_mm,
                neck_fillet_radius_mm=design.neck_fillet_radius_mm)


def sector_geometry(design) -> RingGeometry:
    """One flexure with its rim wedge, free sides at ``pi/2 -+ pi/N`` (no rim holes).

    Args:
        design: a :class:`~springcad.design.spring.SpringDesign` with its ``ring`` profile.

    Raises:
        MeshingError: the ring profile is missing or not laid out as expected.
    """
    if design.ring is None:
        raise MeshingError(f"spring '{design.name}' has no ring profile to mesh")
    n = design.n_flexures
    flexures = design.ring.loop("flexures")
    try:
        (rim_before,), (rim_after,) = flexures.named("rim", n - 1), flexures.named("rim", 0)
    except (KeyError, ValueError) as err:
        raise MeshingError(f"spring '{design.name}': the ring's flexure loop has no single rim "
                           f"arc on each side of flexure 0 ({err})") from err
    own = [i for i in flexures.indices(0) if flexures.features[i].kind != "rim"]
    body = [flexures.segments[i] for i in own]
    body_labels = [_label(flexures.features[i]) for i in own]
    ro, rr = design.outer_radius_mm, design.root_radius_mm
    # the sector sides cut the middle of the rim arcs on either side of flexure 0: a swept
    # flexure whose root sits off its tip's radial line still gets a whole repeating unit
    mid = 0.5 * (rim_before.start_angle + rim_before.end_angle)
    a_r = mid + 2 * math.pi * round((math.pi / 2 - math.pi / n - mid) / (2 * math.pi))
    a_l = a_r + 2 * math.pi / n
    a_r2 = _angle_in(rim_before, a_r)
    a_l2 = _angle_in(rim_after, a_l)

    def polar(r, a):
        return (r * math.cos(a), r * math.sin(a))

    loop = [Arc((0.0, 0.0), ro, a_r, a_l),
            Line(polar(ro, a_l), polar(rr, a_l)),
            Arc((0.0, 0.0), rr, a_l2, rim_after.start_angle)]
    loop += [s.reversed() for s in reversed(body)]
    loop += [Arc((0.0, 0.0), rr, rim_before.end_angle, a_r2),
             Line(polar(rr, a_r), polar(ro, a_r))]
    profile = Profile(Loop(tuple(loop)))
    if profile.outer.signed_area() <= 0:
        raise MeshingError(f"spring '{design.name}': sector loop is not counter-clockwise")
    labels = ("clamp", "side", "rim", *reversed(body_labels), "rim", "side")
    return RingGeometry(profile=profile, sector=True, hole_centres_mm=(), hole_radius_mm=0.0,
                        labels=(labels,), side_angles_rad=(a_r, a_l),
                        flexure_angles_rad=(math.pi / 2,), **_common(design))


def ring_geometry(design, holes: bool = True) -> RingGeometry:
    """The full ring, with its rim holes unless ``holes`` is False."""
    if design.ring is None:
        raise MeshingError(f"spring '{design.name}' has no ring profile to mesh")
    n = design.n_flexures
    ring = design.ring
    flexures = ring.loop("flexures")
    hole_loops = ring.loops_named("hole") if holes else ()
    prof = Profile(ring.loop("outer"), (flexures, *hole_loops),
                   ("outer", "flexures", *(f"hole:{j}" for j in range(len(hole_loops)))))
    inner = tuple(_label(f) for f in flexures.features)
    holes_l = tuple((f"hole:{j}",) for j in range(len(hole_loops)))
    return RingGeometry(
        profile=prof, sector=False, labels=(("clamp",), inner, *holes_l), side_angles_rad=(),
        hole_centres_mm=tuple(design.hole_centres_mm) if holes else (),
        hole_radius_mm=0.5 * design.hole_diameter_mm if holes else 0.0,
        flexure_angles_rad=tuple(math.pi / 2 + 2 * math.pi * i / n for i in range(n)),
        **_common(design))


def check_profile(profile: Profile, step_mm: float = 0.02, name: str = "profile") -> None:
    """Reject a face the mesher cannot handle before it reaches the mesher.

    The test is the planar toolkit's (:func:`springcad.design.planar.find_defect`)
    on the loops sampled every ``step_mm``: no loop crosses or touches itself or
    another loop, every hole lies inside the outer contour and outside the other
    holes. (gmsh does not fail cleanly on such faces: it can loop forever.)

    Raises:
        MeshingError: naming the loops and a point near the problem.
    """
    defect = find_defect(profile, step_mm)
    if defect is None:
        return
    a, b = defect.loops
    x, y = defect.point_mm
    if defect.kind in ("cross", "touch"):
        verb = "crosses" if defect.kind == "cross" else "touches"
        what = (f"loop {a} {verb} itself" if a == b else
                f"{'the outer contour' if a == 0 else f'hole loop {a}'} {verb} hole loop {b}")
        raise MeshingError(f"{name}: {what} near ({x:.3f}, {y:.3f}) mm; the "
                           "face cannot be meshed (check hole positions and fillets)")
    if defect.kind == "outside":
        raise MeshingError(f"{name}: hole loop {a} near ({x:.3f}, {y:.3f}) mm lies "
                           "outside the outer contour")
    raise MeshingError(f"{name}: hole loop {a} lies inside hole loop {b}")
