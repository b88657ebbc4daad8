"""Held-out generator G: benches, sampling and physics beyond the library's own laws.

The first group keeps the spring inside the library but changes how it is driven or
recorded (torque control, 5 kHz, 200 Hz, irregular timestamps, a channel skew, gear lash
or a shaft inside the deflection channel, quantisation, a cubic or hysteretic sensor,
motor cogging). The second adds physics no library law has (temperature-dependent
friction, resonance, mass loading, even sensor nonlinearity, angle crosstalk, a stiffening
coupling, a drifting clock, lost encoder counts). Truth conventions: heldout_fit_g_cases.
"""

from __future__ import annotations

import math

import numpy as np

import heldout_fit_g_sim as sim
from heldout_fit_g_cases import (Case, friction_case, gaps, levels, lib, noisy, sines, springs,
                                 stack_truth, staircase)


def mark(truth, description: str, kind: str, required: str | None = None, optional=()):
    """Record a mechanism of ``kind``; ``required`` is the library name it must be named by."""
    truth.mechanisms.append((description, kind))
    if required:
        truth.required[required] = kind
    truth.optional.update(optional)
    return truth


def torque_bench(rng, ks, gs, peak_rad, cmd_fn, fine, rate, zeta=(0.5, 0.8), j_hub=(2e-4, 6e-4),
                 fr=None, upstream=0.0):
    """A torque-controlled bench: rotor + hub inertia, motor-side damping ``zeta``."""
    k = 1 / sum(1 / x for x in ks)
    J_m, J_h = float(rng.uniform(1e-3, 3e-3)), float(rng.uniform(*j_hub))
    c = 2 * float(rng.uniform(*zeta)) * math.sqrt(k * (J_m + J_h))
    dyn = sim.Dynamics("torque", J_h, J_m, c, upstream_friction_Nm=upstream)
    cmd = cmd_fn(rng, k * peak_rad, fine)
    bench = sim.Bench(cmd, fine, rate, sim.Chain(ks, gap_rad=gs), fr, noisy(rng, k, peak_rad), dyn)
    truth = mark(stack_truth(ks, gs), "torque control: hub inertia between sensor and stack", "out")
    return bench, truth


# --------------------------------------------------------------- library physics, new benches
def c_linear_5khz_sines(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.2, 0.35))
    cmd = sim.sine_blocks([(peak / 2, 1.0, 3), (peak, 2.0, 4), (peak, 4.0, 6)], 10000.0, 0.4)
    return Case(sim.Bench(cmd, 10000.0, 5000.0, sim.Chain(ks), sensors=noisy(rng, ks[0], peak)),
                stack_truth(ks))


def c_backlash_200hz_long(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    cmd = sim.ramp_path(sim.paper_staircase(peak, 0.12 * peak / 0.3, 1.5, 6, repeats=2), 2000.0)
    return Case(sim.Bench(cmd, 2000.0, 200.0, sim.Chain(ks, gap_rad=gs), sensors=noisy(rng, k, peak)),
                lib(stack_truth(ks, gs), "backlash"))


def c_torque_control_linear(rng):
    ks = springs(rng, 1)
    bench, truth = torque_bench(rng, ks, None, float(rng.uniform(0.25, 0.4)),
                                lambda r, p, f: staircase(r, p, f, shape="cosine"), 10000.0, 1000.0)
    return Case(bench, truth)


def c_torque_control_backlash_friction(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.7))
    fr = sim.Friction(float(rng.uniform(0.015, 0.03)) * k * peak, float(rng.uniform(0.003, 0.008)))
    bench, truth = torque_bench(rng, ks, gs, peak, staircase, 10000.0, 1000.0, fr=fr)
    truth.oracle.update(friction_width_rad=fr.width_rad, friction_law=fr.law)
    return Case(bench, lib(truth, "backlash", "hysteresis"))


