"""Held-out generator D: the cases (each a function of a numpy Generator).

A case returns dict(name, desc, t, phi, p, truth, fmt):
  p      parameters of heldout_fit_d_sim.simulate
  truth  required: list of groups (each a list of library names; at least one named per group)
         allowed:  library names that may be named beside the required ones
         in_library: every effect of the record has the library's law (K is checked)
         K_true:   the spring's K (N·m/rad) the fit should report when in_library
         family:   for out-of-library physics, the library names of the same family (allowed;
                   required by the projection rule of heldout_fit_d.py when their law describes it)
         unexplained: False for in-library cases; None = decided by the projection rule
  fmt    None (SI, default columns) or "deg_Nmm" / "deg" / "Nmm" with other column names
"""
from __future__ import annotations

import numpy as np

from heldout_fit_d_sim import (chirp, ramps, random_levels, sines, staircase)

CASES = []


def case(fn):
    CASES.append(fn)
    return fn


def _K(rng, lo=30.0, hi=800.0):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def _base(rng, K, amp, nfrac=(0.002, 0.005), sth=(2e-5, 2e-4)):
    return dict(K=K, noise_T=rng.uniform(*nfrac) * K * amp,
                noise_th=float(np.exp(rng.uniform(np.log(sth[0]), np.log(sth[1])))))


def _stair(rng, amp, fs, profile=None, hold=None, n=3):
    amps = list(np.linspace(amp / n, amp, n))
    rate = rng.uniform(0.08, 0.4) * amp / 0.3
    return staircase(amps, rate, hold if hold is not None else rng.uniform(0.5, 2.0), fs,
                     profile or rng.choice(["linear", "cosine"]))


def T(required=(), allowed=(), K=None, in_library=True, family=(), unexplained=False):
    return dict(required=[list(g) for g in required], allowed=sorted(set(allowed)),
                in_library=in_library, K_true=K, family=sorted(family),
                unexplained=unexplained if in_library else None)


# ------------------------------------------------------------------ in-library cases
@case
def L01_clean_staircase(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000)
    return dict(desc="linear spring, staircase", t=t, phi=phi, p=_base(rng, K, a), truth=T(K=K))


@case
def L02_backlash_deg_Nmm(rng):
    K, a, b = _K(rng), rng.uniform(0.2, 0.35), rng.uniform(0.005, 0.03)
    t, phi = _stair(rng, a, 500)
    p = _base(rng, K, a); p["gap"] = b
    return dict(desc=f"dead band b={b:.4f}, staircase, deg + N·mm, renamed columns", t=t, phi=phi,
                p=p, truth=T([["backlash"]], K=K), fmt="deg_Nmm")


