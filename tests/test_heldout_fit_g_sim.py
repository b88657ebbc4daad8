"""The held-out fit simulator G (bench/heldout_fit_g_sim.py) against closed forms.

The simulator is the reference of bench/heldout_fit_g.py, so its laws are checked here
against their own closed forms and its oracle against records of known content. No
springcad code is involved.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import heldout_fit_g_oracle as oracle  # noqa: E402
import heldout_fit_g_sim as sim  # noqa: E402
from heldout_fit_g import CASES, make_record  # noqa: E402

FINE_HZ = 2000.0


def staircase_command(peak_rad=0.3):
    """The paper's staircase at 0.3 rad/s with 0.5 s holds on a 2 kHz grid."""
    return sim.ramp_path(sim.paper_staircase(peak_rad, 0.3, 0.5), FINE_HZ)


def run(bench, seed=0):
    return sim.simulate(bench, np.random.default_rng(seed))


def test_linear_spring_reads_torque_equal_to_k_times_angle():
    rec = run(sim.Bench(staircase_command(), FINE_HZ, 500.0, sim.Chain([137.0])))
    assert np.max(np.abs(rec.deflection_rad)) == pytest.approx(0.3, rel=1e-3)
    np.testing.assert_allclose(rec.torque_Nm, 137.0 * rec.deflection_rad, rtol=0, atol=1e-11)


def test_pure_delay_shifts_the_torque_by_whole_samples():
    rate_hz, k = 500.0, 90.0
    rec = run(sim.Bench(staircase_command(), FINE_HZ, rate_hz, sim.Chain([k]),
                        sensors=sim.Sensors(delay_s=3 / rate_hz)))
    np.testing.assert_allclose(rec.torque_Nm[3:], k * rec.deflection_rad[:-3], atol=1e-11)
    assert np.all(rec.torque_Nm[:3] == 0.0)


def test_stack_in_series_is_one_dead_band_of_the_summed_clearances():
    ks, gaps = [150.0, 75.0, 60.0], [0.01, 0.015, 0.02]
    rec = run(sim.Bench(staircase_command(0.8), FINE_HZ, 500.0, sim.Chain(ks, gap_rad=gaps)))
    k_eq = 1 / sum(1 / k for k in ks)  # paper eq. 10: compliances add
    h = sum(gaps) / 2
    th = rec.deflection_rad
    expect = k_eq * np.sign(th) * np.maximum(np.abs(th) - h, 0.0)
    np.testing.assert_allclose(rec.torque_Nm, expect, atol=1e-9 * k_eq)


def test_gear_lash_in_the_motor_encoder_reads_as_a_dead_band():
    k, lash = 120.0, 0.02
    rec = run(sim.Bench(staircase_command(), FINE_HZ, 500.0, sim.Chain([k], gear_lash_rad=lash),
                        deflection_from="motor"))
    q = rec.deflection_rad
    np.testing.assert_allclose(rec.torque_Nm, k * np.sign(q) * np.maximum(np.abs(q) - lash / 2, 0),
                               atol=1e-9 * k)


def test_shaft_in_the_deflection_channel_adds_its_compliance():
    k, k_sh = 100.0, 1500.0
    rec = run(sim.Bench(staircase_command(), FINE_HZ, 500.0, sim.Chain([k], shaft_Nm_per_rad=k_sh),
                        deflection_from="motor", encoder_cols=True))
    np.testing.assert_allclose(rec.torque_Nm, rec.deflection_rad / (1 / k + 1 / k_sh), atol=1e-9)


def test_hardening_disk_follows_its_cubic():
    k, c, ref = 80.0, 0.1, 0.3
    rec = run(sim.Bench(staircase_command(), FINE_HZ, 500.0, sim.Chain([k], cubic_frac=c, cubic_ref_rad=ref)))
    d = rec.deflection_rad
    np.testing.assert_allclose(rec.torque_Nm, k * d * (1 + c * (d / ref) ** 2), atol=1e-9)


def test_cubic_sensor_on_a_linear_spring_is_a_cubic_in_angle():
    k, a3 = 100.0, -0.06
    sen = sim.Sensors(full_scale_Nm=40.0, a3=a3)
    rec = run(sim.Bench(staircase_command(), FINE_HZ, 500.0, sim.Chain([k]), sensors=sen))
    th = rec.deflection_rad
    np.testing.assert_allclose(rec.torque_Nm, k * th + a3 * k ** 3 / 40.0 ** 2 * th ** 3, atol=1e-10)


