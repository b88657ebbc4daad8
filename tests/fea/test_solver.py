"""Assembly, loads, supports and checked solves."""

from __future__ import annotations

import math

import numpy as np
import pytest

from springcad.errors import SolverError


def test_vectorised_stiffness_equals_scikit_fem_forms(s1_faces, material):
    """The fast assembly is scikit-fem's linear elasticity form, entry for entry."""
    from skfem import Basis, CellBasis, ElementVector

    from fea.mesh import fea_mesh_2d, fea_mesh_3d
    from fea.problem import elasticity_form, lame, stiffness_matrix

    g, faces = s1_faces
    for fm in (fea_mesh_2d(faces[0], g), fea_mesh_3d(faces[0], g, 1)):
        lam, mu = lame(material, plane_stress=fm.dim == 2)
        sb = CellBasis(fm.mesh, fm.mesh.elem(), intorder=2)
        A = stiffness_matrix(sb, lam, mu)
        vb = Basis(fm.mesh, ElementVector(fm.mesh.elem()), intorder=2)
        # skfem numbers vector DOFs as (scalar DOF) * dim + component, as we do
        assert np.array_equal(vb.element_dofs[0::fm.dim], sb.element_dofs * fm.dim)
        B = elasticity_form(lam, mu).assemble(vb)
        assert abs(A - B).max() <= 1e-9 * abs(B).max()


def test_unit_torque_load_and_equilibrium(s1_faces, material):
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble
    from fea.solve import solve

    g, faces = s1_faces
    sys_ = assemble(fea_mesh_2d(faces[1], g), material, LoadCase())
    assert sys_.torque_Nmm == pytest.approx(1.0, rel=1e-12)
    # the patch pushes along the direction of rotation (-x at flexure 0's tip)
    fx, fy = sys_.f[0::2].sum(), sys_.f[1::2].sum()
    assert fx < 0 and abs(fy) < 1e-3 * abs(fx)
    u, info = solve(sys_)
    assert info.residual < 1e-14  # backward error of a stable direct solve: ~eps
    assert 1 < info.growth < 1e13
    assert info.equilibrium_error < 1e-8


def test_rigid_cam_agrees_with_traction_patch(s1_faces, s1, material):
    """Two cam models, same K: the smooth traction patch and a rigid flat cam pad."""
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase
    from fea.study import solve_mesh

    g, faces = s1_faces
    fm = fea_mesh_2d(faces[2], g, 2)
    k_t = solve_mesh(fm, material, LoadCase(load="traction"), s1.max_deflection_rad)
    k_c = solve_mesh(fm, material, LoadCase(load="rigid_cam"), s1.max_deflection_rad)
    assert k_c.stiffness_Nmm_per_rad / k_t.stiffness_Nmm_per_rad - 1 == pytest.approx(0, abs=2e-4)
    assert k_c.peak_von_mises_MPa == pytest.approx(k_t.peak_von_mises_MPa, rel=5e-3)


def test_patch_width_barely_moves_k(s1_faces, s1, material):
    """A centred smooth patch: K is insensitive to its width while it stays on the ball's
    face (15-30 deg: < 0.02 %); a 60 deg patch reaches the neck and moves K by ~0.4 %."""
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase
    from fea.study import solve_mesh

    g, faces = s1_faces
    fm = fea_mesh_2d(faces[2], g, 2)
    ks = [solve_mesh(fm, material, LoadCase(patch_half_angle_rad=math.radians(a)),
                     s1.max_deflection_rad).stiffness_Nmm_per_rad for a in (15, 30, 60)]
    assert abs(ks[0] / ks[1] - 1) < 2e-4
    assert abs(ks[2] / ks[1] - 1) < 1e-2


def test_unsupported_model_is_singular_error(s1_faces, material):
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble

    g, faces = s1_faces
    fm = fea_mesh_2d(faces[0], g)
    fm.boundaries = {k: v for k, v in fm.boundaries.items() if k != "clamp"}
    with pytest.raises(SolverError, match="singular|support"):
        assemble(fm, material, LoadCase())


def test_singular_matrix_is_an_error_never_a_number(s1_faces, material):
    """A held set that leaves a free rigid body (hold one node only) cannot be solved."""
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble
    from fea.solve import solve

    g, faces = s1_faces
    sys_ = assemble(fea_mesh_2d(faces[0], g), material, LoadCase())
    sys_.fixed = sys_.fixed[:2]  # one node: the part can still rotate about it
    sys_.held = sys_.fixed
    with pytest.raises(SolverError):
        solve(sys_, "superlu")


def test_a_solver_that_cannot_load_is_named_not_the_model(s1_faces, material, monkeypatch):
    """pypardiso without MKL's mkl_rt (a virtual environment without it) raises ImportError
    at the factorisation: the message names the solver install, not rigid motion."""
    from fea import solve as solve_module
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble

    def missing(*args, **kwargs):
        raise ImportError("Shared library mkl_rt not found")

    monkeypatch.setattr(solve_module, "_direct", missing)
    g, faces = s1_faces
    sys_ = assemble(fea_mesh_2d(faces[0], g), material, LoadCase())
    with pytest.raises(SolverError, match="could not be loaded") as err:
        solve_module.solve(sys_, "pardiso")
    assert "rigid motion" not in str(err.value) and "mkl_rt" in str(err.value)


