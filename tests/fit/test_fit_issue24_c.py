"""Issue 24, held-out generator C's misses: the rate at a start from rest, support of a
parameter nothing measures, a filter in the torque sensor, a local departure.

Records written here with the physics of ``issue24_records`` (not ``springcad.fit.bench``).
Units: N·m, rad, s.
"""

import math

import numpy as np
import pytest

from issue24_records import deadband, first_order, ramps
from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.evidence import audit
from springcad.fit.other_laws import FirstOrderLag, TorqueFilter
from springcad.fit.residual import local_departure
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

K = 40.0


def _cosine_steps(fs=1000.0, amp=0.3, ramp_s=1.0, hold_s=0.5):
    """Rest, then cosine ramps 0 → +A → 0 → -A → 0 with holds between; (t, θ, dθ/dt)."""
    u = np.arange(int(ramp_s * fs)) / fs
    up = 0.5 * (1 - np.cos(np.pi * u / ramp_s))
    rate = 0.5 * np.pi / ramp_s * np.sin(np.pi * u / ramp_s)
    hold = np.ones(int(hold_s * fs))
    th, v = [0 * hold], [0 * hold]
    for a0, a1 in ((0, amp), (amp, 0), (0, -amp), (-amp, 0), (0, amp), (amp, 0)):
        th += [a0 + (a1 - a0) * up, a1 * hold]
        v += [(a1 - a0) * rate, 0 * hold]
    th, v = np.concatenate(th), np.concatenate(v)
    return np.arange(th.size) / fs, th, v


def test_the_rate_a_damper_sees_has_no_spike_where_a_cosine_ramp_leaves_a_hold():
    # a hold's trace is its mean and the ramp's cubic after it starts a fraction of a mrad
    # away: differentiated across the cut that read as a 0.2 rad/s speed for two samples,
    # which a damper turned into two 'glitches' (generator C F06); the rate is taken
    # within each piece of the trace, zero in holds
    t, th, v = _cosine_steps()
    rng = np.random.default_rng(3)
    rec = make_record(t, K * th + rng.normal(0, 0.05, t.size), th + rng.normal(0, 1e-4, t.size))
    sig = make_signals(rec, segment(rec))
    err = np.abs(sig.rate_trace - v)
    peak = float(np.max(np.abs(v)))
    assert np.max(err) < 0.05 * peak
    # zero in holds, but for the sample next to a corner (the speed reached over a sample)
    inner = sig.in_hold & np.roll(sig.in_hold, 1) & np.roll(sig.in_hold, -1)
    assert np.all(np.abs(sig.rate_trace[inner]) < 1e-12)


def test_a_parameter_on_its_null_bound_with_no_standard_error_is_not_supported():
    # a filter time constant of zero rests on its bound: the fit cannot move it, its
    # standard error is zero, and nothing measured it; it was counted as infinitely
    # well supported (generator C O11, O16: a zero-size lag named)
    t, th = ramps([10, 20], [20.0], hold_s=0.3)
    rng = np.random.default_rng(2)
    rec = make_record(t, K * th + rng.normal(0, 0.02, t.size), th + rng.normal(0, 1e-4, t.size))
    sig = make_signals(rec, segment(rec))
    idx = np.arange(sig.n)
    model = TorqueModel((FirstOrderLag(),), sig.scales)
    x = np.array([K, 0.0])
    ev = audit(model, x, sig, idx, 0.06, 1e-3, 3.0).effects["time_lag"]
    assert not ev.ok and not ev.supported
    assert all(c.support_z == 0.0 for c in ev.checks)


def test_a_torque_filter_is_the_deflection_filter_on_a_linear_spring():
    # the low-pass is linear: filtering K·θ or θ then multiplying by K is one thing
    t, th = ramps([8, 16], [30.0, 10.0], hold_s=0.3)
    rng = np.random.default_rng(4)
    rec = make_record(t, K * th, th + rng.normal(0, 1e-4, t.size))
    sig = make_signals(rec, segment(rec))
    idx = np.arange(0, sig.n, 3)
    torque = TorqueModel((TorqueFilter(),), sig.scales)
    angle = TorqueModel((FirstOrderLag(),), sig.scales)
    x = np.array([K, 0.015])
    assert torque.predict(x, sig, idx) == pytest.approx(angle.predict(x, sig, idx), abs=1e-9)


def test_a_torque_filter_rounds_the_crossover_that_a_deflection_filter_keeps_sharp():
    # across a dead band the sensor filters the torque: its reading is the reference
    # first_order(K·deadband(θ)), which the deflection filter put through the dead band
    # misses at every take-up; the torque-filter law reproduces it, and the model keeps
    # a sample's own deflection noise (a law that averaged it away would gain from it)
    t, th = ramps([10, 20], [60.0, 20.0], hold_s=0.3, fs=1000.0)
    half, T = 0.015, 0.02
    ref = first_order(t, K * deadband(th, half), T)
    rec = make_record(t, ref, th)
    sig = make_signals(rec, segment(rec))
    idx = np.arange(sig.n)
    bl = get_effect("backlash")
    x = np.array([K, half, 1e-5, T])
    torque = TorqueModel((bl, TorqueFilter()), sig.scales)
    angle = TorqueModel((bl, FirstOrderLag()), sig.scales)
    peak = float(np.max(np.abs(ref)))
    err_torque = np.max(np.abs(torque.predict(x, sig, idx) - ref))
    err_angle = np.max(np.abs(angle.predict(x, sig, idx) - ref))
    assert err_torque < 0.01 * peak
    assert err_angle > 5 * err_torque
    noisy = make_record(t, ref, th + np.random.default_rng(6).normal(0, 1e-4, t.size))
    nsig = make_signals(noisy, segment(noisy))
    jitter = torque.predict(x, nsig, idx) - torque.predict(x, sig, idx)
    # the deflection noise reaches the model torque through the spring's slope, unfiltered
    moving = np.abs(deadband(th, half)) > 0
    slope_noise = K * (nsig.theta - sig.theta)
    assert np.corrcoef(jitter[moving], slope_noise[moving])[0, 1] > 0.9


def test_a_local_departure_counts_when_it_stands_out_of_what_noise_averages_reach():
    # a difference between two laws that lives at a few brief events: 5 noise levels for
    # 10 samples at three places in 20000 counts; 0.5 noise levels does not; nor does a
    # tall single-sample difference narrower than any window's averaging can resolve
    n, sigma = 20000, 1.0
    d = np.zeros(n)
    for at in (3000, 9000, 15000):
        d[at:at + 10] = 5.0 * sigma
    out = local_departure(d, sigma, 1.0, 1e-6)
    # judged on the window that sets it farthest above its bar (its mean over that window)
    assert out["significant"] and out["threshold_Nm"] < out["peak_Nm"] <= 5.0 * sigma
    assert not local_departure(0.1 * d, sigma, 1.0, 1e-6)["significant"]
    spike = np.zeros(n)
    spike[500] = 3.0 * sigma
    assert not local_departure(spike, sigma, 1.0, 1e-6)["significant"]
    # the bar follows the noise's own averages: the z of p = 1e-6 shared over the windows
    w = out["window_samples"]
    assert out["threshold_Nm"] >= sigma and out["threshold_Nm"] <= 8.0 * sigma / math.sqrt(w) + sigma