@case
def L03_dahl_staircase(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    F = rng.uniform(0.01, 0.03) * K * a
    t, phi = _stair(rng, a, 1000, hold=rng.uniform(1.0, 2.5))
    p = _base(rng, K, a); p["dahl"] = (F, rng.uniform(5e-4, 3e-3))
    return dict(desc=f"Dahl friction F={F:.3g}, staircase with holds", t=t, phi=phi, p=p,
                truth=T([["hysteresis"]], K=K))


@case
def L04_delay_sine_sweep(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    d = rng.uniform(0.005, 0.04)
    t, phi = sines([(a / 2, 0.2, 2), (a, 0.3, 2), (a, 1.0, 4), (a / 2, 1.5, 4)], 1000)
    p = _base(rng, K, a); p["delay"] = d
    return dict(desc=f"torque delayed {d*1e3:.1f} ms, sine sweep", t=t, phi=phi, p=p,
                truth=T([["time_lag"]], K=K))


@case
def L05_drift_random_levels(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.4)
    t, phi = random_levels(a, 14, 0.3, 500, rng)
    p = _base(rng, K, a); p["drift"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * K * a / t[-1]
    return dict(desc="linear torque-zero drift 1-3 % of peak over the record, random levels",
                t=t, phi=phi, p=p, truth=T([["drift"]], K=K))


@case
def L06_torque_offset_triangles(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.4)
    t, phi = ramps(a, [0.2], 4, 1000, hold=1.0)
    p = _base(rng, K, a); p["T_offset"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.04) * K * a
    return dict(desc="torque zero offset, triangles with holds", t=t, phi=phi, p=p,
                truth=T([["torque_offset"]], K=K))


@case
def L07_angle_offset_linear(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.4)
    t, phi = sines([(a, 0.25, 5)], 500)
    p = _base(rng, K, a); p["th_offset"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03)
    return dict(desc="angle zero offset on a linear spring (= a torque offset)", t=t, phi=phi, p=p,
                truth=T([["angle_offset", "torque_offset"]], ["angle_offset", "torque_offset"], K=K))


@case
def L08_angle_offset_backlash(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.01, 0.03)
    p["th_offset"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03)
    return dict(desc="angle zero offset + dead band", t=t, phi=phi, p=p,
                truth=T([["backlash"], ["angle_offset"]], K=K))


@case
def L09_cubic_multirate(rng):
    K, a = _K(rng), rng.uniform(0.3, 0.5)
    k3 = rng.uniform(0.1, 0.3) * K / a ** 2
    t, phi = ramps(a, [0.1, 0.3, 0.8], 2, 2000, profile="cosine")
    p = _base(rng, K, a); p["k3"] = k3
    return dict(desc=f"cubic hardening (+{k3*a*a/K*100:.0f} % at peak), 3-rate cosine ramps, 2 kHz",
                t=t, phi=phi, p=p, truth=T([["stiffening"]], K=K))


@case
def L10_asym_sine(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    Kn = K * rng.choice([0.8, 0.88, 1.12, 1.2])
    t, phi = sines([(a, 0.2, 3), (a / 2, 0.5, 3)], 500)
    p = _base(rng, K, a); p["Kneg"] = Kn
    return dict(desc=f"K+ {K:.1f}, K- {Kn:.1f}, sines", t=t, phi=phi, p=p,
                truth=T([["asymmetric_stiffness"]], K=K) | {"K_alt": [Kn, (K + Kn) / 2]})


@case
def L11_spikes_triangles(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.25], 5, 1000)
    p = _base(rng, K, a); p["outliers"] = int(rng.integers(6, 20))
    return dict(desc="isolated torque spikes 15-40 sigma, triangles", t=t, phi=phi, p=p,
                truth=T([["outliers"]], K=K))


@case
def L12_bursts(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 2000)
    p = _base(rng, K, a); p["bursts"] = int(rng.integers(3, 7))
    tr = T([["outliers"]], K=K)
    tr["unexplained"] = None
    return dict(desc="bursts of 3-8 bad torque samples", t=t, phi=phi, p=p, truth=tr)


@case
def L13_stack_with_play(rng):
    n = int(rng.integers(2, 5))
    Ks = [_K(rng, 100, 600) for _ in range(n)]
    bs = [rng.uniform(0.002, 0.008) for _ in range(n)]
    K = 1.0 / sum(1.0 / k for k in Ks)
    a = rng.uniform(0.4, 1.0)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["gap"] = sum(bs)
    return dict(desc=f"{n} springs in series, each with play (total b={sum(bs):.4f})", t=t,
                phi=phi, p=p, truth=T([["backlash"]], K=K))


@case
def L14_backlash_dahl(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000, hold=rng.uniform(1.0, 2.0))
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.008, 0.03)
    p["dahl"] = (rng.uniform(0.01, 0.03) * K * a, rng.uniform(5e-4, 2e-3))
    return dict(desc="dead band + Dahl friction, staircase", t=t, phi=phi, p=p,
                truth=T([["backlash"], ["hysteresis"]], K=K))


@case
def L15_drift_offset_5k_deg(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 5000, n=2)
    p = _base(rng, K, a); p["T_offset"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * K * a
    p["drift"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * K * a / t[-1]
    return dict(desc="torque offset + linear drift, 5 kHz, deg", t=t, phi=phi, p=p,
                truth=T([["drift"], ["torque_offset"]], K=K), fmt="deg")


@case
def L16_delay_cubic_chirp(rng):
    K, a = _K(rng), rng.uniform(0.3, 0.5)
    t, phi = chirp(a, 0.05, 1.5, 30.0, 1000)
    p = _base(rng, K, a); p["delay"] = rng.uniform(0.005, 0.03)
    p["k3"] = rng.uniform(0.1, 0.3) * K / a ** 2
    return dict(desc="delay + cubic, chirp 0.05-1.5 Hz", t=t, phi=phi, p=p,
                truth=T([["time_lag"], ["stiffening"]], K=K))


@case
def L17_asym_backlash_levels(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = random_levels(a, 16, 0.3, 1000, rng)
    Kn = K * rng.choice([0.82, 1.18])
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.008, 0.03); p["Kneg"] = Kn
    return dict(desc="asymmetric K + dead band, random levels", t=t, phi=phi, p=p,
                truth=T([["backlash"], ["asymmetric_stiffness"]], K=K) | {"K_alt": [Kn, (K + Kn) / 2]})


@case
def L18_dahl_delay_3rates(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.05, 0.2, 0.6], 2, 1000)
    p = _base(rng, K, a); p["dahl"] = (rng.uniform(0.01, 0.02) * K * a, rng.uniform(5e-4, 2e-3))
    p["delay"] = rng.uniform(0.01, 0.03)
    return dict(desc="Dahl friction + delay, ramps at 3 rates (separable)", t=t, phi=phi, p=p,
                truth=T([["hysteresis"], ["time_lag"]], K=K))


@case
def L19_dahl_one_rate(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.2], 5, 500)
    p = _base(rng, K, a); p["dahl"] = (rng.uniform(0.01, 0.03) * K * a, rng.uniform(3e-4, 1e-3))
    return dict(desc="Dahl friction, triangles at one rate, no holds (confoundable with a lag)",
                t=t, phi=phi, p=p,
                truth=T([["hysteresis", "time_lag"]], ["hysteresis", "time_lag"], K=K))


@case
def L20_delay_one_rate(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.25], 5, 1000)
    p = _base(rng, K, a); p["delay"] = rng.uniform(0.01, 0.04)
    return dict(desc="delay, triangles at one rate, no holds (confoundable with friction)",
                t=t, phi=phi, p=p,
                truth=T([["hysteresis", "time_lag"]], ["hysteresis", "time_lag"], K=K))


@case
def L21_spikes_drift_Nmm(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.2, 4), (a / 2, 0.4, 4)], 500)
    p = _base(rng, K, a); p["outliers"] = int(rng.integers(6, 15))
    p["drift"] = rng.choice([-1, 1]) * rng.uniform(0.01, 0.03) * K * a / t[-1]
    return dict(desc="spikes + linear drift, sines, N·mm", t=t, phi=phi, p=p,
                truth=T([["outliers"], ["drift"]], K=K), fmt="Nmm")


