"""Generator E's cases with physics the library does not model in the same law.

``unexplained="oracle"``: the flag expected is decided by the oracle on the clean channels
(see ``heldout_fit_e_oracle``); ``k_check`` is off (the truth K of a law outside the library
is not what a library law reports). Names of library effects in the truth are those whose
meaning (FIT_PHYSICS.md) covers the physics: a friction law of any kind is ``hysteresis``;
a first-order sensor filter or a viscous damper (torque ahead/behind the angle in
proportion to the rate) is ``time_lag``; a gap with a Hertzian take-up is ``backlash``; a
settling zero is ``drift``. Hard stops, clipping, relaxation, ripple, a stiffness step, a
temperature-dependent K and hum have no library name.
"""

from __future__ import annotations

import math

from heldout_fit_e_cases import _K, _amax, _case, _hyst, _noise, _sines, _stairs
from heldout_fit_e_sim import Physics, random_levels, triangles

OUT = {"unexplained": "oracle", "k_check": False}


def _lugre(rng, K, a, stribeck=(1.3, 2.0), vs=(0.01, 0.05), viscous_frac=0.2, v_typ=1.0):
    Fc = K * a * rng.uniform(0.01, 0.025)
    s0 = Fc / rng.uniform(1e-3, 3e-3)
    return {"Fc": Fc, "Fs": Fc * rng.uniform(*stribeck), "vs": rng.uniform(*vs), "sigma0": s0,
            "sigma1": 2 * math.sqrt(s0) * 0.01, "sigma2": viscous_frac * Fc / v_typ}


def lugre_sines(rng):
    K, a = _K(rng), _amax(rng)
    fr = _lugre(rng, K, a, v_typ=2 * math.pi * 0.5 * a)
    ph = _noise(rng, Physics(K, friction="lugre", fr=fr), a)
    return _case("lugre_sines", ph, _sines(rng, a), 1000, ["hysteresis"], optional={"time_lag"},
                 hints={"H": fr["Fc"], "pre": fr["Fc"] / fr["sigma0"]}, **OUT)


def stribeck_three_rates(rng):
    K, a = _K(rng), _amax(rng)
    rates = [0.05 * a, 0.3 * a, 1.2 * a]
    fr = _lugre(rng, K, a, stribeck=(2.0, 3.0), vs=(0.03 * a, 0.08 * a), viscous_frac=0.05, v_typ=rates[-1])
    ph = _noise(rng, Physics(K, friction="lugre", fr=fr), a)
    proto = triangles(a, rates, 2, hold_s=0.5)
    return _case("stribeck_three_rates", ph, proto, 500, ["hysteresis"], optional={"time_lag"},
                 hints={"H": fr["Fc"], "pre": fr["Fc"] / fr["sigma0"]}, **OUT)


def dahl_two_rates(rng):
    K, a = _K(rng), _amax(rng)
    fr = {"H": K * a * rng.uniform(0.015, 0.03), "pre": rng.uniform(0.01, 0.03)}
    ph = _noise(rng, Physics(K, friction="dahl", fr=fr), a)
    proto = triangles(a, [0.3 * a, 1.0 * a], 3)
    return _case("dahl_two_rates", ph, proto, 1000, ["hysteresis"], hints=dict(fr), **OUT)


def tanh_sines(rng):
    K, a = _K(rng), _amax(rng)
    fr = {"H": K * a * rng.uniform(0.01, 0.03), "v0": rng.uniform(0.005, 0.02)}
    ph = _noise(rng, Physics(K, friction="tanh", fr=fr), a)
    return _case("tanh_sines", ph, _sines(rng, a), 500, ["hysteresis"], hints={"H": fr["H"], "pre": 0.003}, **OUT)


