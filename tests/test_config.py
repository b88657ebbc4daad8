"""Config validation: every bad input gets one clear message, exit 2 and nothing written."""

import math
import tomllib

import pytest

from springcad.cli import main
from springcad.config import job_from_dict, load_job
from springcad.errors import ConfigError
from tests.conftest import template
from tests.geometry.cad_fixtures import toml_text


def paper_s1():
    return tomllib.loads(template("paper_S1").read_text())


def write(tmp_path, data):
    path = tmp_path / "job.toml"
    path.write_text(toml_text(data))
    return path


BAD = {
    "negative stiffness": (lambda d: d["springs"]["S1"].update(target_stiffness_Nm_per_rad=-150),
                           r"springs\.S1\.target_stiffness_Nm_per_rad.*-150.*from 0\.001 to 100000 N\*m/rad"),
    "zero stiffness": (lambda d: d["springs"]["S1"].update(target_stiffness_Nm_per_rad=0),
                       r"springs\.S1\.target_stiffness_Nm_per_rad.* = 0: .*from 0\.001 to"),
    "unreachable deflection": (lambda d: d["springs"]["S1"].update(max_deflection_deg=89),
                               r"S1.*(no flexure geometry|no curved flexure).*series"),
    "tip below wire": (lambda d: d["springs"]["S1"].update(tip_radius_mm=0.1),
                       r"tip_radius_mm.*0\.1.*wire radius \+ spark gap = 0\.15"),
    "too many flexures": (lambda d: d["springs"]["S1"].update(n_flexures=40),
                          r"n_flexures = 40 do not fit.*at most 28"),
    "empty stack": (lambda d: d["stack"].update(sequence=[]),
                    r"stack\.sequence.*at least one spring.*S1"),
    "unknown spring": (lambda d: d["stack"].update(sequence=["S1", "S9"]),
                       r"stack\.sequence.*'S9'.*not a defined spring; defined: S1"),
    "wrong units": (lambda d: d["springs"]["S1"].update(outer_radius_in=1.3),
                    r"springs\.S1\.outer_radius_in.*not a known key.*outer_radius_mm"),
    "deg and rad": (lambda d: d["springs"]["S1"].update(max_deflection_rad=0.3),
                    r"either max_deflection_deg or max_deflection_rad"),
    "bad output": (lambda d: d["stack"].update(output="shaft"),
                   r"stack\.output.*must be 'rim' for 1 spring"),
    "design stress above yield": (lambda d: d["material"].update(design_stress_MPa=1500),
                                  r"design_stress_MPa.*below the yield strength 1344"),
    "custom material incomplete": (lambda d: d["material"].update(name="unobtainium"),
                                   r"material\.name.*unobtainium.*needs youngs_modulus_GPa"),
    "not a number": (lambda d: d["springs"]["S1"].update(thickness_mm="thick"),
                     r"springs\.S1\.thickness_mm.*'thick'.*must be a number"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_config_message_exit_status_and_nothing_written(tmp_path, capsys, case):
    mutate, pattern = BAD[case]
    data = paper_s1()
    mutate(data)
    path = write(tmp_path, data)
    before = path.read_text()
    out = tmp_path / "out"
    assert main(["design", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err  # one clear line
    import re
    assert re.search(pattern, err), err
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out")]  # no temp leftovers
    assert path.read_text() == before  # input untouched


def test_units_are_converted_once():
    job = load_job(template("paper_S1"))
    s = job.springs["S1"]
    assert s.target_stiffness_Nmm_per_rad == 150_000
    assert s.max_deflection_rad == pytest.approx(math.radians(16))
    d = paper_s1()
    d["springs"]["S1"].pop("max_deflection_deg")
    d["springs"]["S1"]["max_deflection_rad"] = 0.25
    assert job_from_dict(d).springs["S1"].max_deflection_rad == 0.25


def test_material_defaults_and_overrides():
    d = paper_s1()
    job = job_from_dict(d)
    assert job.material.material.name == "420_ht"
    assert job.material.material.youngs_modulus_MPa == 200e3
    d["material"] = {"name": "420_ht", "youngs_modulus_GPa": 210, "safety_factor": 2.0}
    job = job_from_dict(d)
    assert job.material.material.youngs_modulus_MPa == 210e3
    assert job.material.design_stress_MPa == pytest.approx(1344 / 2.0)


def test_hardness_follows_the_heat_treatment():
    """The table's hardness goes with the table's heat treatment; a new treatment needs its own."""
    d = paper_s1()
    mat = job_from_dict(d).material.material
    assert (mat.hardness, mat.heat_treatment_sequence) == ("48-52 HRC", "before EDM")
    d["material"] = {"name": "420_ht", "heat_treatment": "tempered 500 C"}
    assert job_from_dict(d).material.material.hardness == ""
    d["material"]["hardness"] = "44-48 HRC"
    assert job_from_dict(d).material.material.hardness == "44-48 HRC"


def test_unreadable_file(tmp_path):
    with pytest.raises(ConfigError, match="cannot be read"):
        load_job(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[springs.S1\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_job(bad)


def _one_spring(spring: dict, hardware: dict | None = None) -> dict:
    base = {"target_stiffness_Nm_per_rad": 14, "max_deflection_deg": 13.5,
            "outer_radius_mm": 23.0, "thickness_mm": 6.0}
    return {"springs": {"A": {**base, **spring}}, "hardware": hardware or {}}


def test_the_default_bore_steps_below_a_fixed_contact_radius():
    """springcad's 4 mm camshaft bore does not fit a fixed 3.5 mm contact radius: with no
    shaft_diameter_mm given, springcad takes the largest 0.5 mm step at least 0.5 mm
    below it (3.0 mm); a bore the user gives is theirs and still refused; a contact
    radius with room keeps the default."""
    job = job_from_dict(_one_spring({"contact_radius_mm": 3.5}))
    assert job.hardware.shaft_diameter_mm == 3.0
    with pytest.raises(ConfigError, match="shaft_diameter_mm"):
        job_from_dict(_one_spring({"contact_radius_mm": 3.5}, {"shaft_diameter_mm": 4.0}))
    assert job_from_dict(_one_spring({"contact_radius_mm": 6.0})).hardware.shaft_diameter_mm \
        == 4.0


def test_a_fixed_root_radius_below_the_contact_search_bounds_the_search():
    """A root radius fixed at 20 mm on R_o 36 (below 0.6 R_o = 21.6, where springcad's
    contact-radius search ends) is accepted: the design searches contact radii below it,
    and every candidate layout keeps r_c under R_r."""
    from springcad.design.layout import candidate_layouts

    data = tomllib.loads(template("default").read_text())
    data["springs"]["S1"].update(root_radius_mm=20.0, thickness_mm=5.0)
    job = job_from_dict(data)
    spec = job.springs["S1"]
    layouts = candidate_layouts(spec, job.material.design_stress_MPa,
                                job.material.material.youngs_modulus_MPa)
    assert layouts and all(lay.rc < lay.rr == 20.0 for lay in layouts)