@case
def L22_quantised_coloured(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a)
    p["ar"] = rng.uniform(4, 15)
    p["qth"] = 2 * np.pi / 2 ** 16
    p["qT"] = 2.4 * K * a / 2 ** 12
    return dict(desc="linear spring, AR(1) torque noise, 16-bit encoder, 12-bit torque ADC",
                t=t, phi=phi, p=p, truth=T(K=K))


@case
def L23_cubic_dahl_200Hz(rng):
    K, a = _K(rng), rng.uniform(0.3, 0.5)
    t, phi = _stair(rng, a, 200)
    p = _base(rng, K, a); p["k3"] = rng.uniform(0.1, 0.3) * K / a ** 2
    p["dahl"] = (rng.uniform(0.01, 0.03) * K * a, rng.uniform(1e-3, 3e-3))
    return dict(desc="cubic + Dahl friction, staircase at 200 Hz", t=t, phi=phi, p=p,
                truth=T([["stiffening"], ["hysteresis"]], K=K))


@case
def L24_backlash_delay_sines(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.2, 3), (a, 0.6, 4), (a / 2, 1.2, 6)], 1000)
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.008, 0.03); p["delay"] = rng.uniform(0.005, 0.03)
    return dict(desc="dead band + delay, sine sweep", t=t, phi=phi, p=p,
                truth=T([["backlash"], ["time_lag"]], K=K))


@case
def L25_backlash_dahl_drift(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000, hold=rng.uniform(1.0, 2.0))
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.008, 0.03)
    p["dahl"] = (rng.uniform(0.01, 0.03) * K * a, rng.uniform(5e-4, 2e-3))
    p["drift"] = rng.choice([-1, 1]) * rng.uniform(0.015, 0.03) * K * a / t[-1]
    return dict(desc="dead band + Dahl friction + drift, staircase", t=t, phi=phi, p=p,
                truth=T([["backlash"], ["hysteresis"], ["drift"]], K=K))


