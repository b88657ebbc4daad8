"""Held-out generator C: the seeded record list (52 records).

Written from /work/wt/FIT_PHYSICS.md alone. Magnitudes are drawn per seed and stated
against the torque noise std (sigma = noise fraction x K x amplitude), so each effect sits
clearly above (or, where the case says so, clearly below) the noise. Families:
L = library effects alone and together, F = friction laws, G = lag laws,
O = physics outside the library (and a sensor that only adds noise).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from heldout_fit_c_sim import Protocol, Rig, chirp, ramps, random_levels, sines, staircase


@dataclass
class Case:
    """One record to simulate: name, protocol, rig, file units and a one-line note."""

    name: str
    proto: Protocol
    rig: Rig
    angle_unit: str = "rad"
    torque_unit: str = "Nm"
    note: str = ""


def _K(rng, stack=False):
    lo, hi = (20.0, 150.0) if stack else (100.0, 1500.0)
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _A(rng, stack=False):
    return float(rng.uniform(0.6, 1.0) if stack else rng.uniform(0.22, 0.38))


def _frac(rng, lo=0.002, hi=0.004):
    return float(rng.uniform(lo, hi))


def build_cases(rng: np.random.Generator) -> list[Case]:
    """All records for one seed (the same names and families for every seed)."""
    C = []
    u = rng.uniform

    # ---------------------------------------------------------------- L: library effects
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L01_linear_staircase_deg", staircase(500, [A / 3, 2 * A / 3, A], A / 1.2, 1.0),
                  Rig(K, fr), angle_unit="deg", note="ideal spring"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L02_backlash_staircase", staircase(1000, [A / 2, A], A / 1.0, 0.8),
                  Rig(K, fr, gap_rad=u(0.015, 0.04))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 18)
    C.append(Case("L03_dahl_2rates", ramps(500, A, [A / 1.5, A / 0.5], 2, 0.5),
                  Rig(K, fr, friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.003})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L04_delay_sinesweep", sines(1000, [(A, 0.2, 2), (A / 2, 0.5, 3), (A, 1.0, 4)]),
                  Rig(K, fr, delay_s=u(0.008, 0.03))))
    for name, shape, fs, tu in (("L05_stack_fric_lag_backlash_2rates", "lin", 1000, "Nm"),
                                ("L06_stack_fric_lag_backlash_2rates_cos_Nmm", "cos", 1000, "Nmm")):
        K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
        Fc = fr * K * A * u(10, 16)
        C.append(Case(name, ramps(fs, A, [A / 2.0, A / 0.7], 2, 0.5, shape),
                      Rig(K, fr, gap_rad=u(0.03, 0.05), delay_s=0.03,
                          friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.004}),
                      torque_unit=tu, note="the issue's class 1 record"))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("L07_stack_fric_lag_backlash_drift_3rates",
                  ramps(500, A, [A / 2.5, A / 1.2, A / 0.6], 1, 0.4),
                  Rig(K, fr, gap_rad=u(0.02, 0.04), delay_s=u(0.015, 0.04), drift_Nm_per_s=fr * K * A * 0.6,
                      friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.003})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(8, 14)
    C.append(Case("L08_dahl_delay_1rate_triangle", ramps(1000, A, [A / 0.8], 5, 0.0),
                  Rig(K, fr, delay_s=u(0.01, 0.03), friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.001}),
                  note="one rate, no holds: friction and lag confounded"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L09_drift_offset_levels", random_levels(200, rng, A, [A / 1.0, A / 0.4], 14),
                  Rig(K, fr, torque_offset_Nm=fr * K * A * u(8, 15) * rng.choice([-1, 1]),
                      drift_Nm_per_s=fr * K * A * u(0.6, 1.2) * rng.choice([-1, 1]))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L10_stiffening_sines", sines(500, [(A / 2, 0.3, 2), (A, 0.3, 3), (A, 0.8, 4)]),
                  Rig(K, fr, k3=u(0.06, 0.12) * K / A ** 2)))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L11_asymmetric_staircase", staircase(500, [A / 2, A], A / 1.0, 1.0),
                  Rig(K, fr, K_neg_factor=u(0.82, 0.9))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L12_outliers_chirp", chirp(2000, A, 0.05, 1.5, 12.0),
                  Rig(K, fr, outliers=(10, 30.0))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L13_angle_offset_backlash_2rates", ramps(1000, A, [A / 1.5, A / 0.6], 2, 0.3),
                  Rig(K, fr, gap_rad=u(0.02, 0.04), gap_centre_rad=0.0, angle_offset_rad=u(0.008, 0.015))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L14_angle_offset_linear_sines", sines(500, [(A, 0.4, 3), (A / 2, 0.8, 3)]),
                  Rig(K, fr, angle_offset_rad=u(0.01, 0.02)),
                  note="linear spring: an angle zero error is a torque zero error"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("L15_dahl_delay_sinesweep", sines(1000, [(A, 0.15, 2), (A / 2, 0.6, 3), (A, 1.2, 5)]),
                  Rig(K, fr, delay_s=u(0.01, 0.03), friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.002})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("L16_linear_5kHz_triangle_colourednoise", ramps(5000, A, [A / 1.0], 2, 0.5),
                  Rig(K, fr, colour=0.3, noise_theta_rad=2e-5), note="AR(1) share 0.3 in the torque noise"))

    # ---------------------------------------------------------------- F: friction laws
    def fr_case(name, proto, law, K, fr, A, **kw):
        return Case(name, proto, Rig(K, fr, friction={"law": law, **kw}))

    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v = A / 1.0
    C.append(fr_case("F01_tanh_1rate_staircase", staircase(500, [A / 2, A], v, 1.0), "tanh", K, fr, A,
                     Fc=fr * K * A * u(10, 16), v0=0.02 * v))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v = A / 1.5
    C.append(fr_case("F02_tanh_2rates_holds", ramps(500, A, [v, 3 * v], 2, 0.8), "tanh", K, fr, A,
                     Fc=fr * K * A * u(20, 28), v0=0.02 * v))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(fr_case("F03_tanh_sinesweep", sines(1000, [(A, 0.2, 2), (A / 2, 0.6, 3), (A, 1.0, 4)]),
                     "tanh", K, fr, A, Fc=fr * K * A * u(10, 16), v0=0.1 * A * 2 * np.pi * 0.2))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(fr_case("F04_tanh_single_sine", sines(500, [(A, 0.5, 8)]), "tanh", K, fr, A,
                     Fc=fr * K * A * u(10, 16), v0=0.1 * A * 2 * np.pi * 0.5))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v = A / 0.8
    C.append(Case("F05_tanh_drift_1rate_levels", random_levels(500, rng, A, [v], 12),
                  Rig(K, fr, drift_Nm_per_s=fr * K * A * u(0.8, 1.2),
                      friction={"law": "tanh", "Fc": fr * K * A * u(10, 16), "v0": 0.02 * v})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v = A / 1.5
    C.append(fr_case("F06_viscous_2rates_cos", ramps(1000, A, [v, 3 * v], 2, 0.5, "cos"), "viscous",
                     K, fr, A, c=fr * K * A * u(6, 10) / v))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(fr_case("F07_viscous_single_sine", sines(500, [(A, 0.4, 6)]), "viscous", K, fr, A,
                     c=fr * K * A * u(8, 12) / (A * 2 * np.pi * 0.4)))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v, Fc = A / 1.5, fr * K * A * u(10, 16)
    C.append(fr_case("F08_stribeck_mild_2rates", ramps(500, A, [v, 3 * v], 2, 0.6), "lugre", K, fr, A,
                     Fc=Fc, Fs=Fc + 0.4 * fr * K * A, vs=v / 2, sigma0=Fc / 0.002))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v, Fc = A / 2.0, fr * K * A * u(8, 12)
    C.append(fr_case("F09_stribeck_strong_3rates_cos", ramps(500, A, [v, 2.5 * v, 6 * v], 1, 0.5, "cos"),
                     "lugre", K, fr, A, Fc=Fc, Fs=3.5 * Fc, vs=2.5 * v, sigma0=Fc / 0.002))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    v, Fc = A / 1.0, fr * K * A * u(10, 16)
    C.append(fr_case("F10_stribeck_1rate_staircase", staircase(500, [A / 2, A], v, 1.0), "lugre",
                     K, fr, A, Fc=Fc, Fs=2 * Fc, vs=v / 3, sigma0=Fc / 0.002))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(fr_case("F11_lugre_viscous_sinesweep", sines(1000, [(A, 0.2, 2), (A / 2, 0.6, 3), (A, 1.0, 4)]),
                     "lugre", K, fr, A, Fc=Fc, Fs=Fc, vs=1.0, sigma0=Fc / 0.002, sigma1=0.0,
                     sigma2=fr * K * A * u(8, 12) / (A * 2 * np.pi * 1.0)))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("F12_stack_lugre_backlash_2rates", ramps(500, A, [A / 2, A / 0.8], 2, 0.5),
                  Rig(K, fr, gap_rad=u(0.03, 0.05),
                      friction={"law": "lugre", "Fc": Fc, "Fs": Fc, "vs": 1.0, "sigma0": Fc / 0.003})))

    # ---------------------------------------------------------------- G: lag laws
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng, 0.0012, 0.002)
    C.append(Case("G01_stack_filter20ms_backlash_2rates", ramps(1000, A, [A / 1.5, A / 0.5], 2, 0.5),
                  Rig(K, fr, gap_rad=0.04, filter_tau_s=0.02), note="the issue's class 3 filter record"))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    C.append(Case("G02_stack_delay20ms_backlash_2rates", ramps(1000, A, [A / 1.5, A / 0.5], 2, 0.5),
                  Rig(K, fr, gap_rad=0.04, delay_s=0.02), note="G01's twin with a pure delay"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("G03_filter3ms_sines", sines(1000, [(A, 0.5, 4), (A / 2, 1.5, 6)]),
                  Rig(K, fr, filter_tau_s=0.003), note="a short filter on smooth sines is a delay"))
    K, A, fr = _K(rng), _A(rng), _frac(rng, 0.0012, 0.002)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("G04_filter10ms_dahl_backlash_2rates_cos_Nmm",
                  ramps(1000, A, [A / 1.2, A / 0.4], 2, 0.4, "cos"),
                  Rig(K, fr, gap_rad=u(0.02, 0.035), filter_tau_s=0.01,
                      friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.003}), torque_unit="Nmm"))

    # ---------------------------------------------------------------- O: outside the library
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("O01_clip_dahl_2rates", ramps(500, A, [A / 1.5, A / 0.5], 2, 0.4),
                  Rig(K, fr, clip_frac=0.85, friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.003})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("O02_clip_backlash_staircase", staircase(500, [A / 2, A], A / 1.0, 0.8),
                  Rig(K, fr, gap_rad=u(0.02, 0.04), clip_frac=0.8)))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("O03_viscoelastic_staircase", staircase(500, [A / 2, A], A / 0.8, 1.5),
                  Rig(K, fr, maxwell=(u(0.1, 0.2) * K, u(0.3, 0.6)))))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    C.append(Case("O04_stack_viscoelastic_backlash_levels", random_levels(500, rng, A, [A / 1.0], 10),
                  Rig(K, fr, gap_rad=u(0.03, 0.05), maxwell=(u(0.1, 0.2) * K, u(0.3, 0.6)))))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    C.append(Case("O05_stack_hardstop_backlash_2rates", ramps(500, A, [A / 2, A / 0.8], 2, 0.4),
                  Rig(K, fr, gap_rad=u(0.03, 0.05), stop_rad=0.85 * A, stop_K_factor=4.0)))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("O06_hardstop_staircase", staircase(500, [A / 3, 2 * A / 3, A], A / 1.0, 0.8),
                  Rig(K, fr, stop_rad=0.8 * A, stop_K_factor=5.0)))
    for name, amp in (("O07_stickslip_above_noise", u(10, 14)), ("O08_stickslip_below_noise", 0.3)):
        K, A, fr = _K(rng), _A(rng), _frac(rng)
        Fc = fr * K * A * u(10, 16)
        C.append(Case(name, ramps(1000, A, [A / 2.0, A / 0.8], 2, 0.3),
                      Rig(K, fr, stickslip=(amp * fr * K * A, 0.02),
                          friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.002}),
                      note=f"sawtooth {amp:.1f} noise std peak to peak"))
    K, A, fr = _K(rng), _A(rng), _frac(rng, 0.0012, 0.002)
    C.append(Case("O09_hertz_backlash_strong", ramps(1000, A, [A / 1.5, A / 0.6], 2, 0.3),
                  Rig(K, fr, gap_rad=0.03, hertz_w_rad=90 * fr * A)))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("O10_hertz_backlash_mild", ramps(1000, A, [A / 1.5, A / 0.6], 2, 0.3),
                  Rig(K, fr, gap_rad=0.03, hertz_w_rad=0.002)))
    for name, tau_over_T, amp in (("O11_thermal_settle_fast", 1 / 6, u(25, 35)),
                                  ("O12_thermal_settle_slow", 4.0, u(12, 18))):
        K, A, fr = _K(rng), _A(rng), _frac(rng)
        p = staircase(500, [A / 3, 2 * A / 3, A], A / 1.0, 1.0)
        C.append(Case(name, p, Rig(K, fr, settle=(amp * fr * K * A, tau_over_T * float(p.t_s[-1])))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    C.append(Case("O13_ripple_in_angle_triangles", ramps(1000, A, [A / 2.0, A / 1.0], 2, 0.3),
                  Rig(K, fr, ripple=(u(6, 9) * fr * K * A, 0.05, 0.3))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    q = 0.5 * fr * A * math.sqrt(12)            # count size whose error is 0.5 noise std
    C.append(Case("O14_encoder_counts_backlash", staircase(500, [A / 2, A], A / 1.0, 0.8),
                  Rig(K, fr, gap_rad=u(0.02, 0.04), noise_theta_rad=0.0,
                      counts_per_rev=2 ** math.ceil(math.log2(2 * math.pi / q)))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("O15_hum_dahl_sines", sines(1000, [(A, 0.3, 3), (A / 2, 0.8, 4)]),
                  Rig(K, fr, hum=(u(10, 14) * fr * K * A, 50.0),
                      friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.002})))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    p = staircase(500, [A / 2, A, A / 2, A], A / 1.0, 0.8)
    C.append(Case("O16_stiffness_step_staircase", p,
                  Rig(K, fr, K_step=(0.5 * float(p.t_s[-1]), u(0.88, 0.92)))))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    q = 0.4 * fr * A * math.sqrt(12)
    C.append(Case("O17_encoder_counts_delay_chirp_deg", chirp(1000, A, 0.05, 1.2, 14.0),
                  Rig(K, fr, delay_s=u(0.01, 0.025), noise_theta_rad=0.0,
                      counts_per_rev=2 ** math.ceil(math.log2(2 * math.pi / q))), angle_unit="deg"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    p = staircase(500, [A / 2, A, A / 2, A], A / 1.0, 0.8)
    C.append(Case("O18_thermal_K_staircase_deg_Nmm", p,
                  Rig(K, fr, K_thermal=(-u(0.08, 0.12), 0.25 * float(p.t_s[-1]))),
                  angle_unit="deg", torque_unit="Nmm", note="K falls 8-12 % as the spring warms"))
    K, A, fr = _K(rng, True), _A(rng, True), _frac(rng)
    v = A / 2.0
    C.append(Case("O19_stack_tanh_delay_backlash_2rates_holds", ramps(1000, A, [v, 3 * v], 2, 0.6),
                  Rig(K, fr, gap_rad=u(0.03, 0.05), delay_s=0.03,
                      friction={"law": "tanh", "Fc": fr * K * A * u(20, 28), "v0": 0.02 * v}),
                  note="class 1 with a friction that lets go at rest"))
    K, A, fr = _K(rng), _A(rng), _frac(rng)
    Fc = fr * K * A * u(10, 16)
    C.append(Case("O20_clip_dahl_delay_2rates", ramps(500, A, [A / 1.5, A / 0.5], 2, 0.4),
                  Rig(K, fr, clip_frac=0.85, delay_s=u(0.015, 0.03),
                      friction={"law": "dahl", "Fc": Fc, "sigma": Fc / 0.003})))
    return C
