"""Rim fasteners: dowel pins, and socket-head screws with nuts from bd_warehouse.

bd_warehouse (ISO 4762 screws, ISO 4032 nuts) has no dowel pins, so a dowel
is a plain ISO 8734-style cylinder. Part frame: the fastener enters the first
rim at z = 0 and runs toward +z; a screw head sits at z < 0. Units: mm.
"""

from __future__ import annotations

import math

from springcad.design.catalogue import dowel_designation
from springcad.design.curves import Line, Loop, Profile
from springcad.errors import GeometryError
from springcad.geometry.base import COLOURS, PartInfo, Slab, SpringcadPart, circle_loop
from springcad.geometry.spacers import AnnularPart

STEEL = ("steel, hardened (catalogue part)", 7850.0)
#: ISO 8734 type C1 pins for a stack of stainless rings (no carbon-steel pin rusting in them)
STAINLESS = ("martensitic stainless steel C1, hardened (catalogue part)", 7700.0)


class DowelPin(AnnularPart):
    """Hardened dowel pin, ISO 8734 m6, through both joined rims (a catalogue length,
    flush or recessed: :func:`springcad.design.catalogue.rim_dowel_length`)."""

    KIND, TITLE, PROCESS, COLOUR = "fastener", "Dowel pin", "purchased", "fastener"
    CODE = "DOWEL"
    NOTES = ("Catalogue part: ISO 8734 parallel pin, diameter m6.",)

    def __init__(self, name: str, diameter_mm: float, length_mm: float,
                 stainless: bool = False):
        super().__init__(name, 0.0, 0.5 * diameter_mm, length_mm,
                         STAINLESS if stainless else STEEL,
                         standard=dowel_designation(diameter_mm, length_mm, stainless))
        self.diameter = diameter_mm


def _metric_size(cls, diameter_mm: float, standard: str) -> str:
    sizes = [s for s in cls.sizes(standard) if s.startswith(f"M{diameter_mm:g}-")]
    if not sizes:
        raise GeometryError(
            f"rim screws: hardware.fastener_diameter_mm = {diameter_mm:g} is not a size of "
            f"{cls.__name__} {standard} ({', '.join(cls.sizes(standard))}); pick one of them "
            "or use fastener = \"dowel\"")
    return sizes[0]


def _hexagon(across_corners_mm: float) -> Loop:
    r = 0.5 * across_corners_mm
    pts = [(r * math.cos(k * math.pi / 3), r * math.sin(k * math.pi / 3)) for k in range(6)]
    return Loop(tuple(Line(pts[k], pts[(k + 1) % 6]) for k in range(6)))


class RimScrew(SpringcadPart):
    """ISO 4762 socket-head cap screw (bd_warehouse), shank along +z, head below z = 0.

    Args:
        name: job-local label.
        diameter_mm: nominal thread diameter (mm).
        grip_mm: clamped length (mm); the screw is the shortest catalogue length
            that passes the grip and a nut.
    """

    def __init__(self, name: str, diameter_mm: float, grip_mm: float, nut_height_mm: float):
        from bd_warehouse.fastener import SocketHeadCapScrew
        from build123d import Rot

        size = _metric_size(SocketHeadCapScrew, diameter_mm, "iso4762")
        need = grip_mm + nut_height_mm
        probe = SocketHeadCapScrew(size, 10, "iso4762", simple=True)
        lengths = [v for v in probe.nominal_lengths if v >= need - 1e-9]
        if not lengths:
            raise GeometryError(f"rim screws: no {size} ISO 4762 screw is long enough for a "
                                f"{grip_mm:g} mm grip and a nut; use dowels")
        screw = SocketHeadCapScrew(size, lengths[0], "iso4762", simple=True)
        solid = screw.solids()[0].moved(Rot(180, 0, 0))
        self.thread_size, self.length = size, lengths[0]
        self.head_height, self.head_diameter = screw.head_height, screw.head_diameter
        slabs = (Slab(-self.head_height, 0.0, Profile(circle_loop(0.5 * self.head_diameter))),
                 Slab(0.0, self.length, Profile(circle_loop(0.5 * screw.thread_diameter))))
        info = PartInfo(name=name, code="SCREW", title="Socket head cap screw", kind="fastener",
                        material=STEEL[0], heat_treatment="", density_kg_per_m3=STEEL[1],
                        process="purchased", thickness_mm=self.length,
                        standard=f"ISO 4762 - {size.split('-')[0]} x {self.length:g}",
                        notes=("Catalogue part.",))
        super().__init__(info, slabs, COLOURS["fastener"], solid=solid)


class RimNut(SpringcadPart):
    """ISO 4032 hex nut (bd_warehouse) on the far rim face, z from 0 to its height."""

    def __init__(self, name: str, diameter_mm: float):
        from bd_warehouse.fastener import HexNut

        size = _metric_size(HexNut, diameter_mm, "iso4032")
        nut = HexNut(size, "iso4032", simple=True)
        self.nut_height = nut.nut_thickness
        slabs = (Slab(0.0, self.nut_height, Profile(_hexagon(nut.nut_diameter),
                                                (circle_loop(0.5 * nut.thread_diameter),))),)
        info = PartInfo(name=name, code="NUT", title="Hex nut", kind="fastener",
                        material=STEEL[0], heat_treatment="", density_kg_per_m3=STEEL[1],
                        process="purchased", thickness_mm=self.nut_height,
                        standard=f"ISO 4032 - {size.split('-')[0]}", notes=("Catalogue part.",))
        super().__init__(info, slabs, COLOURS["fastener"], solid=nut.solids()[0])


def nut_height_mm(diameter_mm: float) -> float:
    """Height of the ISO 4032 nut for a thread diameter (mm)."""
    from bd_warehouse.fastener import HexNut

    return HexNut(_metric_size(HexNut, diameter_mm, "iso4032"), "iso4032", simple=True).nut_thickness
