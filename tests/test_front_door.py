"""One front door per stage (issue 23): the API and the CLI give the same results, and
failures and inputs are handled below the API once."""

from __future__ import annotations

import pytest

from springcad.errors import CheckFailed


def test_failed_verdicts_are_one_family():
    from fea.verdict import VerificationFailed
    from springcad.geometry.checks import CheckReport, ChecksFailed

    assert issubclass(VerificationFailed, CheckFailed)
    assert issubclass(ChecksFailed, CheckFailed)
    # a report with a failed error check raises the family's class, not a translation
    from springcad.geometry.checks import Check

    bad = CheckReport([Check("solid_valid", "S1-RING", False, message="not a valid solid")])
    with pytest.raises(CheckFailed, match="S1-RING: solid_valid: not a valid solid"):
        bad.raise_if_failed()


# ----------------------------------------------------------------------------- helpers
import json  # noqa: E402
import math  # noqa: E402

import numpy as np  # noqa: E402

import springcad as sc  # noqa: E402
from springcad.cli import main  # noqa: E402
from tests.conftest import template  # noqa: E402

#: keys that hold wall-clock times or dates: the only ones two runs may differ in
VOLATILE = {"timings_s", "started", "timings", "wall_s", "time_s", "total_s", "elapsed_s"}


def stable(doc, drop=()):
    """A JSON document without its wall-clock keys (and ``drop``), for comparison."""
    if isinstance(doc, dict):
        return {k: stable(v, drop) for k, v in doc.items() if k not in VOLATILE and k not in drop}
    if isinstance(doc, list):
        return [stable(v, drop) for v in doc]
    return doc


def as_json(doc):
    """The document as the CLI's JSON file holds it: written by the same writer, read back."""
    import tempfile
    from pathlib import Path

    from springcad.report.jsonio import write_json

    with tempfile.TemporaryDirectory() as tmp:
        write_json(Path(tmp) / "doc.json", doc)
        return json.loads((Path(tmp) / "doc.json").read_text())


# ----------------------------------------------------------------------------- one bench reader
def _bench_files(tmp_path):
    """The same simulated record twice: in rad and N*m (plain), and in deg and N*mm with a
    byte-order mark, a comment line and renamed columns."""
    rec = sc.simulate(40.0, backlash_rad=0.03, seed=5, friction_torque_Nm=0.1).record
    plain = tmp_path / "plain.csv"
    plain.write_text(rec.to_csv())
    rows = np.column_stack([rec.time_s, np.degrees(rec.deflection_rad), 1000.0 * rec.torque_Nm])
    body = "\n".join(f"{t:.9g},{a:.12g},{m:.12g}" for t, a, m in rows)
    odd = tmp_path / "bench_deg_Nmm.csv"
    odd.write_bytes(b"\xef\xbb\xbf" + f"# bench 7, spring S1\nt,angle_deg,T_Nmm\n{body}\n"
                    .encode("utf-8"))
    return rec, plain, odd


def test_bench_csv_with_bom_in_deg_and_Nmm_fits_the_same_through_api_and_cli(tmp_path, capsys):
    rec, plain, odd = _bench_files(tmp_path)
    options = dict(time_col="t", torque_col="T_Nmm", deflection_col="angle_deg",
                   angle_unit="deg", torque_unit="Nmm")
    api = sc.fit_record(odd, 40.0, **options)
    out = tmp_path / "cli"
    assert main(["fit", str(odd), "--out", str(out), "--target-stiffness", "40", "--no-plots",
                 "--time-col", "t", "--torque-col", "T_Nmm", "--deflection-col", "angle_deg",
                 "--angle-unit", "deg", "--torque-unit", "Nmm"]) == 0
    cli = json.loads((out / "fit.json").read_text())
    assert stable(cli) == stable(as_json(api.to_dict()))
    # the reader converted deg and N*mm: the record equals the simulated one (to the
    # printed digits), and the fit the one of the plain rad/N*m file
    got = api.raw.record
    assert np.allclose(got.deflection_rad, rec.deflection_rad, rtol=1e-9, atol=1e-12)
    assert np.allclose(got.torque_Nm, rec.torque_Nm, rtol=1e-9, atol=1e-12)
    reference = sc.fit_record(plain, 40.0)
    assert api.stiffness_Nm_per_rad == pytest.approx(reference.stiffness_Nm_per_rad, rel=1e-6)
    assert api.backlash_rad == pytest.approx(reference.backlash_rad, rel=1e-6, abs=1e-9)
    assert api.stiffness_Nm_per_rad == pytest.approx(40.0, rel=0.03)


