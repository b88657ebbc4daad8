"""The records of held-out generator B, each with its truth label (rules in ``heldout_fit_b_truth``).

Library effects alone, in pairs and threes (some only identifiable together), structure outside
the library alone and beside library effects, borderline sizes (2-5x the noise), clean linear
records and unit mistakes; sine sweeps, chirps, sines at several amplitudes, triangles,
staircases and mixed protocols, stacks of 2-4 springs each with its own play, 200 Hz-5 kHz.
"""

from __future__ import annotations

import numpy as np

from heldout_fit_b_sim import Bench, Protocol, Specimen, Stack, elastoplastic_basis
from heldout_fit_b_truth import (
    AO, A, B, D, H, L, O, S, TO, Label, best_structure, bouc_wen_structure, delay_structure, derivative,
    friction_like_bases, filter_structure, noise_sd, structure, sweep,
)

# ------------------------------------------------------------------ library effects


def _lin_sweep(rng):
    k = rng.uniform(100, 300)
    p = sweep([0.25], [0.1, 0.4, 1.2], cycles=3)
    peak = k * 0.25
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(peak, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k])), b, Label(k_true=k, physics="linear spring, sine sweep 0.1-1.2 Hz"), \
        {"target": 1.03 * k}, None


def _lin_chirp_deg(rng):
    k = rng.uniform(800, 1500)
    p = Protocol().chirp(0.35, 0.05, 2.0, 40.0, taper_s=3.0)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(k * 0.35, 0.2), angle_noise_rad=5e-5)
    return p, Specimen(Stack([k])), b, Label(k_true=k, physics="linear spring, chirp 0.05-2 Hz, angles in degrees"), \
        {"angle": "deg"}, None


def _lin_stack3_nmm(rng):
    ks = [rng.uniform(120, 200), rng.uniform(250, 350), rng.uniform(180, 260)]
    st = Stack(ks)
    p = Protocol()
    for a in (0.2, 0.5, 0.8):
        p.sine(a, 0.25, 2)
        p.hold(0.5)
    b = Bench(sample_rate_hz=2000, torque_noise_Nm=noise_sd(st.k_series * 0.8, 0.15), angle_noise_rad=2e-4)
    return p, Specimen(st), b, Label(k_true=st.k_series, physics="3 springs in series, no play, sines at 3 amplitudes, "
                                                                  "torque in N·mm"), {"torque": "Nmm"}, None


def _lin_quant_200hz(rng):
    k = rng.uniform(12, 25)
    p = Protocol().triangles(1.0, 0.5, 4)
    p.hold(0.5)
    b = Bench(sample_rate_hz=200, torque_noise_Nm=noise_sd(k, 0.4), angle_noise_rad=1e-4, encoder_counts_per_rev=2**16,
              torque_lsb_Nm=0.002)
    return p, Specimen(Stack([k])), b, Label(k_true=k, physics="soft linear spring, triangles +-1 rad, 200 Hz, "
                                                               "quantised encoder and ADC"), {}, None


def _bl_stack2_tri(rng):
    st = Stack([rng.uniform(300, 500), rng.uniform(400, 700)], gap_rad=[0.006, 0.011], gap_centre_rad=[0, 0])
    p = Protocol()
    p.triangles(0.3, 0.4, 3, hold_s=0.5)
    p.triangles(0.5, 0.4, 3, hold_s=0.5)
    p.hold(0.5)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(st.k_series * 0.5, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(st), b, Label(required={B}, k_true=st.k_series,
                                     physics="2 springs in series each with its own play (6 and 11 mrad), triangles"), \
        {"target": 0.97 * st.k_series}, None


def _bl_stack4_multisine(rng):
    gaps = list(rng.uniform(0.003, 0.01, 4))
    st = Stack([rng.uniform(400, 900) for _ in range(4)], gap_rad=gaps, gap_centre_rad=[0] * 4)
    p = Protocol()
    for a in (0.4, 0.8, 1.2):
        p.sine(a, 0.2, 2)
        p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(st.k_series * 1.2, 0.3), angle_noise_rad=2e-4)
    return p, Specimen(st), b, Label(required={B}, k_true=st.k_series,
                                     physics=f"4 springs in series, plays summing to {sum(gaps):.3f} rad, sines 0.4-1.2 rad"), \
        {}, None


