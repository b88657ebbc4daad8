"""`springcad design` end to end, in-process."""

import json

import pytest

from springcad.cli import main
from tests.conftest import template

REQUIRED_SPRING = {"stiffness_Nm_per_rad", "max_deflection_rad", "peak_torque_Nm", "n_flexures",
                   "contact_radius_mm", "root_radius_mm", "tip_radius_mm", "flexure", "mass_kg",
                   "energy_J", "energy_density_J_per_cm3", "specific_energy_J_per_kg"}


def test_design_json_schema(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["design", str(template("paper_S1_2xS2")), "--out", str(out)]) == 0
    d = json.loads((out / "design.json").read_text())
    for spring in d["springs"].values():
        assert REQUIRED_SPRING <= set(spring)
        assert spring["flexure"] in ("straight", "serpentine")
    st = d["stack"]
    assert st["sequence"] == ["S1", "S2", "S2"]
    assert st["connections"] == ["rim-to-rim", "shaft-to-shaft"]
    assert {"nominal", "worst_min", "worst_max", "rss"} <= set(st["backlash_rad"])
    lo, hi = st["backlash_rad"]["rss"]
    assert st["backlash_rad"]["worst_min"] < lo < st["backlash_rad"]["nominal"] < hi
    assert st["stiffness_Nm_per_rad"] == pytest.approx(30, rel=1e-3)
    summary = capsys.readouterr().out
    assert "eq. 10" in summary and "S1" in summary


def test_existing_output_is_not_overwritten(tmp_path, capsys):
    out = tmp_path / "o"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert (out / "keep.txt").read_text() == "mine"
    assert main(["design", str(template("paper_S1")), "--out", str(out), "--overwrite"]) == 0
    assert (out / "design.json").exists() and not (out / "keep.txt").exists()


def test_default_output_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["design", str(template("paper_S2"))]) == 0
    assert (tmp_path / "outputs" / "paper_S2" / "design.json").exists()
