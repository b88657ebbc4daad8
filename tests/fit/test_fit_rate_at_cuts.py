"""The deflection rate a damper sees, at the trace's cuts inside a moving stretch.

A hand jog's motor speed is band-limited (a 3 Hz loop) but changes often; the local
cubic of the trace misses it at some corners and is cut there
(``DeflectionTrace.mend_cuts``), the two sides fitted alone. The trace then steps by a
fraction of a mrad at the cut, along or against the motion. Reference: the true
(noise-free) speed of the simulated motion; at a cut, the rate read on the two samples
either side must stay within the true speed's range about it (a damper's torque is
c times it: a blip of 0.2 rad/s for two samples was taken for two glitches).
"""

import numpy as np
import pytest
from scipy import signal

from springcad.fit.data import make_record
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals

FS_HZ = 1000.0


def _jog(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and deflection (rad) of a manual jog: a random speed (1 Hz band) gated
    off for pauses, low-passed at 3 Hz by the motor's loop, integrated, its slow wander
    removed, scaled to +-0.3 rad."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(24 * FS_HZ)) / FS_HZ
    b, a = signal.butter(2, 1.0 / (FS_HZ / 2))
    speed = signal.filtfilt(b, a, rng.normal(0.0, 1.0, t.size))
    gate = (np.sin(2 * np.pi * 0.3 * t + rng.uniform(0, 6)) > -0.3).astype(float)
    gate = np.convolve(gate, np.ones(150) / 150, mode="same")
    b3, a3 = signal.butter(2, 3.0 / (FS_HZ / 2))
    theta = np.cumsum(signal.lfilter(b3, a3, speed * gate)) / FS_HZ
    bl, al = signal.butter(2, 0.05 / (FS_HZ / 2))
    theta = theta - signal.filtfilt(bl, al, theta)
    return t, 0.3 * theta / np.max(np.abs(theta))


@pytest.mark.parametrize("seed", [0, 1])
def test_the_rate_beside_a_cut_inside_a_moving_stretch_stays_within_the_true_speed(seed):
    t, theta = _jog(seed)
    v = np.gradient(theta, t)
    rng = np.random.default_rng(seed + 100)
    rec = make_record(t, 300.0 * theta, theta + rng.normal(0.0, 5e-5, t.size))
    sig = make_signals(rec, segment(rec))
    cuts = np.array(sig._trace.mend_cuts, dtype=int)
    cuts = cuts[(cuts > 5) & (cuts < sig.n - 5)]
    assert cuts.size >= 5  # the case: the trace is cut inside the motion
    worst = 0.0
    for c in cuts:
        lo, hi = v[c - 5:c + 5].min(), v[c - 5:c + 5].max()
        r = sig.rate_trace[c - 2:c + 2]
        worst = max(worst, float(np.max(r - hi)), float(np.max(lo - r)))
    # the trace's own error over a cubic window is a few % of the speed; a step across
    # the cut read as a speed was 19-21 % of it
    assert worst < 0.08 * np.max(np.abs(v))
