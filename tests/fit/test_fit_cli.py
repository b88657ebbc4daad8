"""``springcad fit`` in process: outputs, fit.json schema, options, and errors (exit 2)."""

import hashlib
import json
import sys
import types

import numpy as np
import pytest

from springcad.cli import main
from springcad.fit.bench import BenchSpring, Protocol, simulate
from springcad.fit.data import to_csv_text
from springcad.fit.effects import EFFECT_NAMES
from fit_helpers import FAST, spring
from test_fit_compare import DESIGN


@pytest.fixture(scope="module")
def bench_csv(tmp_path_factory):
    sim = simulate(spring("backlash", "hysteresis"), protocol=FAST, seed=8)
    path = tmp_path_factory.mktemp("data") / "bench.csv"
    path.write_text(to_csv_text(sim.record))
    return path


@pytest.fixture(scope="module")
def fitted(bench_csv, tmp_path_factory):
    out = tmp_path_factory.mktemp("runs") / "fit1"
    before = (hashlib.sha256(bench_csv.read_bytes()).hexdigest(), bench_csv.stat().st_mtime_ns)
    rc = main(["fit", str(bench_csv), "--out", str(out), "--target-stiffness", "37.5"])
    after = (hashlib.sha256(bench_csv.read_bytes()).hexdigest(), bench_csv.stat().st_mtime_ns)
    return rc, out, before, after


def test_cli_writes_json_report_and_plots(fitted):
    rc, out, _, _ = fitted
    assert rc == 0
    names = {p.name for p in out.iterdir()}
    assert {"fit.json", "report.md", "torque_deflection.png", "crossover.png",
            "residual_step_1_backlash.png", "residual_step_2_hysteresis.png"} <= names
    for png in out.glob("*.png"):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    report = (out / "report.md").read_text()
    assert "## Paper models" in report and "![crossover region](crossover.png)" in report


def test_input_file_is_not_modified(fitted):
    _, _, before, after = fitted
    assert before == after


def test_fit_json_schema(fitted):
    rc, out, _, _ = fitted
    d = json.loads((out / "fit.json").read_text())
    assert d["baseline"]["model"] == "linear"
    assert set(d["baseline"]) >= {"model", "params", "nrmse_pct"}
    assert [s["effect"] for s in d["steps"]] == ["backlash", "hysteresis"]
    for s in d["steps"]:
        assert set(s) >= {"effect", "evidence", "params", "nrmse_before_pct", "nrmse_after_pct"}
        assert s["effect"] in EFFECT_NAMES
        assert s["nrmse_after_pct"] < s["nrmse_before_pct"]
    assert d["steps"][0]["params"]["backlash_rad"] == pytest.approx(0.04, rel=0.05)
    final = d["final"]
    assert set(final) >= {"model", "params", "nrmse_pct", "unexplained"}
    assert final["unexplained"] is False
    # the final stiffness carries the regression-dilution correction (a few 1e-5 relative)
    assert final["nrmse_pct"] == pytest.approx(d["steps"][-1]["nrmse_after_pct"], rel=1e-3)
    for name in ("linear", "deadband", "logit"):
        m = d["paper_models"][name]
        assert set(m) >= {"stiffness_Nm_per_rad", "backlash_rad", "nrmse_pct"}
        assert m["stiffness_error_pct"] == pytest.approx(
            100 * (m["stiffness_Nm_per_rad"] - 37.5) / 37.5)
    assert d["paper_models"]["deadband"]["nrmse_pct"] < d["paper_models"]["linear"]["nrmse_pct"]
    # NRMSE in percent of half the torque range: the linear misfit here is a few percent
    assert 1.0 < d["paper_models"]["linear"]["nrmse_pct"] < 20.0
    assert 0.5 < d["energy_loss_pct"] < 5.0
    assert d["schema"] == "springcad.fit/2"
    assert d["energy_loss"]["source"] == "hysteresis model"
    assert d["energy_loss"]["ci_low_pct"] <= d["energy_loss_pct"] <= d["energy_loss"]["ci_high_pct"]
    # every parameter with its interval, every effect with its evidence across splits
    assert set(final["intervals"]) == set(final["params"])
    for ci in final["intervals"].values():
        assert ci["ci_low"] <= ci["value"] <= ci["ci_high"]
    assert set(d["evidence"]) == {"backlash", "hysteresis"}
    assert all(e["ok"] and e["splits"] for e in d["evidence"].values())
    assert final["effects"] == ["backlash", "hysteresis"] and final["confounded"] == []
    assert d["spring_check"]["above_noise"] and d["rejected"] == []


