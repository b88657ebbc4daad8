"""The design search: from a :class:`~springcad.config.SpringSpec` to a :class:`SpringDesign`.

Every parameter the user did not fix is searched, every rule that can fail later is
checked on the design's own exact profiles (:func:`springcad.design.resize.with_width`
builds the ring and cam), and the choice is deterministic and explained:

1. Layouts (N, r_c, tip ball, root radius) come ranked from
   :func:`springcad.design.layout.candidate_layouts`: the reference method's choice
   first, then every other flexure count that fits, each at its best contact radius.
2. For each, the flexure shape and widths at the design stress, the root flare with the
   lowest predicted peak, and the stress passes that keep the yield margin
   (:mod:`springcad.design.sizing`).
3. The first layout that passes every rule is the design; ``design_choice`` says which
   layouts were tried before it and why each was rejected.
4. When none passes, the refusal names the binding rule and the nearest values of the
   user's own keys that would pass (:mod:`springcad.design.feasibility`).

Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import re
from dataclasses import replace as _replace

from springcad.config import HardwareSpec, ManufacturingSpec, MaterialSpec, SpringSpec
from springcad.config.consistency import min_rim_mm
from springcad.design import duty
from springcad.design.balls import with_larger_ball
from springcad.design.feasibility import (MATERIALS_NAMED, count_probe, describe, fixed_choices,
                                          larger_disk, material_changes, material_clause,
                                          nearest_changes, probe_clock, probes_spent,
                                          series_change)
from springcad.design.flexure import without_shape_detail
from springcad.design.layout import MAX_CANDIDATES, Layout
from springcad.design.resize import WebsHoldStiffness, stiffness_out_of_reach, widening_room_short
from springcad.design.shortfalls import margin_shortfall, profile_defect, soft_shortfalls
from springcad.design.sizing import _design_with_margin, _NoMoreLayouts
from springcad.design.spring import SpringDesign
from springcad.errors import DesignError, SpecInfeasible
from springcad.parallel import each_on_two_cores
from springcad.progress import report

def short_reason(err: Exception) -> str:
    """An error's message without the spring's name prefix."""
    text = str(err)
    return text.split("': ", 1)[1] if text.startswith("spring '") and "': " in text else text


def design_spring(spec: SpringSpec, material: MaterialSpec, manufacturing: ManufacturingSpec,
                  hardware: HardwareSpec, explain: bool = True,
                  max_root_radius_mm: float = math.inf,
                  candidates: int = MAX_CANDIDATES) -> SpringDesign:
    """Synthesise one spring for yield and its duty (:func:`design_for_margin`).

    A job that declares no ``[duty]`` gets springcad's default duty
    (:data:`springcad.config.specs.DEFAULT_DUTY_PRESET`): the spring is sized for it when
    its envelope can carry it, else for the yield margin alone, and the duty check then
    gates the release with the rated life and the change that would meet it
    (:func:`springcad.design.duty.required_margin`).
    """
    if not material.duty.declared:
        with kept_layouts():
            return _for_default_duty(spec, material, manufacturing, hardware, explain,
                                     max_root_radius_mm, candidates)
    return design_for_margin(spec, material, manufacturing, hardware, explain,
                             max_root_radius_mm, candidates)


def _for_default_duty(spec, material, manufacturing, hardware, explain, max_root_radius_mm,
                      candidates) -> SpringDesign:
    """:func:`design_spring` of a job that declares no duty."""
    sized = duty.sized_for(material)
    if duty.fatigue_limited(sized, spec.max_deflection_rad):
        # the probe's layouts come first in the full search too: its design is the one
        # the search would return
        d, _, why = probe_why(spec, sized, manufacturing, hardware, max_root_radius_mm)
        if d is not None and soft_shortfalls(d):
            # every probed layout has a soft shortfall: the full search may find one
            # without (the kept layouts make the probe's share of it free)
            d = _clean_or(d, spec, sized, manufacturing, hardware, max_root_radius_mm,
                          candidates)
        if d is not None:
            return _replace(d, material=material, sized_for_default_duty=True, design_choice=(
                f"{d.design_choice}; sized for springcad's default duty "
                f"({duty.describe(material.duty)})"))
        d = design_for_margin(spec, material, manufacturing, hardware, explain,
                              max_root_radius_mm, candidates)
        # the binding rule, so the user sees what keeps the duty out of reach
        why = (f"none of the first {PROBE_CANDIDATES} layouts of the search for the duty within "
               f"your keys designs: {why}")
        d = _replace(d, design_choice=f"{d.design_choice}; sized for the yield margin alone: {why}")
        if not explain:
            return d
        with probe_clock():
            advice, _ = duty.alternatives(spec, sized, lambda s, m: _designs(
                s, m, manufacturing, hardware, max_root_radius_mm, base=spec),
                deadline=ADVICE_PROBES)
        return _replace(d, duty_advice=f"{advice.lstrip('; ')}; {why}")
    return design_for_margin(spec, material, manufacturing, hardware, explain,
                             max_root_radius_mm, candidates)


def _clean_or(d: SpringDesign, spec, material, manufacturing, hardware, max_root_radius_mm,
              candidates) -> SpringDesign:
    """The full search's design for ``material`` when it has no soft shortfall and keeps
    the margin, else ``d`` (a probe's design with one)."""
    try:
        full = design_for_margin(spec, material, manufacturing, hardware, explain=False,
                                 max_root_radius_mm=max_root_radius_mm, candidates=candidates)
    except DesignError:
        return d
    return full if not soft_shortfalls(full) and _keeps_margin(full, material) else d


def _keeps_margin(d: SpringDesign, material) -> bool:
    """Whether ``d`` keeps the yield margin and duty of ``material`` (to 1e-3)."""
    return d.yield_margin >= duty.required_margin(material, d.spec.max_deflection_rad) * (1.0 - 1e-3)


def probe(spec, material, manufacturing, hardware, max_root_radius_mm) -> SpringDesign | None:
    """A feasibility probe: the design the search (:data:`PROBE_CANDIDATES` layouts) finds
    for ``spec`` with the yield margin and duty of ``material``, or None."""
    return probe_thickness(spec, material, manufacturing, hardware, max_root_radius_mm)[0]


def probe_thickness(spec, material, manufacturing, hardware, max_root_radius_mm
                    ) -> tuple[SpringDesign | None, bool]:
    """:func:`probe`, and whether the disk is too thick when it does not design (a layout
    was passed over because its minimum webs hold the stiffness above the target:
    :class:`~springcad.design.resize.WebsHoldStiffness`)."""
    return probe_why(spec, material, manufacturing, hardware, max_root_radius_mm)[:2]


def probe_why(spec, material, manufacturing, hardware, max_root_radius_mm
              ) -> tuple[SpringDesign | None, bool, str]:
    """:func:`probe_thickness`, and why the probe finds no design (the binding rule of its
    best-ranked layout, with numbers; "" when it designs)."""
    count_probe()
    try:
        d = design_for_margin(spec, material, manufacturing, hardware, explain=False,
                              max_root_radius_mm=max_root_radius_mm,
                              candidates=PROBE_CANDIDATES, larger_balls=False)
    except WebsHoldStiffness as err:
        return None, True, short_reason(err)
    except DesignError as err:
        return None, False, short_reason(err)
    if not _keeps_margin(d, material):
        allowed = material.material.yield_strength_MPa / duty.required_margin(
            material, spec.max_deflection_rad)
        return None, False, (
            f"the best of them (N = {d.n_flexures}, r_c = {d.contact_radius_mm:.3g} mm, "
            f"{d.flexure}) keeps a predicted peak of {d.predicted_peak_stress_MPa:.0f} MPa at "
            f"the {d.stress.region}, above the {allowed:.0f} MPa allowed")
    # a fixed ball outside its contact window designs with a warning; a probe's suggestion
    # must give a spring whose ball carries the contact too
    if d.tip_radius_mm < d.tip_radius_required_mm * (1.0 - 1e-6):
        return None, False, (f"the tip balls of the best of them ({d.tip_radius_mm:.3g} mm) are "
                             f"below the {d.tip_radius_required_mm:.3g} mm their contact needs")
    return d, False, ""


#: the stack's root radius cap (mm) as a function of the designed spring's outer radius
#: (mm), set by :func:`rim_cap_rule` while a job designs a spring pinned rim to rim
_RIM_CAP: contextvars.ContextVar = contextvars.ContextVar("springcad_rim_cap", default=None)


@contextlib.contextmanager
def rim_cap_rule(cap_mm):
    """Within it, a refusal's probe of an outer radius ``R_o`` (mm) caps the root radius at
    ``cap_mm(R_o)`` (mm): the stack's own rule (:func:`springcad.design.job.
    shared_rim_limit_mm`), under which the smallest pinned rim, not the refused spring's,
    may hold the rim holes' circle (held-out A 6203 g04: spring B's R_o 24.5 -> 36.5 was
    named, and A's 24.5 mm rim kept the cap where it was)."""
    token = _RIM_CAP.set(cap_mm)
    try:
        yield
    finally:
        _RIM_CAP.reset(token)


def _designs(spec, material, manufacturing, hardware, max_root_radius_mm, base=None) -> bool:
    """Whether :func:`probe` designs ``spec``; with ``base`` (the refused spec) a stack's
    root radius cap (the rim holes' circle, mm) moves with the rim when ``spec`` changes
    the outer radius: by the stack's rule (:func:`rim_cap_rule`) when a job set one, else
    by the change of R_o minus the change of the rim it needs."""
    if base is not None and math.isfinite(max_root_radius_mm) and \
            spec.outer_radius_mm != base.outer_radius_mm:
        rule = _RIM_CAP.get()
        if rule is not None:
            max_root_radius_mm = rule(spec.outer_radius_mm)
        else:
            def inner(ro: float) -> float:
                return ro - min_rim_mm(ro, manufacturing, hardware)

            max_root_radius_mm += inner(spec.outer_radius_mm) - inner(base.outer_radius_mm)
    return probe(spec, material, manufacturing, hardware, max_root_radius_mm) is not None


def design_for_margin(spec: SpringSpec, material: MaterialSpec, manufacturing: ManufacturingSpec,
                      hardware: HardwareSpec, explain: bool = True,
                      max_root_radius_mm: float = math.inf,
                      candidates: int = MAX_CANDIDATES, larger_balls: bool = True
                      ) -> SpringDesign:
    """Synthesise one spring whose *predicted* peak stress keeps the required yield margin
    (yield and a declared duty, :func:`springcad.design.duty.required_margin`).

    ``max_root_radius_mm``: a root radius cap from the stack (the common rim-hole circle of
    springs pinned rim to rim must fit the thinnest rim; mm). The candidate layouts are tried best first (module docstring); for each:

    1. Layout, flexure shape and widths at the design stress (:func:`springcad.design.sizing._design_at`).
    2. The root flare with the lowest predicted peak (:func:`_choose_root`).
    3. While yield / predicted peak < the required margin (``material.safety_factor``),
       the beam stress is lowered by that ratio and the spring redesigned (longer,
       more serpentine flexures store the same energy at a lower stress).

    The first layout that passes every rule is returned, its ``design_choice`` naming the
    layouts rejected before it and why.

    Args:
        explain: when no layout passes, find the nearest thickness, outer radius,
            deflection and stiffness that would (:mod:`springcad.design.feasibility`;
            seconds to a minute; False for searches that only need a yes or no).
        candidates: how many ranked layouts to try.
        larger_balls: when every layout falls short of a contact rule at full deflection
            and the tip ball is springcad's choice, search again with larger balls
            (:func:`~springcad.design.balls.with_larger_ball`; off for feasibility probes,
            which only ask whether some layout is drawable, and for a search of the
            reference layout alone, ``candidates`` 1).

    Raises:
        DesignError: no layout meets the spec in its envelope (the message names the
            binding constraint of the reference layout, how many others were tried, and,
            with ``explain``, the thickness or deflection that would fit).
    """
    d, rejected, fallback, fallback_short = _first_passing(
        spec, material, manufacturing, hardware, max_root_radius_mm, candidates)
    if d is not None:
        return d
    if fallback is not None and larger_balls and candidates > 1 \
            and spec.tip_radius_mm is None and soft_shortfalls(fallback):
        larger = with_larger_ball(_first_passing, spec, material, manufacturing, hardware,
                                  max_root_radius_mm, candidates, fallback, fallback_short)
        if larger is not None:
            return larger
    if fallback is not None:  # every layout tried has a soft shortfall: the best one, warned
        choice = fallback.design_choice.replace(" that passes every rule", "")
        return _replace(fallback, design_choice=(
            f"{choice}; kept although it falls short ({fallback_short}): every one of the "
            f"{len(rejected)} layouts tried falls short of a rule, and this is the first"))
    if not rejected:
        raise DesignError(f"spring '{spec.name}': no candidate layout")
    _, first, history = rejected[0]
    alike = _alike(rejected)
    tried = ("" if len(rejected) == 1 else
             f" ({len(rejected)} layouts tried, all short of this rule; the best-ranked:)"
             if alike == len(rejected) else
             f" ({len(rejected)} layouts tried, {alike} short of this rule; the best-ranked:)")
    text = _stress_text(spec, material, history, first) if history else str(first)
    webs = any(isinstance(e, WebsHoldStiffness) for _, e, _ in rejected)
    if explain:
        raise _refusal(spec, material, manufacturing, hardware, max_root_radius_mm,
                       text, tried, webs) from first
    raise (WebsHoldStiffness if webs else DesignError)(
        text + tried.replace("; the best-ranked:", "")) from first


def _alike(rejected: list) -> int:
    """How many of the rejected layouts (``(layout, error, history)``, best first) fell short
    of the best-ranked one's rule (two errors are the same rule when their messages differ
    only in numbers). The refusal's "Why" names the best-ranked layout's rule, not the most
    common one: a thick disk's best layout is held stiff by its webs (a thinner disk or a
    higher stiffness helps) while most others fail the curved-flexure rule, whose advice
    (a thicker disk) points the other way (tests/test_stiffness_reach.py)."""
    def rule(entry) -> str:
        return re.sub(r"[-+]?\d[\d.,e]*", "#", without_shape_detail(str(entry[1])))

    first = rule(rejected[0])
    return sum(rule(e) == first for e in rejected)


def _first_passing(spec, material, manufacturing, hardware, max_root_radius_mm, candidates):
    """The candidate layouts tried best first (:func:`design_for_margin`).

    Returns:
        (design, rejected, fallback, fallback_short): the first design that passes every
        rule (or None), the layouts rejected before it with why, and the first design that
        is drawable but falls short of a soft rule, with that rule.
    """
    rejected: list[tuple[Layout | None, DesignError, list]] = []
    fallback, fallback_short = None, ""
    required = duty.required_margin(material, spec.max_deflection_rad)
    for rank in range(candidates):
        try:
            d, history, err, defect = _layout_design(spec, material, manufacturing, hardware,
                                                     rank, max_root_radius_mm)
        except _NoMoreLayouts:
            break
        if d is not None and defect:
            rejected.append((None, DesignError(f"spring '{spec.name}': {defect}"), []))
            continue
        if d is not None:
            unreachable = stiffness_out_of_reach(d)
            if unreachable:
                rejected.append((None, WebsHoldStiffness(unreachable), []))
                continue
            d = _replace(d, design_choice=_choice_text(d, rejected),
                         max_root_radius_mm=max_root_radius_mm)
            short = soft_shortfalls(d) + margin_shortfall(d, required) + widening_room_short(d)
            if not short:
                return d, rejected, fallback, fallback_short
            if fallback is None:
                fallback, fallback_short = d, short[0].split(":")[0]
            rejected.append((None, DesignError("; ".join(short)), []))
            continue
        rejected.append((None, err, history))
        if rank == 0 and not history and isinstance(err, SpecInfeasible):
            break  # no layout can help: the energy bound or the torque cap
    return None, rejected, fallback, fallback_short


#: layout designs :func:`kept_layouts` keeps at most (each with its profiles, ~1 MB): the
#: chosen plate's probe is among the last few dozen a stock choice makes
KEPT_LAYOUTS = 64
#: within :func:`kept_layouts`: each layout rank's design and contour check by its arguments
_KEPT: contextvars.ContextVar[dict | None] = contextvars.ContextVar("springcad_kept_layouts",
                                                                   default=None)


@contextlib.contextmanager
def kept_layouts():
    """Within it, :func:`design_for_margin` designs and checks each (spec, material, rank) once:
    the stock plate bisection's probe at the chosen thickness and the search that follows
    there try the same first layouts. Pure: the same arguments give the same design."""
    token = _KEPT.set(_KEPT.get() if _KEPT.get() is not None else {})
    try:
        yield
    finally:
        _KEPT.reset(token)


def _layout_design(spec, material, manufacturing, hardware, rank, max_root_radius_mm):
    """(design or None, stress-pass history, error, contour defect) of one layout rank
    (:func:`_design_with_margin`, :func:`profile_defect`), kept within :func:`kept_layouts`.

    Raises:
        _NoMoreLayouts: ``rank`` is past the last candidate.
    """
    kept, key = _KEPT.get(), (spec, material, manufacturing, hardware, rank, max_root_radius_mm)
    if kept is not None and key in kept:
        d, history, err, defect = kept[key]
        return d, list(history), err, defect
    d, history, err = _design_with_margin(spec, material, manufacturing, hardware, rank,
                                          max_root_radius_mm)
    defect = profile_defect(d) if d is not None else ""
    if kept is not None:
        if len(kept) >= KEPT_LAYOUTS:  # a refusal probes many specs: the oldest go first
            del kept[next(iter(kept))]
        kept[key] = (d, tuple(history), err, defect)
    return d, history, err, defect


def _choice_text(d: SpringDesign, rejected) -> str:
    """Why this layout: the reference choice, or the rejected ones before it."""
    what = (f"N = {d.n_flexures}, r_c = {d.contact_radius_mm:.3f} mm, tip ball "
            f"{d.tip_radius_mm:.3f} mm, R_r = {d.root_radius_mm:.3f} mm, {d.flexure}")
    if not rejected:
        return f"{what}: the layout with the longest straight reach that passes every rule"
    reasons: dict[str, int] = {}
    for _, e, _ in rejected:  # the same reason once, with how many layouts gave it
        reasons[short_reason(e)] = reasons.get(short_reason(e), 0) + 1
    return (f"{what}: layout {len(rejected) + 1} of the ranked candidates; rejected before it: "
            + "; ".join(r if k == 1 else f"{r} ({k} layouts)" for r, k in reasons.items()))


def _stress_text(spec, material, history, err) -> str:
    """Why no beam stress keeps the yield margin (the last stress pass, numbers)."""
    derating, peak, region = history[-1]
    required = duty.required_margin(material, spec.max_deflection_rad)
    sigma_need = material.design_stress_MPa * derating * (
        material.material.yield_strength_MPa / required / peak)
    return (f"spring '{spec.name}': the predicted peak {peak:.0f} MPa at the {region} leaves a "
            f"yield margin {material.material.yield_strength_MPa / peak:.3f} < required "
            f"{required:.3f}; the flexures would need a beam stress of about {sigma_need:.0f} MPa, "
            f"and at that stress {short_reason(err)}")


#: design probes the refusal spends on the user's keys (their far ends are always probed;
#: the bisection towards the nearest value stops when these are spent; every printed value
#: is still one the design search accepted). Probes, not seconds: the same spec gets the
#: same refusal on a quiet machine and a loaded one (1-8 s a probe)
REFUSAL_BUDGET_PROBES = 20
#: design probes the default duty's advice on a spring that designs (sized for yield
#: alone) may spend on refining its nearest values beyond the bisection's first two steps:
#: none (the advice is rounded outward and checked like a refusal's, to 1/4 of the span)
ADVICE_PROBES = 0
#: design probes a whole refusal may spend before it stops starting new kinds of change
#: (the user's own keys are always probed)
REFUSAL_TOTAL_PROBES = 48
#: stress headroom of a suggested change (-): the refusal's probes design with both safety
#: factors raised by it, so a change at the edge of what the stress model allows leaves
#: the FEA stress correction room for a peak this much above the prediction (the model's
#: calibration spread; a held-out suggestion at the exact edge verified at margin 0.999 < 1
#: and its correction found no redesign)
SUGGESTION_HEADROOM = 1.04
#: candidate layouts each feasibility probe tries (a subset of the full search's, in the
#: same order, so a probe that designs implies the full search designs)
PROBE_CANDIDATES = 4


def _freed_choices(spec, material, manufacturing, hardware, max_root_radius_mm) -> str:
    """When the user fixed layout keys springcad would otherwise choose: the smallest set
    of them (one at a time, then all) whose removal lets the search design the spring,
    with the values it then chooses, or ""."""
    fixed = fixed_choices(spec)
    trials = [[ku] for ku in fixed] + ([fixed] if len(fixed) > 1 else [])
    for keys in trials:
        free = _replace(spec, **{k: None for k, _ in keys})
        d = probe(free, material, manufacturing, hardware, max_root_radius_mm)
        if d is None:
            continue
        chosen = {"n_flexures": d.n_flexures, "contact_radius_mm": d.contact_radius_mm,
                  "tip_radius_mm": d.tip_radius_mm, "root_radius_mm": d.root_radius_mm}
        return "feasible with " + " and ".join(
            f"springs.{spec.name}.{k} removed (now {getattr(spec, k):g}{u}; springcad then "
            f"chooses {chosen[k]:.4g}{u})" for k, u in keys)
    return ""


def _changes(spec, material, manufacturing, hardware, max_root_radius_mm,
             stop: float = math.inf, webs: bool = False
             ) -> tuple[str, bool, list[tuple[str, float, float]], tuple, list]:
    """The changes that design ``spec`` with ``material``'s yield margin and duty (with
    :data:`SUGGESTION_HEADROOM`): the user's fixed layout keys left free, the nearest values
    of the user's own keys, a stronger material or disks in series, and a declared duty's
    own alternatives.

    ``stop`` (a count of :func:`~springcad.design.feasibility.probes_spent`) is the
    refusal's box: the user's own keys are always probed; the other kinds of change are
    searched only while it lasts. ``webs``: layouts were held stiff by their minimum webs
    (the thickness and stiffness are then probed downward and upward).

    Returns:
        (text, found, keys, disks, materials): the clause, whether it names a change that
        designs, the user keys' changes it names
        (:func:`~springcad.design.feasibility.nearest_changes`), its change of the whole disk
        as ``(clause, spec)`` pairs (:func:`~springcad.design.feasibility.larger_disk`; empty
        when it names none) and the other materials it names.
    """
    def designs(s, m=material) -> bool:
        return _designs(s, duty.biased(m, SUGGESTION_HEADROOM), manufacturing, hardware,
                        max_root_radius_mm, base=spec)

    def deadline() -> float:
        return min(probes_spent() + REFUSAL_BUDGET_PROBES, stop)

    def designs_each(specs: list) -> list[bool]:  # half on the other core, all counted here
        answers, beside = each_on_two_cores(designs, specs)
        for _ in range(beside):
            count_probe()
        return answers

    def say(what: str) -> None:
        report(f"spring {spec.name}: {what}")

    if fixed_choices(spec):
        say("probing the layout keys you fixed, left free")
    freed = _freed_choices(spec, material, manufacturing, hardware, max_root_radius_mm)
    say("probing the nearest value of each of your keys that designs")
    nearest = nearest_changes(spec, designs, deadline=deadline(), webs=webs,
                              designs_each=designs_each)
    series, materials, alternatives, duty_disk = None, [], "", ()
    if not duty.fatigue_limited(material, spec.max_deflection_rad):
        # (when the duty sets the allowed peak, its own alternatives, below, replace these)
        if probes_spent() < stop:
            say("probing disks in series")
            series = series_change(spec, designs)
        if probes_spent() < stop:
            say("probing other materials")
            materials = material_changes(material, lambda m: designs(spec, m))
    changes = describe(spec.name, nearest, materials, series, spec, webs)
    if freed:
        changes = freed + ("; or " + changes if not changes.startswith("no change") else "")
    if probes_spent() < stop and duty.fatigue_limited(material, spec.max_deflection_rad):
        say("probing surface finishes, materials and disks for the duty")
        alternatives, duty_disk = duty.alternatives(spec, material, designs,
                                                    deadline=deadline())
    found = bool(freed or nearest or materials or series is not None) or (
        bool(alternatives) and not alternatives.endswith(duty.NOTHING_MEETS))
    if not found and not alternatives:  # several keys: the whole disk larger
        say("probing the whole disk scaled up")
        big, scaled = larger_disk(spec, designs, deadline=deadline())
        if big:
            return (f"{changes}; it designs with {big}", True, nearest, ((big, scaled, None),),
                    materials)
    return (changes + alternatives, found, nearest, (duty_disk,) if duty_disk else (),
            materials)


def changes_for_margin(spec: SpringSpec, material: MaterialSpec, manufacturing: ManufacturingSpec,
                       hardware: HardwareSpec, max_root_radius_mm: float,
                       model_bias: float) -> str:
    """The changes (a refusal's search, :func:`_changes`) under which the spring keeps
    ``material``'s margin with its predicted peak x ``model_bias``: what the FEA's stress
    correction names when no redesign in the envelope meets the margin the FEA measured
    (held-out B 016: FEA peak 1.16 x the prediction, yield margin 1.923 < 2, no change named).

    Returns:
        "feasible with springs.S1.thickness_mm = 14 (now 12) or ..." or "no change of ...".
    """
    report(f"spring {spec.name}: searching the changes that keep the margin with the FEA's "
           f"peak ({model_bias:.3f} x the prediction)")
    with probe_clock():
        text, *_ = _changes(spec, duty.biased(material, model_bias), manufacturing, hardware,
                            max_root_radius_mm, stop=REFUSAL_TOTAL_PROBES)
    return text


def _refusal(spec, material, manufacturing, hardware, max_root_radius_mm, text,
             tried: str = "", webs: bool = False) -> DesignError:
    """The refusal: the nearest values of the user's own keys that design (numbers) first,
    then why (the binding rule of the reference layout), so a console line cut at its
    length limit keeps the change.

    A job without a ``[duty]`` gets springcad's default duty, which gates its release:
    the changes named are those that meet it too when any does, else those that meet the
    yield margin, with the default duty's shortfall said.
    """
    args = (manufacturing, hardware, max_root_radius_mm)
    stop = REFUSAL_TOTAL_PROBES
    report(f"spring {spec.name}: no layout passes; searching the changes that would design "
           f"it (up to {REFUSAL_TOTAL_PROBES} design probes)")
    with probe_clock():
        changes, _, keys, disks, materials = _changes(spec, material, *args, stop=stop,
                                                      webs=webs)
        sized = duty.sized_for(material)
        if not material.duty.declared and duty.fatigue_limited(sized, spec.max_deflection_rad):
            if probes_spent() < stop:
                report(f"spring {spec.name}: the same for springcad's default duty")
                for_duty, found, duty_keys, duty_disks, duty_materials = _changes(
                    spec, sized, *args, stop=stop, webs=webs)
                keys, disks = keys + duty_keys, disks + duty_disks
                materials = materials + duty_materials
                for_duty = (for_duty if found else "no change springcad probes meets it: "
                            "declare the duty the spring will see in [duty]")
            else:
                for_duty = (f"not searched (the refusal's {REFUSAL_TOTAL_PROBES} design probes "
                            "were spent): declare the duty the spring will see in [duty], or "
                            "check the change above with it")
            changes += (f"; for springcad's default duty ({duty.describe(material.duty)}) as "
                        "well, " + for_duty)
    refusal = DesignError(f"spring '{spec.name}' cannot be made as specified; {changes}. "
                          f"Why{tried}: {short_reason(text)}")
    refusal.key_changes = tuple((spec.name, *k) for k in keys)
    refusal.disk_changes = tuple((spec.name, *d) for d in disks)
    refusal.material_changes = tuple(
        (spec.name, material_clause(m), m.material.name, m.design_stress_MPa)
        for m in materials[:MATERIALS_NAMED])
    return refusal