def tanh_staircase_cos(rng):
    K, a = _K(rng), _amax(rng)
    fr = {"H": K * a * rng.uniform(0.01, 0.03), "v0": rng.uniform(0.005, 0.02)}
    ph = _noise(rng, Physics(K, friction="tanh", fr=fr), a)
    return _case("tanh_staircase_cos", ph, _stairs(rng, a, shape="cos"), 500, ["hysteresis"],
                 hints={"H": fr["H"], "pre": 0.003}, **OUT,
                 note="friction that lets go in holds on cosine ramps (varying speed)")


def tanh_one_rate_linear(rng):
    K, a = _K(rng), _amax(rng)
    fr = {"H": K * a * rng.uniform(0.01, 0.03), "v0": rng.uniform(0.005, 0.01)}
    ph = _noise(rng, Physics(K, friction="tanh", fr=fr), a)
    proto = _stairs(rng, a, shape="lin")
    rate = abs(proto.pieces[1][3] - proto.pieces[1][2]) / (proto.pieces[1][1] - proto.pieces[1][0])
    return _case("tanh_one_rate_linear", ph, proto, 500, [["hysteresis"], ["time_lag"], ["hysteresis", "time_lag"]],
                 hints={"H": fr["H"], "pre": 0.003, "tau": -fr["H"] / (K * rate)}, **OUT,
                 note="H tanh(v/v0) at one speed, zero in holds, equals a damper c v: confounded")


def filter_staircase(rng):
    K, a = _K(rng), _amax(rng)
    tf = rng.uniform(0.01, 0.03)
    ph = _noise(rng, Physics(K, filter_s=tf), a)
    return _case("filter_staircase", ph, _stairs(rng, a, shape="lin"), 1000, ["time_lag"], hints={"tau": tf}, **OUT)


def filter_sines(rng):
    K, a = _K(rng), _amax(rng)
    tf = rng.uniform(0.005, 0.02)
    ph = _noise(rng, Physics(K, filter_s=tf), a)
    return _case("filter_sines", ph, _sines(rng, a, freqs=(0.1, 0.4, 1.0)), 1000, ["time_lag"], hints={"tau": tf}, **OUT)


def filter_backlash_staircase(rng):
    K, a = _K(rng), _amax(rng)
    tf, b = rng.uniform(0.01, 0.03), rng.uniform(8e-3, 3e-2)
    ph = _noise(rng, Physics(K, filter_s=tf, backlash_rad=b), a)
    return _case("filter_backlash_staircase", ph, _stairs(rng, a, shape="lin"), 1000, ["time_lag", "backlash"],
                 hints={"tau": tf, "b": b}, **OUT)


def viscous_sines(rng):
    K, a = _K(rng), _amax(rng)
    c = K * rng.uniform(0.005, 0.02)
    ph = _noise(rng, Physics(K, viscous=c), a)
    return _case("viscous_sines", ph, _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000, ["time_lag"],
                 hints={"tau": -c / K}, **OUT)


def hertz_backlash_staircase(rng):
    K, a = _K(rng), _amax(rng)
    b = rng.uniform(8e-3, 3e-2)
    hc = b * rng.uniform(0.3, 1.0)
    ph = _noise(rng, Physics(K, backlash_rad=b, hertz_contact_rad=hc), a)
    return _case("hertz_backlash_staircase", ph, _stairs(rng, a), 1000, ["backlash"], hints={"b": b + hc}, **OUT)


def hardstop_sines(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, hardstop_rad=a * rng.uniform(0.75, 0.9), hardstop_K=K * rng.uniform(3, 10)), a)
    return _case("hardstop_sines", ph, _sines(rng, a, freqs=(0.1, 0.4)), 500, [], optional={"stiffening"}, **OUT)


def clipping_triangles(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, clip_Nm=K * a * rng.uniform(0.8, 0.9)), a)
    proto = triangles(a, [0.3 * a, 0.8 * a], 3)
    return _case("clipping_triangles", ph, proto, 500, [], optional={"stiffening"}, **OUT)


