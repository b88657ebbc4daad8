"""The residual loop on simulated records with undeclared effects.

For every effect of the library, and for pairs: the loop names exactly the
injected effects, recovers their size, and ends within 20 % of the noise floor.
Clean data gets no effect; structure outside the library is reported as
unexplained.
"""

import itertools

import numpy as np
import pytest

from springcad.fit.bench import BenchNoise, BenchSpring, simulate
from springcad.fit.data import make_record
from springcad.fit.effects import EFFECT_NAMES
from springcad.fit.noise import noise_model
from fit_helpers import FAST, INJECT, K, floor_pct, loop_on, simulate_fast

#: effect -> (reported parameter, injected value, relative tolerance)
RECOVER = {
    "backlash": ("backlash_rad", 0.04, 0.05),
    "hysteresis": ("friction_torque_Nm", 0.15, 0.1),
    "time_lag": ("lag_s", 0.015, 0.1),
    "drift": ("drift_Nm_per_s", 0.01, 0.1),
    "torque_offset": ("torque_offset_Nm", 0.2, 0.1),
    "angle_offset": ("angle_offset_rad", 0.008, 0.1),
    "stiffening": ("cubic_stiffness_Nm_per_rad3", 7.6, 0.15),
    "asymmetric_stiffness": ("stiffness_pos_Nm_per_rad", K * 1.04, 0.01),
    "outliers": ("n_outliers", 20, 0.1),
    "series_compliance": ("series_stiffness_Nm_per_rad", 200.0, 0.05),
}


