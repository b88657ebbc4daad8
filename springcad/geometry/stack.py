"""Assemble a designed stack into placed, named, coloured parts.

Every solid is built from the stack's :class:`~springcad.design.hardware.Component`
list (the single source of sizes and axial places). Identical parts are built
once and placed several times (four S1 rings are one part, quantity 4). An end
camshaft or torque shaft on the output side is the input part turned over.
Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from springcad.design.hardware import Component
from springcad.errors import GeometryError
from springcad.geometry.base import COLOURS, SpringcadPart


@dataclass(frozen=True)
class Placement:
    """Where a part sits in the stack: optional turn-over, rotation about z, translation.

    A point p of the part frame goes to T + Rz(angle) F p, where F = diag(-1, 1, -1)
    (half a turn about y) when ``flipped`` and T = (x, y, z).
    """

    z_mm: float
    x_mm: float = 0.0
    y_mm: float = 0.0
    flipped: bool = False
    angle_rad: float = 0.0

    def location(self):
        from build123d import Location, Rot

        loc = Location((self.x_mm, self.y_mm, self.z_mm)) * Rot(0, 0, math.degrees(self.angle_rad))
        return loc * Rot(0, 180, 0) if self.flipped else loc

    def map_xy(self, pts: np.ndarray) -> np.ndarray:
        """Part-frame (n, 2) points to stack coordinates (mm)."""
        p = np.asarray(pts, dtype=float)
        if self.flipped:
            p = p * np.array([-1.0, 1.0])
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        return p @ np.array([[c, s], [-s, c]]) + np.array([self.x_mm, self.y_mm])

    def map_z(self, z0: float, z1: float) -> tuple[float, float]:
        """Part-frame axial interval to stack coordinates (mm)."""
        if self.flipped:
            return self.z_mm - z1, self.z_mm - z0
        return self.z_mm + z0, self.z_mm + z1


@dataclass
class Instance:
    """One placed part of the stack.

    Attributes:
        name: unique instance name (the Component name, with ``_k`` for sets).
        part: the part.
        placement: where it sits.
        component: the Component it was built from.
        role: "input", "output" or "".
        colour: RGB (0-1) for renders and the assembly STEP.
    """

    name: str
    part: SpringcadPart
    placement: Placement
    component: Component
    role: str = ""
    colour: tuple = ()
    _shape: object = field(default=None, repr=False)
    _face_boxes: object = field(default=None, repr=False)

    @property
    def shape(self):
        """The part's solid moved into place (cached)."""
        if self._shape is None:
            self._shape = self.part.solid.moved(self.placement.location())
        return self._shape

    @property
    def z_range_mm(self) -> tuple[float, float]:
        z0, z1 = self.part.z_range_mm
        return self.placement.map_z(z0, z1)


@dataclass
class StackAssembly:
    """The placed parts of a stack, which of them carry the input and the output.

    Attributes:
        design: the :class:`~springcad.design.job.JobDesign` it was built from.
        instances: placed parts, input side first.
        parts: distinct parts by part number.
    """

    design: object
    instances: list[Instance]
    parts: dict[str, SpringcadPart]

    @property
    def input_names(self) -> list[str]:
        return [i.name for i in self.instances if i.role == "input"]

    @property
    def output_names(self) -> list[str]:
        return [i.name for i in self.instances if i.role == "output"]

    def quantities(self) -> dict[str, int]:
        """Number of placed instances of each part number."""
        out: dict[str, int] = {}
        for inst in self.instances:
            out[inst.part.part_number] = out.get(inst.part.part_number, 0) + 1
        return out

    def instance(self, name: str) -> Instance:
        for inst in self.instances:
            if inst.name == name:
                return inst
        raise KeyError(name)

    def compound(self):
        """A build123d Compound whose children are the named, coloured instances."""
        from build123d import Color, Compound

        children = []
        for inst in self.instances:
            shape = inst.shape
            shape.label = inst.name
            shape.color = Color(*inst.colour)
            children.append(shape)
        return Compound(children=children, label=self.design.job.name)


class _PartCache:
    """Builds each distinct part once; numbers parts of one kind PREFIX, PREFIX-2, ..."""

    def __init__(self, progress):
        self.parts: dict[tuple, SpringcadPart] = {}
        self.by_number: dict[str, SpringcadPart] = {}
        self.count: dict[str, int] = {}
        self.progress = progress

    def get(self, key: tuple, make, prefix: str | None = None):
        if key not in self.parts:
            number = None
            if prefix is not None:
                k = self.count.get(prefix, 0) + 1
                self.count[prefix] = k
                number = prefix if k == 1 else f"{prefix}-{k}"
            part = make(number)
            if part.part_number in self.by_number:
                raise GeometryError(f"two different parts would share part number {part.part_number}")
            self.progress(f"built {part.part_number}")
            self.parts[key] = part
            self.by_number[part.part_number] = part
        return self.parts[key]


def _r(x: float) -> float:
    return round(float(x), 6)


