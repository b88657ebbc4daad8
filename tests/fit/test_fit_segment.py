"""Segmentation into half-cycles and cycles, folds, and energy loss per cycle."""

import numpy as np
import pytest

from springcad.errors import DataError
from springcad.fit.bench import BenchNoise, BenchSpring, simulate
from springcad.fit.data import make_record
from springcad.fit.segment import cycle_energies, energy_loss_pct, noise_std, segment
from fit_helpers import FAST, K


def test_paper_protocol_gives_twelve_cycles_at_the_commanded_amplitudes():
    sim = simulate(BenchSpring(K, backlash_rad=0.03), protocol=FAST, seed=1)
    seg = segment(sim.record)
    assert len(seg.excursions) == 12
    assert len(seg.half_cycles) == 24
    expected = np.repeat(FAST.amplitudes_rad, 2)
    np.testing.assert_allclose(seg.amplitudes_rad, expected, rtol=0.01)
    assert [e.sign for e in seg.excursions] == [1, -1] * 6
    kinds = [h.kind for h in seg.half_cycles]
    assert kinds == ["loading", "unloading"] * 12
    for h in seg.half_cycles:  # |θ| grows while loading and shrinks while unloading
        th = np.abs(seg.theta_smooth_rad[h.start:h.stop])
        grows = th[-1] > th[0]
        assert grows == (h.kind == "loading")


def test_folds_hold_both_signs_and_both_small_and_large_cycles():
    sim = simulate(BenchSpring(K), protocol=FAST, seed=2)
    seg = segment(sim.record)
    for f in (0, 1):
        mine = [e for e in seg.excursions if seg.fold[e.start] == f]
        assert {e.sign for e in mine} == {1, -1}
        amps = [e.amplitude_rad for e in mine]
        assert min(amps) < 0.15 and max(amps) > 0.35
    assert set(np.unique(seg.fold)) == {0, 1}


def test_one_sided_ramps_are_cycles_too():
    t = np.arange(0, 12, 0.002)
    theta = 0.2 * np.abs(np.sin(np.pi * t / 2))  # 0 -> 0.2 -> 0, six times
    rng = np.random.default_rng(0)
    rec = make_record(t, K * theta + rng.normal(0, 0.02, t.size), theta)
    seg = segment(rec)
    assert len(seg.excursions) == 6
    assert all(e.sign == 1 for e in seg.excursions)


def test_too_few_cycles():
    t = np.arange(0, 2, 0.002)
    theta = 0.2 * np.sin(np.pi * t / 2)  # a single excursion 0 -> 0.2 -> 0
    rec = make_record(t, K * theta + 0.01 * np.cos(t), theta)
    with pytest.raises(DataError, match=r"too few cycles: found 1 complete loading-unloading "
                                        r"cycle\(s\).*need at least 2"):
        segment(rec)


def test_noise_std_of_white_noise_with_slow_signal_and_spikes():
    rng = np.random.default_rng(4)
    x = np.sin(np.linspace(0, 20, 50_000)) + rng.normal(0, 0.1, 50_000)
    x[::500] += 5.0
    assert noise_std(x) == pytest.approx(0.1, rel=0.03)


def test_energy_loss_matches_coulomb_friction_loop_area():
    # friction H adds H·A on loading and removes it on unloading: loss = 2HA / (K A²/2 + H A)
    friction = 0.2
    sim = simulate(BenchSpring(K, friction_torque_Nm=friction, presliding_rad=1e-4),
                   protocol=FAST, noise=BenchNoise(torque_Nm=0.01, deflection_rad=2e-4), seed=5)
    seg = segment(sim.record)
    a = max(FAST.amplitudes_rad)
    expected = 100 * 2 * friction * a / (0.5 * K * a * a + friction * a)
    assert energy_loss_pct(cycle_energies(sim.record, seg)) == pytest.approx(expected, rel=0.03)


def test_backlash_alone_loses_no_energy():
    sim = simulate(BenchSpring(K, backlash_rad=0.05), protocol=FAST, seed=6)
    cycles = cycle_energies(sim.record, segment(sim.record))
    assert abs(energy_loss_pct(cycles)) < 0.3
    big = max(c.amplitude_rad for c in cycles)
    stored = [c.stored_J for c in cycles if c.amplitude_rad > 0.9 * big]
    h = 0.025
    assert np.mean(stored) == pytest.approx(0.5 * K * (big - h) ** 2, rel=0.02)


def test_energy_loss_comes_from_the_hysteresis_model_not_the_measured_loop():
    # a lagging torque channel and a drifting zero distort the measured loop area; the
    # reported loss is the friction term's loop area, the spring's own loss
    from springcad.fit.analysis import fit_record

    plain = simulate(BenchSpring(K, friction_torque_Nm=0.15), protocol=FAST, seed=8)
    skewed = simulate(BenchSpring(K, friction_torque_Nm=0.15, lag_s=0.015, drift_Nm_per_s=0.01),
                      protocol=FAST, seed=8)
    truth = energy_loss_pct(cycle_energies(plain.record, segment(plain.record)))
    apparent = energy_loss_pct(cycle_energies(skewed.record, segment(skewed.record)))
    assert abs(apparent - truth) > 1.0
    res = fit_record(skewed.record)
    assert res.energy_loss_pct == pytest.approx(truth, rel=0.05)
    assert res.energy.ci_low <= res.energy_loss_pct <= res.energy.ci_high


def test_a_lag_alone_loses_no_energy():
    # the measured loop of a late torque channel runs backwards (negative apparent loss);
    # with no friction in the model the reported loss is zero, never negative
    from springcad.fit.analysis import fit_record

    sim = simulate(BenchSpring(K, lag_s=0.02), protocol=FAST, seed=9)
    assert energy_loss_pct(cycle_energies(sim.record, segment(sim.record))) < -0.5
    res = fit_record(sim.record)
    assert res.loop.identified == ("time_lag",)
    assert res.energy_loss_pct == 0.0
