"""Issue 24, held-out generator E's misses: friction laws (elasto-plastic, Stribeck), an
asymmetric K beside a cubic, coloured sensor noise, a settling torque zero.

Records written here with their own physics (not ``springcad.fit.bench``), checked
against the truth they were made with. Units: N·m, rad, s.
"""

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from issue24_records import dahl_friction, ramps, sine_sweep
from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.evidence import _one_way
from springcad.fit.noise import coloured_noise_model
from springcad.fit.residual import residual_structure
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

K = 60.0


def ep_friction(th, level_Nm, presliding_rad):
    """Coulomb friction with a presliding stiffness ``level/presliding``: after a turn the
    friction changes linearly with the travel, then slides at ±level."""
    out = np.empty_like(th)
    f = 0.0
    k = level_Nm / presliding_rad
    d = np.diff(th, prepend=th[0])
    for i in range(th.size):
        f = min(max(f + k * d[i], -level_Nm), level_Nm)
        out[i] = f
    return out


def stribeck_friction(t, th, sliding_Nm, breakaway_Nm, v_s, presliding_rad):
    """Friction whose level falls from ``breakaway`` at rest to ``sliding`` above ``v_s``,
    taken up over ``presliding_rad`` after each turn (a Dahl-like bristle state)."""
    v = np.gradient(th, t)
    level = sliding_Nm + (breakaway_Nm - sliding_Nm) * np.exp(-(v / v_s) ** 2)
    z = dahl_friction(th, 1.0, presliding_rad)
    return level * z


def ar1(rng, n, sigma, rho):
    """Stationary AR(1) noise of standard deviation ``sigma``."""
    e = rng.normal(0.0, sigma * math.sqrt(1 - rho * rho), n)
    return lfilter([1.0], [1.0, -rho], e, zi=[rho * rng.normal(0.0, sigma)])[0]


