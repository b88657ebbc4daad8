"""The duty of a spring: what it will see in service, and whether it lasts.

A duty is a set of blocks, each ``cycles`` cycles of deflection ``mean +- amplitude``
(fractions of the spring's theta_max, or rad), from a named preset
(:data:`PRESETS`), from the job's ``[[duty.blocks]]`` or from a deflection time
series counted by rainflow (:func:`rainflow`, ASTM E1049-85 sec. 5.4.4).

The flexure stress is linear in the deflection (linear elasticity, the cam pushes
either flank), so a block's stress at a point whose von Mises stress at theta_max
is ``peak`` is amplitude ``peak |a|`` about mean ``peak |m|``: the edge whose mean
is tensile is the critical one (the other edge sees the same amplitude in
compression). For every block:

* Goodman (Haigh diagram): the equivalent fully reversed amplitude
  sigma_ar = sigma_a / (1 - sigma_m / S_ut) (sigma_m >= 0);
* S-N of the part (:func:`springcad.design.fatigue.part_curve`: Marin surface,
  size and reliability factors) gives the life N of sigma_ar; damage n / N;
* Miner's sum D over the blocks (Palmgren-Miner, blocks below the endurance limit
  do no damage).

The fatigue safety factor is the factor on stress that brings D to 1 (every
block's stress scaled by it, so the Goodman mean scales too); the duty is met
when it is at least the required ``duty.safety_factor``. Since D depends only on
the peak times that factor, the largest allowed peak at theta_max is the peak at
which D = 1 divided by the required factor (:func:`allowed_peak_MPa`), and the
*fatigue-rated deflection* is theta_max x achieved factor / required factor: the
largest theta_max at which the same duty (same fractions) is still met.

Units: MPa, rad, cycles.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

from springcad.config.specs import DutyBlock, DutySpec, MaterialSpec
from springcad.design import fatigue
from springcad.design.feasibility import larger_disk, nearest_changes
from springcad.design.feasibility import describe as feasibility_text
from springcad.materials import material_table
from springcad.units import NMM_PER_NM

#: named duties: (blocks as fractions of theta_max, basis, static/prototype)
PRESETS: dict[str, tuple[tuple[DutyBlock, ...], str, bool]] = {
    "static": (
        (DutyBlock(1e3, 1.0, 0.0, "fraction", "bench and prototype use at +-theta_max"),),
        "static/prototype: 1e3 full reversals, a bench campaign of a prototype (ODOP's life "
        "category 1 'static' is < 1e4 cycles). Released as 'rated for 1e3 cycles'; not for "
        "cyclic service.", True),
    "robot_joint": (
        (DutyBlock(1e7, 0.5, 0.0, "fraction", "walking/working at half deflection"),
         DutyBlock(1e5, 1.0, 0.0, "fraction", "peaks at full deflection")),
        "springcad's default for a robotic spring (engineering judgement, not a standard): "
        "1e7 reversals at +-0.5 theta_max (about 3000 h of work at 1 Hz, the top of the "
        "1e5-1e7 ratings of spring software, e.g. ODOP's life categories) and 1e5 reversals "
        "at +-theta_max (impacts and peak torques, 1 % of the cycles).", False),
    "series_elastic_actuator": (
        (DutyBlock(1e7, 0.3, 0.0, "fraction", "torque control about zero"),
         DutyBlock(1e6, 0.7, 0.0, "fraction", "large motions"),
         DutyBlock(1e4, 1.0, 0.0, "fraction", "torque limit")),
        "series elastic actuator (engineering judgement, not a standard): 1e7 reversals at "
        "+-0.3 theta_max (torque control), 1e6 at +-0.7 theta_max, 1e4 at the torque limit "
        "+-theta_max.", False),
    "prosthesis": (
        (DutyBlock(3e6, 0.5, 0.5, "fraction", "gait: 0 to theta_max"),),
        "prosthesis: 3e6 load cycles from zero to the full test load, the cyclic test of ISO "
        "10328:2016 (lower-limb prostheses, 3e6 cycles; ISO 22675:2016 for ankle-foot units "
        "asks 2e6); about 2-3 years of walking at 1-1.5 million steps a year. The spring is "
        "taken loaded one way (stance), 0 to +theta_max.", False),
}


# ====================================================================== rainflow
def turning_points(series) -> list[float]:
    """The reversals of a series (plateaus and monotone runs removed)."""
    out: list[float] = []
    for x in series:
        x = float(x)
        if out and x == out[-1]:
            continue
        if len(out) >= 2 and (out[-1] - out[-2]) * (x - out[-1]) > 0:
            out[-1] = x  # still going the same way
        else:
            out.append(x)
    return out


def rainflow(series) -> list[tuple[float, float, float]]:
    """Rainflow counting, ASTM E1049-85 (reapproved 2017) sec. 5.4.4.

    Returns:
        (range, mean, count) of every counted cycle, count 1.0 or 0.5 (half cycles).
    """
    out: list[tuple[float, float, float]] = []
    stack: list[float] = []
    for point in turning_points(series):
        stack.append(point)
        while len(stack) >= 3:
            x = abs(stack[-1] - stack[-2])
            y = abs(stack[-2] - stack[-3])
            if x < y:
                break
            if len(stack) == 3:  # Y contains the starting point: count it as a half cycle
                out.append((y, 0.5 * (stack[0] + stack[1]), 0.5))
                stack.pop(0)
            else:
                out.append((y, 0.5 * (stack[-2] + stack[-3]), 1.0))
                last = stack.pop()
                stack.pop()
                stack.pop()
                stack.append(last)
    for a, b in zip(stack, stack[1:]):
        out.append((abs(b - a), 0.5 * (a + b), 0.5))
    return out


def series_blocks(series, unit: str, repeats: float = 1.0) -> tuple[DutyBlock, ...]:
    """The rainflow cycles of a deflection series as duty blocks (equal cycles merged)."""
    merged: dict[tuple[float, float], float] = {}
    for rng, mean, count in rainflow(series):
        if rng <= 0.0:
            continue
        key = (round(0.5 * rng, 12), round(mean, 12))
        merged[key] = merged.get(key, 0.0) + count * repeats
    return tuple(DutyBlock(n, a, m, unit, f"rainflow {i + 1}")
                 for i, ((a, m), n) in enumerate(sorted(merged.items(), reverse=True)))


# ====================================================================== the duty
@functools.lru_cache(maxsize=256)
def blocks(duty: DutySpec, theta_max_rad: float) -> tuple[DutyBlock, ...]:
    """The duty's blocks as fractions of ``theta_max_rad`` (rad); cached (a time series is
    counted once)."""
    if duty.preset is not None:
        raw = PRESETS[duty.preset][0]
    elif duty.series:
        raw = series_blocks(duty.series, duty.series_unit, duty.series_repeats)
    else:
        raw = duty.blocks
    return tuple(b if b.unit == "fraction" else
                 replace(b, amplitude=b.amplitude / theta_max_rad, mean=b.mean / theta_max_rad,
                         unit="fraction") for b in raw)


def describe(duty: DutySpec) -> str:
    """One line: which duty, and where it comes from."""
    if duty.preset is not None:
        text = f"preset '{duty.preset}'" + ("" if duty.declared else " (springcad's default)")
    elif duty.series:
        text = (f"rainflow count of {duty.series_file or 'a time series'} "
                f"x {duty.series_repeats:g}")
    else:
        parts = [f"{b.cycles:.3g} x " + (
            (f"{b.mean:+.2f} " if b.mean else "") + f"+-{b.amplitude:.2f} theta_max"
            if b.unit == "fraction" else (f"{math.degrees(b.mean):+.1f} " if b.mean else "")
            + f"+-{math.degrees(b.amplitude):.1f} deg") for b in duty.blocks[:4]]
        more = f" and {len(duty.blocks) - 4} more" if len(duty.blocks) > 4 else ""
        text = f"blocks {', '.join(parts)}{more}"
    return (f"{text}; surface {duty.surface}, reliability {duty.reliability:g}, required "
            f"fatigue safety factor {duty.safety_factor:g}")


def source(duty: DutySpec) -> str:
    """Where the duty's cycle counts come from."""
    if duty.preset is not None:
        return PRESETS[duty.preset][1]
    if duty.series:
        return f"rainflow count (ASTM E1049-85) of {duty.series_file or 'a time series'}"
    return "the job's [[duty.blocks]]"