def _hyst_ep_sines(rng):
    k = rng.uniform(150, 400)
    peak = k * 0.35
    fr = {"law": "elastoplastic", "force_Nm": 0.02 * peak, "presliding_rad": 0.004}
    p = sweep([0.15, 0.25, 0.35], [0.1, 0.5], cycles=2)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(peak, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), friction=fr), b, Label(required={H}, k_true=k,
                                                          physics="Coulomb friction 2 % of peak with 4 mrad presliding, "
                                                                  "sines at 3 amplitudes x 2 rates"), {}, None


def _hyst_bw_chirp(rng):
    k = rng.uniform(200, 500)
    peak = k * 0.3
    fr = {"law": "bouc_wen", "force_Nm": 0.015 * peak, "presliding_rad": 0.002, "n": 1.5, "beta": 0.5}
    p = Protocol().chirp(0.3, 0.05, 1.0, 45.0)
    p.hold(0.5)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(peak, 0.3), angle_noise_rad=1e-4)
    lab = Label(required={H}, k_true=k, physics="Bouc-Wen friction (n=1.5, 2 mrad) 1.5 % of peak, chirp 0.05-1 Hz")
    return p, Specimen(Stack([k]), friction=fr), b, lab, {}, lambda rec: bouc_wen_structure(rec, 1000, k)


def _lag_sweep(rng):
    k = rng.uniform(300, 800)
    p = sweep([0.15, 0.3], [0.1, 0.3, 1.0], cycles=3)
    b = Bench(sample_rate_hz=1000, delay_s=0.015, torque_noise_Nm=noise_sd(k * 0.3, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k])), b, Label(required={L}, k_true=k, physics="torque channel 15 ms late (clock offset), "
                                                                             "sine sweep"), {}, None


def _drift_staircase(rng):
    k = rng.uniform(100, 250)
    p = Protocol().staircase([0.1, 0.2, 0.3], ramp_s=1.5, hold_s=1.5)
    p.hold(0.5)
    peak = k * 0.3
    b = Bench(sample_rate_hz=500, torque_drift_Nm_per_s=0.03 * peak / p.duration_s(),
              torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k])), b, Label(required={D}, optional={TO, AO}, k_true=k,
                                             physics="torque zero drifts linearly by 3 % of peak from 0 at t=0, staircase"), \
        {}, None


def _bl_torque_offset(rng):
    st = Stack([rng.uniform(500, 900), rng.uniform(500, 900)], gap_rad=[0.012, 0.008], gap_centre_rad=[0, 0])
    p = Protocol()
    p.triangles(0.25, 0.3, 2, hold_s=0.3)
    p.triangles(0.4, 0.3, 2, hold_s=0.3)
    peak = st.k_series * 0.4
    b = Bench(sample_rate_hz=1000, torque_offset_Nm=0.015 * peak, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(st), b, Label(required={B, TO}, k_true=st.k_series,
                                     physics="2-spring stack with plays + torque zero error 1.5 % of peak "
                                             "(the dead band shows the offset is in torque)"), {}, None


def _bl_angle_offset_stack3(rng):
    st = Stack([rng.uniform(300, 600) for _ in range(3)], gap_rad=[0.008, 0.006, 0.007],
               gap_centre_rad=[0.003, 0.002, 0.002])
    p = sweep([0.3, 0.6], [0.15, 0.4], cycles=2)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(st.k_series * 0.6, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(st), b, Label(required={B, AO}, k_true=st.k_series,
                                     physics="3-spring stack, plays not centred (dead band centre 7 mrad off zero)"), {}, None


def _stiff_tri(rng):
    k = rng.uniform(200, 600)
    k3 = 0.08 * k / 0.6**2
    p = Protocol()
    p.triangles(0.3, 0.3, 2)
    p.triangles(0.6, 0.3, 2)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(k * 0.6, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), k3_Nm_per_rad3=k3), b, Label(required={S}, k_true=k,
                                                                physics="cubic hardening, +8 % at 0.6 rad, triangles"), {}, None


def _asym_sine(rng):
    k = rng.uniform(300, 700)
    p = sweep([0.2, 0.35], [0.2, 0.6], cycles=3)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(k * 0.35, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), neg_ratio=0.9), b, Label(required={A}, k_true=(k, 0.9 * k),
                                                            physics="K for negative deflection 10 % lower, sines"), {}, None


