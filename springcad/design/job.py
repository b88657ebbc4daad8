"""Design a whole job: every named spring once, then the stack."""

from __future__ import annotations

import contextlib
import contextvars
import math
from dataclasses import dataclass, replace

from springcad.version import stamp
from springcad.config import Job, ManufacturingSpec
from springcad.config.consistency import check as check_config
from springcad.config.consistency import ROOT_STEP_MM, min_rim_mm
from springcad.config.schema import BOLT_DIAMETERS_MM
from springcad.data import dowel_lengths
from springcad.design import duty
from springcad.design.camshaft_share import share_camshafts
from springcad.design.connections import RIM, connection_sequence
from springcad.design.feasibility import as_material, fewer_disks, key_clause, with_key
from springcad.design.hardware import bolt_circle_limit_mm, rim_spacer_rim_mm
from springcad.design.plausibility import check_hardware, design_warnings
from springcad.design.ring import pinned_hole_patterns
from springcad.design.search import probe, rim_cap_rule, short_reason
from springcad.design.sizing import designing_for_a_user, for_a_user
from springcad.design.stock import design_spring
from springcad.design.spring import SpringDesign
from springcad.design.stack import StackDesign, design_stack
from springcad.design.tolerance import gap_range_mm
from springcad.errors import ConfigError, DesignError, RemedyError, change_text, one_line
from springcad.parallel import each_on_two_cores
from springcad.progress import Progress, report, reporting

SCHEMA = "springcad.design/1"


@dataclass(frozen=True, repr=False)
class JobDesign:
    """Designed springs (by name) and the stack built from them."""

    job: Job
    springs: dict[str, SpringDesign]
    stack: StackDesign

    def __repr__(self) -> str:
        return f"JobDesign({self.job.name!r}, springs={list(self.springs)}, {self.stack!r})"

    def with_springs(self, springs: dict[str, SpringDesign]) -> "JobDesign":
        """The same job with some springs replaced (e.g. FEA-corrected); the stack is redone."""
        merged = common_hole_circle({**self.springs, **springs}, self.job)
        stack = design_stack([merged[n] for n in self.job.stack.sequence], self.job.stack.input,
                             self.job.analysis.monte_carlo_samples, self.job.analysis.seed)
        return JobDesign(self.job, merged, stack)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Plausibility warnings: the config's and the designed geometry's."""
        return tuple(self.job.warnings) + tuple(design_warnings(self))

    def notes(self) -> list[str]:
        out = []
        for s in self.springs.values():
            out.extend(f"spring {s.name}: {w}" for w in s.warnings)
        out.extend(self.stack.notes())
        return out

    def release_warnings(self) -> list[str]:
        """Every spring warning and stack warning (the notes that stop a release)."""
        out = [f"spring {s.name}: {w}" for s in self.springs.values() for w in s.warnings]
        return out + self.stack.warnings()

    def to_dict(self) -> dict:
        """The ``design.json`` document (units in key names)."""
        mat = self.job.material
        return {
            **stamp(SCHEMA),
            "job": {"name": self.job.name, "description": self.job.description,
                    "config": self.job.source},
            "material": {
                "name": mat.material.name, "description": mat.material.description,
                "youngs_modulus_MPa": mat.material.youngs_modulus_MPa,
                "poisson_ratio": mat.material.poisson_ratio,
                "yield_strength_MPa": mat.material.yield_strength_MPa,
                "density_kg_per_m3": mat.material.density_kg_per_m3,
                "heat_treatment": mat.material.heat_treatment,
                "design_stress_MPa": mat.design_stress_MPa,
                "safety_factor": mat.safety_factor},
            "manufacturing": {k: getattr(self.job.manufacturing, k) for k in (
                "process", "t_spring_mm", "t_shaft_mm", "w_gap_mm", "wire_diameter_mm",
                "spark_gap_mm", "min_slot_width_mm", "min_web_mm", "min_hole_edge_mm",
                "tolerance_distribution")},
            "springs": {name: s.to_dict() for name, s in self.springs.items()},
            "stack": self.stack.to_dict(),
            "duty": {"description": duty.describe(mat.duty), "source": duty.source(mat.duty),
                     "declared": mat.duty.declared},
            "notes": self.notes(),
            "warnings": list(self.warnings),
        }


def common_hole_circle(springs: dict[str, SpringDesign], job: Job) -> dict[str, SpringDesign]:
    """Put the rim holes of the springs whose rims are pinned to each other
    (:func:`~springcad.design.connections.rim_groups`) on one circle at the same angles
    (:func:`springcad.design.ring.common_hole_pattern`), inside the job's
    :func:`bolt_circle_limit_mm`; a rim pinned only to its end flange keeps its own."""
    return pinned_hole_patterns(springs, job.stack.sequence, job.stack.input,
                                _bolt_circle_mm(job))


def _bolt_circle_mm(job: Job) -> float:
    """The job's :func:`~springcad.design.hardware.bolt_circle_limit_mm` (mm; inf without)."""
    ro = min(job.springs[n].outer_radius_mm for n in set(job.stack.sequence))
    return bolt_circle_limit_mm(job.hardware, len(job.stack.sequence), ro)


