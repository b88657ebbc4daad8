"""`springcad synthesize` and `springcad explore` end to end on small spaces."""

import json
import math

import numpy as np
import pytest

from springcad.cli import main
from springcad.config import load_job
from springcad.design.job import design_job
from synth_fixtures import SMALL, requirements_toml, small


@pytest.fixture(scope="module")
def synthesized(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("synth")
    path = tmp / "req.toml"
    path.write_text(requirements_toml(small()))
    code = main(["synthesize", str(path), "--out", str(tmp / "run"), "--workers", "2",
                 "--batch-size", "300", "--no-verify", "--finalists", "4"])
    return code, tmp / "run"


def test_synthesize_writes_a_buildable_winner(synthesized):
    code, run = synthesized
    assert code == 0
    report = json.loads((run / "synthesis.json").read_text())
    assert report["n_feasible"] > 0
    winner = report["winner"]
    # the winner is the lightest finalist that passed the full design
    passed = [f for f in report["finalists_full_design"] if f["ok"]]
    assert winner["cid"] == min(passed, key=lambda f: f["mass_kg"])["cid"]
    job = load_job(run / "winner.toml")
    jd = design_job(job)
    st = jd.stack
    assert st.stiffness_Nmm_per_rad == pytest.approx(37.5e3, rel=0.01)
    assert st.max_deflection_rad == pytest.approx(
        math.radians(SMALL["requirement"]["deflection_deg"]), rel=1e-6)
    assert st.height_mm <= 19.5 + 1e-9 and st.envelope_radius_mm <= 35.05 + 1e-9
    full = next(f for f in report["finalists_full_design"] if f["cid"] == winner["cid"])
    assert st.mass_kg == pytest.approx(full["mass_kg"], rel=1e-9)
    # screening mass agrees with the exact profiles within 3 %
    assert winner["mass_kg"] == pytest.approx(st.mass_kg, rel=0.03)
    assert job.material.design_stress_MPa == pytest.approx(912.0, abs=0.05)


@pytest.mark.slow
def test_winner_passes_the_build_checks(synthesized):
    """`springcad build`'s solids and geometry checks (no FEA, no exports) pass on the
    winner's job as written: no geometry error, no manufacturability violation (~60 s)."""
    from springcad.synthesis.finalists import build_checks

    _, run = synthesized
    checks = build_checks(design_job(load_job(run / "winner.toml")))
    assert checks["ok"], checks["failures"]
    assert checks["failures"] == [] and "0 geometry errors, 0 manufacturability" in checks["summary"]


def test_synthesize_resumes(synthesized, capsys):
    """A second run in the same folder evaluates no candidate again."""
    _, run = synthesized
    req = run.parent / "req.toml"
    code = main(["synthesize", str(req), "--out", str(run), "--workers", "1", "--batch-size",
                 "300", "--no-verify", "--finalists", "1"])
    assert code == 0
    report = json.loads((run / "synthesis.json").read_text())
    assert report["sweep"]["evaluated_candidates"] == 0
    assert report["sweep"]["skipped_batches"] == report["sweep"]["batches"]


def test_a_winner_that_failed_its_verification_is_not_written_as_the_winner(synthesized):
    """When the FEA or build checks fail every verified finalist, the best of them is written
    as closest.toml, saying it is not a winner, and no winner.toml a user would build."""
    import dataclasses

    import springcad.api as sc

    _, run = synthesized
    result = sc.synthesize(run.parent / "req.toml", run, workers=1, batch_size=300,
                           verify=False, finalists=1)  # resumes: no candidate again
    assert result.ok and result.winner_file == "winner.toml"
    assert "Build it with: springcad build" in result.winner_toml()
    failed = dataclasses.replace(result, verifications={
        int(result.winner["cid"]): {"ok": False}})
    assert not failed.ok and failed.winner_file == "closest.toml"
    text = failed.winner_toml()
    assert "NOT a winner" in text and "Build it with" not in text


def test_explore_writes_region_fronts_and_plots(tmp_path, capsys):
    import pyarrow.parquet as pq

    out = tmp_path / "map"
    code = main(["explore", "--out", str(out), "--workers", "1", "--stiffness-Nm-per-rad",
                 "10:300:8", "--deflection-rad", "0.1:2.5:10", "--max-disks", "3",
                 "--thickness-mm", "4.5", "--contact-radius-mm", "6", "7.5"])
    assert code == 0
    region = pq.read_table(out / "region.parquet").to_pydict()
    n, th = np.array(region["n_disks"]), np.array(region["deflection_rad"])
    reach = [th[n == k].max() for k in (1, 2, 3)]
    # the series stack widens the deflection range (paper Fig. 8)
    assert reach[0] < reach[1] < reach[2]
    lo, hi = np.array(region["min_peak_torque_Nm"]), np.array(region["max_peak_torque_Nm"])
    assert np.all(lo <= hi)
    efront = pq.read_table(out / "pareto_energy.parquet").to_pydict()
    ed = np.array(efront["energy_density_J_per_cm3"])
    assert np.all(np.diff(ed) < 0)  # along the front, more deflection costs energy density
    for name in ("region.png", "pareto_mass.png", "pareto_energy.png"):
        assert (out / name).stat().st_size > 10_000
    summary = json.loads((out / "explore.json").read_text())
    assert summary["n_candidates"] == 8 * 10 * 3 * 2


def test_explore_bad_range_is_one_line(tmp_path, capsys):
    assert main(["explore", "--out", str(tmp_path), "--deflection-rad", "2:1:5"]) == 2
    assert "MIN < MAX" in capsys.readouterr().err
