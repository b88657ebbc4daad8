"""A lag that grows along the record (clock skew) is still a lag, and no friction.

Two free-running clocks (the torque amplifier's and the encoder's) drift apart: the
delay between the channels grows linearly with the time. Read with one lag, the lag
fitted is a mean and the structure its change leaves is the lag's own; a friction
fitted beside it takes up the part that follows the direction of motion (held-out B's
``skew``: a 2 → 32 ms delay on a sine sweep run twice, named friction and a lag).
Freed per window of whole cycles (:data:`springcad.fit.patches.CHANGING_SIZES`), the
lag takes the change and the friction keeps 12 % of its size; and the lag is no patch
over structure it leaves changing (:func:`springcad.fit.patches.lag_patches`). Known
truth: records written here, the control with a true friction and a constant lag.
"""

import numpy as np
import pytest

from issue24_records import dahl_friction, sine_sweep
from springcad.fit.analysis import fit_record
from springcad.fit.bench import BenchSpring, simulate
from springcad.fit.data import make_record

from tests.fit.fit_helpers import K, TWO_RATES, loop_on_record, with_extra_torque

LAG0_S, SKEW_S = 0.002, 0.03


def _sweep_twice():
    t1, th1 = sine_sweep([17], [0.2, 0.5, 1.0], cycles=4)
    t = np.arange(2 * t1.size) / 500.0
    th = np.concatenate([th1, th1])
    return t, lambda tt: np.interp(tt, t, th)


def _sweep_record(seed, lag_s, friction_Nm=0.0):
    t, path = _sweep_twice()
    rng = np.random.default_rng(seed)
    late = path(t - lag_s(t))
    tau = K * late + friction_Nm * dahl_friction(late, 1.0, 0.004)
    return make_record(t, tau + rng.normal(0, 0.03, t.size),
                       path(t) + rng.normal(0, 1e-4, t.size))


def test_a_growing_delay_on_a_sine_sweep_is_a_lag_and_no_friction():
    # on the code before this rule: friction (1.5 N·m) and a 26 ms lag
    t_end = _sweep_twice()[0][-1]
    loop = fit_record(_sweep_record(1, lambda t: LAG0_S + SKEW_S * t / t_end)).loop
    assert set(loop.final.effects) == {"time_lag"}, loop.rejected
    lag = loop.final.model.report(loop.final.x)["lag_s"]
    assert LAG0_S < lag < LAG0_S + SKEW_S
    # one lag does not describe it: flagged
    assert loop.unexplained


def test_a_true_friction_beside_a_constant_lag_on_the_sweep_is_kept():
    loop = fit_record(_sweep_record(2, lambda t: 0.01 + 0 * t, friction_Nm=0.15)).loop
    assert {"hysteresis", "time_lag"} <= set(loop.final.effects), loop.rejected
    p = loop.final.model.report(loop.final.x)
    assert p["lag_s"] == pytest.approx(0.01, rel=0.1)


def test_a_growing_delay_on_two_ramp_rates_is_named():
    # on the code before this rule the lag was dropped as a patch: its term 2.8 times the
    # structure its own change leaves (at least 3 asked)
    sim = simulate(BenchSpring(K), protocol=TWO_RATES, seed=1)
    t_end = sim.record.time_s[-1]

    def late(t, th):
        return K * (TWO_RATES.deflection(t - LAG0_S - SKEW_S * t / t_end)
                    - TWO_RATES.deflection(t))

    res, _ = loop_on_record(with_extra_torque(sim, late))
    assert set(res.final.effects) == {"time_lag"}, res.rejected
    assert LAG0_S < res.final.model.report(res.final.x)["lag_s"] < LAG0_S + SKEW_S
