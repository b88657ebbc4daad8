"""Every template, verified as `springcad build` verifies it: a template the release gate
passes meets the contact rules at +-theta_max, checked from the fea.json document with
an independent reading (the Hertz closed form with the textbook 0.557 p0, the clearances
against the job's own tolerances), and a template that breaks them is refused for it.

The gate is asked without the geometry checks (they can only add reasons), so the
templates it passes include every one that builds RELEASED. Springs shared between
templates are verified once.
"""

from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest

from fea_helpers import TEMPLATES

#: the job templates (the others are a title block and synthesis requirements)
NAMES = sorted(p.stem for p in TEMPLATES.glob("*.toml")
               if "springs" in tomllib.loads(p.read_text()))


def _c_vm(nu: float) -> float:
    """Largest von Mises / p0 on the load axis of a line contact (Johnson eq. 4.49, plane
    strain), on a fine depth grid: 0.557 for nu = 0.3, 0.566 for 0.28."""
    z = np.linspace(0.0, 2.0, 200001)
    r = np.sqrt(1 + z * z)
    sx, sz = -((1 + 2 * z * z) / r - 2 * z), -1 / r
    sy = nu * (sx + sz)
    return float(np.max(np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))))


@pytest.fixture(scope="module")
def verified():
    return {}


def _independent_violations(doc: dict, job_design) -> list[str]:
    """The contact rules read from fea.json and recomputed here."""
    out = []
    for name, s in doc["springs"].items():
        d = job_design.springs[name]
        mat = d.material.material
        at = s["contact_sweep"]["at_max_deflection"]
        m = d.manufacturing
        assert at["t_spring_mm"] == m.t_spring_mm and at["t_shaft_mm"] == m.t_shaft_mm
        for key, end in at["ends"].items():
            c = end["contact"]
            if not c:
                out.append(f"{name} {key}: no contact")
                continue
            k = 1 / c["ball_radius_mm"] + (0 if math.isinf(c["flank_radius_mm"])
                                           else 1 / c["flank_radius_mm"])
            e_star = mat.youngs_modulus_MPa / (2 * (1 - mat.poisson_ratio ** 2))
            p0 = math.sqrt(c["force_N"] / d.thickness_mm * e_star * k / math.pi)
            assert c["p0_MPa"] == pytest.approx(p0, rel=1e-6)
            assert c["von_mises_MPa"] == pytest.approx(_c_vm(mat.poisson_ratio) * p0, rel=1e-6)
            if mat.yield_strength_MPa / c["von_mises_MPa"] < d.material.safety_factor:
                out.append(f"{name} {key}: contact von Mises {c['von_mises_MPa']:.0f} MPa")
            for gap, g in end["clearances"].items():
                # the pocket's driving half is cut with the driving flank: its gap to the ball
                # is between the contact pair's own surfaces, no independent stack
                stack = (2 * m.t_spring_mm if gap == "neighbour_flexure"
                         else 0.0 if gap == "driving_pocket/ball"
                         else m.t_spring_mm + m.t_shaft_mm)
                assert g["stack_mm"] == pytest.approx(stack)
                if g["nominal_mm"] <= stack or g["worst_case_mm"] <= 0:
                    out.append(f"{name} {key}: {gap} {1000 * g['nominal_mm']:.1f} um")
    return out


@pytest.mark.slow
@pytest.mark.parametrize("template", NAMES)
def test_released_templates_meet_the_contact_rules(template, verified):
    from fea.study import VerifyOptions
    from fea.verdict import JobVerification, verify_stack
    from fea.verify import verify_spring
    from springcad.config import load_job
    from springcad.design.job import design_job
    from springcad.export.release import release_status

    job = design_job(load_job(TEMPLATES / f"{template}.toml"))
    options = VerifyOptions(keep_fields=False)  # build's: 2d3d with the contact sweep
    springs = {}
    for name, d in job.springs.items():
        key = json.dumps([d.to_dict(), repr(d.manufacturing)], sort_keys=True, default=str)
        if key not in verified:
            verified[key] = verify_spring(d, options)
        springs[name] = verified[key]
    stack = verify_stack(job.stack.sequence, springs, job.job.material.safety_factor)
    ver = JobVerification(job.job.name, springs, stack, options, {})
    status = release_status(ver.corrected_job_design(job), ver)
    doc = json.loads(json.dumps(ver.to_dict()))  # what fea.json holds
    violations = _independent_violations(doc, job)
    contact_reasons = [r for r in status.reasons if r.startswith("contact at full deflection")]
    if status.released:
        assert not violations
    assert bool(violations) == bool(contact_reasons), (violations, contact_reasons)
    assert len(doc["release_failures"]) == len(contact_reasons)