def shared_rim_limit_mm(job: Job) -> float:
    """Largest root radius any spring of a stack with rim-to-rim joints may have (mm): the
    rim holes lie on one circle (:func:`common_hole_circle`) that must fit the rim of the
    spring with the smallest outer radius, with its holes' edge distances, and the rim
    spacer between the rims needs its clearance holes and webs there
    (:func:`springcad.design.hardware.rim_spacer_rim_mm`)."""
    seq = job.stack.sequence
    joints, _ = connection_sequence(len(seq), job.stack.input)
    if RIM not in joints or job.hardware.fastener_count == 0:
        return math.inf
    ro = min(job.springs[n].outer_radius_mm for n in set(seq))
    spacer_rim = rim_spacer_rim_mm(job.hardware, job.manufacturing)
    # bolt heads and nuts inside the rims: the holes sit at most on that circle, with the
    # spring's hole edge and the spacer's web, tolerances and play inside them (held-out
    # 2614 g04: M5 bolts pulled the circle in and the 1 mm spacer's web hit the roots)
    inside = max(0.5 * job.hardware.hole_diameter_mm + job.manufacturing.min_hole_edge_mm,
                 0.5 * spacer_rim)
    return min(_bolt_circle_mm(job) - inside,
               ro - max(min_rim_mm(ro, job.manufacturing, job.hardware), spacer_rim))


#: how a refusal of a spring starts (``springcad.design.search``)
REFUSAL_HEAD = "cannot be made as specified; "


def jamming_tolerances(mfg: ManufacturingSpec) -> str:
    """What the job's tolerances add to a refusal when they alone keep every spring from
    release: a design gap ``w_gap_mm`` below t_spring + t_shaft lets worst-case parts jam at
    the cam (the stack's interference warning stops the release whatever the spring); then
    the change to springcad's tolerances (the schema's defaults: wire EDM with skim cuts),
    else ''. The paper's S1 with a 1e7-cycle duty: its scaled disk builds RELEASED at
    those, NOT FOR MANUFACTURE at the paper's t_spring 0.05, t_shaft 0.02, w_gap 0.025."""
    if gap_range_mm(mfg.w_gap_mm, mfg.t_spring_mm, mfg.t_shaft_mm)[0] >= 0:
        return ""
    ours = ManufacturingSpec()
    return (f"; and for a release the cam interfaces need w_gap_mm >= t_spring_mm + t_shaft_mm "
            f"(now {mfg.w_gap_mm:g} < {mfg.t_spring_mm + mfg.t_shaft_mm:g} mm: worst-case parts "
            f"jam whatever the spring): springcad's tolerances, manufacturing.t_spring_mm = "
            f"{ours.t_spring_mm:g}, manufacturing.t_shaft_mm = {ours.t_shaft_mm:g} and "
            f"manufacturing.w_gap_mm = {ours.w_gap_mm:g} (wire EDM with skim cuts)")


#: spring designs :func:`kept_springs` keeps at most (each with its profiles, ~1 MB)
KEPT_SPRINGS = 32
#: within :func:`kept_springs`: each yes-or-no spring design (or its refusal) by its arguments
_KEPT_SPRINGS: contextvars.ContextVar[dict | None] = contextvars.ContextVar(
    "springcad_kept_springs", default=None)


