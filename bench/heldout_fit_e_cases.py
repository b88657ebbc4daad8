"""Generator E's cases: physics, protocol, sampling, file format and truth of each record.

Every builder takes the seed's generator and returns a ``Case``; its truth is fixed here
(and, for physics outside the library, by the oracle on the clean channels) before any fit
runs. Truth fields:

- ``alternatives``: the acceptable sets of required library effects (one set, or several
  when the protocol cannot separate a pair: a confounded pair lists {A}, {B} and {A, B});
- ``optional``: effects that may be named or not (an offset beside a drift, whose zero is
  a convention; a cubic beside a hard stop or a clipping sensor, a hardening by another law;
  friction or a lag beside a relaxation, whose loop is rate-dependent; a lag beside a
  viscous part of a LuGre friction);
- ``unexplained``: True, False, or "oracle" (decided by ``heldout_fit_e_oracle``);
- ``k_check``: K within 2 % is required (only records whose physics is all in the library);
  ``k_truth`` lists the acceptable K (asymmetric: either side, their mean or harmonic mean,
  as which one a fit calls K is a convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from heldout_fit_e_sim import Physics, chirp, random_levels, sine_sweep, staircase, triangles

RAD_COLS = ("time_s", "torque_Nm", "deflection_rad")


@dataclass
class Case:
    name: str
    physics: Physics
    protocol: object
    fs_hz: float
    alternatives: list
    optional: set = field(default_factory=set)
    unexplained: object = False
    k_check: bool = True
    k_truth: list = field(default_factory=list)
    hints: dict = field(default_factory=dict)
    cols: tuple = RAD_COLS
    angle_unit: str = "rad"
    torque_unit: str = "Nm"
    note: str = ""


def _K(rng):
    return float(math.exp(rng.uniform(math.log(10.0), math.log(2000.0))))


def _noise(rng, ph, amax, frac=None, sigma_th=None, rho=0.0):
    """Torque noise 0.1-1 % of the peak torque (frac), angle noise 1e-5..3e-4 rad."""
    peak = ph.K * amax
    ph.sigma_T = peak * (frac if frac is not None else math.exp(rng.uniform(math.log(1e-3), math.log(6e-3))))
    ph.sigma_th = sigma_th if sigma_th is not None else math.exp(rng.uniform(math.log(1e-5), math.log(3e-4)))
    ph.rho_T = rho
    return ph


def _amax(rng, lo=0.2, hi=0.6):
    return float(rng.uniform(lo, hi))


def _stairs(rng, amax, shape="cos", hold=(0.5, 1.5)):
    n = int(rng.integers(3, 6))
    amps = np.linspace(amax / n, amax, n)
    return staircase(amps, rate_rad_per_s=rng.uniform(0.15, 0.5) * amax / 0.3, hold_s=rng.uniform(*hold), shape=shape)


def _sines(rng, amax, freqs=(0.1, 0.3, 1.0), cycles=3):
    blocks = []
    for f in freqs:
        for a in (0.5 * amax, amax):
            blocks.append((a, f * rng.uniform(0.9, 1.1), cycles))
    return sine_sweep(blocks)


def _hyst(rng, K, amax, lo=0.01, hi=0.03):
    return {"H": float(K * amax * rng.uniform(lo, hi)), "pre": float(rng.uniform(1e-3, 4e-3))}


def _case(name, ph, proto, fs, req, **kw):
    nested = bool(req) and all(isinstance(a, (list, tuple, set)) for a in req)
    alts = [set(a) for a in req] if nested else [set(req)]
    c = Case(name, ph, proto, fs, alts, **kw)
    if not c.k_truth:
        c.k_truth = [ph.K]
    c.hints.setdefault("K", ph.K)
    return c


# ----------------------------------------------------------------- library effects alone
def linear_staircase(rng):
    K, a = _K(rng), _amax(rng)
    return _case("linear_staircase", _noise(rng, Physics(K), a), _stairs(rng, a), 500, [])


def backlash_staircase(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, backlash_rad=rng.uniform(5e-3, 3e-2)), a)
    return _case("backlash_staircase", ph, _stairs(rng, a), 1000, ["backlash"])


def hysteresis_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, friction="ep", fr=_hyst(rng, K, a)), a)
    return _case("hysteresis_sines", ph, _sines(rng, a), 500, ["hysteresis"])


def lag_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, lag_s=rng.uniform(0.005, 0.03)), a)
    return _case("lag_sines", ph, _sines(rng, a, freqs=(0.2, 0.7, 2.0), cycles=4), 1000, ["time_lag"])


def drift_triangles(rng):
    K, a = _K(rng), _amax(rng)
    proto = triangles(a, [0.3 * a, 1.0 * a], 3)
    ph = Physics(K, drift=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03) / proto.duration_s)
    return _case("drift_triangles", _noise(rng, ph, a), proto, 500, ["drift"], optional={"torque_offset"})


def torque_offset_levels(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, torque_offset=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.04))
    proto = random_levels(rng, 14, a, 0.4 * a, (0.5, 2.0))
    return _case("torque_offset_levels", _noise(rng, ph, a), proto, 500, ["torque_offset"])


def angle_offset_linear(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, angle_offset=rng.choice([-1, 1]) * rng.uniform(5e-3, 2e-2)), a)
    return _case("angle_offset_linear", ph, _stairs(rng, a), 500,
                 [["angle_offset"], ["torque_offset"], ["angle_offset", "torque_offset"]],
                 note="on a linear spring an angle zero error is a torque zero error: confounded")


def angle_offset_backlash(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(1e-2, 3e-2), angle_offset=rng.choice([-1, 1]) * rng.uniform(4e-3, 1.5e-2))
    return _case("angle_offset_backlash", _noise(rng, ph, a), _stairs(rng, a), 1000, ["backlash", "angle_offset"])


def stiffening_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, k3=K * rng.uniform(0.05, 0.15) / a**2), a)
    return _case("stiffening_sines", ph, _sines(rng, a, freqs=(0.1, 0.4)), 500, ["stiffening"])


def asymmetric_staircase(rng):
    K, a = _K(rng), _amax(rng)
    Kn = K * rng.uniform(0.8, 0.93)
    ph = _noise(rng, Physics(K, K_neg=Kn), a)
    return _case("asymmetric_staircase", ph, _stairs(rng, a), 500, ["asymmetric_stiffness"],
                 k_truth=[K, Kn, (K + Kn) / 2, 2 * K * Kn / (K + Kn)], hints={"Kn": Kn})


def outliers_torque_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K), a)
    ph.spikes_T = (int(rng.integers(15, 40)), K * a * rng.uniform(0.05, 0.12))
    return _case("outliers_torque_sines", ph, _sines(rng, a), 500, ["outliers"])


def outliers_angle_levels(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K), a)
    ph.spikes_th = (int(rng.integers(15, 40)), rng.uniform(0.02, 0.05))
    proto = random_levels(rng, 14, a, 0.4 * a, (0.5, 2.0))
    return _case("outliers_angle_levels", ph, proto, 500, ["outliers"])


def angle_drift_staircase(rng):
    K, a = _K(rng), _amax(rng)
    proto = _stairs(rng, a)
    ph = Physics(K, angle_drift=rng.choice([-1, 1]) * rng.uniform(5e-3, 1.5e-2) / proto.duration_s)
    return _case("angle_drift_staircase", _noise(rng, ph, a), proto, 500, ["drift"],
                 optional={"torque_offset", "angle_offset"})


# ----------------------------------------------------------------- pairs
def backlash_hysteresis_staircase(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(5e-3, 3e-2), friction="ep", fr=_hyst(rng, K, a))
    return _case("backlash_hysteresis_staircase", _noise(rng, ph, a), _stairs(rng, a), 1000,
                 ["backlash", "hysteresis"])


def hysteresis_lag_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, friction="ep", fr=_hyst(rng, K, a), lag_s=rng.uniform(0.008, 0.03))
    return _case("hysteresis_lag_sines", _noise(rng, ph, a), _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000,
                 ["hysteresis", "time_lag"])


def hysteresis_lag_one_rate(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, friction="ep", fr=_hyst(rng, K, a), lag_s=rng.uniform(0.01, 0.03))
    proto = triangles(a, [rng.uniform(0.3, 0.8) * a], 8)
    return _case("hysteresis_lag_one_rate", _noise(rng, ph, a), proto, 1000,
                 [["hysteresis"], ["time_lag"], ["hysteresis", "time_lag"]],
                 note="Coulomb friction and a delay on one ramp rate without holds: confounded")


def hysteresis_lag_two_rates(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, friction="ep", fr=_hyst(rng, K, a), lag_s=rng.uniform(0.01, 0.03))
    proto = triangles(a, [0.25 * a, 1.2 * a], 4, hold_s=0.5)
    return _case("hysteresis_lag_two_rates", _noise(rng, ph, a), proto, 1000, ["hysteresis", "time_lag"])


def stiffening_asymmetric_levels(rng):
    K, a = _K(rng), _amax(rng)
    Kn = K * rng.uniform(0.8, 0.92)
    ph = _noise(rng, Physics(K, K_neg=Kn, k3=K * rng.uniform(0.06, 0.15) / a**2), a)
    proto = random_levels(rng, 20, a, 0.5 * a, (0.4, 1.5))
    return _case("stiffening_asymmetric_levels", ph, proto, 500, ["stiffening", "asymmetric_stiffness"],
                 k_truth=[K, Kn, (K + Kn) / 2, 2 * K * Kn / (K + Kn)], hints={"Kn": Kn})


def drift_backlash_staircase(rng):
    K, a = _K(rng), _amax(rng)
    proto = _stairs(rng, a)
    ph = Physics(K, backlash_rad=rng.uniform(8e-3, 3e-2),
                 drift=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03) / proto.duration_s)
    return _case("drift_backlash_staircase", _noise(rng, ph, a), proto, 500, ["drift", "backlash"],
                 optional={"torque_offset"})


def lag_stiffening_chirp(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, lag_s=rng.uniform(0.005, 0.02), k3=K * rng.uniform(0.06, 0.15) / a**2)
    return _case("lag_stiffening_chirp", _noise(rng, ph, a), chirp(a, 0.05, 1.5, rng.uniform(30, 60)), 1000,
                 ["time_lag", "stiffening"])


def offset_hysteresis_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, friction="ep", fr=_hyst(rng, K, a), torque_offset=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03))
    return _case("offset_hysteresis_sines", _noise(rng, ph, a), _sines(rng, a), 500, ["torque_offset", "hysteresis"])


def outliers_lag_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, lag_s=rng.uniform(0.01, 0.03)), a)
    ph.spikes_T = (int(rng.integers(15, 40)), K * a * rng.uniform(0.05, 0.12))
    return _case("outliers_lag_sines", ph, _sines(rng, a, freqs=(0.2, 0.6, 1.5)), 1000, ["outliers", "time_lag"])


def backlash_lag_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(8e-3, 3e-2), lag_s=rng.uniform(0.008, 0.03))
    return _case("backlash_lag_sines", _noise(rng, ph, a), _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000,
                 ["backlash", "time_lag"])


# ----------------------------------------------------------------- triples
def backlash_hysteresis_lag_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(8e-3, 3e-2), friction="ep", fr=_hyst(rng, K, a),
                 lag_s=rng.uniform(0.01, 0.03))
    return _case("backlash_hysteresis_lag_sines", _noise(rng, ph, a), _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000,
                 ["backlash", "hysteresis", "time_lag"])


def stiffening_drift_outliers_staircase(rng):
    K, a = _K(rng), _amax(rng)
    proto = _stairs(rng, a)
    ph = Physics(K, k3=K * rng.uniform(0.06, 0.15) / a**2,
                 drift=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03) / proto.duration_s)
    _noise(rng, ph, a)
    ph.spikes_T = (int(rng.integers(15, 40)), K * a * rng.uniform(0.05, 0.12))
    return _case("stiffening_drift_outliers_staircase", ph, proto, 500, ["stiffening", "drift", "outliers"],
                 optional={"torque_offset"})


def asymmetric_hysteresis_offset_levels(rng):
    K, a = _K(rng), _amax(rng)
    Kn = K * rng.uniform(0.8, 0.92)
    ph = Physics(K, K_neg=Kn, friction="ep", fr=_hyst(rng, K, a),
                 torque_offset=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03))
    proto = random_levels(rng, 20, a, 0.5 * a, (0.4, 1.5))
    return _case("asymmetric_hysteresis_offset_levels", _noise(rng, ph, a), proto, 500,
                 ["asymmetric_stiffness", "hysteresis", "torque_offset"],
                 k_truth=[K, Kn, (K + Kn) / 2, 2 * K * Kn / (K + Kn)], hints={"Kn": Kn})


def backlash_stiffening_angle_offset(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(1e-2, 3e-2), k3=K * rng.uniform(0.06, 0.15) / a**2,
                 angle_offset=rng.choice([-1, 1]) * rng.uniform(4e-3, 1.5e-2))
    return _case("backlash_stiffening_angle_offset", _noise(rng, ph, a), _stairs(rng, a), 1000,
                 ["backlash", "stiffening", "angle_offset"])


def stack2_backlash_hysteresis(rng):
    # two springs in series, each with its own play: K = K1 K2/(K1+K2), gap b1 + b2
    K1, K2, a = _K(rng), _K(rng), _amax(rng, 0.6, 1.2)
    K = K1 * K2 / (K1 + K2)
    b = rng.uniform(4e-3, 1.5e-2) + rng.uniform(4e-3, 1.5e-2)
    ph = Physics(K, backlash_rad=b, friction="ep", fr=_hyst(rng, K, a))
    return _case("stack2_backlash_hysteresis", _noise(rng, ph, a), _stairs(rng, a), 500, ["backlash", "hysteresis"])


# ----------------------------------------------------------------- noise, sampling, units
def coloured_noise_hysteresis(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, friction="ep", fr=_hyst(rng, K, a, 0.015, 0.03)), a, rho=rng.uniform(0.8, 0.95))
    return _case("coloured_noise_hysteresis", ph, _sines(rng, a), 500, ["hysteresis"])


def quantised_backlash_staircase(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, backlash_rad=rng.uniform(8e-3, 3e-2)), a, sigma_th=0.0)
    ph.counts_per_rev = int(rng.choice([2**15, 2**16, 2**17]))
    return _case("quantised_backlash_staircase", ph, _stairs(rng, a), 1000, ["backlash"])


def deg_nmm_backlash_lag(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, backlash_rad=rng.uniform(8e-3, 3e-2), lag_s=rng.uniform(0.008, 0.03))
    return _case("deg_nmm_backlash_lag", _noise(rng, ph, a), _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000,
                 ["backlash", "time_lag"], cols=("t_s", "T_Nmm", "angle_deg"), angle_unit="deg", torque_unit="Nmm")


def deg_stiffening_levels(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, k3=K * rng.uniform(0.06, 0.15) / a**2), a)
    proto = random_levels(rng, 18, a, 0.5 * a, (0.4, 1.5))
    return _case("deg_stiffening_levels", ph, proto, 250, ["stiffening"], cols=("time", "torque", "theta_deg"),
                 angle_unit="deg")


def fast_short_lag_stiffening(rng):
    K, a = _K(rng), _amax(rng)
    ph = Physics(K, lag_s=rng.uniform(0.002, 0.006), k3=K * rng.uniform(0.06, 0.15) / a**2)
    proto = sine_sweep([(0.5 * a, 1.0, 3), (a, 1.0, 3), (a, 2.0, 6)])
    return _case("fast_short_lag_stiffening", _noise(rng, ph, a), proto, 5000, ["time_lag", "stiffening"])


def slow_long_drift_hysteresis(rng):
    K, a = _K(rng), _amax(rng)
    amps = np.linspace(a / 6, a, 6)
    proto = staircase(amps, rate_rad_per_s=0.05 * a / 0.3, hold_s=2.5, shape="cos")
    ph = Physics(K, friction="ep", fr=_hyst(rng, K, a),
                 drift=rng.choice([-1, 1]) * K * a * rng.uniform(0.01, 0.03) / proto.duration_s)
    return _case("slow_long_drift_hysteresis", _noise(rng, ph, a), proto, 200, ["drift", "hysteresis"],
                 optional={"torque_offset"})


def nmm_asymmetric_hysteresis_triangles(rng):
    K, a = _K(rng), _amax(rng)
    Kn = K * rng.uniform(0.8, 0.92)
    ph = Physics(K, K_neg=Kn, friction="ep", fr=_hyst(rng, K, a))
    proto = triangles(a, [0.4 * a, 1.0 * a], 4, hold_s=0.4)
    return _case("nmm_asymmetric_hysteresis_triangles", _noise(rng, ph, a), proto, 1000,
                 ["asymmetric_stiffness", "hysteresis"], k_truth=[K, Kn, (K + Kn) / 2, 2 * K * Kn / (K + Kn)],
                 hints={"Kn": Kn}, cols=("time_s", "torque_Nmm", "deflection_rad"), torque_unit="Nmm")