def test_html_report_and_overwrite(bench_csv, tmp_path, capsys):
    out = tmp_path / "html"
    assert main(["fit", str(bench_csv), "--out", str(out), "--format", "html", "--no-plots"]) == 0
    assert (out / "report.html").read_text().startswith("<!DOCTYPE html>")
    assert not list(out.glob("*.png"))
    assert main(["fit", str(bench_csv), "--out", str(out)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert main(["fit", str(bench_csv), "--out", str(out), "--no-plots", "--overwrite"]) == 0
    assert (out / "report.md").exists()


def test_degrees_and_other_column_names(tmp_path):
    sim = simulate(BenchSpring(40.0, backlash_rad=0.04), protocol=FAST, seed=4)
    rec = sim.record
    lines = ["t_s,T_Nmm,angle_deg"] + [f"{t:.4f},{1000 * q:.3f},{np.degrees(a):.6f}" for t, q, a in
                                      zip(rec.time_s, rec.torque_Nm, rec.deflection_rad)]
    path = tmp_path / "deg.csv"
    path.write_text("\n".join(lines))
    out = tmp_path / "out"
    rc = main(["fit", str(path), "--out", str(out), "--no-plots", "--time-col", "t_s",
               "--torque-col", "T_Nmm", "--deflection-col", "angle_deg", "--angle-unit", "deg",
               "--torque-unit", "Nmm"])
    assert rc == 0
    d = json.loads((out / "fit.json").read_text())
    assert d["paper_models"]["deadband"]["stiffness_Nm_per_rad"] == pytest.approx(40.0, rel=0.01)
    assert d["paper_models"]["deadband"]["backlash_rad"] == pytest.approx(0.04, rel=0.05)


@pytest.mark.parametrize("content, message", [
    ("time_s,torque,deflection_rad\n0,1,2\n", "missing column(s) 'torque_Nm'"),
    ("time_s,torque_Nm,deflection_rad\n0,x,2\n", "column 'torque_Nm', line 2: 'x' is not a number"),
    ("time_s,torque_Nm,deflection_rad\n0,nan,2\n", "non-finite"),
])
def test_bad_input_exits_2_with_message(tmp_path, capsys, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    assert main(["fit", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("springcad fit: error: ") and message in err
    assert not (tmp_path / "o").exists()


def test_too_few_cycles_exits_2(tmp_path, capsys):
    t = np.arange(0, 2, 0.002)
    theta = 0.2 * np.sin(np.pi * t / 2)
    path = tmp_path / "one.csv"
    path.write_text("time_s,torque_Nm,deflection_rad\n"
                    + "\n".join(f"{a},{40 * b + 0.01 * np.cos(a)},{b}" for a, b in zip(t, theta)))
    assert main(["fit", str(path), "--out", str(tmp_path / "o")]) == 2
    assert "too few cycles" in capsys.readouterr().err


def _csv_with(path, header, rec, deflection, torque=None):
    torque = rec.torque_Nm if torque is None else torque
    path.write_text(header + "\n" + "\n".join(
        f"{t},{q},{a}" for t, q, a in zip(rec.time_s, torque, deflection)))
    return path


def test_degrees_read_as_radians_beyond_a_turn_are_refused(tmp_path, capsys):
    # ±24° read as rad is ±24 rad, almost four turns: the data contradicts the unit
    rec = simulate(BenchSpring(40.0), protocol=FAST, seed=5).record
    path = _csv_with(tmp_path / "deg_as_rad.csv", "time_s,torque_Nm,angle",
                     rec, np.degrees(rec.deflection_rad))
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--no-plots",
                 "--deflection-col", "angle"]) == 2
    err = capsys.readouterr().err
    assert "more than a full turn" in err and "--angle-unit deg" in err
    assert not (tmp_path / "o").exists()


def test_unit_warnings_are_printed(tmp_path, capsys):
    # ±4° read as rad is ±4 rad: implausible but not impossible, so a warning
    rec = simulate(BenchSpring(40.0), protocol=Protocol(amplitudes_rad=(0.03, 0.07), ramp_s=0.8),
                   seed=5).record
    path = _csv_with(tmp_path / "deg_as_rad.csv", "time_s,torque_Nm,angle", rec,
                     np.degrees(rec.deflection_rad))
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--no-plots",
                 "--deflection-col", "angle"]) == 0
    assert "warning: deflection reaches" in capsys.readouterr().err


def test_radians_read_as_degrees_are_refused_by_the_column_name(tmp_path, capsys):
    # the case: rad data with --angle-unit deg gave K 57 times too high, silently
    rec = simulate(BenchSpring(40.0), protocol=FAST, seed=5).record
    path = tmp_path / "rad.csv"
    path.write_text(to_csv_text(rec))
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--angle-unit", "deg"]) == 2
    err = capsys.readouterr().err
    assert "'deflection_rad' is named in rad but --angle-unit deg" in err


def test_radians_read_as_degrees_are_refused_by_the_data(tmp_path, capsys):
    # with an unnamed column, the angles themselves contradict --angle-unit deg: read as
    # degrees they never reach one degree (tests/fit/test_fit_heldout_patterns.py too)
    rec = simulate(BenchSpring(40.0), protocol=FAST, seed=5).record
    path = _csv_with(tmp_path / "rad.csv", "time_s,torque_Nm,angle", rec, rec.deflection_rad)
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--deflection-col", "angle",
                 "--angle-unit", "deg", "--target-stiffness", "40", "--no-plots"]) == 2
    assert "drop --angle-unit deg" in capsys.readouterr().err