def _outliers_levels(rng):
    k = rng.uniform(50, 150)
    p = Protocol().levels(rng, 14, 0.4, 0.4, hold_s=(0.5, 2.0))
    p.hold(0.5)
    sd = noise_sd(k * 0.4, 0.3)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=sd, angle_noise_rad=1e-4, spikes=12, spike_Nm=20 * sd)
    return p, Specimen(Stack([k])), b, Label(required={O}, k_true=k, physics="12 isolated torque spikes of 20-40 sigma, "
                                                                             "random levels"), {}, None


def _bl_hyst_2rates(rng):
    st = Stack([rng.uniform(200, 400), rng.uniform(200, 400)], gap_rad=[0.01, 0.008], gap_centre_rad=[0, 0])
    peak = st.k_series * 0.3
    fr = {"law": "elastoplastic", "force_Nm": 0.02 * peak, "presliding_rad": 0.003}
    p = Protocol().staircase([0.15, 0.3], rate_rad_per_s=0.1, hold_s=1.0)
    p.staircase([0.15, 0.3], rate_rad_per_s=0.4, hold_s=1.0)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(peak, 0.3), angle_noise_rad=1e-4)
    return p, Specimen(st, friction=fr), b, Label(required={B, H}, k_true=st.k_series,
                                                  physics="2-spring stack with plays + Coulomb friction, staircase at 2 "
                                                          "rates with holds"), {}, None


def _hyst_lag_1rate(rng):
    k = rng.uniform(200, 400)
    peak = k * 0.3
    fr = {"law": "elastoplastic", "force_Nm": 0.015 * peak, "presliding_rad": 0.004}
    p = Protocol().triangles(0.3, 0.3, 6)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, delay_s=0.02, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), friction=fr), b, Label(anyof=[{H, L}], may_confound=[{H, L}], k_true=k,
                                                          physics="Coulomb friction + 20 ms delay on ONE ramp rate "
                                                                  "(confounded pair)"), {}, None


def _hyst_lag_sweep(rng):
    k = rng.uniform(200, 400)
    peak = k * 0.3
    fr = {"law": "elastoplastic", "force_Nm": 0.015 * peak, "presliding_rad": 0.003}
    p = sweep([0.3], [0.05, 0.3, 1.5], cycles=3)
    b = Bench(sample_rate_hz=1000, delay_s=0.01, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), friction=fr), b, Label(required={H, L}, k_true=k,
                                                          physics="Coulomb friction + 10 ms delay, sine sweep over 30x "
                                                                  "in frequency (separable)"), {"target": 1.05 * k}, None


def _bl_stiff_drift(rng):
    st = Stack([rng.uniform(200, 400), rng.uniform(300, 500)], gap_rad=[0.01, 0.012], gap_centre_rad=[0, 0])
    k = st.k_series
    p = Protocol().staircase([0.2, 0.4, 0.6], ramp_s=2.0, hold_s=1.0)
    p.hold(0.5)
    peak = k * 0.6
    b = Bench(sample_rate_hz=500, torque_drift_Nm_per_s=0.03 * peak / p.duration_s(),
              torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    return p, Specimen(st, k3_Nm_per_rad3=0.1 * k / 0.6**2), b, Label(
        required={B, S, D}, optional={TO}, k_true=k,
        physics="stack with plays + cubic hardening 10 % + torque drift 3 %, staircase"), {}, None


def _asym_bw_outliers_mixed(rng):
    k = rng.uniform(400, 900)
    peak = k * 0.35
    fr = {"law": "bouc_wen", "force_Nm": 0.02 * peak, "presliding_rad": 0.002, "n": 2.0, "beta": 0.5}
    p = Protocol().triangles(0.25, 0.3, 2, hold_s=0.5)
    p.sine(0.35, 0.3, 3)
    p.hold(0.3)
    p.chirp(0.3, 0.1, 0.8, 20.0)
    p.hold(0.5)
    sd = noise_sd(peak, 0.3)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=sd, angle_noise_rad=1e-4, spikes=8, spike_Nm=25 * sd)
    lab = Label(required={A, H, O}, k_true=(k, 0.92 * k),
                physics="asymmetric K (-8 %) + Bouc-Wen friction (n=2) 2 % + 8 spikes, triangles+sines+chirp")
    return p, Specimen(Stack([k]), neg_ratio=0.92, friction=fr), b, lab, {}, lambda rec: bouc_wen_structure(rec, 1000, k)