@contextlib.contextmanager
def kept_springs():
    """Within it, a yes-or-no design of the whole job (``explain`` False) designs each spring
    of given arguments once: checking a refusal's changes, or a hardware refusal's, designs
    the job again and again with one spring or one [hardware] key changed, and the other
    springs are the same (held-out A 5821 g27: spring A designed three times for the checks
    of B's changes, 19 of its 152 s). Pure: the same arguments give the same design."""
    token = _KEPT_SPRINGS.set(_KEPT_SPRINGS.get() if _KEPT_SPRINGS.get() is not None else {})
    try:
        yield
    finally:
        _KEPT_SPRINGS.reset(token)


def _design_or_fewer(job: Job, name: str, explain: bool, rr_max: float) -> SpringDesign:
    """The spring ``name`` of ``job``; a refusal of a disk the stack holds several times
    names the stack with fewer of them first (:func:`~springcad.design.feasibility.
    fewer_disks`), each checked with the design search; a yes or no within
    :func:`kept_springs` is designed once."""
    kept = _KEPT_SPRINGS.get() if not explain else None
    if kept is None:
        return _design_or_fewer_now(job, name, explain, rr_max)
    key = (job.springs[name], job.material, job.manufacturing, job.hardware, rr_max,
           designing_for_a_user())
    if key not in kept:
        if len(kept) >= KEPT_SPRINGS:
            del kept[next(iter(kept))]
        try:
            kept[key] = _design_or_fewer_now(job, name, explain, rr_max)
        except DesignError as err:
            kept[key] = err
    if isinstance(kept[key], DesignError):
        raise kept[key]
    return kept[key]


def _design_or_fewer_now(job: Job, name: str, explain: bool, rr_max: float) -> SpringDesign:
    """:func:`_design_or_fewer`, designed now."""
    spec = job.springs[name]

    def cap_mm(outer_radius_mm: float) -> float:
        grown = _rims_grown(replace(job, springs={
            **job.springs, name: replace(spec, outer_radius_mm=outer_radius_mm)}), name)[0]
        return shared_rim_limit_mm(grown)

    try:
        with rim_cap_rule(cap_mm):
            return design_spring(spec, job.material, job.manufacturing, job.hardware,
                                 explain=explain, max_root_radius_mm=rr_max)
    except DesignError as err:
        copies = job.stack.sequence.count(name)
        if not explain or copies < 2 or spec.thickness_mm is None:
            raise

        def designs(s) -> bool:
            return probe(s, job.material, job.manufacturing, job.hardware, rr_max) is not None

        fewer = fewer_disks(spec, copies, designs)
        if not fewer:
            raise
        text = str(err)
        at = text.find(REFUSAL_HEAD)
        head, rest = (text[:at + len(REFUSAL_HEAD)], text[at + len(REFUSAL_HEAD):]) if at >= 0 \
            else (f"spring '{name}' {REFUSAL_HEAD}", text)
        raise err.carrying_changes_to(
            DesignError(f"{head}feasible with fewer disks: {fewer}; or {rest}")) from err


#: hardware changes in a row :func:`_free_hardware` may make (a thinner screw that then
#: needs more of them is two)
HARDWARE_CHOICES = 2


def design_job(job: Job, explain: bool = True, progress: Progress | None = None) -> JobDesign:
    """Design every spring named in the job and the stack (:func:`_design_job`); with
    ``explain`` (a user's job, not a yes or no) a spring only its profile tolerances keep
    from release is made for nominal parts (:func:`~springcad.design.sizing.for_a_user`)."""
    if not explain:
        return _design_job(job, explain, progress)
    with for_a_user(), kept_springs():
        return _design_job(job, explain, progress)


