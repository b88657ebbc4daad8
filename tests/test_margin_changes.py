"""When the FEA's stress correction finds no redesign in the envelope that keeps the yield
margin at the peak it measured, it names the change of the user's keys that would, and that
change designs with the margin at that peak (held-out B 016: FEA peak 1.16 x the prediction,
yield margin 1.923 < 2, and the build named no change)."""

import math
import re
from dataclasses import replace

import pytest

from springcad.config import job_from_dict
from springcad.design import duty
from springcad.design.job import design_job
from springcad.design.redesign import redesign_for_margin
from springcad.design.search import design_spring
from springcad.errors import DesignError


def test_a_margin_no_redesign_meets_names_a_change_that_does():
    job = job_from_dict({
        "job": {"name": "b016"}, "material": {"name": "420_ht", "safety_factor": 2.0},
        "springs": {"S1": {"target_stiffness_Nm_per_rad": 20, "max_deflection_deg": 14.0,
                           "outer_radius_mm": 22.0, "thickness_mm": 12.0}},
        "stack": {"sequence": ["S1"], "input": "shaft"},
        "hardware": {"fastener": "bolt", "fastener_diameter_mm": 2.0, "fastener_count": 3},
        "duty": {"preset": "static"}})
    d = design_job(job, explain=False).springs["S1"]
    bias = 1.6 * d.yield_margin / 2.0  # an FEA peak no layout at this size absorbs
    with pytest.raises(DesignError, match="with that peak the spring is") as err:
        redesign_for_margin(d, bias)
    text = str(err.value).split("with that peak the spring is", 1)[1]
    named = re.search(r"springs\.S1\.(\w+) = ([\d.]+) \(now", text)
    assert named, text
    key, value = named.group(1), float(named.group(2))
    spec = job.springs["S1"]
    changed = {"thickness_mm": lambda v: replace(spec, thickness_mm=v),
               "outer_radius_mm": lambda v: replace(spec, outer_radius_mm=v),
               "max_deflection_deg": lambda v: replace(spec, max_deflection_rad=math.radians(v)),
               "target_stiffness_Nm_per_rad": lambda v: replace(
                   spec, target_stiffness_Nmm_per_rad=1000 * v)}[key](value)
    biased = duty.biased(job.material, bias)
    new = design_spring(changed, biased, job.manufacturing, job.hardware, explain=False)
    assert new.yield_margin >= duty.required_margin(biased, new.max_deflection_rad) * (1 - 1e-3)
