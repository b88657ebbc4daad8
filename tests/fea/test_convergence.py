"""Richardson extrapolation and the observed convergence rates."""

from __future__ import annotations

import math

import pytest


def test_richardson_recovers_order_and_limit():
    from fea.convergence import richardson

    h = [1.0, 0.5, 0.25]
    r = richardson([2.0 + 0.3 * x ** 3 for x in h], formal_order=4.0)
    assert r.behaviour == "monotone"
    assert r.observed_order == pytest.approx(3.0, abs=1e-9)
    assert r.extrapolated == pytest.approx(2.0, abs=1e-12)
    # an order above the formal one is not trusted for the error estimate
    r2 = richardson([2.0 + 0.3 * x ** 6 for x in h], formal_order=4.0)
    assert r2.order_used == 4.0 and r2.error > 0


def test_richardson_with_unequal_ratios():
    """Non-nested meshes (pytetwild levels): ratios from DOF counts, Celik's iteration."""
    from fea.convergence import richardson

    h = [1.0, 0.7, 0.45]
    r = richardson([2.0 + 0.3 * x ** 3 for x in h], 4.0, ratios=(1 / 0.7, 0.7 / 0.45))
    assert r.observed_order == pytest.approx(3.0, abs=1e-9)
    assert r.extrapolated == pytest.approx(2.0, abs=1e-12)


def test_richardson_oscillating_and_diverging():
    from fea.convergence import richardson

    osc = richardson([100.0, 101.0, 100.5], formal_order=2.0)
    assert osc.behaviour == "oscillatory" and osc.extrapolated == 100.5
    assert osc.error == pytest.approx(1.25 * 1.0 / 100.5)
    # growing changes of several per cent: a singularity, no finite error
    sing = richardson([1500.0, 1560.0, 1700.0], formal_order=2.0)
    assert sing.behaviour == "diverging" and math.isinf(sing.error)
    with pytest.raises(ValueError):
        richardson([1.0, 2.0], formal_order=2.0)


def test_observed_stiffness_rate_2d(s1, material):
    """Quadratic triangles: K (an energy) converges at ~h^3.5 (formal 4; the clamp
    corners of the sector cost a little)."""
    from fea_helpers import sector_2d

    st = sector_2d(s1, material, levels=(1, 2, 3))
    assert st.stiffness.behaviour == "monotone"
    assert 2.5 < st.stiffness.observed_order < 4.5
    assert st.stiffness.error < 1e-4
    # the nodal peak stress settles within a fraction of a per cent
    vals = st.peak_stress.values
    assert max(vals) / min(vals) - 1 < 0.01
    assert st.peak_stress.error < 0.01


@pytest.mark.slow
def test_observed_stiffness_rate_3d(s1, s1_faces, material):
    """Quadratic tets, uniform refinement in all three directions (layers double too)."""
    from fea.convergence import study
    from fea.mesh import fea_mesh_3d
    from fea.problem import LoadCase
    from fea.study import solve_mesh

    g, faces = s1_faces
    res = [solve_mesh(fea_mesh_3d(faces[k], g, 2 ** k, k), material, LoadCase(),
                      s1.max_deflection_rad) for k in range(3)]
    st = study(res, "3d")
    assert st.stiffness.behaviour == "monotone"
    assert 2.0 < st.stiffness.observed_order < 4.5
    assert st.stiffness.error < 1e-3