def _design_job(job: Job, explain: bool = True, progress: Progress | None = None,
                hardware_choices: int = HARDWARE_CHOICES) -> JobDesign:
    """Design every spring named in the job and the stack.

    Args:
        explain: a refused spring names the changes that would design (seconds to a
            minute; False for searches that only need a yes or no, e.g. synthesis).
        progress: ``progress(message, fraction)`` for the springs, the stock plate choice
            and a refusal's search (:mod:`springcad.progress`).
        hardware_choices: how many hardware changes in a row springcad may make on
            ``[hardware]`` keys the config does not give (:func:`_free_hardware`).

    Raises:
        DesignError: a spring or a hardware part cannot be made as specified.
    """
    rr_max = shared_rim_limit_mm(job)
    _check_fixed_roots(job, rr_max, explain)
    asked = job  # the remedies of a hardware refusal are changes to the job as given
    springs, refusals = {}, []
    with reporting(progress):
        for i, name in enumerate(job.springs):
            report(f"designing spring {name} ({i + 1}/{len(job.springs)})", i / len(job.springs))
            try:
                springs[name] = _design_or_fewer(job, name, explain, rr_max)
            except DesignError as err:
                if not explain:
                    raise
                refusals.append((name, err))
    if refusals:
        refused = {name for name, _ in refusals}
        checked = [_checked_key_changes(job, err, refused - {name}) for name, err in refusals]
        raise _all_refusals(checked, jamming_tolerances(job.manufacturing),
                            _together(job, checked) if len(checked) > 1 else "")
    # the thickness springcad chose (stock plate) is the job's from here on
    job = replace(job, springs={n: replace(s, thickness_mm=springs[n].thickness_mm)
                                for n, s in job.springs.items()})
    springs = share_camshafts(job, springs, rr_max, explain)
    springs = common_hole_circle(springs, job)
    try:  # the stack's hardware (pins, screws) and its strength
        stack = design_stack([springs[n] for n in job.stack.sequence], job.stack.input,
                             job.analysis.monte_carlo_samples, job.analysis.seed)
        design = JobDesign(job, springs, stack)
        check_hardware(design)
    except RemedyError as err:
        chosen = _free_hardware(asked, err, hardware_choices) if hardware_choices else None
        if chosen is not None:
            return chosen
        if not explain:
            raise
        raise _checked_pin_remedies(asked, err) from err
    return design


def _free_hardware(job: Job, err: RemedyError, choices: int) -> JobDesign | None:
    """A designer's answer to a hardware refusal on its own defaults: the first of ``err``'s
    changes that touches only ``[hardware]`` keys the config does not give
    (:attr:`~springcad.config.specs.HardwareSpec.given`) and under which the whole job
    designs, the job designed with it and the choice said among its warnings; None when no
    such change designs (the refusal then names the changes, the user's keys included).
    The default seven rim screws of a small disk whose nuts overlap, or default dowels too
    weak for a stack's torque, become the count or size that holds."""
    given = set(job.hardware.given)
    for changes, text in err.remedies:
        keys = [k.split(".", 1) for k in changes]
        if not all(sec == "hardware" and key not in given for sec, key in keys):
            continue
        try:
            d = _design_job(with_changes(job, changes), explain=False,
                            hardware_choices=choices - 1)
        except (DesignError, ConfigError):
            continue
        note = (f"hardware chosen by springcad: {text.replace('(now ', '(default ', 1)}, "
                f"since with the default {one_line(err.head, 240)}; give the key in [hardware] "
                "to fix it")
        return replace(d, job=replace(d.job, warnings=(*d.job.warnings, note)))
    return None


#: how far, and on what step, an outer radius is searched past the user's for a fixed root
#: radius to fit (mm; the refusals' outer-radius step)
ROOT_ROOM_SEARCH_MM = 20.0
OUTER_STEP_MM = 0.5