def _lag_stiff_offset_chirp(rng):
    k = rng.uniform(500, 1200)
    p = Protocol().chirp(0.5, 0.05, 1.0, 50.0)
    p.hold(0.5)
    peak = k * 0.5
    b = Bench(sample_rate_hz=1000, delay_s=0.008, torque_offset_Nm=0.02 * peak, torque_noise_Nm=noise_sd(peak, 0.3),
              angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), k3_Nm_per_rad3=0.1 * k / 0.25), b, Label(
        required={L, S}, anyof=[{TO, AO}], may_confound=[{TO, AO}], k_true=k,
        physics="8 ms delay + cubic hardening 10 % + torque offset 2 %, chirp"), {}, None


# ---- out of the library


def _hum50(rng):
    k = rng.uniform(100, 300)
    p = sweep([0.3], [0.1, 0.4, 1.0], cycles=3)
    sd = noise_sd(k * 0.3, 0.25)
    b = Bench(sample_rate_hz=1000, hum=[(3 * sd, 50.0), (0.8 * sd, 150.0)], torque_noise_Nm=sd, angle_noise_rad=1e-4)
    lab = Label(in_library=False, unexplained=True, k_true=k, physics="linear spring + 50 Hz mains hum (3 sigma, "
                                                                      "with 150 Hz), sine sweep")
    return p, Specimen(Stack([k])), b, lab, {}, lambda rec: structure(rec, rec.parts["hum"], [], k)


def _hum60_backlash_200hz(rng):
    st = Stack([rng.uniform(600, 1000), rng.uniform(800, 1200)], gap_rad=[0.008, 0.01], gap_centre_rad=[0, 0])
    p = Protocol().triangles(0.3, 0.25, 4, hold_s=0.5)
    p.hold(0.5)
    sd = noise_sd(st.k_series * 0.3, 0.3)
    b = Bench(sample_rate_hz=200, hum=[(3 * sd, 60.0)], torque_noise_Nm=sd, angle_noise_rad=1e-4)
    lab = Label(required={B}, in_library=False, unexplained=True, k_true=st.k_series,
                physics="stack with plays + 60 Hz hum (3 sigma) sampled at 200 Hz, triangles")
    return p, Specimen(st), b, lab, {}, lambda rec: structure(rec, rec.parts["hum"], [], st.k_series)


def _ripple_angle(rng):
    k = rng.uniform(300, 600)
    p = Protocol().triangles(0.4, 0.2, 3)
    p.hold(0.5)
    sd = noise_sd(k * 0.4, 0.25)
    b = Bench(sample_rate_hz=500, ripple_Nm=4 * sd, ripple_period_rad=0.031, torque_noise_Nm=sd, angle_noise_rad=1e-4)
    lab = Label(in_library=False, unexplained=True, k_true=k,
                physics="torque ripple periodic in angle (31 mrad pitch, 4 sigma), triangles")
    return p, Specimen(Stack([k])), b, lab, {}, lambda rec: structure(rec, rec.parts["ripple"],
                                                                       [rec.theta_torque_rad**3], k)