def test_newton_millimetres_read_as_newton_metres_are_refused_by_the_target(tmp_path, capsys):
    # a torque column with no unit in its name, in N·mm, read as N·m: magnitudes alone only
    # warn (a stiff spring is possible), the target stiffness is what the data contradicts
    rec = simulate(BenchSpring(40.0), protocol=FAST, seed=5).record
    path = _csv_with(tmp_path / "nmm.csv", "time_s,torque,deflection_rad", rec,
                     rec.deflection_rad, torque=1000.0 * rec.torque_Nm)
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--torque-col", "torque",
                 "--target-stiffness", "40", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "a unit factor" in err and "N·mm was read as N·m" in err


def test_non_positive_target_is_rejected(bench_csv, tmp_path):
    """A usage error is exit status 2, whether argparse exits or main returns it."""
    try:
        rc = main(["fit", str(bench_csv), "--out", str(tmp_path / "o"), "--target-stiffness", "-3"])
    except SystemExit as exc:
        rc = exc.code
    assert rc == 2
    assert not (tmp_path / "o").exists()


def test_config_without_design_core_exits_2(bench_csv, tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "springcad.config", None)
    cfg = tmp_path / "job.toml"
    cfg.write_text("")
    assert main(["fit", str(bench_csv), "--out", str(tmp_path / "o"), "--config", str(cfg)]) == 2
    assert "--config needs the design core" in capsys.readouterr().err


def test_config_compares_with_the_design(bench_csv, tmp_path, monkeypatch):
    calls = []
    config = types.ModuleType("springcad.config")
    config.load_job = lambda path: calls.append(path) or "job"
    job_mod = types.ModuleType("springcad.design.job")

    class FakeDesign:
        def to_dict(self):
            return DESIGN

    job_mod.design_job = lambda job: FakeDesign()
    monkeypatch.setitem(sys.modules, "springcad.config", config)
    monkeypatch.setitem(sys.modules, "springcad.design.job", job_mod)
    cfg = tmp_path / "job.toml"
    cfg.write_text("")
    out = tmp_path / "o"
    assert main(["fit", str(bench_csv), "--out", str(out), "--config", str(cfg), "--no-plots"]) == 0
    assert [str(p) for p in calls] == [str(cfg)]
    d = json.loads((out / "fit.json").read_text())
    comp = d["design_comparison"]
    assert comp["stiffness"]["target_stiffness_Nm_per_rad"] == 37.5
    assert set(comp["backlash"]["ranges"]) == {"worst_case", "rss", "monte_carlo_p01_p99"}
    assert "## Comparison with the design" in (out / "report.md").read_text()


