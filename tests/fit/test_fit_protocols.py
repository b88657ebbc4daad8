"""Test protocols: the staircase at rates and with holds, sine sweeps, and `springcad simulate`."""

import math

import numpy as np
import pytest

from springcad.cli import main
from springcad.errors import DataError
from springcad.fit.bench import BenchSpring, simulate
from springcad.fit.data import read_bench_csv
from springcad.fit.protocols import PAPER_AMPLITUDES_RAD, Protocol, SineSweep
from springcad.fit.segment import segment


def test_staircase_at_rates_runs_at_constant_speed_once_per_rate():
    p = Protocol(amplitudes_rad=(0.1, 0.3), rates_rad_per_s=(0.2, 0.05), profile="linear",
                 rest_s=0.5)
    t = p.times()
    theta = p.deflection(t)
    # each ramp lasts A/rate: 4 ramps per amplitude, per rate
    expected = 2 * 0.5 + sum(4 * a / r for r in (0.2, 0.05) for a in (0.1, 0.3))
    assert p.duration_s == pytest.approx(expected)
    speed = np.abs(np.gradient(theta, t))
    moving = speed > 1e-9
    # the two staircases: the first at 0.2 rad/s, the second at 0.05 rad/s
    half = t < 0.5 + sum(4 * a / 0.2 for a in (0.1, 0.3))
    assert np.median(speed[moving & half]) == pytest.approx(0.2, rel=1e-6)
    assert np.median(speed[moving & ~half]) == pytest.approx(0.05, rel=1e-6)
    assert theta.max() == pytest.approx(0.3) and theta.min() == pytest.approx(-0.3)


def test_holds_keep_the_peak():
    p = Protocol(amplitudes_rad=(0.2,), rates_rad_per_s=(0.1,), profile="linear", hold_s=1.5)
    t = p.times()
    theta = p.deflection(t)
    at_peak = np.isclose(theta, 0.2, atol=1e-12)
    assert at_peak.sum() / p.sample_rate_hz == pytest.approx(1.5, abs=0.01)
    assert p.duration_s == pytest.approx(1.0 + 4 * 2.0 + 2 * 1.5)


def test_sine_sweep_whole_cycles_at_each_frequency():
    s = SineSweep(amplitudes_rad=(0.3,), frequencies_hz=(0.5, 2.0), cycles=2, rest_s=0.5)
    t = s.times()
    theta = s.deflection(t)
    assert s.duration_s == pytest.approx(1.0 + 2 / 0.5 + 2 / 2.0)
    assert theta.max() == pytest.approx(0.3, rel=1e-3)
    assert abs(theta[-1]) < 1e-9 and abs(theta[0]) < 1e-12
    # faded in and out: at rest where each block starts and ends, no jump in speed
    speed = np.gradient(theta, t)
    for edge in (0.5, 4.5, 5.5):
        assert abs(speed[np.argmin(np.abs(t - edge))]) < 0.01
    assert np.max(np.abs(speed)) == pytest.approx(2 * np.pi * 2.0 * 0.3, rel=0.01)
    block = (t >= 0.5) & (t < 4.5)
    spec = np.abs(np.fft.rfft(theta[block]))
    freq = np.fft.rfftfreq(block.sum(), 1 / s.sample_rate_hz)
    assert freq[np.argmax(spec)] == pytest.approx(0.5, abs=0.01)
    # the segmenter reads a sine sweep: two excursions per cycle
    sim = simulate(BenchSpring(40.0), protocol=s, seed=1)
    assert len(segment(sim.record).excursions) == 2 * 2 * 2


@pytest.mark.parametrize("kwargs", [dict(amplitudes_rad=()), dict(rates_rad_per_s=(0.1, -1.0)),
                                    dict(profile="square"), dict(hold_s=-1.0)])
def test_bad_staircase_is_refused(kwargs):
    with pytest.raises(ValueError):
        Protocol(**kwargs)


def test_sine_sweep_needs_samples_per_cycle():
    with pytest.raises(ValueError, match="20 samples per cycle"):
        SineSweep(frequencies_hz=(50.0,), sample_rate_hz=500.0)


def test_describe_and_cli_args_name_the_protocol():
    p = Protocol(rates_rad_per_s=(math.radians(10), math.radians(3)), profile="linear", hold_s=2)
    d = p.describe()
    assert d["kind"] == "staircase" and d["rates_rad_per_s"] == list(p.rates_rad_per_s)
    assert "--rates-deg-per-s 10,3" in p.cli_args() and "--hold-s 2" in p.cli_args()
    s = SineSweep(frequencies_hz=(0.1, 0.3))
    assert "--protocol sine" in s.cli_args() and "--frequencies-hz 0.1,0.3" in s.cli_args()


def test_simulate_cli_writes_the_protocol_it_is_given(tmp_path):
    out = tmp_path / "rec.csv"
    args = ("--protocol staircase --profile linear --amplitudes-deg 5,10 --rates-deg-per-s 10,2 "
            "--hold-s 1 --sample-rate-hz 200").split()
    assert main(["simulate", "--stiffness", "40", "--out", str(out), *args,
                 "--deflection-noise-rad", "1e-9", "--torque-noise-Nm", "1e-6"]) == 0
    rec = read_bench_csv(out)
    p = Protocol(amplitudes_rad=(math.radians(5), math.radians(10)), profile="linear",
                 rates_rad_per_s=(math.radians(10), math.radians(2)), hold_s=1.0,
                 sample_rate_hz=200.0)
    np.testing.assert_allclose(rec.deflection_rad, p.deflection(rec.time_s), atol=1e-7)
    np.testing.assert_allclose(rec.torque_Nm, 40.0 * p.deflection(rec.time_s), atol=1e-4)


def test_simulate_cli_sine_and_errors(tmp_path, capsys):
    out = tmp_path / "sine.csv"
    assert main(["simulate", "--stiffness", "30", "--out", str(out), "--protocol", "sine",
                 "--frequencies-hz", "0.5,1", "--cycles", "2"]) == 0
    assert read_bench_csv(out).duration_s == pytest.approx(1.0 + 4.0 + 2.0, abs=0.01)
    assert main(["simulate", "--out", str(tmp_path / "x.csv")]) == 2
    assert "give a job CONFIG or --stiffness" in capsys.readouterr().err
    assert main(["simulate", "--stiffness", "30", "--out", str(tmp_path / "y.csv"),
                 "--protocol", "sine", "--frequencies-hz", "100"]) == 2
    assert "20 samples per cycle" in capsys.readouterr().err


def test_paper_amplitudes_are_the_default():
    assert Protocol().amplitudes_rad == PAPER_AMPLITUDES_RAD
    with pytest.raises(DataError):
        from argparse import Namespace

        from springcad.cli.simulate import protocol_from_args
        protocol_from_args(Namespace(protocol="staircase", amplitudes_deg=(-4.0,), ramp_s=1.0,
                                     rates_deg_per_s=None, profile="cosine", hold_s=0.0,
                                     sample_rate_hz=500.0, rest_s=0.5, frequencies_hz=(1.0,),
                                     cycles=1))
