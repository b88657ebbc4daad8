"""Bench CSV ingest: round trip, options, and a clear error for each bad input."""

import numpy as np
import pytest

from springcad.errors import DataError
from springcad.fit.data import ColumnMap, make_record, read_bench_csv, to_csv_text
from fit_helpers import simulate_fast


@pytest.fixture(scope="module")
def sim():
    return simulate_fast("backlash", seed=3)


def _csv(tmp_path, text, name="bench.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _good_lines(sim, n=None):
    rec = sim.record
    n = n or rec.n_samples
    return [f"{t:.6f},{q:.6f},{d:.8f}" for t, q, d in
            zip(rec.time_s[:n], rec.torque_Nm[:n], rec.deflection_rad[:n])]


def test_round_trip_preserves_channels(sim, tmp_path):
    path = _csv(tmp_path, to_csv_text(sim.record))
    rec = read_bench_csv(path)
    assert rec.n_samples == sim.record.n_samples
    np.testing.assert_allclose(rec.torque_Nm, sim.record.torque_Nm, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(rec.deflection_rad, sim.record.deflection_rad, rtol=1e-8, atol=1e-12)
    assert rec.sample_rate_hz == pytest.approx(500.0)
    assert rec.warnings == ()


def test_header_with_spaces_comments_and_blank_lines(sim, tmp_path):
    lines = ["# bench run 3, 4xS1", "", "time_s, torque_Nm, deflection_rad"] + _good_lines(sim, 500)
    rec = read_bench_csv(_csv(tmp_path, "\n".join(lines)))
    assert rec.n_samples == 500


@pytest.mark.parametrize("sep,decimal", [(";", ","), (";", "."), ("\t", ".")])
def test_semicolon_and_tab_separated_files_read_as_the_comma_file(sim, tmp_path, sep, decimal):
    """A spreadsheet in a locale with a decimal comma writes ``time_s;torque_Nm;...`` and
    ``0,002;1,25;...``; a tab-separated export is the other common form. Both give the
    same record as the comma file (the header was read as one column name before)."""
    lines = [ln.replace(",", sep).replace(".", decimal) for ln in _good_lines(sim, 400)]
    path = _csv(tmp_path, "\n".join(["# exported", sep.join(["time_s", "torque_Nm",
                                                            "deflection_rad"])] + lines))
    rec = read_bench_csv(path)
    ref = read_bench_csv(_csv(tmp_path, "\n".join(["time_s,torque_Nm,deflection_rad"]
                                                  + _good_lines(sim, 400)), "ref.csv"))
    np.testing.assert_array_equal(rec.time_s, ref.time_s)
    np.testing.assert_array_equal(rec.torque_Nm, ref.torque_Nm)
    np.testing.assert_array_equal(rec.deflection_rad, ref.deflection_rad)


def test_other_names_degrees_and_newton_millimetres(sim, tmp_path):
    rec0 = sim.record
    lines = ["t,tau_Nmm,angle_deg,motor_in_deg,motor_out_deg"]
    for t, q, d in zip(rec0.time_s, rec0.torque_Nm, rec0.deflection_rad):
        lines.append(f"{t:.6f},{q * 1000:.6f},{np.degrees(d):.8f},{np.degrees(d) + 1:.8f},0.5")
    cols = ColumnMap("t", "tau_Nmm", "angle_deg", ("motor_in_deg", "motor_out_deg"))
    rec = read_bench_csv(_csv(tmp_path, "\n".join(lines)), cols, angle_unit="deg", torque_unit="Nmm")
    np.testing.assert_allclose(rec.torque_Nm, rec0.torque_Nm, atol=2e-9)
    np.testing.assert_allclose(rec.deflection_rad, rec0.deflection_rad, atol=1e-9)
    # encoder deflection = input - output = deflection + 0.5 deg
    np.testing.assert_allclose(rec.encoder_deflection_rad - rec.deflection_rad,
                               np.radians(0.5), atol=1e-9)
    assert rec.warnings == ()


def test_encoder_columns_found_by_default_name(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad,encoder_in_rad,encoder_out_rad"]
    lines += [f"{ln},0.25,0.05" for ln in _good_lines(sim, 400)]
    rec = read_bench_csv(_csv(tmp_path, "\n".join(lines)))
    np.testing.assert_allclose(rec.encoder_deflection_rad, 0.2)


def test_missing_file(tmp_path):
    with pytest.raises(DataError, match="does not exist"):
        read_bench_csv(tmp_path / "nope.csv")


def test_missing_column_names_it_and_the_option(sim, tmp_path):
    lines = ["time_s,torque,deflection_rad"] + _good_lines(sim, 300)
    with pytest.raises(DataError, match=r"missing column\(s\) 'torque_Nm'.*--torque-col.*"
                                        r"header has: time_s, torque, deflection_rad"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_missing_encoder_column(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    with pytest.raises(DataError, match="'enc_a' \\(encoder"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)), ColumnMap(encoder=("enc_a",)))


def test_non_numeric_value_names_line_and_column(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    t, _, d = lines[17].split(",")
    lines[17] = f"{t},abc,{d}"
    with pytest.raises(DataError, match=r"column 'torque_Nm', line 18: 'abc' is not a number"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_empty_cell(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    t, q, _ = lines[5].split(",")
    lines[5] = f"{t},{q},"
    with pytest.raises(DataError, match="column 'deflection_rad', line 6: an empty cell"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf"])
def test_non_finite_values(sim, tmp_path, bad):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    t, _, d = lines[40].split(",")
    lines[40] = f"{t},{bad},{d}"
    with pytest.raises(DataError, match=r"'torque_Nm' has 1 non-finite value\(s\) \(NaN or inf\), "
                                        r"first at line 41"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


@pytest.mark.parametrize("t_bad", ["0.0", "0.03"])
def test_time_not_increasing(sim, tmp_path, t_bad):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    _, q, d = lines[21].split(",")
    lines[21] = f"{t_bad},{q},{d}"  # line 22 goes back in time (t was 0.040)
    with pytest.raises(DataError, match="must increase strictly, but line 22 has t = "):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_repeated_time_is_not_increasing(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    lines[11] = lines[10]
    with pytest.raises(DataError, match="line 12 has t = 0.018 after t = 0.018 on line 11"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_too_few_samples(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 50)
    with pytest.raises(DataError, match="too few samples: 50; need at least 200"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_torque_that_never_changes(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"]
    lines += [f"{ln.split(',')[0]},0.0,{ln.split(',')[2]}" for ln in _good_lines(sim, 400)]
    with pytest.raises(DataError, match="torque channel 'torque_Nm' never changes \\(constant 0\\)"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_deflection_that_never_changes(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"]
    lines += [f"{ln.rsplit(',', 1)[0]},0.1" for ln in _good_lines(sim, 400)]
    with pytest.raises(DataError, match="deflection channel 'deflection_rad' never changes"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


def test_ragged_row(sim, tmp_path):
    lines = ["time_s,torque_Nm,deflection_rad"] + _good_lines(sim, 300)
    lines[9] = lines[9] + ",7"
    with pytest.raises(DataError, match="line 10 has 4 field\\(s\\) but the header has 3"):
        read_bench_csv(_csv(tmp_path, "\n".join(lines)))


@pytest.mark.parametrize("text, msg", [("", "no header line"), ("# only a comment\n", "no header line"),
                                       ("time_s,torque_Nm,deflection_rad\n", "no data rows")])
def test_empty_files(tmp_path, text, msg):
    with pytest.raises(DataError, match=msg):
        read_bench_csv(_csv(tmp_path, text))


def test_duplicate_header(tmp_path):
    with pytest.raises(DataError, match="duplicate column name\\(s\\) in header: torque_Nm"):
        read_bench_csv(_csv(tmp_path, "time_s,torque_Nm,torque_Nm\n0,1,2\n"))


def test_degrees_read_as_radians_beyond_a_turn_are_refused(sim):
    rec = sim.record
    with pytest.raises(DataError, match="more than a full turn.*--angle-unit deg"):
        make_record(rec.time_s, rec.torque_Nm, np.degrees(rec.deflection_rad))


def test_degrees_read_as_radians_within_a_turn_warn(sim):
    rec = sim.record
    out = make_record(rec.time_s, rec.torque_Nm, np.degrees(rec.deflection_rad) / 5)
    assert any("--angle-unit deg" in w for w in out.warnings)


@pytest.mark.parametrize("header, angle_unit, torque_unit, message", [
    ("time_s,torque_Nm,deflection_rad", "deg", "Nm", "'deflection_rad' is named in rad"),
    ("time_s,torque_Nm,deflection_deg", "rad", "Nm", "'deflection_deg' is named in deg"),
    ("time_s,torque_Nmm,deflection_rad", "rad", "Nm", "'torque_Nmm' is named in Nmm"),
    ("time_s,torque_Nm,deflection_rad", "rad", "Nmm", "'torque_Nm' is named in Nm"),
])
def test_column_names_contradicting_the_units_are_refused(sim, tmp_path, header, angle_unit,
                                                          torque_unit, message):
    cols = ColumnMap(*header.split(","))
    path = _csv(tmp_path, "\n".join([header] + _good_lines(sim, 400)))
    with pytest.raises(DataError, match=message):
        read_bench_csv(path, cols, angle_unit=angle_unit, torque_unit=torque_unit)


def test_newton_millimetres_read_as_newton_metres_warns(sim):
    rec = sim.record
    out = make_record(rec.time_s, rec.torque_Nm * 1000, rec.deflection_rad)
    assert any("--torque-unit Nmm" in w for w in out.warnings)


def test_milliseconds_read_as_seconds_warns(sim):
    rec = sim.record
    out = make_record(rec.time_s * 1000, rec.torque_Nm, rec.deflection_rad)
    assert any("in seconds" in w for w in out.warnings)


def test_plausible_record_has_no_warnings(sim):
    assert sim.record.warnings == ()
