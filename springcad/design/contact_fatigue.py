"""Contact fatigue (pitting) of the flexure's tip ball on the cam flank over the duty.

The Hertz pressure p0 at +-theta_max (from the FEA contact sweep) is judged against the
repeatedly applied contact strength S_c of the material at its hardness
(``springcad/data/contact_fatigue.csv``, AGMA 2001-D04 / Shigley ch. 14, 1e7 cycles, 99 %
reliability) times the stress-cycle factor Z_N(N). Each cycle of a duty block loads a ball
flank to |mean| + amplitude of theta_max; p0 grows with the square root of the load.
Miner's sum over the blocks; the safety factor is on pressure (AGMA's S_H).

Units: MPa, cycles.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass
from importlib import resources

from springcad.config.specs import DutySpec
from springcad.design import duty


@functools.cache
def contact_fatigue_table() -> dict[str, tuple[float, float, str]]:
    """name -> (hardness HRC min, contact strength S_c at 1e7 cycles MPa, source)."""
    text = resources.files("springcad.data").joinpath("contact_fatigue.csv").read_text()
    return {r["name"]: (float(r["hardness_HRC_min"]), float(r["contact_strength_MPa"]),
                        r["source"]) for r in csv.DictReader(text.splitlines())}


def contact_life_factor(cycles: float) -> float:
    """Stress-cycle factor Z_N of the contact strength (AGMA 2001-D04 Fig. 18, Shigley
    Fig. 14-15): 1.4488 N^-0.023 up to 1e7 cycles (held at its 1e4 value below), 2.466
    N^-0.056 beyond."""
    if cycles > 1e7:
        return 2.466 * cycles ** -0.056
    return 1.4488 * max(cycles, 1e4) ** -0.023


def contact_life(p0_MPa: float, strength_MPa: float) -> float:
    """Cycles to pitting at Hertz pressure ``p0_MPa`` (the inverse of S_c Z_N(N); contact
    fatigue has no endurance limit)."""
    ratio = p0_MPa / strength_MPa
    if ratio <= 0:
        return math.inf
    if ratio >= contact_life_factor(1e7):
        if ratio >= contact_life_factor(1e4):
            return 1e4 * (ratio / contact_life_factor(1e4)) ** (-1 / 0.023)
        return (ratio / 1.4488) ** (-1 / 0.023)
    return (ratio / 2.466) ** (-1 / 0.056)


@dataclass(frozen=True)
class ContactFatigueCheck:
    """The tip ball's Hertz pressure over the duty (MPa, cycles).

    Every cycle of a block loads a ball flank to |mean| + amplitude of theta_max; the
    Hertz pressure grows with the square root of the load. Miner's sum of those cycles
    against S_c Z_N(N); the safety factor is on pressure (AGMA's S_H).
    """

    p0_max_MPa: float
    strength_MPa: float
    hardness_HRC_min: float
    miner_sum: float
    safety_factor: float
    required_safety_factor: float
    life_at_max_cycles: float
    allowable_MPa: float
    """largest p0 at theta_max meeting the duty with its factor."""
    source: str

    @property
    def met(self) -> bool:
        return self.safety_factor >= self.required_safety_factor * (1.0 - 1e-6)

    def text(self) -> str:
        life = self.life_at_max_cycles
        life_text = "< 1e4 cycles (beyond the chart)" if life < 1e4 else f"{life:.3g} cycles"
        return (f"tip ball Hertz pressure {self.p0_max_MPa:.0f} MPa at theta_max against the "
                f"contact-fatigue strength {self.strength_MPa:.0f} MPa at 1e7 cycles "
                f"({self.hardness_HRC_min:g} HRC): Miner sum {self.miner_sum:.3g}, safety "
                f"factor {self.safety_factor:.2f} (required {self.required_safety_factor:g}), "
                f"allowable {self.allowable_MPa:.0f} MPa; life at +-theta_max {life_text}")

    def to_dict(self) -> dict:
        d = dict(self.__dict__)
        d["met"] = self.met
        d["text"] = self.text()
        return d


def contact_check(duty_spec: DutySpec, material_name: str, p0_max_MPa: float,
                  theta_max_rad: float) -> ContactFatigueCheck | None:
    """Contact fatigue of the tip ball over the duty; None without contact-fatigue data."""
    row = contact_fatigue_table().get(material_name)
    if row is None or not p0_max_MPa > 0:
        return None
    hrc, sc, src = row
    loads = [(b.cycles, min(abs(b.mean) + b.amplitude, 1.0))
             for b in duty.blocks(duty_spec, theta_max_rad)]

    def damage(p0):
        return sum(n / contact_life(p0 * math.sqrt(f), sc) for n, f in loads if f > 0)

    lo, hi = 1e-3, 1e7
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if damage(mid) >= 1.0 else (mid, hi)
        if hi / lo - 1 < 1e-9:
            break
    critical = math.sqrt(lo * hi)
    return ContactFatigueCheck(p0_max_MPa, sc, hrc, damage(p0_max_MPa), critical / p0_max_MPa,
                               duty_spec.safety_factor, contact_life(p0_max_MPa, sc),
                               critical / duty_spec.safety_factor, src)
