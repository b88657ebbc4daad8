"""What a part is without its solid: :class:`Slab` (a z-prism piece) and :class:`PartInfo`.

Plain data (no CAD kernel), so that what the exports, the bill of materials and a cached
build read of a part (:mod:`springcad.export.skeleton`) loads without importing build123d
(~2.6 s of CPU); :mod:`springcad.geometry.base` builds the solids from them. Units: mm.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from springcad.design.curves import Profile


@dataclass(frozen=True)
class Slab:
    """A planar region swept along z from ``z0_mm`` to ``z1_mm`` (part frame, mm)."""

    z0_mm: float
    z1_mm: float
    region: Profile

    @property
    def length_mm(self) -> float:
        return self.z1_mm - self.z0_mm

    def volume_mm3(self) -> float:
        return self.region.area_mm2() * self.length_mm


@dataclass(frozen=True)
class PartInfo:
    """What a drawing, a DXF and the bill of materials need to know about a part.

    Attributes:
        name: the job-local label of the part (``"S1-RING"``, ``"RIM-SPACER-2"``),
            used in messages and shown beside the part number.
        title: human-readable name, e.g. ``"Flexure ring, 28 flexures"``.
        kind: Component kind (flexure_ring, camshaft, ...).
        material: material name.
        heat_treatment: as written on the drawing ("" if none).
        density_kg_per_m3: density for the mass (kg/m^3).
        process: "wire_edm", "turned", "laser", "purchased".
        thickness_mm: plate thickness of a planar part, or its length (mm).
        cut_profile: the 2D contour the shop cuts (wire EDM / laser), or None.
        dimensions: key dimensions for the drawing, ``{label: value_mm}``.
        notes: drawing notes specific to this part.
        standard: catalogue designation for purchased parts.
        code: the family code that starts the part number (``"RING"``, ``"CAM"``).
        hardness: hardness to order, as written on the drawing (``"48-52 HRC"``).
        heat_treatment_sequence: when the heat treatment happens (``"before EDM"``).
        fits: ISO fits and purposes of features: ``"outer"``, ``"bore"``, ``"holes"``
            (e.g. ``"g6"``, ``"H7"``) and ``"hole_purpose"`` (``"(dowel pins)"``).
        part_number: ``CODE-HASH`` of the part's identity (module docstring); set by
            :class:`SpringcadPart`, never by hand.
        secondary_processes: processes that finish features after the main one (keys of
            ``springcad/data/processes.toml``: ``("ground",)`` for the fits of a turned
            and hardened shaft, ``("sinker_edm",)`` for a blind socket).
        stock: what a buyer orders to make the part, when the drawing's material name
            alone does not say it (a sheet part: the strip or sheet, its standard, temper,
            thickness and tolerance, smallest width); "" otherwise.
    """

    name: str
    title: str
    kind: str
    material: str
    heat_treatment: str
    density_kg_per_m3: float
    process: str
    thickness_mm: float
    cut_profile: Profile | None = None
    dimensions: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    standard: str = ""
    code: str = ""
    hardness: str = ""
    heat_treatment_sequence: str = ""
    fits: dict = field(default_factory=dict)
    part_number: str = ""
    secondary_processes: tuple[str, ...] = ()
    stock: str = ""


class NamedByInfo:
    """``part_number`` and ``name`` read from the object's ``info`` (:class:`PartInfo`):
    a built part and its cached record answer them alike."""

    info: PartInfo

    @property
    def part_number(self) -> str:
        return self.info.part_number

    @property
    def name(self) -> str:
        """The job-local label (``"S1-RING"``)."""
        return self.info.name
