"""Fit one bench record end to end: segment, paper models, residual loop, design check.

:func:`fit_record` is the library entry point of ``springcad fit``; its
:class:`FitResult` serialises to the ``fit.json`` the CLI writes.

Torque in N·m, angles in rad, stiffness in N·m/rad, NRMSE in percent of half
the measured torque range (Table I).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from springcad.fit.compare import compare_with_design
from springcad.fit.data import BenchRecord
from springcad.fit.loop import LoopResult, LoopSettings, State, run_loop
from springcad.fit.models import PaperModelFit, fit_paper_models, rmse, stiffness_error_pct
from springcad.fit.segment import (CycleEnergy, Segmentation, cycle_energies, energy_loss_pct,
                                   segment)
from springcad.fit.signals import Signals, make_signals
from springcad.fit.torque_model import single_threaded_blas

SCHEMA = "springcad.fit/1"

#: effects of the measurement, not of the spring: removed before the corrected energy loss
MEASUREMENT_EFFECTS = ("time_lag", "drift", "torque_offset", "angle_offset", "outliers")


@dataclass(frozen=True)
class FitResult:
    """Everything ``springcad fit`` found about one record.

    Attributes:
        record: the record.
        segmentation: its half-cycles and excursions.
        signals: per-sample signals used by the loop.
        paper_models: linear, deadband and logit fits.
        cycles: energy of each loading–unloading cycle.
        energy_loss_pct: loss at the largest amplitude (%), from the measured data.
        energy_loss_corrected_pct: the same after removing the measurement
            effects the loop found (lag, drift, offsets, glitches), or ``None``.
        energy_loss_corrections: the effects removed for the corrected loss.
        loop: the residual loop's outcome.
        target_stiffness_Nm_per_rad: target given by the user or the design.
        design_comparison: comparison with the design, if a design was given.
    """

    record: BenchRecord
    segmentation: Segmentation
    signals: Signals
    paper_models: dict[str, PaperModelFit]
    cycles: list[CycleEnergy]
    energy_loss_pct: float
    energy_loss_corrected_pct: float | None
    energy_loss_corrections: tuple[str, ...]
    loop: LoopResult
    target_stiffness_Nm_per_rad: float | None
    design_comparison: dict | None

    @property
    def half_range_Nm(self) -> float:
        return self.signals.scales.torque_ref

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
        out = {
            "schema": SCHEMA,
            "input": {"source": rec.source, "n_samples": rec.n_samples,
                      "duration_s": rec.duration_s, "sample_rate_hz": rec.sample_rate_hz,
                      "has_encoder": rec.encoder_deflection_rad is not None,
                      "torque_half_range_Nm": self.half_range_Nm},
            "warnings": list(rec.warnings),
            "segmentation": {"n_half_cycles": len(seg.half_cycles),
                             "n_cycles": len(seg.excursions),
                             "cycle_amplitudes_rad": seg.amplitudes_rad,
                             "reversal_threshold_rad": seg.threshold_rad},
            "paper_models": {k: m.to_dict(target) for k, m in self.paper_models.items()},
            "energy_loss_pct": self.energy_loss_pct,
            "energy_loss_corrected_pct": self.energy_loss_corrected_pct,
            "energy_loss_corrections": list(self.energy_loss_corrections),
            "energy_by_cycle": [{"sign": c.sign, "amplitude_rad": c.amplitude_rad,
                                 "stored_J": c.stored_J, "returned_J": c.returned_J,
                                 "loss_pct": c.loss_pct} for c in self.cycles],
            "baseline": {"model": loop.baseline.label, "params": loop.baseline.params(),
                         "nrmse_pct": self.nrmse_pct(loop.baseline)},
            "steps": [s.to_dict() for s in loop.steps],
            "final": {"model": final.label, "effects": list(final.effects),
                      "params": final_params, "nrmse_pct": self.nrmse_pct(final),
                      "rmse_Nm": rmse(final.model.residual(final.x, self.signals, idx)),
                      "noise_Nm": loop.noise_Nm,
                      "noise_floor_nrmse_pct": 100.0 * loop.noise_Nm / self.half_range_Nm,
                      "unexplained": loop.unexplained,
                      "unexplained_evidence": loop.structure},
            "loop_settings": dataclasses.asdict(loop.settings),
            "search_log": list(loop.search_log),
            "last_round_candidates": [c.to_dict() for c in loop.rounds[-1]] if loop.rounds else [],
            "target_stiffness_Nm_per_rad": target,
            "stiffness_error_pct": None,
            "design_comparison": self.design_comparison,
        }
        if target:
            out["stiffness_error_pct"] = {
                "deadband": stiffness_error_pct(self.paper_models["deadband"].stiffness_Nm_per_rad,
                                                target),
                "final": stiffness_error_pct(final_params["stiffness_Nm_per_rad"], target)}
        return out


def fit_record(record: BenchRecord, target_stiffness_Nm_per_rad: float | None = None,
               design: dict | None = None, settings: LoopSettings = LoopSettings()) -> FitResult:
    """Fit the paper's models and run the residual loop on one record.

    Args:
        record: validated bench record.
        target_stiffness_Nm_per_rad: target stiffness; taken from the design
            (``stack.target_stiffness_Nm_per_rad``) when not given.
        design: the job's design dict, for the comparison with the design.
        settings: residual-loop settings.

    Returns:
        The fit result.

    Raises:
        DataError: the record has too few cycles.
        ConfigError: the design dict lacks the keys the comparison needs.
    """
    seg = segment(record)
    sig = make_signals(record, seg)
    half = sig.scales.torque_ref
    with single_threaded_blas():
        paper = fit_paper_models(record.deflection_rad, record.torque_Nm, half)
        loop = run_loop(sig, settings)
    cycles = cycle_energies(record, seg)
    comparison = None
    if design is not None:
        dead = paper["deadband"]
        comparison = compare_with_design(design, dead.stiffness_Nm_per_rad, dead.backlash_rad)
        if target_stiffness_Nm_per_rad is None:
            target_stiffness_Nm_per_rad = comparison["stiffness"]["target_Nm_per_rad"]
        final = loop.final.params()
        if "backlash_rad" in final:
            comparison["residual_loop"] = compare_with_design(
                design, final["stiffness_Nm_per_rad"], final["backlash_rad"],
                method=f"residual loop final model ({loop.final.label})")
    corrected, corrections = _corrected_energy_loss(record, seg, sig, loop)
    return FitResult(record, seg, sig, paper, cycles, energy_loss_pct(cycles), corrected,
                     corrections, loop, target_stiffness_Nm_per_rad, comparison)


def _corrected_energy_loss(record: BenchRecord, seg: Segmentation, sig: Signals,
                           loop: LoopResult) -> tuple[float | None, tuple[str, ...]]:
    """Energy loss (%) with the measurement effects of the final model removed.

    A lagging torque channel draws a loop of its own (of either sign) and a
    drifting zero adds or removes energy over a cycle; neither belongs to the
    spring. The torque loses the fitted offset and drift terms, the deflection
    is shifted by the fitted lag and offset, and glitches are replaced by the
    model torque, before the loop areas are integrated again.
    """
    final = loop.final
    corrections = tuple(e for e in final.effects if e in MEASUREMENT_EFFECTS)
    if not corrections:
        return None, ()
    idx = np.arange(sig.n)
    model, x = final.model, final.x
    sensor = model.torque_terms(x, sig, idx, {"drift", "torque_offset"})
    torque = sig.torque - sensor
    if final.mask is not None:
        torque[final.mask] = (model.predict(x, sig, idx) - sensor)[final.mask]
    corrected = dataclasses.replace(record, torque_Nm=torque,
                                    deflection_rad=model.effective_angle(x, sig, idx))
    return energy_loss_pct(cycle_energies(corrected, seg)), corrections