def test_fit_holds_its_summary_as_fields_equal_to_its_document(tmp_path, monkeypatch):
    f = sc.fit_record(sc.simulate(40.0, backlash_rad=0.03, seed=5, friction_torque_Nm=0.1))
    doc = as_json(f.to_dict())
    # the fields, read without the document (a fit that would write its JSON fails here)
    monkeypatch.setattr(type(f.raw), "to_dict", lambda self: pytest.fail("read its own JSON"))
    held = {k: vars(f)[k] for k in ("model", "stiffness_Nm_per_rad", "backlash_rad", "nrmse_pct")}
    effects, text = f.effects(), repr(f)
    monkeypatch.undo()
    # ... equal the document fit.json holds (the second reader)
    final = doc["final"]
    assert held == {"model": final["model"],
                    "stiffness_Nm_per_rad": final["intervals"]["stiffness_Nm_per_rad"]["value"],
                    "backlash_rad": doc["paper_models"]["deadband"]["backlash_rad"],
                    "nrmse_pct": final["nrmse_pct"]}
    assert effects == [{k: s.get(k) for k in ("effect", "action", "nrmse_before_pct",
                                              "nrmse_after_pct")} for s in doc["steps"]]
    assert effects and f.model.startswith("linear + ")
    assert f"K={held['stiffness_Nm_per_rad']:.4g} N*m/rad" in text


def test_bench_reader_refuses_the_same_way_through_both_doors(tmp_path, capsys):
    _, _, odd = _bench_files(tmp_path)
    # read as rad, a column named in degrees: both doors refuse, each naming its option
    with pytest.raises(sc.SpringcadError, match=r"'angle_deg' is named in deg but "
                                                r"angle_unit='rad' .*pass angle_unit='deg'"):
        sc.fit_record(odd, time_col="t", torque_col="T_Nmm", deflection_col="angle_deg",
                      torque_unit="Nmm")
    assert main(["fit", str(odd), "--out", str(tmp_path / "o"), "--time-col", "t",
                 "--torque-col", "T_Nmm", "--deflection-col", "angle_deg",
                 "--torque-unit", "Nmm"]) == 2
    err = capsys.readouterr().err
    assert "'angle_deg' is named in deg but --angle-unit rad" in err
    assert "pass --angle-unit deg" in err
    assert "angle_unit=" not in err
    # an option outside its choices is a ConfigError naming the parameter
    with pytest.raises(sc.SpringcadError, match="angle_unit"):
        sc.fit_record(odd, angle_unit="grad")


def test_verify_options_are_checked_once_with_the_public_names(tmp_path):
    from springcad.errors import ConfigError

    d = sc.design_job(template("paper_S1"))
    # the core refused 50 % with a bare error while the doors accepted it: one rule now
    for bad, name in ((dict(tolerance_pct=50.0), "tolerance_pct"), (dict(mesher="tetgen"), "mesher"),
                      (dict(load="magnet"), "load"), (dict(levels=6), "levels"),
                      (dict(model="4d"), "model")):
        with pytest.raises(ConfigError, match=name):
            sc.verify(d, **bad)
    from fea.study import VerifyOptions

    with pytest.raises(ConfigError, match="tolerance"):
        VerifyOptions(tolerance=0.5)
    # one set of defaults: the API's are the core's and the CLI's
    import inspect

    from springcad.cli import build_parser
    from springcad.options import VERIFY

    params = inspect.signature(sc.verify).parameters
    core = VerifyOptions()
    ns = build_parser().parse_args(["verify", "x.toml"])
    for name in ("model", "levels", "mesher", "tolerance_pct", "correct", "load",
                 "support_study", "contact"):
        assert params[name].default == getattr(VERIFY, name) == getattr(ns, name), name
    assert (core.model, core.levels, core.mesher, core.case.load, core.contact) == (
        VERIFY.model, VERIFY.levels, VERIFY.mesher, VERIFY.load, VERIFY.contact)
    assert math.isclose(core.tolerance, VERIFY.tolerance_pct / 100)


