"""Annular parts: rim spacer, rim washer, centre spacer and the outer bushing.

All are rings (or discs) of constant section along the axis, built from
their :class:`~springcad.design.plans.AnnulusPlan` (:meth:`AnnularPart.from_plan`).
Part frame: z from 0 to the part length. Units: mm.
"""

from __future__ import annotations

import math

from springcad.design.plans import AnnulusPlan
from springcad.design.processes import SHEET_STOCK_MAX_MM, SHEET_THICKNESS_TOLERANCE_MM
from springcad.design.processes import process as process_of
from springcad.geometry.base import (COLOURS, GENERAL_TOLERANCE_MM, PartInfo, Slab, SpringcadPart,
                                     annulus, circle_loop)


class AnnularPart(SpringcadPart):
    """A ring from ``inner_radius`` to ``outer_radius`` over ``length`` with optional holes.

    Subclasses set ``KIND``, ``CODE``, ``TITLE``, ``PROCESS``, ``COLOUR`` and ``NOTES``.

    Args:
        name: job-local label (the part number is made from the geometry).
        inner_radius_mm: bore radius, 0 for a disc (mm).
        outer_radius_mm: outer radius (mm).
        length_mm: axial length / sheet thickness (mm).
        material: (name, density kg/m^3).
        hole_centres: centres of axial holes (mm).
        hole_diameter_mm: their diameter (mm).
        heat_treatment: as written on the drawing.
        standard: catalogue designation of a purchased part.
        process: manufacturing process key (default the class's ``PROCESS``).
    """

    KIND = "annulus"
    #: family code that starts the part number
    CODE = "RING"
    TITLE = "Ring"
    PROCESS = "turned"
    COLOUR = "steel"
    NOTES: tuple[str, ...] = ()
    #: planar sheet parts get a DXF cutting profile
    SHEET = False
    #: ISO fits of the outer diameter and bore (e.g. ``{"outer": "g6"}``)
    FITS: dict = {}
    #: processes that finish the fits after the main one (e.g. ``("ground",)``)
    SECONDARY: tuple[str, ...] = ()

    def __init__(self, name: str, inner_radius_mm: float, outer_radius_mm: float,
                 length_mm: float, material: tuple[str, float], hole_centres=(),
                 hole_diameter_mm: float = 0.0, heat_treatment: str = "", standard: str = "",
                 hardness: str = "", heat_treatment_sequence: str = "", fits: dict | None = None,
                 process: str | None = None):
        self.inner_radius = inner_radius_mm
        self.outer_radius = outer_radius_mm
        self.length = length_mm
        self.hole_centres = tuple(hole_centres)
        self.hole_diameter = hole_diameter_mm
        self.process = process or self.PROCESS
        self.hole_purpose = (fits or {}).get("hole_purpose", "")
        holes = tuple(circle_loop(0.5 * hole_diameter_mm, c) for c in self.hole_centres)
        region = annulus(inner_radius_mm, outer_radius_mm, holes)
        dims = {"outer diameter": 2 * outer_radius_mm}
        if inner_radius_mm > 0:
            dims["inner diameter"] = 2 * inner_radius_mm
        dims["thickness" if self.SHEET else "length"] = length_mm
        if self.hole_centres:
            dims["bolt circle diameter"] = 2 * math.hypot(*self.hole_centres[0])
            dims["hole diameter"] = hole_diameter_mm
        info = PartInfo(name=name, code=self.CODE, title=self.TITLE, kind=self.KIND,
                        material=material[0], heat_treatment=heat_treatment,
                        density_kg_per_m3=material[1], process=self.process,
                        thickness_mm=length_mm, cut_profile=region if self.SHEET else None,
                        dimensions=dims, notes=self.part_notes(), standard=standard,
                        hardness=hardness, heat_treatment_sequence=heat_treatment_sequence,
                        fits={k: v for k, v in {**self.FITS, **(fits or {})}.items()
                              if k != "bore" or inner_radius_mm > 0},
                        secondary_processes=self.SECONDARY, stock=self.stock_text())
        super().__init__(info, (Slab(0.0, length_mm, region),), COLOURS[self.COLOUR])

    def part_notes(self) -> tuple[str, ...]:
        """The drawing notes of this part (the class's ``NOTES``; subclasses add notes that
        depend on the sizes and the process), and what to order (:meth:`stock_text`)."""
        stock = self.stock_text()
        return (*self.NOTES, *((f"Stock to order: {stock}.",) if stock else ()))

    @property
    def is_thin_sheet(self) -> bool:
        """Cut from sheet stock :data:`~springcad.design.processes.SHEET_STOCK_MAX_MM` thick
        or thinner."""
        return self.SHEET and self.length <= SHEET_STOCK_MAX_MM

    def stock_text(self) -> str:
        """What a buyer orders to make the part, beyond the material's name ("" when the
        material, thickness and general tolerances say it all)."""
        return ""

    def _stock_sizes(self) -> tuple[str, int]:
        """The thickness as drawn (mm text) and the smallest stock width: the outer
        diameter rounded up to a whole mm."""
        return f"{self.length:g}", math.ceil(round(2.0 * self.outer_radius, 6))

    def webs_mm(self, hole_tolerance_mm: float = 0.0) -> tuple[float, float]:
        """Material between the holes, ``hole_tolerance_mm`` over size, and the inner and
        outer edges (mm; inf without holes)."""
        if not self.hole_centres:
            return math.inf, math.inf
        r = [math.hypot(*c) for c in self.hole_centres]
        h = 0.5 * (self.hole_diameter + hole_tolerance_mm)
        return min(r) - h - self.inner_radius, self.outer_radius - max(r) - h

    @property
    def length_tolerance_mm(self) -> float:
        """Thickness tolerance of a part cut from sheet stock (mm; the sheet as supplied,
        :data:`~springcad.design.processes.SHEET_THICKNESS_TOLERANCE_MM`), else 0: the
        general tolerance."""
        return SHEET_THICKNESS_TOLERANCE_MM if self.is_thin_sheet else 0.0

    @property
    def tolerance_mm(self) -> float:
        """Contour tolerance (mm): a sheet part's process's contour tolerance (the one its
        worst-case web rules count with), else the general one, or the process's hole
        tolerance if that is coarser."""
        proc = process_of(self.process)
        if self.SHEET and proc.contour_tolerance_mm:
            return proc.contour_tolerance_mm
        return max(GENERAL_TOLERANCE_MM, proc.hole_tolerance_mm)

    @classmethod
    def from_plan(cls, name: str, plan: AnnulusPlan, length_mm: float,
                  material: tuple[str, float], heat_treatment: str = "", **spec) -> "AnnularPart":
        """The part of a stack plan: its radii and holes, ``length_mm`` long (mm).

        ``spec``: ``hardness``, ``heat_treatment_sequence``, ``fits`` (see :class:`PartInfo`).
        The plan's ``process``, if it has one, overrides the class's.
        """
        return cls(name, plan.inner_radius_mm, plan.outer_radius_mm, length_mm, material,
                   plan.hole_centres_mm, plan.hole_diameter_mm, heat_treatment,
                   process=getattr(plan, "process", None), **spec)


