"""Issue 24, held-out generator D's misses: a crossover off zero, shapes invented beside
structure in deflection the library cannot describe (motor cogging), and effects invented
for a stiffness that changed mid-test.

Records written here with the physics of ``issue24_records`` (not ``springcad.fit.bench``),
each with its truth. Units: N·m, rad, s.
"""

import math

import numpy as np
import pytest

from fit_helpers import loop_on_record
from issue24_records import deadband, ramps
from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.patches import profile_patches, stiffness_patches
from springcad.fit.search import LoopSettings, Search, State
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

K = 60.0
AMPS_DEG = (6.0, 12.0, 18.0)
#: ramps at two speeds for the cogging records
COG_AMPS_DEG, COG_RATES_DEG_S = (15.0, 22.0), (3.0, 11.0)


def _record(t, th, torque, seed, noise_frac=0.003, theta_noise=5e-5):
    """A record of ``torque`` (N·m) against ``th`` (rad) with torque noise of ``noise_frac``
    of the largest torque and deflection noise ``theta_noise`` (rad)."""
    rng = np.random.default_rng(seed)
    sigma = noise_frac * float(np.max(np.abs(torque)))
    return make_record(t, torque + rng.normal(0.0, sigma, t.size),
                       th + rng.normal(0.0, theta_noise, t.size)), sigma


def _cogging(th, size_Nm, per_turn):
    """Torque periodic in the angle (a motor's cogging), ``per_turn`` periods per turn."""
    return size_Nm * np.sin(per_turn * th + 0.4)


def test_a_crossover_off_zero_is_named_with_its_angle_offset():
    # a dead band of 2h centred at θ0 = 1.5 h does not hold zero: the crossover alone at
    # zero describes little of it and a torque offset more, and the angle offset is a
    # candidate only beside a crossover; the two are tried together (generator D L08:
    # read as a torque offset, K 2.7-5.9 % off, flagged unexplained)
    t, th = ramps(AMPS_DEG, (8.0,), hold_s=0.5)
    half, off = 0.01, 0.015
    rec, _ = _record(t, th, K * deadband(th - off, half), seed=5)
    res, _ = loop_on_record(rec)
    assert set(res.final.effects) == {"backlash", "angle_offset"}
    assert not res.unexplained
    p = res.final.params()
    assert abs(p["stiffness_Nm_per_rad"] / K - 1) < 0.01
    assert abs(p["angle_offset_rad"] / off - 1) < 0.05
    assert abs(p["backlash_rad"] / (2 * half) - 1) < 0.05


def _crossover_off_zero_round():
    """A crossover of 27 mrad centred at 26 mrad on one ramp rate, fitted linear, ready for
    the first round: (loop, state, score, f_scale)."""
    t, th = ramps(AMPS_DEG, (8.0,), hold_s=0.5)
    rec, _ = _record(t, th, K * deadband(th - 0.026, 0.0135), seed=2, theta_noise=1e-4)
    sig, lp, model, x = _fitted(rec)
    state = State(model, model.fit(sig, lp.all, x, 1e9))
    f_scale = lp.f_scale(state)
    lp.update_noise(state)
    score, _ = lp.cv_score(state.model, state.x, None, f_scale)
    return lp, state, score, f_scale


def test_the_first_round_proposes_the_crossover_with_its_offset_together():
    # known truth: crossover of 27 mrad centred at 26 mrad; the pair describes the record
    # to its noise and beats a torque offset (which describes the line's shift only)
    lp, state, score, f_scale = _crossover_off_zero_round()
    _, proposals = lp.round(state, score, f_scale)
    best = proposals[0][2]
    assert set(best.effects) == {"backlash", "angle_offset"}
    offset = {p[1].name: p[0] for p in proposals}.get("torque_offset", -math.inf)
    assert proposals[0][0] > offset + lp.s.gain_threshold
    p = best.model.report(best.x)
    assert abs(p["angle_offset_rad"] / 0.026 - 1) < 0.05


def test_motor_cogging_is_flagged_and_no_shape_is_named_for_it():
    # torque periodic in the angle (4 noise levels, 50 per turn): a crossover, a cubic or
    # an asymmetry fitted beside it takes up the part that looks like its shape and passes
    # the audit (generator D X15: backlash, stiffening or asymmetric_stiffness invented)
    t, th = ramps(COG_AMPS_DEG, COG_RATES_DEG_S)
    clean = K * th
    sigma = 0.003 * float(np.max(np.abs(clean)))
    rec, _ = _record(t, th, clean + _cogging(th, 4.0 * sigma, 50.0), seed=7)
    res, _ = loop_on_record(rec)
    assert res.final.effects == ()
    assert res.unexplained
    assert abs(res.final.params()["stiffness_Nm_per_rad"] / K - 1) < 0.01


def test_a_cubic_beside_cogging_is_named_and_nothing_else():
    # the same cogging beside a 20 % cubic: the cubic describes tens of times what the
    # cogging leaves in the deflection profile and is named; nothing is invented beside it
    t, th = ramps(COG_AMPS_DEG, COG_RATES_DEG_S)
    a = math.radians(COG_AMPS_DEG[-1])
    clean = K * th + 0.2 * K / a ** 2 * th ** 3
    sigma = 0.003 * float(np.max(np.abs(clean)))
    rec, _ = _record(t, th, clean + _cogging(th, 4.0 * sigma, 50.0), seed=8)
    res, _ = loop_on_record(rec)
    assert res.final.effects == ("stiffening",)
    assert res.unexplained
    assert abs(res.final.params()["stiffness_Nm_per_rad"] / K - 1) < 0.02


