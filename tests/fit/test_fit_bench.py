"""The bench simulator: protocol, reproducibility, injected truth, noise floor."""

import numpy as np
import pytest

from springcad.fit.bench import BenchNoise, BenchSpring, Protocol, dahl_friction, simulate
from springcad.fit.protocols import PAPER_AMPLITUDES_RAD
from fit_helpers import FAST, INJECT, K, spring


def test_protocol_follows_the_paper():
    p = Protocol()
    t = p.times()
    theta = p.deflection(t)
    assert p.sample_rate_hz == 500.0
    assert np.degrees(PAPER_AMPLITUDES_RAD) == pytest.approx([4, 8, 12, 16, 20, 24])
    assert theta.max() == pytest.approx(np.radians(24)) and theta.min() == pytest.approx(-np.radians(24))
    assert theta[0] == 0.0 and theta[-1] == pytest.approx(0.0, abs=1e-12)
    assert t[-1] == pytest.approx(p.duration_s)
    # each ramp is 0 -> +A -> 0 -> -A -> 0: the sign changes twice per amplitude
    crossings = np.sum(np.diff(np.sign(theta[np.abs(theta) > 1e-6])) != 0)
    assert crossings == 2 * len(PAPER_AMPLITUDES_RAD) - 1


def test_linear_profile_has_constant_speed_per_ramp():
    p = Protocol(profile="linear", ramp_s=1.0)
    t = np.linspace(p.rest_s + 0.1, p.rest_s + 0.9, 50)
    assert np.ptp(np.diff(p.deflection(t))) < 1e-12


def test_same_seed_same_record_other_seed_other_noise():
    a = simulate(spring("hysteresis", "outliers"), protocol=FAST, seed=3).record
    b = simulate(spring("hysteresis", "outliers"), protocol=FAST, seed=3).record
    c = simulate(spring("hysteresis", "outliers"), protocol=FAST, seed=4).record
    np.testing.assert_array_equal(a.torque_Nm, b.torque_Nm)
    np.testing.assert_array_equal(a.deflection_rad, b.deflection_rad)
    assert not np.allclose(a.torque_Nm, c.torque_Nm)


@pytest.mark.parametrize("effect", list(INJECT))
def test_injected_names(effect):
    expected = {"backlash", "angle_offset"} if effect == "angle_offset" else {effect}
    assert set(spring(effect).injected()) == expected


def test_noise_floor_is_the_error_of_the_true_model():
    sim = simulate(BenchSpring(K), protocol=FAST, seed=9)
    rec = sim.record
    err = rec.torque_Nm - K * rec.deflection_rad
    assert np.std(err) == pytest.approx(sim.noise_floor_Nm, rel=0.03)
    assert sim.noise_floor_Nm == pytest.approx(np.hypot(0.03, K * 1e-3), rel=1e-6)


def test_glitches_and_encoder_channel():
    sim = simulate(BenchSpring(K, outlier_fraction=0.01, outlier_size_Nm=2.0,
                               series_stiffness_Nm_per_rad=100.0), protocol=FAST, seed=2)
    rec = sim.record
    assert sim.glitch_mask.sum() == round(0.01 * rec.n_samples)
    jump = np.abs(rec.torque_Nm - K * rec.deflection_rad)
    assert np.all(jump[sim.glitch_mask] > 0.8)
    wind_up = rec.encoder_deflection_rad - rec.deflection_rad
    ok = ~sim.glitch_mask
    slope = np.polyfit(K * rec.deflection_rad[ok], wind_up[ok], 1)[0]
    assert slope == pytest.approx(1 / 100.0, rel=0.03)


def test_dahl_friction_saturates_and_reverses():
    theta = np.concatenate([np.linspace(0, 0.1, 1000), np.linspace(0.1, 0.0, 1000)])
    f = dahl_friction(theta, 0.5, 0.005)
    assert f[0] == 0.0
    assert f[999] == pytest.approx(0.5, rel=1e-6)
    assert f[-1] == pytest.approx(-0.5, rel=1e-6)


def test_from_design_uses_stack_stiffness_and_nominal_backlash():
    design = {"stack": {"stiffness_Nm_per_rad": 37.5, "backlash_rad": {"nominal": 0.036}}}
    s = BenchSpring.from_design(design, friction_torque_Nm=0.1)
    assert (s.stiffness_Nm_per_rad, s.backlash_rad, s.friction_torque_Nm) == (37.5, 0.036, 0.1)


def test_camera_rate_noise_is_correlated():
    sim = simulate(BenchSpring(K), protocol=FAST, noise=BenchNoise(torque_Nm=1e-6, camera_fps=60), seed=1)
    e = sim.record.deflection_rad - FAST.deflection(sim.record.time_s)
    e = e - e.mean()
    lag1 = float(e[1:] @ e[:-1] / (e @ e))
    assert lag1 > 0.9
