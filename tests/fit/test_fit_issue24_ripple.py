"""Issue 24, session 8: a ripple periodic in deflection beside library effects, and a law
outside the library flagged from its held-out criterion.

Records written here with their own physics (not ``springcad.fit.bench``): an encoder read
through a gear with an eccentric pinion (a ripple G times per turn in the measured angle),
Dahl friction integrated exactly in angle, ramps with holds at two rates. Checked against
the truth they were made with. Units: N·m, rad, s.
"""

import math

import numpy as np
import pytest

from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.laws import left_rms_over_noise

FS_HZ = 500.0


def ramps(amp_rad, rates_rad_s, hold_s=1.0, cycles=2, fs=FS_HZ):
    """Cosine ramps 0 → +amp → 0 → -amp → 0 with holds at each end, at each rate; (t, θ)."""
    pieces = [np.zeros(int(0.5 * fs))]
    for rate in rates_rad_s:
        n = max(4, int(round(amp_rad / rate * fs)))
        up = 0.5 * amp_rad * (1.0 - np.cos(np.linspace(0.0, math.pi, n)))
        for _ in range(cycles):
            for sign in (1.0, -1.0):
                pieces += [sign * up, np.full(int(hold_s * fs), sign * amp_rad),
                           sign * up[::-1], np.zeros(int(hold_s * fs))]
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


def dahl(th, level_Nm, presliding_rad):
    """Dahl friction (exponent 1), exact in angle: df/dθ = (F·sign(dθ) - f)/θp."""
    f = np.zeros(th.size)
    for i in range(1, th.size):
        d = th[i] - th[i - 1]
        target = level_Nm * np.sign(d) if d != 0.0 else f[i - 1]
        f[i] = target + (f[i - 1] - target) * math.exp(-abs(d) / presliding_rad)
    return f


def ripple_record(seed, gear=15.0, ecc_rad=1e-3, cubic=0.0):
    """A spring (K 150 N·m/rad) with Dahl friction, an angle channel read through an
    eccentric gear (``ecc_rad`` · sin(G·θ + φ)), optionally a cubic ``K·cubic·θ³``."""
    rng = np.random.default_rng(seed)
    k = 150.0
    t, th = ramps(0.3, [0.1, 0.3])
    torque = k * th * (1.0 + cubic * th ** 2) + dahl(th, 0.9, 2e-3)
    torque += rng.normal(0.0, 0.15, t.size)
    phase = rng.uniform(0.0, 2.0 * math.pi)
    meas = th + ecc_rad * np.sin(gear * th + phase) + rng.normal(0.0, 2e-5, t.size)
    return k, t, torque, meas


@pytest.mark.parametrize("seed", [1, 2])
def test_a_geared_encoder_ripple_is_taken_out_and_the_friction_beside_it_is_named(seed):
    # the ripple (K·e = 0.15 N·m, about the noise) spans 1.4 periods of the ±0.3 rad range:
    # fitted beside it, a cubic and an asymmetry took up part of it and the friction was lost
    gear = 15.0
    k, t, torque, meas = ripple_record(seed, gear)
    loop = fit_record(make_record(t, torque, meas)).loop
    assert set(loop.identified) == {"hysteresis"}
    assert loop.unexplained
    assert loop.nuisance is not None
    assert loop.nuisance["period_rad"] == pytest.approx(2 * math.pi / gear, rel=0.03)
    assert loop.nuisance["amplitude_Nm"] == pytest.approx(k * 1e-3, rel=0.15)
    assert loop.localisation["findings"][0]["kind"] == "periodic_deflection"
    assert loop.final.params()["stiffness_Nm_per_rad"] == pytest.approx(k, rel=0.005)
    assert loop.final.params()["friction_torque_Nm"] == pytest.approx(0.9, rel=0.1)


def test_a_true_stiffening_beside_friction_is_no_ripple():
    # a 10 % cubic (K·0.1·θ³/θ_max²) and the same friction, no ripple: a sinusoid of 1.2
    # periods or more describes a cubic to a few per cent only, and never replaces it
    k, t, torque, meas = ripple_record(3, ecc_rad=0.0, cubic=0.1 / 0.3 ** 2)
    loop = fit_record(make_record(t, torque, meas)).loop
    assert loop.nuisance is None
    assert {"stiffening", "hysteresis"} <= set(loop.final.effects)
    assert loop.final.params()["stiffness_Nm_per_rad"] == pytest.approx(k, rel=0.01)


@pytest.mark.parametrize("rms", [0.1, 0.25, 0.6])
def test_the_structure_a_law_leaves_is_read_back_from_its_criterion(rms):
    # criterion n·ln(SSE): a law that leaves structure of RMS ρ noise levels has SSE
    # (1 + ρ²) times the other's, so loses by n·ln(1 + ρ²)
    n_eff = 7500.0
    assert left_rms_over_noise(n_eff * math.log1p(rms ** 2), n_eff) == pytest.approx(rms)
    assert left_rms_over_noise(-3.0, n_eff) == 0.0
