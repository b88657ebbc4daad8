"""The held-out fit simulator A (bench/heldout_fit_a_sim.py) against closed forms.

The simulator is the reference for bench/heldout_fit_a.py, so its laws are checked here
against their own closed forms (no springcad code involved).
"""

import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import heldout_fit_a_sim as sim  # noqa: E402
from heldout_fit_a_cases import CASES  # noqa: E402


def test_jenkins_loop_width_is_twice_the_friction():
    theta = np.concatenate([np.linspace(0, 0.3, 3001), np.linspace(0.3, -0.3, 6001)[1:]])
    F = sim.jenkins(theta, 2.0, 2.0 / 1e-3)
    assert F[3000] == pytest.approx(2.0)
    assert F[-1] == pytest.approx(-2.0)
    # presliding: after the turn the friction falls by k_pre * angle until it saturates
    i = 3000 + 5  # 5 steps of 1e-4 rad back
    assert F[i] == pytest.approx(2.0 - 2.0 / 1e-3 * 5e-4, rel=1e-9)


def test_dahl_reverses_exponentially_over_its_angle():
    xc, Fc = 1e-3, 3.0
    theta = np.concatenate([np.linspace(0, 0.1, 10001), 0.1 - np.linspace(0, 0.01, 10001)[1:]])
    F = sim.dahl(theta, Fc, Fc / xc)
    back = 0.1 - theta[10000:]
    expected = -Fc + 2 * Fc * np.exp(-back / xc)
    np.testing.assert_allclose(F[10000:], expected, atol=1e-9)


def test_lugre_at_constant_speed_gives_the_stribeck_curve():
    dt, v = 1e-4, 0.05
    theta = v * np.arange(0, 2.0, dt)
    Fc, Fs, vs = 1.0, 2.0, 0.05
    F = sim.lugre(theta, dt, Fc, Fs, vs, 1e4, 0.5)
    g = Fc + (Fs - Fc) * np.exp(-(v / vs) ** 2)
    assert F[-1] == pytest.approx(g + 0.5 * v, rel=1e-6)


def test_hertz_backlash_solves_its_compliance_equation():
    theta = np.linspace(-0.4, 0.4, 801)
    b, K, dp, Tp = 0.02, 300.0, 0.01, 100.0
    T = sim.hertz_backlash_torque(theta, b, K, dp, Tp)
    kh = Tp / dp ** 1.5
    x = np.maximum(np.abs(theta) - b / 2, 0)
    back = np.abs(T) / K + (np.abs(T) / kh) ** (2 / 3)
    np.testing.assert_allclose(back, x, atol=1e-9)
    assert np.all(T[np.abs(theta) <= b / 2] == 0)


def test_first_order_filter_step_response():
    dt, tau = 1e-4, 0.02
    y = sim.first_order_filter(np.ones(5000), dt, tau)
    t = dt * np.arange(1, 5001)
    np.testing.assert_allclose(y, 1 - np.exp(-t / tau), atol=1e-9)


def test_pure_delay_and_records_are_deterministic():
    spec = {"fs": 1000, "path": sim.staircase([0.1, 0.2], 0.5, 0.5), "K": 200.0, "delay": 0.02,
            "noise_frac": 1e-12, "angle_noise": 0.0}
    rec = sim.simulate(spec, np.random.default_rng(1))
    t, T, th = rec["t_s"], rec["torque_Nm"], rec["deflection_rad"]
    np.testing.assert_allclose(T, 200.0 * np.interp(t - 0.02, t, th, left=0.0), atol=1e-6)
    case = CASES[0]
    a = sim.simulate(case.build(np.random.default_rng([1, zlib.crc32(b"x")])), np.random.default_rng(3))
    b = sim.simulate(case.build(np.random.default_rng([1, zlib.crc32(b"x")])), np.random.default_rng(3))
    np.testing.assert_array_equal(a["torque_Nm"], b["torque_Nm"])


def test_case_names_are_unique_and_labels_use_library_names():
    names = [c.name for c in CASES]
    assert len(names) == len(set(names)) >= 32
    library = {"backlash", "hysteresis", "time_lag", "drift", "torque_offset", "angle_offset", "stiffening",
               "asymmetric_stiffness", "outliers", "series_compliance"}
    for c in CASES:
        flat = {x for i in c.required for x in (i if isinstance(i, tuple) else (i,))}
        assert flat | c.allowed <= library, c.name
        assert not (c.k_check and c.unexplained), c.name
