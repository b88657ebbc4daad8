"""Ranking, the family report of an infeasible requirement, and Pareto fronts."""

import numpy as np
import pytest

from springcad.cli import main
from springcad.synthesis.candidates import CandidateSpace
from springcad.synthesis.evaluate import evaluate_batch
from springcad.synthesis.explore import pareto_front
from springcad.report.synthesis_text import format_family_report
from springcad.synthesis.ranking import distinct, family_report, rank
from springcad.synthesis.requirements import requirements_from_dict
from synth_fixtures import requirements_toml, small

#: 150 N*m/rad over +-60 deg in a 20 mm radius, 8 mm long: far beyond any stack
IMPOSSIBLE = small(requirement={"stiffness_Nm_per_rad": 150, "deflection_deg": 60},
                   envelope={"max_outer_radius_mm": 20.0, "max_axial_length_mm": 8.0},
                   search={"max_disks": 3, "mixed": False})


def _evaluate(data):
    req = requirements_from_dict(data)
    space = CandidateSpace.from_requirements(req)
    return req, evaluate_batch(space, 0, space.total)


def test_rank_is_by_objective_then_mass():
    req, cols = _evaluate(small())
    order = rank(cols, "mass_kg")
    m = cols["mass_kg"][order]
    assert len(order) == cols["feasible"].sum() > 0
    assert np.all(np.diff(m) >= 0)
    order_ax = rank(cols, "axial_length_mm")
    assert np.all(np.diff(cols["axial_length_mm"][order_ax]) >= 0)
    # mirrored/identical duplicates collapse to one stack
    tops = distinct(cols, order, 50)
    assert len(tops) <= len(order)
    assert len({(t["input"], t["thickness_a_mm"], t["family"]) for t in tops}) >= 1


def test_infeasible_requirement_names_binding_constraints_with_numbers():
    req, cols = _evaluate(IMPOSSIBLE)
    assert not cols["feasible"].any()
    report = family_report(cols, "mass_kg")
    assert [e["family"] for e in report] == ["1 disk", "2 identical", "3 identical"]
    for e in report:
        assert e["feasible"] == 0
        assert sum(b["candidates"] for b in e["binding"]) == e["candidates"]
    one = report[0]["binding"]
    # one disk would have to store 0.5 * 150 * (pi/3)^2 = 82 J in a 20 mm disk
    energy = next(b for b in one if b["constraint"] == "energy_bound")
    assert "stores 82.2 J" in energy["nearest_miss"]
    text = format_family_report(report, "mass_kg")
    assert "1 disk:      0 /" in text and "energy_bound" in text and "J" in text


def test_cli_reports_an_infeasible_requirement(tmp_path, capsys):
    path = tmp_path / "impossible.toml"
    path.write_text(requirements_toml(IMPOSSIBLE))
    code = main(["synthesize", str(path), "--out", str(tmp_path / "run"), "--workers", "1",
                 "--no-verify", "--batch-size", "500"])
    out = capsys.readouterr().out
    assert code == 1
    assert "no winner: no feasible stack" in out
    assert "energy_bound" in out and "nearest miss" in out
    assert not (tmp_path / "run" / "winner.toml").exists()
    assert (tmp_path / "run" / "synthesis.json").exists()


def test_bad_requirement_is_one_line_exit_2(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(requirements_toml(small(envelope={"max_axial_length_mm": -1})))
    assert main(["synthesize", str(path), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert "envelope.max_axial_length_mm" in err and "Traceback" not in err


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_pareto_front_against_brute_force(seed):
    rng = np.random.default_rng(seed)
    x, y = rng.random(200), rng.random(200)
    front = set(pareto_front(x, y, maximise_x=True, maximise_y=False).tolist())
    brute = {i for i in range(200)
             if not any((x[j] >= x[i] and y[j] <= y[i]) and (x[j] > x[i] or y[j] < y[i])
                        for j in range(200))}
    assert front == brute
