"""S-N data of the spring materials, the Marin factors of the part and its S-N line.

The endurance limit of the part is the polished-specimen limit S_e' of
``springcad/data/fatigue.csv`` (typical, mean values: see each row's source) times
Marin factors (Shigley, Mechanical Engineering Design, sec. 6-9):

* surface k_a from the surface condition of the cut faces
  (``springcad/data/surface.csv``: wire-EDM main cut, skim cuts, recast removed by
  polishing, shot-peened; each with its factor, its drawing note and its source);
* size k_b = 1.0: the flexure sections are a few millimetres (k_b ~ 1.1 in the
  Shigley fit for d < 8 mm, not taken);
* reliability k_e = 1 - 0.08 z_a (Shigley Eq. 6-27: 8 % standard deviation of the
  endurance limit; 0.897 at 90 %, 0.814 at 99 %).

The S-N line of the part is Basquin's, S = a N^b, through (1e3, f S_ut) and
(N_e, S_e) (Shigley Eq. 6-13 to 6-15, f per material in the CSV). Steels and
titanium have an endurance limit: below S_e the life is infinite. Aluminium has
none: the line continues past N_e.

Units: MPa, cycles.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import asdict, dataclass
from importlib import resources
from statistics import NormalDist

SIZE_FACTOR = 1.0
#: surface condition of the cut faces when the job does not choose one
DEFAULT_SURFACE = "edm_skim_cuts"
#: reliability when the job does not choose one (endurance limits are mean values)
DEFAULT_RELIABILITY = 0.99
#: cycles at which the S-N line starts (Shigley: f S_ut at 1e3 cycles)
LOW_CYCLE_N = 1e3


def reliability_factor(reliability: float) -> float:
    """Marin reliability factor k_e = 1 - 0.08 z_a (Shigley Eq. 6-27) (-)."""
    return 1.0 - 0.08 * NormalDist().inv_cdf(reliability)


@dataclass(frozen=True)
class FatigueProperties:
    """Fully reversed fatigue data of one material (MPa, cycles)."""

    name: str
    ultimate_strength_MPa: float
    endurance_limit_MPa: float
    cycles_at_endurance: float
    source: str = ""
    fraction_at_1e3: float = 0.9
    has_endurance_limit: bool = True


@dataclass(frozen=True)
class Surface:
    """A surface condition of the cut faces: Marin factor, drawing note, source."""

    name: str
    factor: float
    drawing_note: str
    source: str


@functools.cache
def fatigue_table() -> dict[str, FatigueProperties]:
    """Built-in fatigue data by material name."""
    text = resources.files("springcad.data").joinpath("fatigue.csv").read_text()
    return {r["name"]: FatigueProperties(
        r["name"], float(r["ultimate_strength_MPa"]), float(r["endurance_limit_MPa"]),
        float(r["cycles_at_endurance"]), r["source"], float(r["fraction_at_1e3"]),
        r["endurance_limit"].strip() == "yes")
        for r in csv.DictReader(text.splitlines())}


@functools.cache
def surface_table() -> dict[str, Surface]:
    """Built-in surface conditions by name (``springcad/data/surface.csv``)."""
    text = resources.files("springcad.data").joinpath("surface.csv").read_text()
    return {r["name"]: Surface(r["name"], float(r["factor"]), r["drawing_note"], r["source"])
            for r in csv.DictReader(text.splitlines())}


@dataclass(frozen=True)
class SNCurve:
    """The S-N line of the part (fully reversed stress amplitude, MPa; cycles).

    Attributes:
        endurance_limit_MPa: S_e of the part (Marin factors applied).
        low_cycle_strength_MPa: f S_ut, the amplitude at 1e3 cycles.
        cycles_at_endurance: N_e, the knee.
        has_endurance_limit: infinite life below S_e (steels, titanium).
        ultimate_strength_MPa: S_ut, the amplitude that fails in one cycle.
    """

    endurance_limit_MPa: float
    low_cycle_strength_MPa: float
    cycles_at_endurance: float
    has_endurance_limit: bool = True
    ultimate_strength_MPa: float = math.inf

    @property
    def exponent(self) -> float:
        """Basquin exponent b (negative) of S = a N^b."""
        return (math.log10(self.endurance_limit_MPa / self.low_cycle_strength_MPa)
                / (math.log10(self.cycles_at_endurance) - math.log10(LOW_CYCLE_N)))

    @property
    def coefficient_MPa(self) -> float:
        return self.low_cycle_strength_MPa / LOW_CYCLE_N ** self.exponent

    def life(self, amplitude_MPa: float) -> float:
        """Cycles to failure at a fully reversed amplitude (inf below the endurance limit;
        the Basquin line from 1e3 cycles at f S_ut to N_e at S_e; above f S_ut the
        low-cycle line to one cycle at S_ut)."""
        if amplitude_MPa <= 0.0:
            return math.inf
        if self.has_endurance_limit and amplitude_MPa < self.endurance_limit_MPa:
            return math.inf
        if amplitude_MPa >= self.low_cycle_strength_MPa:
            # Shigley sec. 6-7: the low-cycle line from (1, S_ut) to (1e3, f S_ut)
            if amplitude_MPa >= self.ultimate_strength_MPa:
                return 1.0
            return LOW_CYCLE_N ** (math.log(self.ultimate_strength_MPa / amplitude_MPa)
                                   / math.log(self.ultimate_strength_MPa
                                              / self.low_cycle_strength_MPa))
        return (amplitude_MPa / self.coefficient_MPa) ** (1.0 / self.exponent)

    def strength(self, cycles: float) -> float:
        """The amplitude that fails in ``cycles`` (MPa)."""
        if self.has_endurance_limit and cycles >= self.cycles_at_endurance:
            return self.endurance_limit_MPa
        return self.coefficient_MPa * max(cycles, LOW_CYCLE_N) ** self.exponent


def part_curve(props: FatigueProperties, surface: str = DEFAULT_SURFACE,
               reliability: float = DEFAULT_RELIABILITY) -> SNCurve:
    """The S-N line of a part of this material with this surface and reliability."""
    se = (props.endurance_limit_MPa * surface_table()[surface].factor * SIZE_FACTOR
          * reliability_factor(reliability))
    return SNCurve(se, props.fraction_at_1e3 * props.ultimate_strength_MPa,
                   props.cycles_at_endurance, props.has_endurance_limit,
                   props.ultimate_strength_MPa)


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
    surface: str
    surface_factor: float
    size_factor: float
    reliability: float
    reliability_factor: float
    margin: float
    life_cycles: float
    source: str

    def to_dict(self) -> dict:
        d = asdict(self)
        d["life_cycles"] = None if math.isinf(self.life_cycles) else self.life_cycles
        d["criterion"] = "fully reversed (R = -1) at +-theta_max, zero mean"
        return d


def check(material_name: str, amplitude_MPa: float, surface: str = DEFAULT_SURFACE,
          reliability: float = DEFAULT_RELIABILITY) -> FatigueCheck | None:
    """Fully reversed fatigue check of a stress amplitude; None without fatigue data."""
    props = fatigue_table().get(material_name)
    if props is None:
        return None
    curve = part_curve(props, surface, reliability)
    se = curve.endurance_limit_MPa
    return FatigueCheck(props.name, amplitude_MPa, se, props.endurance_limit_MPa,
                        props.ultimate_strength_MPa, surface, surface_table()[surface].factor,
                        SIZE_FACTOR, reliability, reliability_factor(reliability),
                        se / amplitude_MPa, curve.life(amplitude_MPa), props.source)