def is_static(duty: DutySpec) -> bool:
    """A static/prototype duty: released with 'rated for N cycles at ...'."""
    return duty.preset is not None and PRESETS[duty.preset][2]


# ====================================================================== evaluation
#: what an infinite life is called in every output (console, JSON text, report, drawing)
INFINITE_LIFE = "infinite (stress below the endurance limit: no failure predicted)"


def life_text(cycles: float | None) -> str:
    """A life in cycles as text: ``INFINITE_LIFE`` for inf or None (JSON's infinite life)."""
    if cycles is None or math.isinf(cycles):
        return INFINITE_LIFE
    return f"{cycles:.3g} cycles"


def goodman_amplitude(amplitude_MPa: float, mean_MPa: float, ultimate_MPa: float) -> float:
    """Equivalent fully reversed amplitude sigma_a / (1 - sigma_m / S_ut) (MPa; inf at or
    beyond S_ut; a compressive mean is given no credit)."""
    mean = max(mean_MPa, 0.0)
    if mean >= ultimate_MPa:
        return math.inf
    return amplitude_MPa / (1.0 - mean / ultimate_MPa)


def _damage(bl, curve: fatigue.SNCurve, ultimate_MPa: float, peak_MPa: float) -> float:
    total = 0.0
    for b in bl:
        life = curve.life(goodman_amplitude(peak_MPa * b.amplitude, peak_MPa * abs(b.mean),
                                            ultimate_MPa))
        total += b.cycles / life
    return total