def c_irregular_timestamps_backlash(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    bench = sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks, gap_rad=gs),
                      sensors=noisy(rng, k, peak), jitter=0.3, drop_frac=0.03, n_bursts=3)
    truth = lib(stack_truth(ks, gs), "backlash")
    return Case(bench, mark(truth, "jittered timestamps, dropped samples", "noise"))


def c_channel_skew(rng):
    """Torque read 2-8 ms before the encoder, both logged with the encoder's time."""
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak, delay_s=float(rng.uniform(0.002, 0.008)))
    cmd = staircase(rng, peak, 4000.0, n_levels=3, speeds=(0.2, 0.8))
    truth = mark(stack_truth(ks), "torque sampled before the angle", "equiv", "time_lag")
    truth.oracle["delay_s"] = sen.delay_s
    return Case(sim.Bench(cmd, 4000.0, 1000.0, sim.Chain(ks), sensors=sen, jitter=0.2), truth)


def c_gear_lash_motor_encoder(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.3, 0.45))
    lash = float(rng.uniform(0.01, 0.03))
    bench = sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks, gear_lash_rad=lash),
                      sensors=noisy(rng, ks[0], peak), deflection_from="motor")
    truth = stack_truth(ks)
    truth.confusable.clear()
    truth.oracle["gap_rad"] = lash
    return Case(bench, mark(truth, "gear lash between motor encoder and spring", "equiv", "backlash"))


def c_shaft_in_deflection_channel(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.3, 0.45))
    k_sh = ks[0] * float(rng.uniform(10.0, 30.0))
    bench = sim.Bench(levels(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks, shaft_Nm_per_rad=k_sh),
                      sensors=noisy(rng, ks[0], peak), deflection_from="motor")
    truth = stack_truth(ks)
    truth.k_true = [1 / (1 / ks[0] + 1 / k_sh)]
    return Case(bench, mark(truth, "shaft compliance inside the deflection channel", "equiv"))


def c_quantised_adc_encoder(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.adc_step_Nm = sen.torque_noise_Nm * float(rng.uniform(0.8, 1.5))
    sen.encoder_counts = int(2 ** round(math.log2(2 * math.pi * ks[0] / sen.torque_noise_Nm)))
    sen.angle_noise_rad = 0.0
    truth = mark(stack_truth(ks), "12-bit-like ADC and encoder counts near the noise", "noise")
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks), sensors=sen), truth)


def c_sensor_cubic(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.a3 = float(rng.choice([-1, 1]) * rng.uniform(0.05, 0.09))
    truth = mark(stack_truth(ks), "torque sensor cubic in torque (on a linear spring: a cubic)",
                 "equiv", "stiffening")
    return Case(sim.Bench(sines(rng, peak, 2000.0), 2000.0, 1000.0, sim.Chain(ks), sensors=sen), truth)


def c_sensor_hysteresis(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.sensor_hyst_Nm = float(rng.uniform(0.015, 0.03)) * ks[0] * peak
    sen.sensor_hyst_width_Nm = float(rng.uniform(0.003, 0.008)) * ks[0]
    truth = mark(stack_truth(ks), "magnetic hysteresis of the torque sensor (Dahl in torque)",
                 "equiv", "hysteresis")
    truth.oracle.update(friction_width_rad=sen.sensor_hyst_width_Nm / ks[0], friction_law="dahl")
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks), sensors=sen), truth)


def c_upstream_friction_torque_control(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.4))
    bench, truth = torque_bench(rng, ks, None, peak, lambda r, p, f: staircase(r, p, f, shape="cosine"),
                                10000.0, 1000.0, upstream=0.05 * ks[0] * peak)
    return Case(bench, mark(truth, "bearing friction on the rotor, before the sensor", "invisible"))


