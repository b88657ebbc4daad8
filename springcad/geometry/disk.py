"""The wire-EDM steel parts of a spring: the flexure ring and the camshaft.

Both are z-prisms of the design's exact profiles (:mod:`springcad.design.ring`,
:mod:`springcad.design.cam`); the camshaft of a stack end adds a turned hub.
Part frame: the stack axis is z, flexure 0 / pocket 0 point along +y, the
toothed section starts at z = 0 and a hub lies at z < 0. Units: mm, rad.
"""

from __future__ import annotations

import math

from springcad.design.curves import Profile
from springcad.design.plans import CamshaftPlan
from springcad.design.ring import hole_fits
from springcad.errors import GeometryError
from springcad.units import fmt_mm
from springcad.geometry.base import (COLOURS, PartInfo, Slab, SpringcadPart, across_flat_check,
                                     circle_loop, d_loop)

#: a turned camshaft hub: its diameter toleranced minus only by this (mm; turning holds
#: +-0.02), so at its largest it keeps the wire clearance inside the tooth root
HUB_TOLERANCE_MM = 0.04
#: coaxiality of a turned hub to the camshaft's bore, datum A (diameter of the zone, mm)
HUB_COAXIALITY_MM = 0.01


def _sector(x: float, y: float, n: int) -> int:
    """Index of the flexure / tooth sector containing (x, y); sector 0 on +y."""
    a = math.atan2(y, x) - math.pi / 2
    return int(round(a / (2 * math.pi / n))) % n


class FlexureRing(SpringcadPart):
    """The spring disk: outer rim, N flexures with tip balls, root fillets and rim holes.

    Args:
        spring: a :class:`~springcad.design.spring.SpringDesign`.

    Attributes:
        spring: the design it was built from.
        n_flexures: N.
        outer_radius, root_radius, contact_radius, tip_radius, thickness: mm.
        hole_centres: rim hole centres (mm); hole_diameter: mm.
        root_fillet_radius, neck_fillet_radius: mm.
    """

    def __init__(self, spring):
        self.spring = spring
        self.n_flexures = spring.n_flexures
        self.outer_radius = spring.outer_radius_mm
        self.root_radius = spring.root_radius_mm
        self.contact_radius = spring.contact_radius_mm
        self.tip_radius = spring.tip_radius_mm
        self.thickness = spring.thickness_mm
        self.hole_centres = tuple(spring.hole_centres_mm)
        self.hole_diameter = spring.hole_diameter_mm
        self.root_fillet_radius = spring.root_fillet_radius_mm
        self.neck_fillet_radius = spring.neck_fillet_radius_mm
        mat = spring.material.material
        dims = {
            "outer diameter": 2 * self.outer_radius,
            "contact radius r_c": self.contact_radius,
            "tip radius r_b": self.tip_radius,
            "root radius R_r": self.root_radius,
            "thickness": self.thickness,
        }
        if self.hole_centres:
            dims["bolt circle diameter"] = 2 * math.hypot(*self.hole_centres[0])
            dims["hole diameter"] = self.hole_diameter
        info = PartInfo(
            name=f"{spring.name}-RING", code="RING",
            title=f"Flexure ring, {self.n_flexures} flexures", kind="flexure_ring",
            material=mat.description or mat.name,
            heat_treatment=mat.heat_treatment, density_kg_per_m3=mat.density_kg_per_m3,
            process="wire_edm", thickness_mm=self.thickness, cut_profile=spring.ring,
            dimensions=dims, hardness=mat.hardness,
            heat_treatment_sequence=mat.heat_treatment_sequence,
            fits=hole_fits(spring.hardware) if self.hole_centres else {},
            notes=(f"{self.n_flexures} flexures equally spaced, flexure 0 on +Y (details C, D "
                   "show flexure 0; every flexure is the same).",
                   f"Tip balls R{fmt_mm(self.tip_radius)} on R{fmt_mm(self.contact_radius)}: "
                   "critical to "
                   f"function (cam-to-tip gap {spring.manufacturing.w_gap_mm:g} mm).",
                   "Do not round or chamfer the cut edges of the flexures: remove burrs "
                   "only, edges sharp to 0.02 mm."))
        super().__init__(info, (Slab(0.0, self.thickness, spring.ring),), COLOURS["steel"])

    @property
    def tolerance_mm(self) -> float:
        return self.spring.manufacturing.t_spring_mm

    @property
    def length_tolerance_mm(self) -> float:
        """Thickness tolerance (mm): the stiffness is proportional to the thickness, so it
        gets the spring's manufacturing tolerance, not the general one."""
        return self.spring.manufacturing.t_spring_mm

    def describe(self, x: float, y: float) -> str:
        """Name the feature at (x, y): rim, or flexure k tip / edge / root (mm)."""
        r = math.hypot(x, y)
        if r > self.root_radius + 1e-6:
            return "rim"
        k = _sector(x, y, self.n_flexures)
        where = ("tip" if r < self.contact_radius + 3 * self.tip_radius else
                 "root" if r > self.root_radius - 2 * self.root_fillet_radius else "edge")
        return f"flexure {k} {where}"