def test_impossible_load_cases(s1_faces, material):
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble

    g, faces = s1_faces
    fm = fea_mesh_2d(faces[0], g)
    with pytest.raises(SolverError, match="full ring"):
        assemble(fm, material, LoadCase(support="holes"))
    with pytest.raises(SolverError):
        LoadCase(patch_half_angle_rad=0.0)
    with pytest.raises(SolverError):
        LoadCase(load="torque wrench")


def test_missing_material_data(s1):
    from dataclasses import replace

    from fea.problem import solver_material

    bad = replace(s1.material.material, youngs_modulus_MPa=float("nan"))
    with pytest.raises(SolverError, match="youngs_modulus"):
        solver_material(bad)
    with pytest.raises(SolverError, match="Poisson"):
        solver_material(replace(s1.material.material, poisson_ratio=0.5))


def test_solver_uses_the_one_material_type(s1):
    """The solver checks and uses the job's own Material (no second material class)."""
    from fea.problem import lame, solver_material
    from springcad.materials import Material

    m = solver_material(s1.material)
    assert isinstance(m, Material) and m is s1.material.material
    E = m.youngs_modulus_MPa
    lam3, mu = lame(m, plane_stress=False)
    # Young's modulus back from the 3D Lame parameters: E = mu (3 lam + 2 mu) / (lam + mu)
    assert mu * (3 * lam3 + 2 * mu) / (lam3 + mu) == pytest.approx(E, rel=1e-12)
    lam2, _ = lame(m, plane_stress=True)
    assert lam2 == pytest.approx(2 * lam3 * mu / (lam3 + 2 * mu), rel=1e-12)


def _chain(n: int, hold_first: bool):
    """A 1D chain of n springs whose stiffnesses span 1e-4..1 (a badly scaled but regular
    system), loaded at its far end; held at node 0 unless ``hold_first`` is False."""
    from types import SimpleNamespace

    from scipy.sparse import diags

    k = np.logspace(-4, 0, n)
    main = np.concatenate([k, [0.0]]) + np.concatenate([[0.0], k])
    A = diags([main, -k, -k], [0, 1, -1], format="csr")
    f = np.zeros(n + 1)
    f[-1] = 1.0
    fixed = np.array([0]) if hold_first else np.array([], dtype=int)
    return SimpleNamespace(A=A, f=f, fixed=fixed, constraints=None, dim=2,
                           rotation=np.linspace(0.0, 1.0, n + 1))


def test_solve_check_is_scaled_by_the_backward_error_not_the_size():
    """A large badly scaled chain has a relative residual at round-off far above 1e-8
    (the old test refused it), yet its backward error is ~eps; the same chain with its
    hold removed (singular) is still refused."""
    from fea.solve import backward_error, solve

    system = _chain(200_000, hold_first=True)
    u, info = solve(system, "superlu")
    x_true = np.cumsum(1.0 / np.logspace(-4, 0, 200_000))  # closed form: the compliances add
    assert u[1:] == pytest.approx(x_true, rel=1e-6)
    free = np.arange(1, 200_001)
    M = system.A[free][:, free]
    r_rel = np.linalg.norm(M @ u[1:] - system.f[1:]) / np.linalg.norm(system.f[1:])
    assert info.residual < 1e-14 and info.residual == pytest.approx(
        backward_error(M, u[1:], system.f[1:])[0])
    assert r_rel > 1e-8  # the relative residual has a size-dependent floor: the old check refused it

    singular = _chain(2_000, hold_first=True)
    singular.fixed = np.array([], dtype=int)
    with pytest.raises(SolverError):
        solve(singular, "superlu")
    floating = _chain(2_000, hold_first=True)
    floating.A = floating.A.tolil()
    floating.A[1000, 1001] = floating.A[1001, 1000] = 0.0  # cut the chain: a free piece
    floating.A[1000, 1000] -= 1e-4 * 10 ** (4 * 1000 / 1999)
    floating.A[1001, 1001] -= 1e-4 * 10 ** (4 * 1000 / 1999)
    with pytest.raises(SolverError):
        solve(floating, "superlu")


def test_exclusion_mask_is_the_unbounded_nearest_distance_test(s1_faces, material):
    """The stress exclusion near the held rim uses a bounded nearest-node search: the same
    mask as the full nearest distance below the exclusion radius, at the nodes and at points
    spread over the face (brute force over every held node)."""
    from fea.mesh import fea_mesh_2d
    from fea.problem import LoadCase, assemble
    from fea.results import _excluded_mask

    g, faces = s1_faces
    fm = fea_mesh_2d(faces[1], g, 1)
    case = LoadCase()
    system = assemble(fm, material, case)
    held = system.basis.doflocs[:2, np.unique(system.held // system.dim)]
    rng = np.random.default_rng(5)
    x = system.basis.doflocs
    pts = np.hstack([x, x[:, rng.integers(0, x.shape[1], 2000)]
                     + rng.normal(0.0, 0.3, (2, 2000))])
    for radius in (0.5 * g.rim_thickness_mm, 0.05, 3.0):
        d = np.sqrt(((pts[:, :, None] - held[:, None, :]) ** 2).sum(axis=0)).min(axis=1)
        expect = d < radius
        for c in g.contact_points_mm():  # the load patch, as the function adds it
            expect |= np.hypot(pts[0] - c[0], pts[1] - c[1]) < \
                2.0 * case.patch_half_width_mm(g.tip_radius_mm)
        assert np.array_equal(_excluded_mask(pts, system, fm, case, radius), expect)