def _ripple_hyst(rng):
    k = rng.uniform(200, 500)
    peak = k * 0.35
    fr = {"law": "elastoplastic", "force_Nm": 0.02 * peak, "presliding_rad": 0.003}
    p = sweep([0.2, 0.35], [0.1, 0.3], cycles=2)
    sd = noise_sd(peak, 0.25)
    b = Bench(sample_rate_hz=1000, ripple_Nm=3 * sd, ripple_period_rad=0.045, torque_noise_Nm=sd, angle_noise_rad=1e-4)
    lab = Label(required={H}, in_library=False, unexplained=True, k_true=k,
                physics="Coulomb friction + torque ripple periodic in angle (45 mrad, 3 sigma), sines")
    return p, Specimen(Stack([k]), friction=fr), b, lab, {}, lambda rec: structure(
        rec, rec.parts["ripple"], [rec.theta_torque_rad**3, elastoplastic_basis(rec.theta_torque_rad, 0.003)], k)


def _stickslip(rng):
    k = rng.uniform(150, 350)
    peak = k * 0.3
    fs_, fk = 0.03 * peak, 0.018 * peak
    fr = {"law": "stickslip", "static_Nm": fs_, "kinetic_Nm": fk, "stick_Nm_per_rad": (fs_ - fk) / 0.012}
    p = Protocol().triangles(0.3, 0.15, 2)
    p.triangles(0.3, 0.45, 3)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    lab = Label(required={H}, in_library=False, unexplained=True, k_true=k,
                physics="stick-slip: friction builds 1.8->3 % of peak over 12 mrad then drops (sawtooth in angle)")
    return p, Specimen(Stack([k]), friction=fr), b, lab, {}, lambda rec: best_structure(
        rec, rec.parts["friction"], friction_like_bases(rec, 500, (2e-3, 8e-3, 2e-2, 5e-2)), k)


def _kstep(rng):
    k = rng.uniform(150, 400)
    p = Protocol().staircase([0.1, 0.2, 0.3], ramp_s=1.5, hold_s=1.0)
    p.staircase([0.1, 0.2, 0.3], ramp_s=1.5, hold_s=1.0)
    p.hold(0.5)
    ts = 0.55 * p.duration_s()
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(k * 0.3, 0.25), angle_noise_rad=1e-4)
    sp = Specimen(Stack([k]), step_at_s=ts, step_ratio=0.95)
    lab = Label(in_library=False, unexplained=True, k_true=k, k_scored=False,
                physics="stiffness drops 5 % at 55 % of the record (a crack/slip), staircase repeated")

    def struct(rec):
        x = rec.theta_torque_rad
        comp = -0.05 * k * x * (rec.t_s >= ts)
        return structure(rec, comp, [x**3], k)

    return p, sp, b, lab, {}, struct

def _lpf20_fast(rng):
    k = rng.uniform(300, 700)
    p = Protocol().triangles(0.4, 2.0, 6)
    p.hold(0.3)
    p.sine(0.3, 2.0, 8)
    p.hold(0.5)
    b = Bench(sample_rate_hz=2000, filter_tau_s=0.02, torque_noise_Nm=noise_sd(k * 0.4, 0.25), angle_noise_rad=1e-4)
    lab = Label(required={L}, in_library=False, unexplained=True, k_true=k, k_scored=False,
                physics="torque sensor first-order filter 20 ms, fast triangles (2 rad/s) and 2 Hz sines")
    return p, Specimen(Stack([k])), b, lab, {}, lambda rec: filter_structure(rec, k, 0.02)


def _lpf5_slow(rng):
    k = rng.uniform(300, 700)
    p = sweep([0.3], [0.05, 0.1, 0.2], cycles=2)
    b = Bench(sample_rate_hz=500, filter_tau_s=0.005, torque_noise_Nm=noise_sd(k * 0.3, 0.2), angle_noise_rad=1e-4)
    lab = Label(required={L}, k_true=k,
                physics="torque sensor first-order filter 5 ms on slow sines (omega*tau < 0.007: a pure delay)")
    return p, Specimen(Stack([k])), b, lab, {}, lambda rec: filter_structure(rec, k, 0.005)


