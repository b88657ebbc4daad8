"""Shared truths and helpers of the fit tests (simulated, seeded records only)."""

from __future__ import annotations

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
