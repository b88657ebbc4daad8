"""Cross-key checks of a job config, and plausibility warnings for legal but odd values.

Errors (:class:`ConfigError`) are combinations no spring can be made from:
radii out of order, a rim too thin for its holes, slots narrower than the wire's
kerf, more fasteners than flexure gaps, bolts that are not a catalogue size.
Warnings are kept on :attr:`Job.warnings` and printed by the CLI. Checks that
need the designed geometry (the chosen N, r_c and R_r) are in
:mod:`springcad.design.plausibility`.
"""

from __future__ import annotations

import math
from dataclasses import replace

from springcad.config.schema import BOLT_DIAMETERS_MM, keys
from springcad.config.specs import HardwareSpec, Job, ManufacturingSpec, SpringSpec
from springcad.connections import rim_joint_count
from springcad.data import dowel_lengths
from springcad.errors import ConfigError, change_text

#: Monte Carlo stacks below which the 1 %/99 % percentiles are not worth quoting
MIN_USEFUL_SAMPLES = 1000
#: largest contact radius springcad tries, as a fraction of R_o, and below a fixed root
#: radius (design.layout.candidate_layouts)
CONTACT_SEARCH_FRACTION = 0.6
#: thinnest rim as a fraction of the outer radius (the rim carries the whole torque)
MIN_RIM_FRACTION = 0.02


def min_rim_mm(outer_radius_mm: float, mfg: ManufacturingSpec, hw: HardwareSpec) -> float:
    """Thinnest rim (R_o - R_r) a spring may have (mm).

    The wire must leave a web, the root fillets need room and the rim carries the whole
    reaction torque; with fasteners the holes and their edge distances must fit radially.
    """
    rim = max(mfg.min_web_mm, 2.0 * mfg.min_inside_radius_mm, MIN_RIM_FRACTION * outer_radius_mm)
    if hw.fastener_count > 0:
        rim = max(rim, hw.hole_diameter_mm + 2.0 * mfg.min_hole_edge_mm)
    return rim


#: steps of the camshaft bore springcad chooses below the default (mm)
SHAFT_STEP_MM = 0.5
#: what springcad leaves between its chosen bore and the smallest fixed contact radius (mm)
SHAFT_ROOM_MM = 0.5
#: a root radius the rim rule names is rounded down to this step (mm)
ROOT_STEP_MM = 0.1


def shaft_diameter_below_mm(contact_radius_mm: float) -> float:
    """The camshaft bore springcad chooses under a fixed contact radius (mm): the largest
    step of :data:`SHAFT_STEP_MM` at least :data:`SHAFT_ROOM_MM` below it (never below the
    schema's minimum; the design checks the cam's wall over it)."""
    fit = math.floor((contact_radius_mm - SHAFT_ROOM_MM) / SHAFT_STEP_MM + 1e-9) * SHAFT_STEP_MM
    return max(fit, keys("hardware")["shaft_diameter_mm"].lo)


def _rim_remedies(s: SpringSpec, mfg: ManufacturingSpec, hw: HardwareSpec) -> list[str]:
    """``key = value (now old)`` changes under which the rim of ``s`` (a fixed root radius)
    is wide enough: the largest root radius on a :data:`ROOT_STEP_MM` step, and the largest
    catalogue fastener diameter whose holes fit the rim as it is."""
    p = f"springs.{s.name}"
    ro, rr = s.outer_radius_mm, s.root_radius_mm
    fit = math.floor((ro - min_rim_mm(ro, mfg, hw)) / ROOT_STEP_MM + 1e-9) * ROOT_STEP_MM
    out = [change_text(f"{p}.root_radius_mm", round(fit, 6), rr)] if fit > 0 else []
    sizes = BOLT_DIAMETERS_MM if hw.fastener == "bolt" else sorted(dowel_lengths())
    smaller = [d for d in sizes if d < hw.fastener_diameter_mm
               and ro - rr >= min_rim_mm(ro, mfg, replace(hw, fastener_diameter_mm=d)) - 1e-9]
    if smaller:
        out.append(change_text("hardware.fastener_diameter_mm", smaller[-1],
                               hw.fastener_diameter_mm))
    return out