def _clip(rng):
    k = rng.uniform(100, 300)
    p = sweep([0.2, 0.35], [0.2, 0.5], cycles=3)
    peak = k * 0.35
    b = Bench(sample_rate_hz=1000, clip_Nm=0.85 * peak, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    lab = Label(in_library=False, unexplained=True, k_true=k, k_scored=False,
                physics="torque sensor clips at 85 % of peak torque, sines at 2 amplitudes")
    return p, Specimen(Stack([k])), b, lab, {}, lambda rec: structure(rec, rec.parts["clip"],
                                                                       [rec.theta_torque_rad**3], k)


def _creep(rng):
    k = rng.uniform(150, 300)
    p = Protocol().staircase([0.1, 0.2, 0.3], ramp_s=1.0, hold_s=3.0)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(k * 0.3, 0.25), angle_noise_rad=1e-4)
    sp = Specimen(Stack([k]), ve_stiffness_Nm_per_rad=0.08 * k, ve_tau_s=1.2)
    lab = Label(optional={H, L}, in_library=False, unexplained=True, k_true=k, k_scored=False,
                physics="viscoelastic relaxation: 8 % extra stiffness relaxing with tau 1.2 s during 3 s holds")

    def struct(rec):
        v = derivative(rec.theta_torque_rad, 500)
        return best_structure(rec, rec.parts["viscoelastic"],
                               [[v] + b_ for b_ in friction_like_bases(rec, 500)], k)

    return p, sp, b, lab, {}, struct


def _pink(rng):
    k = rng.uniform(200, 500)
    p = sweep([0.3], [0.1, 0.3, 0.9], cycles=3)
    sd = noise_sd(k * 0.3, 0.25)
    b = Bench(sample_rate_hz=1000, pink_Nm=0.7 * sd, torque_noise_Nm=sd, angle_noise_rad=1e-4)
    lab = Label(optional={D, TO, AO}, k_true=k, physics="linear spring, white + 1/f torque noise (0.7 sigma), sine sweep")
    return p, Specimen(Stack([k])), b, lab, {}, None


def _skew(rng):
    k = rng.uniform(300, 600)
    p = sweep([0.3], [0.2, 0.5, 1.0], cycles=4)
    p2 = sweep([0.3], [0.2, 0.5, 1.0], cycles=4)
    for s in p2.segments:  # repeat the sweep
        d = p.t_s
        p.segments.append(type(s)(s.kind, s.t0_s + d, s.t1_s + d, s.a_rad, s.b_rad, s.f_hz, s.f2_hz, s.shape, s.taper_s))
    p.t_s = p.segments[-1].t1_s
    skew = 0.03 / p.duration_s()
    b = Bench(sample_rate_hz=1000, delay_s=0.002, skew=skew, torque_noise_Nm=noise_sd(k * 0.3, 0.25), angle_noise_rad=1e-4)
    lab = Label(required={L}, in_library=False, unexplained=True, k_true=k,
                physics="clock skew: torque delay grows 2 -> 32 ms over the record, sine sweep run twice")

    def struct(rec):
        lag = 0.002 + skew * rec.t_s
        comp = k * (p.theta(rec.t_s - lag) - p.theta(rec.t_s - lag.mean()))
        return structure(rec, comp, [derivative(k * rec.theta_torque_rad, 1000)], k)

    return p, Specimen(Stack([k])), b, lab, {}, struct


def _fading(rng):
    k = rng.uniform(150, 350)
    peak = k * 0.3
    p = Protocol().staircase([0.15, 0.3], rate_rad_per_s=0.05, hold_s=1.5, shape="linear")
    p.staircase([0.15, 0.3], rate_rad_per_s=0.4, hold_s=1.5, shape="linear")
    p.hold(0.5)
    fr = {"law": "fading", "force_Nm": 0.03 * peak, "v0_rad_per_s": 0.08}
    b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(peak, 0.25), angle_noise_rad=1e-4)
    lab = Label(anyof=[{H, L}], may_confound=[{H, L}], in_library=False, unexplained=True, k_true=k,
                physics="velocity-fading friction 3 % * tanh(v/0.08 rad/s) (zero at rest), ramps at 0.05 and 0.4 rad/s")

    def struct(rec):
        v = derivative(rec.theta_torque_rad, 500)
        return best_structure(rec, rec.parts["friction"], [[v] + b_ for b_ in friction_like_bases(rec, 500)], k)

    return p, Specimen(Stack([k]), friction=fr), b, lab, {}, struct


