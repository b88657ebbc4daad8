"""The public API (springcad.api): light import, SI results, short reprs, notebook views."""

from __future__ import annotations

import base64
import re
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import springcad as sc
from springcad.config import read_toml
from springcad.errors import ConfigError, DataError

ROOT = Path(__file__).resolve().parents[1]
S1 = ROOT / "templates" / "paper_S1.toml"


@pytest.fixture(scope="module")
def s1():
    return sc.design_job(S1)


def test_import_is_light():
    code = ("import sys, springcad; heavy = [m for m in sys.modules if m.split('.')[0] in "
            "('numpy', 'scipy', 'skfem', 'build123d', 'OCP', 'pyvista', 'matplotlib', 'gmsh')]; "
            "print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert out.stdout.strip() == "[]"
    assert set(sc.__all__) >= {"load", "design_job", "verify", "simulate", "fit_record"}



def test_design_imports_no_scipy_or_cad(tmp_path):
    """Designing a job (cold result cache) needs numpy only: scipy alone costs ~0.5 s of
    ``springcad design``'s CPU to import (the contour check's close pairs are numpy's)."""
    code = (f"import sys, springcad as sc; sc.design_job({str(S1)!r}); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'scipy', 'skfem', "
            "'build123d', 'OCP', 'pyvista', 'matplotlib', 'gmsh'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin",
                              "SPRINGCAD_CACHE_DIR": str(tmp_path)})
    assert out.stdout.strip() == "[]"
    assert any(tmp_path.iterdir())   # the design was computed and stored, not read

def test_load_dict_equals_load_file():
    from_file = sc.load(S1)
    from_dict = sc.load(read_toml(S1))
    assert sc.design_job(from_dict).stack.stiffness_Nm_per_rad == pytest.approx(
        sc.design_job(from_file).stack.stiffness_Nm_per_rad, rel=1e-12)


def test_bad_inputs_get_domain_errors(s1):
    with pytest.raises(ConfigError, match="TOML path or a dict"):
        sc.load(42)
    with pytest.raises(DataError, match="positive stiffness"):
        sc.simulate(-3.0)
    with pytest.raises(ConfigError, match="model"):
        sc.verify(s1, model="4d")
    with pytest.raises(DataError, match="simulate"):
        sc.simulate(100.0, not_an_effect=1)


def test_results_are_si_and_match_design_json(s1):
    doc = s1.to_dict()
    sp = s1.springs["S1"]
    assert sp.stiffness_Nm_per_rad == pytest.approx(doc["springs"]["S1"]["stiffness_Nm_per_rad"])
    # the paper's S1 is a 150 N*m/rad spring: N*mm would be 1000x
    assert sp.target_stiffness_Nm_per_rad == pytest.approx(150.0)
    assert s1.stack.stiffness_Nm_per_rad == pytest.approx(doc["stack"]["stiffness_Nm_per_rad"])
    assert s1.stack.max_deflection_rad == pytest.approx(doc["stack"]["max_deflection_rad"])
    assert sp.mass_kg == pytest.approx(doc["springs"]["S1"]["mass_kg"])


def test_reprs_are_short(s1):
    for obj in (s1, s1.springs["S1"], s1.stack, s1.raw, s1.raw.springs["S1"], s1.raw.stack):
        text = repr(obj)
        assert len(text) < 400, (type(obj).__name__, len(text))
    assert "N*m/rad" in repr(s1.springs["S1"])


def test_spring_svg_is_the_profile(s1):
    sp = s1.springs["S1"]
    svg = sp._repr_svg_()
    coords = np.array([[float(a), float(b)] for a, b in
                       re.findall(r"[ML](-?[\d.]+),(-?[\d.]+)", svg)])
    radii = np.hypot(coords[:, 0], coords[:, 1])
    # the outer rim is a circle of the design's outer radius; the cam is inside the flexure tips
    assert radii.max() == pytest.approx(sp.outer_radius_mm, rel=2e-3)
    assert radii.min() < sp.raw.contact_radius_mm
    html = s1._repr_html_()
    assert "<svg" in html and "stack" in html and "N·m/rad" in html


