"""Stack hardware layout: every part of a stack with its plan, axial place and mass.

This is the single source of part dimensions: each part's numbers are a typed
plan (:mod:`springcad.design.plans`), the CAD step builds solids from the plans
and the design step sums their masses. Axial positions ``z_mm`` run from the
input side (z = 0 at the first spring's input face). The stack height and
whether the camshafts float on an alignment shaft are decided here, once.
Units: mm, kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from springcad.connections import RIM, SHAFT
from springcad.design import plans as pl
from springcad.design.cam import d_bore
from springcad.design.catalogue import bolt_set, drive_pin_length, rim_dowel_length, rim_pin_fit
from springcad.design.connections import camshaft_indices
from springcad.design.processes import process
# rim_spacer_rim_mm: the design search's rim rule (springcad.design.job) imports it from here
from springcad.design.rim_spacer import (ROOT_CLEARANCE_MM, rim_spacer_plan,  # noqa: F401
                                         rim_spacer_rim_mm)
from springcad.design.tolerance import DJoint, RimPinJoint, d_half_chord_mm
from springcad.errors import DesignError
from springcad.materials import material_table
from springcad.units import KG_PER_MM3_PER_KG_PER_M3

#: profile tolerance of the turned torque shafts (mm): their D flats are toleranced
#: one-sided by it (springcad.geometry.adapters.TorqueShaft)
TORQUE_SHAFT_TOLERANCE_MM = 0.02
#: radial clearance of the plastic bushing over the rims (mm)
BUSHING_CLEARANCE_MM = 0.05
#: centre spacer overhang beyond the cam teeth (mm)
CENTRE_SPACER_OVERHANG_MM = 0.5
#: thickness of an input/output rim flange adapter (mm)
FLANGE_THICKNESS_MM = 3.0
#: how far an input/output torque shaft sticks out beyond its camshaft (mm)
TORQUE_SHAFT_STICKOUT_MM = 10.0
#: radial wall of a torque-shaft socket over a camshaft hub (mm)
SOCKET_WALL_MM = 2.0
#: axial clearance between a torque shaft's inner end and the spring face / spacer (mm)
SOCKET_FACE_CLEARANCE_MM = 0.5
#: camshaft hub radius below the cam root radius, so the EDM wire clears the hub (mm)
HUB_WIRE_CLEARANCE_MM = 0.1
#: drive flat on a D bore or a D hub, as a fraction of its radius (-)
FLAT_RATIO = 0.8
#: stacks of this many springs or more float their middle camshafts on an alignment shaft
#: inside an outer bushing (paper Section II-A)
FLOATING_FROM_SPRINGS = 3
#: axial clearance between a bolt's head or nut (or its screw's end) and the rim washer
#: that turns against it at a shaft-to-shaft joint (mm)
BOLT_END_CLEARANCE_MM = 0.3
#: rim-spacer stock, a name in springcad/data/materials.csv: stainless shim strip, stocked
#: as thin as the spacer gap (6061-T6 is not stocked below ~0.8 mm: the table's source)
RIM_SPACER_MATERIAL = "301_shim"
#: (material, default density kg/m^3) of the plastic parts; the densities used are
#: hardware.rim_spacer_density_kg_per_m3 / plastic_density_kg_per_m3
PLASTIC = ("acetal copolymer POM-C, unfilled, natural", 1420.0)
FASTENER_STEEL = ("steel", 7850.0)


@dataclass(frozen=True)
class Component:
    """One part (or a set of identical parts) of a stack.

    Attributes:
        name: unique part name, e.g. ``"camshaft_1"``.
        plan: the part's typed plan (its kind and sizes).
        material: material name.
        count: number of identical parts.
        volume_mm3: volume of one part (mm^3).
        density_kg_per_m3: density (kg/m^3).
        z_mm: axial start of the part (mm).
        length_mm: axial length of the part (mm).
        role: "input", "output" or "" (for the parts that carry the load in or out).
        in_mass: counted in the stack mass (adapters are system parts: not counted).
    """

    name: str
    plan: pl.PartPlan
    material: str
    count: int
    volume_mm3: float
    density_kg_per_m3: float
    z_mm: float
    length_mm: float
    role: str = ""
    in_mass: bool = True

    @property
    def kind(self) -> str:
        """flexure_ring, camshaft, rim_spacer, centre_spacer, rim_washer, bushing,
        alignment_shaft, fastener, rim_flange or torque_shaft."""
        return self.plan.KIND

    @property
    def mass_kg(self) -> float:
        return self.count * self.volume_mm3 * self.density_kg_per_m3 * KG_PER_MM3_PER_KG_PER_M3

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": self.kind, "material": self.material,
                "count": self.count, "volume_mm3": self.volume_mm3,
                "density_kg_per_m3": self.density_kg_per_m3, "z_mm": self.z_mm,
                "length_mm": self.length_mm, "dims": self.plan.to_dict(), "role": self.role,
                "in_mass": self.in_mass, "mass_kg": self.mass_kg}


def bolt_circle_limit_mm(hardware, n_springs: int, outer_radius_mm: float) -> float:
    """Largest rim-hole circle radius (mm) for a stack's fasteners.

    In a stack that floats inside an outer bushing (:data:`FLOATING_FROM_SPRINGS` or
    more springs), a bolt's head and nut turn with its rims against the bushing: their
    circles (the ISO 4762 head, the ISO 4032 nut through its corners) stay inside the
    rims' outer radius ``outer_radius_mm``. Dowels are flush: no limit (inf).
    """
    if (hardware.fastener != "bolt" or hardware.fastener_count == 0
            or n_springs < FLOATING_FROM_SPRINGS):
        return math.inf
    b = bolt_set(hardware.fastener_diameter_mm)
    return outer_radius_mm - 0.5 * max(b.head_diameter_mm, b.nut_across_corners_mm)




def _camshaft_volume_mm3(spring, toothed_mm: float, hub_mm: float, hub_radius_mm: float,
                         bore_diameter_mm: float, round_bore: bool, d_hub: bool) -> float:
    """Volume (mm^3) of a camshaft as built (:class:`~springcad.geometry.disk.Camshaft`):
    the spring's tooth profile over the toothed length and the hub, a D (its flat drives
    the torque shaft) or round, less the bore, the spring's D bore or a round one on the
    alignment shaft. ``spring.cam_area_mm2`` is the tooth profile less the spring's D bore
    (a synthesis screening's stand-in without a profile: less a round bore)."""
    corner = spring.manufacturing.min_inside_radius_mm
    round_area = math.pi * (0.5 * bore_diameter_mm) ** 2
    d_area = abs(d_bore(0.5 * bore_diameter_mm, FLAT_RATIO, corner).signed_area())
    cam = getattr(spring, "cam", None)
    teeth = spring.cam_area_mm2 + (abs(cam.loop("bore").signed_area()) if cam is not None
                                   else round_area)
    bore = round_area if round_bore else d_area
    hub = (abs(d_bore(hub_radius_mm, FLAT_RATIO, corner).signed_area()) if d_hub
           else math.pi * hub_radius_mm ** 2)
    return (teeth - bore) * toothed_mm + (hub - bore) * hub_mm




@dataclass(frozen=True)
class StackLayout:
    """Every part of a stack and the numbers the layout decides once.

    Attributes:
        components: the parts, input side first.
        spring_z_mm: axial start of each spring (mm).
        height_mm: first spring's input face to the last spring's output face (mm).
        floating_camshafts: the middle camshafts float on an alignment shaft inside an
            outer bushing (three or more springs).
        envelope_radius_mm: outer radius of the stack, bushing included (mm).
    """

    components: tuple[Component, ...]
    spring_z_mm: tuple[float, ...]
    height_mm: float
    floating_camshafts: bool
    envelope_radius_mm: float


def _annulus_volume(plan: pl.AnnulusPlan, length_mm: float) -> float:
    holes = plan.holes * math.pi * plan.hole_diameter_mm ** 2 / 4
    return (math.pi * (plan.outer_radius_mm ** 2 - plan.inner_radius_mm ** 2) - holes) * length_mm


def _annular(name, plan: pl.AnnulusPlan, material, z_mm, length_mm, role="", in_mass=True):
    return Component(name, plan, material[0], 1, _annulus_volume(plan, length_mm), material[1],
                     z_mm, length_mm, role, in_mass)


class _Layout:
    """The running state of one layout: springs, their places, the common numbers."""

    def __init__(self, springs, joints, input_connection, output_connection):
        self.springs = springs
        self.joints = joints
        self.input, self.output = input_connection, output_connection
        self.hw = springs[0].hardware
        mat = springs[0].material.material
        self.steel = (mat.name, mat.density_kg_per_m3)
        self.gap = self.hw.rim_spacer_thickness_mm
        n = len(springs)
        #: per joint: (axial gap between the two rims, washer offset from the first rim) (mm)
        self.joint_gaps = [self._joint_gap(j) for j in range(n - 1)]
        z, z0 = 0.0, []
        for i, s in enumerate(springs):
            z0.append(z)
            z += s.thickness_mm + (self.joint_gaps[i][0] if i < n - 1 else 0.0)
        self.z0, self.height = tuple(z0), z
        self.r_outer = max(s.outer_radius_mm for s in springs)
        self.floating = n >= FLOATING_FROM_SPRINGS

    def _bolted(self, j: int) -> bool:
        """Rim joint j (0 <= j < n - 1) is clamped by through bolts; j = -1 (n - 1): the
        input (output) rim flange is bolted to spring 0 (n - 1)."""
        n = len(self.springs)
        if self.hw.fastener != "bolt":
            return False
        if j == -1 or j == n - 1:
            end = self.input if j == -1 else self.output
            return end == RIM and bool(self.springs[max(j, 0)].hole_centres_mm)
        return (0 <= j < len(self.joints) and self.joints[j] == RIM
                and bool(self.springs[j].hole_centres_mm))

    def _thickness(self, i: int) -> float:
        """Thickness of spring i, or of the rim flange beyond either end (mm)."""
        return (self.springs[i].thickness_mm if 0 <= i < len(self.springs)
                else FLANGE_THICKNESS_MM)

    def _joint_gap(self, j: int) -> tuple[float, float]:
        """(axial gap, washer offset) of joint j (mm).

        A rim joint and a plain shaft joint keep ``rim_spacer_thickness_mm`` between the
        rims. A bolt's head and nut stand proud of the rims it clamps
        (:func:`springcad.design.fastener_room.fastener_pieces`): at a shaft-to-shaft
        joint next to a bolted rim joint, the nuts (or screw ends) of the pair below and
        the heads of the pair above turn against each other, so the gap holds both with
        the rim washer between them and :data:`BOLT_END_CLEARANCE_MM` on each side.
        """
        washer = self.gap
        if self.joints[j] != SHAFT:
            return washer, 0.0
        below = above = 0.0
        if self._bolted(j - 1):
            b = bolt_set(self.hw.fastener_diameter_mm)
            # a flange (j - 1 = -1) sits on its ring with no gap
            grip = (self._thickness(j - 1) + (self.gap if j > 0 else 0.0)
                    + self.springs[j].thickness_mm)
            below = max(b.nut_height_mm, b.screw_length_mm(grip) - grip)
        if self._bolted(j + 1):
            above = bolt_set(self.hw.fastener_diameter_mm).head_height_mm
        if below == above == 0.0:
            return washer, 0.0
        lo = below + BOLT_END_CLEARANCE_MM if below else 0.0
        hi = above + BOLT_END_CLEARANCE_MM if above else 0.0
        return lo + washer + hi, lo

    def end_z(self, i: int) -> float:
        return self.z0[i] + self.springs[i].thickness_mm

    def rings(self) -> list[Component]:
        n = len(self.springs)
        out = []
        for i, s in enumerate(self.springs):
            role = ("input" if i == 0 and self.input != SHAFT else
                    "output" if i == n - 1 and self.output != SHAFT else "")
            plan = pl.FlexureRingPlan(spring_index=i, outer_radius_mm=s.outer_radius_mm,
                                      root_radius_mm=s.root_radius_mm)
            out.append(Component(f"spring_{i + 1}_{s.name}", plan, self.steel[0], 1,
                                 s.profile_area_mm2 * s.thickness_mm, self.steel[1], self.z0[i],
                                 s.thickness_mm, role))
        return out

    def camshafts(self) -> list[Component]:
        """Camshafts (springs joined shaft-to-shaft share one) and the end torque shafts."""
        springs, hw, n = self.springs, self.hw, len(self.springs)
        cams = camshaft_indices(self.joints)
        out = []
        for c in sorted(set(cams)):
            members = tuple(i for i in range(n) if cams[i] == c)
            first, last = members[0], members[-1]
            start, end = self.z0[first], self.end_z(last)
            # a shared camshaft is cut to the smallest member tooth (same pockets and flanks,
            # which depend on r_c and the tip ball only): it clears every member ring
            s = min((springs[i] for i in members), key=lambda sp: sp.cam_tip_radius_mm)
            role = ("input" if first == 0 and self.input == SHAFT else
                    "output" if last == n - 1 and self.output == SHAFT else "")
            hub = hw.camshaft_hub_length_mm if role else 0.0
            # the wire cutting the pockets runs the full length: keep the turned hub inside it
            r_hub = s.cam_root_radius_mm - HUB_WIRE_CLEARANCE_MM
            # With an alignment shaft every camshaft runs on it (round bore) and an end
            # camshaft takes its torque through a flat on its hub; otherwise the D bore
            # takes a D shaft.
            drive = "" if not role else "hub_flat" if self.floating else "bore_flat"
            vol = _camshaft_volume_mm3(s, end - start, hub, r_hub, hw.shaft_diameter_mm,
                                       self.floating, drive == "hub_flat")
            plan = pl.CamshaftPlan(
                springs=members, profile_spring=s.name, toothed_start_mm=start,
                toothed_end_mm=end, hub_length_mm=hub, hub_radius_mm=r_hub,
                tip_radius_mm=s.cam_tip_radius_mm, bore_diameter_mm=hw.shaft_diameter_mm,
                bore="round" if self.floating else "d_flat", drive=drive, flat_ratio=FLAT_RATIO)
            out.append(Component(f"camshaft_{c + 1}", plan, self.steel[0], 1, vol, self.steel[1],
                                 start - hub if role == "input" else start, end - start + hub,
                                 role))
            if role:
                out.append(self._torque_shaft(role, plan))
        return out

    def _torque_shaft(self, role: str, cam: pl.CamshaftPlan) -> Component:
        """Input/output torque shaft on an end camshaft (mm).

        ``drive == "bore_flat"``: a D shaft through the camshaft's D bore, sticking out
        beyond the hub. ``"hub_flat"``: a shaft whose D socket fits over the camshaft's
        D hub (the bore is taken by the alignment shaft), stopping short of the spring.
        """
        out_mm = TORQUE_SHAFT_STICKOUT_MM
        hub = cam.hub_length_mm
        cam_start = cam.toothed_start_mm - (hub if role == "input" else 0.0)
        cam_end = cam.toothed_end_mm + (hub if role == "output" else 0.0)
        corner = self.springs[0].manufacturing.min_inside_radius_mm
        if cam.drive == "bore_flat":
            r = 0.5 * cam.bore_diameter_mm
            # stops short of the camshaft's inner face, clear of the centre spacer
            inside = cam_end - cam_start - SOCKET_FACE_CLEARANCE_MM
            plan = pl.DShaftPlan(diameter_mm=cam.bore_diameter_mm, flat_ratio=FLAT_RATIO,
                                 engaged_length_mm=inside, stickout_mm=out_mm,
                                 corner_radius_mm=corner)
            # the D section, as the part is made (design.json and the BOM agree)
            volume = abs(d_bore(r, FLAT_RATIO, corner).signed_area()) * (inside + out_mm)
        else:
            inside = hub - SOCKET_FACE_CLEARANCE_MM
            r_out = cam.hub_radius_mm + SOCKET_WALL_MM
            plan = pl.HubSocketPlan(outer_radius_mm=r_out, socket_depth_mm=inside,
                                    hub_radius_mm=cam.hub_radius_mm, flat_ratio=FLAT_RATIO,
                                    stickout_mm=out_mm, corner_radius_mm=corner)
            socket = abs(d_bore(cam.hub_radius_mm, FLAT_RATIO, corner).signed_area())
            volume = math.pi * r_out ** 2 * (inside + out_mm) - socket * inside
        z = cam_start - out_mm if role == "input" else cam_end - inside
        return Component(f"{role}_torque_shaft", plan, self.steel[0], 1, volume, self.steel[1], z,
                         inside + out_mm, role, in_mass=False)

    def joint_parts(self, j: int, kind: str) -> list[Component]:
        """What sits between springs j and j + 1: a washer, or a spacer, a centre spacer and pins."""
        springs, hw, gap = self.springs, self.hw, self.gap
        zj = self.end_z(j)
        # clear the roots of the two springs it sits between (not the stack's largest root,
        # which would leave a sliver of material inside the holes of a thicker rim)
        r_in = max(springs[j].root_radius_mm, springs[j + 1].root_radius_mm) + ROOT_CLEARANCE_MM
        if kind == SHAFT:
            plan = pl.RimWasherPlan(inner_radius_mm=r_in, outer_radius_mm=self.r_outer, joint=j)
            return [_annular(f"rim_washer_{j + 1}", plan, self.plastic,
                             zj + self.joint_gaps[j][1], gap)]
        centres = springs[j].hole_centres_mm
        spacer = self.rim_spacer(j, centres)
        r_cs = max(springs[j].cam_tip_radius_mm, springs[j + 1].cam_tip_radius_mm) \
            + CENTRE_SPACER_OVERHANG_MM
        centre = pl.CentreSpacerPlan(
            inner_radius_mm=0.5 * hw.shaft_diameter_mm if self.floating else 0.0,
            outer_radius_mm=r_cs, joint=j)
        out = [_annular(f"rim_spacer_{j + 1}", spacer, self.rim_spacer_material, zj, gap),
               _annular(f"centre_spacer_{j + 1}", centre, self.plastic, zj, gap)]
        if centres:
            out.append(self.pins(f"{hw.fastener}s_{j + 1}", j, springs[j].thickness_mm, gap,
                                 springs[j + 1].thickness_mm, self.z0[j], centres))
        return out

    def pins(self, name: str, j: int, lower_mm: float, gap_mm: float, upper_mm: float,
             z_mm: float, centres, in_mass: bool = True) -> Component:
        """The fasteners of joint ``j`` through two plates ``lower_mm`` and ``upper_mm`` thick
        with ``gap_mm`` between them, the lower one starting at ``z_mm`` (mm): dowels of a
        catalogue length centred in the two, or bolts whose head is below the lower plate.
        ``j`` is -1 for the input rim flange on spring 0 and n - 1 for the output flange
        (system parts like the flanges: ``in_mass`` False)."""
        hw = self.hw
        d = hw.fastener_diameter_mm
        grip = lower_mm + gap_mm + upper_mm
        length, z = grip, z_mm
        if hw.fastener == "dowel":  # a catalogue length, centred in the two
            length = rim_dowel_length(d, lower_mm, gap_mm, upper_mm)
            z += 0.5 * (grip - length)
        plan = pl.FastenerPlan(type=hw.fastener, diameter_mm=d, length_mm=length,
                               hole_centres_mm=centres, joint=j)
        return Component(name, plan, FASTENER_STEEL[0], len(centres),
                         math.pi * d ** 2 / 4 * length, FASTENER_STEEL[1], z, length,
                         in_mass=in_mass)

    def rim_spacer(self, j: int, centres) -> pl.RimSpacerPlan:
        """The rim spacer of joint j: process, holes and inner edge from
        :func:`~springcad.design.rim_spacer.rim_spacer_fit` (a plain ring when the rims have
        no holes)."""
        return rim_spacer_plan(self.springs[j], self.springs[j + 1], self.r_outer, self.gap,
                               j, centres)

    @property
    def rim_spacer_material(self) -> tuple[str, float]:
        """Rim-spacer material (the table's description of :data:`RIM_SPACER_MATERIAL`) and
        density (kg/m^3) from the hardware config."""
        return (material_table()[RIM_SPACER_MATERIAL].description,
                self.hw.rim_spacer_density_kg_per_m3)

    @property
    def plastic(self) -> tuple[str, float]:
        """Washer, centre-spacer and bushing material and density (kg/m^3) from the hardware config."""
        return PLASTIC[0], self.hw.plastic_density_kg_per_m3

    def alignment_parts(self) -> list[Component]:
        """Outer bushing and alignment shaft of a stack whose camshafts float."""
        if not self.floating:
            return []
        r_in = self.r_outer + BUSHING_CLEARANCE_MM
        bushing = pl.BushingPlan(inner_radius_mm=r_in,
                                 outer_radius_mm=r_in + self.hw.bushing_wall_mm)
        d = self.hw.shaft_diameter_mm
        shaft = Component("alignment_shaft", pl.AlignmentShaftPlan(diameter_mm=d), self.steel[0],
                          1, math.pi * d ** 2 / 4 * self.height, self.steel[1], 0.0, self.height)
        return [_annular("outer_bushing", bushing, self.plastic, 0.0, self.height), shaft]

    def flanges(self) -> list[Component]:
        """Rim flange adapters at the ends that take their torque through a rim."""
        n = len(self.springs)
        out = []
        for end, conn, i, z in (("input", self.input, 0, -FLANGE_THICKNESS_MM),
                                ("output", self.output, n - 1, self.height)):
            if conn == SHAFT:
                continue
            s = self.springs[i]
            r_in = s.root_radius_mm + ROOT_CLEARANCE_MM
            if s.hole_centres_mm:  # keep the wire-EDM hole-edge web inside the rim holes
                r_hc = min(math.hypot(*c) for c in s.hole_centres_mm)
                web_edge = r_hc - 0.5 * s.hole_diameter_mm - s.manufacturing.min_hole_edge_mm
                # never inside the roots (a rim too narrow for its holes is the spring's
                # own plausibility error)
                r_in = max(s.root_radius_mm, min(r_in, web_edge))
            plan = pl.RimFlangePlan(inner_radius_mm=r_in,
                                    outer_radius_mm=self.r_outer, hole_centres_mm=s.hole_centres_mm,
                                    hole_diameter_mm=s.hole_diameter_mm, spring_index=i)
            out.append(_annular(f"{end}_rim_flange", plan, self.steel, z, FLANGE_THICKNESS_MM,
                                end, in_mass=False))
            if s.hole_centres_mm:  # the flange is pinned (or bolted) to its ring's rim
                out.append(self.flange_pins(end, i, z))
        return out

    def flange_pins(self, end: str, i: int, z_flange_mm: float) -> Component:
        """The fasteners of a rim flange on spring i (system parts: not in the mass).

        Dowels are drive pins (:func:`~springcad.design.catalogue.drive_pin_length`): in
        the ring, at least its length tolerance short of the ring's far face (a washer or a
        spring turns against that face), through the flange and proud of its outer face by
        at least the engagement the user's drive part needs. Bolts: head on the flange's
        outer face, nut on the ring's far face (:meth:`_joint_gap` makes room for it)."""
        s, n, f = self.springs[i], len(self.springs), FLANGE_THICKNESS_MM
        j, name = (-1 if end == "input" else n - 1), f"{self.hw.fastener}s_{end}_flange"
        if self.hw.fastener != "dowel":
            lower, upper, z_lo = ((f, s.thickness_mm, z_flange_mm) if end == "input"
                                  else (s.thickness_mm, f, self.z0[i]))
            return self.pins(name, j, lower, 0.0, upper, z_lo, s.hole_centres_mm,
                             in_mass=False)
        d = self.hw.fastener_diameter_mm
        length, in_ring = drive_pin_length(d, s.thickness_mm, f)
        # input: the ring's far face is its output face (z0 + t); output: its input face
        z = (self.z0[i] + in_ring - length if end == "input"
             else self.z0[i] + s.thickness_mm - in_ring)
        plan = pl.FastenerPlan(type="dowel", diameter_mm=d, length_mm=length,
                               hole_centres_mm=s.hole_centres_mm, joint=j)
        return Component(name, plan, FASTENER_STEEL[0], len(s.hole_centres_mm),
                         math.pi * d ** 2 / 4 * length, FASTENER_STEEL[1], z, length,
                         in_mass=False)


def d_joints(layout: StackLayout, t_camshaft_mm: float) -> tuple:
    """The joints of a stack that add rotational play in series with the cam interfaces:
    each torque shaft on its end camshaft (:class:`~springcad.design.tolerance.DJoint`: a
    D shaft in the camshaft's D bore, or a D socket over its D hub), flats toleranced
    one-sided by the camshaft's ``t_camshaft_mm`` and :data:`TORQUE_SHAFT_TOLERANCE_MM`
    (mm); and each dowelled rim-to-rim joint
    (:class:`~springcad.design.tolerance.RimPinJoint`: m6 pins in E7 holes)."""
    out = []
    for c in layout.components:
        plan = c.plan
        if isinstance(plan, pl.DShaftPlan):  # the shaft is inside, the camshaft's bore outside
            h = d_half_chord_mm(0.5 * plan.diameter_mm, plan.flat_ratio, plan.corner_radius_mm)
            out.append(DJoint(h, t_camshaft_mm, TORQUE_SHAFT_TOLERANCE_MM, c.name))
        elif isinstance(plan, pl.HubSocketPlan):  # the camshaft's hub inside the socket
            h = d_half_chord_mm(plan.hub_radius_mm, plan.flat_ratio, plan.corner_radius_mm)
            out.append(DJoint(h, TORQUE_SHAFT_TOLERANCE_MM, t_camshaft_mm, c.name))
        elif isinstance(plan, pl.FastenerPlan) and plan.type == "dowel" and plan.hole_centres_mm:
            fit = rim_pin_fit(plan.diameter_mm, process("wire_edm").pattern_zone)
            if not fit.cannot_jam:
                raise DesignError(
                    f"{c.name}: the E7/m6 slip fit leaves {fit.clearance_min_mm:g} mm, less than "
                    f"the {fit.mismatch_mm:g} mm two rims' hole patterns may be apart: the "
                    "pins could jam (processes.toml wire_edm pattern_zone_mm)")
            out.append(RimPinJoint(plan.hole_circle_radius_mm, fit.clearance_min_mm,
                                   fit.clearance_max_mm, c.name))
    return tuple(out)


def stack_layout(springs, joints, input_connection: str, output_connection: str) -> StackLayout:
    """Every part of a stack, with axial positions (input side first).

    Args:
        springs: the :class:`~springcad.design.spring.SpringDesign` of each position.
        joints: ``joints[i]`` joins springs i and i + 1 ("rim" or "shaft").
        input_connection, output_connection: "rim" or "shaft".
    """
    lay = _Layout(springs, joints, input_connection, output_connection)
    comps = lay.rings() + lay.camshafts()
    for j, kind in enumerate(joints):
        comps += lay.joint_parts(j, kind)
    comps += lay.alignment_parts() + lay.flanges()
    envelope = lay.r_outer + (BUSHING_CLEARANCE_MM + lay.hw.bushing_wall_mm if lay.floating else 0.0)
    return StackLayout(tuple(comps), lay.z0, lay.height, lay.floating, envelope)