def _check(sim, res, sig):
    injected = set(sim.injected)
    added = {s.effect for s in res.steps if s.action == "add"}
    assert set(res.identified) == injected, [(s.action, s.effect) for s in res.steps]
    assert res.confounded == () and res.rejected == ()
    assert set(res.final.effects) == injected
    assert added <= injected, "spurious effect added"
    assert all(s.action == "add" for s in res.steps)
    final = res.nrmse_pct(res.final, sig)
    assert final == pytest.approx(floor_pct(sim, sig), rel=0.2)
    assert not res.unexplained, res.structure
    assert res.final.params()["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.01)


def test_effect_library_is_the_issue_list():
    assert set(EFFECT_NAMES) == {"backlash", "hysteresis", "time_lag", "drift", "torque_offset",
                                 "angle_offset", "stiffening", "asymmetric_stiffness", "outliers",
                                 "series_compliance"}
    assert set(INJECT) == set(EFFECT_NAMES)


def test_clean_data_gets_no_effect():
    sim = simulate_fast(seed=11)
    res, sig = loop_on(sim)
    assert res.steps == ()
    assert res.final.effects == ()
    assert not res.unexplained
    assert res.nrmse_pct(res.final, sig) == pytest.approx(floor_pct(sim, sig), rel=0.05)


def test_clean_data_with_camera_rate_deflection_noise_gets_no_effect():
    sim = simulate(BenchSpring(K), protocol=FAST, noise=BenchNoise(camera_fps=60.0), seed=12)
    res, sig = loop_on(sim)
    assert res.final.effects == ()
    assert not res.unexplained, res.structure
    assert noise_model(sim.record.torque_Nm - K * sim.record.deflection_rad, 500.0).tau > 2


@pytest.mark.parametrize("effect", list(INJECT))
def test_single_effect_is_named_and_recovered(effect):
    sim = simulate_fast(effect, seed=21)
    res, sig = loop_on(sim)
    _check(sim, res, sig)
    key, value, rel = RECOVER[effect]
    assert res.final.params()[key] == pytest.approx(value, rel=rel)
    step = next(s for s in res.steps if s.effect == effect)
    assert step.nrmse_after_pct < step.nrmse_before_pct or effect == "series_compliance"
    assert step.evidence["heldout_gain"] > res.settings.gain_threshold
    assert step.evidence["meaning"] and step.evidence["detector"]["looks_for"]


FAST_PAIRS = [("backlash", "hysteresis"), ("hysteresis", "time_lag"), ("drift", "torque_offset"),
              ("stiffening", "asymmetric_stiffness"), ("outliers", "backlash"),
              ("series_compliance", "stiffening"), ("angle_offset", "hysteresis"),
              ("time_lag", "drift")]


@pytest.mark.parametrize("pair", FAST_PAIRS, ids="+".join)
def test_pair_of_effects(pair):
    sim = simulate_fast(*pair, seed=31)
    res, sig = loop_on(sim)
    _check(sim, res, sig)


@pytest.mark.slow
@pytest.mark.parametrize("pair", [p for p in itertools.combinations(INJECT, 2)
                                  if p not in FAST_PAIRS and p[::-1] not in FAST_PAIRS],
                         ids="+".join)
def test_every_other_pair_of_effects(pair):
    sim = simulate_fast(*pair, seed=41)
    res, sig = loop_on(sim)
    _check(sim, res, sig)


TRIPLES = [("backlash", "hysteresis", "stiffening"), ("drift", "torque_offset", "asymmetric_stiffness"),
           ("backlash", "hysteresis", "time_lag"), ("outliers", "backlash", "time_lag"),
           ("hysteresis", "time_lag", "drift"), ("series_compliance", "hysteresis", "backlash")]


@pytest.mark.parametrize("triple", TRIPLES[:3], ids="+".join)
def test_three_effects(triple):
    sim = simulate_fast(*triple, seed=43)
    res, sig = loop_on(sim)
    _check(sim, res, sig)


@pytest.mark.slow
@pytest.mark.parametrize("triple", TRIPLES[3:], ids="+".join)
def test_three_more_effects(triple):
    sim = simulate_fast(*triple, seed=44)
    res, sig = loop_on(sim)
    _check(sim, res, sig)


def test_every_parameter_has_an_interval_covering_the_truth():
    sim = simulate_fast("backlash", "hysteresis", "time_lag", seed=45)
    res, _ = loop_on(sim)
    truth = {"stiffness_Nm_per_rad": K, "backlash_rad": 0.04, "transition_rad": 0.005,
             "friction_torque_Nm": 0.15, "lag_s": 0.015}
    for key, value in truth.items():
        ci = res.intervals[key]  # one record: within 3 standard errors
        assert abs(ci["value"] - value) <= 3 * ci["se"], (key, ci)
    assert set(res.intervals) == set(res.final.params())


def _with_extra_torque(sim, extra):
    rec = sim.record
    return make_record(rec.time_s, rec.torque_Nm + extra(rec.time_s, rec.deflection_rad),
                       rec.deflection_rad)


def _loop_record(rec):
    from springcad.fit.loop import run_loop
    from springcad.fit.segment import segment
    from springcad.fit.signals import make_signals
    sig = make_signals(rec, segment(rec))
    return run_loop(sig), sig


def test_ripple_outside_the_library_is_unexplained():
    # a torque ripple periodic in deflection (cam tooth passing): no effect models it
    sim = simulate_fast(seed=51)
    rec = _with_extra_torque(sim, lambda t, th: 0.2 * np.sin(2 * np.pi * th / 0.1))
    res, _ = _loop_record(rec)
    assert res.unexplained
    test = res.structure["tests"]["by_deflection_and_direction"]
    assert test["significant"] and test["p_value"] < 1e-6
    assert test["structure_rms_over_noise"] > 0.5


def test_slow_wandering_zero_is_unexplained_after_what_can_be_explained():
    # the torque zero wanders (not linearly): offset and drift explain part of it only
    sim = simulate_fast("backlash", seed=52)
    rec = _with_extra_torque(sim, lambda t, th: 0.3 * np.sin(3 * np.pi * t / t[-1]))
    res, _ = _loop_record(rec)
    assert "backlash" in res.final.effects
    assert res.unexplained
    assert res.structure["tests"]["by_time"]["significant"]


def test_noise_model_of_white_and_camera_rate_noise():
    rng = np.random.default_rng(0)
    white = noise_model(rng.normal(0, 0.05, 20_000), 500.0)
    assert white.lag == 1 and white.tau == pytest.approx(1.0, abs=0.05)
    assert white.sigma == pytest.approx(0.05, rel=0.03)
    t = np.arange(20_000) / 500.0
    frames = np.arange(0, t[-1] + 0.05, 1 / 60)
    held = np.interp(t, frames, rng.normal(0, 0.05, frames.size))
    corr = noise_model(held, 500.0)
    assert corr.lag > 3 and corr.tau > 3
    assert corr.sigma == pytest.approx(np.std(held), rel=0.1)


def test_viscous_damping_is_named_in_the_lag_family_with_its_own_law():
    # rate-proportional torque c·dθ/dt is, on this bench, a torque channel leading by c/K;
    # of the lag family's laws the damper's fits best, and reports c itself
    sim = simulate_fast(seed=53)
    rec = sim.record
    rate = np.gradient(FAST.deflection(rec.time_s), rec.time_s)
    res, _ = _loop_record(_with_extra_torque(sim, lambda t, th: 0.6 * rate))
    assert res.final.effects == ("time_lag",)
    assert res.laws["time_lag"]["law"] == "viscous"
    # a damper is within the time lag's meaning: no physics outside the library
    assert not res.unexplained
    params = res.final.params()
    assert params["viscous_damping_Nms_per_rad"] == pytest.approx(0.6, rel=0.05)
    assert params["equivalent_lag_s"] == pytest.approx(-0.6 / K, rel=0.05)