def c_cogging_invisible(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    bench = sim.Bench(staircase(rng, peak, 4000.0), 4000.0, 1000.0, sim.Chain(ks),
                      sensors=noisy(rng, ks[0], peak), cogging_rad=float(rng.uniform(0.001, 0.003)))
    return Case(bench, mark(stack_truth(ks), "motor cogging in the motion", "invisible"))


# ------------------------------------------------------------------- outside the library
def temperature_friction(rng, case, tau=(8.0, 25.0)):
    """Make the case's friction fade as its contact warms (F drops 30-50 %)."""
    case.bench.friction.thermal_drop = float(rng.uniform(0.3, 0.5))
    case.bench.friction.thermal_tau_s = float(rng.uniform(*tau))
    case.truth.required["hysteresis"] = "family"
    case.truth.mechanisms = [m for m in case.truth.mechanisms if m[0] != "hysteresis"]
    return mark(case.truth, "friction falling with the contact's temperature", "family")


def c_temperature_friction_staircase(rng):
    case = friction_case(rng, "elastoplastic", staircase, 500.0)
    temperature_friction(rng, case)
    return case


def c_temperature_friction_sines(rng):
    case = friction_case(rng, "dahl", sines, 1000.0)
    temperature_friction(rng, case, (5.0, 15.0))
    return case


def c_temperature_friction_backlash(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    fr = sim.Friction(float(rng.uniform(0.02, 0.04)) * k * peak, float(rng.uniform(0.003, 0.008)))
    truth = lib(stack_truth(ks, gs), "backlash", "hysteresis")
    truth.oracle.update(friction_width_rad=fr.width_rad, friction_law=fr.law)
    cmd = staircase(rng, peak, 2000.0, n_levels=3, speeds=(0.3, 1.0))
    case = Case(sim.Bench(cmd, 2000.0, 1000.0, sim.Chain(ks, gap_rad=gs), fr, noisy(rng, k, peak)), truth)
    temperature_friction(rng, case)
    return case


def step_levels(rng, peak, fine, n=16):
    """Random levels reached in 15-40 ms (steps that excite the rig) and held 0.5-1.5 s."""
    wps = [(float(rng.uniform(-peak, peak)), float(rng.uniform(0.015, 0.04)), float(rng.uniform(0.5, 1.5)))
           for _ in range(n)]
    return sim.ramp_path(wps + [(0.0, 0.01, 0.5)], fine, "cosine")


def c_resonance_torque_steps(rng):
    ks = springs(rng, 1)
    bench, truth = torque_bench(rng, ks, None, float(rng.uniform(0.25, 0.4)), step_levels, 10000.0,
                                2000.0, zeta=(0.1, 0.25), j_hub=(5e-4, 1.5e-3))
    return Case(bench, mark(truth, "lightly damped rig resonance rung by torque steps", "out"))


def c_resonance_shaft_angle_steps(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.4))
    k_sh = ks[0] * float(rng.uniform(5.0, 10.0))
    f_n = float(rng.uniform(40.0, 80.0))
    J = (ks[0] + k_sh) / (2 * math.pi * f_n) ** 2
    c_sh = 2 * float(rng.uniform(0.05, 0.12)) * math.sqrt((ks[0] + k_sh) * J)
    dyn = sim.Dynamics("shaft", J, k_shaft_Nm_per_rad=k_sh, c_shaft_Nms_per_rad=c_sh)
    cmd = step_levels(rng, peak * (1 + ks[0] / k_sh), 10000.0)
    bench = sim.Bench(cmd, 10000.0, 2000.0, sim.Chain(ks), sensors=noisy(rng, ks[0], peak), dynamics=dyn)
    return Case(bench, mark(stack_truth(ks), "shaft-hub resonance, sensor on the shaft", "out"))


def c_mass_loading_sine_sweep(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.2, 0.3))
    k_sh = 200.0 * ks[0]
    J = float(rng.uniform(0.03, 0.06)) * ks[0] / (2 * math.pi * 8.0) ** 2
    c_sh = 2 * 0.3 * math.sqrt(k_sh * J)
    dyn = sim.Dynamics("shaft", J, k_shaft_Nm_per_rad=k_sh, c_shaft_Nms_per_rad=c_sh)
    cmd = sim.sine_blocks([(peak, 1.0, 3), (peak, 3.0, 6), (peak / 2, 8.0, 12)], 20000.0, 0.5)
    bench = sim.Bench(cmd, 20000.0, 2000.0, sim.Chain(ks), sensors=noisy(rng, ks[0], peak), dynamics=dyn)
    return Case(bench, mark(stack_truth(ks), "hub inertia read by the sensor (J·θ'' on 1-8 Hz sines)",
                            "out", optional=("time_lag",)))


