"""Generator H's bench simulator against closed forms (bench/heldout_fit_h_sim.py)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import heldout_fit_h_sim as sim  # noqa: E402


def _sine_bench(**kw):
    amp, f = 0.3, 0.5
    q = lambda dt, rng: amp * np.sin(2 * np.pi * f * np.arange(0, 6.0, dt))  # noqa: E731
    stack = sim.Stack([sim.Spring(k_pos=120.0)])
    return sim.Bench(stack=stack, fs=1000.0, q=q, **kw)


def test_linear_spring_gives_k_exactly():
    rec = sim.simulate(_sine_bench(), np.random.default_rng(0))
    k = np.sum(rec["T_clean"] * rec["theta_clean"]) / np.sum(rec["theta_clean"] ** 2)
    assert k == pytest.approx(120.0, rel=1e-9)


def test_series_law_and_clearances_add():
    """Two springs in series: 1/K = 1/K1 + 1/K2 beyond the clearance b1 + b2 (paper eq. 10)."""
    st = sim.Stack([sim.Spring(k_pos=100.0, b=0.01), sim.Spring(k_pos=300.0, b=0.02)])
    th = np.array([-0.3, -0.0149, 0.0, 0.0149, 0.3])
    T = st.torque_of(th, 100.0)
    k = 1 / (1 / 100 + 1 / 300)
    assert T[0] == pytest.approx(k * (-0.3 + 0.015), rel=1e-6)
    assert T[4] == pytest.approx(k * (0.3 - 0.015), rel=1e-6)
    assert np.all(T[1:4] == 0.0)


def test_pure_delay_shifts_sine_phase():
    d = 0.012
    rec = sim.simulate(_sine_bench(delay_s=d), np.random.default_rng(0))
    t, T, th = rec["t"], rec["T_clean"], rec["theta_clean"]
    sel = t > 1.0
    w = 2 * np.pi * 0.5
    ph = lambda x: np.angle(np.sum(x[sel] * np.exp(-1j * w * t[sel])))  # noqa: E731
    assert ph(th) - ph(T) == pytest.approx(w * d, abs=1e-4)


def test_first_order_filter_gain_at_corner():
    tau, dt = 0.01, 1e-5
    t = np.arange(0, 0.6, dt)
    w = 1 / tau
    y = sim.first_order(np.sin(w * t), tau, dt)
    sel = t > 0.3  # 30 time constants: the transient is gone
    assert np.max(np.abs(y[sel])) == pytest.approx(1 / np.sqrt(2), rel=1e-3)


def test_equal_filters_keep_linear_relation():
    """The same Butterworth on both channels of a linear spring: torque = K x filtered angle."""
    rec = sim.simulate(_sine_bench(aa_torque_hz=30.0, aa_angle_hz=30.0), np.random.default_rng(0))
    assert np.max(np.abs(rec["T_clean"] - 120.0 * rec["theta_clean"])) < 1e-9


def test_dahl_saturates_and_flips():
    th = np.concatenate([np.linspace(0, 0.05, 500), np.linspace(0.05, -0.05, 1000)])
    z = sim.dahl(th, 0.002)
    assert z[499] == pytest.approx(1 - np.exp(-25), abs=1e-9)
    assert z[-1] == pytest.approx(-1.0, abs=1e-9)
    # exact law: after reversal, 1 + z decays as exp(-travel/w)
    travel = 0.05 - th[700]
    assert 1 + z[700] == pytest.approx((1 + z[499]) * np.exp(-travel / 0.002), rel=1e-9)


def test_iwan_full_slip_at_twice_width():
    th = np.linspace(0, 0.02, 2001)
    z = sim.iwan(th, 0.004, n=40)
    assert z[-1] == pytest.approx(1.0)
    # Masing initial slope: all elements stick, sum of 1/(n widths)
    widths = 2 * 0.004 * (np.arange(40) + 1) / 40
    assert (z[1] - z[0]) / (th[1] - th[0]) == pytest.approx(np.mean(1 / widths), rel=1e-6)


def test_zoh_mean_lag_half_update():
    rec = sim.simulate(_sine_bench(zoh_hz=50.0), np.random.default_rng(3))
    t, T, th = rec["t"], rec["T_clean"], rec["theta_clean"]
    sel = t > 1.0
    w = 2 * np.pi * 0.5
    ph = lambda x: np.angle(np.sum(x[sel] * np.exp(-1j * w * t[sel])))  # noqa: E731
    assert (ph(th) - ph(T)) / w == pytest.approx(0.5 / 50.0, abs=3e-4)
