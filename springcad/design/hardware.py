"""Stack hardware layout: every part of a stack with its size, axial place and mass.

This is the single source of part dimensions: the CAD step builds solids from
these numbers and the design step sums their masses. Axial positions ``z_mm``
run from the input side (z = 0 at the first spring's input face).
Units: mm, kg.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

#: radial clearance between the rim spacer / washer and the flexure roots (mm)
ROOT_CLEARANCE_MM = 0.3
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
#: (material, default density kg/m^3) of the rim spacers and of the plastic parts; the
#: densities used are hardware.rim_spacer_density_kg_per_m3 / plastic_density_kg_per_m3
ALUMINIUM = ("aluminium 6061-T6", 2700.0)
PLASTIC = ("acetal (POM)", 1420.0)


@dataclass(frozen=True)
class Component:
    """One part (or a set of identical parts) of a stack.

    Attributes:
        name: unique part name, e.g. ``"camshaft_1"``.
        kind: flexure_ring, camshaft, rim_spacer, centre_spacer, rim_washer,
            bushing, alignment_shaft, fastener, rim_flange, torque_shaft.
        material: material name.
        count: number of identical parts.
        volume_mm3: volume of one part (mm^3).
        density_kg_per_m3: density (kg/m^3).
        z_mm: axial start of the part (mm).
        length_mm: axial length of the part (mm).
        dims: kind-specific dimensions (mm), e.g. inner/outer radius.
        role: "input", "output" or "" (for the parts that carry the load in or out).
        in_mass: counted in the stack mass (adapters are system parts: not counted).
    """

    name: str
    kind: str
    material: str
    count: int
    volume_mm3: float
    density_kg_per_m3: float
    z_mm: float
    length_mm: float
    dims: dict = field(default_factory=dict)
    role: str = ""
    in_mass: bool = True

    @property
    def mass_kg(self) -> float:
        return self.count * self.volume_mm3 * self.density_kg_per_m3 * 1e-9

    def to_dict(self) -> dict:
        d = asdict(self)
        d["mass_kg"] = self.mass_kg
        return d


def _ring_volume(r_in, r_out, length, holes=0, hole_d=0.0):
    return (math.pi * (r_out ** 2 - r_in ** 2) - holes * math.pi * hole_d ** 2 / 4) * length


def _torque_shaft(role, drive, cam_start, cam_end, hub_radius, shaft_diameter, hub_length,
                  steel, corner_radius_mm) -> Component:
    """Input/output torque shaft on an end camshaft (mm).

    ``drive == "bore_flat"``: a D shaft through the camshaft's D bore, sticking out
    beyond the hub. ``"hub_flat"``: a shaft whose D socket fits over the camshaft's
    D hub (the bore is taken by the alignment shaft), stopping short of the spring.
    """
    out = TORQUE_SHAFT_STICKOUT_MM
    if drive == "bore_flat":
        r = 0.5 * shaft_diameter
        # stops short of the camshaft's inner face, clear of the centre spacer
        engaged = cam_end - cam_start - SOCKET_FACE_CLEARANCE_MM
        length = engaged + out
        z = cam_start - out if role == "input" else cam_end - engaged
        dims = {"style": "d_shaft", "diameter_mm": shaft_diameter, "flat_ratio": FLAT_RATIO,
                "engaged_length_mm": engaged, "stickout_mm": out,
                "corner_radius_mm": corner_radius_mm}
        volume = math.pi * r ** 2 * length
    else:
        depth = hub_length - SOCKET_FACE_CLEARANCE_MM
        r_out = hub_radius + SOCKET_WALL_MM
        length = depth + out
        z = cam_start - out if role == "input" else cam_end - depth
        dims = {"style": "hub_socket", "outer_radius_mm": r_out, "socket_depth_mm": depth,
                "hub_radius_mm": hub_radius, "flat_ratio": FLAT_RATIO, "stickout_mm": out,
                "corner_radius_mm": corner_radius_mm}
        volume = math.pi * r_out ** 2 * length - math.pi * hub_radius ** 2 * depth
    return Component(f"{role}_torque_shaft", "torque_shaft", steel[0], 1, volume, steel[1], z,
                     length, dims, role, in_mass=False)


def stack_components(springs, joints, input_connection, output_connection) -> tuple[Component, ...]:
    """Every part of a stack, with axial positions (input side first)."""
    from springcad.design.stack import SHAFT, camshaft_indices

    hw = springs[0].hardware
    steel = (springs[0].material.material.name, springs[0].material.material.density_kg_per_m3)
    gap = hw.rim_spacer_thickness_mm
    alu = (ALUMINIUM[0], hw.rim_spacer_density_kg_per_m3)
    plastic = (PLASTIC[0], hw.plastic_density_kg_per_m3)
    n = len(springs)
    z0 = []
    z = 0.0
    for i, s in enumerate(springs):
        z0.append(z)
        z += s.thickness_mm + (gap if i < n - 1 else 0.0)
    height = z
    r_o = max(s.outer_radius_mm for s in springs)
    floating_cams = n >= 3
    comps: list[Component] = []
    for i, s in enumerate(springs):
        role = "input" if i == 0 and input_connection != SHAFT else (
            "output" if i == n - 1 and output_connection != SHAFT else "")
        comps.append(Component(
            f"spring_{i + 1}_{s.name}", "flexure_ring", steel[0], 1,
            s.profile_area_mm2 * s.thickness_mm, steel[1], z0[i], s.thickness_mm,
            {"outer_radius_mm": s.outer_radius_mm, "root_radius_mm": s.root_radius_mm,
             "spring_index": i}, role))
    cams = camshaft_indices(joints)
    for c in sorted(set(cams)):
        members = [i for i in range(n) if cams[i] == c]
        first, last = members[0], members[-1]
        start, end = z0[first], z0[last] + springs[last].thickness_mm
        # a shared camshaft is cut to the smallest member tooth (same pockets and flanks,
        # which depend on r_c and the tip ball only): it clears every member ring
        s = min((springs[i] for i in members), key=lambda sp: sp.cam_tip_radius_mm)
        role = ("input" if first == 0 and input_connection == SHAFT else
                "output" if last == n - 1 and output_connection == SHAFT else "")
        hub = hw.camshaft_hub_length_mm if role else 0.0
        # the wire cutting the pockets runs the full length: keep the turned hub inside it
        r_hub = s.cam_root_radius_mm - HUB_WIRE_CLEARANCE_MM
        bore = 0.5 * hw.shaft_diameter_mm
        vol = s.cam_area_mm2 * (end - start) + math.pi * (r_hub ** 2 - bore ** 2) * hub
        # With an alignment shaft every camshaft runs on it (round bore) and an end camshaft
        # takes its torque through a flat on its hub; otherwise the D bore takes a D shaft.
        drive = ("" if not role else "hub_flat" if floating_cams else "bore_flat")
        comps.append(Component(
            f"camshaft_{c + 1}", "camshaft", steel[0], 1, vol, steel[1],
            start - hub if role == "input" else start, end - start + hub,
            {"springs": members, "profile_spring": s.name, "toothed_start_mm": start, "toothed_end_mm": end,
             "hub_length_mm": hub, "hub_radius_mm": r_hub, "tip_radius_mm": s.cam_tip_radius_mm,
             "bore_diameter_mm": hw.shaft_diameter_mm,
             "bore": "round" if floating_cams else "d_flat", "drive": drive,
             "flat_ratio": FLAT_RATIO, "floating": not role}, role))
        if role:
            cam_start = start - hub if role == "input" else start
            cam_end = end + hub if role == "output" else end
            comps.append(_torque_shaft(role, drive, cam_start, cam_end, r_hub,
                                       hw.shaft_diameter_mm, hub, steel,
                                       springs[0].manufacturing.min_inside_radius_mm))
    fastener_len = lambda a, b: springs[a].thickness_mm + gap + springs[b].thickness_mm  # noqa: E731
    for j, kind in enumerate(joints):
        zj = z0[j] + springs[j].thickness_mm
        # clear the roots of the two springs it sits between (not the stack's largest root,
        # which would leave a sliver of material inside the holes of a thicker rim)
        r_in = max(springs[j].root_radius_mm, springs[j + 1].root_radius_mm) + ROOT_CLEARANCE_MM
        if kind == SHAFT:
            comps.append(Component(
                f"rim_washer_{j + 1}", "rim_washer", plastic[0], 1,
                _ring_volume(r_in, r_o, gap), plastic[1], zj, gap,
                {"inner_radius_mm": r_in, "outer_radius_mm": r_o, "joint": j}))
            continue
        holes = min(hw.fastener_count, springs[j].n_flexures)
        hole_d = springs[j].hole_diameter_mm
        comps.append(Component(
            f"rim_spacer_{j + 1}", "rim_spacer", alu[0], 1,
            _ring_volume(r_in, r_o, gap, holes, hole_d), alu[1], zj, gap,
            {"inner_radius_mm": r_in, "outer_radius_mm": r_o, "holes": holes,
             "hole_diameter_mm": hole_d, "joint": j}))
        r_cs = max(springs[j].cam_tip_radius_mm, springs[j + 1].cam_tip_radius_mm) \
            + CENTRE_SPACER_OVERHANG_MM
        r_cs_in = 0.5 * hw.shaft_diameter_mm if floating_cams else 0.0
        comps.append(Component(
            f"centre_spacer_{j + 1}", "centre_spacer", plastic[0], 1,
            _ring_volume(r_cs_in, r_cs, gap), plastic[1], zj, gap,
            {"inner_radius_mm": r_cs_in, "outer_radius_mm": r_cs, "joint": j}))
        if holes:
            d = hw.fastener_diameter_mm
            length = fastener_len(j, j + 1)
            comps.append(Component(
                f"{hw.fastener}s_{j + 1}", "fastener", "steel", holes,
                math.pi * d ** 2 / 4 * length, 7850.0, z0[j], length,
                {"diameter_mm": d, "length_mm": length, "type": hw.fastener,
                 "hole_circle_radius_mm": math.hypot(*springs[j].hole_centres_mm[0]),
                 "joint": j}))
    if floating_cams:
        t = hw.bushing_wall_mm
        comps.append(Component(
            "outer_bushing", "bushing", plastic[0], 1,
            _ring_volume(r_o + BUSHING_CLEARANCE_MM, r_o + BUSHING_CLEARANCE_MM + t, height),
            plastic[1], 0.0, height,
            {"inner_radius_mm": r_o + BUSHING_CLEARANCE_MM,
             "outer_radius_mm": r_o + BUSHING_CLEARANCE_MM + t}))
        r = 0.5 * hw.shaft_diameter_mm
        comps.append(Component(
            "alignment_shaft", "alignment_shaft", steel[0], 1, math.pi * r ** 2 * height,
            steel[1], 0.0, height, {"diameter_mm": hw.shaft_diameter_mm}))
    for end, conn, zf in (("input", input_connection, -FLANGE_THICKNESS_MM),
                          ("output", output_connection, height)):
        if conn == SHAFT:
            continue
        r_in = springs[0 if end == "input" else n - 1].root_radius_mm + ROOT_CLEARANCE_MM
        comps.append(Component(
            f"{end}_rim_flange", "rim_flange", steel[0], 1,
            _ring_volume(r_in, r_o, FLANGE_THICKNESS_MM), steel[1], zf, FLANGE_THICKNESS_MM,
            {"inner_radius_mm": r_in, "outer_radius_mm": r_o,
             "spring_index": 0 if end == "input" else n - 1}, end, in_mass=False))
    return tuple(comps)
