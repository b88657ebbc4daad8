"""When no design meets a spec: the nearest values of the user's own keys that would.

A refusal must name a change that works. For each key a user sets on a spring
(thickness, outer radius, deflection, stiffness) the spec is probed with the other keys
fixed: first at the far end of a plausible range, then by bisection towards the
user's value; the boundary is rounded outward to a value a person would write
(0.1 mm, 0.5 mm, 0.1 deg, 1 %) and that rounded value is checked once more with the
full design search, so what is printed is a value that designs.

Every probe stays inside the config schema's range of its key (a suggestion a user
cannot write is no suggestion). Beyond the single keys, two changes of several keys
are probed the same way: another built-in material with a higher energy density
sigma^2/E (its design stress scaled with the yield strength, both keys named), and the
spring split into m = 2..4 disks in series (each m x the stiffness over 1/m of the
deflection, the same torque and energy as the one it replaces). When no single key
works, the whole disk is scaled up, and when no scale works (a deflection-bound spec),
reshaped: thicker or larger in radius than in proportion.

The probe is any function ``designs(spec) -> bool`` (``designs_with(material)`` for the
material); :func:`springcad.design.search` passes the design search itself with a small
candidate budget. Units: mm, deg, N*m/rad, MPa.
"""

from __future__ import annotations

import math
import contextlib
from contextvars import ContextVar
from dataclasses import dataclass
from dataclasses import replace as _replace
from typing import Callable

from springcad.config import MaterialSpec, SpringSpec
from springcad.config.schema import keys as schema_keys
from springcad.materials import material_table
from springcad.units import NMM_PER_NM

#: design probes spent within :func:`probe_clock` (a one-item list per context, or None)
_PROBES: ContextVar[list[int] | None] = ContextVar("springcad_refusal_probes", default=None)


@contextlib.contextmanager
def probe_clock():
    """Within it, :func:`probes_spent` counts the design probes (:func:`count_probe`): the
    refusal's deadlines are probe counts, not seconds, so the same spec gets the same
    suggestions however loaded the machine."""
    token = _PROBES.set([0])
    try:
        yield
    finally:
        _PROBES.reset(token)


def count_probe() -> None:
    """One design probe spent (the design search's feasibility probe calls it)."""
    spent = _PROBES.get()
    if spent is not None:
        spent[0] += 1


def probes_spent() -> int:
    """Design probes spent within the innermost :func:`probe_clock` (0 outside one)."""
    spent = _PROBES.get()
    return spent[0] if spent is not None else 0


#: bisection steps per key (the boundary to ~1/32 of the searched span before rounding)
STEPS = 5
#: steps every key gets whatever the deadline (the boundary to 1/4 of the span)
MIN_STEPS = 2
#: disks in series probed for one that cannot be made (each m x K over theta / m)
SERIES_COUNTS = (2, 3, 4)
#: the design stress of a suggested material is rounded down to this step (MPa)
STRESS_STEP_MPA = 10.0
#: layout keys a user may fix that the design search otherwise chooses, with their units
FREE_CHOICES = (("n_flexures", ""), ("contact_radius_mm", " mm"), ("tip_radius_mm", " mm"),
                ("root_radius_mm", " mm"))
#: the largest factor a whole disk (thickness and outer radius together) is scaled by
MAX_SCALE = 2.5
#: outer-radius and thickness factors of the reshaped disks probed when no disk of the same
#: proportions designs (a uniform scale keeps the flexures' strain-limited angle)
RESHAPE_RADIUS_FACTORS = (1.0, 1.5, 2.0, 3.0)
RESHAPE_THICKNESS_FACTORS = (1.0, 1.5, 2.5, 5.0)


@dataclass(frozen=True)
class KeyRange:
    """One user key probed: its name in the config, how to read and set it on a spec,
    the far end of its search as a factor on the user's value, and the rounding step;
    ``nearer``: factors probed before the far end, nearest first, where the values that
    design may end before it (a thinner disk for stiff webs also carries less stress)."""

    key: str
    get: Callable[[SpringSpec], float]
    set: Callable[[SpringSpec, float], SpringSpec]
    far_factor: float
    step: float
    nearer: tuple[float, ...] = ()