def _viscous(rng):
    k = rng.uniform(300, 600)
    p = sweep([0.25], [0.1, 0.4, 1.2], cycles=3)
    fr = {"law": "viscous", "c_Nms_per_rad": 0.012 * k}
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=noise_sd(k * 0.25, 0.25), angle_noise_rad=1e-4)
    lab = Label(required={L}, k_true=k, physics="viscous damping c = 0.012 K (torque leads angle by 12 ms: a "
                                                "negative channel delay except at the velocity steps where each "
                                                "sine starts and stops), sine sweep")
    return p, Specimen(Stack([k]), friction=fr), b, lab, {}, lambda rec: delay_structure(
        rec, rec.parts["friction"], rec.parts["elastic"], -0.012 * np.linspace(0.5, 1.5, 41), k)


# ---- borderline (effect 2-5x the noise)


def _bl_small(rng):
    k = rng.uniform(300, 600)
    peak = k * 0.3
    sd = noise_sd(peak, 0.3)
    gap = 2 * 3 * sd / k  # K * b / 2 = 3 sigma
    p = Protocol().triangles(0.3, 0.3, 4, hold_s=0.3)
    p.hold(0.5)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=sd, angle_noise_rad=2e-5)
    return p, Specimen(Stack([k], gap_rad=[gap], gap_centre_rad=[0])), b, Label(
        required={B}, k_true=k, physics=f"small play {gap * 1e3:.2f} mrad (K b/2 = 3 sigma), triangles"), {}, None


def _hyst_small(rng):
    k = rng.uniform(200, 400)
    peak = k * 0.3
    sd = noise_sd(peak, 0.3)
    fr = {"law": "elastoplastic", "force_Nm": 2.5 * sd, "presliding_rad": 0.003}
    p = sweep([0.3], [0.1, 0.3], cycles=4)
    b = Bench(sample_rate_hz=1000, torque_noise_Nm=sd, angle_noise_rad=1e-4)
    return p, Specimen(Stack([k]), friction=fr), b, Label(required={H}, k_true=k,
                                                          physics="Coulomb friction of 2.5 sigma, sines"), {}, None


def _ripple_small_bl(rng):
    k = rng.uniform(400, 800)
    peak = k * 0.35
    sd = noise_sd(peak, 0.3)
    p = sweep([0.2, 0.35], [0.15, 0.4], cycles=3)
    b = Bench(sample_rate_hz=1000, ripple_Nm=2.5 * sd, ripple_period_rad=0.025, torque_noise_Nm=sd, angle_noise_rad=1e-4)
    st = Stack([k], gap_rad=[0.012], gap_centre_rad=[0])
    lab = Label(required={B}, in_library=False, unexplained=True, k_true=k,
                physics="play 12 mrad + ripple periodic in angle of 2.5 sigma (25 mrad pitch), sines")
    return p, Specimen(st), b, lab, {}, lambda rec: structure(rec, rec.parts["ripple"], [rec.theta_torque_rad**3], k)


def _drift_small(rng):
    k = rng.uniform(100, 300)
    peak = k * 0.3
    sd = noise_sd(peak, 0.3)
    p = Protocol().triangles(0.3, 0.2, 5, hold_s=0.5)
    p.hold(0.5)
    b = Bench(sample_rate_hz=500, torque_drift_Nm_per_s=4 * sd / p.duration_s(), torque_noise_Nm=sd, angle_noise_rad=1e-4)
    return p, Specimen(Stack([k])), b, Label(required={D}, optional={TO, AO}, k_true=k,
                                             physics="torque drift of 4 sigma over the record, triangles"), {}, None