def _spring(s: SpringSpec, mfg: ManufacturingSpec, hw: HardwareSpec, given: dict,
            rim_pinned: bool = False) -> list[str]:
    """Checks of one spring's keys; warnings. ``rim_pinned``: the spring's rim is pinned to
    another's (rim-to-rim joints with fasteners), whose hardware the design checks a fixed
    root radius against (``springcad.design.job``: the rim spacer's holes and webs, the
    fasteners' circle, a stricter rule than the rim's own), so the rim rule is left to it:
    a remedy named here would be refused there."""
    p = f"springs.{s.name}"
    ro, rc, rr = s.outer_radius_mm, s.contact_radius_mm, s.root_radius_mm
    if rc is not None and rc >= ro:
        raise ConfigError(f"{p}.contact_radius_mm", rc,
                          f"must be smaller than outer_radius_mm = {ro:g}")
    if rr is not None and rr >= ro:
        raise ConfigError(f"{p}.root_radius_mm", rr,
                          f"must be smaller than outer_radius_mm = {ro:g}")
    if rr is not None and rc is not None and rr <= rc:
        raise ConfigError(f"{p}.root_radius_mm", rr,
                          f"must be larger than contact_radius_mm = {rc:g}")
    wire = mfg.min_inside_radius_mm
    for key in ("tip_radius_mm", "min_tip_radius_mm"):
        r = getattr(s, key)
        if r is None or (key == "min_tip_radius_mm" and key not in given):
            continue
        if r < wire:
            raise ConfigError(f"{p}.{key}", r, f"must be at least the wire radius + spark gap = "
                                               f"{wire:g} mm for wire EDM")
        if rc is not None and r >= 0.5 * rc:
            raise ConfigError(f"{p}.{key}", r, f"must be below half the contact radius "
                                               f"({0.5 * rc:g} mm): the cam needs room inside "
                                               "the tip balls")
    if s.n_flexures is not None and hw.fastener_count > s.n_flexures:
        raise ConfigError("hardware.fastener_count", hw.fastener_count,
                          f"must be at most n_flexures = {s.n_flexures} of spring {s.name} "
                          "(one rim hole per gap between flexures): use "
                          + change_text("hardware.fastener_count", s.n_flexures,
                                        hw.fastener_count))
    # the rim and the bore are independent: a spec that breaks both hears of both
    problems: list[ConfigError] = []
    if rr is not None and not rim_pinned:
        need = min_rim_mm(ro, mfg, hw)
        if ro - rr < need - 1e-9:  # the root radius this names is on a 0.1 mm step
            problems.append(ConfigError(
                f"{p}.root_radius_mm", rr,
                f"leaves a rim of {ro - rr:.3g} mm; the rim needs at least {need:.3g} mm "
                f"(web, fillets, {hw.fastener_count} rim hole(s) of {hw.hole_diameter_mm:g} mm "
                f"with min_hole_edge_mm on both sides): use "
                + " or ".join(_rim_remedies(s, mfg, hw))))
    if rc is not None and hw.shaft_diameter_mm >= rc:
        d, d_now = shaft_diameter_below_mm(rc), hw.shaft_diameter_mm
        problems.append(ConfigError(
            "hardware.shaft_diameter_mm", d_now,
            f"must be smaller than the contact radius {rc:g} mm of spring {s.name}: the "
            f"camshaft bore must leave the cam teeth standing; use "
            f"{change_text('hardware.shaft_diameter_mm', d, d_now)} (springcad's choice when the "
            f"key is not given) or "
            f"{change_text(f'{p}.contact_radius_mm', d_now + SHAFT_ROOM_MM, rc)}"))
    if problems:
        first, *more = problems
        raise ConfigError(first.key, first.value, first.allowed + "".join(
            f"; also {m}" for m in more))
    warnings = []
    if s.tip_radius_mm is not None and "min_tip_radius_mm" in given:
        warnings.append(f"spring {s.name}: min_tip_radius_mm = {s.min_tip_radius_mm:g} is ignored "
                        f"because tip_radius_mm = {s.tip_radius_mm:g} fixes the tip ball")
    return warnings


