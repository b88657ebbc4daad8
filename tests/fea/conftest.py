"""Shared fixtures for the FEA tests: designed springs, reused across tests (session scope)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the worktree under test, whatever is pip-installed
    sys.path.insert(0, str(ROOT))

from fea_helpers import TEMPLATES  # noqa: E402, F401

#: a straight constant-stiffness flexure ring (N = 24, K = 150 N*m/rad): beam theory is exact
#: Euler-Bernoulli for its parabolic flexures, the closed form of check (a)
STRAIGHT = {
    "job": {"name": "straight"},
    "material": {"name": "420_ht", "design_stress_MPa": 912},
    "springs": {"F": {"stiffness_Nm_per_rad": 150, "max_deflection_deg": 8,
                      "outer_radius_mm": 33.5, "thickness_mm": 4.5, "contact_radius_mm": 5.5,
                      "n_flexures": 24, "flexure": "straight", "tip_radius_mm": 0.3}},
    # the contact tests judge 30 um profile tolerances against a 25 um designed gap
    "manufacturing": {"t_spring_mm": 0.03, "t_shaft_mm": 0.03, "w_gap_mm": 0.025},
}


def _design(path_or_dict):
    from springcad.config import job_from_dict, load_job
    from springcad.design.job import design_job

    job = job_from_dict(path_or_dict) if isinstance(path_or_dict, dict) else load_job(path_or_dict)
    return design_job(job, explain=False)  # the same springs without the duty advice search


@pytest.fixture(scope="session")
def s1_job():
    return _design(TEMPLATES / "paper_S1.toml")


@pytest.fixture(scope="session")
def s2_job():
    return _design(TEMPLATES / "paper_S2.toml")


@pytest.fixture(scope="session")
def s1(s1_job):
    return s1_job.springs["S1"]


@pytest.fixture(scope="session")
def s2(s2_job):
    return s2_job.springs["S2"]


@pytest.fixture(scope="session")
def straight():
    """The plain parabolic flexure (no root flare): the closed-form beam of check (a)."""
    from springcad.design.resize import with_root

    return with_root(_design(STRAIGHT).springs["F"], 0.0)


@pytest.fixture(scope="session")
def material(s1):
    from fea.problem import solver_material

    return solver_material(s1.material)


@pytest.fixture(scope="session")
def s1_faces(s1):
    """Nested quadratic triangle meshes of the S1 sector, levels 0-2."""
    from fea.geometry import sector_geometry
    from fea.mesh import mesh_face_levels
    from fea.mesh_size import DEFAULT_SIZE

    g = sector_geometry(s1)
    return g, mesh_face_levels(g, DEFAULT_SIZE, 3)
