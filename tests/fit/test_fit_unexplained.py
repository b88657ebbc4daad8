"""Structure outside the effect library: not patched with library effects, flagged as
unexplained, and localised (in time, in deflection, by period) with its kind of cause."""

import numpy as np
import pytest

from springcad.fit.bench import BenchSpring, simulate
from springcad.fit.evidence import split_parts
from springcad.fit.protocols import Protocol, SineSweep
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from fit_helpers import FAST, K, loop_on_record, simulate_fast, spring, with_extra_torque

T_CHANGE = 0.55     # fraction of the record at which a part changes
STOP_RAD = 0.33     # hard stop angle


def stiffness_change(t, th):
    """A part changing mid-test: the stiffness rises by 6 %."""
    return 0.06 * K * th * (t > T_CHANGE * t[-1])


def hard_stop(t, th):
    return 400.0 * np.sign(th) * np.clip(np.abs(th) - STOP_RAD, 0.0, None)


def ripple(t, th):
    """A ripple periodic in deflection, period 0.07 rad."""
    return 0.15 * np.sin(2 * np.pi * th / 0.07)


def hum(t, th):
    """A sensor artefact periodic in time, 7.3 Hz."""
    return 0.1 * np.sin(2 * np.pi * 7.3 * t)


def zero_jump(t, th):
    return 0.3 * (t > 0.4 * t[-1])


STRUCTURES = {"stiffness_change": stiffness_change, "hard_stop": hard_stop, "ripple": ripple,
              "hum": hum, "zero_jump": zero_jump}


def _kinds(res):
    return [f["kind"] for f in res.localisation["findings"]]


@pytest.mark.parametrize("name", list(STRUCTURES))
def test_structure_alone_names_no_effect_and_is_unexplained(name):
    sim = simulate_fast(seed=61)
    res, _ = loop_on_record(with_extra_torque(sim, STRUCTURES[name]))
    assert res.identified == () and res.confounded == (), res.rejected
    assert res.unexplained
    assert res.localisation["findings"], res.localisation
    # every rejection names the split that failed it
    for r in res.rejected:
        assert r["reason"] and r["audit"]["ok"] is False


@pytest.mark.parametrize("effects, name", [
    (("backlash",), "stiffness_change"), (("hysteresis",), "stiffness_change"),
    (("backlash", "hysteresis"), "ripple"), (("time_lag",), "hum"), (("drift",), "zero_jump"),
    (("stiffening",), "zero_jump"), (("hysteresis",), "hard_stop_soft"),
])
def test_library_effects_beside_a_structure_are_named_exactly(effects, name):
    extra = (STRUCTURES[name] if name != "hard_stop_soft" else
             lambda t, th: 0.1 * hard_stop(t, th))
    sim = simulate(spring(*effects), protocol=FAST, seed=62)
    res, _ = loop_on_record(with_extra_torque(sim, extra))
    assert set(res.identified) == set(effects), (res.identified, res.rejected)
    assert res.unexplained


def test_a_stiffness_change_is_placed_in_time():
    sim = simulate_fast(seed=63)
    res, _ = loop_on_record(with_extra_torque(sim, stiffness_change))
    f = res.localisation["findings"][0]
    assert f["kind"] == "time_step" and f["feature"] == "stiffness"
    t_end = sim.record.time_s[-1]
    assert f["at_s"] == pytest.approx(T_CHANGE * t_end, abs=0.3)
    assert f["change_Nm_per_rad"] == pytest.approx(0.06 * K, rel=0.2)
    assert "part changing during the test" in f["causes"]


def test_a_hard_stop_is_placed_in_deflection_not_in_time():
    # on the staircase the late cycles are also the large ones; the small deflections of
    # late cycles show no change, so the structure is placed at large deflection
    sim = simulate_fast(seed=64)
    res, _ = loop_on_record(with_extra_torque(sim, hard_stop))
    kinds = _kinds(res)
    assert kinds[0] == "large_deflection" and "time_step" not in kinds
    f = res.localisation["findings"][0]
    assert STOP_RAD - 0.03 <= f["beyond_rad"] <= 0.419
    assert "hard stop" in f["causes"]