def check(job: Job, spring_values: dict[str, dict]) -> Job:
    """Cross-key checks of a job built from checked values; returns it with its warnings.

    Args:
        job: the job built from single-key-checked values.
        spring_values: per spring, the keys actually given (for "ignored key" warnings).

    Raises:
        ConfigError: the first inconsistent combination.
    """
    mfg, hw, an = job.manufacturing, job.hardware, job.analysis
    if mfg.min_slot_width_mm < mfg.kerf_mm:
        raise ConfigError("manufacturing.min_slot_width_mm", mfg.min_slot_width_mm,
                          f"must be at least the kerf the wire cuts: wire_diameter_mm + 2 x "
                          f"spark_gap_mm = {mfg.kerf_mm:g} mm")
    if hw.fastener == "bolt" and hw.fastener_count > 0 and not any(
            abs(hw.fastener_diameter_mm - d) < 1e-9 for d in BOLT_DIAMETERS_MM):
        raise ConfigError("hardware.fastener_diameter_mm", hw.fastener_diameter_mm,
                          "must be an ISO 4762 screw size for fastener = \"bolt\": "
                          + ", ".join(f"{d:g}" for d in BOLT_DIAMETERS_MM)
                          + " mm (or use fastener = \"dowel\")")
    warnings: list[str] = []
    springs = {}
    rim_joints = rim_joint_count(len(job.stack.sequence), job.stack.input)
    for name, s in job.springs.items():
        pinned = bool(rim_joints) and hw.fastener_count > 0 and name in job.stack.sequence
        warnings += _spring(s, mfg, hw, spring_values.get(name, {}), pinned)
        wire = mfg.min_inside_radius_mm
        if s.min_tip_radius_mm < wire and "min_tip_radius_mm" not in spring_values.get(name, {}):
            # the default smallest ball is below what this wire can cut: the wire's smallest
            s = replace(s, min_tip_radius_mm=wire)
        springs[name] = s
    unused = [n for n in job.springs if n not in job.stack.sequence]
    if unused:
        warnings.append(f"spring(s) {', '.join(unused)} are defined but not in stack.sequence; "
                        "they are designed but not built")
    if an.monte_carlo_samples < MIN_USEFUL_SAMPLES:
        warnings.append(f"analysis.monte_carlo_samples = {an.monte_carlo_samples}: the Monte Carlo "
                        "backlash statistics (mean, std, 1 %/99 % percentiles) need at least "
                        f"{MIN_USEFUL_SAMPLES} samples to mean anything"
                        + ("; with one sample the spread is zero" if an.monte_carlo_samples == 1
                           else ""))
    if mfg.t_spring_mm == 0 and mfg.t_shaft_mm == 0:
        warnings.append("manufacturing.t_spring_mm and t_shaft_mm are both 0: the worst-case, "
                        "RSS and Monte Carlo backlash have zero spread (perfect parts)")
    mat = job.material
    if mat.design_stress_MPa * mat.safety_factor > mat.material.yield_strength_MPa * (1 + 1e-9):
        warnings.append(f"material: design stress {mat.design_stress_MPa:.4g} MPa x safety factor "
                        f"{mat.safety_factor:.4g} exceeds the yield strength "
                        f"{mat.material.yield_strength_MPa:g} MPa: the flexures are not designed to "
                        "it but to a predicted peak of at most yield / safety factor = "
                        f"{mat.material.yield_strength_MPa / mat.safety_factor:.0f} MPa (the design "
                        "search lowers the beam stress until the yield margin holds)")
    if hw.fastener_count == 0 and rim_joints:
        raise ConfigError("hardware.fastener_count", 0,
                          f"must be at least 1: this stack has {rim_joints} rim-to-rim joint(s), "
                          "pinned or bolted through the rim holes")
    return replace(job, springs=springs, warnings=tuple(warnings))