def test_output_refusals_name_the_option_as_the_door_spells_it(tmp_path, capsys, s1_built):
    """The output-folder checks live below the API: from Python they name the parameters
    (out, overwrite=True), from the command line the flags (--out, --overwrite)."""
    taken = tmp_path / "taken"
    taken.mkdir()
    (taken / "x.txt").write_text("kept")
    from springcad.errors import OutputExistsError

    # the module's shared build (refused before any file is written; the export that
    # follows in test_build_through_api_and_cli_gives_the_same_json reads it whole)
    with pytest.raises(OutputExistsError, match=r"choose another out or pass overwrite=True$"):
        sc.export_build(s1_built, taken, render=False)
    assert (taken / "x.txt").read_text() == "kept"
    assert main(["design", str(template("paper_S1")), "--out", str(taken)]) == 2
    err = capsys.readouterr().err
    assert "choose another --out or pass --overwrite" in err


# ----------------------------------------------------------------------------- one door per stage
def test_design_through_api_and_cli_gives_the_same_json(tmp_path):
    cfg = template("paper_S1_2xS2")
    assert main(["design", str(cfg), "--out", str(tmp_path / "cli")]) == 0
    cli = json.loads((tmp_path / "cli" / "design.json").read_text())
    assert stable(cli) == stable(as_json(sc.design_job(cfg).to_dict()))


def test_simulate_through_api_and_cli_gives_the_same_record(tmp_path):
    cfg = template("paper_S1")
    out = tmp_path / "rec.csv"
    assert main(["simulate", str(cfg), "--out", str(out), "--seed", "4", "--protocol", "sine",
                 "--frequencies-hz", "0.5,1", "--friction-Nm", "0.05"]) == 0
    sim = sc.simulate(sc.design_job(cfg), seed=4, friction_torque_Nm=0.05,
                      protocol=sc.bench_protocol("sine", frequencies_hz=(0.5, 1.0)))
    assert out.read_text() == sim.record.to_csv()


def test_verify_through_api_and_cli_gives_the_same_json(tmp_path):
    cfg = template("paper_S1")
    assert main(["verify", str(cfg), "--out", str(tmp_path / "cli"), "--model", "2d",
                 "--no-contact", "--no-render", "--quiet"]) == 0
    cli = json.loads((tmp_path / "cli" / "fea.json").read_text())
    api = sc.verify(cfg, model="2d", contact=False)
    assert stable(cli) == stable(as_json(api.to_dict()))


@pytest.fixture(scope="module")
def s1_built():
    """The paper S1 built through the API (no FEA), once for the module: the tests only
    read it and export it (``export_build`` leaves the Build it is given, which
    test_export_build_leaves_the_build_it_was_given checks on this shared Build), or are
    refused exporting it (test_output_refusals_name_the_option_as_the_door_spells_it)."""
    return sc.build(sc.design_job(template("paper_S1")))


@pytest.mark.slow
def test_build_through_api_and_cli_gives_the_same_json(tmp_path, monkeypatch, s1_built):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")  # the same date on both drawings
    cfg = template("paper_S1")
    assert main(["build", str(cfg), "--out", str(tmp_path / "cli"), "--no-verify",
                 "--no-render"]) == 0
    cli = json.loads((tmp_path / "cli" / "build.json").read_text())
    # the date is the export's (api/pipeline.py build_date): the shared Build takes it here
    built = sc.export_build(s1_built, tmp_path / "api", render=False)
    # file sizes left out: a second build in one process can write a coordinate as -0. where
    # the first wrote 0. (the CAD kernel's signed zero), two bytes in a STEP file
    assert stable(cli, drop={"bytes"}) == stable(as_json(built.to_dict()), drop={"bytes"})
    assert [f["path"] for f in cli["files"]] == [f.path for f in built.files]
    design_cli = json.loads((tmp_path / "cli" / "design.json").read_text())
    design_api = json.loads((tmp_path / "api" / "design.json").read_text())
    assert stable(design_cli) == stable(design_api)


@pytest.fixture(scope="module")
def paper_validation():
    """The paper's validation without FEA through the API, once for the module (read only)."""
    return sc.validate_paper(use_fea=False)


def test_paper_through_api_and_cli_gives_the_same_json(tmp_path, paper_validation):
    assert main(["paper", "--out", str(tmp_path / "cli"), "--no-fea"]) == 0
    cli = json.loads((tmp_path / "cli" / "validation.json").read_text())
    api = paper_validation
    assert len(cli["configurations"]) == 7
    assert stable(cli) == stable(as_json(api.to_dict()))