def _check_fixed_roots(job: Job, rr_max: float, explain: bool) -> None:
    """Root radii the user fixed must leave the rim the pinned rims' hardware needs
    (:func:`shared_rim_limit_mm`: the rim spacer's clearance holes and webs, the bolts'
    circle), which the config's own rim rule does not know: held-out B 012, given a root
    radius of 20.2 mm by that rule, was refused at the build's spacer check with no number.
    Checked here, in milliseconds, for every spring at once (held-out A 6203 g15: two
    springs with the same fixed root radius, the change named for the first refused on the
    second), naming the root radii, outer radii or fastener under which they fit, each
    checked with the whole job when ``explain``.

    Raises:
        DesignError: a fixed root radius past ``rr_max`` (mm).
    """
    over = {n: job.springs[n] for n in dict.fromkeys(job.stack.sequence)
            if job.springs[n].root_radius_mm is not None
            and job.springs[n].root_radius_mm > rr_max + 1e-9}
    if not over:
        return
    rr = max(s.root_radius_mm for s in over.values())
    changes = {}
    fit = math.floor(rr_max / ROOT_STEP_MM + 1e-9) * ROOT_STEP_MM
    if fit > 0:
        _add_change(changes, {f"springs.{n}.root_radius_mm": round(fit, 6) for n in over}, job)
    # every rim grows by the same step: the smallest pinned rim holds the holes' circle
    for k in range(1, int(ROOT_ROOM_SEARCH_MM / OUTER_STEP_MM) + 1):
        grown = {f"springs.{n}.outer_radius_mm": job.springs[n].outer_radius_mm
                 + OUTER_STEP_MM * k for n in dict.fromkeys(job.stack.sequence)}
        if shared_rim_limit_mm(with_changes(job, grown)) >= rr - 1e-9:
            _add_change(changes, grown, job)
            break
    hw = job.hardware
    sizes = BOLT_DIAMETERS_MM if hw.fastener == "bolt" else sorted(dowel_lengths())
    for d in sorted((d for d in sizes if d < hw.fastener_diameter_mm), reverse=True):
        if shared_rim_limit_mm(replace(job, hardware=replace(hw, fastener_diameter_mm=d))) \
                >= rr - 1e-9:
            _add_change(changes, {"hardware.fastener_diameter_mm": d}, job)
            break
    named = []
    for clause, change in changes.items():
        if explain:
            report(f"checking {clause} with the whole job")
            try:
                design_job(with_changes(job, change), explain=False)
            except (DesignError, ConfigError) as e:
                clause = f"{clause} (then {one_line(short_reason(e), 160)})"
        named.append(clause)
    each = "; ".join(f"springs.{n}.root_radius_mm = {s.root_radius_mm:g} leaves a rim of "
                     f"{s.outer_radius_mm - s.root_radius_mm:.3g} mm" for n, s in over.items())
    raise DesignError(
        f"{each}; the pinned rims' hardware (the rim spacer's clearance holes and webs, the "
        f"fasteners' circle) needs the root radius at most {rr_max:.4g} mm: use "
        + (" or ".join(named) if named else "a larger outer radius"))


def _add_change(changes: dict, change: dict, job: Job) -> None:
    """``changes[clause] = change``, the clause naming each key's new value and the job's
    (``a = 1 (now 2) and b = 3 (now 4)``)."""
    def now(key: str):
        section, *rest = key.split(".")
        if section == "hardware":
            return getattr(job.hardware, rest[0])
        return getattr(job.springs[rest[0]], rest[1])
    changes[" and ".join(change_text(k, v, now(k)) for k, v in change.items())] = change


#: the changes of a spring refusal checked with the whole job, first named first: each costs
#: a design of the job (seconds to a minute)
CHECKED_CHANGES = 4


def _checked_key_changes(job: Job, err: DesignError, refused: set[str] = frozenset()
                         ) -> DesignError:
    """The spring refusal ``err`` with its first :data:`CHECKED_CHANGES` changes checked
    with the whole job (the design search probes the spring alone): a change under which a
    hardware part does not fit (a screw too short for the thicker rims' grip, pins too weak
    on a larger rim's bolt circle, or a drive pin no catalogue length fits the ring, which
    the spring's refusal hid) names the hardware change with which the job designs too, or
    what stops it. Three kinds are checked: one key (``err.key_changes``), the whole disk
    scaled (``err.disk_changes``) and another material (``err.material_changes``; held-out
    A 5821 g15: maraging 300 designed its six disks, whose stack torque then broke the
    three dowels the config gave). A change whose check stops on another spring of
    ``refused`` (refused on its own, with its own changes) is left as it is: that spring's
    refusal, not this change, is what stops the job (held-out B 9041 010: A's thicker disk
    was named "(then storing 29.9 J ...)", B's own refusal)."""
    text = str(err)
    changes = [(key_clause(name, key, now, value), name,
                with_key(job.springs[name], key, value), None, job.material)
               for name, key, now, value in err.key_changes]
    changes += [(clause, name, spec, surface, job.material)
                for name, clause, spec, surface in err.disk_changes]
    changes += [(clause, name, job.springs[name], None, replace(
        as_material(job.material, material), design_stress_MPa=stress_MPa))
                for name, clause, material, stress_MPa in err.material_changes]
    changes = sorted(({c[0]: c for c in changes if c[0] in text}).values(),
                     key=lambda c: text.find(c[0]))[:CHECKED_CHANGES]
    for (clause, *_), shown in zip(changes, _checked_clauses(job, changes, refused)):
        text = text.replace(clause, shown, 1)
    if text == str(err):
        return err
    checked = err.carrying_changes_to(type(err)(text))
    checked.__cause__ = err
    return checked


