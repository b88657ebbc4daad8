"""Issue 24 class 1 on a triangle at three speeds: backlash, Dahl friction and a delay together.

On linear ramps at three speeds a friction's step (±F, the same at every speed) and a lag's
term (K·delay·speed) are partly alike, so the greedy search fits the lag first, holding part
of the friction; beside it the backlash and the friction fail their audits one at a time, and
a cubic takes up what is left. The set {backlash, friction, lag} fitted afresh from the linear
model describes the record, and the cubic that stood in for it fails beside the set. Truth
from the simulator's inputs.
"""

from __future__ import annotations

import pytest

from springcad.fit.bench import BenchNoise, BenchSpring, simulate
from springcad.fit.protocols import Protocol

from fit_helpers import loop_on

K = 50.0
LAG_S = 0.033
FRICTION_NM = 1.25
BACKLASH_RAD = 0.024

#: two cycles of ±0.88 rad at each of three constant speeds (rad/s)
TRIANGLES = Protocol(amplitudes_rad=(0.88, 0.88), rates_rad_per_s=(0.27, 0.8, 2.2),
                     profile="linear", rest_s=1.0)


def test_backlash_friction_and_lag_on_three_speeds_are_found_together():
    spring = BenchSpring(K, backlash_rad=BACKLASH_RAD, friction_torque_Nm=FRICTION_NM,
                         presliding_rad=0.004, lag_s=LAG_S)
    sim = simulate(spring, protocol=TRIANGLES,
                   noise=BenchNoise(torque_Nm=0.11, deflection_rad=5e-5), seed=0)
    res, _ = loop_on(sim)
    assert set(res.final.effects) == {"backlash", "hysteresis", "time_lag"}
    assert not res.unexplained
    p = res.final.params()
    assert p["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.01)
    assert p["lag_s"] == pytest.approx(LAG_S, rel=0.1)
    assert p["friction_torque_Nm"] == pytest.approx(FRICTION_NM, rel=0.1)
    assert p["backlash_rad"] == pytest.approx(BACKLASH_RAD, rel=0.15)