def _keys(webs: bool = False) -> tuple[KeyRange, ...]:
    """The user keys probed, each towards the end that adds room: a thicker disk, a larger
    one, less deflection, a lower stiffness; with ``webs`` (the minimum webs hold the
    stiffness above the target) a thinner disk and a higher stiffness instead."""
    return (
        KeyRange("thickness_mm", lambda s: s.thickness_mm,
                 lambda s, v: _replace(s, thickness_mm=v), 0.4 if webs else 2.5, 0.1,
                 (0.85, 0.65) if webs else ()),
        KeyRange("outer_radius_mm", lambda s: s.outer_radius_mm,
                 lambda s, v: _replace(s, outer_radius_mm=v), 1.8, 0.5),
        KeyRange("max_deflection_deg", lambda s: math.degrees(s.max_deflection_rad),
                 lambda s, v: _replace(s, max_deflection_rad=math.radians(v)), 0.3, 0.1),
        KeyRange("target_stiffness_Nm_per_rad", lambda s: s.target_stiffness_Nmm_per_rad / NMM_PER_NM,
                 lambda s, v: _replace(s, target_stiffness_Nmm_per_rad=v * NMM_PER_NM),
                 3.0 if webs else 0.3, 0.0, (1.3, 1.8) if webs else ()),
    )


def _rounded(value: float, step: float, up: bool) -> float:
    """``value`` rounded outward to a multiple of ``step`` (or to 3 significant figures)."""
    if step <= 0:
        q = 10 ** (math.floor(math.log10(abs(value))) - 2)
        return (math.ceil if up else math.floor)(value / q) * q
    return round((math.ceil if up else math.floor)(value / step - 1e-9) * step, 6)


def nearest_changes(spec: SpringSpec, designs: Callable[[SpringSpec], bool],
                    keys: tuple[str, ...] | None = None,
                    deadline: float | None = None, webs: bool = False,
                    designs_each: Callable[[list], list] | None = None
                    ) -> list[tuple[str, float, float]]:
    """The nearest value of each user key at which the spec designs, other keys unchanged.

    Each key's far end (inside the schema's range; its nearer stops first when it has
    them) is probed first; only the keys whose far end designs are then bisected towards the user's value, all keys a step at a time,
    at least :data:`MIN_STEPS` steps and then until ``deadline`` (:func:`probes_spent`)
    passes: a key cut short keeps the nearest value its bisection had proven.
    Each value is then rounded outward to the key's step and kept when that designs too.

    Args:
        spec: the refused spring spec.
        designs: the probe (True when a spec designs).
        keys: config keys to probe (default thickness, outer radius, deflection, stiffness).
        deadline: the probe count after which refining stops (None: never).
        webs: the refusal's layouts were held stiff by their minimum webs: the thickness
            and stiffness are probed the other way (:func:`_keys`).
        designs_each: ``designs`` of a list of specs, in order (default one after another;
            the keys' probes of one round do not depend on each other, so a caller may run
            them on both cores: the same answers, so the same changes).

    Returns:
        (key, user value, suggested value) for every key whose change designs, in the
        order probed; the suggestion was itself checked by ``designs``.
    """
    each = designs_each or (lambda specs: [designs(s) for s in specs])
    ranges = [(kr, kr.get(spec), schema_keys("springs.<name>")[kr.key]) for kr in _keys(webs)
              if keys is None or kr.key in keys]
    # each key's nearer stops, then its far end, until one designs: round by round
    ends: dict[int, float] = {}
    trials = {i: [f for f in (min(max(v0 * factor, bound.lo), bound.hi)
                              for factor in (*kr.nearer, kr.far_factor)) if f != v0]
              for i, (kr, v0, bound) in enumerate(ranges)}
    while trials := {i: t for i, t in trials.items() if t and i not in ends}:
        answers = each([ranges[i][0].set(spec, t[0]) for i, t in trials.items()])
        for (i, t), yes in zip(trials.items(), answers):
            if yes:
                ends[i] = t[0]
            t.pop(0)
    open_keys = [(kr, v0, ends[i], bound) for i, (kr, v0, bound) in enumerate(ranges)
                 if i in ends]
    spans = [[v0, far] for _, v0, far, _ in open_keys]  # [fails, designs]
    for step in range(STEPS):  # every key one step at a time, so a deadline leaves all refined
        if step >= MIN_STEPS and deadline is not None and probes_spent() > deadline:
            break
        mids = [0.5 * (span[0] + span[1]) for span in spans]
        answers = each([kr.set(spec, mid) for (kr, *_), mid in zip(open_keys, mids)])
        for span, mid, yes in zip(spans, mids, answers):
            span[yes] = mid
    # the proven value rounded outward to the key's step (one probe each, also after the
    # deadline: a user buys 7.7 mm plate, not 7.6875), kept when it designs too
    rounded = [(span, min(max(_rounded(span[1], kr.step, kr.far_factor > 1), bound.lo),
                          bound.hi)) for (kr, _, _, bound), span in zip(open_keys, spans)]
    moved = [(span, value, kr) for (span, value), (kr, *_) in zip(rounded, open_keys)
             if value != span[1]]
    for (span, value, _), yes in zip(moved, each([kr.set(spec, v) for _, v, kr in moved])):
        if yes:
            span[1] = value
    return [(kr.key, v0, span[1]) for (kr, v0, _, _), span in zip(open_keys, spans)]