class RimSpacer(AnnularPart):
    """Thin ring between two bolted rims (paper Fig. 2a: aluminium; here stainless shim
    strip, which is stocked as thin as the gap): keeps the rims apart, reduces friction."""

    KIND, TITLE, PROCESS, COLOUR, SHEET = "rim_spacer", "Rim spacer", "laser", "steel", True
    CODE = "RIM-SPACER"
    NOTES = ("Holes clear the rim dowels (slip, never pressed): their position matters, "
             "their size only as toleranced.",)

    def part_notes(self) -> tuple[str, ...]:
        """How the sheet is cut, by process (its webs are at least the sheet thickness
        whatever the process: the build's ``sheet_web`` rules), and what to order."""
        if self.process != "wire_edm":
            return ("Cut from flat sheet, one sheet at a time; deburr both faces.",
                    *super().part_notes())
        return ("Wire EDM, several sheets clamped as one stack between two plates.",
                *super().part_notes())

    def stock_text(self) -> str:
        """Strip of the material's grade and temper (its name: ``1.4310+C1300 ... EN 10151``),
        thickness tolerance EN ISO 9445-1 normal: at most ±0.05 mm for strip up to 1 mm thick
        in widths below 600 mm (EN 10258 / ISO 9445-1 narrow-strip table), within the
        :data:`~springcad.design.processes.SHEET_THICKNESS_TOLERANCE_MM` drawn. The part
        carries no load (clamped, its holes clear the pins), so the temper only makes the
        order complete: another is no reason to call."""
        if not self.is_thin_sheet:
            return ""
        t, w = self._stock_sizes()
        return (f"strip {t} mm thick, EN ISO 9445-1 normal thickness tolerance (inside the "
                f"±{self.length_tolerance_mm:g} drawn), at least {w} mm wide; the part carries "
                "no load: another EN 10151 temper will do")