def build_stack(job_design, progress=None) -> StackAssembly:
    """Build and place every part of a designed job's stack.

    Args:
        job_design: a :class:`~springcad.design.job.JobDesign`.
        progress: optional callable taking a short message per part built.

    Raises:
        GeometryError: a part cannot be made (the message names it and the cause).
    """
    from springcad.geometry.adapters import AlignmentShaft, RimFlange, TorqueShaft
    from springcad.geometry.disk import Camshaft, FlexureRing
    from springcad.geometry.fasteners import DowelPin, RimNut, RimScrew, nut_height_mm
    from springcad.geometry.spacers import Bushing, CentreSpacer, RimSpacer, RimWasher

    stack = job_design.stack
    springs = stack.springs
    mat = springs[0].material.material
    steel = (mat.description or mat.name, mat.density_kg_per_m3)
    cache = _PartCache(progress or (lambda msg: None))
    out: list[Instance] = []

    def place(name, part, comp, placement, role=""):
        colour = COLOURS[role] if role and comp.kind in ("torque_shaft", "rim_flange") else part.colour
        out.append(Instance(name, part, placement, comp, role, colour))

    def annular(cls, prefix, comp, material, holes=(), hole_d=0.0, heat=""):
        d = comp.dims
        key = (cls.__name__, _r(d["inner_radius_mm"]), _r(d["outer_radius_mm"]),
               _r(comp.length_mm), tuple((_r(x), _r(y)) for x, y in holes), _r(hole_d))
        return cache.get(key, lambda pn: cls(pn, d["inner_radius_mm"], d["outer_radius_mm"],
                                             comp.length_mm, material, holes, hole_d, heat),
                         prefix)

    for comp in stack.components:
        d, kind = comp.dims, comp.kind
        own = (comp.material, comp.density_kg_per_m3)  # as designed (hardware densities)
        if kind == "flexure_ring":
            s = springs[d["spring_index"]]
            part = cache.get(("ring", s.name), lambda pn: FlexureRing(s))
            place(comp.name, part, comp, Placement(comp.z_mm), comp.role)
        elif kind == "camshaft":
            members = [springs[i] for i in d["springs"]]
            prof = next(m for m in members if m.name == d.get("profile_spring", members[0].name))
            length = d["toothed_end_mm"] - d["toothed_start_mm"]
            hub = d["hub_length_mm"]
            key = ("cam", prof.name, _r(length), _r(hub), _r(d["hub_radius_mm"]),
                   d.get("bore", "d_flat"), d.get("drive", ""))
            part = cache.get(key, lambda pn: Camshaft(
                prof, length, hub, d.get("bore", "d_flat"), d.get("drive", ""),
                d["bore_diameter_mm"], d.get("flat_ratio", 0.8), d["hub_radius_mm"]))
            part.check_members(members)
            flipped = comp.role == "output" and hub > 0
            z = d["toothed_start_mm"] + (length if flipped else 0.0)
            place(comp.name, part, comp, Placement(z, flipped=flipped), comp.role)
        elif kind == "rim_spacer":
            s = springs[d["joint"]]
            part = annular(RimSpacer, "RIM-SPACER", comp, own, s.hole_centres_mm,
                           d["hole_diameter_mm"], "T6")
            place(comp.name, part, comp, Placement(comp.z_mm))
        elif kind == "rim_washer":
            place(comp.name, annular(RimWasher, "RIM-WASHER", comp, own), comp,
                  Placement(comp.z_mm))
        elif kind == "centre_spacer":
            place(comp.name, annular(CentreSpacer, "CENTRE-SPACER", comp, own), comp,
                  Placement(comp.z_mm))
        elif kind == "bushing":
            place(comp.name, annular(Bushing, "BUSHING", comp, own), comp, Placement(comp.z_mm))
        elif kind == "alignment_shaft":
            r = 0.5 * d["diameter_mm"]
            part = cache.get(("align", _r(r), _r(comp.length_mm)), lambda pn: AlignmentShaft(
                pn, 0.0, r, comp.length_mm, steel, heat_treatment=mat.heat_treatment),
                "ALIGNMENT-SHAFT")
            place(comp.name, part, comp, Placement(comp.z_mm))
        elif kind == "rim_flange":
            s = springs[d["spring_index"]]
            part = annular(RimFlange, "RIM-FLANGE", comp, steel, s.hole_centres_mm,
                           s.hole_diameter_mm, mat.heat_treatment)
            place(comp.name, part, comp, Placement(comp.z_mm), comp.role)
        elif kind == "torque_shaft":
            key = ("torque", tuple(sorted((k, str(v)) for k, v in d.items())), _r(comp.length_mm))
            part = cache.get(key, lambda pn: TorqueShaft(pn, d, comp.length_mm, steel,
                                                         mat.heat_treatment), "TORQUE-SHAFT")
            flipped = comp.role == "output"
            z = comp.z_mm + (comp.length_mm if flipped else 0.0)
            place(comp.name, part, comp, Placement(z, flipped=flipped), comp.role)
        elif kind == "fastener":
            s = springs[d["joint"]]
            dia = d["diameter_mm"]
            if d["type"] == "dowel":
                parts = [(cache.get(("dowel", _r(dia), _r(d["length_mm"])),
                                    lambda pn: DowelPin(pn, dia, d["length_mm"]), "DOWEL"),
                          comp.z_mm, "")]
            else:
                nut_h = nut_height_mm(dia)
                screw = cache.get(("screw", _r(dia), _r(d["length_mm"])),
                                  lambda pn: RimScrew(pn, dia, d["length_mm"], nut_h), "SCREW")
                nut = cache.get(("nut", _r(dia)), lambda pn: RimNut(pn, dia), "NUT")
                parts = [(screw, comp.z_mm, ""), (nut, comp.z_mm + d["length_mm"], "_nut")]
            centres = s.hole_centres_mm[:comp.count]
            for k, (x, y) in enumerate(centres):
                for part, z, suffix in parts:
                    place(f"{comp.name}_{k + 1}{suffix}", part, comp, Placement(z, x, y))
        else:
            raise GeometryError(f"{comp.name}: no part class for component kind '{kind}'")
    return StackAssembly(job_design, out, dict(cache.by_number))
