"""Exit statuses, output folders and console messages of the CLI (issue 11), in-process.

Each class of failure the issue lists has a regression test here or in
``test_config_schema.py`` / ``test_interrupts.py`` / ``test_fuzz_properties.py``.
"""

import dataclasses
import json
import os
import re
import stat
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

from springcad.cli import main
from springcad.errors import EXIT_BAD_INPUT, EXIT_CHECK_FAILED, EXIT_INTERNAL
from tests.conftest import template
from tests.geometry.cad_fixtures import toml_text


def one_error_line(err: str, word: str = "error") -> str:
    lines = [line for line in err.splitlines() if f": {word}:" in line]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def write_job(tmp_path, mutate=None, name="job.toml", base="paper_S1"):
    data = tomllib.loads(template(base).read_text())
    if mutate:
        mutate(data)
    path = tmp_path / name
    path.write_text(toml_text(data))
    return path


# ----------------------------------------------------------------------------- exit statuses
def test_version_and_help_list_the_exit_statuses(capsys):
    from springcad import __version__

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"springcad {__version__}"
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for status in ("0 ", "1 ", "2 ", "3 "):
        assert f"\n  {status}" in out
    assert main(["build", "--help"]) == 0
    assert "internal error" in capsys.readouterr().out


def test_usage_errors_are_exit_2(capsys):
    assert main(["frobnicate"]) == 2
    assert main(["design"]) == 2
    assert main(["verify", str(template("paper_S1")), "--levels", "99"]) == 2
    assert main(["simulate", str(template("paper_S1")), "--out", "x.csv", "--stiffness", "nan"]) == 2
    assert main(["fit", "x.csv", "--target-stiffness", "inf"]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_internal_error_is_exit_3_with_a_log(tmp_path, capsys, monkeypatch):
    import springcad.design.job as job_module

    def broken(job, **kwargs):
        raise KeyError("a bug")

    monkeypatch.setattr(job_module, "design_job", broken)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    assert main(["design", str(template("paper_S1")), "--out", str(tmp_path / "o")]) == EXIT_INTERNAL
    line = one_error_line(capsys.readouterr().err, "internal error")
    log = Path(re.search(r"traceback in (\S+);", line).group(1))
    assert log.parent == tmp_path and "KeyError: 'a bug'" in log.read_text()
    assert "Traceback (most recent call last)" in log.read_text()
    assert not (tmp_path / "o").exists()
    assert main(["--debug", "design", str(template("paper_S1")), "--out", str(tmp_path / "o")]) == 3
    assert "Traceback (most recent call last)" in capsys.readouterr().err


@pytest.mark.parametrize("signum", [2, 15], ids=["SIGINT", "SIGTERM"])
def test_an_interrupt_inside_a_c_extension_import_is_an_interrupt(tmp_path, capsys, monkeypatch,
                                                                  signum):
    """A signal while OCP initialises surfaces as ImportError("initialization failed") caused
    by the interrupt (fuzz --interrupt, seed 15): exit 130/143, not an internal error."""
    import springcad.design.job as job_module
    from springcad.errors import Interrupted

    def importing(job, **kwargs):
        try:
            raise KeyboardInterrupt() if signum == 2 else Interrupted(signum)
        except BaseException as err:
            raise ImportError("initialization failed") from err

    monkeypatch.setattr(job_module, "design_job", importing)
    out = tmp_path / "o"
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 128 + signum
    err = capsys.readouterr().err
    assert "temporary files removed" in err and "internal error" not in err
    assert list(tmp_path.iterdir()) == []


def test_a_library_failure_names_the_stage(tmp_path, capsys, monkeypatch):
    """A numerical library failure inside design is one line naming stage and job, exit 2."""
    import springcad.design.job as job_module

    def broken(job, **kwargs):
        raise ValueError("abscissae must increase")

    monkeypatch.setattr(job_module, "design_job", broken)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    assert main(["design", str(template("paper_S1")), "--out", str(tmp_path / "o")]) == 2
    line = one_error_line(capsys.readouterr().err)
    assert re.search(r"stage 'design' failed on job paper_S1 \(ValueError: abscissae must "
                     r"increase\); the design math broke down.*details in", line), line


class _FailedVerification:
    ok = False

    def summary(self):
        return "S1: K off by 5 %"

    def release_failures(self):
        return []

    def raise_for_failures(self):
        from fea.verdict import VerificationFailed
        raise VerificationFailed("FEA verification failed: S1 stiffness 5 % off target")


def _fake_table(monkeypatch):
    """The console table of the fake verification is its own summary (the report layer
    renders the real ones)."""
    from springcad.report import tables

    monkeypatch.setattr(tables, "verification_table", lambda v: v.summary())


def test_failed_verification_is_exit_1_from_build(tmp_path, capsys, monkeypatch):
    import fea.verify

    monkeypatch.setattr(fea.verify, "verify_job", lambda *a, **k: _FailedVerification())
    _fake_table(monkeypatch)
    out = tmp_path / "o"
    assert main(["build", str(template("paper_S1")), "--out", str(out), "--no-render"]) == \
        EXIT_CHECK_FAILED
    line = one_error_line(capsys.readouterr().err, "failed")
    assert "S1 stiffness 5 % off target" in line
    assert not out.exists() and not list(tmp_path.iterdir())


def test_failed_verification_is_exit_1_from_verify_and_the_report_is_written(tmp_path, capsys,
                                                                            monkeypatch):
    """verify and build agree: a failed verification is exit 1 (it was 1 and 2), not 3."""
    import fea.verify
    import springcad.api.pipeline as pipeline  # the CLI writes through sc.export_verification

    monkeypatch.setattr(fea.verify, "verify_job", lambda *a, **k: _FailedVerification())
    _fake_table(monkeypatch)
    written = []

    def write_outputs(result, folder, **k):
        written.append(folder)
        (folder / "fea.json").write_text("{}")
        return [folder / "fea.json"]

    monkeypatch.setattr(pipeline, "write_outputs", write_outputs)
    out = tmp_path / "o"
    assert main(["verify", str(template("paper_S1")), "--out", str(out), "--quiet"]) == \
        EXIT_CHECK_FAILED
    captured = capsys.readouterr()
    assert "S1: K off by 5 %" in captured.out and "Traceback" not in captured.err
    assert (out / "fea.json").exists() and written


def test_failed_checks_are_exit_1_and_overwrite_keeps_the_old_output(tmp_path, capsys,
                                                                     monkeypatch):
    """A build that fails after its solids (a failed check) is exit 1, and under --overwrite
    the old output folder comes back byte-identical."""
    from springcad.geometry import checks

    out = tmp_path / "out"
    (out / "parts").mkdir(parents=True)
    (out / "design.json").write_bytes(b'{"old": true}\n')
    (out / "parts" / "old.step").write_bytes(b"ISO-10303-21;\x00\xff")
    before = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    real = checks.run_checks

    def failing(assembly, progress=None):
        report = real(assembly, progress)
        report.checks[0] = dataclasses.replace(report.checks[0], passed=False, kind="error")
        return report

    monkeypatch.setattr(checks, "run_checks", failing)
    rc = main(["build", str(template("paper_S1")), "--out", str(out), "--overwrite",
               "--no-verify", "--no-render"])
    assert rc == EXIT_CHECK_FAILED, capsys.readouterr().err
    assert {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


# ----------------------------------------------------------------------------- output paths
@pytest.mark.parametrize("command", ["design", "build", "verify", "fit", "simulate", "paper"])
def test_out_that_is_a_file_or_under_a_file_is_refused_before_work(tmp_path, capsys, command):
    afile = tmp_path / "afile"
    afile.write_text("mine")
    rec = tmp_path / "rec.csv"
    if command == "fit":
        assert main(["simulate", str(template("paper_2xS1")), "--out", str(rec)]) == 0
    for out, pattern in ((afile, r"is a file|already exists"),
                         (afile / "sub", r"lies under '.*afile', which is a file"),
                         (Path("/proc/springcad-test-out"), r"not writable")):
        argv = {"fit": ["fit", str(rec)], "paper": ["paper"],
                "simulate": ["simulate", str(template("paper_S1"))]}.get(
            command, [command, str(template("paper_S1"))])
        t0 = time.perf_counter()
        assert main(argv + ["--out", str(out)]) == EXIT_BAD_INPUT
        assert time.perf_counter() - t0 < 5  # refused before any FEA or CAD work
        line = one_error_line(capsys.readouterr().err)
        assert re.search(pattern, line), line
    assert afile.read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["afile"] + (["rec.csv"] if command == "fit" else []))


def test_paper_refuses_an_existing_output_before_any_fea(tmp_path, capsys):
    """paper ran ~27 s of FEA before refusing an existing --out; now as fast as the others."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    t0 = time.perf_counter()
    assert main(["paper", "--out", str(out)]) == EXIT_BAD_INPUT
    assert time.perf_counter() - t0 < 5
    assert re.search(r"already exists.*--overwrite", one_error_line(capsys.readouterr().err))
    assert [p.name for p in out.iterdir()] == ["keep.txt"]


def test_out_containing_the_input_or_the_current_folder_is_refused(tmp_path, capsys, monkeypatch):
    (tmp_path / "inputs").mkdir()
    job = write_job(tmp_path / "inputs")
    assert main(["design", str(job), "--out", str(tmp_path / "inputs"), "--overwrite"]) == 2
    assert "contains the input" in capsys.readouterr().err
    monkeypatch.chdir(tmp_path / "inputs")
    assert main(["design", str(job), "--out", ".", "--overwrite"]) == 2
    assert main(["design", str(job), "--out", str(tmp_path), "--overwrite"]) == 2
    assert job.exists()


def test_overwrite_never_deletes_an_unrelated_hidden_folder(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "old.txt").write_text("old")
    unrelated = tmp_path / ".out.old"
    unrelated.mkdir()
    (unrelated / "precious.txt").write_text("keep me")
    assert main(["design", str(template("paper_S1")), "--out", str(out), "--overwrite"]) == 0
    assert (unrelated / "precious.txt").read_text() == "keep me"
    assert (out / "design.json").exists() and not (out / "old.txt").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.old", "out"]


def test_a_failing_overwrite_leaves_the_old_output_unchanged(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    bad = write_job(tmp_path, lambda d: d["springs"]["S1"].update(target_stiffness_Nm_per_rad=5e4))
    for command in (["design"], ["build", "--no-verify", "--no-render"]):
        assert main(command[:1] + [str(bad), "--out", str(out), "--overwrite"] + command[1:]) == 2
        one_error_line(capsys.readouterr().err)
        assert {p.name: p.read_bytes() for p in out.iterdir()} == before
        assert sorted(p.name for p in tmp_path.iterdir()) == ["job.toml", "out"]


@pytest.mark.parametrize("mask", [0o022, 0o002, 0o077])
def test_output_modes_follow_the_umask(tmp_path, mask):
    old = os.umask(mask)
    try:
        out = tmp_path / "deep" / "out"
        assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 0
        rec = tmp_path / "rec.csv"
        assert main(["simulate", str(template("paper_S1")), "--out", str(rec)]) == 0
    finally:
        os.umask(old)
    for path, full in ((tmp_path / "deep", 0o777), (out, 0o777), (out / "design.json", 0o666),
                       (rec, 0o666)):
        assert stat.S_IMODE(path.stat().st_mode) == full & ~mask, path


def test_simulate_out_is_a_folder_even_with_overwrite(tmp_path, capsys):
    folder = tmp_path / "outdir"
    folder.mkdir()
    (folder / "keep.txt").write_text("mine")
    assert main(["simulate", str(template("paper_S1")), "--out", str(folder), "--overwrite"]) == 2
    assert "is a folder" in one_error_line(capsys.readouterr().err)
    assert (folder / "keep.txt").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["outdir"]


def test_failed_run_removes_the_parent_folders_it_created(tmp_path, capsys):
    bad = write_job(tmp_path, lambda d: d["springs"]["S1"].update(target_stiffness_Nm_per_rad=5e4))
    assert main(["build", str(bad), "--out", str(tmp_path / "a" / "b" / "out"), "--no-verify"]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.toml"]


# ----------------------------------------------------------------------------- warnings, names
def test_warnings_are_printed_on_the_console_and_kept_in_design_json(tmp_path, capsys):
    job = write_job(tmp_path, lambda d: (d["springs"]["S1"].update(min_tip_radius_mm=0.3),
                                         d.update(analysis={"monte_carlo_samples": 1})))
    out = tmp_path / "o"
    assert main(["design", str(job), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert re.search(r"springcad design: warning: spring S1: min_tip_radius_mm .* ignored", err)
    assert re.search(r"springcad design: warning: analysis\.monte_carlo_samples = 1", err)
    warnings = json.loads((out / "design.json").read_text())["warnings"]
    assert len(warnings) == 2


def test_fastener_count_cut_is_a_warning(tmp_path, capsys):
    job = write_job(tmp_path, lambda d: (d["springs"]["S1"].pop("n_flexures"),
                                         d.update(hardware={"fastener_count": 150})))
    assert main(["design", str(job), "--out", str(tmp_path / "o")]) == 0
    assert re.search(r"warning: spring S1: hardware\.fastener_count = 150 cut to \d+",
                     capsys.readouterr().err)


def test_low_stiffness_in_range_warns_of_flexures_thinner_than_the_wire(tmp_path, capsys):
    job = write_job(tmp_path, lambda d: d["springs"]["S1"].update(target_stiffness_Nm_per_rad=0.001),
                    base="default")
    rc = main(["design", str(job), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc in (0, 2), err
    if rc == 0:  # the tip web is kept at min_web_mm, so the envelope cannot reach the target
        assert "thinner than the EDM wire" in err or "cannot give that stiffness" in err
    else:
        one_error_line(err)


def test_fastener_too_big_for_the_rim_rule_gets_a_wider_rim(tmp_path, capsys):
    """The rim rule makes a ~2.5 mm rim that 3 mm dowels cannot fit (negative mass, then a
    refusal before): the design search now lowers the root radius so the holes keep their
    edge distance, or refuses with the change that works."""
    job = write_job(tmp_path, lambda d: d.update(hardware={"fastener_diameter_mm": 3.0}))
    code = main(["design", str(job), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    if code == 2:
        assert "feasible with" in err
        return
    assert code == 0
    doc = json.loads((tmp_path / "o" / "design.json").read_text())
    edge = doc["manufacturing"]["min_hole_edge_mm"]
    for s in doc["springs"].values():
        circle, r_hole = s["hole_circle_radius_mm"], 0.5 * s["hole_diameter_mm"]
        assert circle - r_hole - s["root_radius_mm"] >= edge - 1e-9
        assert s["outer_radius_mm"] - circle - r_hole >= edge - 1e-9


def test_no_layout_message_does_not_blame_the_torque_cap(tmp_path, capsys):
    """120 flexures cannot fit a 20 mm disk; the torque cap is not the reason (it was quoted)."""
    job = write_job(tmp_path, lambda d: (d["springs"]["S1"].update(
        n_flexures=120, outer_radius_mm=20, target_stiffness_Nm_per_rad=5), d.update(
        hardware={"fastener_count": 0}), d["stack"].update(sequence=["S1"])), base="default")
    assert main(["design", str(job), "--out", str(tmp_path / "o")]) == 2
    line = one_error_line(capsys.readouterr().err)
    assert "no layout fits" in line and "N = 120" in line and "torque cap" not in line


# ----------------------------------------------------------------------------- bench CSVs
@pytest.fixture(scope="module")
def clean_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("rec") / "rec.csv"
    assert main(["simulate", str(template("paper_2xS1")), "--out", str(path), "--seed", "2"]) == 0
    return path.read_text()


def _scaled(text: str, column: str, factor: float) -> str:
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line and not line.startswith("#"))
    col = lines[i].split(",").index(column)
    out = lines[:i + 1]
    for line in lines[i + 1:]:
        cells = line.split(",")
        cells[col] = repr(float(cells[col]) * factor)
        out.append(",".join(cells))
    return "\n".join(out) + "\n"


CSV_CASES = {
    "latin-1 byte": (lambda t: b"# caf\xe9\n" + t.encode(), r"not UTF-8: byte 0xe9 at byte offset 5"),
    "utf-16": (lambda t: t.encode("utf-16"), r"is UTF-16"),
    "negative stiffness": (lambda t: _scaled(t, "torque_Nm", -1).encode(),
                           r"torque falls as the deflection rises.*flipped"),
    "torque x 1e300": (lambda t: _scaled(t, "torque_Nm", 1e300).encode(), r"torque peaks at .*e\+"),
    "torque x 1e-300": (lambda t: _scaled(t, "torque_Nm", 1e-300).encode(), r"torque peaks at"),
}


@pytest.mark.parametrize("case", list(CSV_CASES))
def test_bad_bench_csv_is_one_line_exit_2(tmp_path, capsys, clean_csv, case):
    make, pattern = CSV_CASES[case]
    data = make(clean_csv)
    path = tmp_path / "bad.csv"
    path.write_bytes(data)
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--no-plots"]) == 2
    assert re.search(pattern, one_error_line(capsys.readouterr().err))
    assert path.read_bytes() == data
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]


def test_clean_csv_still_fits(tmp_path, clean_csv):
    path = tmp_path / "rec.csv"
    path.write_text(clean_csv)
    assert main(["fit", str(path), "--out", str(tmp_path / "o"), "--no-plots"]) == 0
    k = json.loads((tmp_path / "o" / "fit.json").read_text())["final"]["params"]
    assert np.isfinite(k["stiffness_Nm_per_rad"]) and k["stiffness_Nm_per_rad"] > 0