def fixed_choices(spec: SpringSpec) -> list[tuple[str, str]]:
    """The layout keys of :data:`FREE_CHOICES` the user fixed on ``spec`` (key, unit); not
    those springcad fixed for a shared camshaft (``spec.shared_camshaft``)."""
    return [(k, u) for k, u in FREE_CHOICES
            if getattr(spec, k) is not None and k not in spec.shared_camshaft]


def freed(spec: SpringSpec) -> SpringSpec:
    """``spec`` with every fixed layout key left to the design search."""
    return _replace(spec, **{k: None for k, _ in fixed_choices(spec)})


def _scaled(spec: SpringSpec, s: float) -> SpringSpec:
    """The disk's envelope scaled by ``s``: thickness and outer radius, each rounded up to
    its key's step (0.1 mm, 0.5 mm; :func:`_envelope`)."""
    return _envelope(spec, spec.thickness_mm * s, spec.outer_radius_mm * s)


def scaled_envelope(spec: SpringSpec, designs: Callable[[SpringSpec], bool],
                    deadline: float | None = None) -> SpringSpec | None:
    """The smallest disk of the same proportions that designs: thickness and outer
    radius scaled together by s (energy capacity ~ s^3 at the same stress, the tip balls'
    Hertz capacity ~ s^2), up to :data:`MAX_SCALE` and the schema's ranges, by bisection
    on s like :func:`nearest_changes`; the printed values are the ones checked.

    Returns:
        The scaled spec whose envelope designs, or None when the largest does not.
    """
    hi = MAX_SCALE
    for kr in _keys()[:2]:
        hi = min(hi, schema_keys("springs.<name>")[kr.key].hi / kr.get(spec))
    if hi <= 1.0 or not designs(_scaled(spec, hi)):
        return None
    span = [1.0, hi]  # [fails, designs]
    for step in range(STEPS):
        if step >= MIN_STEPS and deadline is not None and probes_spent() > deadline:
            break
        mid = 0.5 * (span[0] + span[1])
        span[designs(_scaled(spec, mid))] = mid
    return _scaled(spec, span[1])


def _envelope(spec: SpringSpec, thickness_mm: float, outer_radius_mm: float) -> SpringSpec:
    """``spec`` with another envelope, each key rounded up to its step (0.1 mm, 0.5 mm)
    and kept inside the schema's range."""
    z, ro = _keys()[0], _keys()[1]
    zb, rb = (schema_keys("springs.<name>")[k.key] for k in (z, ro))
    return _replace(spec, thickness_mm=min(_rounded(thickness_mm, z.step, True), zb.hi),
                    outer_radius_mm=min(_rounded(outer_radius_mm, ro.step, True), rb.hi))


def reshaped_envelope(spec: SpringSpec, designs: Callable[[SpringSpec], bool],
                      deadline: float | None = None) -> SpringSpec | None:
    """The lightest disk of other proportions that designs, when no scaled one does.

    A uniform scale keeps the reachable angle (the flexures' strain-limited deflection
    over the contact radius does not change with size), so a deflection-bound spec needs
    a disk larger in radius (longer flexures) or thicker (a smaller contact radius for
    the same tip-ball torque) than in proportion; and a thicker disk is not always
    better (its minimum webs stiffen a soft spring). The grid of
    :data:`RESHAPE_THICKNESS_FACTORS` x :data:`RESHAPE_RADIUS_FACTORS` is probed lightest
    first (volume z R_o^2); at the first envelope that designs, the thickness is bisected
    down towards the grid's next thinner plate of that radius (lighter, so already
    refused) like :func:`nearest_changes`, or for the user's own plate the radius down to
    the next smaller one. The printed values are the ones checked.

    Returns:
        The reshaped spec, or None when no envelope of the grid designs.
    """
    z0, r0 = spec.thickness_mm, spec.outer_radius_mm
    grid = sorted(((fz, fr) for fr in RESHAPE_RADIUS_FACTORS for fz in RESHAPE_THICKNESS_FACTORS
                   if (fz, fr) != (1.0, 1.0)), key=lambda g: g[0] * g[1] ** 2)
    for fz, fr in grid:
        if not designs(_envelope(spec, z0 * fz, r0 * fr)):
            continue
        # the lighter neighbour on the grid (refused): a thinner plate of this radius, or
        # for the user's own plate, a smaller radius
        if fz > 1.0:
            lighter = max(f for f in RESHAPE_THICKNESS_FACTORS if f < fz)
            envelope = lambda v: _envelope(spec, v, r0 * fr)  # noqa: E731
            span = [z0 * lighter, z0 * fz]  # [fails, designs]
        else:
            lighter = max(f for f in RESHAPE_RADIUS_FACTORS if f < fr)
            envelope = lambda v: _envelope(spec, z0, v)  # noqa: E731
            span = [r0 * lighter, r0 * fr]
        for step in range(STEPS):
            if step >= MIN_STEPS and deadline is not None and probes_spent() > deadline:
                break
            mid = 0.5 * (span[0] + span[1])
            span[designs(envelope(mid))] = mid
        return envelope(span[1])
    return None


