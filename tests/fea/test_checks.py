"""The four independent checks of the FEA (issue 4, item 4).

(a) closed-form beam theory, (b) CalculiX on the identical mesh, (c) one sector
vs the full ring, (d) 2D plane stress vs 3D quadratic tets.
"""

from __future__ import annotations

import pytest

from fea_helpers import sector_2d


# ------------------------------------------------------------------ (a) beam theory
def test_a_straight_flexure_against_closed_form_beam_theory(straight, material):
    """Parabolic (constant-stress) straight flexures: K_beam = N r_c^2 E z w0^3 / (8 L^3).

    Euler-Bernoulli is exact for this shape, so the FEA difference is what beam
    theory leaves out. FEA comes out ~0.8 % below: shear compliance, largest
    where the flexure is thin (Timoshenko, kappa = 5/6, adds (1+nu)/(2 kappa)
    (w0/L)^2 = 1.2 % of the compliance here), partly offset by the root
    fillets (extra material where the moment is largest) and the tip ball and
    neck. Bounds: FEA between the Timoshenko and the Euler-Bernoulli values,
    within 1.5 % of beam theory, within 1 % of Timoshenko.
    """
    d = straight
    assert d.flexure == "straight" and d.width_law == "stiffness"
    E, nu = material.youngs_modulus_MPa, material.poisson_ratio
    N, rc, z, w0, L = d.n_flexures, d.contact_radius_mm, d.thickness_mm, d.root_width_mm, \
        d.length_mm
    k_beam = N * rc ** 2 * E * z * w0 ** 3 / (8 * L ** 3)
    assert d.stiffness_beam_Nmm_per_rad == pytest.approx(k_beam, rel=1e-5)  # trapezoid rule
    c_bend = 8 * L ** 3 / (E * z * w0 ** 3)
    c_shear = 2 * L / (5 / 6 * E / (2 * (1 + nu)) * z * w0)  # int ds / (kappa G z w(s))
    k_timo = N * rc ** 2 / (c_bend + c_shear)
    st = sector_2d(d, material)
    k_fea = st.stiffness.extrapolated
    assert st.stiffness.error < 1e-4
    assert k_timo < k_fea < k_beam
    assert k_fea / k_beam - 1 > -0.015
    assert abs(k_fea / k_timo - 1) < 0.01


# ------------------------------------------------------------------ (b) CalculiX
def _ccx_or_skip():
    from fea.calculix import ccx_path

    if ccx_path() is None:
        pytest.skip("CalculiX (ccx) not installed")


@pytest.mark.parametrize("level,layers,peak_tol", [(0, 1, 0.06), (1, 2, 0.02)])
def test_b_calculix_on_the_identical_mesh(s1, s1_faces, material, level, layers, peak_tol):
    """Same mesh, two solvers: K to 1e-4; the nodal peak (each code averages element
    stresses at the nodes its own way) to 6 % on the coarsest mesh (5.04 % measured at
    6.3k DOFs on the uncoupled S1, whose peak sits in the root-zone bend; 4.1 % on the
    root-aligned one) and 2 % one level finer."""
    _ccx_or_skip()
    from fea.calculix import cross_check
    from fea.mesh import fea_mesh_3d
    from fea.problem import LoadCase

    g, faces = s1_faces
    fm = fea_mesh_3d(faces[level], g, layers, level)
    cc = cross_check(fm, material, LoadCase(), s1.max_deflection_rad)
    assert cc.stiffness_rel_diff < 1e-4
    assert cc.peak_rel_diff < peak_tol


# ------------------------------------------------------------------ (c) sector vs ring
def test_c_sector_against_full_ring(s1, s1_faces, material):
    """The free-sided sector against the full ring built from the same elements.

    The full ring is N rotated copies of the (periodically meshed) sector, so
    the only difference is the sector's free cut faces: measured +0.12 %
    (the ring's rim between flexures is continuous, hence a little stiffer).
    """
    from fea.geometry import ring_geometry
    from fea.mesh import fea_mesh_2d, pattern_sector
    from fea.problem import LoadCase
    from fea.study import solve_mesh

    g, faces = s1_faces
    case, theta = LoadCase(), s1.max_deflection_rad
    sector = solve_mesh(fea_mesh_2d(faces[0], g), material, case, theta)
    ring = solve_mesh(fea_mesh_2d(pattern_sector(faces[0], s1.n_flexures),
                                  ring_geometry(s1, holes=False)), material, case, theta)
    rel = ring.stiffness_Nmm_per_rad / sector.stiffness_Nmm_per_rad - 1
    assert abs(rel) < 0.005
    assert 0 < rel < 0.003
    # every flexure of the ring carries the same stress as the sector's
    assert ring.peak_von_mises_MPa == pytest.approx(sector.peak_von_mises_MPa, rel=0.01)


@pytest.mark.slow
def test_c_rim_held_at_the_holes_vs_the_outer_rim(s1, material):
    """Support study on the full ring with its dowel holes (7 holes, 28 flexures).

    Held at the outer rim (housing) vs held only at the dowel holes (rim free):
    the free rim between dowels adds compliance; measured K(holes) / K(rim)
    = 0.991 on the same mesh. The holes themselves barely matter when the outer
    rim is held (< 0.1 %).
    """
    from fea.geometry import ring_geometry
    from fea.mesh import fea_mesh_2d, mesh_face_levels
    from fea.problem import LoadCase
    from fea.mesh_size import DEFAULT_SIZE
    from fea.study import solve_mesh

    g = ring_geometry(s1, holes=True)
    fm = fea_mesh_2d(mesh_face_levels(g, DEFAULT_SIZE, 1)[0], g)
    theta = s1.max_deflection_rad
    rim = solve_mesh(fm, material, LoadCase(support="rim"), theta)
    holes = solve_mesh(fm, material, LoadCase(support="holes"), theta)
    ratio = holes.stiffness_Nmm_per_rad / rim.stiffness_Nmm_per_rad
    assert 0.97 < ratio < 1.0


# ------------------------------------------------------------------ (d) 2D vs 3D
def test_d_plane_stress_against_3d_tets(s1, s1_faces, material):
    """A 4.5 mm thick flat disk: plane stress vs quadratic tets on the same in-plane mesh.

    Measured +0.4 % for 3D (the disk is thick next to the thin flexure tips, so
    not quite plane stress), within the 1 % of the check.
    """
    from fea.mesh import fea_mesh_2d, fea_mesh_3d
    from fea.problem import LoadCase
    from fea.study import solve_mesh

    g, faces = s1_faces
    case, theta = LoadCase(), s1.max_deflection_rad
    k2 = solve_mesh(fea_mesh_2d(faces[1], g), material, case, theta)
    k3 = solve_mesh(fea_mesh_3d(faces[1], g, 2), material, case, theta)
    rel = k3.stiffness_Nmm_per_rad / k2.stiffness_Nmm_per_rad - 1
    assert 0 < rel < 0.01
    assert k3.peak_von_mises_MPa == pytest.approx(k2.peak_von_mises_MPa, rel=0.03)