def test_config_with_the_design_core_and_a_simulated_designed_stack(tmp_path):
    # the paper's 4xS1 stack (Mfr. 2 tolerances) designed by springcad, put on the simulated
    # bench at its beam stiffness and nominal backlash, then fitted against its own config
    pytest.importorskip("springcad.config")
    from pathlib import Path
    from springcad.fit.compare import design_from_config

    config = Path(__file__).resolve().parents[2] / "templates" / "paper_4xS1_mfr2.toml"
    if not config.exists():
        pytest.skip("paper templates not in this checkout")
    design = design_from_config(config)
    bench_spring = BenchSpring.from_design(design, friction_torque_Nm=0.1)
    sim = simulate(bench_spring, protocol=FAST, seed=13)
    path = tmp_path / "stack.csv"
    path.write_text(to_csv_text(sim.record))
    out = tmp_path / "o"
    assert main(["fit", str(path), "--out", str(out), "--config", str(config), "--no-plots"]) == 0
    d = json.loads((out / "fit.json").read_text())
    comp = d["design_comparison"]["residual_loop"]
    assert abs(comp["stiffness"]["error_vs_beam_pct"]) < 1.0
    assert comp["measured"]["backlash_rad"] == pytest.approx(
        design["stack"]["backlash_rad"]["nominal"], rel=0.05)
    assert all(r["inside"] for r in comp["backlash"]["ranges"].values())
    assert d["final"]["effects"] == ["backlash", "hysteresis"]


def test_default_output_folder_is_outputs_data_name(bench_csv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["fit", str(bench_csv), "--no-plots"]) == 0
    assert (tmp_path / "outputs" / "bench" / "fit.json").exists()


def test_encoder_column_lets_the_loop_find_series_compliance(tmp_path):
    sim = simulate(spring("series_compliance"), protocol=FAST, seed=14)
    path = tmp_path / "enc.csv"
    path.write_text(to_csv_text(sim.record))
    assert "encoder_in_rad" in path.read_text().splitlines()[0]
    out = tmp_path / "o"
    assert main(["fit", str(path), "--out", str(out), "--no-plots"]) == 0
    d = json.loads((out / "fit.json").read_text())
    assert [s["effect"] for s in d["steps"]] == ["series_compliance"]
    step = d["steps"][0]
    assert step["params"]["series_stiffness_Nm_per_rad"] == pytest.approx(200.0, rel=0.05)
    assert step["evidence"]["heldout_rmse_after_rad"] < step["evidence"]["heldout_rmse_before_rad"]


def test_cli_reports_confounded_and_unexplained_structure(tmp_path, capsys):
    # friction and lag on one ramp rate, plus a stiffness that changes mid-test
    from fit_helpers import ONE_RATE, with_extra_torque

    sim = simulate(spring("hysteresis", "time_lag"), protocol=ONE_RATE, seed=81)
    rec = with_extra_torque(sim, lambda t, th: 0.06 * 40.0 * th * (t > 0.55 * t[-1]))
    path = tmp_path / "rec.csv"
    path.write_text(to_csv_text(rec))
    out = tmp_path / "o"
    assert main(["fit", str(path), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "confounded: hysteresis and time_lag" in printed
    assert "to separate them: springcad simulate" in printed
    assert "unexplained:" in printed and "change at t" in printed
    d = json.loads((out / "fit.json").read_text())
    assert d["final"]["unexplained"] and d["final"]["unexplained_where"]["findings"]
    assert d["protocol_advice"] and d["energy_loss_pct"] is None
    report = (out / "report.md").read_text()
    for section in ("## Evidence audit", "## Identifiability", "**Recommended protocol**",
                    "Where it lives", "![where the unexplained structure lives](unexplained.png)"):
        assert section in report
    assert (out / "unexplained.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