def test_explore_through_api_and_cli_gives_the_same_json(tmp_path):
    grid = dict(stiffness_Nm_per_rad="10:300:3", deflection_rad="0.1:2.5:3", max_disks=2,
                thickness_mm=[4.5], contact_radius_mm=[6.0])
    assert main(["explore", "--out", str(tmp_path / "cli"), "--workers", "1",
                 "--stiffness-Nm-per-rad", grid["stiffness_Nm_per_rad"], "--deflection-rad",
                 grid["deflection_rad"], "--max-disks", "2", "--thickness-mm", "4.5",
                 "--contact-radius-mm", "6"]) == 0
    cli = json.loads((tmp_path / "cli" / "explore.json").read_text())
    api = sc.explore(tmp_path / "api", workers=1, **grid)
    assert cli["n_candidates"] == 3 * 3 * 2
    # the sweep's rate is a wall-clock figure too
    assert stable(cli, drop={"candidates_per_s"}) == stable(as_json(api),
                                                            drop={"candidates_per_s"})


def test_synthesize_through_api_and_cli_gives_the_same_json(tmp_path):
    from tests.synthesis.synth_fixtures import requirements_toml, small

    req = tmp_path / "req.toml"
    req.write_text(requirements_toml(small()))
    options = ["--workers", "1", "--batch-size", "300", "--no-verify", "--finalists", "2"]
    assert main(["synthesize", str(req), "--out", str(tmp_path / "cli"), *options]) == 0
    cli = json.loads((tmp_path / "cli" / "synthesis.json").read_text())
    api = sc.synthesize(req, tmp_path / "api", workers=1, batch_size=300, verify=False,
                        finalists=2)
    assert cli["winner"] is not None and api.winner is not None
    # the sweep's rate is a wall-clock figure too
    assert stable(cli, drop={"candidates_per_s"}) == stable(as_json(api.to_dict()),
                                                            drop={"candidates_per_s"})
    assert (tmp_path / "cli" / "winner.toml").read_text() == api.winner_toml()


def test_verification_files_through_api_and_cli_are_the_same(tmp_path):
    """``springcad verify`` writes its folder through ``sc.export_verification``: the API
    writes the same fea.json, lists what it wrote, and refuses what is not a Verification."""
    cfg = template("paper_S1")
    assert main(["verify", str(cfg), "--out", str(tmp_path / "cli"), "--model", "2d",
                 "--no-contact", "--no-render", "--quiet"]) == 0
    v = sc.verify(cfg, model="2d", contact=False)
    files = sc.export_verification(v, tmp_path / "api", render=False)
    assert files == [tmp_path / "api" / "fea.json"] and files[0].is_file()
    assert (stable(json.loads(files[0].read_text()))
            == stable(json.loads((tmp_path / "cli" / "fea.json").read_text())))
    with pytest.raises(sc.SpringcadError, match="takes the Verification that sc.verify returned"):
        sc.export_verification(v.design, tmp_path / "other")
    assert not (tmp_path / "other").exists()


def test_export_build_leaves_the_build_it_was_given(tmp_path, s1_built):
    """``export_build`` returns a new Build with the folder, files and release; the Build it
    was given is left as it was (as build123d's ``export_step`` leaves its shape). The
    module's shared Build may have been exported before: an export that changed it would
    fail here either way (its folder, release and files must still be unset)."""
    built = s1_built
    before = (built.out_dir, list(built.files), built.release, dict(built.timings_s),
              dict(built.options), list(built.roundtrip))
    exported = sc.export_build(built, tmp_path / "out", render=False)
    assert exported is not built
    assert (built.out_dir, built.files, built.release, built.timings_s, built.options,
            built.roundtrip) == before
    assert built.out_dir is None and built.released is None and built.report_html is None
    assert exported.out_dir == tmp_path / "out" and exported.report_html.is_file()
    assert {f.path for f in exported.files} >= {"design.json", "report.html"}
    assert (tmp_path / "out" / "build.json").is_file()
    assert exported.release is not None and exported.roundtrip