def relaxation_staircase(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, relax=(K * rng.uniform(0.05, 0.12), rng.uniform(0.3, 1.5))), a)
    return _case("relaxation_staircase", ph, _stairs(rng, a, hold=(2.0, 3.0)), 500, [],
                 optional={"hysteresis", "time_lag"}, **OUT)


def stickslip_two_rates(rng):
    K, a = _K(rng), _amax(rng)
    Fc = K * a * rng.uniform(0.01, 0.025)
    fr = {"Fc": Fc, "dF": Fc * rng.uniform(0.5, 1.0), "lam": rng.uniform(5e-3, 2e-2), "pre": 2e-3}
    ph = _noise(rng, Physics(K, friction="stickslip", fr=fr), a)
    proto = triangles(a, [0.3 * a, 1.0 * a], 3)
    return _case("stickslip_two_rates", ph, proto, 1000, ["hysteresis"],
                 hints={"H": Fc + fr["dF"] / 2, "pre": 2e-3}, **OUT)


def ripple_levels(rng):
    K, a = _K(rng), _amax(rng)
    teeth = int(rng.choice([24, 28, 36]))
    ph = _noise(rng, Physics(K, ripple=(K * a * rng.uniform(0.01, 0.02), 2 * math.pi / teeth)), a)
    proto = random_levels(rng, 16, a, 0.3 * a, (0.5, 1.5))
    return _case("ripple_levels", ph, proto, 500, [], **OUT)


def kstep_triangles(rng):
    K, a = _K(rng), _amax(rng)
    proto = triangles(a, [0.3 * a, 1.0 * a], 3)
    ph = _noise(rng, Physics(K, kstep=(proto.duration_s * rng.uniform(0.4, 0.6), rng.uniform(0.85, 0.93))), a)
    return _case("kstep_triangles", ph, proto, 500, [], **OUT)


def thermal_settle_sines(rng):
    K, a = _K(rng), _amax(rng)
    proto = _sines(rng, a)
    A = rng.choice([-1, 1]) * K * a * rng.uniform(0.02, 0.05)
    tau = proto.duration_s * rng.uniform(0.1, 0.3)
    ph = _noise(rng, Physics(K, settle=(A, tau)), a)
    return _case("thermal_settle_sines", ph, proto, 500, ["drift"], optional={"torque_offset"},
                 hints={"d": A / proto.duration_s, "c": A / 2}, **OUT)


def temperature_K_staircase(rng):
    K, a = _K(rng), _amax(rng)
    proto = _stairs(rng, a)
    ph = _noise(rng, Physics(K, tempK=(rng.choice([-1, 1]) * rng.uniform(0.03, 0.06), 0.3 * proto.duration_s)), a)
    return _case("temperature_K_staircase", ph, proto, 500, [], **OUT)


def hum_hysteresis_staircase(rng):
    K, a = _K(rng), _amax(rng)
    ph = _noise(rng, Physics(K, friction="ep", fr=_hyst(rng, K, a)), a)
    ph.hum = (ph.sigma_T * rng.uniform(2.0, 4.0), float(rng.choice([50.0, 60.0])))
    return _case("hum_hysteresis_staircase", ph, _stairs(rng, a), 1000, ["hysteresis"],
                 hints=dict(ph.fr), **OUT)


def lugre_lag_deg(rng):
    K, a = _K(rng), _amax(rng)
    fr = _lugre(rng, K, a, v_typ=2 * math.pi * 0.5 * a)
    tau = rng.uniform(0.008, 0.02)
    ph = _noise(rng, Physics(K, friction="lugre", fr=fr, lag_s=tau), a)
    return _case("lugre_lag_deg", ph, _sines(rng, a, freqs=(0.1, 0.5, 1.5)), 1000, ["hysteresis", "time_lag"],
                 hints={"H": fr["Fc"], "pre": fr["Fc"] / fr["sigma0"], "tau": tau},
                 cols=("time_s", "torque_Nm", "defl_deg"), angle_unit="deg", **OUT)
