"""``springcad verify`` in-process: outputs, exit status, bad input."""

from __future__ import annotations

import json

import pytest

from fea_helpers import TEMPLATES


@pytest.fixture(scope="module")
def s2_out(tmp_path_factory):
    from springcad.cli import main

    out = tmp_path_factory.mktemp("verify") / "S2"
    code = main(["verify", str(TEMPLATES / "paper_S2.toml"), "--out", str(out), "--quiet"])
    return code, out


def test_verify_writes_fea_json_vtu_and_png(s2_out):
    code, out = s2_out
    assert code == 0
    doc = json.loads((out / "fea.json").read_text())
    s = doc["springs"]["S2"]
    for key in ("stiffness_fea_Nm_per_rad", "stiffness_beam_Nm_per_rad",
                "target_stiffness_Nm_per_rad", "error_vs_target_pct", "discretisation_error_pct",
                "peak_von_mises_MPa", "peak_location_mm", "yield_margin", "dofs", "n_elements",
                "mesh_quality", "convergence", "correction_iterations", "timings_s"):
        assert key in s, key
    assert abs(s["error_vs_target_pct"]) <= 1.0
    assert {"mesh", "assemble", "solve"} <= set(s["timings_s"])
    assert len(s["convergence"]) >= 3
    assert doc["stack"]["sequence"] == ["S2"] and doc["ok"] is True
    for name in ("S2_sector_2d.vtu", "S2_sector_3d.vtu", "S2_von_mises.png",
                 "S2_von_mises_peak.png"):
        assert (out / name).stat().st_size > 1000, name


def test_vtu_reads_back(s2_out):
    import pyvista as pv

    _, out = s2_out
    grid = pv.read(out / "S2_sector_3d.vtu")
    assert {"displacement_mm", "von_mises_MPa"} <= set(grid.point_data)
    doc = json.loads((out / "fea.json").read_text())["springs"]["S2"]
    # the mirrored full-thickness sector has the CAD volume
    assert grid.volume == pytest.approx(doc["mesh_quality"]["cad_volume_mm3"], rel=1e-4)


def test_existing_output_is_not_overwritten(s2_out, capsys):
    from springcad.cli import main

    _, out = s2_out
    code = main(["verify", str(TEMPLATES / "paper_S2.toml"), "--out", str(out), "--quiet",
                 "--no-render", "--model", "2d"])
    assert code == 2
    assert "already exists" in capsys.readouterr().err


def test_missing_material_data_gives_no_result_file(tmp_path, capsys):
    from springcad.cli import main

    cfg = tmp_path / "bad.toml"
    cfg.write_text((TEMPLATES / "paper_S2.toml").read_text().replace(
        'name = "420_ht"', 'name = "mystery_steel"'))
    out = tmp_path / "out"
    assert main(["verify", str(cfg), "--out", str(out), "--quiet"]) == 2
    assert "mystery_steel" in capsys.readouterr().err
    assert not out.exists()
