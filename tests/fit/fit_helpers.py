"""Shared truths and helpers of the fit tests (simulated, seeded records only)."""

from __future__ import annotations

import numpy as np

from springcad.fit.bench import BenchSpring, Protocol, simulate
from springcad.fit.loop import run_loop
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals

#: stiffness of the test spring (N·m/rad), near the paper's 37.5 N·m/rad stacks
K = 40.0

#: the paper's amplitudes with shorter ramps: about 10 000 samples at 500 Hz
FAST = Protocol(ramp_s=0.8)

#: one clearly measurable injection per effect (BenchSpring fields)
INJECT = {
    "backlash": dict(backlash_rad=0.04, transition_rad=0.005),
    "hysteresis": dict(friction_torque_Nm=0.15),
    "time_lag": dict(lag_s=0.015),
    "drift": dict(drift_Nm_per_s=0.01),
    "torque_offset": dict(torque_offset_Nm=0.2),
    # an angle offset is a torque offset unless the curve has a crossover to locate
    "angle_offset": dict(backlash_rad=0.04, angle_offset_rad=0.008),
    "stiffening": dict(cubic_stiffness_Nm_per_rad3=7.6),
    "asymmetric_stiffness": dict(asymmetry=0.04),
    "outliers": dict(outlier_fraction=0.002, outlier_size_Nm=1.5),
    "series_compliance": dict(series_stiffness_Nm_per_rad=200.0),
}


def spring(*effects: str, stiffness: float = K) -> BenchSpring:
    """A test spring with the listed effects injected."""
    kw = {}
    for e in effects:
        kw.update(INJECT[e])
    return BenchSpring(stiffness, **kw)


def loop_on(sim):
    """Run the residual loop on a simulated record; returns ``(result, signals)``."""
    sig = make_signals(sim.record, segment(sim.record))
    return run_loop(sig), sig


def simulate_fast(*effects: str, seed: int = 0, **kw):
    return simulate(spring(*effects), protocol=kw.pop("protocol", FAST), seed=seed, **kw)


def floor_pct(sim, sig) -> float:
    """Noise floor of a simulated record as an NRMSE (%)."""
    return 100.0 * sim.noise_floor_Nm / sig.scales.torque_ref


# --- protocols other than the paper's fixed-time staircase ---------------------------------

#: the paper's staircase with linear ramps at one speed (0.15 rad/s): friction and a lag
#: read alike here
ONE_RATE = Protocol(rates_rad_per_s=(0.15,), profile="linear")

#: the same staircase at two speeds: friction and a lag come apart
TWO_RATES = Protocol(rates_rad_per_s=(0.3, 0.08), profile="linear")


def with_extra_torque(sim, extra):
    """The record of ``sim`` with ``extra(t, theta)`` (N·m) added to its torque: structure
    outside the effect library."""
    from springcad.fit.data import make_record

    rec = sim.record
    return make_record(rec.time_s, rec.torque_Nm + extra(rec.time_s, rec.deflection_rad),
                       rec.deflection_rad, rec.encoder_deflection_rad)


def loop_on_record(rec):
    """Run the residual loop on a record; returns ``(result, signals)``."""
    sig = make_signals(rec, segment(rec))
    return run_loop(sig), sig


def triangles(time_s: np.ndarray, speeds_rad_per_s: tuple[float, ...],
              amp_rad: float = 0.3) -> np.ndarray:
    """Deflection (rad) at ``time_s`` (s): one triangle of ``amp_rad`` from zero per speed (in
    order), sharp turns, zero after the last."""
    out, t0 = np.zeros_like(time_s), 0.0
    for speed in speeds_rad_per_s:
        period_s = 4.0 * amp_rad / speed
        on = (time_s >= t0) & (time_s < t0 + period_s)
        phase = (time_s[on] - t0) / period_s
        out[on] = amp_rad * np.where(phase < 0.25, 4 * phase,
                                     np.where(phase < 0.75, 2 - 4 * phase, 4 * phase - 4))
        t0 += period_s
    return out
