"""Small requirement spaces for the synthesis tests (each sweep takes well under a second)."""

from __future__ import annotations

import copy
from pathlib import Path

from springcad.synthesis.finalists import toml_text  # noqa: F401  (re-exported for tests)

ROOT = Path(__file__).resolve().parents[2]
TEMPLATES = ROOT / "templates"

#: a small space near the paper's 4xS1 requirement (37.5 N*m/rad over +-60 deg: at the
#: paper's +-64 deg this grid holds no disk whose uncoupled serpentine keeps the margin)
SMALL = {
    "requirement": {"name": "small", "stiffness_Nm_per_rad": 37.5, "stiffness_tolerance_pct": 5,
                    "deflection_deg": 60},
    "envelope": {"max_outer_radius_mm": 35.05, "max_axial_length_mm": 19.5},
    "materials": {"names": ["420_ht"], "yield_margin": 1.0, "stress_concentration": 1.4737},
    "objective": {"minimise": "mass"},
    "search": {"max_disks": 5, "thickness_mm": [3.0, 4.5], "contact_radius_mm": [5.9, 7.5],
               "outer_radius_fractions": [1.0], "inputs": ["shaft", "rim"], "mixed": True,
               "compliance_splits": [0.5], "fewer_flexures": [0, 2, 4]},
    "manufacturing": {"t_spring_mm": 0.05, "t_shaft_mm": 0.02, "w_gap_mm": 0.025},
}


def small(**changes) -> dict:
    """A deep copy of :data:`SMALL` with ``section={key: value}`` changes merged in."""
    data = copy.deepcopy(SMALL)
    for section, table in changes.items():
        data.setdefault(section, {}).update(table)
    return data


def requirements_toml(data: dict) -> str:
    """Requirements dict -> TOML text (flat tables only)."""
    return toml_text(data)