def _mixed_5khz(rng):
    st = Stack([rng.uniform(800, 1500), rng.uniform(1000, 2000)], gap_rad=[0.004, 0.006], gap_centre_rad=[0, 0])
    p = Protocol().staircase([0.15, 0.3], ramp_s=1.0, hold_s=0.5)
    p.sine(0.3, 0.5, 3)
    p.hold(0.3)
    p.chirp(0.25, 0.2, 1.5, 10.0, taper_s=1.5)
    p.hold(0.5)
    sd = noise_sd(st.k_series * 0.3, 0.3)
    b = Bench(sample_rate_hz=5000, delay_s=0.006, hum=[(2.5 * sd, 50.0)], torque_noise_Nm=sd, angle_noise_rad=5e-5)
    lab = Label(required={B, L}, in_library=False, unexplained=True, k_true=st.k_series,
                physics="stack with plays + 6 ms delay + 50 Hz hum 2.5 sigma, staircase+sine+chirp at 5 kHz")
    return p, Specimen(st), b, lab, {"angle": "deg", "torque": "Nmm"}, lambda rec: structure(rec, rec.parts["hum"], [],
                                                                                              st.k_series)


# ---- unit mistakes


def _unit(kind):
    def build(rng):
        k = rng.uniform(100, 300)
        p = sweep([0.3], [0.2, 0.5], cycles=3)
        b = Bench(sample_rate_hz=500, torque_noise_Nm=noise_sd(k * 0.3, 0.3), angle_noise_rad=1e-4)
        lab = Label(refusal=True, k_true=k, physics={
            "deg_as_rad": "angles written in degrees under deflection_rad, --target-stiffness given",
            "nmm_as_nm": "torque written in N·mm under torque_Nm, --target-stiffness given",
            "rad_as_deg": "angles in rad but --angle-unit deg (0.3 'degrees' of travel)"}[kind])
        fmt = {"deg_as_rad": {"angle": "deg", "header_as_si": True, "target": k},
               "nmm_as_nm": {"torque": "Nmm", "header_as_si": True, "target": k},
               "rad_as_deg": {"claim_angle_deg": True}}[kind]
        return p, Specimen(Stack([k])), b, lab, fmt, None

    return build


CASES = [
    ("lin_sweep", _lin_sweep),
    ("lin_chirp_deg", _lin_chirp_deg),
    ("lin_stack3_nmm", _lin_stack3_nmm),
    ("lin_quant_200hz", _lin_quant_200hz),
    ("bl_stack2_tri", _bl_stack2_tri),
    ("bl_stack4_multisine", _bl_stack4_multisine),
    ("hyst_ep_sines", _hyst_ep_sines),
    ("hyst_bw_chirp", _hyst_bw_chirp),
    ("lag_sweep", _lag_sweep),
    ("drift_staircase", _drift_staircase),
    ("bl_torque_offset", _bl_torque_offset),
    ("bl_angle_offset_stack3", _bl_angle_offset_stack3),
    ("stiff_tri", _stiff_tri),
    ("asym_sine", _asym_sine),
    ("outliers_levels", _outliers_levels),
    ("bl_hyst_2rates", _bl_hyst_2rates),
    ("hyst_lag_1rate", _hyst_lag_1rate),
    ("hyst_lag_sweep", _hyst_lag_sweep),
    ("bl_stiff_drift", _bl_stiff_drift),
    ("asym_bw_outliers_mixed", _asym_bw_outliers_mixed),
    ("lag_stiff_offset_chirp", _lag_stiff_offset_chirp),
    ("viscous_sweep", _viscous),
    ("lpf5_slow", _lpf5_slow),
    ("hum50", _hum50),
    ("hum60_bl_200hz", _hum60_backlash_200hz),
    ("ripple_angle", _ripple_angle),
    ("ripple_hyst", _ripple_hyst),
    ("stickslip", _stickslip),
    ("kstep", _kstep),
    ("lpf20_fast", _lpf20_fast),
    ("clip", _clip),
    ("creep", _creep),
    ("pink_noise", _pink),
    ("skew", _skew),
    ("fading_friction", _fading),
    ("bl_small", _bl_small),
    ("hyst_small", _hyst_small),
    ("ripple_small_bl", _ripple_small_bl),
    ("drift_small", _drift_small),
    ("mixed_5khz", _mixed_5khz),
    ("unit_deg_as_rad", _unit("deg_as_rad")),
    ("unit_nmm_as_nm", _unit("nmm_as_nm")),
    ("unit_rad_as_deg", _unit("rad_as_deg")),
]


