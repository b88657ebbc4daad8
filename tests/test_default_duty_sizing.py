"""A job without ``[duty]`` is sized for springcad's default duty when its envelope can
carry it, and for the yield margin alone (the duty then gating the release) when not."""

import re
from dataclasses import replace

from springcad.config import job_from_dict
from springcad.config.specs import DEFAULT_DUTY_PRESET
from springcad.design import duty
from springcad.design.job import design_job


def _job(thickness_mm, duty_table=None):
    data = {"job": {"name": "default_duty", "description": "one 420 disk, no duty table"},
            "material": {"name": "420_ht"},
            "springs": {"A": {"stiffness_Nm_per_rad": 100, "max_deflection_deg": 10,
                              "outer_radius_mm": 30.0, "thickness_mm": thickness_mm}},
            "manufacturing": {"process": "wire_edm"}}
    if duty_table:
        data["duty"] = duty_table
    return job_from_dict(data)


def test_an_envelope_that_carries_the_default_duty_is_sized_for_it():
    job = _job(9.0)
    assert not job.material.duty.declared and job.material.duty.preset == DEFAULT_DUTY_PRESET
    s = design_job(job, explain=False).springs["A"]
    assert "sized for springcad's default duty" in s.design_choice
    assert not s.material.duty.declared  # reported as springcad's default, not the user's
    check = s.duty_check
    assert check.met and check.safety_factor >= check.required_safety_factor
    sized = replace(s.material, duty=replace(s.material.duty, declared=True))
    assert s.yield_margin >= duty.required_margin(sized, s.max_deflection_rad) * (1 - 1e-3)
    # the FEA stress correction holds it to the same duty (fea.verify reads sizing_margin)
    assert s.sized_for_default_duty
    assert s.sizing_margin == duty.required_margin(sized, s.max_deflection_rad)
    assert s.sizing_margin > s.required_yield_margin == s.material.safety_factor


def test_an_envelope_that_cannot_is_sized_for_yield_and_fails_the_duty():
    plain = design_job(_job(7.0), explain=False).springs["A"]
    static = design_job(_job(7.0, {"preset": "static"}), explain=False).springs["A"]
    assert "default duty" not in plain.design_choice
    # the same spring as a job that asks for no fatigue life at all
    assert (plain.n_flexures, plain.contact_radius_mm) == (static.n_flexures,
                                                           static.contact_radius_mm)
    assert plain.yield_margin == static.yield_margin
    assert not plain.duty_check.met and static.duty_check.met
    assert plain.duty_advice == ""  # the advice is only searched with explain
    assert not plain.sized_for_default_duty
    assert plain.sizing_margin == plain.required_yield_margin  # yield alone


def test_a_spring_sized_for_yield_names_what_keeps_the_duty_out_of_reach():
    """The choice says why the default duty's search found no design: the best of its
    layouts and its predicted peak against the peak the duty allows (the closed-form S-N,
    Goodman and Miner bound of :func:`duty.allowed_peak_MPa`)."""
    plain = design_job(_job(7.0), explain=False).springs["A"]
    found = re.search(r"sized for the yield margin alone: .*predicted peak of (\d+) MPa at the "
                      r"[a-z -]+, above the (\d+) MPa allowed", plain.design_choice)
    assert found, plain.design_choice
    peak, allowed = int(found.group(1)), int(found.group(2))
    sized = replace(plain.material, duty=replace(plain.material.duty, declared=True))
    assert allowed == round(duty.allowed_peak_MPa(sized, plain.max_deflection_rad))
    assert peak > allowed
    carried = design_job(_job(9.0), explain=False).springs["A"]
    assert "sized for the yield margin alone" not in carried.design_choice
