"""A refusal in a job whose own tolerances jam at the cam names the tolerances a release
needs too (issue 21: the paper's S1 with a 1e7-cycle duty was stopped with a disk that meets
the duty, which then built NOT FOR MANUFACTURE on the paper's t_spring 0.05, t_shaft 0.02,
w_gap 0.025; at the tolerances named here it builds RELEASED, measured with
``springcad build``)."""

import pytest

from springcad.config import ManufacturingSpec, job_from_dict
from springcad.design import job as job_module
from springcad.design.job import design_job, jamming_tolerances
from springcad.design.tolerance import gap_range_mm
from springcad.errors import DesignError, SpecInfeasible


def _job(**manufacturing):
    return job_from_dict({
        "job": {"name": "tolerances", "description": "one disk"},
        "material": {"name": "420_ht"},
        "springs": {"A": {"stiffness_Nm_per_rad": 100, "max_deflection_deg": 10,
                          "outer_radius_mm": 30.0, "thickness_mm": 6.0}},
        "manufacturing": {"process": "wire_edm", **manufacturing}})


def test_jamming_tolerances_name_a_change_that_cannot_jam():
    paper = ManufacturingSpec(t_spring_mm=0.05, t_shaft_mm=0.02, w_gap_mm=0.025)
    text = jamming_tolerances(paper)
    assert "now 0.025 < 0.07 mm" in text
    ours = ManufacturingSpec()
    assert (f"manufacturing.t_spring_mm = {ours.t_spring_mm:g}, manufacturing.t_shaft_mm = "
            f"{ours.t_shaft_mm:g} and manufacturing.w_gap_mm = {ours.w_gap_mm:g}") in text
    # the named change itself cannot jam: its worst-case gap d = 2 (w - t_s - t_sh) > 0
    assert gap_range_mm(ours.w_gap_mm, ours.t_spring_mm, ours.t_shaft_mm)[0] > 0
    # tolerances whose worst case does not jam add nothing, even tight ones at the limit
    assert jamming_tolerances(ours) == ""
    assert jamming_tolerances(ManufacturingSpec(t_spring_mm=0.02, t_shaft_mm=0.02,
                                                w_gap_mm=0.04)) == ""


@pytest.mark.parametrize("error", [DesignError, SpecInfeasible])
def test_a_refusal_carries_the_advice_and_keeps_its_kind(monkeypatch, error):
    def refuse(spec, *args, **kwargs):
        raise error(f"spring '{spec.name}' cannot be made as specified; thicker")

    monkeypatch.setattr(job_module, "design_spring", refuse)
    with pytest.raises(error) as paper:
        design_job(_job(t_spring_mm=0.05, t_shaft_mm=0.02, w_gap_mm=0.025))
    assert str(paper.value).startswith("spring 'A' cannot be made as specified; thicker; and "
                                       "for a release the cam interfaces need")
    with pytest.raises(error) as ours:
        design_job(_job())
    assert str(ours.value) == "spring 'A' cannot be made as specified; thicker"
    with pytest.raises(error) as quiet:  # a yes/no search (synthesis) is not explained
        design_job(_job(t_spring_mm=0.05, t_shaft_mm=0.02, w_gap_mm=0.025), explain=False)
    assert "w_gap_mm" not in str(quiet.value)
