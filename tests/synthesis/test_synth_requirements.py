"""Requirements schema: the templates load, bad values name key, value and what is allowed."""

import math

import pytest

from springcad.errors import ConfigError
from springcad.synthesis.requirements import load_requirements, requirements_from_dict
from synth_fixtures import TEMPLATES, small


@pytest.mark.parametrize("path", sorted(TEMPLATES.glob("requirements_*.toml")), ids=lambda p: p.stem)
def test_templates_load(path):
    req = load_requirements(path)
    assert req.target_stiffness_Nmm_per_rad > 0 and req.deflection_rad > 0
    for m in req.materials:
        assert req.design_stress_MPa(m) < m.yield_strength_MPa


def test_paper_template_reproduces_the_paper_design_stress():
    req = load_requirements(TEMPLATES / "requirements_4xS1.toml")
    assert req.target_stiffness_Nmm_per_rad == pytest.approx(37.5e3)
    assert req.deflection_rad == pytest.approx(4 * math.radians(16))  # 4 x S1's 16 deg
    assert req.design_stress_MPa(req.materials[0]) == pytest.approx(912.0, abs=0.05)


@pytest.mark.parametrize("section, key, value, match", [
    ("requirement", "stiffness_Nm_per_rad", -3, "requirement.stiffness_Nm_per_rad.*greater than zero"),
    ("envelope", "max_outer_radius_mm", 1.0, "envelope.max_outer_radius_mm.*at least 3"),
    ("materials", "names", ["unobtainium"], "materials.names.*built-in materials"),
    ("materials", "fatigue_margin", 0.01, "materials.fatigue_margin.*at least 0.05"),
    ("objective", "minimise", "energy_density", "objective.minimise.*one of mass"),
    ("search", "inputs", ["gear"], "search.inputs.*shaft, rim"),
    ("search", "thickness_mm", [], "search.thickness_mm.*non-empty list"),
    ("search", "max_disk", 3, "search.max_disk.*not a known key"),
    ("search", "tip_radius_mm", 0.1, "search.tip_radius_mm.*wire radius"),
    ("manufacturing", "w_gap_mm", -1, "manufacturing.w_gap_mm.*from 0.005 to 1 mm"),
])
def test_bad_values_name_the_key(section, key, value, match):
    with pytest.raises(ConfigError, match=match):
        requirements_from_dict(small(**{section: {key: value}}))


def test_design_stress_must_stay_below_yield():
    with pytest.raises(ConfigError, match="yield_margin.*must exceed 1"):
        requirements_from_dict(small(materials={"yield_margin": 1.0, "stress_concentration": 1.0}))


def test_fingerprint_changes_with_the_space_only():
    a = requirements_from_dict(small())
    b = requirements_from_dict(small(requirement={"description": "other words"}))
    c = requirements_from_dict(small(search={"thickness_mm": [3.0]}))
    assert a.fingerprint() == b.fingerprint() != c.fingerprint()


def test_fatigue_margin_is_a_peak_stress_limit():
    """S_e / peak >= fatigue_margin is peak <= S_e / fatigue_margin; the stricter of it and
    the yield margin sets the allowed peak and the winner's safety_factor."""
    # 420_ht polished limit x skim-cut EDM surface x 99 % reliability (Shigley Table 6-5)
    se = 700.0 * 0.70 * (1 - 0.08 * 2.3263478740408408)
    loose = requirements_from_dict(small(materials={"fatigue_margin": 0.25}))
    strict = requirements_from_dict(small(materials={"fatigue_margin": 0.4}))
    m = loose.materials[0]
    assert loose.endurance_limit_MPa(m) == pytest.approx(se, rel=1e-12)
    assert loose.allowed_peak_MPa(m) == pytest.approx(1344.0)  # yield / 1.0 governs
    assert not loose.fatigue_limited(m)
    assert strict.allowed_peak_MPa(m) == pytest.approx(se / 0.4, rel=1e-12)
    assert strict.fatigue_limited(m)
    assert strict.required_yield_margin(m) == pytest.approx(1344.0 * 0.4 / se, rel=1e-12)
    assert loose.fingerprint() != strict.fingerprint()


def test_fatigue_margin_needs_fatigue_data(monkeypatch):
    from springcad.design import fatigue

    monkeypatch.setattr(fatigue, "fatigue_table", lambda: {})
    with pytest.raises(ConfigError, match="fatigue_margin.*cannot be checked for 420_ht"):
        requirements_from_dict(small(materials={"fatigue_margin": 1.0}))


def test_fatigue_margin_objective():
    data = small()
    data["objective"] = {"maximise": "fatigue_margin"}
    req = requirements_from_dict(data)
    assert req.objective_column == "fatigue_margin" and not req.minimise
    data["objective"] = {"maximise": "mass"}
    with pytest.raises(ConfigError, match="objective.maximise.*one of energy_density, fatigue_margin"):
        requirements_from_dict(data)


def test_fixed_tip_balls_reach_the_winner_job():
    """search.tip_radius_mm becomes each spring's tip_radius_mm in the job a winner is built from."""
    from springcad.config import job_from_dict
    from springcad.synthesis.finalists import job_document

    req = load_requirements(TEMPLATES / "requirements_4xS1.toml")
    assert req.search.tip_radius_mm == 0.3
    cand = {"n_a": 4, "n_b": 0, "split": 1.0, "target_stiffness_Nm_per_rad": 37.5,
            "deflection_rad": req.deflection_rad, "material": req.materials[0].name,
            "outer_radius_mm": 33.5, "thickness_a_mm": 4.5, "contact_radius_mm": 5.5,
            "n_flexures_a": 28, "family": "4 identical", "cid": 1, "input": "rim"}
    job = job_from_dict(job_document(req, cand))
    assert job.springs["A"].tip_radius_mm == 0.3
    assert job.springs["A"].target_stiffness_Nmm_per_rad == pytest.approx(150e3)


def test_a_duty_in_the_requirements_is_a_peak_stress_limit_passed_to_the_winner():
    """A duty in fractions of theta_max allows one peak per material (the same for every
    disk): the synthesis ranks against it and the winner's job declares it."""
    from springcad.design import duty
    from springcad.synthesis.finalists import job_document

    req = requirements_from_dict(small(duty={"preset": "robot_joint"},
                                       manufacturing={"surface": "polished"}))
    m = req.materials[0]
    allowed = duty.check(req.duty, m.name, 1.0, 1.0).allowed_peak_MPa
    assert req.duty.surface == "polished" and req.duty.declared
    assert req.allowed_peak_MPa(m) == pytest.approx(min(allowed, 1344.0 / req.yield_margin))
    assert req.fatigue_limited(m)
    cand = {"n_a": 2, "n_b": 0, "split": 1.0, "target_stiffness_Nm_per_rad": 75.0,
            "deflection_rad": 0.5, "material": m.name, "outer_radius_mm": 30.0,
            "thickness_a_mm": 5.0, "n_flexures_a": 30, "contact_radius_mm": 6.0,
            "family": "2xA", "cid": 1, "input": "shaft"}
    doc = job_document(req, cand)
    assert doc["duty"] == {"preset": "robot_joint"}
    assert doc["manufacturing"]["surface"] == "polished"
    with pytest.raises(ConfigError, match="fractions of each disk's theta_max"):
        requirements_from_dict(small(duty={"blocks": [{"cycles": 1e6, "amplitude_deg": 5.0}]}))