def _checked_clauses(job: Job, changes: list, refused: set[str]) -> list[str]:
    """:func:`_checked_clause` of each change, in order, half of them on the other core
    (:func:`springcad.parallel.each_on_two_cores`: each check designs the whole job, and
    none depends on another)."""
    return each_on_two_cores(lambda c: _checked_clause(job, c, refused), changes)[0]


def _checked_clause(job: Job, change: tuple, refused: set[str]) -> str:
    """One change of a spring refusal, ``(clause, spring name, spec, surface, material)``,
    checked with the whole job (:func:`_checked_key_changes`): the clause to print in its
    place (the clause itself when the job designs with it)."""
    clause, name, spec, surface, material = change
    report(f"spring {name}: checking {clause.split(' (')[0]} with the whole job")
    changed, grown = _with_spring(replace(job, material=material), name, spec)
    if grown:
        clause = f"{clause} and {grown}"
    if surface is not None:
        finished = replace(job.material.duty, surface=surface)
        changed = replace(changed, material=replace(changed.material, duty=finished))
    try:
        design_job(changed, explain=False)
    except RemedyError as e:
        works = _second_changes(changed, {}, clause, e, HARDWARE_CHOICES)
        return works[0] if works else f"{clause} (then {short_reason(e).split('; use')[0]})"
    except (DesignError, ConfigError) as e:
        if not any(str(e).startswith(f"spring '{n}'") for n in refused):
            return f"{clause} (then {one_line(short_reason(e), 160)})"
    return clause


def _with_spring(job: Job, name: str, spec) -> tuple[Job, str]:
    """``job`` with spring ``name``'s spec changed to ``spec``, and with a larger disk the
    rims pinned to it grown (:func:`_rims_grown`; the change as text, "" when none grows)."""
    changed = replace(job, springs={**job.springs, name: spec})
    if spec.outer_radius_mm > job.springs[name].outer_radius_mm + 1e-9:  # a larger disk
        return _rims_grown(changed, name)
    return changed, ""


def _rims_grown(job: Job, name: str) -> tuple[Job, str]:
    """``job`` with every rim pinned to spring ``name``'s grown to at least its outer radius,
    and the change as text ("springs.B.outer_radius_mm = 24 (now 17)", "" when none grows):
    the smallest pinned rim holds the rim holes' circle (:func:`shared_rim_limit_mm`), so a
    larger disk in a rim-pinned stack gains room only with the rims it is pinned to (held-out
    B 9041 018: A refused on a 17 mm disk pinned to B's 17 mm rim; A's R_o 24 alone did not
    move the circle)."""
    if not math.isfinite(shared_rim_limit_mm(job)):
        return job, ""
    ro = job.springs[name].outer_radius_mm
    smaller = [n for n in dict.fromkeys(job.stack.sequence)
               if n != name and job.springs[n].outer_radius_mm < ro - 1e-9]
    if not smaller:
        return job, ""
    text = " and ".join(change_text(f"springs.{n}.outer_radius_mm", ro,
                                    job.springs[n].outer_radius_mm) for n in smaller)
    return replace(job, springs={**job.springs, **{
        n: replace(job.springs[n], outer_radius_mm=ro) for n in smaller}}), text


#: the refused springs' key changes tried together (the i-th of each, i below this)
TOGETHER_TRIES = 2


def _together(job: Job, refusals: list[DesignError]) -> str:
    """A change of every refused spring at once under which the whole job designs: each
    spring's first named key change (then its second), applied together, rims grown with a
    larger disk as a single change's check does; "feasible with A and B, together" or "".
    A refusal of several springs names each one's changes, and one of them applied alone
    meets the next spring's refusal only then (held-out A 5821 g01, g23 and A 4242 g23)."""
    if any(not e.key_changes for e in refusals):
        return ""
    for i in range(TOGETHER_TRIES):
        picks = [e.key_changes[min(i, len(e.key_changes) - 1)] for e in refusals]
        if len({name for name, *_ in picks}) < len(picks):
            return ""  # two refusals of one spring: not a change of each
        changed, clauses = job, []
        for name, key, now, value in picks:
            changed, grown = _with_spring(changed, name, with_key(changed.springs[name], key,
                                                                  value))
            clauses.append(key_clause(name, key, now, value) + (f" and {grown}" if grown else ""))
        try:
            design_job(changed, explain=False)
        except (DesignError, ConfigError):
            continue
        return "feasible with " + " and ".join(clauses) + ", together"
    return ""


