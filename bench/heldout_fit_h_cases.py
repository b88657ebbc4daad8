"""Held-out generator H: the records and their truth, decided from physics before any fit.

Each case is a function of a random generator returning a ``Case``: the bench, the file
format, and the truth. Truth fields:
- ``required``: names that must be in the named set N (final.effects + confounded); a tuple
  inside is a group of which any one member is enough (a confounded pair);
- ``optional``: names that may be in N (physically present in a form the name describes);
- ``unexplained``: True / False / None (either) / 'oracle' (decided by the oracle's E before
  any fit: >= 2000 True, <= 200 False, between None);
- ``k_true``: accepted stiffness values (N·m/rad); ``k_scored``: whether K is scored (2 %);
- ``not_both``: a pair that must not both be named as identified effects (only as one
  confounded group), for records where physics cannot separate them.
Units: rad, N·m, s.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import heldout_fit_h_sim as sim
from heldout_fit_h_sim import Bench, FileFormat, Spring, Stack

FRICTION_LAG = ("hysteresis", "time_lag")


@dataclass
class Case:
    bench: Bench
    required: list
    optional: list = field(default_factory=list)
    unexplained: object = False
    k_scored: bool = True
    k_true: list = field(default_factory=list)
    not_both: tuple | None = None
    fmt: FileFormat = field(default_factory=FileFormat)
    note: str = ""
    starts: list = field(default_factory=list)   # oracle starting points (h, a, l, delay, w)


# ----------------------------------------------------------------------------- draws


def log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def base(rng, n_springs=1, amp=None, fs=None, gaps=(0.0, 0.0)):
    """A stack, its peak deflection, rate and noise: (stack, amp rad, peak torque N·m, fs, sT, sth)."""
    k_each = [log_uniform(rng, 40, 900) for _ in range(n_springs)]
    springs = [Spring(k_pos=k, b=rng.uniform(*gaps) if gaps[1] else 0.0) for k in k_each]
    stack = Stack(springs)
    if amp is None:
        amp = rng.uniform(0.22, 0.45) if n_springs == 1 else rng.uniform(0.5, 0.9)
    fs = fs or float(rng.choice([500.0, 1000.0, 2000.0]))
    peak = stack.k_series * amp
    s_T = rng.uniform(0.0015, 0.004) * peak
    s_th = log_uniform(rng, 2e-5, 1e-4)
    return stack, amp, peak, fs, s_T, s_th


# ----------------------------------------------------------------------------- protocols


def p_prbs(amp, n_bits=22, move=(0.2, 0.45), hold=(0.5, 1.4)):
    def q(dt, rng):
        lev = sim.prbs_levels(rng, n_bits, amp)
        lev = np.append(lev, 0.0)
        return sim.moves(lev, rng.uniform(*move, lev.size), rng.uniform(*hold, lev.size), dt)
    return q


def p_multisine(amp, f0=None, harm=(1, 2, 3, 5, 8, 13), periods=2):
    def q(dt, rng):
        f = f0 or rng.uniform(0.06, 0.1)
        t = np.arange(0, periods / f, dt)
        return sim.multisine(t, amp, f, harm)
    return q


def p_triangle_rates(amp, rates=(0.25, 0.75, 2.0), cycles=2, hold=0.6):
    """Triangles +-amp at several speeds (rates in amplitudes per second), blocks apart by holds."""
    def q(dt, rng):
        lev, sp, ho = [], [], []
        for r in rates:
            for _ in range(cycles):
                lev += [amp, -amp]
                sp += [r * amp, r * amp]
                ho += [0.0, 0.0]
            lev.append(0.0)
            sp.append(r * amp)
            ho.append(hold)
        return sim.linear_moves(lev, sp, ho, dt)
    return q


def p_trapezoid(amp, speed_amp=0.5, hold=(2.0, 4.0), cycles=2):
    """Trapezoids 0 -> +amp -> 0 -> -amp -> 0, one ramp speed (amp/s), long holds everywhere."""
    def q(dt, rng):
        lev = [amp, 0.0, -amp, 0.0] * cycles
        return sim.linear_moves(lev, speed_amp * amp, rng.uniform(*hold, len(lev)), dt)
    return q


def p_logchirp(amp, f1=0.05, f2=1.5, dur=30.0):
    def q(dt, rng):
        return sim.log_chirp(np.arange(0, dur, dt), amp, f1, f2)
    return q


def p_jog(amp, dur=28.0, speed=1.2):
    def q(dt, rng):
        return sim.jog(rng, np.arange(0, dur, dt), amp, speed * amp)
    return q


def p_sawtooth(amp, fast=2.0, slow=0.4, cycles=3, fracs=(0.5, 0.75, 1.0)):
    """Loading fast, unloading slow (amp/s), to growing levels each way."""
    def q(dt, rng):
        lev, sp, ho = [], [], []
        for f in fracs:
            for s in (1, -1):
                lev += [s * f * amp, 0.0]
                sp += [fast * amp, slow * amp]
                ho += [0.3, 0.3]
        return sim.linear_moves(lev * (cycles // 2 + 1), sp * (cycles // 2 + 1), ho * (cycles // 2 + 1), dt)
    return q


def p_staircase(amp, steps=4, move=0.5, hold=1.5):
    def q(dt, rng):
        lev = []
        for k in range(1, steps + 1):
            lev += [k / steps * amp, 0.0, -k / steps * amp, 0.0]
        return sim.moves(lev, move, hold, dt)
    return q


def bench(stack, fs, q, s_T, s_th, **kw) -> Bench:
    return Bench(stack=stack, fs=fs, q=q, sigma_T=s_T, sigma_th=s_th, **kw)


# ----------------------------------------------------------------------------- library alone


def linear_prbs(rng):
    st, A, P, fs, sT, sth = base(rng)
    return Case(bench(st, fs, p_prbs(A), sT, sth), [], k_true=[st.k_series])


def backlash_stack3_multisine(rng):
    st, A, P, fs, sT, sth = base(rng, 3, gaps=(0.008, 0.015))
    b = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_multisine(A), sT, sth), ["backlash"], k_true=[st.k_series],
                starts=[(b / 2, 0, 1e-4, 0, 0.003)], note=f"total clearance {b:.4f} rad")


def dahl_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.04) * P, "w": rng.uniform(0.002, 0.006)}
    return Case(bench(st, fs, p_trapezoid(A, 0.6), sT, sth, friction=fr), ["hysteresis"],
                k_true=[st.k_series])


def delay_logchirp(rng):
    st, A, P, fs, sT, sth = base(rng)
    return Case(bench(st, fs, p_logchirp(A), sT, sth, delay_s=rng.uniform(0.008, 0.02)),
                ["time_lag"], k_true=[st.k_series])


def damper_jog(rng):
    st, A, P, fs, sT, sth = base(rng)
    c = rng.uniform(0.02, 0.04) * P / (1.2 * A)  # c * rms speed ~ 2-4 % of the peak torque
    return Case(bench(st, fs, p_jog(A), sT, sth, damper=c), ["time_lag"], k_true=[st.k_series],
                note="viscous damper = time_lag's damping law (README)")


def drift_sawtooth(rng):
    st, A, P, fs, sT, sth = base(rng)
    b = bench(st, fs, p_sawtooth(A), sT, sth, drift_per_s=rng.choice([-1, 1]) * rng.uniform(0.02, 0.04) * P / 25)
    return Case(b, ["drift"], ["torque_offset"], k_true=[st.k_series])


def offset_triangle_rates(rng):
    st, A, P, fs, sT, sth = base(rng)
    b = bench(st, fs, p_triangle_rates(A), sT, sth, torque_offset=rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * P)
    return Case(b, [("torque_offset", "angle_offset")], k_true=[st.k_series],
                note="a linear spring: an angle offset d is exactly a torque offset -K d")


def offcentre_backlash_prbs(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    c = rng.choice([-1, 1]) * rng.uniform(0.004, 0.008)
    st.springs[0].c = c
    b = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_prbs(A), sT, sth), ["backlash", "angle_offset"],
                ["torque_offset"], k_true=[st.k_series], starts=[(b / 2, c, 1e-4, 0, 0.003)])


def stiffening_multisine(rng):
    st, A, P, fs, sT, sth = base(rng)
    g = rng.uniform(0.08, 0.2)  # torque gain at the peak over the linear part
    st.springs[0].k3 = g * st.springs[0].k_pos / A ** 2
    return Case(bench(st, fs, p_multisine(A), sT, sth), ["stiffening"], k_true=[st.k_series])


def asymmetric_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    r = rng.choice([rng.uniform(0.85, 0.92), rng.uniform(1.08, 1.15)])
    st.springs[0].k_neg = st.springs[0].k_pos * r
    kp, kn = st.springs[0].k_pos, st.springs[0].k_neg
    return Case(bench(st, fs, p_trapezoid(A, 0.8, hold=(1.0, 2.0)), sT, sth),
                ["asymmetric_stiffness"], k_true=[kp, kn, 0.5 * (kp + kn)])


def spikes_jog(rng):
    st, A, P, fs, sT, sth = base(rng)
    return Case(bench(st, fs, p_jog(A), sT, sth, spikes=int(rng.integers(15, 30))), ["outliers"],
                k_true=[st.k_series])


def equal_antialias_offset(rng):
    st, A, P, fs, sT, sth = base(rng, fs=1000.0)
    fc = rng.uniform(20, 60)
    b = bench(st, fs, p_multisine(A), sT, sth, aa_torque_hz=fc, aa_angle_hz=fc,
              torque_offset=rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * P)
    return Case(b, [("torque_offset", "angle_offset")], k_true=[st.k_series],
                note=f"the same {fc:.0f} Hz Butterworth on both channels: a linear spring's "
                     "torque is K times the filtered angle exactly; no lag")


# ----------------------------------------------------------------------------- library, together


def backlash_dahl_delay_tri3(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.008, 0.016))
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    d = rng.uniform(0.02, 0.035)
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_triangle_rates(A, rates=(0.3, 0.9, 2.4)), sT, sth, friction=fr, delay_s=d),
                ["backlash", "hysteresis", "time_lag"], k_true=[st.k_series],
                starts=[(bl / 2, 0, 1e-4, d, fr["w"])], note="issue 24 class 1, three rates")


def offcentre_drift_dahl_prbs(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.018))
    c = rng.choice([-1, 1]) * rng.uniform(0.004, 0.008)
    st.springs[1].c = c
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    b = bench(st, fs, p_prbs(A, n_bits=26), sT, sth, friction=fr,
              drift_per_s=rng.choice([-1, 1]) * rng.uniform(0.02, 0.035) * P / 30)
    bl = sum(s.b for s in st.springs)
    return Case(b, ["backlash", "angle_offset", "drift", "hysteresis"], ["torque_offset"],
                k_true=[st.k_series], starts=[(bl / 2, c, 1e-4, 0, fr["w"])])


def asym_cubic_delay_logchirp(rng):
    st, A, P, fs, sT, sth = base(rng)
    s = st.springs[0]
    s.k_neg = s.k_pos * rng.choice([0.88, 1.12])
    s.k3 = rng.uniform(0.1, 0.2) * s.k_pos / A ** 2
    d = rng.uniform(0.01, 0.02)
    return Case(bench(st, fs, p_logchirp(A), sT, sth, delay_s=d),
                ["asymmetric_stiffness", "stiffening", "time_lag"],
                k_true=[s.k_pos, s.k_neg, 0.5 * (s.k_pos + s.k_neg)], starts=[(0, 0, 1e-4, d, 0.003)])


def backlash_damper_offset_jog(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    c = rng.uniform(0.025, 0.04) * P / (1.2 * A)
    b = bench(st, fs, p_jog(A), sT, sth, damper=c,
              torque_offset=rng.choice([-1, 1]) * rng.uniform(0.015, 0.03) * P)
    bl = sum(s.b for s in st.springs)
    return Case(b, ["backlash", "time_lag", "torque_offset"], k_true=[st.k_series],
                starts=[(bl / 2, 0, 1e-4, 0, 0.003)])


def dahl_viscous_multisine(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    c = rng.uniform(0.02, 0.035) * P / (A * 2 * np.pi * 0.4)
    return Case(bench(st, fs, p_multisine(A), sT, sth, friction=fr, damper=c),
                ["hysteresis", "time_lag"], k_true=[st.k_series],
                note="many speeds: a friction and a damper are told apart")


def deg_nmm_backlash_dahl_sawtooth(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    fmt = FileFormat(time_col="t", torque_col="T_Nmm", deflection_col="angle_deg", angle_unit="deg",
                     torque_unit="Nmm", order=("time", "deflection", "torque"),
                     extras=("temp_C", "motor_current_A"),
                     comments=("# rig 2, torsion stack, logged by daq v3", "# units: s, deg, N.mm"))
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_sawtooth(A), sT, sth, friction=fr), ["backlash", "hysteresis"],
                k_true=[st.k_series], fmt=fmt, starts=[(bl / 2, 0, 1e-4, 0, fr["w"])])


def unix_crlf_backlash_offset(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02), fs=500.0)
    fmt = FileFormat(order=("deflection", "torque", "time"), extras=("temp_C",), crlf=True,
                     t0=1764288000.0 + float(rng.integers(0, 86400)))
    b = bench(st, fs, p_staircase(A), sT, sth, torque_offset=rng.choice([-1, 1]) * rng.uniform(0.015, 0.03) * P)
    bl = sum(s.b for s in st.springs)
    return Case(b, ["backlash", "torque_offset"], k_true=[st.k_series], fmt=fmt,
                starts=[(bl / 2, 0, 1e-4, 0, 0.003)], note="Unix timestamps, CRLF, columns reordered")


# ----------------------------------------------------------------------------- family: the library's name, another law


def iwan_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "iwan", "F": rng.uniform(0.02, 0.04) * P, "w": rng.uniform(0.002, 0.006)}
    return Case(bench(st, fs, p_trapezoid(A, 0.6), sT, sth, friction=fr), ["hysteresis"],
                unexplained="oracle", k_true=[st.k_series], starts=[(0, 0, 1e-4, 0, fr["w"])],
                note="Iwan/Masing presliding friction (parabolic take-up)")


def stribeck_tri3(rng):
    st, A, P, fs, sT, sth = base(rng)
    fc = rng.uniform(0.02, 0.035) * P
    fr = {"law": "stribeck", "Fc": fc, "Fs": fc * rng.uniform(1.5, 2.0), "vs": 0.4 * A, "v0": 0.01 * A}
    return Case(bench(st, fs, p_triangle_rates(A, rates=(0.2, 0.6, 1.8)), sT, sth, friction=fr),
                ["hysteresis"], ["time_lag"], unexplained="oracle", k_true=[st.k_series],
                note="Stribeck fading with speed, zero at rest; a damper may take "
                "part of the speed dependence (time_lag optional)")


def atan_one_rate_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "atan", "F": rng.uniform(0.02, 0.04) * P, "v0": 0.02 * A}
    return Case(bench(st, fs, p_trapezoid(A, 0.6), sT, sth, friction=fr), [FRICTION_LAG],
                unexplained="oracle", k_true=[st.k_series], not_both=FRICTION_LAG,
                note="issue 24 class 2: regularised Coulomb on one ramp speed = a damper wherever "
                     "the spring moves; one confounded group, never both identified")


def atan_multisine(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "atan", "F": rng.uniform(0.02, 0.04) * P, "v0": 0.05 * A}
    return Case(bench(st, fs, p_multisine(A), sT, sth, friction=fr), ["hysteresis"], ["time_lag"],
                unexplained="oracle", k_true=[st.k_series])


def load_friction_sawtooth(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "load_dahl", "F0": 0.005 * P, "mu": rng.uniform(0.04, 0.07), "w": rng.uniform(0.002, 0.005)}
    return Case(bench(st, fs, p_sawtooth(A), sT, sth, friction=fr), ["hysteresis"], [],
                unexplained="oracle", k_true=[st.k_series], k_scored=False,
                note="cam-contact friction proportional to the transmitted torque: the loop "
                     "widens with load (loading slope K(1+mu), unloading K(1-mu))")


def angle_filter_multisine(rng):
    st, A, P, fs, sT, sth = base(rng, fs=1000.0)
    tau = rng.uniform(0.006, 0.015)
    return Case(bench(st, fs, p_multisine(A), sT, sth, angle_filter_s=tau), ["time_lag"],
                unexplained="oracle", k_true=[st.k_series], starts=[(0, 0, 1e-4, -tau, 0.003)],
                note="first-order filter on the angle: to first order a damper K tau")


def antialias_unequal_logchirp(rng):
    st, A, P, fs, sT, sth = base(rng, fs=1000.0)
    fc = rng.uniform(12, 25)
    return Case(bench(st, fs, p_logchirp(A), sT, sth, aa_torque_hz=fc, aa_angle_hz=300.0),
                ["time_lag"], unexplained="oracle", k_true=[st.k_series],
                starts=[(0, 0, 1e-4, np.sqrt(2) / (2 * np.pi * fc), 0.003)],
                note=f"2nd-order Butterworth {fc:.0f} Hz on torque, 300 Hz on angle")


def zoh_triangle(rng):
    st, A, P, fs, sT, sth = base(rng, fs=1000.0)
    zh = float(rng.choice([40.0, 50.0, 80.0]))
    return Case(bench(st, fs, p_triangle_rates(A, rates=(0.5, 1.5, 3.0)), sT, sth, zoh_hz=zh),
                ["time_lag"], unexplained="oracle", k_true=[st.k_series],
                starts=[(0, 0, 1e-4, 0.5 / zh, 0.003)],
                note=f"torque sensor updating at {zh:.0f} Hz, logged at 1 kHz: a mean lag of half "
                     "an update, a sawtooth of K speed / rate")


def flexure_engagement_prbs(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.008, 0.014))
    for s in st.springs:
        s.spread = rng.uniform(0.01, 0.02)
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_prbs(A), sT, sth), ["backlash"], ["stiffening"],
                unexplained="oracle", k_true=[st.k_series],
                starts=[(bl / 2 + 0.01, 0, 0.005, 0, 0.003)],
                note="flexure tips engage one by one (gaps spread by the EDM tolerance)")


# ----------------------------------------------------------------------------- outside the library, beside library effects


def clip_backlash_prbs(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    rail = rng.uniform(0.78, 0.88) * P
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_prbs(A), sT, sth, rail=rail), ["backlash"], ["stiffening"],
                unexplained=True, k_true=[st.k_series], starts=[(bl / 2, 0, 1e-4, 0, 0.003)],
                note="torque ADC rails at ~83 % of the peak: flat tops")


def bumpstop_dahl_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    th_s = 0.8 * A
    k2 = rng.uniform(0.1, 0.2) * P / (0.2 * A) ** 2  # the stop adds 10-20 % of P at the peak
    return Case(bench(st, fs, p_trapezoid(A, 0.6), sT, sth, friction=fr, bump={"theta": th_s, "k2": k2}),
                ["hysteresis"], ["stiffening"], unexplained=True, k_true=[st.k_series],
                starts=[(0, 0, 1e-4, 0, fr["w"])], note="progressive elastomer stop beyond 0.8 A")


def hubslip_backlash_staircase(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    bl = sum(s.b for s in st.springs)
    slip = rng.uniform(0.7, 0.8) * P
    return Case(bench(st, fs, p_staircase(A, steps=4), sT, sth, hub_slip=slip, deflection_source="motor"),
                ["backlash"], ["angle_offset", "torque_offset", "drift", "hysteresis"], unexplained=True,
                k_true=[st.k_series], starts=[(bl / 2, 0, 1e-4, 0, 0.003)],
                note="a clamped hub slips above ~75 % of the peak; the deflection is the motor "
                     "encoder, so the zero moves at each slip")


def torquefilter_backlash_multisine(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.015, 0.025), fs=1000.0)
    tau = rng.uniform(0.012, 0.025)
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_multisine(A), sT, sth, torque_filter_s=tau), ["backlash", "time_lag"],
                unexplained="oracle", k_true=[st.k_series], starts=[(bl / 2, 0, 1e-4, tau, 0.003)],
                note="issue 24 class 3: a first-order torque filter beside a 0.03-0.05 rad clearance; "
                     "the filter has unit DC gain, so K is the stack's")


def creep_coupling_delay_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    K = st.k_series
    d = rng.uniform(0.01, 0.02)
    return Case(bench(st, fs, p_trapezoid(A, 0.8), sT, sth, creep={"k": 8 * K, "tau": rng.uniform(0.6, 1.5)},
                      delay_s=d, deflection_source="motor"),
                ["time_lag"], ["hysteresis", "drift"], unexplained=True, k_scored=False,
                k_true=[K * 8 / 9], starts=[(0, 0, 1e-4, d, 0.003)],
                note="a creeping (Kelvin) coupling in series, read by the motor encoder: the torque "
                     "relaxes in holds; K between K and 8K/9 depending on the time scale")


def preload_pair_drift_triangle(rng):
    st, A, P, fs, sT, sth = base(rng)
    tp = rng.uniform(0.08, 0.15) * A
    b = bench(st, fs, p_triangle_rates(A, rates=(0.3, 1.0)), sT, sth, preload={"theta_p": tp},
              drift_per_s=rng.choice([-1, 1]) * rng.uniform(0.02, 0.035) * st.k_series * A / 20)
    return Case(b, ["drift"], ["stiffening", "torque_offset"], unexplained=True, k_scored=False,
                k_true=[st.k_series], note="antagonistic preloaded pair: twice as stiff within "
                "+-theta_p (a negative clearance)")


def prony_dahl_trapezoid(rng):
    st, A, P, fs, sT, sth = base(rng)
    K = st.k_series
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    pr = [(rng.uniform(0.04, 0.07) * K, rng.uniform(0.3, 0.6)), (rng.uniform(0.03, 0.05) * K, rng.uniform(3, 6))]
    return Case(bench(st, fs, p_trapezoid(A, 0.6, hold=(3.0, 5.0)), sT, sth, friction=fr, prony=pr),
                ["hysteresis"], ["time_lag", "drift"], unexplained=True, k_scored=False, k_true=[K],
                starts=[(0, 0, 1e-4, 0, fr["w"])],
                note="viscoelastic bushing (two Maxwell branches) relaxing in long holds; "
                     "no clearance exists, so backlash must not be named")


def pink_noise_backlash_jog(rng):
    st, A, P, fs, sT, sth = base(rng, 2, gaps=(0.01, 0.02))
    bl = sum(s.b for s in st.springs)
    return Case(bench(st, fs, p_jog(A), sT, sth, noise="pink"), ["backlash"], ["drift", "torque_offset"],
                unexplained=None, k_true=[st.k_series], note="1/f torque noise (a wandering zero)")


def student_noise_dahl_prbs(rng):
    st, A, P, fs, sT, sth = base(rng)
    fr = {"law": "dahl", "F": rng.uniform(0.02, 0.035) * P, "w": rng.uniform(0.002, 0.005)}
    return Case(bench(st, fs, p_prbs(A), sT, sth, friction=fr, noise="student3"), ["hysteresis"],
                ["outliers"], unexplained=False, k_true=[st.k_series],
                note="heavy-tailed (Student t, 3 dof) torque noise: no structure")


CASES = {f.__name__: f for f in [
    linear_prbs, backlash_stack3_multisine, dahl_trapezoid, delay_logchirp, damper_jog,
    drift_sawtooth, offset_triangle_rates, offcentre_backlash_prbs, stiffening_multisine,
    asymmetric_trapezoid, spikes_jog, equal_antialias_offset,
    backlash_dahl_delay_tri3, offcentre_drift_dahl_prbs, asym_cubic_delay_logchirp,
    backlash_damper_offset_jog, dahl_viscous_multisine, deg_nmm_backlash_dahl_sawtooth,
    unix_crlf_backlash_offset,
    iwan_trapezoid, stribeck_tri3, atan_one_rate_trapezoid, atan_multisine, load_friction_sawtooth,
    angle_filter_multisine, antialias_unequal_logchirp, zoh_triangle, flexure_engagement_prbs,
    clip_backlash_prbs, bumpstop_dahl_trapezoid, hubslip_backlash_staircase,
    torquefilter_backlash_multisine, creep_coupling_delay_trapezoid, preload_pair_drift_triangle,
    prony_dahl_trapezoid, pink_noise_backlash_jog, student_noise_dahl_prbs,
]}