@case
def L26_soft_stack_cubic_deg(rng):
    K, a = _K(rng, 10, 30), rng.uniform(0.8, 1.2)
    t, phi = _stair(rng, a, 500)
    p = _base(rng, K, a); p["k3"] = rng.uniform(0.1, 0.25) * K / a ** 2
    return dict(desc="soft stack (K 10-30) to +-0.8-1.2 rad, cubic, deg", t=t, phi=phi, p=p,
                truth=T([["stiffening"]], K=K), fmt="deg")


@case
def L27_stiff_short_5k(rng):
    K, a = _K(rng, 800, 2000), rng.uniform(0.15, 0.25)
    t, phi = sines([(a, 0.5, 3), (a, 1.0, 4)], 5000)
    p = _base(rng, K, a, nfrac=(0.001, 0.003)); p["ar"] = rng.uniform(3, 10)
    return dict(desc="stiff spring (K 800-2000), 10 s at 5 kHz, AR noise", t=t, phi=phi, p=p,
                truth=T(K=K))


# ------------------------------------------------------------------ out-of-library cases
def X(required=(), allowed=(), family=(), K=None):
    return T(required, set(allowed) | set(family), K=K, in_library=False, family=family)


@case
def X01_hard_stop(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["stop"] = (0.8 * a, rng.uniform(5, 10) * K, 2)
    return dict(desc="two-sided hard stop at 0.8 of the peak angle", t=t, phi=phi, p=p,
                truth=X(family=["stiffening"], K=K))


@case
def X02_one_sided_stop(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = ramps(a, [0.1, 0.3], 3, 1000)
    p = _base(rng, K, a); p["stop"] = (0.75 * a, rng.uniform(5, 10) * K, 1)
    return dict(desc="one-sided hard stop at 0.75 of +peak", t=t, phi=phi, p=p,
                truth=X(family=["stiffening", "asymmetric_stiffness"], K=K))


@case
def X03_clipping(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["clip"] = rng.uniform(0.8, 0.9) * K * a
    return dict(desc="torque sensor saturates at 80-90 % of the peak", t=t, phi=phi, p=p,
                truth=X(K=K))


@case
def X04_hertz_takeup(rng):
    # Truth fixed after the first run (2026-11-26): a Hertzian contact's stiffness rises with
    # load, a hardening, so `stiffening` is of its family (it was left out of the list).
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    b = rng.uniform(0.01, 0.03)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["gap"] = b
    # Hertz contact: at 30 % of the peak torque the contact takes 8-15 mrad
    T0 = 0.3 * K * a
    p["hertz"] = T0 / rng.uniform(0.008, 0.015) ** 1.5
    return dict(desc=f"gap b={b:.3f} with a Hertzian contact in series (smooth take-up)", t=t,
                phi=phi, p=p, truth=X([["backlash"]], family=["series_compliance", "stiffening"], K=K))


@case
def X05_impact_gap(rng):
    # Truth fixed after the first run (2026-11-26): the damper that settles the body (zeta_b)
    # is a viscous element in the load path (an angle lag cb*v/kc on every ramp), so
    # `time_lag` is of its family (it was left out of the list).
    K, a = _K(rng), rng.uniform(0.25, 0.35)
    b = rng.uniform(0.01, 0.03)
    t, phi = ramps(a, [0.3, 0.8], 3, 2000)
    kc = rng.uniform(8, 15) * K
    f = rng.uniform(40, 80)
    J = (kc + K) / (2 * np.pi * f) ** 2
    p = _base(rng, K, a); p["gap"] = b
    p["impact"] = dict(J=J, kc=kc, zeta_c=rng.uniform(0.05, 0.12), zeta_b=0.7)
    return dict(desc=f"gap b={b:.3f}, compliant contact kc={kc/K:.0f}K with impact ringing {f:.0f} Hz",
                t=t, phi=phi, p=p, truth=X([["backlash"]], family=["series_compliance", "time_lag"], K=K))


@case
def X06_lugre_multirate(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.03, 0.1, 0.4], 2, 1000, hold=0.5)
    Fc = rng.uniform(0.01, 0.02) * K * a
    p = _base(rng, K, a)
    p["lugre"] = dict(Fc=Fc, Fs=Fc * rng.uniform(1.8, 2.5), vs=rng.uniform(0.02, 0.06),
                      sigma0=Fc / rng.uniform(3e-4, 1e-3), sigma2=rng.uniform(0.5, 1.5) * Fc / 0.2)
    return dict(desc="LuGre friction (Stribeck weakening 2x, viscous), ramps at 3 rates with holds",
                t=t, phi=phi, p=p, truth=X(family=["hysteresis", "time_lag"], K=K))


@case
def X07_stribeck_sines(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.1, 2), (a, 0.4, 3), (a / 3, 0.3, 3), (a, 1.0, 4)], 1000)
    Fc = rng.uniform(0.01, 0.02) * K * a
    p = _base(rng, K, a)
    p["lugre"] = dict(Fc=Fc, Fs=Fc * rng.uniform(2.0, 3.0), vs=rng.uniform(0.02, 0.05),
                      sigma0=Fc / 5e-4, sigma2=0.0)
    return dict(desc="Stribeck velocity-weakening friction (static 2-3x kinetic), sine sweep",
                t=t, phi=phi, p=p, truth=X(family=["hysteresis", "time_lag"], K=K))


