"""Turning points, and the deflection trace used for time shifts and friction's travel since the turn.

References: the true (noise-free) deflection of the simulated bench, and the
variance of a cubic least-squares fit (centred in its window: about 2.25 σ²/w;
at the end of a one-sided window: about 16 σ²/w).
"""

import numpy as np
import pytest

from springcad.fit.bench import BenchSpring, Protocol, simulate
from springcad.fit.protocols import SineSweep
from springcad.fit.segment import _sharp_turn, segment
from springcad.fit.signals import make_signals

FS_HZ = 500.0
NOISE_RAD = 8e-4


def _turn_errors(protocol, seed):
    """Trace minus true deflection at the true turning points (rad), and the noise level."""
    sim = simulate(BenchSpring(40.0), protocol=protocol, seed=seed)
    rec = sim.record
    sig = make_signals(rec, segment(rec))
    true = protocol.deflection(rec.time_s)
    d = np.diff(true)
    turns = np.flatnonzero(np.sign(d[1:]) * np.sign(d[:-1]) < 0) + 1
    return sig.theta_trace[turns] - true[turns], sig.scales.theta_noise


@pytest.mark.parametrize("seed", [1, 2])
def test_a_straight_turn_is_sharp_and_a_round_one_is_not(seed):
    rng = np.random.default_rng(seed)
    i = np.arange(-60, 61, dtype=float)
    noise = NOISE_RAD * rng.normal(size=i.size)
    v_shape = 0.3 - 0.2 * np.abs(i) / FS_HZ + noise          # a linear ramp reversing at 0.2 rad/s
    sine = 0.3 * np.cos(2 * np.pi * 1.0 * i / FS_HZ) + noise  # the turn of a 1 Hz sine
    assert _sharp_turn(v_shape, 60, 60)
    assert not _sharp_turn(sine, 60, 60)


def test_the_trace_at_a_sine_turn_is_fitted_from_both_sides():
    # a fit cut at the turn reads the turn angle at the end of a one-sided window (noise
    # about 4 σ/√w); fitted across the turn it is about 1.5 σ/√w
    sweep = SineSweep(amplitudes_rad=(0.15, 0.3), frequencies_hz=(0.4, 1.0), cycles=4)
    err, sigma = _turn_errors(sweep, seed=11)
    assert err.size >= 20
    rms = float(np.sqrt(np.mean(err ** 2)))
    # the window is at least 60 ms (31 samples): one-sided ≈ 0.72 σ, two-sided ≈ 0.27 σ
    assert rms < 0.45 * sigma, (rms, sigma)


def test_the_trace_keeps_a_linear_ramps_corner():
    # fitted across, a corner at 0.3 rad/s would be rounded off by millirad
    ramps = Protocol(amplitudes_rad=(0.1, 0.2, 0.3), rates_rad_per_s=(0.3,), profile="linear")
    err, sigma = _turn_errors(ramps, seed=12)
    assert err.size >= 5
    assert float(np.sqrt(np.mean(err ** 2))) < 1.2 * sigma


def test_a_linear_ramps_turn_is_placed_at_its_corner():
    # the moving average's extreme sits on the rounded top of the corner and moves by a
    # few samples with the noise; the V fitted across the turn places it within a sample
    ramps = Protocol(amplitudes_rad=(0.1, 0.2, 0.3), rates_rad_per_s=(0.3, 0.1), profile="linear")
    sim = simulate(BenchSpring(40.0), protocol=ramps, seed=13)
    rec = sim.record
    true = ramps.deflection(rec.time_s)
    d = np.diff(true)
    corners = np.flatnonzero(np.sign(d[1:]) * np.sign(d[:-1]) < 0) + 1
    found = segment(rec).turning_points
    assert found.size == corners.size
    off = found - corners
    assert np.sqrt(np.mean(off ** 2.0)) <= 1.0, off


def _staircase(profile: str, fs: float = 1000.0, hold_s: float = 0.8, ramp_s: float = 0.15):
    """0 → 0.1 → 0.2 → 0.3 → 0 → -0.3 → 0 rad, a hold after every step (the stops inside a
    run: the motion halts without turning); ``profile`` "cosine" or "linear"; (t, θ)."""
    levels = [0.0, 0.1, 0.2, 0.3, 0.0, -0.1, -0.2, -0.3, 0.0]
    pieces = [np.zeros(int(0.5 * fs))]
    n = int(ramp_s * fs)
    s = np.arange(1, n + 1) / n
    shape = 0.5 * (1.0 - np.cos(np.pi * s)) if profile == "cosine" else s
    for a, b in zip(levels[:-1], levels[1:]):
        steps = max(1, round(abs(b - a) / 0.1))
        for k in range(steps):
            lo = a + (b - a) * k / steps
            hi = a + (b - a) * (k + 1) / steps
            pieces += [lo + (hi - lo) * shape, np.full(int(hold_s * fs), hi)]
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


@pytest.mark.parametrize("profile", ["cosine", "linear"])
def test_the_trace_keeps_the_steps_of_a_staircase_whose_stops_lie_inside_a_run(profile):
    # a stop between two steps in the same direction is no turn: fitted across it with a
    # window of 15 % of the run (0.3 s), the cubic rounded a 0.15 s step off by 20 mrad and
    # a pure delay read as a first-order filter; cut at the stop, the trace keeps the step
    from springcad.fit.data import make_record

    t, true = _staircase(profile)
    rng = np.random.default_rng(5)
    meas = true + rng.normal(0.0, 3e-5, t.size)
    rec = make_record(t, 40.0 * true + rng.normal(0.0, 0.01, t.size), meas)
    sig = make_signals(rec, segment(rec))
    err = sig.theta_trace - true
    # the moving average (20 ms) alone misses a 0.15 s cosine step by up to ~1 mrad
    assert float(np.max(np.abs(err))) < 1.5e-3, float(np.max(np.abs(err)))
    assert float(np.sqrt(np.mean(err ** 2))) < 1e-4, float(np.sqrt(np.mean(err ** 2)))
