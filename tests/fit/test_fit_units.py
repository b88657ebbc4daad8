"""Unit mistakes the data contradicts are refused, naming the option, the factor and the fix;
right units and genuine stiffness misses are not; ``--trust-units`` keeps them with a warning."""

import json
import math

import numpy as np
import pytest

from springcad.cli import main
from springcad.fit.analysis import UNIT_FACTORS, unit_factor_problem
from springcad.fit.bench import BenchSpring, Protocol, simulate

#: about 4500 samples: a quick fit
SHORT = Protocol(amplitudes_rad=(0.1, 0.2, 0.3, 0.4), ramp_s=0.5)
#: 1.7° and 4°: in degrees the numbers stay below 2π, so read as rad only the target tells
SMALL = Protocol(amplitudes_rad=(0.03, 0.07), ramp_s=0.8)


def _csv(path, rec, torque_scale=1.0, angle_scale=1.0, header="time_s,torque,angle"):
    data = np.column_stack([rec.time_s, torque_scale * rec.torque_Nm,
                            angle_scale * rec.deflection_rad])
    np.savetxt(path, data, delimiter=",", header=header, comments="", fmt="%.9g")
    return path


def _fit(tmp_path, path, *args):
    out = tmp_path / "out"
    rc = main(["fit", str(path), "--out", str(out), "--no-plots", "--deflection-col", "angle",
               "--torque-col", "torque", *args])
    return rc, out


@pytest.mark.parametrize("factor, words, fix", [
    (180 / math.pi, "57.3", "drop --angle-unit deg"),
    (math.pi / 180, "1/57.3", "pass --angle-unit deg"),
    (1000.0, "1000", "pass --torque-unit Nmm"),
    (1e-3, "1/1000", "drop --torque-unit Nmm")])
def test_each_unit_factor_is_named_with_its_fix(factor, words, fix):
    for off in (0.8, 1.0, 1.3):  # a spring a little off its target, then misread
        msg = unit_factor_problem(40.0 * factor * off, 40.0)
        assert msg is not None and words in msg and fix in msg
    # a genuine miss of its target, even by 2 or 3 times, is no unit mistake
    for miss in (0.33, 0.5, 2.0, 3.0):
        assert unit_factor_problem(40.0 * miss, 40.0) is None
    assert {f for f, *_ in UNIT_FACTORS} >= {1000.0, 1e-3}


def test_newton_metres_read_as_newton_millimetres_are_refused_by_the_target(tmp_path, capsys):
    # K = 60 read as N·mm is 0.06 N·m/rad: soft, but not impossible on magnitudes alone
    rec = simulate(BenchSpring(60.0), protocol=SHORT, seed=31).record
    path = _csv(tmp_path / "nm.csv", rec)
    rc, out = _fit(tmp_path, path, "--torque-unit", "Nmm", "--target-stiffness", "55")
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    assert "unit factor of 1/1000" in err and "drop --torque-unit Nmm" in err
    assert "--trust-units" in err and "Traceback" not in err
    assert len([line for line in err.splitlines() if "error" in line]) == 1


def test_degrees_read_as_radians_are_refused_by_the_target(tmp_path, capsys):
    rec = simulate(BenchSpring(40.0), protocol=SMALL, seed=32).record
    path = _csv(tmp_path / "deg.csv", rec, angle_scale=180 / math.pi)
    rc, out = _fit(tmp_path, path, "--target-stiffness", "40")
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    assert "unit factor of 1/57.3" in err and "pass --angle-unit deg" in err


def test_right_units_and_a_genuine_miss_are_accepted(tmp_path, capsys):
    # the same records read in their own units fit; a spring twice as stiff as its target
    # is a design or build miss, reported as a stiffness error, not refused
    rec = simulate(BenchSpring(60.0), protocol=SHORT, seed=31).record
    path = _csv(tmp_path / "nmm.csv", rec, torque_scale=1000.0)
    rc, out = _fit(tmp_path, path, "--torque-unit", "Nmm", "--target-stiffness", "55")
    assert rc == 0 and (out / "fit.json").is_file()
    rec = simulate(BenchSpring(40.0), protocol=SMALL, seed=32).record
    path = _csv(tmp_path / "deg.csv", rec, angle_scale=180 / math.pi)
    rc, out = _fit(tmp_path / "b", path, "--angle-unit", "deg", "--target-stiffness", "40")
    assert rc == 0
    rc, out = _fit(tmp_path / "c", _csv(tmp_path / "stiff.csv", simulate(
        BenchSpring(80.0), protocol=SHORT, seed=33).record), "--target-stiffness", "40")
    assert rc == 0
    d = json.loads((out / "fit.json").read_text())
    assert d["stiffness_error_pct"]["final"] == pytest.approx(100.0, abs=2.0)
    assert "unit" not in capsys.readouterr().err


def test_trust_units_keeps_the_units_with_a_warning(tmp_path, capsys):
    rec = simulate(BenchSpring(60.0), protocol=SHORT, seed=31).record
    path = _csv(tmp_path / "nm.csv", rec)
    rc, out = _fit(tmp_path, path, "--torque-unit", "Nmm", "--target-stiffness", "55",
                   "--trust-units")
    assert rc == 0
    err = capsys.readouterr().err
    assert "warning" in err and "unit factor of 1/1000" in err and "(kept: --trust-units)" in err
    d = json.loads((out / "fit.json").read_text())
    assert any("unit factor" in w for w in d["warnings"])
    assert d["final"]["intervals"]["stiffness_Nm_per_rad"]["value"] == pytest.approx(0.06, rel=0.01)


def test_newton_metres_read_as_newton_millimetres_warn_without_a_target(tmp_path, capsys):
    # with no target the data cannot refuse a soft spring, but it asks
    rec = simulate(BenchSpring(60.0), protocol=SHORT, seed=31).record
    rc, _ = _fit(tmp_path, _csv(tmp_path / "nm.csv", rec), "--torque-unit", "Nmm")
    assert rc == 0
    assert "is the column in N·m? If so, drop --torque-unit Nmm" in capsys.readouterr().err


def test_angles_below_a_degree_read_as_degrees_are_kept_with_trust_units(tmp_path, capsys):
    rec = simulate(BenchSpring(40.0), protocol=SHORT, seed=34).record
    path = _csv(tmp_path / "rad.csv", rec)
    rc, out = _fit(tmp_path, path, "--angle-unit", "deg")
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists() and "drop --angle-unit deg" in err
    rc, out = _fit(tmp_path, path, "--angle-unit", "deg", "--trust-units")
    assert rc == 0 and "(kept: --trust-units)" in capsys.readouterr().err
