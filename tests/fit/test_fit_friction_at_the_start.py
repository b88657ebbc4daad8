"""Friction through a record's first small reversal (a settling wiggle before the cycles).

Physics: Dahl's presliding friction, integrated exactly over each sample's monotone
step (``f <- s·H - (s·H - f)·exp(-|dθ|/θp)``, s the step's sign), with a viscous damper
c·dθ/dt, on a spring K. The motion first wiggles 5 mrad the other way (a motor finding
its zero, a fade-in) and then runs whole sine cycles of 0.25 rad at three frequencies,
which tell the damper from the friction. Friction reverses at that wiggle although it
is far below a cycle's turn; read as one run from rest, the friction had the sign of
the motion after it over the whole wiggle (2H·0.8 there) and the record was flagged.
"""

import numpy as np
import pytest

from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.effects import Hysteresis
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals

FS_HZ = 1000.0
K, H, THETA_P, C = 90.0, 0.5, 0.003, 0.8  # N·m/rad, N·m, rad, N·m·s/rad


def _motion() -> np.ndarray:
    """Deflection (rad) at FS_HZ: a 5 mrad wiggle, then 0.25 rad cycles at 0.2/0.4/0.8 Hz."""
    parts = [0.005 * np.sin(np.pi * np.arange(int(0.3 * FS_HZ)) / (0.3 * FS_HZ)) ** 2]
    for f, n in ((0.2, 2), (0.4, 3), (0.8, 4)):
        u = np.arange(int(n / f * FS_HZ)) / FS_HZ
        parts.append(-0.25 * np.sin(2 * np.pi * f * u))
    parts.append(np.zeros(int(0.5 * FS_HZ)))
    return np.concatenate(parts)


def _dahl(theta: np.ndarray) -> np.ndarray:
    """Dahl friction (N·m) from rest, exact over each monotone sample step."""
    out = np.zeros_like(theta)
    for i in range(1, theta.size):
        d = theta[i] - theta[i - 1]
        s = np.sign(d)
        out[i] = s * H - (s * H - out[i - 1]) * np.exp(-abs(d) / THETA_P) if d else out[i - 1]
    return out


def _record(seed: int):
    rng = np.random.default_rng(seed)
    theta = _motion()
    t = np.arange(theta.size) / FS_HZ
    torque = K * theta + _dahl(theta) + C * np.gradient(theta, t) + rng.normal(0, 0.06, t.size)
    return make_record(t, torque, theta + rng.normal(0, 3e-5, t.size))


def test_the_library_friction_follows_dahls_law_through_the_wiggle():
    rec = _record(0)
    sig = make_signals(rec, segment(rec))
    model = Hysteresis().torque(np.array([H, THETA_P]), sig, np.arange(sig.n))
    exact = _dahl(_motion())
    first = slice(0, int(0.6 * FS_HZ))  # the wiggle and the first 0.3 s after it
    # the deflection is read with 3e-5 rad noise (a hundredth of the presliding angle)
    assert np.max(np.abs(model[first] - exact[first])) < 0.1 * H


@pytest.mark.parametrize("seed", [0, 1])
def test_friction_and_a_damper_after_a_wiggle_are_named_and_explain_the_record(seed):
    loop = fit_record(_record(seed)).loop
    assert set(loop.final.effects) == {"hysteresis", "time_lag"}
    assert not loop.unexplained
    p = loop.final.params()
    assert p["friction_torque_Nm"] == pytest.approx(H, rel=0.03)
    assert p["viscous_damping_Nms_per_rad"] == pytest.approx(C, rel=0.05)
    assert p["stiffness_Nm_per_rad"] == pytest.approx(K, rel=0.005)