def _disk_text(spec: SpringSpec, big: SpringSpec, how: str, freed_keys) -> str:
    """The clause naming a whole-disk change (``how``: "scaled" or "reshaped"), e.g. "the
    disk scaled by 1.76: springs.A.thickness_mm = 7.9 (now 4.5) and ..., all together"."""
    name = f"springs.{spec.name}"
    changed = [k for k in ("thickness_mm", "outer_radius_mm")
               if getattr(big, k) != getattr(spec, k)]
    if how == "scaled":
        head = f"the disk scaled by {big.thickness_mm / spec.thickness_mm:.2f}"
    else:
        head = {("thickness_mm",): "a thicker disk", ("outer_radius_mm",): "a larger disk"
                }.get(tuple(changed), "a disk of other proportions")
    clauses = [f"{name}.{k} = {getattr(big, k):g} (now {getattr(spec, k):g})" for k in changed]
    if freed_keys:
        clauses.append(", ".join(f"{name}.{k} removed (now {getattr(spec, k):g}{u})"
                                 for k, u in freed_keys))
    together = ", all together" if len(changed) + len(freed_keys) > 1 else ""
    return f"{head}: {' and '.join(clauses)}{together}"


def larger_disk(spec: SpringSpec, designs: Callable[[SpringSpec], bool],
                deadline: float | None = None) -> tuple[str, SpringSpec | None]:
    """A change of several keys when none alone works: the whole disk scaled up
    (:func:`scaled_envelope`), else reshaped (:func:`reshaped_envelope`), with the user's
    fixed layout keys left free when that is what it takes.

    Returns:
        (text, spec): "the disk scaled by 1.76: springs.A.thickness_mm = 7.9 (now 4.5) and
        ..., all together" and the spec it names, or ("", None) when no probed disk
        designs.
    """
    fixed = fixed_choices(spec)
    trials = [spec, freed(spec)] if fixed else [spec]
    # a scaled disk (the user's layout kept, then freed) before any reshaped one: a scale
    # freeing a fixed ball is a far lighter change than a plate 4 x thicker that keeps it
    for search, how in ((scaled_envelope, "scaled"), (reshaped_envelope, "reshaped")):
        for trial in trials:
            big = search(trial, designs, deadline=deadline)
            if big is not None:
                freed_keys = fixed if trial is not spec else ()
                return _disk_text(spec, big, how, freed_keys), big
    return "", None


def in_series(spec: SpringSpec, m: int) -> SpringSpec:
    """``spec`` as one of ``m`` equal disks in series replacing it: m x the stiffness over
    1/m of the deflection (same peak torque, 1/m of the energy each)."""
    return _replace(spec, target_stiffness_Nmm_per_rad=spec.target_stiffness_Nmm_per_rad * m,
                    max_deflection_rad=spec.max_deflection_rad / m)


def fewer_disks(spec: SpringSpec, copies: int,
                designs: Callable[[SpringSpec], bool]) -> str:
    """When a stack holds ``copies`` of a disk that cannot be made: the same stack with
    fewer of them, each deflecting more (m of them as one: K / m over m theta, the same
    torque and energy), for the fewest merges m dividing ``copies`` that design. A small
    deflection per disk leaves the tip ball a short, sharp flank (radius r_c theta - r_b -
    w_gap), which fewer disks lengthen.

    Returns:
        "'A' 3 times in stack.sequence where it is 6 times, each springs.A.target_..."
        or "" when no merge designs.
    """
    for m in range(2, copies + 1):
        if copies % m:
            continue
        one = in_series(spec, 1.0 / m)
        if designs(one):
            return (f"'{spec.name}' {copies // m} times in stack.sequence where it is {copies} "
                    f"times, each springs.{spec.name}.target_stiffness_Nm_per_rad = "
                    f"{one.target_stiffness_Nmm_per_rad / NMM_PER_NM:.4g}, max_deflection_deg = "
                    f"{math.degrees(one.max_deflection_rad):.4g}")
    return ""