def test_every_result_document_is_stamped_by_the_one_writer(paper_validation):
    """Each document's head (schema, version) comes from ``springcad.version.stamp`` and
    from nowhere else in the package."""
    import re
    from pathlib import Path

    from springcad.version import __version__

    docs = {"design": sc.design_job(template("paper_S1")).to_dict(),
            "fit": sc.fit_record(sc.simulate(40.0, seed=5)).to_dict(),
            "validation": paper_validation.to_dict()}
    for name, doc in docs.items():
        assert list(doc)[:2] == ["schema", "springcad_version"], name
        assert doc["schema"].startswith(f"springcad.{name}/") and \
            doc["springcad_version"] == __version__
    root = Path(sc.__file__).parent
    literal = re.compile(r"""["']schema["']\s*:""")
    writers = sorted(str(p.relative_to(root)) for p in root.rglob("*.py")
                     if literal.search(p.read_text()))
    # the writer, and the sweep's resume manifest (not a result document)
    assert writers == ["synthesis/store.py", "version.py"]


# ----------------------------------------------------------------------------- leftovers of issue 23
def test_results_hold_data_and_report_renders_their_tables():
    """The terminal tables are made in report/ (as the notebook views are): the internal
    results have no text renderer, and the API results hand over to report.tables."""
    from fea.verdict import JobVerification, SpringVerification
    from springcad.design.job import JobDesign
    from springcad.report import tables

    assert not any(hasattr(cls, name) for cls in (JobDesign, JobVerification, SpringVerification)
                   for name in ("summary", "contact_summary"))
    d = sc.design_job(template("paper_S1_2xS2"))
    text = d.summary()
    assert text == tables.design_table(d.raw)
    # the table's numbers are the design's (a second reader: design.json)
    doc = as_json(d.to_dict())
    for name, s in doc["springs"].items():
        row = next(r for r in text.splitlines() if r.split()[:1] == [name])
        assert row.split()[1] == f"{s['stiffness_Nm_per_rad']:.2f}"
    assert f"K = {doc['stack']['stiffness_Nm_per_rad']:.2f} N*m/rad" in text


def test_documents_name_a_skipped_verification_the_same_from_both_doors():
    """A skipped FEA is written as the parameter and the flag, whichever door built it, so
    build.json is the same through the API and the CLI; messages still follow the door."""
    from springcad.export.release import release_status
    from springcad.options import spell, spelled

    d = sc.design_job(template("paper_S1")).raw
    with spelled("parameter"):
        from_api = release_status(d, None, verify_skipped=True).reasons[0]
        assert spell("verify", False) == "verify=False"
    with spelled("flag"):
        from_cli = release_status(d, None, verify_skipped=True).reasons[0]
        assert spell("verify", False) == "--no-verify"
    assert from_api == from_cli
    assert "verify=False" in from_api and "--no-verify" in from_api


def test_sweep_columns_name_the_target_stiffness_and_carry_units(tmp_path):
    """The sweep's Parquet says which stiffness it holds: the target of the requirement
    (target_stiffness_Nm_per_rad, as the job configs name it), while the finalists'
    stiffness_Nm_per_rad in synthesis.json is the designed stack's."""
    import pyarrow.parquet as pq

    from tests.synthesis.synth_fixtures import SMALL, requirements_toml, small

    req = tmp_path / "req.toml"
    req.write_text(requirements_toml(small()))
    result = sc.synthesize(req, tmp_path / "run", workers=1, batch_size=300, verify=False,
                           finalists=2)
    cols = pq.read_table(sorted((tmp_path / "run" / "parts").glob("*.parquet"))[0]).to_pydict()
    target = SMALL["requirement"]["stiffness_Nm_per_rad"]
    assert "stiffness_Nm_per_rad" not in cols
    assert cols["target_stiffness_Nm_per_rad"] == pytest.approx(
        [target] * len(cols["cid"]), rel=1e-12)
    physical = ("radius", "thickness", "stress", "torque", "mass", "length", "energy",
                "deflection", "backlash")
    unitless = {"stress_derating_a", "stress_derating_b", "stiffness_built_error"}
    for name in cols:
        if any(p in name for p in physical) and name not in unitless:
            assert name.rsplit("_", 1)[-1] in {"mm", "MPa", "Nm", "kg", "J", "rad", "cm3"} \
                or name.endswith(("_per_rad", "_per_cm3", "_per_kg")), name
    doc = json.loads((tmp_path / "run" / "synthesis.json").read_text())
    assert all("target_stiffness_Nm_per_rad" in r for r in doc["top_screened"])
    done = [f for f in result.finalists if f["ok"]]
    assert done and all(f["stiffness_Nm_per_rad"] == pytest.approx(target, rel=0.05)
                        for f in done)
