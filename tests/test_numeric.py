"""The numpy-only kernels of springcad.design.numeric against scipy."""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq
from scipy.spatial import cKDTree

from springcad.design.numeric import ClampedCubic, close_pairs, cumtrapz, find_root


def test_clamped_cubic_matches_scipy():
    x = np.array([0.0, 0.7, 1.5, 2.0, 3.1, 4.0])
    y = np.column_stack([np.sin(x), x ** 2 - 3 * x])
    ours = ClampedCubic(x, y, (0.3, -1.0), (0.5, 2.0))
    ref = CubicSpline(x, y, bc_type=((1, [0.3, -1.0]), (1, [0.5, 2.0])), axis=0)
    t = np.linspace(0, 4, 301)
    for nu in (0, 1, 2):
        assert np.allclose(ours(t, nu), ref(t, nu), atol=1e-12)


def test_clamped_cubic_scalar_and_end_slopes():
    x = np.linspace(1.0, 5.0, 7)
    s = ClampedCubic(x, np.cos(x), 0.0, 0.0)
    assert s(x).shape == x.shape
    assert s(np.array([1.0, 5.0]), 1) == pytest.approx([0.0, 0.0], abs=1e-12)


@pytest.mark.parametrize("a,b", [(0.0, 2.0), (2.0, 0.0), (-1.0, 3.0)])
def test_find_root_matches_brentq(a, b):
    f = lambda v: np.cos(v) - v ** 3 + 0.2  # noqa: E731
    assert find_root(f, a, b) == pytest.approx(brentq(f, min(a, b), max(a, b)), abs=1e-10)


def test_find_root_needs_bracket():
    with pytest.raises(ValueError, match="not bracketed"):
        find_root(lambda v: v * v + 1, -1.0, 1.0)


def test_cumtrapz_matches_scipy():
    x = np.sort(np.random.default_rng(3).uniform(0, 5, 50))
    assert np.allclose(cumtrapz(np.exp(x), x), cumulative_trapezoid(np.exp(x), x, initial=0))


@pytest.mark.parametrize("nu", [0.25, 0.28, 0.3, 0.33])
def test_minimize_bounded_is_scipys_bounded_brent_bit_for_bit(nu):
    from scipy.optimize import minimize_scalar

    from springcad.design.contact_stress import subsurface_stress, von_mises
    from springcad.design.numeric import minimize_bounded

    def f(t):  # the contact stress's use: the subsurface von Mises peak on the load axis
        return -float(von_mises(*subsurface_stress(0.0, np.array([t]), nu))[0])

    cases = [(f, 0.69, 0.71, 1e-10), (f, 0.0, 3.0, 1e-10),
             (lambda t: (t - 0.3) ** 2 + nu, -1.0, 2.0, 1e-5),
             (lambda t: abs(np.sin(5 * t)) - t * nu, 0.1, 0.9, 1e-8),
             (lambda t: t, 0.0, 1.0, 1e-10)]  # the minimum at a bound
    for g, lo, hi, tol in cases:
        ref = minimize_scalar(g, bounds=(lo, hi), method="bounded", options={"xatol": tol})
        x, fx = minimize_bounded(g, lo, hi, xatol=tol)
        assert (x, fx) == (ref.x, ref.fun)


@pytest.mark.parametrize("n,r_mm", [(1, 0.1), (2, 20.0), (60, 0.3), (4000, 0.02)])
def test_close_pairs_are_the_kd_trees_and_brute_forces(n, r_mm):
    rng = np.random.default_rng(n)
    xy = rng.uniform(-5.0, 5.0, (n, 2))
    # repeated points, points on the grid lines, pairs exactly r apart along an axis
    xy = np.vstack([xy, xy[:3], np.round(xy[:50], 1), xy[:10] + [r_mm, 0.0]])
    ours = close_pairs(xy, r_mm)
    tree = cKDTree(xy).query_pairs(r_mm, output_type="ndarray")
    assert np.array_equal(ours, tree[np.lexsort((tree[:, 1], tree[:, 0]))])
    if len(xy) <= 200:
        i, j = np.triu_indices(len(xy), 1)
        near = ((xy[i] - xy[j]) ** 2).sum(axis=1) <= r_mm ** 2
        assert np.array_equal(ours, np.column_stack([i, j])[near])
