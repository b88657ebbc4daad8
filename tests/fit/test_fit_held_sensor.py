"""A torque sensor sampled and held between updates (issue 24, generator H's miss).

A sensor that updates at 50 Hz, logged at 1 kHz, reads the torque of its last update: late
by zero to one update (20 ms), a sawtooth at 50 Hz whose size follows the speed and whose
sign follows the direction of motion, so it cancels out of the residual's plain spectrum
over every cycle. Its lag (half an update on average) is the record's: it describes only
about sqrt(3) times the sawtooth it leaves, which a lag beside structure the library cannot
describe must not be taken for (``patches.lag_patches``; before, it was dropped so, and on
generator H the sawtooth passed for noise). Reference: the same spring read by a sensor late
by the held sensor's mean lag, which the library's delay describes exactly.
"""

import numpy as np

from springcad.fit.data import make_record
from tests.fit.fit_helpers import loop_on_record, triangles

K_NM_PER_RAD = 40.0
SAMPLE_RATE_HZ = 1000.0
UPDATE_HZ = 50.0
NOISE_NM = 0.15
#: 0.3 rad triangles at eight speeds (27.4 s)
SPEEDS_RAD_PER_S = (0.2, 0.5, 0.3, 0.6, 0.25, 0.45, 0.35, 0.55)


def _record(read_at_s, seed: int = 11):
    """A linear spring whose torque sensor reads the torque at ``read_at_s(t)`` (s)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 27.4, 1.0 / SAMPLE_RATE_HZ)
    theta = triangles(t, SPEEDS_RAD_PER_S)
    torque = (K_NM_PER_RAD * triangles(read_at_s(t), SPEEDS_RAD_PER_S)
              + NOISE_NM * rng.normal(size=t.size))
    return make_record(t, torque, theta + 2e-5 * rng.normal(size=t.size))


def _held(t):
    # updates on the sensor's own clock, 3 ms out of phase with the logger's
    return np.floor((t - 0.003) * UPDATE_HZ) / UPDATE_HZ + 0.003


def test_a_held_sensor_is_a_lag_with_structure_left():
    res, _ = loop_on_record(_record(_held))
    assert "time_lag" in res.final.effects
    assert res.unexplained
    test = res.structure["tests"]["periodic_with_direction"]
    assert test["significant"]
    assert abs(test["peak_frequency_hz"] - UPDATE_HZ) < 0.5


def test_a_delay_of_the_same_mean_lag_leaves_no_such_line():
    res, _ = loop_on_record(_record(lambda t: t - 0.5 / UPDATE_HZ))
    assert "time_lag" in res.final.effects
    assert not res.structure["tests"]["periodic_with_direction"]["significant"]
    assert not res.unexplained