def test_simulate_then_fit_recovers_the_truth():
    rec = sc.simulate(120.0, backlash_rad=0.01, seed=3)
    f = sc.fit_record(rec)
    assert f.stiffness_Nm_per_rad == pytest.approx(120.0, rel=0.02)
    assert f.backlash_rad == pytest.approx(0.01, abs=0.002)
    assert len(repr(f)) < 400 and len(repr(f.raw.loop)) < 200
    png = re.search(r"base64,([A-Za-z0-9+/=]+)", f._repr_html_()).group(1)
    assert base64.b64decode(png)[:8] == b"\x89PNG\r\n\x1a\n"


def test_notebook_example_runs_the_whole_flow(tmp_path, monkeypatch):
    """examples/notebook_flow.py: load, design, 2D FEA, build, export, simulate, fit; API only."""
    import json

    out = tmp_path / "S1"
    monkeypatch.setattr(sys, "argv", ["notebook_flow.py", str(out)])
    ns = runpy.run_path(str(ROOT / "examples" / "notebook_flow.py"), run_name="__main__")
    v, built, result = ns["verification"], ns["built"], ns["result"]
    assert v.ok
    k_fea = v.stack_stiffness_Nm_per_rad
    assert k_fea == pytest.approx(150.0, rel=0.01)  # corrected to the target within 1 %
    assert result.stiffness_Nm_per_rad == pytest.approx(k_fea, rel=0.02)
    assert "<table>" in v._repr_html_() and len(repr(v)) < 400 and len(repr(v.raw)) < 600
    # the export is the same folder the CLI writes: build.json lists what is on disk
    assert built.out_dir == out and built.report_html.is_file() and built.ok
    doc = json.loads((out / "build.json").read_text())
    on_disk = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()} - {"build.json"}
    assert on_disk == {f["path"] for f in doc["files"]}
    # the corrected (FEA) widths were built: design.json holds the verified design
    saved = json.loads((out / "design.json").read_text())
    assert saved["springs"]["S1"]["stiffness_Nm_per_rad"] == pytest.approx(
        v.design.springs["S1"].stiffness_Nm_per_rad, rel=1e-9)
    assert doc["verification"]["ok"] is True
    assert doc["verification"]["springs"]["S1"]["stiffness_fea_Nm_per_rad"] == pytest.approx(k_fea)
    assert len(repr(built)) < 400 and "FEA" in repr(built) and "<table>" in built._repr_html_()
    source = (ROOT / "examples" / "notebook_flow.py").read_text()
    assert "springcad.cli" not in source and "import springcad as sc" in source
    for call in ("sc.load(", "sc.design_job(", "sc.verify(", "sc.build(", "sc.export_build(",
                 "sc.simulate(", "sc.fit_record("):
        assert call in source


def test_stack_svg_shows_the_sequence_and_the_limit():
    d = sc.design_job(ROOT / "templates" / "paper_S1_2xS2.toml")
    svg = d.stack._repr_svg_()
    st = d.stack
    names = re.findall(r"font-weight='bold'>([^<]+)</text>", svg)
    assert names == list(st.sequence) == ["S1", "S2", "S2"]
    # the limiting spring's boxes are the thick red ones; the others are not
    thick = re.findall(r"stroke='#b8322a' stroke-width='3'", svg)
    assert len(thick) == sum(n == st.limiting_spring for n in st.sequence) == 2
    for n in ("S1", "S2"):
        sp = d.springs[n]
        assert f"{sp.stiffness_Nm_per_rad:.4g} N·m/rad" in svg
        assert f"θmax {sp.max_deflection_rad:.3g} rad" in svg
    assert f"limit {st.max_deflection_rad:.4g} rad" in svg and "<svg" in st._repr_html_()


def test_export_refuses_what_build_did_not_make(tmp_path):
    with pytest.raises(ConfigError, match="Build"):
        sc.export_build("not a build", tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_api_never_imports_the_cli():
    import ast

    for path in (ROOT / "springcad" / "api").glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(m.startswith("springcad.cli") for m in mods), path.name


def test_public_names_survive_importing_every_subpackage():
    """A subpackage import rebinds its name on ``springcad``: no public function may share one."""
    import importlib
    import pkgutil

    import springcad

    for mod in pkgutil.iter_modules(springcad.__path__):
        if mod.name != "__main__":  # running it is the CLI
            importlib.import_module(f"springcad.{mod.name}")
    for name in ("load", "design_job", "verify", "build", "export_build", "simulate", "fit_record"):
        assert callable(getattr(springcad, name)) and name in springcad.__all__, name
        assert getattr(springcad, name).__module__.startswith("springcad.api"), name