def test_a_ripple_is_periodic_in_deflection_with_its_period():
    sim = simulate_fast(seed=65)
    res, _ = loop_on_record(with_extra_torque(sim, ripple))
    f = res.localisation["findings"][0]
    assert f["kind"] == "periodic_angle"
    assert f["period_rad"] == pytest.approx(0.07, rel=0.05)
    assert f["amplitude_Nm"] == pytest.approx(0.15, rel=0.3)


def test_a_hum_is_periodic_in_time_with_its_frequency():
    sim = simulate_fast(seed=66)
    res, _ = loop_on_record(with_extra_torque(sim, hum))
    f = res.localisation["findings"][0]
    assert f["kind"] == "periodic_time"
    assert f["frequency_hz"] == pytest.approx(7.3, rel=0.01)
    assert f["amplitude_Nm"] == pytest.approx(0.1, rel=0.2)
    assert "electrical" in f["causes"]


def test_a_zero_jump_is_placed_in_time():
    sim = simulate_fast(seed=67)
    res, _ = loop_on_record(with_extra_torque(sim, zero_jump))
    f = res.localisation["findings"][0]
    assert f["kind"] == "time_step" and f["feature"] == "zero"
    assert f["at_s"] == pytest.approx(0.4 * sim.record.time_s[-1], abs=0.3)
    assert f["change_Nm"] == pytest.approx(0.3, rel=0.15)


def test_clean_records_on_other_protocols_are_explained():
    for protocol in (SineSweep(frequencies_hz=(0.2, 0.6, 1.5)),):
        res, _ = loop_on_record(simulate(spring("backlash"), protocol=protocol, seed=68).record)
        assert res.identified == ("backlash",) and not res.unexplained


def test_splits_of_the_record():
    sim = simulate_fast(seed=69)
    sig = make_signals(sim.record, segment(sim.record))
    idx = np.arange(sig.n)
    parts = split_parts(sig, idx)
    assert set(parts) == {"time", "amplitude", "direction"}
    early, late = parts["time"]
    assert sig.t[early.mask].max() < sig.t[late.mask].min()
    small, large = parts["amplitude"]
    assert np.abs(sig.theta_smooth[small.mask]).max() < np.abs(sig.theta_smooth[large.mask]).max()
    # one amplitude only: no amplitude split (the fade-in and fade-out half cycles are too
    # few samples to make a part)
    sine = simulate(spring(), protocol=SineSweep(frequencies_hz=(0.5, 1.0), cycles=6), seed=1)
    sig = make_signals(sine.record, segment(sine.record))
    assert "amplitude" not in split_parts(sig, np.arange(sig.n))


def settling(t, th):
    """A torque sensor that settles after switch-on: its zero creeps to 0.35 N·m."""
    return 0.35 * (1.0 - np.exp(-(t - t[0]) / (0.2 * (t[-1] - t[0]))))


#: the paper's staircase to 18°: the record on which a settling zero was named an offset
STAIRCASE_18 = Protocol(amplitudes_rad=tuple(np.radians([3, 6, 9, 12, 15, 18])), ramp_s=1.0)


@pytest.mark.parametrize("seed", [1, 6, 7])
def test_a_settling_zero_is_not_named_a_torque_offset(seed):
    # the offset fitted to a settling zero is its mean; the time split alone missed it on
    # these seeds (the early third's own settling widened its interval), so the record's
    # zero is checked for motion the offset does not describe. A drift may be named: it
    # is the settling's trend
    sim = simulate(BenchSpring(35.0), protocol=STAIRCASE_18, seed=seed)
    res, _ = loop_on_record(with_extra_torque(sim, settling))
    assert set(res.identified) <= {"drift"}, res.identified
    assert res.unexplained
    assert _kinds(res)[0].startswith("time_"), _kinds(res)


def test_a_true_offset_beside_friction_is_still_named():
    sim = simulate_fast("torque_offset", "hysteresis", seed=66)
    res, _ = loop_on_record(sim.record)
    assert set(res.identified) == {"torque_offset", "hysteresis"}, res.rejected
    assert not res.unexplained
