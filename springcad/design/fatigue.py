"""Fatigue of a spring cycled fully reversed between -theta_max and +theta_max.

The flexure stress alternates with amplitude sigma_a = predicted peak at theta_max and
zero mean (the cam pushes either flank), so the modified Goodman line
sigma_a / S_e + sigma_m / S_ut = 1 reduces to sigma_a <= S_e. The endurance limit
of the part is the polished-specimen limit S_e' (``springcad/data/fatigue.csv``)
times Marin factors:

* surface k_a = 0.70 for wire-EDM cut faces with their recast (white) layer left in
  place: wire-EDM recast and its micro-cracks lower the fatigue strength of hardened
  steels by roughly 20-40 % against polished (main cut) and less after trim cuts;
  0.70 is a mid value for a main cut plus trim cuts. A part whose cut faces are
  polished or shot-peened after EDM does better; this check does not assume it.
* size k_b = 1.0: the flexure sections are a few millimetres (k_b ~ 1.1 in the
  Shigley fit for d < 8 mm, not taken);
* reliability k_e = 0.897 (90 % survival, 8 % scatter of the endurance limit).

Below the endurance limit the margin S_e / sigma_a is reported; above it, the finite
life from the Basquin line through (1e3, 0.9 S_ut) and (N_e, S_e).

Units: MPa, cycles.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import asdict, dataclass
from importlib import resources

#: Marin surface factor for wire-EDM faces with the recast layer in place (see module docstring)
EDM_SURFACE_FACTOR = 0.70
SIZE_FACTOR = 1.0
#: 90 % reliability
RELIABILITY_FACTOR = 0.897


@dataclass(frozen=True)
class FatigueProperties:
    """Fully reversed fatigue data of one material (MPa, cycles)."""

    name: str
    ultimate_strength_MPa: float
    endurance_limit_MPa: float
    cycles_at_endurance: float
    source: str = ""


@functools.cache
def fatigue_table() -> dict[str, FatigueProperties]:
    """Built-in fatigue data by material name."""
    text = resources.files("springcad.data").joinpath("fatigue.csv").read_text()
    return {r["name"]: FatigueProperties(r["name"], float(r["ultimate_strength_MPa"]),
                                         float(r["endurance_limit_MPa"]),
                                         float(r["cycles_at_endurance"]), r["source"])
            for r in csv.DictReader(text.splitlines())}


@dataclass(frozen=True)
class FatigueCheck:
    """Fully reversed fatigue at +-theta_max.

    Attributes:
        amplitude_MPa: stress amplitude (the peak at theta_max), zero mean.
        endurance_limit_MPa: corrected endurance limit of the part S_e.
        margin: S_e / amplitude (>= 1: infinite life under these assumptions).
        life_cycles: predicted cycles to failure (inf when margin >= 1).
    """

    material: str
    amplitude_MPa: float
    endurance_limit_MPa: float
    polished_endurance_limit_MPa: float
    ultimate_strength_MPa: float
    surface_factor: float
    size_factor: float
    reliability_factor: float
    margin: float
    life_cycles: float
    source: str

    def to_dict(self) -> dict:
        d = asdict(self)
        d["life_cycles"] = None if math.isinf(self.life_cycles) else self.life_cycles
        d["criterion"] = "fully reversed (R = -1), modified Goodman with zero mean"
        return d


def check(material_name: str, amplitude_MPa: float,
          surface_factor: float = EDM_SURFACE_FACTOR) -> FatigueCheck | None:
    """Fatigue check of a stress amplitude; None for a material without fatigue data."""
    props = fatigue_table().get(material_name)
    if props is None:
        return None
    se = props.endurance_limit_MPa * surface_factor * SIZE_FACTOR * RELIABILITY_FACTOR
    margin = se / amplitude_MPa
    life = math.inf
    if margin < 1.0:
        f = 0.9 * props.ultimate_strength_MPa
        n_e = props.cycles_at_endurance
        b = -math.log10(f / se) / (math.log10(n_e) - 3.0)
        a = f / 1e3 ** b
        life = (amplitude_MPa / a) ** (1.0 / b) if amplitude_MPa < f else 1e3
    return FatigueCheck(props.name, amplitude_MPa, se, props.endurance_limit_MPa,
                        props.ultimate_strength_MPa, surface_factor, SIZE_FACTOR,
                        RELIABILITY_FACTOR, margin, life, props.source)
