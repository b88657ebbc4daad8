"""A torque sensor that saturates: the spring fitted off its rails.

Physics: a spring of stiffness K with a clearance of 2h (the paper's dead band, torque
K·(θ - sign(θ)·h) beyond it), driven through a multi-level staircase; the torque sensor
adds white noise and its ADC then clips at ±rail, set below the torque of the largest
level, so the holds there read the rail. Fitted on every sample the clipped holds
read as a softer spring (K 17-22 % low) and the clearance was lost; the rails are
samples the sensor did not measure.
"""

import numpy as np
import pytest

from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.region import at_rails

FS_HZ = 500.0
K, H_RAD = 60.0, 0.015  # N·m/rad, rad (half the clearance)


def _motion(seed: int) -> np.ndarray:
    """Deflection (rad): random levels of seven (0, ±0.12, ±0.25, ±0.35 rad), each held
    1-2 s, moved between by 0.5 s cosine ramps (a multi-level staircase)."""
    rng = np.random.default_rng(seed)
    levels = rng.choice([-0.35, -0.25, -0.12, 0.0, 0.12, 0.25, 0.35], 24)
    out, now = [np.zeros(int(0.5 * FS_HZ))], 0.0
    ramp = np.arange(int(0.5 * FS_HZ)) / (0.5 * FS_HZ)
    for level in levels:
        out.append(now + (level - now) * (0.5 - 0.5 * np.cos(np.pi * ramp)))
        out.append(np.full(int(rng.uniform(1.0, 2.0) * FS_HZ), level))
        now = level
    return np.concatenate(out)


def _record(seed: int, rail_Nm: float | None, step_Nm: float = 0.0):
    rng = np.random.default_rng(seed + 50)
    theta = _motion(seed)
    t = np.arange(theta.size) / FS_HZ
    spring = np.sign(theta) * np.maximum(np.abs(theta) - H_RAD, 0.0)
    torque = K * spring + rng.normal(0.0, 0.03, t.size)
    if step_Nm:  # an ADC's quantisation, no clipping
        torque = step_Nm * np.round(torque / step_Nm)
    if rail_Nm is not None:
        torque = np.clip(torque, -rail_Nm, rail_Nm)
    return make_record(t, torque, theta + rng.normal(0.0, 5e-5, t.size))


@pytest.mark.parametrize("seed", [0, 1])
def test_a_clipped_spring_keeps_its_clearance_and_stiffness_and_is_flagged(seed):
    rail = 0.72 * K * (0.35 - H_RAD)  # the ±0.35 rad holds read the rails
    result = fit_record(_record(seed, rail))
    loop = result.loop
    assert "backlash" in loop.final.effects
    assert "stiffening" not in loop.final.effects
    p = loop.final.params()
    assert p["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.01)
    assert p["backlash_rad"] == pytest.approx(2 * H_RAD, rel=0.1)
    assert loop.unexplained  # the clipping is structure outside the library, still flagged
    assert loop.region["torque_rails_Nm"] == pytest.approx([-rail, rail])


def test_a_quantised_torque_is_not_taken_for_rails():
    # an ADC's steps up to about twice the noise (0.03 N·m) on an unclipped record: its top
    # level is the tail of the levels below it. (Steps of several noise levels read a hold
    # as one value, which no record can tell from a rail.)
    for step in (0.02, 0.05):
        assert not at_rails(_record(0, None, step_Nm=step).torque_Nm).any()
