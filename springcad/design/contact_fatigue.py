"""Contact fatigue (pitting) of the flexure's tip ball on the cam flank over the duty.

The tip ball is a cylinder as long as the disk is thick, the cam flank at the contact a
convex cylinder of radius r_c theta - r_b - w_gap (the involute flank offset by the ball and
gap, :func:`~springcad.design.contact_stress.flank_radius_at_contact_mm`): a Hertz *line* contact
(:mod:`springcad.design.contact_stress`, p0 = sqrt(P E* / (pi R)), P = force / thickness).
Its peak pressure p0 at +-theta_max (from the FEA contact sweep; at design time from the
tip load and the flank radius) is judged against the repeatedly applied contact strength
S_c of the material at its hardness (``springcad/data/contact_fatigue.csv``, AGMA
2001-D04 / Shigley ch. 14, 1e7 cycles, 99 % reliability) times the stress-cycle factor
Z_N(N) (:func:`contact_life_factor`). Each cycle of a duty block loads a ball flank to
|mean| + amplitude of theta_max; p0 grows with the square root of the load. Miner's sum
over the blocks; the safety factor is on pressure (AGMA's S_H), the duty's own.

AGMA's chart starts at 1e4 cycles: a duty of fewer than 1e4 cycles in all (a bench or
prototype duty) is left to the static contact rule (the ball's von Mises stress against
yield, :mod:`fea.contact_tolerance`) and is not judged here (:func:`judged`).

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
from springcad.design.contact_stress import ball_advice, von_mises_peak


@functools.cache
def contact_fatigue_table() -> dict[str, tuple[float, float, str]]:
    """name -> (hardness HRC min, contact strength S_c at 1e7 cycles MPa, source)."""
    text = resources.files("springcad.data").joinpath("contact_fatigue.csv").read_text()
    return {r["name"]: (float(r["hardness_HRC_min"]), float(r["contact_strength_MPa"]),
                        r["source"]) for r in csv.DictReader(text.splitlines())}


#: below this many cycles AGMA's stress-cycle chart has no values
CHART_START_CYCLES = 1e4


def contact_life_factor(cycles: float) -> float:
    """Stress-cycle factor Z_N of the contact strength (AGMA 2001-D04 Fig. 18, Shigley
    Fig. 14-15): 2.466 N^-0.056 from 1e4 to 1e7 cycles (1.47 at 1e4, 1 at 1e7), 1.4488
    N^-0.023 beyond (the upper, general-service line Shigley's examples use, e.g. 0.948 at
    1e8). Below 1e4 the line 2.466 N^-0.056 is extended (not charted: 1.68 at 1e3)."""
    if cycles > 1e7:
        return 1.4488 * cycles ** -0.023
    return 2.466 * cycles ** -0.056


def contact_life(p0_MPa: float, strength_MPa: float) -> float:
    """Cycles to pitting at Hertz pressure ``p0_MPa`` (the inverse of S_c Z_N(N); contact
    fatigue has no endurance limit)."""
    ratio = p0_MPa / strength_MPa
    if ratio <= 0:
        return math.inf
    if ratio >= contact_life_factor(1e7):
        return (ratio / 2.466) ** (-1 / 0.056)
    return (ratio / 1.4488) ** (-1 / 0.023)


def judged(duty_spec: DutySpec, theta_max_rad: float) -> bool:
    """Whether the duty is judged for contact fatigue: not a static/prototype duty, and at
    least :data:`CHART_START_CYCLES` cycles in all (below, the static contact rule
    governs)."""
    if duty.is_static(duty_spec):
        return False
    return sum(b.cycles for b in duty.blocks(duty_spec, theta_max_rad)) >= CHART_START_CYCLES


def _loads(duty_spec: DutySpec, theta_max_rad: float) -> list[tuple[float, float]]:
    """(cycles, load fraction of theta_max) of every block: |mean| + amplitude."""
    return [(b.cycles, min(abs(b.mean) + b.amplitude, 1.0))
            for b in duty.blocks(duty_spec, theta_max_rad)]


def _damage(loads, p0_MPa: float, strength_MPa: float) -> float:
    return sum(n / contact_life(p0_MPa * math.sqrt(f), strength_MPa) for n, f in loads if f > 0)


@functools.lru_cache(maxsize=1024)
def critical_p0_MPa(duty_spec: DutySpec, material_name: str, theta_max_rad: float) -> float:
    """The p0 at theta_max at which Miner's sum reaches 1 (MPa; inf without data):
    bisection on the monotone damage (relative tolerance 1e-9)."""
    row = contact_fatigue_table().get(material_name)
    if row is None:
        return math.inf
    loads = _loads(duty_spec, theta_max_rad)
    lo, hi = 1e-3, 1e7
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if _damage(loads, mid, row[1]) >= 1.0 else (mid, hi)
        if hi / lo - 1 < 1e-9:
            break
    return math.sqrt(lo * hi)


def allowable_p0_MPa(duty_spec: DutySpec, material_name: str, theta_max_rad: float) -> float:
    """Largest Hertz p0 at theta_max that meets the duty with its safety factor (MPa; inf
    when the duty is not judged or the material has no contact-fatigue data)."""
    if not judged(duty_spec, theta_max_rad):
        return math.inf
    return critical_p0_MPa(duty_spec, material_name, theta_max_rad) / duty_spec.safety_factor


def allowable_von_mises_MPa(material, theta_max_rad: float) -> float:
    """The contact von Mises stress at theta_max that keeps the ball's p0 within
    :func:`allowable_p0_MPa` (c_vm p0, MPa; inf when not judged): what the design step
    sizes its tip balls to, beside yield. Only a *declared* duty sizes the balls (as
    :func:`springcad.design.duty.required_margin` for the flexures); springcad's default
    duty of a job without ``[duty]`` is checked and gates the release.

    Args:
        material: a :class:`~springcad.config.MaterialSpec` (material and duty).
        theta_max_rad: the spring's maximum deflection (rad).
    """
    if not material.duty.declared:
        return math.inf
    p0 = allowable_p0_MPa(material.duty, material.material.name, theta_max_rad)
    if not math.isfinite(p0):
        return math.inf
    return von_mises_peak(round(float(material.material.poisson_ratio), 6))[0] * p0


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
    judged: bool = True
    """False: a duty below the chart's 1e4 cycles or static/prototype (reported only)."""

    @property
    def met(self) -> bool:
        return self.safety_factor >= self.required_safety_factor * (1.0 - 1e-6)

    def text(self) -> str:
        strength = (f"contact-fatigue strength S_c {self.strength_MPa:.0f} MPa at 1e7 cycles "
                    f"({self.hardness_HRC_min:g} HRC)")
        if not self.judged:
            return (f"tip ball Hertz pressure {self.p0_max_MPa:.0f} MPa at theta_max against the "
                    f"{strength}: not judged (a duty of fewer than 1e4 cycles or a static/prototype "
                    f"duty: below AGMA's chart, the static contact rule, von Mises against "
                    f"yield, governs); S_c Z_N at 1e4 cycles is "
                    f"{self.strength_MPa * contact_life_factor(CHART_START_CYCLES):.0f} MPa")
        life = self.life_at_max_cycles
        life_text = ("fewer than 1e4 cycles (below the chart)" if life < CHART_START_CYCLES
                     else f"{life:.3g} cycles")
        # the allowable first: a pressure above S_c (1e7 cycles) is met by a duty with
        # fewer full-deflection cycles, which read as a contradiction after S_c
        return (f"tip ball Hertz pressure {self.p0_max_MPa:.0f} MPa at theta_max, allowable "
                f"{self.allowable_MPa:.0f} MPa for this duty (its cycles by Miner's rule on the "
                f"{strength} and its S-N factor Z_N, with the required safety factor "
                f"{self.required_safety_factor:g}): Miner sum {self.miner_sum:.3g}, safety "
                f"factor {self.safety_factor:.2f}; life at +-theta_max {life_text}")

    def changes(self, force_N: float, r_tip_mm: float, thickness_mm: float, E_MPa: float,
                nu: float, contact_radius_mm: float, gap_mm: float, theta_max_rad: float,
                min_flank_position_mm: float) -> str:
        """The changes that would meet the duty, in numbers, for a ball pressed by
        ``force_N`` at full deflection ``theta_max_rad`` of a layout with contact radius
        ``contact_radius_mm`` and design gap ``gap_mm`` (mm): the tip balls whose contact
        meets the allowable on the flank radius they leave
        (:func:`~springcad.design.contact_stress.ball_advice`), and the disk thickness at
        the same force (p0 ~ thickness^-1/2)."""
        vm = von_mises_peak(round(float(nu), 6))[0] * self.allowable_MPa
        ball = ball_advice(force_N, contact_radius_mm, gap_mm, theta_max_rad, thickness_mm,
                           E_MPa, nu, vm, min_flank_position_mm, r_tip_mm)
        z_min = thickness_mm * (self.p0_max_MPa / self.allowable_MPa) ** 2
        return (f"p0 must fall to {self.allowable_MPa:.0f} MPa: {ball}; or thickness_mm >= "
                f"{z_min:.3g} (now {thickness_mm:g}) at the same force; or a harder material "
                "(springcad/data/contact_fatigue.csv) or a duty with fewer full-deflection "
                "cycles")

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
    critical = critical_p0_MPa(duty_spec, material_name, theta_max_rad)
    return ContactFatigueCheck(p0_max_MPa, sc, hrc,
                               _damage(_loads(duty_spec, theta_max_rad), p0_max_MPa, sc),
                               critical / p0_max_MPa, duty_spec.safety_factor,
                               contact_life(p0_max_MPa, sc),
                               critical / duty_spec.safety_factor, src,
                               judged(duty_spec, theta_max_rad))