#: thickness tolerance of acetal sheet as ASTM D6100 gives it when the order names none
#: (fraction of the thickness)
D6100_SHEET_TOLERANCE = 0.10


class PlasticSheetPart(AnnularPart):
    """A POM-C part cut from sheet or film (rim washer, centre spacer)."""

    def stock_text(self) -> str:
        """POM-C sheet or film to ASTM D6100 (Type I: unfilled), its thickness tolerance
        (±10 % unless ordered closer) against the
        :data:`~springcad.design.processes.SHEET_THICKNESS_TOLERANCE_MM` drawn."""
        if not self.is_thin_sheet:
            return ""
        t, w = self._stock_sizes()
        drawn, d6100 = self.length_tolerance_mm, D6100_SHEET_TOLERANCE * self.length
        tol = (f"ASTM D6100's ±10 % (±{d6100:.3g}) is inside the ±{drawn:g} drawn"
               if d6100 <= drawn + 1e-12 else
               f"order ±{drawn:g}, closer than ASTM D6100's ±10 % (±{d6100:.3g})")
        return (f"POM-C (acetal copolymer) sheet or film to ASTM D6100, Type I (unfilled), "
                f"natural, {t} mm thick: {tol}; at least {w} x {w} mm")


class RimWasher(PlasticSheetPart):
    """Plastic ring between the rims of two springs that share a camshaft."""

    KIND, TITLE, PROCESS, COLOUR, SHEET = "rim_washer", "Rim washer", "milled", "plastic", True
    CODE = "RIM-WASHER"
    NOTES = ()


class CentreSpacer(PlasticSheetPart):
    """Low-friction plastic disc, larger than the cam teeth, between rim-joined springs.

    It keeps either camshaft from loading both springs (paper Fig. 2a).
    """

    KIND, TITLE, PROCESS, COLOUR, SHEET = "centre_spacer", "Centre spacer", "milled", "plastic", True
    CODE = "CENTRE-SPACER"
    NOTES = ("The parts beside it slide on both faces: faces as supplied, no scratches.",)
    #: the bore (floating stacks) runs on the g6 alignment shaft of the same nominal size
    FITS = {"bore": "H11"}


class Bushing(AnnularPart):
    """Plastic sleeve around the rims: keeps floating rims concentric (paper Section II-A)."""

    KIND, TITLE, PROCESS, COLOUR = "bushing", "Outer bushing", "turned", "plastic"
    CODE = "BUSHING"
    NOTES = ("Running clearance over the rims: bore and outer diameter turned in one setting.",)
    #: the bore clears the rims by 0.1 mm on the diameter: less than the general tolerance
    #: (ISO 2768-m: ±0.3 mm at this size), so it gets a fit whose lower deviation is zero
    FITS = {"bore": "H9"}