def test_elasto_plastic_friction_is_fitted_with_its_own_law_and_not_flagged():
    # a Coulomb friction with a linear presliding take-up (0.5 N·m over 8 mrad) on a sine
    # sweep: Dahl's exponential take-up leaves a kink at every turn; the family's
    # elasto-plastic law describes it, with the friction and presliding stiffness made with
    t, th = sine_sweep([15, 25], [0.2, 0.6], cycles=3)
    rng = np.random.default_rng(3)
    tau = K * th + ep_friction(th, 0.5, 0.008)
    loop = fit_record(make_record(t, tau + rng.normal(0, 0.01, t.size),
                                  th + rng.normal(0, 5e-5, t.size))).loop
    assert set(loop.final.effects) == {"hysteresis"}
    assert loop.laws["hysteresis"]["law"] == "elasto_plastic"
    p = loop.final.params()
    assert p["friction_torque_Nm"] == pytest.approx(0.5, rel=0.03)
    assert p["presliding_stiffness_Nm_per_rad"] == pytest.approx(0.5 / 0.008, rel=0.1)
    assert p["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.005)
    assert not loop.unexplained


def test_an_asymmetric_stiffness_beside_a_cubic_is_their_sum_not_a_cubic_per_side():
    # τ = K±·θ + k3·θ³: the model with both effects reproduces it exactly (closed form)
    t, th = sine_sweep([20], [0.3], cycles=2)
    rec = make_record(t, K * th, th)
    sig = make_signals(rec, segment(rec))
    model = TorqueModel((get_effect("asymmetric_stiffness"), get_effect("stiffening")),
                        sig.scales)
    a, alpha = 0.1, 0.2
    x = model.transfer(TorqueModel((), sig.scales), np.array([K]),
                       {"asymmetric_stiffness": np.array([a]), "stiffening": np.array([alpha])})
    idx = np.arange(sig.n)
    x_rad = model.effective_angle(x, sig, idx)  # the deflection the spring sees
    k3 = K * alpha / sig.scales.theta_ref ** 2
    expect = K * (1 + a * np.sign(x_rad)) * x_rad + k3 * x_rad ** 3
    assert np.allclose(model.predict(x, sig, idx), expect, rtol=0, atol=1e-9 * K)
    report = model.effect_report("stiffening", x)
    assert report["cubic_stiffness_Nm_per_rad3"] == pytest.approx(k3, rel=1e-9)


@pytest.mark.parametrize("rho", [0.0, 0.9])
def test_coloured_noise_model_recovers_the_correlation_time_of_ar1_noise(rho):
    # AR(1) torque noise (ρ = 0.9: correlation time (1 + ρ)/(1 - ρ) = 19 samples) beside
    # white deflection noise read through K; the flexible remainder's 0.1 s windows cut
    # its correlation short: the model matched through the same remainder recovers it
    t, th = sine_sweep([20, 10], [0.2, 0.5], cycles=4)
    rng = np.random.default_rng(7)
    n = t.size
    torque_noise = ar1(rng, n, 0.05, rho)
    white = rng.normal(0.0, 0.015, n)
    rec = make_record(t, K * th + torque_noise + white, th)
    sig = make_signals(rec, segment(rec))
    idx = np.arange(sig.n)
    r = torque_noise + white
    nm = coloured_noise_model(r, idx, sig)
    total = math.hypot(0.05, 0.015)
    share = 0.05 ** 2 / total ** 2
    tau_true = 1.0 + 2.0 * share * rho / (1.0 - rho)
    assert nm.tau == pytest.approx(tau_true, rel=0.25)
    assert nm.sigma == pytest.approx(total, rel=0.06)
    # noise alone, however coloured, is no structure
    assert not residual_structure(r, idx, sig)[1]


def test_slow_structure_left_in_the_remainder_is_not_taken_for_coloured_noise():
    # what a stiffness that dropped by 2 % mid-test leaves (∝ θ in the second half), beside
    # white noise: its correlation reaches past the remainder's 0.1 s windows, so it is not
    # read as AR(1) noise with a long correlation time, and the residual tests find it
    t, th = ramps([10, 20], [10.0], hold_s=0.5, fs=1000.0)
    t, th = np.concatenate([t, t + t[-1] + t[1]]), np.concatenate([th, th])
    rng = np.random.default_rng(4)
    step = np.where(t > 0.5 * t[-1], -0.02 * K * th, 0.0)
    noise = rng.normal(0.0, 0.01, t.size)
    rec = make_record(t, K * th + step + noise, th)
    sig = make_signals(rec, segment(rec))
    idx = np.arange(sig.n)
    r = step - np.mean(step) + noise
    assert coloured_noise_model(r, idx, sig).tau < 2.0
    assert residual_structure(r, idx, sig)[1]


def test_a_drift_whose_rate_settles_is_named_and_what_its_line_leaves_is_flagged():
    # a torque zero settling exponentially (by 0.6 N·m, time constant a fifth of the
    # record) on a staircase: a drift, though not a linear one; each third of the record
    # shows it with the same sign, the residual holds the curve a line cannot follow
    assert _one_way(((-4.3, 0.5), (-0.34, 0.08)), 0.0, 3.0)
    assert _one_way(((-0.45, 0.087), (0.002, 0.005)), 0.0, 3.0)  # settled in the last third
    assert not _one_way(((-4.3, 0.5), (0.34, 0.08)), 0.0, 3.0)  # one way, then back
    assert not _one_way(((-0.1, 0.5), (0.1, 0.08)), 0.0, 3.0)  # nowhere
    t, th = ramps([8, 16], [10.0, 10.0], hold_s=0.8)
    t, th = np.concatenate([t, t + t[-1] + t[1]]), np.concatenate([th, th])
    rng = np.random.default_rng(11)
    zero = 0.6 * (1.0 - np.exp(-t / (0.2 * t[-1])))
    loop = fit_record(make_record(t, K * th + zero + rng.normal(0, 0.01, t.size),
                                  th + rng.normal(0, 5e-5, t.size))).loop
    assert "drift" in loop.final.effects
    assert loop.unexplained
    assert loop.final.params()["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.005)


def test_stribeck_friction_on_three_rates_is_fitted_with_its_law_and_flagged():
    # friction breaking away at 0.8 N·m and sliding at 0.4 N·m above 0.03 rad/s, ramps at
    # three speeds with holds: one friction torque cannot serve every speed; the Stribeck
    # law describes it (sliding and breakaway levels as made) and, being outside the
    # library's one-level friction, the record is flagged with a finding that names it
    t, th = ramps([12], [2.0, 8.0, 32.0], hold_s=0.5)
    rng = np.random.default_rng(5)
    fr = stribeck_friction(t, th, 0.4, 0.8, 0.03, 0.003)
    loop = fit_record(make_record(t, K * th + fr + rng.normal(0, 0.01, t.size),
                                  th + rng.normal(0, 5e-5, t.size))).loop
    assert "hysteresis" in loop.final.effects
    assert loop.laws["hysteresis"]["law"] == "stribeck"
    p = loop.final.params()
    assert p["friction_torque_Nm"] == pytest.approx(0.4, rel=0.1)  # sliding
    assert p["breakaway_friction_Nm"] == pytest.approx(0.8, rel=0.15)
    assert loop.unexplained
    found = [f for f in loop.localisation["findings"] if f["kind"] == "law_outside_library"]
    assert ("hysteresis", "stribeck") in [(f["family"], f["law"]) for f in found]


def hertz_gap(th, half_rad, contact_at_peak_rad, peak_rad):
    """Spring deflection past a gap closed through a Hertzian contact in series: the
    contact compresses by ``contact_at_peak·(u/u_peak)^(2/3)`` while the spring deflects
    by u (tabulated on a fine grid of u and interpolated, no root finding)."""
    u = np.linspace(0.0, peak_rad, 200001)
    d = u + contact_at_peak_rad * (u / peak_rad) ** (2.0 / 3.0)
    return np.sign(th) * np.interp(np.maximum(np.abs(th) - half_rad, 0.0), d, u)


def test_a_gap_taken_up_through_a_hertzian_contact_is_fitted_with_its_law_not_a_cubic():
    # a 16 mrad gap closed through a contact that compresses 20 mrad at the peak torque, on
    # a staircase: the library's crossover leaves a take-up that a cubic would patch (and K
    # 5 % low); the backlash family's Hertzian law describes it, with K and the gap as made,
    # and the record is flagged as physics outside the library's crossover
    t, th = ramps([8, 16, 24], [10.0], hold_s=0.6)
    rng = np.random.default_rng(2)
    peak = math.radians(24)
    u = hertz_gap(th, 0.008, 0.02, peak)
    loop = fit_record(make_record(t, K * u + rng.normal(0, 0.002 * K * peak, t.size),
                                  th + rng.normal(0, 5e-5, t.size))).loop
    assert set(loop.final.effects) == {"backlash"}
    assert loop.laws["backlash"]["law"] == "hertzian_contact"
    p = loop.final.params()
    assert p["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.01)
    assert p["backlash_rad"] == pytest.approx(0.016, rel=0.1)
    assert loop.unexplained
    found = [f for f in loop.localisation["findings"] if f["kind"] == "law_outside_library"]
    assert ("backlash", "hertzian_contact") in [(f["family"], f["law"]) for f in found]
