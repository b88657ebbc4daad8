"""Total Lagrangian St Venant-Kirchhoff forms (fea.nonlinear) against the linear forms and
exact kinematic identities."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="module")
def sector(straight, material):
    from fea.geometry import sector_geometry
    from fea.mesh import fea_mesh_2d, mesh_face_levels
    from fea.problem import LoadCase, assemble
    from fea.mesh_size import DEFAULT_SIZE

    g = sector_geometry(straight)
    fm = fea_mesh_2d(mesh_face_levels(g, DEFAULT_SIZE, 1)[0], g, 0)
    return fm, assemble(fm, material, LoadCase())


def _rigid_rotation(X, angle):
    u = np.zeros(2 * X.shape[1])
    c, s = np.cos(angle), np.sin(angle)
    u[0::2] = (c - 1) * X[0] - s * X[1]
    u[1::2] = s * X[0] + (c - 1) * X[1]
    return u


def test_tangent_at_rest_is_the_linear_stiffness(sector):
    from fea.nonlinear import internal_force

    fm, s = sector
    f, K = internal_force(s.basis, np.zeros(s.A.shape[0]), s.lam, s.mu, fm.thickness_mm)
    assert np.abs(f).max() == 0.0
    assert abs(K - s.A).max() <= 1e-12 * abs(s.A).max()


def test_tangent_is_the_derivative_of_the_internal_force(sector):
    from fea.nonlinear import internal_force

    fm, s = sector
    rng = np.random.default_rng(3)
    u = 0.01 * rng.normal(size=s.A.shape[0])
    du = 1e-6 * rng.normal(size=u.size)
    _, K = internal_force(s.basis, u, s.lam, s.mu, fm.thickness_mm)
    fp, _ = internal_force(s.basis, u + du, s.lam, s.mu, fm.thickness_mm, tangent=False)
    fm_, _ = internal_force(s.basis, u - du, s.lam, s.mu, fm.thickness_mm, tangent=False)
    fd = 0.5 * (fp - fm_)
    assert np.linalg.norm(fd - K @ du) <= 1e-6 * np.linalg.norm(K @ du)


def test_small_displacement_is_linear(sector):
    from fea.nonlinear import internal_force

    fm, s = sector
    u = 1e-7 * np.random.default_rng(4).normal(size=s.A.shape[0])
    f, _ = internal_force(s.basis, u, s.lam, s.mu, fm.thickness_mm, tangent=False)
    lin = s.A @ u
    assert np.linalg.norm(f - lin) <= 1e-5 * np.linalg.norm(lin)


def test_rigid_rotation_is_stress_free(sector):
    """A 0.3 rad rigid rotation: no internal force and no Green-Lagrange stress, where the
    linear strain sees ~omega^2 / 2 of fake strain."""
    from fea.nonlinear import internal_force, nodal_von_mises_green
    from fea.results import nodal_von_mises

    fm, s = sector
    u = _rigid_rotation(s.basis.doflocs, 0.3)
    f, _ = internal_force(s.basis, u, s.lam, s.mu, fm.thickness_mm, tangent=False)
    assert np.abs(f).max() <= 1e-9 * np.abs(s.A @ u).max()
    assert nodal_von_mises_green(s, u).max() < 1e-6
    assert nodal_von_mises(s, u)[0].max() > 1000.0  # what linear kinematics would report
