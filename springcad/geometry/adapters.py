"""Shafts and adapters: the internal alignment shaft, torque shafts and rim flanges.

Part frames follow the *input* orientation: the end that meets the springs is
at the top (+z); output instances are the same parts turned over. Units: mm.
"""

from __future__ import annotations

from springcad.design.curves import Profile
from springcad.design.hardware import TORQUE_SHAFT_TOLERANCE_MM
from springcad.design.plans import DShaftPlan, HubSocketPlan, TorqueShaftPlan
from springcad.errors import GeometryError
from springcad.geometry.base import (COLOURS, PartInfo, Slab, SpringcadPart, across_flat_check,
                                     circle_loop, d_loop)
from springcad.geometry.spacers import AnnularPart


class AlignmentShaft(AnnularPart):
    """Ground pin on which the floating camshafts run (stacks of three or more)."""

    KIND, TITLE, PROCESS, COLOUR = "alignment_shaft", "Alignment shaft", "turned", "cam"
    CODE = "ALIGNMENT-SHAFT"
    FITS = {"outer": "g6"}
    SECONDARY = ("ground",)
    NOTES = ("Ground to g6 after hardening; the camshaft bores and centre spacers run on it; "
             "chamfer 0.2 x 45° both ends.",)


class RimFlange(AnnularPart):
    """Input/output adapter bolted to a stack-end rim (torque through the rim)."""

    KIND, TITLE, PROCESS, COLOUR, SHEET = "rim_flange", "Rim flange", "wire_edm", "steel", True
    CODE = "RIM-FLANGE"
    NOTES = ("Holes match the flexure-ring rim holes (same pattern, same fit).",)

    def part_notes(self) -> tuple[str, ...]:
        """How torque gets in and out: drive pins (a dowelled stack) or the rim bolts."""
        if "dowel" in self.hole_purpose:
            how = ("Torque path: the drive pins (BOM, ISO 8734, bonded like the rim dowels) "
                   "pass these holes into the end ring's rim, stopping short of its far face, "
                   "and stand proud of this flange's face away from the ring; the user's "
                   "drive part takes them in holes of this pattern and fit. Holding the "
                   "stack along the axis is left to the user.")
        else:
            how = ("Torque path: the rim bolts (BOM) clamp this flange to the end ring's rim, "
                   "heads on this flange's face away from the ring; the user's drive part "
                   "bears on that face and its outer diameter. Holding the stack along the "
                   "axis is left to the user.")
        return (*self.NOTES, how)


#: a socket torque shaft is hardened between turning and the sinker EDM of its socket
SOCKET_HEAT_TREATMENT_SEQUENCE = "after turning, before the sinker EDM of the socket"


class TorqueShaft(SpringcadPart):
    """Input/output torque shaft on an end camshaft.

    Styles (the plan's class): :class:`~springcad.design.plans.DShaftPlan`, a D
    shaft that fills the camshaft's D bore and sticks out beyond the hub;
    :class:`~springcad.design.plans.HubSocketPlan`, a shaft whose D socket fits
    over the camshaft's D hub (the bore is then taken by the alignment shaft).

    Args:
        name: job-local label (the part number is made from the geometry).
        plan: the torque shaft's plan.
        length_mm: overall length (mm).
        material: (name, density kg/m^3).
        heat_treatment: as written on the drawing.
    """

    def __init__(self, name: str, plan: TorqueShaftPlan, length_mm: float,
                 material: tuple[str, float], heat_treatment: str = "", hardness: str = "",
                 heat_treatment_sequence: str = ""):
        self.style = plan.STYLE
        self.length = length_mm
        self.flat_ratio = plan.flat_ratio
        self.stickout = plan.stickout_mm
        if isinstance(plan, DShaftPlan):
            self.diameter = plan.diameter_mm
            slabs = (Slab(0.0, length_mm,
                          Profile(d_loop(0.5 * self.diameter, self.flat_ratio,
                                         plan.corner_radius_mm))),)
            key = {"shaft diameter": self.diameter, "length": length_mm,
                   "engaged length": plan.engaged_length_mm}
            note = ("D flat matches the camshaft bore (slip fit): ground after hardening, "
                    "like the g6 diameter; chamfer 0.2 x 45° at the inner end (lead into the "
                    f"bore). {across_flat_check(self.diameter, self.flat_ratio, TORQUE_SHAFT_TOLERANCE_MM)}")
            fits = {"outer": "g6"}
            secondary = ("ground",)
            retention = ("Coupling to the drive, and holding the camshaft along the axis (it "
                         "slides on this shaft), are left to the user.")
        elif isinstance(plan, HubSocketPlan):
            self.outer_radius = plan.outer_radius_mm
            self.socket_depth = plan.socket_depth_mm
            hub = d_loop(plan.hub_radius_mm, self.flat_ratio, plan.corner_radius_mm)
            slabs = (Slab(0.0, self.stickout, Profile(circle_loop(self.outer_radius))),
                     Slab(self.stickout, length_mm,
                          Profile(circle_loop(self.outer_radius), (hub,))))
            key = {"outer diameter": 2 * self.outer_radius, "length": length_mm,
                   "socket depth": self.socket_depth,
                   "socket diameter": 2 * plan.hub_radius_mm}
            note = (f"D socket (blind, {self.socket_depth:.4g} deep, corners "
                    f"R{plan.corner_radius_mm:g}): sinker EDM after hardening with a D "
                    "electrode (cannot be turned, ground or wire cut); H7 on the round part, "
                    "flat toleranced as drawn; 0.2 x 45° chamfer at the mouth. Bottom: flat, "
                    "square to the axis within 0.02 mm (it bears on the camshaft hub's end "
                    "face), bottom corners R0.1 max (the hub's end edge is broken 0.1-0.2 "
                    "mm).")
            fits = {"bore": "H7"}
            # nothing on it is ground: the H7 socket is finished by the sinker EDM, the
            # outside is a plain turned diameter
            secondary = ("sinker_edm",)
            heat_treatment_sequence = SOCKET_HEAT_TREATMENT_SEQUENCE
            retention = ("Coupling to the drive is left to the user, who holds this shaft "
                         "along the axis: the socket bottom holds the camshaft's hub.")
        else:
            raise GeometryError(f"{name}: no torque shaft of style "
                                f"{type(plan).__name__}; use a D shaft or a hub socket")
        info = PartInfo(name=name, code="TORQUE-SHAFT", title="Torque shaft", kind="torque_shaft",
                        material=material[0], heat_treatment=heat_treatment,
                        density_kg_per_m3=material[1], process="turned",
                        thickness_mm=length_mm, dimensions=key, hardness=hardness,
                        heat_treatment_sequence=heat_treatment_sequence, fits=fits,
                        notes=(note, retention),
                        secondary_processes=secondary)
        super().__init__(info, slabs, COLOURS["steel"])

    @property
    def tolerance_mm(self) -> float:
        return TORQUE_SHAFT_TOLERANCE_MM
