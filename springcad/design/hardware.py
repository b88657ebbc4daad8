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
ALUMINIUM = ("aluminium 6061-T6", 2700.0)
PLASTIC = ("acetal (POM)", 1420.0)


@dataclass(frozen=True)
class Component:
    """One part (or a set of identical parts) of a stack.

    Attributes:
        name: unique part name, e.g. ``"camshaft_1"``.
        kind: flexure_ring, camshaft, rim_spacer, centre_spacer, rim_washer,
            bushing, alignment_shaft, fastener, rim_flange.
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


def stack_components(springs, joints, input_connection, output_connection) -> tuple[Component, ...]:
    """Every part of a stack, with axial positions (input side first)."""
    from springcad.design.stack import SHAFT, camshaft_indices

    hw = springs[0].hardware
    steel = (springs[0].material.material.name, springs[0].material.material.density_kg_per_m3)
    gap = hw.rim_spacer_thickness_mm
    n = len(springs)
    z0 = []
    z = 0.0
    for i, s in enumerate(springs):
        z0.append(z)
        z += s.thickness_mm + (gap if i < n - 1 else 0.0)
    height = z
    r_o = max(s.outer_radius_mm for s in springs)
    r_root = max(s.root_radius_mm for s in springs)
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
        s = springs[first]
        role = ("input" if first == 0 and input_connection == SHAFT else
                "output" if last == n - 1 and output_connection == SHAFT else "")
        hub = hw.camshaft_hub_length_mm if role else 0.0
        r_hub = s.cam_root_radius_mm
        bore = 0.5 * hw.shaft_diameter_mm
        vol = s.cam_area_mm2 * (end - start) + math.pi * (r_hub ** 2 - bore ** 2) * hub
        comps.append(Component(
            f"camshaft_{c + 1}", "camshaft", steel[0], 1, vol, steel[1],
            start - hub if role == "input" else start, end - start + hub,
            {"springs": members, "toothed_start_mm": start, "toothed_end_mm": end,
             "hub_length_mm": hub, "hub_radius_mm": r_hub, "tip_radius_mm": s.cam_tip_radius_mm,
             "bore_diameter_mm": hw.shaft_diameter_mm,
             "floating": not role}, role))
    fastener_len = lambda a, b: springs[a].thickness_mm + gap + springs[b].thickness_mm  # noqa: E731
    for j, kind in enumerate(joints):
        zj = z0[j] + springs[j].thickness_mm
        r_in = r_root + ROOT_CLEARANCE_MM
        if kind == SHAFT:
            comps.append(Component(
                f"rim_washer_{j + 1}", "rim_washer", PLASTIC[0], 1,
                _ring_volume(r_in, r_o, gap), PLASTIC[1], zj, gap,
                {"inner_radius_mm": r_in, "outer_radius_mm": r_o}))
            continue
        holes = min(hw.fastener_count, springs[j].n_flexures)
        hole_d = springs[j].hole_diameter_mm
        comps.append(Component(
            f"rim_spacer_{j + 1}", "rim_spacer", ALUMINIUM[0], 1,
            _ring_volume(r_in, r_o, gap, holes, hole_d), ALUMINIUM[1], zj, gap,
            {"inner_radius_mm": r_in, "outer_radius_mm": r_o, "holes": holes,
             "hole_diameter_mm": hole_d}))
        r_cs = max(springs[j].cam_tip_radius_mm, springs[j + 1].cam_tip_radius_mm) \
            + CENTRE_SPACER_OVERHANG_MM
        r_cs_in = 0.5 * hw.shaft_diameter_mm if floating_cams else 0.0
        comps.append(Component(
            f"centre_spacer_{j + 1}", "centre_spacer", PLASTIC[0], 1,
            _ring_volume(r_cs_in, r_cs, gap), PLASTIC[1], zj, gap,
            {"inner_radius_mm": r_cs_in, "outer_radius_mm": r_cs}))
        if holes:
            d = hw.fastener_diameter_mm
            length = fastener_len(j, j + 1)
            comps.append(Component(
                f"{hw.fastener}s_{j + 1}", "fastener", "steel", holes,
                math.pi * d ** 2 / 4 * length, 7850.0, z0[j], length,
                {"diameter_mm": d, "length_mm": length, "type": hw.fastener,
                 "hole_circle_radius_mm": math.hypot(*springs[j].hole_centres_mm[0])}))
    if floating_cams:
        t = hw.bushing_wall_mm
        comps.append(Component(
            "outer_bushing", "bushing", PLASTIC[0], 1,
            _ring_volume(r_o + BUSHING_CLEARANCE_MM, r_o + BUSHING_CLEARANCE_MM + t, height),
            PLASTIC[1], 0.0, height,
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
        r_in = r_root + ROOT_CLEARANCE_MM
        comps.append(Component(
            f"{end}_rim_flange", "rim_flange", steel[0], 1,
            _ring_volume(r_in, r_o, FLANGE_THICKNESS_MM), steel[1], zf, FLANGE_THICKNESS_MM,
            {"inner_radius_mm": r_in, "outer_radius_mm": r_o}, end, in_mass=False))
    return tuple(comps)