def critical_peak_MPa(bl, curve: fatigue.SNCurve, ultimate_MPa: float) -> float:
    """The peak at theta_max at which Miner's sum reaches 1 (MPa): bisection on the
    monotone damage (relative tolerance 1e-9)."""
    lo, hi = 1e-3, 1e6
    if _damage(bl, curve, ultimate_MPa, hi) < 1.0:
        return hi
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if _damage(bl, curve, ultimate_MPa, mid) >= 1.0:
            hi = mid
        else:
            lo = mid
        if hi / lo - 1.0 < 1e-9:
            break
    return math.sqrt(lo * hi)


@dataclass(frozen=True)
class BlockResult:
    """One block at the critical point (MPa, cycles)."""

    label: str
    cycles: float
    amplitude_fraction: float
    mean_fraction: float
    amplitude_deg: float
    mean_deg: float
    amplitude_MPa: float
    mean_MPa: float
    equivalent_amplitude_MPa: float
    life_cycles: float
    damage: float

    def to_dict(self) -> dict:
        d = dict(self.__dict__)
        d["life_cycles"] = None if math.isinf(self.life_cycles) else self.life_cycles
        return d


@dataclass(frozen=True)
class DutyCheck:
    """The duty judged at one stress point (the critical one: the largest damage).

    Attributes:
        peak_MPa: von Mises stress at theta_max at the point (MPa).
        blocks: per block amplitude, mean, Goodman amplitude, life and damage.
        miner_sum: Miner's sum D of the duty.
        safety_factor: factor on stress that brings D to 1 (-).
        required_safety_factor: the duty's required factor.
        life_at_max_cycles: cycles to failure at +-theta_max (inf: below the endurance
            limit, no failure predicted).
        rated_deflection_rad: largest theta_max meeting the duty with its factor (rad).
        allowed_peak_MPa: largest peak at theta_max meeting the duty with its factor.
    """

    duty: DutySpec
    material: str
    where: str
    theta_max_rad: float
    peak_MPa: float
    curve: fatigue.SNCurve
    ultimate_strength_MPa: float
    polished_endurance_limit_MPa: float
    surface_factor: float
    reliability_factor: float
    blocks: tuple[BlockResult, ...]
    miner_sum: float
    safety_factor: float
    life_at_max_cycles: float
    allowed_peak_MPa: float
    material_source: str

    @property
    def required_safety_factor(self) -> float:
        return self.duty.safety_factor

    @property
    def met(self) -> bool:
        return self.safety_factor >= self.required_safety_factor * (1.0 - 1e-6)

    @property
    def rated_deflection_rad(self) -> float:
        return self.theta_max_rad * self.safety_factor / self.required_safety_factor

    @property
    def static(self) -> bool:
        return is_static(self.duty)

    def rating_text(self) -> str:
        """One line for the console and the drawing."""
        deg = math.degrees(self.theta_max_rad)
        life = life_text(self.life_at_max_cycles)
        if self.static:
            return (f"rated for {PRESETS[self.duty.preset][0][0].cycles:.3g} cycles at "
                    f"+-{deg:.1f} deg (static/prototype duty; life at +-theta_max {life}); "
                    "not for cyclic service")
        return (f"duty {'met' if self.met else 'NOT met'}: Miner sum {self.miner_sum:.3g}, "
                f"fatigue safety factor {self.safety_factor:.2f} (required "
                f"{self.required_safety_factor:g}); life at +-{deg:.1f} deg {life}; "
                f"fatigue-rated deflection {math.degrees(self.rated_deflection_rad):.1f} deg")

    def to_dict(self) -> dict:
        life = self.life_at_max_cycles
        return {
            "duty": describe(self.duty),
            "duty_source": source(self.duty),
            "declared": self.duty.declared,
            "static_prototype": self.static,
            "where": self.where,
            "material": self.material,
            "criterion": "Goodman (Haigh) equivalent amplitude, Basquin S-N of the part, "
                         "Palmgren-Miner sum; safety factor on stress",
            "peak_at_max_deflection_MPa": self.peak_MPa,
            "max_deflection_deg": math.degrees(self.theta_max_rad),
            "ultimate_strength_MPa": self.ultimate_strength_MPa,
            "polished_endurance_limit_MPa": self.polished_endurance_limit_MPa,
            "surface": self.duty.surface,
            "surface_factor": self.surface_factor,
            "reliability": self.duty.reliability,
            "reliability_factor": self.reliability_factor,
            "size_factor": fatigue.SIZE_FACTOR,
            "endurance_limit_MPa": self.curve.endurance_limit_MPa,
            "cycles_at_endurance": self.curve.cycles_at_endurance,
            "low_cycle_strength_MPa": self.curve.low_cycle_strength_MPa,
            "has_endurance_limit": self.curve.has_endurance_limit,
            "sn_exponent": self.curve.exponent,
            "blocks": [b.to_dict() for b in self.blocks],
            "miner_sum": self.miner_sum,
            "safety_factor": self.safety_factor,
            "required_safety_factor": self.required_safety_factor,
            "met": self.met,
            "life_at_max_deflection_cycles": None if math.isinf(life) else life,
            "fatigue_rated_deflection_deg": math.degrees(self.rated_deflection_rad),
            "allowed_peak_MPa": self.allowed_peak_MPa,
            "rating": self.rating_text(),
            "material_source": self.material_source,
        }