def test_elastoplastic_friction_takes_up_linearly_and_saturates():
    F, w = 2.0, 1e-3
    theta = np.concatenate([np.linspace(0, 0.1, 1001), np.linspace(0.1, -0.1, 2001)[1:]])
    f = sim.friction_path(theta, 1e-3, sim.Friction(F, w))
    assert f[1000] == pytest.approx(F)
    assert f[1000 + 5] == pytest.approx(F - F / w * 5 * 1e-4, rel=1e-9)  # 0.5 mrad back
    assert f[-1] == pytest.approx(-F)


def test_dahl_friction_reverses_exponentially_over_its_width():
    F, w = 1.5, 2e-3
    theta = np.concatenate([np.linspace(0, 0.1, 1001), np.linspace(0.1, 0.09, 101)[1:]])
    f = sim.friction_path(theta, 1e-3, sim.Friction(F, w, "dahl"))
    back = 0.1 - theta[1000 + 30]
    assert f[1000] == pytest.approx(F, rel=1e-9)
    assert f[1000 + 30] == pytest.approx(-F + 2 * F * math.exp(-back / w), rel=1e-9)


def test_warming_friction_settles_at_f0_over_one_plus_drop():
    F0, drop, dt = 1.0, 0.4, 1e-3
    theta = 0.05 * sim.sine_blocks([(1.0, 0.5, 200)], 1 / dt, 0.0)  # 400 s of cycling
    fr = sim.Friction(F0, 1e-5, thermal_drop=drop, thermal_tau_s=10.0)
    f = sim.friction_path(theta, dt, fr)
    last = np.abs(f[-int(20 / dt):])  # the last 20 s: sliding almost everywhere
    assert np.percentile(last, 90) == pytest.approx(F0 / (1 + drop), rel=0.02)


def test_torque_controlled_hub_rings_at_the_natural_frequency():
    k, J = 100.0, 2e-3
    dt = 1e-5
    cmd = np.full(int(0.5 / dt), 5.0)  # a torque step, no damping
    dyn = sim.Dynamics("torque", J_hub_kgm2=0.0, J_motor_kgm2=J)
    theta, sensor = sim.integrate(cmd, dt, k, 0.0, dyn, None)
    crossings = np.flatnonzero(np.diff(np.sign(theta - 5.0 / k)) != 0)
    period_s = 2 * np.mean(np.diff(crossings)) * dt
    assert period_s == pytest.approx(2 * math.pi * math.sqrt(J / k), rel=2e-3)
    # undamped from rest: swings between 0 and twice the static deflection
    assert theta.max() == pytest.approx(2 * 5.0 / k, rel=2e-3)
    assert abs(theta.min()) < 1e-3 * 5.0 / k
    np.testing.assert_allclose(sensor, k * theta, atol=1e-12)  # J_hub = 0: the stack's torque


def test_rotor_friction_before_the_sensor_sticks_without_chatter():
    k, J, F_up, dt = 90.0, 2.4e-3, 1.3, 1e-4
    cmd = np.concatenate([np.linspace(0, 10.0, 10000), np.full(20000, 10.0)])  # ramp, hold
    dyn = sim.Dynamics("torque", J_hub_kgm2=5e-4, J_motor_kgm2=J - 5e-4,
                       damping_Nms_per_rad=0.5, upstream_friction_Nm=F_up)
    theta, sensor = sim.integrate(cmd, dt, k, 0.0, dyn, None)
    hold = slice(25000, None)
    assert np.ptp(theta[hold]) == 0.0  # stuck: the rotor's friction holds the difference
    assert abs(10.0 - k * theta[-1]) <= F_up
    np.testing.assert_allclose(sensor[hold], k * theta[hold], atol=1e-12)


def test_dropped_and_jittered_samples_stay_ordered():
    t = sim.sample_times(20.0, 500.0, np.random.default_rng(3), jitter=0.3, drop_frac=0.03, n_bursts=3)
    assert np.all(np.diff(t) > 0)
    assert 0.9 * 10000 < t.size < 0.98 * 10000


def test_oracle_leaves_nothing_of_library_physics_and_much_of_a_quadratic_sensor(tmp_path):
    lib = make_record(5, "stack3_four_effects", tmp_path)
    assert lib["oracle_E"] < 20 and lib["unexplained"] is False
    out = make_record(5, "sensor_quadratic", tmp_path)
    assert out["oracle_E"] > 2000 and out["unexplained"] is True


def test_every_case_builds_a_sampled_bench():
    for name, case_fn in CASES.items():
        case = case_fn(np.random.default_rng(1))
        assert case.bench.fine_rate_hz % case.bench.rate_hz == 0, name
        assert 200.0 <= case.bench.rate_hz <= 5000.0, name
        assert case.truth.k_true, name
