"""The torque model's Jacobian: each column moves only the part of the model its parameter
reaches, and must equal scipy's own forward difference of the whole residual."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize._numdiff import approx_derivative

from fit_helpers import simulate_fast
from springcad.fit.effects import get_effect
from springcad.fit.other_laws import (RegularisedCoulomb, StandardLinearSolid, TorqueFilter,
                                      ViscousDamping)
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel, forward_steps

LIBRARY_SETS = [
    ("backlash", "hysteresis", "time_lag", "drift", "torque_offset"),
    ("angle_offset", "backlash", "stiffening", "asymmetric_stiffness", "hysteresis"),
]
OTHER = [None, StandardLinearSolid(), TorqueFilter(), ViscousDamping(), RegularisedCoulomb()]


@pytest.fixture(scope="module")
def sig():
    sim = simulate_fast("backlash", "hysteresis", "time_lag", seed=3)
    return make_signals(sim.record, segment(sim.record))


@pytest.mark.parametrize("names", LIBRARY_SETS)
@pytest.mark.parametrize("other", OTHER, ids=lambda e: "library" if e is None else e.law)
def test_the_jacobian_is_the_forward_difference_of_the_whole_residual(sig, names, other):
    effects = tuple(get_effect(n) for n in names)
    if other is not None:
        effects = tuple(e for e in effects if e.name != other.name) + (other,)
    model = TorqueModel(effects, sig.scales)
    lo, hi = model.bounds
    rng = np.random.default_rng(len(names))
    x = model.transfer(TorqueModel((), sig.scales), np.array([40.0]))
    x = np.clip(x * (1.0 + 0.2 * rng.standard_normal(x.size)), lo, hi)
    x[0] = 40.0
    idx = np.arange(0, sig.n, 3)
    f0 = model.residual(x, sig, idx)
    mine = model.residual_jacobian(x, sig, idx, f0)
    scipy_fd = approx_derivative(lambda z: model.residual(z, sig, idx), x, method="2-point",
                                 f0=f0, bounds=(lo, hi))
    scale = np.max(np.abs(scipy_fd), axis=0)
    # the difference of one term and of the whole sum differ by the sum's round-off only:
    # eps·|τ| over a step of √eps·max(1, |x|)
    assert np.all(np.max(np.abs(mine - scipy_fd), axis=0) <= 1e-5 * scale + 1e-9)


def test_steps_turn_back_at_a_bound_and_shorten_where_neither_way_fits():
    x = np.array([0.0, 2.0, 1.0 - 1e-12, -3.0, 0.5])
    lo = np.array([-1.0, 0.0, 0.0, -10.0, 0.5 - 1e-10])
    hi = np.array([1.0, 10.0, 1.0, 0.0, 0.5 + 5e-11])
    h = forward_steps(x, lo, hi)
    eps = np.sqrt(np.finfo(float).eps)
    assert h[0] == pytest.approx(eps)            # at 0: forward, absolute √eps
    assert h[1] == pytest.approx(2.0 * eps)      # relative beyond |x| = 1
    assert h[2] == pytest.approx(-eps)           # at the upper bound: turned back
    assert h[3] == pytest.approx(-3.0 * eps)     # negative x: steps down
    assert h[4] == pytest.approx(-1e-10)         # neither way fits: the larger room
    assert np.all((x + h >= lo) & (x + h <= hi))