def _all_refusals(refusals: list[DesignError], advice: str, together: str = "") -> DesignError:
    """One refusal naming every spring that cannot be made, each with its own changes (a
    change applied to the first spring alone would meet the next one's refusal only then),
    first the change of all of them at once that designs the job (``together``,
    :func:`_together`) when there is one, followed once by the job's ``advice``
    (:func:`jamming_tolerances`); the first refusal's type (e.g.
    :class:`~springcad.errors.SpecInfeasible`) is kept."""
    text = "; and ".join(str(e) for e in refusals)
    if len(refusals) > 1:
        text = (f"{len(refusals)} springs cannot be made as specified: "
                + (f"{together}; or each one's own: " if together else "") + text)
    if not advice and len(refusals) == 1:
        return refusals[0]
    error = type(refusals[0])(f"{text}{advice}")
    error.__cause__ = refusals[0]
    return error


def with_changes(job: Job, changes: dict) -> Job:
    """The job with config changes applied: dotted keys ``hardware.<key>`` or
    ``springs.<name>.<key>`` (as :class:`~springcad.errors.RemedyError` names them) to
    their new values, and the config's cross-key checks run on it as on a loaded file.

    Raises:
        ConfigError: the changed job breaks a cross-key rule.
    """
    for key, value in changes.items():
        section, *rest = key.split(".")
        if section == "hardware" and len(rest) == 1:
            job = replace(job, hardware=replace(job.hardware, **{rest[0]: value}))
        elif section == "springs" and len(rest) == 2:
            name, field = rest
            job = replace(job, springs={**job.springs,
                                        name: replace(job.springs[name], **{field: value})})
        else:
            raise ValueError(f"with_changes: cannot apply {key!r}")
    return check_config(job, {})


def _checked_pin_remedies(job: Job, err: RemedyError) -> DesignError:
    """The hardware refusal ``err`` (pins too weak, a pin, screw or bore that does not fit)
    with only the changes under which the whole job designs (more pins crowd the rim;
    larger ones need a wider rim, which shortens the flexures): each is tried with the
    design search. A change that meets another hardware rule is tried once more with
    each of that rule's own changes (a thinner pin that then needs more of them). When
    none designs, the refusal says so and names what stopped the first."""
    if not err.remedies:
        return DesignError(str(err))
    works, why = [], ""
    for changes, text in err.remedies:
        try:
            design_job(with_changes(job, changes), explain=False)
        except RemedyError as e:
            why = why or f"with {text}: {short_reason(e)}"
            works += _second_changes(job, changes, text, e)
            continue
        except (DesignError, ConfigError) as e:
            why = why or f"with {text}: {short_reason(e)}"
            continue
        works.append(text)
    last = [err.fallback] if err.fallback else []
    if works:
        return DesignError(f"{err.head}; use " + " or ".join(works + last))
    tried = " or ".join(t for _, t in err.remedies)
    return DesignError(f"{err.head}; no change of this part alone designs the job ({tried} "
                       f"tried; {why})" + (f": use {err.fallback}" if err.fallback else ""))


def _second_changes(job: Job, changes: dict, text: str, err: RemedyError,
                    depth: int = 1) -> list[str]:
    """``changes`` with the first of ``err``'s remedies (on other keys) under which the
    job designs, as text (an empty list when none does); with ``depth`` > 1 a remedy
    that meets another hardware rule is tried with that rule's own remedies too, that
    many levels deep (held-out A 7311 g29: the scaled disk's thicker rims need M2 screws,
    whose five then need to be fifteen)."""
    for more, more_text in err.remedies:
        if set(more) & set(changes):
            continue
        try:
            design_job(with_changes(job, {**changes, **more}), explain=False)
        except RemedyError as e:
            deeper = _second_changes(job, {**changes, **more}, f"{text} and {more_text}", e,
                                     depth - 1) if depth > 1 else []
            if deeper:
                return deeper
            continue
        except (DesignError, ConfigError):
            continue
        return [f"{text} and {more_text}"]
    return []