def c_sensor_quadratic(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.a2 = float(rng.choice([-1, 1]) * rng.uniform(0.03, 0.06))
    truth = mark(stack_truth(ks), "torque sensor quadratic in torque", "out",
                 optional=("asymmetric_stiffness", "stiffening"))
    return Case(sim.Bench(levels(rng, peak, 2000.0, 18), 2000.0, 500.0, sim.Chain(ks), sensors=sen), truth)


def c_sensor_quadratic_backlash(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    sen = noisy(rng, k, peak)
    sen.a2 = float(rng.choice([-1, 1]) * rng.uniform(0.03, 0.06))
    truth = mark(lib(stack_truth(ks, gs), "backlash"), "torque sensor quadratic in torque", "out",
                 optional=("asymmetric_stiffness", "stiffening"))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks, gap_rad=gs),
                          sensors=sen), truth)


def c_sensor_angle_crosstalk(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.3, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.crosstalk = float(rng.uniform(0.02, 0.04))
    sen.crosstalk_phase_rad = float(rng.uniform(0, 2 * math.pi))
    truth = mark(stack_truth(ks), "sensor gain once per revolution of the shaft", "out",
                 optional=("asymmetric_stiffness", "stiffening"))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks), sensors=sen), truth)


def c_coupling_stiffening_motor_encoder(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.3, 0.45))
    chain = sim.Chain(ks, coupling_Nm_per_rad=ks[0] * float(rng.uniform(2.0, 4.0)),
                      coupling_ref_Nm=ks[0] * peak * float(rng.uniform(0.4, 0.8)))
    bench = sim.Bench(sines(rng, peak * 1.3, 2000.0), 2000.0, 500.0, chain,
                      sensors=noisy(rng, ks[0], peak), deflection_from="motor")
    return Case(bench, mark(stack_truth(ks), "jaw coupling stiffening inside the deflection channel",
                            "out", optional=("stiffening",)))


def c_clock_drift(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    cmd = sines(rng, peak, 2000.0, (0.3, 0.8, 1.5))
    sen = noisy(rng, ks[0], peak)
    sen.clock_drift = float(rng.uniform(0.015, 0.03)) / (cmd.size / 2000.0)
    return Case(sim.Bench(cmd, 2000.0, 1000.0, sim.Chain(ks), sensors=sen),
                mark(stack_truth(ks), "torque logged on a clock running 300-900 ppm slow", "out",
                     optional=("time_lag",)))


def c_backlash_ringing_torque_control(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    bench, truth = torque_bench(rng, ks, gs, float(rng.uniform(0.5, 0.7)), staircase, 10000.0, 1000.0,
                                zeta=(0.1, 0.2))
    return Case(bench, lib(truth, "backlash"))


def c_encoder_count_slip(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak)
    sen.encoder_counts = 2 ** 14
    cmd = staircase(rng, peak, 2000.0)
    dur = cmd.size / 2000.0
    sen.slips = [(float(rng.uniform(0.25, 0.45)) * dur, int(rng.choice([-1, 1]) * rng.integers(15, 40))),
                 (float(rng.uniform(0.6, 0.8)) * dur, int(rng.choice([-1, 1]) * rng.integers(15, 40)))]
    truth = mark(stack_truth(ks), "lost encoder counts: the angle zero steps twice", "out",
                 optional=("angle_offset", "torque_offset", "drift"))
    return Case(sim.Bench(cmd, 2000.0, 500.0, sim.Chain(ks), sensors=sen), truth)


OUT_CASES = {name[2:]: fn for name, fn in list(globals().items()) if name.startswith("c_")}