@case
def X08_tanh_holds(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000, hold=rng.uniform(1.5, 3.0), profile="linear")
    F = rng.uniform(0.015, 0.03) * K * a
    p = _base(rng, K, a); p["tanh"] = (F, rng.uniform(0.002, 0.01))
    return dict(desc="regularised Coulomb F*tanh(v/v0) (zero at rest), staircase with holds",
                t=t, phi=phi, p=p, truth=X(family=["hysteresis", "time_lag"], K=K))


@case
def X09_viscous_sweep(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.2, 2), (a, 0.6, 4), (a / 2, 1.5, 6)], 1000)
    c = rng.uniform(0.005, 0.03) * K
    p = _base(rng, K, a); p["visc"] = c
    return dict(desc=f"viscous damping c={c:.3g} (c/K {c/K*1e3:.0f} ms), sine sweep", t=t, phi=phi,
                p=p, truth=X(family=["time_lag"], K=K))


@case
def X10_filter_delay_staircase(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 2000, profile="linear")
    p = _base(rng, K, a); p["lowpass"] = rng.uniform(0.02, 0.05); p["delay"] = rng.uniform(0.005, 0.02)
    return dict(desc="torque sensor low-pass 20-50 ms + transport delay, staircase (sharp corners)",
                t=t, phi=phi, p=p, truth=X([["time_lag"]], family=["time_lag"], K=K))


@case
def X11_filter_sines(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.2, 3), (a, 0.8, 4)], 1000)
    p = _base(rng, K, a); p["lowpass"] = rng.uniform(0.005, 0.02)
    return dict(desc="torque sensor low-pass 5-20 ms, slow sines", t=t, phi=phi, p=p,
                truth=X([["time_lag"]], family=["time_lag"], K=K))


@case
def X12_relaxation(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 500, hold=rng.uniform(2.0, 3.0))
    p = _base(rng, K, a); p["sls"] = (rng.uniform(0.04, 0.1) * K, rng.uniform(0.3, 1.0))
    return dict(desc="viscoelastic relaxation (SLS, 4-10 % of K, tau 0.3-1 s) in holds", t=t, phi=phi,
                p=p, truth=X(family=["hysteresis", "time_lag"], K=K))