def check(duty: DutySpec, material_name: str, peak_MPa: float, theta_max_rad: float,
          where: str = "predicted peak") -> DutyCheck | None:
    """The duty at a point whose von Mises stress at theta_max is ``peak_MPa``.

    Returns None for a material without fatigue data (``springcad/data/fatigue.csv``).
    """
    props = fatigue.fatigue_table().get(material_name)
    if props is None:
        return None
    curve = fatigue.part_curve(props, duty.surface, duty.reliability)
    sut = props.ultimate_strength_MPa
    bl = blocks(duty, theta_max_rad)
    results = []
    for b in bl:
        sa, sm = peak_MPa * b.amplitude, peak_MPa * abs(b.mean)
        sar = goodman_amplitude(sa, sm, sut)
        life = curve.life(sar)
        results.append(BlockResult(
            b.label, b.cycles, b.amplitude, b.mean, math.degrees(b.amplitude * theta_max_rad),
            math.degrees(b.mean * theta_max_rad), sa, sm, sar, life, b.cycles / life))
    critical = critical_peak_MPa(bl, curve, sut)
    return DutyCheck(duty, props.name, where, theta_max_rad, peak_MPa, curve, sut,
                     props.endurance_limit_MPa, fatigue.surface_table()[duty.surface].factor,
                     fatigue.reliability_factor(duty.reliability), tuple(results),
                     sum(r.damage for r in results), critical / peak_MPa,
                     curve.life(peak_MPa), critical / duty.safety_factor, props.source)