def _k_step_staircase(seed, step=0.94):
    """A staircase of rising amplitudes whose stiffness drops to ``step`` of K half-way."""
    t, th = ramps((5.0, 10.0, 15.0, 20.0), (8.0,), hold_s=0.5)
    k = np.where(t >= 0.5 * t[-1], step * K, K)
    return _record(t, th, k * th, seed=seed)[0]


def test_a_stiffness_step_mid_test_names_no_effect():
    # late cycles are the large ones: a stiffness that drops half-way reads as a softening
    # cubic, and a change inside a cycle as friction (generator D X16, every seed); the
    # record is too short for the audit's time split
    res, _ = loop_on_record(_k_step_staircase(seed=3))
    assert res.final.effects == ()
    assert res.unexplained


def _fitted(rec, *names):
    """The record's signals, its search and ``names`` fitted by least squares."""
    sig = make_signals(rec, segment(rec))
    lp = Search(sig, LoopSettings())
    model = TorqueModel((), sig.scales)
    x = np.array([K])
    for name in names:  # each from its best start, as the loop does
        effect = get_effect(name)
        m2 = model.with_effect(effect)
        starts = [m2.solve_stiffness(m2.transfer(model, x, {name: s}), sig, lp.cv)
                  for s in effect.starts(m2.scales)]
        model, x = m2, min(starts, key=lambda xs: float(np.sum(m2.residual(xs, sig, lp.cv) ** 2)))
    return sig, lp, model, model.fit(sig, lp.cv, x, 1e9, max_nfev=200)


def test_a_cubic_fitted_over_a_stiffness_step_loses_its_size_with_the_stiffness_free():
    sig, lp, model, x = _fitted(_k_step_staircase(seed=4), "stiffening")
    assert abs(x[model.slice_of("stiffening")][0]) > 0.01  # the step reads as a cubic
    found = stiffness_patches(model, x, sig, lp.cv, lp.cv_rate_hz)
    assert set(found) == {"stiffening"}
    assert found["stiffening"][0] < 0.5


def test_a_true_cubic_keeps_its_size_with_the_stiffness_free():
    # the same staircase and step with a 15 % cubic: freed per cycle, the stiffness absorbs
    # the step and the cubic keeps its size (known truth: alpha = 0.15 · (θ_ref/a)²)
    t, th = ramps((5.0, 10.0, 15.0, 20.0), (8.0,), hold_s=0.5)
    a = math.radians(20.0)
    k = np.where(t >= 0.5 * t[-1], 0.94 * K, K)
    rec = _record(t, th, k * th * (1 + 0.15 * (th / a) ** 2), seed=6)[0]
    sig, lp, model, x = _fitted(rec, "stiffening")
    assert stiffness_patches(model, x, sig, lp.cv, lp.cv_rate_hz) == {}


def test_the_profile_rule_leaves_a_record_the_model_explains_alone():
    # a true crossover on a record with no other structure: the residual's profile is
    # noise, nothing is judged (the rule only speaks beside structure)
    t, th = ramps(AMPS_DEG, (8.0,))
    rec = _record(t, th, K * deadband(th, 0.01), seed=9)[0]
    sig, lp, model, x = _fitted(rec, "backlash")
    assert profile_patches(model, x, sig, lp.cv) == {}


def test_a_crossover_fitted_over_cogging_is_a_patch_and_a_true_one_beside_it_is_not():
    t, th = ramps((8.0, 16.0), (6.0, 20.0))
    sigma = 0.003 * K * math.radians(16.0)
    cog = _cogging(th, 4.0 * sigma, 40.0)
    sig, lp, model, x = _fitted(_record(t, th, K * th + cog, seed=10)[0], "backlash")
    assert "backlash" in profile_patches(model, x, sig, lp.cv)
    sig, lp, model, x = _fitted(_record(t, th, K * deadband(th, 0.015) + cog, seed=10)[0],
                                "backlash")
    assert profile_patches(model, x, sig, lp.cv) == {}


def test_a_standard_error_of_round_off_is_no_support():
    # a filter time constant resting on its bound has a standard error of round-off
    # (7.7e-15 s against 5.3e-5 s on generator C O11 seed 3), which read as z = 7e9
    # and kept a 0.05 ms "filter"; zero and round-off alike carry no information
    from springcad.fit.evidence import _support_z

    assert _support_z(((5.25e-5, 7.7e-15),), 0.0) == 0.0
    assert _support_z(((5.25e-5, 0.0),), 0.0) == 0.0
    assert _support_z(((5.25e-5, 1e-5),), 0.0) == pytest.approx(5.25)


def test_a_crossover_off_zero_is_not_proposed_where_a_torque_offset_was_rejected():
    # an angle offset beside a vanishing or smeared crossover reads as a torque offset:
    # where the audit rejected the torque offset (the zero moves), the pair would bring
    # it back in disguise (generator C O11: a settling zero read as a 0.08 rad crossover
    # off zero)
    lp, state, score, f_scale = _crossover_off_zero_round()
    _, proposals = lp.round(state, score, f_scale, excluded=frozenset({"torque_offset"}))
    assert all("angle_offset" not in p[2].effects for p in proposals)
