"""A job with several springs that cannot be made names every one of them in one refusal,
each with its own change (a held-out stack A + B + B was refused naming only A's change;
applied, the job was then refused for B), and the job-wide advice once."""

import pytest

from springcad.config import job_from_dict
from springcad.design import job as job_module
from springcad.design.job import design_job
from springcad.design.stock import design_spring
from springcad.errors import DesignError, SpecInfeasible

PAPER_TOLERANCES = {"process": "wire_edm", "t_spring_mm": 0.05, "t_shaft_mm": 0.02,
                    "w_gap_mm": 0.025}


def _job(manufacturing=None):
    spring = {"target_stiffness_Nm_per_rad": 100, "max_deflection_deg": 10,
              "outer_radius_mm": 30.0, "thickness_mm": 6.0}
    return job_from_dict({
        "job": {"name": "two", "description": "two designs"},
        "material": {"name": "420_ht"},
        "springs": {"A": spring, "B": dict(spring, outer_radius_mm=31.0),
                    "C": dict(spring, outer_radius_mm=32.0)},
        "stack": {"sequence": ["A", "B", "C"], "input": "shaft"},
        **({"manufacturing": manufacturing} if manufacturing else {})})


def _refusing(names, error=DesignError):
    def design(spec, *args, **kwargs):
        if spec.name in names:
            raise error(f"spring '{spec.name}' cannot be made as specified; "
                        f"springs.{spec.name}.outer_radius_mm = {spec.outer_radius_mm + 5:g}")
        return design_spring(spec, *args, **kwargs)
    return design


@pytest.mark.parametrize("error", [DesignError, SpecInfeasible])
def test_every_refused_spring_is_named_with_its_change(monkeypatch, error):
    monkeypatch.setattr(job_module, "design_spring", _refusing({"A", "C"}, error))
    monkeypatch.setattr(job_module, "fewer_disks", lambda *a: None)
    with pytest.raises(error) as refused:
        design_job(_job(manufacturing=PAPER_TOLERANCES))
    text = str(refused.value)
    assert text.startswith("2 springs cannot be made as specified: spring 'A'")
    assert "springs.A.outer_radius_mm = 35" in text and "springs.C.outer_radius_mm = 37" in text
    assert "'B'" not in text
    assert text.count("for a release the cam interfaces need") == 1


def test_a_yes_no_search_stops_at_the_first_refusal(monkeypatch):
    calls = []

    def design(spec, *args, **kwargs):
        calls.append(spec.name)
        raise DesignError(f"spring '{spec.name}' cannot be made as specified")

    monkeypatch.setattr(job_module, "design_spring", design)
    with pytest.raises(DesignError, match="^spring 'A' cannot be made as specified$"):
        design_job(_job(), explain=False)
    assert calls == ["A"]
