"""Built-in material table (``springcad/data/materials.csv``).

Values are handbook figures; a config may override any of them.
"""

from __future__ import annotations

import csv
import functools
from dataclasses import dataclass
from importlib import resources

from springcad.units import KG_PER_MM3_PER_KG_PER_M3, MPA_PER_GPA


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material.

    Attributes:
        name: table key, e.g. ``"420_ht"``.
        youngs_modulus_MPa: E (MPa).
        poisson_ratio: nu (-).
        yield_strength_MPa: 0.2 % proof stress (MPa).
        density_kg_per_m3: density (kg/m^3).
        heat_treatment: as written on drawings.
        description: human-readable name.
        hardness: the hardness to order, as written on drawings (e.g. ``"48-52 HRC"``).
        heat_treatment_sequence: when the heat treatment happens relative to the cut
            (``"before EDM"``: the shop cuts heat-treated stock).
    """

    name: str
    youngs_modulus_MPa: float
    poisson_ratio: float
    yield_strength_MPa: float
    density_kg_per_m3: float
    heat_treatment: str = ""
    description: str = ""
    source: str = ""
    hardness: str = ""
    heat_treatment_sequence: str = ""

    @property
    def density_kg_per_mm3(self) -> float:
        return self.density_kg_per_m3 * KG_PER_MM3_PER_KG_PER_M3


@functools.cache
def material_table() -> dict[str, Material]:
    """All built-in materials by name."""
    text = resources.files("springcad.data").joinpath("materials.csv").read_text()
    out = {}
    for row in csv.DictReader(text.splitlines()):
        out[row["name"]] = Material(
            name=row["name"],
            youngs_modulus_MPa=float(row["youngs_modulus_GPa"]) * MPA_PER_GPA,
            poisson_ratio=float(row["poisson_ratio"]),
            yield_strength_MPa=float(row["yield_strength_MPa"]),
            density_kg_per_m3=float(row["density_kg_per_m3"]),
            heat_treatment=row["heat_treatment"],
            description=row["description"],
            source=row["source"],
            hardness=row["hardness"],
            heat_treatment_sequence=row["heat_treatment_sequence"],
        )
    return out


DEFAULT_MATERIAL = "420_ht"