def allowed_peak_MPa(material: MaterialSpec, theta_max_rad: float) -> float:
    """Largest von Mises peak at theta_max that meets the duty with its safety factor
    (MPa; inf for a material without fatigue data)."""
    return _allowed_peak_MPa(material.duty, material.material.name, theta_max_rad)


@functools.lru_cache(maxsize=4096)
def _allowed_peak_MPa(duty_spec: DutySpec, material_name: str, theta_max_rad: float) -> float:
    """:func:`allowed_peak_MPa` cached: the design search asks it in every stress pass."""
    c = check(duty_spec, material_name, 1.0, theta_max_rad)
    return math.inf if c is None else c.allowed_peak_MPa


def required_margin(material: MaterialSpec, theta_max_rad: float) -> float:
    """The yield margin (yield / peak) a design needs for yield AND the duty (-):
    yield / min(yield / safety_factor, :func:`allowed_peak_MPa`).

    Only a *declared* duty sizes the design (a job with a ``[duty]`` table). springcad's
    default duty of a job without one is checked and reported, and gates the release,
    but does not resize the springs: most envelopes written for a yield margin alone
    cannot carry it, and refusing them would hide the design the job asked for.
    """
    if not material.duty.declared:
        return material.safety_factor
    y = material.material.yield_strength_MPa
    return max(material.safety_factor, y / allowed_peak_MPa(material, theta_max_rad))


def fatigue_limited(material: MaterialSpec, theta_max_rad: float) -> bool:
    """Whether the duty, not the yield margin, sets the allowed peak."""
    return required_margin(material, theta_max_rad) > material.safety_factor * (1 + 1e-9)


def sized_for(material: MaterialSpec) -> MaterialSpec:
    """``material`` with its duty declared: a job without ``[duty]`` gets springcad's default
    duty, which sizes the spring when its envelope can carry it and gates the release."""
    return replace(material, duty=replace(material.duty, declared=True))


def biased(material: MaterialSpec, bias: float) -> MaterialSpec:
    """The material spec with both safety factors (yield and duty) raised by ``bias`` (the
    FEA stress correction: the FEA found the peak ``bias`` x the design's prediction)."""
    return replace(material, safety_factor=material.safety_factor * bias,
                   duty=replace(material.duty, safety_factor=material.duty.safety_factor * bias))


# ====================================================================== refusals
#: how :func:`alternatives` ends when no change it probes meets the duty
NOTHING_MEETS = ": relax the duty"