def series_change(spec: SpringSpec, designs: Callable[[SpringSpec], bool]) -> int | None:
    """The fewest disks in series (of :data:`SERIES_COUNTS`) whose each designs, or None."""
    return next((m for m in SERIES_COUNTS if designs(in_series(spec, m))), None)


def as_material(material: MaterialSpec, name: str) -> MaterialSpec:
    """``material`` with the built-in ``name`` instead, its design stress scaled with the
    yield strength and rounded down to :data:`STRESS_STEP_MPA` (MPa), the margin kept."""
    other = material_table()[name]
    sigma = material.design_stress_MPa * other.yield_strength_MPa / \
        material.material.yield_strength_MPa
    sigma = math.floor(sigma / STRESS_STEP_MPA) * STRESS_STEP_MPA
    return _replace(material, material=other, design_stress_MPa=float(sigma))


def material_changes(material: MaterialSpec,
                     designs_with: Callable[[MaterialSpec], bool]) -> list[MaterialSpec]:
    """Built-in materials storing more energy per volume (sigma^2 / E at the scaled
    design stress) than ``material`` with which the spring designs, best first."""
    def density(m: MaterialSpec) -> float:
        return m.design_stress_MPa ** 2 / m.material.youngs_modulus_MPa

    others = sorted((as_material(material, n) for n in material_table()
                     if n != material.material.name), key=density, reverse=True)
    return [m for m in others if density(m) > density(material) and designs_with(m)]


def material_clause(material: MaterialSpec) -> str:
    """The clause naming a change of material, e.g. ``material.name = "maraging_300" with
    material.design_stress_MPa = 1320``."""
    return (f'material.name = "{material.material.name}" with material.design_stress_MPa = '
            f"{material.design_stress_MPa:g}")


def key_clause(spring_name: str, key: str, now: float, value: float) -> str:
    """The clause naming one key's change, e.g. "springs.A.thickness_mm = 6.3 (now 5)"."""
    return f"springs.{spring_name}.{key} = {value:g} (now {now:.4g})"


def with_key(spec: SpringSpec, key: str, value: float) -> SpringSpec:
    """``spec`` with the user key ``key`` (a :func:`nearest_changes` key, in the config's
    unit) set to ``value``."""
    return next(kr for kr in _keys() if kr.key == key).set(spec, value)


#: other materials a refusal names at most (the best first)
MATERIALS_NAMED = 2


def describe(spring_name: str, changes: list[tuple[str, float, float]],
             materials: list[MaterialSpec] = (), series: int | None = None,
             spec: SpringSpec | None = None, webs: bool = False) -> str:
    """One clause naming the changes, e.g. "springs.A.thickness_mm = 6.3 (now 5)".

    ``materials`` (:func:`material_changes`) and ``series`` (:func:`series_change`, with
    the refused ``spec``) add their clauses when given; ``webs``: the keys were probed as
    :func:`_keys` does for layouts held stiff by their webs (said when none designs).
    """
    clauses = [key_clause(spring_name, k, v0, v) for k, v0, v in changes]
    clauses += [material_clause(m) for m in materials[:MATERIALS_NAMED]]
    if series is not None and spec is not None:
        one = in_series(spec, series)
        clauses.append(
            f"{series} disks in series in its place (each springs.{spring_name}."
            f"target_stiffness_Nm_per_rad = {one.target_stiffness_Nmm_per_rad / NMM_PER_NM:.4g}, "
            f"max_deflection_deg = {math.degrees(one.max_deflection_rad):.4g}, and "
            f"each '{spring_name}' in stack.sequence written {series} times)")
    if not clauses:
        probed = [f"{kr.key} (to {kr.far_factor:g}x)" for kr in _keys(webs)]
        probed = ", ".join(probed[:-1]) + " or " + probed[-1]
        return (f"no change of {probed} alone, no stronger built-in material and no "
                f"{SERIES_COUNTS[-1]} disks in series design: a larger change or several keys")
    return "feasible with " + " or ".join(clauses) + " (each alone, other keys unchanged)"
