"""Glitches among a model's errors at the turns (issue 24, generator H's misses).

A friction law that switches sharper than the model's (a Stribeck or regularised Coulomb
friction read with the presliding law) leaves the residual swinging for a few samples at
every reversal, far beyond the noise. One of those swings can stand out from both its
neighbours like a sensor spike, a few samples from where the segmentation placed the turn:
alone, its timing cannot be told from a random draw, and it was named ``outliers`` on pure
Gaussian noise. Every turn's excursion together gathers at the turns
(``residual.motion_locked_p``), which says the model errs there. Reference: spikes drawn
at random times on the same record are still named.
"""

import numpy as np

from springcad.fit.data import make_record
from tests.fit.fit_helpers import loop_on_record, triangles

K_NM_PER_RAD = 40.0
NOISE_NM = 0.05
SPEEDS_RAD_PER_S = (0.2, 0.5, 0.3, 0.6, 0.25, 0.45, 0.35, 0.55)
#: the swing the model leaves at a turn (noise standard deviations, three samples)
SWING = np.array([8.0, 10.0, 6.0])


def _record(spike_times_s=(), seed: int = 1):
    """A linear spring on triangles whose residual swings at every turn; at the fourth turn,
    four samples late, the swing is one sample of 14 noise levels instead."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 27.4, 1e-3)
    theta = triangles(t, SPEEDS_RAD_PER_S)
    torque = K_NM_PER_RAD * theta + NOISE_NM * rng.normal(size=t.size)
    turns = np.flatnonzero(np.diff(np.sign(np.diff(theta))) != 0) + 1
    for k, i in enumerate(turns):
        side = np.sign(theta[i])
        if k == 3:
            torque[i + 4] += side * 14.0 * NOISE_NM
        else:
            torque[i:i + 3] += side * NOISE_NM * SWING
    for at in spike_times_s:
        torque[int(round(at * 1e3))] += 25.0 * NOISE_NM
    return make_record(t, torque, theta + 2e-5 * rng.normal(size=t.size))


def test_a_swing_at_a_turn_is_no_glitch_where_every_turn_swings():
    res, _ = loop_on_record(_record())
    assert "outliers" not in res.final.effects


def test_spikes_away_from_the_turns_are_still_glitches():
    res, _ = loop_on_record(_record(spike_times_s=(2.345, 7.1, 11.777, 16.03, 21.5)))
    assert "outliers" in res.final.effects
    assert res.final.mask.sum() >= 5