def alternatives(spec, material: MaterialSpec, designs, deadline: float | None = None
                 ) -> tuple[str, tuple]:
    """When a declared duty sets the allowed peak and the envelope cannot meet it: the
    changes beyond the spring's own keys that would, each checked with ``designs``.

    Args:
        spec: the :class:`~springcad.config.SpringSpec` refused.
        material: its material spec (with the duty).
        designs: ``designs(spec, material) -> bool``, the design search as a probe.
        deadline: the probe count after which the nearest-value bisection stops refining
            (:func:`springcad.design.feasibility.probes_spent`; None: never).

    Returns:
        (text, disk): "" or text to append to the refusal: a better surface finish,
        another material with fatigue data, or the spring split into two disks in series
        (each twice the stiffness at half the deflection; a stack of n such disks needs
        n+1); when none alone: the best surface with the nearest thickness, outer radius
        or deflection, else with the whole disk larger
        (:func:`~springcad.design.feasibility.larger_disk`; the user's fixed layout keys
        left free when that is what it takes). ``disk``: that last change as ``(clause,
        spec, surface)`` for the job's check with its hardware, else ().
    """
    if not fatigue_limited(material, spec.max_deflection_rad):
        return "", ()
    found = []
    surfaces = fatigue.surface_table()
    now = surfaces[material.duty.surface].factor
    for name, s in sorted(surfaces.items(), key=lambda kv: kv[1].factor):
        if s.factor > now and designs(spec, replace(material, duty=replace(material.duty,
                                                                          surface=name))):
            found.append(f'manufacturing.surface = "{name}" (now "{material.duty.surface}", '
                         f"surface factor {s.factor:g} vs {now:g})")
            break
    y = material.material.yield_strength_MPa
    for name in fatigue.fatigue_table():
        m = material_table().get(name)
        if m is None or name == material.material.name:
            continue
        ratio = m.yield_strength_MPa / y
        other = replace(material, material=m, design_stress_MPa=material.design_stress_MPa * ratio)
        if allowed_peak_MPa(other, spec.max_deflection_rad) <= allowed_peak_MPa(
                material, spec.max_deflection_rad):
            continue
        if designs(spec, other):
            found.append(f'material.name = "{name}" (now "{material.material.name}")')
    split = replace(spec, target_stiffness_Nmm_per_rad=2 * spec.target_stiffness_Nmm_per_rad,
                    max_deflection_rad=0.5 * spec.max_deflection_rad)
    if designs(split, material):
        found.append(f"one more disk in series: this spring as two disks of "
                     f"{2 * spec.target_stiffness_Nmm_per_rad / NMM_PER_NM:.4g} N*m/rad at "
                     f"{math.degrees(split.max_deflection_rad):.2f} deg each")
    allowed = allowed_peak_MPa(material, spec.max_deflection_rad)
    head = (f"; the duty ({describe(material.duty)}) allows a peak of {allowed:.0f} MPa at "
            f"theta_max")
    if found:
        return head + "; it is also met with " + " or ".join(found), ()
    # nothing alone: the best surface together with the nearest thickness, radius, deflection
    best = max(surfaces.values(), key=lambda x: x.factor)
    better = replace(material, duty=replace(material.duty, surface=best.name))
    changes = nearest_changes(spec, lambda s: designs(s, better), keys=(
        "thickness_mm", "outer_radius_mm", "max_deflection_deg"), deadline=deadline)
    if changes:
        return (head + f'; no surface finish, material or extra disk alone meets it; with '
                f'manufacturing.surface = "{best.name}" it is '
                + feasibility_text(spec.name, changes)), ()
    head += ("; no surface finish, material or extra disk alone meets it, nor the best surface "
             "with another thickness, outer radius or deflection")
    # several keys: the whole disk larger (the user's fixed layout keys left free too)
    big, bigger = larger_disk(spec, lambda s: designs(s, better), deadline=deadline)
    if big:
        return (head + f'; it is met with manufacturing.surface = "{best.name}" and {big}',
                (big, bigger, best.name))
    return (head + ", nor a larger or reshaped disk with the best surface" + NOTHING_MEETS,
            ())