@case
def X13_stick_slip(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = ramps(a, [0.05, 0.15], 2, 1000)
    Fk = rng.uniform(0.015, 0.03) * K * a
    p = _base(rng, K, a); p["stickslip"] = dict(kd=rng.uniform(1.0, 3.0) * K, Fs=Fk * rng.uniform(1.4, 1.8), Fk=Fk)
    return dict(desc="stick-slip sawtooth through a compliant drive", t=t, phi=phi, p=p,
                truth=X(family=["hysteresis", "time_lag"], K=K))


@case
def X14_hum(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["hum"] = (rng.uniform(1.5, 3.0) * p["noise_T"], rng.choice([50.0, 60.0]), 0.3)
    return dict(desc="mains hum 1.5-3 sigma with a 3rd harmonic", t=t, phi=phi, p=p, truth=X(K=K))


@case
def X15_cogging(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = ramps(a, [0.05, 0.2], 2, 1000)
    p = _base(rng, K, a); p["cog"] = (rng.uniform(3, 6) * p["noise_T"], float(rng.integers(20, 60)), rng.uniform(0, 6.28))
    return dict(desc="motor cogging torque periodic in the motor angle (20-60 per rev)", t=t, phi=phi,
                p=p, truth=X(K=K))


@case
def X16_k_step(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = _stair(rng, a, 1000, n=4)
    p = _base(rng, K, a); p["kstep"] = (t[-1] * rng.uniform(0.4, 0.6), rng.choice([0.93, 0.95, 1.06]))
    return dict(desc="stiffness steps 5-7 % mid-test (a crack or a slip)", t=t, phi=phi, p=p,
                truth=X(K=K))


@case
def X17_settling_zero(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = random_levels(a, 16, 0.3, 500, rng)
    p = _base(rng, K, a)
    p["expdrift"] = (rng.choice([-1, 1]) * rng.uniform(0.02, 0.04) * K * a, t[-1] * rng.uniform(0.1, 0.2))
    return dict(desc="thermal zero settling exponentially (tau 10-20 % of the record)", t=t, phi=phi,
                p=p, truth=X(family=["drift", "torque_offset"], K=K))


@case
def X18_k_temperature(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.2, 12)], 500)
    p = _base(rng, K, a); p["ktemp"] = (rng.uniform(0.03, 0.06), t[-1] * rng.uniform(0.2, 0.4))
    return dict(desc="K falls 3-6 % as the bench warms (exponential)", t=t, phi=phi, p=p, truth=X(K=K))


@case
def X19_power_stiffening(rng):
    K, a = _K(rng), rng.uniform(0.3, 0.5)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["power"] = (a * rng.uniform(1.0, 1.5), rng.choice([1.0, 4.0]))
    return dict(desc="contact-geometry hardening K*u*(|u|/uc)^p, p 1 or 4", t=t, phi=phi, p=p,
                truth=X(family=["stiffening"], K=K))


@case
def X20_encoder_ripple(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = ramps(a, [0.1, 0.3], 2, 1000)
    p = _base(rng, K, a); p["th_ripple"] = (rng.uniform(1.5e-3, 3e-3), float(rng.integers(20, 40)))
    return dict(desc="angle ripple periodic in angle (cam tooth / encoder), 1.5-3 mrad", t=t, phi=phi,
                p=p, truth=X(K=K))


@case
def X21_drift_hum(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = sines([(a, 0.25, 8)], 1000)
    p = _base(rng, K, a); p["drift"] = rng.choice([-1, 1]) * rng.uniform(0.015, 0.03) * K * a / t[-1]
    p["hum"] = (rng.uniform(1.5, 3.0) * p["noise_T"], 50.0, 0.0)
    return dict(desc="linear drift + 50 Hz hum", t=t, phi=phi, p=p,
                truth=X([["drift"]], allowed=["drift"], K=K))


@case
def X22_backlash_clip(rng):
    K, a = _K(rng), rng.uniform(0.25, 0.4)
    t, phi = _stair(rng, a, 1000)
    p = _base(rng, K, a); p["gap"] = rng.uniform(0.01, 0.03); p["clip"] = rng.uniform(0.8, 0.88) * K * (a - p["gap"] / 2)
    return dict(desc="dead band + sensor clipping at 80-88 % of the peak", t=t, phi=phi, p=p,
                truth=X([["backlash"]], allowed=["backlash"], K=K))


@case
def X23_cubic_cogging(rng):
    K, a = _K(rng), rng.uniform(0.3, 0.45)
    t, phi = ramps(a, [0.05, 0.2], 2, 2000, profile="cosine")
    p = _base(rng, K, a); p["k3"] = rng.uniform(0.15, 0.3) * K / a ** 2
    p["cog"] = (rng.uniform(3, 6) * p["noise_T"], float(rng.integers(20, 60)), 0.3)
    return dict(desc="cubic + motor cogging", t=t, phi=phi, p=p,
                truth=X([["stiffening"]], allowed=["stiffening"], K=K))


@case
def X24_filter_dahl_chirp(rng):
    K, a = _K(rng), rng.uniform(0.2, 0.35)
    t, phi = chirp(a, 0.05, 2.0, 30.0, 2000)
    p = _base(rng, K, a); p["lowpass"] = rng.uniform(0.01, 0.03)
    p["dahl"] = (rng.uniform(0.01, 0.02) * K * a, rng.uniform(5e-4, 2e-3))
    return dict(desc="Dahl friction + torque low-pass 10-30 ms, chirp to 2 Hz", t=t, phi=phi, p=p,
                truth=X([["hysteresis"], ["time_lag"]], family=["time_lag", "hysteresis"], K=K))
