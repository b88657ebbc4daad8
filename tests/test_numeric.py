"""The numpy-only kernels of springcad.design.numeric against scipy."""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from springcad.design.numeric import ClampedCubic, cumtrapz, find_root


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
