"""Issue 24, session 7: misses of held-out generators E and F (spikes in the angle channel
during holds, a motion that changes speed at once without turning).

Records written here with their own physics (not ``springcad.fit.bench``), checked
against the truth they were made with. Units: N·m, rad, s.
"""

import math

import numpy as np
import pytest

from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals

FS_HZ = 500.0


def levels(targets_rad, rate_rad_s, hold_s, fs=FS_HZ):
    """Random levels: linear ramps between ``targets`` at ``rate``, each held ``hold_s``; (t, θ)."""
    pieces, last = [np.zeros(int(0.5 * fs))], 0.0
    for a in targets_rad:
        n = max(2, int(round(abs(a - last) / rate_rad_s * fs)))
        pieces.append(np.linspace(last, a, n, endpoint=False))
        pieces.append(np.full(int(hold_s * fs), a))
        last = a
    pieces.append(np.linspace(last, 0.0, max(2, int(round(abs(last) / rate_rad_s * fs)))))
    pieces.append(np.zeros(int(0.5 * fs)))
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


def test_spikes_in_the_angle_channel_during_holds_are_all_outliers():
    # a linear spring on random levels with 1.5 s holds; 24 spikes of 20-35 mrad in the
    # angle channel, every one inside a hold (where the turn guard applies): the model's
    # elastic torque jumps with the angle sample, which is no step of the model to excuse
    rng = np.random.default_rng(11)
    k_true = 370.0
    targets = [0.15, -0.1, 0.25, -0.2, 0.05, -0.25, 0.2, -0.05, 0.1, -0.15, 0.22, -0.12]
    t, th = levels(targets, 0.2, 1.5)
    torque = k_true * th + rng.normal(0.0, 0.18, t.size)
    meas = th + rng.normal(0.0, 1e-4, t.size)
    holds = np.flatnonzero((np.abs(np.gradient(th)) == 0) & (np.abs(th) > 0.02))
    at = rng.choice(holds[(holds > 20) & (holds < t.size - 20)], 24, replace=False)
    meas[at] += rng.choice([-1.0, 1.0], at.size) * rng.uniform(0.02, 0.035, at.size)
    loop = fit_record(make_record(t, torque, meas)).loop
    assert set(loop.final.effects) == {"outliers"}
    assert set(np.flatnonzero(loop.final.mask)) >= set(at)
    assert not loop.unexplained
    assert loop.final.params()["stiffness_Nm_per_rad"] == pytest.approx(k_true, rel=0.002)


def chirp_then_ramp(fs=1000.0):
    """A chirp 0.05 → 1.5 Hz of 0.5 rad over about 30 s that ends moving fast (23.45 cycles:
    at 0.15 rad, moving toward zero at 4.5 rad/s), then a cosine ramp to rest from zero speed: the motion
    changes speed at once without turning or holding; (t, θ)."""
    amp, f0, f1 = 0.5, 0.05, 1.5
    dur = 23.45 / (0.5 * (f0 + f1))
    u = np.arange(int(dur * fs)) / fs
    pieces = [np.zeros(int(0.5 * fs)), amp * np.sin(2 * np.pi * (f0 * u + (f1 - f0) * u ** 2 / (2 * dur)))]
    end = pieces[-1][-1]
    n = int(0.3 * fs)
    s = np.arange(1, n + 1) / n
    pieces += [end * (1 - 0.5 * (1 - np.cos(np.pi * s))), np.zeros(int(0.5 * fs))]
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


def test_the_deflection_trace_keeps_a_corner_where_the_motion_changes_speed_at_once():
    t, th = chirp_then_ramp()
    rng = np.random.default_rng(5)
    sigma = 1.5e-4
    rec = make_record(t, 20.0 * th, th + rng.normal(0.0, sigma, t.size))
    sig = make_signals(rec, segment(rec))
    corner = int(0.5 * 1000.0) + int(23.45 / 0.775 * 1000.0)
    near = slice(corner - 40, corner + 40)
    # the trace follows the true motion through the corner within a few noise levels
    assert np.max(np.abs(sig.theta_trace[near] - th[near])) < 6 * sigma


def test_a_delay_and_a_cubic_on_a_chirp_ending_fast_are_not_flagged():
    # τ(t) = K·θ(t - 18 ms) + k3·θ³(t - 18 ms): both in the library; the corner at the
    # chirp's end, rounded off by the trace, left a 35-noise-level swing and a flag
    t, th = chirp_then_ramp()
    rng = np.random.default_rng(8)
    k_true, k3, lag = 22.5, 7.8, 0.018
    late = np.interp(t - lag, t, th)
    torque = k_true * late + k3 * late ** 3 + rng.normal(0.0, 0.02, t.size)
    loop = fit_record(make_record(t, torque, th + rng.normal(0.0, 1.5e-4, t.size))).loop
    assert set(loop.final.effects) == {"time_lag", "stiffening"}
    assert not loop.unexplained
    p = loop.final.params()
    assert p["stiffness_Nm_per_rad"] == pytest.approx(k_true, rel=0.01)
    assert p["lag_s"] == pytest.approx(lag, abs=5e-4)
    assert math.isfinite(p["cubic_stiffness_Nm_per_rad3"])


def test_the_trace_follows_a_sine_sweep_through_the_junction_of_its_blocks():
    # whole cycles of 0.3 rad at 0.5 Hz, then of 0.3 rad at 1.5 Hz: at the junction the
    # speed jumps from 0.94 to 2.8 rad/s (generator E's sine sweeps); the cut is placed on
    # the junction itself (a parabola with a kink put it 6 samples early and the trace
    # stepped by 4 mrad there)
    fs = 1000.0
    u1 = np.arange(int(3 / 0.5 * fs)) / fs
    u2 = np.arange(int(4 / 1.5 * fs)) / fs
    th = np.concatenate([np.zeros(500), 0.3 * np.sin(2 * np.pi * 0.5 * u1),
                         0.3 * np.sin(2 * np.pi * 1.5 * u2), np.zeros(500)])
    t = np.arange(th.size) / fs
    rng = np.random.default_rng(4)
    sigma = 1e-4
    rec = make_record(t, 50.0 * th, th + rng.normal(0.0, sigma, t.size))
    sig = make_signals(rec, segment(rec))
    junction = 500 + u1.size
    near = slice(junction - 60, junction + 60)
    assert np.max(np.abs(sig.theta_trace[near] - th[near])) < 6 * sigma
    # and the rate a damper sees has no step there beyond the speed's own jump
    v = np.gradient(th, t)
    assert np.max(np.abs(sig.rate_trace[near] - v[near])) < 0.05 * np.max(np.abs(v))
