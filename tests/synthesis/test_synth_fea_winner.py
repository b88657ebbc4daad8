"""The synthesized winner passes the 2D FEA and build checks synthesize runs on its finalists (slow),
with the peak stress that screening predicted."""

import json

import pytest

from springcad.cli import main
from springcad.config import load_job
from synth_fixtures import requirements_toml, small

#: the conservative 4xS1 requirement (first beam stress yield / 1.6, straight flexures) on a
#: small space
CONSERVATIVE = small(materials={"names": ["maraging_300"], "yield_margin": 1.0,
                                "stress_concentration": 1.6},
                     search={"max_disks": 5, "thickness_mm": [4.0], "contact_radius_mm": [6.5, 7.0],
                             "mixed": False, "inputs": ["rim"], "flexure": "straight",
                             "fewer_flexures": [0, 2]})


@pytest.mark.slow
def test_winner_passes_fea(tmp_path, capsys):
    path = tmp_path / "req.toml"
    path.write_text(requirements_toml(CONSERVATIVE))
    code = main(["synthesize", str(path), "--out", str(tmp_path / "run"), "--workers", "1",
                 "--fea-model", "2d",
                 "--finalists", "2", "--verify-top", "1"])
    report = json.loads((tmp_path / "run" / "synthesis.json").read_text())
    assert code == 0, report["winner_status"]
    fea = report["fea"][str(report["winner"]["cid"])]
    assert fea["ok"]
    winner = report["winner"]
    full = next(f for f in report["finalists_full_design"] if f["cid"] == winner["cid"])
    # screening predicted the full design's peak, and the FEA finds it within the stress
    # model's calibration error (5.5 % over its FEA cases; 10 % allowed on this coarse mesh)
    assert winner["peak_stress_MPa"] == pytest.approx(full["peak_stress_MPa"], rel=0.01)
    for s in fea["springs"].values():
        assert s["stiffness_fea_Nm_per_rad"] == pytest.approx(150.0, rel=0.01)
        assert s["yield_margin"] >= 1.0
        assert s["peak_region"] in ("root fillet", "flexure flank")
        assert s["peak_von_mises_MPa"] == pytest.approx(full["peak_stress_MPa"], rel=0.10)
    job = load_job(tmp_path / "run" / "winner.toml")
    assert job.material.material.name == "maraging_300"
    assert all(s.flexure == "straight" for s in job.springs.values())
