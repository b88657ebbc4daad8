"""Fit one bench record end to end: segment, paper models, residual loop, design check.

:func:`fit_record` is the library entry point of ``springcad fit``; its
:class:`FitResult` serialises to the ``fit.json`` the CLI writes.

Quantities reported are physically valid or refused:

* the record must hold a spring (stiffness above noise) — otherwise it is
  reported as such and nothing else is fitted;
* a torque that falls with deflection, or a stiffness a unit factor (180/π,
  1000) away from the target, is refused as a channel sign or unit mistake
  (the unit mistake is kept with a warning when the user vouches for the
  units: ``trust_units``);
* the energy loss comes from the hysteresis model only (the loop area of the
  friction term over the energy stored on loading), so lags, drifts and
  offsets cannot make it negative; with no hysteresis above noise it is zero,
  and with hysteresis confounded with another effect it is not determined.

Torque in N·m, angles in rad, stiffness in N·m/rad, NRMSE in percent of half
the measured torque range (Table I).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from springcad.errors import DataError
from springcad.fit.compare import compare_with_design
from springcad.fit.data import BenchRecord, unit_contradiction
from springcad.fit.identify import record_protocol
from springcad.fit.loop import LoopResult, LoopSettings, State, run_loop
from springcad.fit.models import PaperModelFit, fit_paper_models, rmse, stiffness_error_pct
from springcad.fit.segment import CycleEnergy, Segmentation, cycle_energies, segment
from springcad.fit.signals import Signals, make_signals
from springcad.parallel import single_threaded_blas
from springcad.options import spell
from springcad.units import DEG_PER_RAD, NMM_PER_NM, RAD_PER_DEG
from springcad.version import stamp

SCHEMA = "springcad.fit/2"

#: unit factors a stiffness can be off by when a unit is misread:
#: (factor, the factor in words, what happened, the fix: pass or drop an option's value)
UNIT_FACTORS = (
    (DEG_PER_RAD, "57.3 (180/pi)", "angles in rad were read as degrees",
     ("drop", "angle_unit", "deg")),
    (RAD_PER_DEG, "1/57.3 (pi/180)", "angles in degrees were read as rad",
     ("pass", "angle_unit", "deg")),
    (NMM_PER_NM, "1000", "torque in N·mm was read as N·m", ("pass", "torque_unit", "Nmm")),
    (1 / NMM_PER_NM, "1/1000", "torque in N·m was read as N·mm", ("drop", "torque_unit", "Nmm")))
#: a stiffness within this factor of a unit factor times the target reads as a unit mistake
#: (a real spring misses its target by tens of percent, not by 38 to 86 times)
UNIT_FACTOR_TOLERANCE = 1.5


@dataclass(frozen=True)
class EnergyLoss:
    """Energy loss per loading–unloading cycle from the hysteresis model.

    Attributes:
        pct: loss at the largest amplitude (%): friction loop area over the
            energy stored on loading; ``None`` when not determined.
        ci_low: lower end of its confidence interval (%), ≥ 0.
        ci_high: upper end (%).
        note: how it was obtained or why it is not determined.
    """

    pct: float | None
    ci_low: float | None
    ci_high: float | None
    note: str

    def to_dict(self) -> dict:
        return {"pct": self.pct, "ci_low_pct": self.ci_low, "ci_high_pct": self.ci_high,
                "source": "hysteresis model", "note": self.note}


@dataclass(frozen=True)
class FitResult:
    """Everything ``springcad fit`` found about one record.

    Attributes:
        record: the record.
        segmentation: its half-cycles and excursions.
        signals: per-sample signals used by the loop.
        paper_models: linear, deadband and logit fits.
        cycles: measured energy of each loading–unloading cycle (apparent: it
            holds lags, drifts and offsets as well as the spring's loss).
        energy: energy loss from the hysteresis model.
        loop: the residual loop's outcome.
        target_stiffness_Nm_per_rad: target given by the user or the design.
        design_comparison: comparison with the design, if a design was given.
    """

    record: BenchRecord
    segmentation: Segmentation
    signals: Signals
    paper_models: dict[str, PaperModelFit]
    cycles: list[CycleEnergy]
    energy: EnergyLoss
    loop: LoopResult
    target_stiffness_Nm_per_rad: float | None
    design_comparison: dict | None

    @property
    def energy_loss_pct(self) -> float | None:
        return self.energy.pct

    @property
    def half_range_Nm(self) -> float:
        return self.signals.scales.torque_ref

    @property
    def final_model(self) -> str:
        """The final model in words (see :func:`final_label`)."""
        return final_label(self.loop)

    @property
    def stiffness_Nm_per_rad(self) -> float:
        """The final model's stiffness (N·m/rad); the deadband fit's when no spring was found
        (the loop then reports no interval for it)."""
        ci = self.loop.intervals.get("stiffness_Nm_per_rad")
        return ci["value"] if ci else self.paper_models["deadband"].stiffness_Nm_per_rad

    def nrmse_pct(self, state: State) -> float:
        """NRMSE (%) of a loop state over its non-glitch samples."""
        return self.loop.nrmse_pct(state, self.signals)

    def to_dict(self) -> dict:
        """The ``fit.json`` content."""
        rec, seg, loop = self.record, self.segmentation, self.loop
        target = self.target_stiffness_Nm_per_rad
        final = loop.final
        final_params = final.params()
        idx = final.inliers(np.arange(self.signals.n))
        amps, speed = record_protocol(self.signals)
        out = {
            **stamp(SCHEMA),
            "input": {"source": rec.source, "n_samples": rec.n_samples,
                      "duration_s": rec.duration_s, "sample_rate_hz": rec.sample_rate_hz,
                      "has_encoder": rec.encoder_deflection_rad is not None,
                      "torque_half_range_Nm": self.half_range_Nm},
            "warnings": list(rec.warnings),
            "segmentation": {"n_half_cycles": len(seg.half_cycles),
                             "n_cycles": len(seg.excursions),
                             "cycle_amplitudes_rad": seg.amplitudes_rad,
                             "reversal_threshold_rad": seg.threshold_rad,
                             "distinct_amplitudes_rad": list(amps),
                             "typical_speed_rad_per_s": speed},
            "paper_models": {k: m.to_dict(target) for k, m in self.paper_models.items()},
            "energy_loss_pct": self.energy.pct,
            "energy_loss": self.energy.to_dict(),
            "energy_by_cycle": [{"sign": c.sign, "amplitude_rad": c.amplitude_rad,
                                 "stored_J": c.stored_J, "returned_J": c.returned_J,
                                 "apparent_loss_pct": c.loss_pct} for c in self.cycles],
            "spring_check": loop.spring,
            "baseline": {"model": loop.baseline.label, "params": loop.baseline.params(),
                         "nrmse_pct": self.nrmse_pct(loop.baseline)},
            "steps": [s.to_dict() for s in loop.steps],
            "final": {"model": self.final_model, "effects": list(loop.identified),
                      "terms": list(final.effects),
                      "confounded": [g.to_dict() for g in loop.confounded],
                      "no_spring": loop.no_spring,
                      "params": final_params,
                      "intervals": loop.intervals,
                      "confidence": 0.95,
                      "nrmse_pct": self.nrmse_pct(final),
                      "rmse_Nm": rmse(final.model.residual(final.x, loop.described(self.signals),
                                                           idx)),
                      "noise_Nm": loop.noise_Nm,
                      "noise_floor_nrmse_pct": 100.0 * loop.noise_Nm / self.half_range_Nm,
                      "unexplained": loop.unexplained,
                      "unexplained_evidence": loop.structure,
                      "unexplained_where": _where(loop.localisation),
                      "fitted_region": loop.region,
                      "nuisance_taken_out": loop.nuisance,
                      "laws": loop.laws},
            "evidence": {k: v.to_dict() for k, v in loop.evidence.items()},
            "rejected": list(loop.rejected),
            "protocol_advice": [g.advice.to_dict() for g in loop.confounded if g.advice],
            "loop_settings": dataclasses.asdict(loop.settings),
            "search_log": list(loop.search_log),
            "last_round_candidates": [c.to_dict() for c in loop.rounds[-1]] if loop.rounds else [],
            "target_stiffness_Nm_per_rad": target,
            "stiffness_error_pct": None,
            "design_comparison": self.design_comparison,
        }
        if target and not loop.no_spring:
            out["stiffness_error_pct"] = {
                "deadband": stiffness_error_pct(self.paper_models["deadband"].stiffness_Nm_per_rad,
                                                target),
                "final": stiffness_error_pct(final_params["stiffness_Nm_per_rad"], target)}
        return out


def final_label(loop: LoopResult) -> str:
    """The final model in words: identified effects, confounded groups in brackets."""
    if loop.no_spring:
        return "no stiffness above noise"
    parts = ["linear", *loop.identified]
    parts += ["(" + " | ".join(g.effects) + ")" for g in loop.confounded]
    return " + ".join(parts)


def _where(loc: dict | None) -> dict | None:
    if loc is None:
        return None
    return {"summary": loc["summary"], "findings": loc["findings"]}


def fit_record(record: BenchRecord, target_stiffness_Nm_per_rad: float | None = None,
               design: dict | None = None, settings: LoopSettings = LoopSettings(),
               trust_units: bool = False) -> FitResult:
    """Fit the paper's models and run the residual loop on one record.

    Args:
        record: validated bench record.
        target_stiffness_Nm_per_rad: target stiffness; taken from the design
            (``stack.target_stiffness_Nm_per_rad``) when not given.
        design: the job's design dict, for the comparison with the design.
        settings: residual-loop settings.
        trust_units: keep a stiffness a unit factor away from the target (the
            user vouches for the units): a warning in the
            record's warnings instead of the refusal.

    Returns:
        The fit result.

    Raises:
        DataError: the record has too few cycles, its torque falls with
            deflection, or its stiffness is a unit factor away from the target.
        ConfigError: the design dict lacks the keys the comparison needs.
    """
    seg = segment(record)
    sig = make_signals(record, seg)
    half = sig.scales.torque_ref
    with single_threaded_blas():
        paper = fit_paper_models(record.deflection_rad, record.torque_Nm, half)
        loop = run_loop(sig, settings)
    _check_sign(record, loop)
    comparison = None
    if design is not None:
        dead = paper["deadband"]
        comparison = compare_with_design(design, dead.stiffness_Nm_per_rad, dead.backlash_rad)
        if target_stiffness_Nm_per_rad is None:
            target_stiffness_Nm_per_rad = comparison["stiffness"]["target_stiffness_Nm_per_rad"]
        final = loop.final.params()
        if "backlash_rad" in final and not loop.no_spring:
            comparison["residual_loop"] = compare_with_design(
                design, final["stiffness_Nm_per_rad"], final["backlash_rad"],
                method=f"residual loop final model ({loop.final.label})")
    if target_stiffness_Nm_per_rad and not loop.no_spring:
        problem = unit_factor_problem(loop.final.params()["stiffness_Nm_per_rad"],
                                      target_stiffness_Nm_per_rad)
        if problem:
            note = unit_contradiction(problem, record.source, trust_units)
            record = dataclasses.replace(record, warnings=record.warnings + (note,))
    cycles = cycle_energies(record, seg)
    energy = model_energy_loss(sig, seg, loop)
    return FitResult(record, seg, sig, paper, cycles, energy, loop, target_stiffness_Nm_per_rad,
                     comparison)


def _check_sign(record: BenchRecord, loop: LoopResult) -> None:
    spring = loop.spring
    if spring["stiffness_Nm_per_rad"] < 0 and spring["z"] <= -loop.settings.spring_z:
        raise DataError(
            f"{record.source}: torque falls as deflection grows (K = "
            f"{spring['stiffness_Nm_per_rad']:.4g} ± {spring['se_Nm_per_rad']:.2g} N·m/rad): one "
            "channel's sign is reversed (sensor mounted the other way, or encoder/deflection "
            "columns swapped); flip the sign of the torque or the deflection column")


def unit_factor_problem(k: float, target: float) -> str | None:
    """Why a fitted stiffness ``k`` (N·m/rad) a unit factor from ``target`` reads as a unit
    mistake, naming the factor and the option to fix; ``None`` when it does not."""
    ratio = k / target
    for factor, words, why, (verb, option, value) in UNIT_FACTORS:
        if abs(math.log(ratio / factor)) < math.log(UNIT_FACTOR_TOLERANCE):
            return (f"the fitted stiffness {k:.4g} N·m/rad is {ratio:.4g} × the target "
                    f"{target:.4g} N·m/rad, close to a unit factor of {words}: the data "
                    f"contradicts the units it was read in; likely {why}: {verb} "
                    f"{spell(option, value)} (if the target is what is wrong, correct "
                    f"{spell('target_stiffness_Nm_per_rad')} or the job's stiffness)")
    return None


def model_energy_loss(sig: Signals, seg: Segmentation, loop: LoopResult) -> EnergyLoss:
    """Energy loss (%) at the largest amplitude from the hysteresis term of the final model.

    The loop area of the friction torque along the measured path of each
    largest-amplitude cycle, over the energy the model spring (elastic plus
    friction torque) stores while loading; the interval follows the friction
    torque's interval. Lags, drifts and offsets are measurement effects and
    do not enter.
    """
    if loop.no_spring:
        return EnergyLoss(None, None, None, "no stiffness above noise: no spring to lose energy")
    grouped = {n: g for g in loop.confounded for n in g.effects}
    if "hysteresis" in grouped:
        g = grouped["hysteresis"]
        return EnergyLoss(None, None, None,
                          f"not determined: hysteresis is confounded with "
                          f"{', '.join(n for n in g.effects if n != 'hysteresis')} on this "
                          "record (see the confounded effects and the recommended protocol)")
    final = loop.final
    if "hysteresis" not in final.model.names:
        return EnergyLoss(0.0, 0.0, 0.0, "no hysteresis above noise in the final model")
    sl = final.model.slice_of("hysteresis")
    ci = loop.intervals.get("friction_torque_Nm", {})

    def loss(friction: float) -> float:
        x = final.x.copy()
        x[sl.start] = max(friction, 0.0)
        return _friction_loss_pct(sig, seg, final, x)

    value = loss(float(final.x[sl.start]))
    lo = loss(ci.get("ci_low", final.x[sl.start])) if ci else value
    hi = loss(ci.get("ci_high", final.x[sl.start])) if ci else value
    return EnergyLoss(value, max(min(lo, hi), 0.0), max(lo, hi),
                      "friction loop area over the energy stored on loading, largest cycles")


def _friction_loss_pct(sig: Signals, seg: Segmentation, state: State, x: np.ndarray) -> float:
    """Friction loop area over stored energy (%) of the largest cycles, for parameters ``x``."""
    model = state.model
    kept = tuple(e for e in model.effects if e.stage in ("map", "factor") or e.name == "hysteresis")
    spring_model = type(model)(kept, model.scales)
    xs = spring_model.transfer(model, x)
    idx = np.arange(sig.n)
    theta = sig.theta_smooth
    friction = spring_model.torque_terms(xs, sig, idx, {"hysteresis"})
    total = spring_model.predict(xs, sig, idx)
    cycles = []
    for e in seg.excursions:
        ld = slice(e.loading.start, e.loading.stop + 1)
        whole = slice(e.loading.start, e.unloading.stop + 1)
        stored = _integral(total[ld], theta[ld])
        # ∮ friction dθ: friction opposes the motion, so the area is positive either side of zero
        cycles.append((e.amplitude_rad, stored, _integral(friction[whole], theta[whole])))
    a_max = max(c[0] for c in cycles)
    big = [c for c in cycles if c[0] >= 0.9 * a_max and c[1] > 0]
    stored = sum(c[1] for c in big)
    area = sum(c[2] for c in big)
    return max(100.0 * area / stored, 0.0) if stored > 0 else 0.0


def _integral(y: np.ndarray, x: np.ndarray) -> float:
    """Trapezoidal ``∫ y dx`` along the path."""
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))