def axial_location_note(hub_length_mm: float, drive: str) -> str:
    """What holds a camshaft along its axis (drawing note): nothing in the spring does. An
    end camshaft (``hub_length_mm`` > 0) is held by the user's drive at its hub end face,
    directly (``drive`` "bore_flat": the D shaft slides in its bore and holds nothing) or
    through the bottom of the torque shaft's socket ("hub_flat"); a floating one runs
    between the centre spacers beside it."""
    if not hub_length_mm:
        return ("Axial location: runs between the centre spacers beside it; no part retains "
                "it along the axis (the user's housing holds the stack's end parts).")
    by = ("bears on the bottom of the torque shaft's socket, and the user's drive holds "
          "that shaft along the axis" if drive == "hub_flat" else
          "is the thrust face by which the user's drive holds it (the D shaft slides in the "
          "bore and retains nothing)")
    return (f"Axial location: no part of the spring retains this camshaft along its axis; the "
            f"hub end face {by}. The teeth are as long as the ring is thick: an axial offset "
            "shortens the contact line.")


class Camshaft(SpringcadPart):
    """The gear-like camshaft: toothed section(s) and, at a stack end, a turned hub.

    Args:
        spring: the spring whose cam profile is cut (for a shared camshaft, the
            member with the smallest tooth; see :meth:`check_members`).
        toothed_length_mm: length of the toothed section (mm).
        hub_length_mm: hub length (mm), 0 for a floating camshaft.
        bore: "d_flat" (the design's D bore, takes a D shaft) or "round" (runs on
            the alignment shaft).
        drive: "bore_flat", "hub_flat" (D flat on the hub) or "" (floating).
        bore_diameter_mm, flat_ratio: bore size (mm) and hub flat position (-).
        hub_radius_mm: hub radius (mm), inside the cam root radius.

    Attributes:
        travel_rad: cam rotation the tooth flank covers (rad).
    """

    def __init__(self, spring, toothed_length_mm: float, hub_length_mm: float,
                 bore: str, drive: str, bore_diameter_mm: float, flat_ratio: float,
                 hub_radius_mm: float = 0.0):
        self.spring = spring
        self.n_teeth = spring.n_flexures
        self.contact_radius = spring.contact_radius_mm
        self.tip_radius = spring.cam_tip_radius_mm
        self.root_radius = spring.cam_root_radius_mm
        self.toothed_length = toothed_length_mm
        self.hub_length = hub_length_mm
        self.hub_radius = hub_radius_mm
        self.bore, self.drive = bore, drive
        self.bore_diameter = bore_diameter_mm
        self.gap = spring.manufacturing.w_gap_mm
        self.travel_rad = spring.cam_overtravel * spring.max_deflection_rad
        tag = f"{spring.name}-CAM-L{toothed_length_mm:g}"
        if hub_length_mm:
            tag += f"-H{hub_length_mm:g}"
        tag += "-R" if bore == "round" else ""
        bore_loop = (spring.cam.loop("bore") if bore == "d_flat"
                     else circle_loop(0.5 * bore_diameter_mm))
        teeth = Profile(spring.cam.loop("teeth"), (bore_loop,), ("teeth", "bore"))
        slabs = [Slab(0.0, toothed_length_mm, teeth)]
        if hub_length_mm:
            hub_outer = (d_loop(self.hub_radius, flat_ratio,
                                spring.manufacturing.min_inside_radius_mm) if drive == "hub_flat"
                         else circle_loop(self.hub_radius))
            slabs.insert(0, Slab(-hub_length_mm, 0.0, Profile(hub_outer, (bore_loop,))))
        mat = spring.material.material
        names = spring.name
        dims = {"tooth tip diameter": 2 * self.tip_radius,
                "root diameter": 2 * self.root_radius,
                "contact radius r_c": self.contact_radius,
                "bore diameter": bore_diameter_mm,
                "toothed length": toothed_length_mm}
        if hub_length_mm:
            dims["hub length"] = hub_length_mm
            dims["hub diameter"] = 2 * self.hub_radius
        notes = [f"{self.n_teeth} teeth equally spaced, pocket 0 on +Y (detail C). Tooth flanks "
                 f"keep a {self.gap:g} mm gap to the flexure tips.",
                 "Bore: D bore, takes the D torque shaft (slip fit)." if bore == "d_flat" else
                 "Bore: running fit on the alignment shaft (H7/g6).",
                 "Do not round or chamfer the cut edges of the teeth; remove burrs only."]
        if hub_length_mm:
            # the blank is hardened before the EDM, so the hub is finished hard
            notes.append("Hub: finished after the heat treatment (hard turned) and before the "
                         "teeth are cut, coaxial to the bore (datum A) within "
                         f"Ø{fmt_mm(HUB_COAXIALITY_MM)} (frame in view B); its end edges "
                         "broken 0.1-0.2 mm x 45°; "
                         + ("its g6 diameter and its D flat ground (the flat drives the torque "
                            "shaft, view B). " + across_flat_check(
                                2 * self.hub_radius, flat_ratio,
                                spring.manufacturing.t_shaft_mm) if drive == "hub_flat"
                            else "torque through the D bore."))
            notes.append(f"The hub is {self.root_radius - self.hub_radius:.2f} mm inside the "
                         "tooth root at its largest size (toleranced minus only): the wire "
                         "cutting the teeth passes it.")
        notes.append(axial_location_note(hub_length_mm, drive))
        info = PartInfo(
            name=tag, code="CAM",
            title=("End camshaft" if hub_length_mm else "Camshaft") + f", {self.n_teeth} teeth",
            kind="camshaft", material=mat.description or mat.name,
            heat_treatment=mat.heat_treatment, density_kg_per_m3=mat.density_kg_per_m3,
            process="wire_edm", thickness_mm=toothed_length_mm + hub_length_mm,
            cut_profile=teeth, dimensions=dims, notes=tuple(notes), hardness=mat.hardness,
            heat_treatment_sequence=mat.heat_treatment_sequence,
            fits={"bore": "H7", **({"outer": "g6"} if drive == "hub_flat" else
                                   {"outer": f"0/-{fmt_mm(HUB_TOLERANCE_MM)}"} if hub_length_mm
                                   else {})},
            secondary_processes=(("turned", "ground") if drive == "hub_flat" else ("turned",))
            if hub_length_mm else ())
        super().__init__(info, tuple(slabs), COLOURS["cam"])

    @classmethod
    def from_plan(cls, plan: CamshaftPlan, spring) -> "Camshaft":
        """The camshaft of a stack plan, its teeth cut to ``spring`` (the plan's profile spring)."""
        return cls(spring, plan.toothed_length_mm, plan.hub_length_mm, plan.bore, plan.drive,
                   plan.bore_diameter_mm, plan.flat_ratio, plan.hub_radius_mm)

    def check_members(self, members) -> None:
        """Check that the cut tooth serves every spring the camshaft engages.

        Raises:
            GeometryError: a member has another pocket (contact radius, tip ball,
                gap or flexure count) or a larger deflection than the flank covers.
        """
        s = self.spring
        for m in members:
            same = (m.n_flexures, m.contact_radius_mm, m.tip_radius_mm, m.manufacturing.w_gap_mm) \
                == (s.n_flexures, s.contact_radius_mm, s.tip_radius_mm, s.manufacturing.w_gap_mm)
            if not same:
                raise GeometryError(
                    f"camshaft {self.name}: springs {s.name} and {m.name} share it but "
                    "differ in flexure count, contact radius, tip radius or gap; give springs "
                    "that share a camshaft the same n_flexures, contact_radius_mm and tip_radius_mm")
            if self.travel_rad < m.max_deflection_rad * (1 - 1e-9):
                raise GeometryError(
                    f"camshaft {self.name}: its teeth (cut to spring {s.name}) cover "
                    f"{self.travel_rad:.4f} rad, less than spring {m.name}'s max deflection "
                    f"{m.max_deflection_rad:.4f} rad; do not share a camshaft between these "
                    "springs, or give them the same max deflection")

    @property
    def tolerance_mm(self) -> float:
        return self.spring.manufacturing.t_shaft_mm

    @property
    def length_tolerance_mm(self) -> float:
        """Tolerance of the axial lengths (mm): the teeth are as long as the ring is thick
        (its thickness ±t_spring), so they get the camshaft's manufacturing tolerance,
        not the general one."""
        return self.spring.manufacturing.t_shaft_mm

    def describe(self, x: float, y: float) -> str:
        """Name the feature at (x, y): bore, or tooth k (mm)."""
        if math.hypot(x, y) < self.root_radius - 0.05:
            return "bore"
        return f"pocket {_sector(x, y, self.n_teeth)}"
