"""Held-out generator G: the records and their truth, decided from physics (issue 24).

Every case is a function of a seeded ``numpy.random.Generator`` that returns a
:class:`Case`: the bench to simulate, the CLI options to read its CSV, and the truth.
Kinds of mechanism (bench/heldout_fit_g.md, "Truth"): ``lib`` (a library effect's own
law), ``equiv`` (a rig mechanism that is exactly a library effect in this record: gear lash
in the deflection channel is a clearance, a channel skew is a delay, a cubic sensor on a
linear spring is a cubic), ``family`` (the family is the library's, the law is not),
``out`` (no library name), ``invisible`` (no trace in torque against deflection) and
``noise`` (quantisation, sampling irregularities).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import heldout_fit_g_sim as sim


@dataclass
class Truth:
    """What is in a record.

    Attributes:
        required: library names that must be named, with their kind.
        optional: names that may be named (physically present in a form they describe).
        confusable: pairs {a, b} of which naming either satisfies the other.
        mechanisms: (description, kind) of everything simulated beyond a linear spring.
        k_true: accepted stiffness values (N·m/rad) of what the deflection channel spans.
        oracle: parameters of the library laws the oracle fits (clearance, centre, delay).
    """

    required: dict = field(default_factory=dict)
    optional: set = field(default_factory=set)
    confusable: list = field(default_factory=list)
    mechanisms: list = field(default_factory=list)
    k_true: list = field(default_factory=list)
    oracle: dict = field(default_factory=dict)

    @property
    def in_library(self) -> bool:
        """Everything simulated is within the library's meaning (K is then scored; K is
        also scored where the oracle finds physics outside it at the noise, E <= 200)."""
        return all(kind in ("lib", "equiv", "invisible", "noise") for _, kind in self.mechanisms)

    @property
    def needs_oracle(self) -> bool:
        """The unexplained label is decided by the oracle when physics outside is present."""
        return any(kind in ("family", "out") for _, kind in self.mechanisms)


@dataclass
class Case:
    """A bench to simulate, the CLI options for its CSV, and its truth."""

    bench: sim.Bench
    truth: Truth
    angle_unit: str = "rad"
    torque_unit: str = "Nm"
    names: tuple = ("time_s", "torque_Nm", "deflection_rad")


# --------------------------------------------------------------------------- shared draws
def log_uniform(rng, lo: float, hi: float) -> float:
    """A value log-uniform in [lo, hi]."""
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def springs(rng, n: int) -> list:
    """Stiffness of n disks (N·m/rad), 30-400 each (the paper's S1/S2 are 150 and 75)."""
    return [log_uniform(rng, 30.0, 400.0) for _ in range(n)]


def gaps(rng, n: int) -> list:
    """Clearance of n cam-flexure interfaces (rad): the paper measured 0.011-0.06 per stack."""
    return [float(rng.uniform(0.008, 0.02)) for _ in range(n)]


def noisy(rng, k_Nm_per_rad: float, peak_rad: float, **kw) -> sim.Sensors:
    """Sensors with torque noise 0.15-0.5 % of peak torque and angle noise 2e-5-2e-4 rad."""
    peak_T = k_Nm_per_rad * peak_rad
    return sim.Sensors(torque_noise_Nm=float(rng.uniform(0.0015, 0.005)) * peak_T,
                       angle_noise_rad=log_uniform(rng, 2e-5, 2e-4),
                       full_scale_Nm=1.3 * peak_T, **kw)


def staircase(rng, peak: float, fine: float, n_levels: int = 6, shape: str = "linear",
              speeds=None, hold=(0.5, 1.5)) -> np.ndarray:
    """The paper's staircase at one speed (or one run per speed in ``speeds``)."""
    hold_s = float(rng.uniform(*hold))
    if speeds:
        return sim.ramp_path(sim.multi_rate(peak, speeds, hold_s, n_levels), fine, shape)
    speed = float(rng.uniform(0.15, 0.4)) * peak / 0.3
    return sim.ramp_path(sim.paper_staircase(peak, speed, hold_s, n_levels), fine, shape)


def sines(rng, peak: float, fine: float, freqs=(0.3, 0.7, 1.5)) -> np.ndarray:
    """Sine blocks: half and full amplitude at the first frequency (Hz), then full
    amplitude at the others, each block lasting 2/freqs[0] seconds."""
    f0 = freqs[0]
    blocks = [(0.5 * peak, f0, 2), (peak, f0, 2)] + [(peak, f, int(round(2 * f / f0))) for f in freqs[1:]]
    return sim.sine_blocks(blocks, fine)


def levels(rng, peak: float, fine: float, n: int = 14) -> np.ndarray:
    """Random levels reached at 0.1-0.5 rad/s (scaled with the peak) and held 0.5-2 s."""
    s = peak / 0.3
    return sim.ramp_path(sim.random_levels(rng, peak, n, (0.1 * s, 0.5 * s), (0.5, 2.0)), fine)


def stack_truth(ks, gs=None, **kw) -> Truth:
    """Truth of a stack: K_true = series stiffness, clearance in the oracle."""
    k = 1.0 / sum(1.0 / x for x in ks)
    t = Truth(k_true=[k], oracle={"gap_rad": sum(gs or [0.0])}, **kw)
    if not gs:
        t.confusable.append({"torque_offset", "angle_offset"})
    return t


def lib(truth: Truth, *names) -> Truth:
    """Mark library effects as present with their own law."""
    for n in names:
        truth.required[n] = "lib"
        truth.mechanisms.append((n, "lib"))
    return truth


# ------------------------------------------------------------------- library, one at a time
def c_linear_staircase(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks),
                          sensors=noisy(rng, ks[0], peak)), stack_truth(ks))


def c_backlash_stack2_staircase(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    return Case(sim.Bench(staircase(rng, peak, 2000.0, shape="cosine"), 2000.0, 500.0,
                          sim.Chain(ks, gap_rad=gs), sensors=noisy(rng, k, peak)),
                lib(stack_truth(ks, gs), "backlash"))


def c_backlash_stack3_rates_deg(rng):
    ks, gs = springs(rng, 3), gaps(rng, 3)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.7, 1.0))
    cmd = staircase(rng, peak, 2000.0, n_levels=3, speeds=(0.3, 0.8, 1.6), hold=(0.3, 0.8))
    return Case(sim.Bench(cmd, 2000.0, 500.0, sim.Chain(ks, gap_rad=gs), sensors=noisy(rng, k, peak)),
                lib(stack_truth(ks, gs), "backlash"), "deg", "Nmm",
                ("t", "torque_Nmm", "angle_deg"))


def friction_case(rng, law, cmd_fn, rate=1000.0):
    """A single disk with friction (1.5-4 % of the peak torque) of the given law."""
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    fr = sim.Friction(float(rng.uniform(0.015, 0.04)) * ks[0] * peak,
                      float(rng.uniform(0.002, 0.008)), law)
    t = lib(stack_truth(ks), "hysteresis")
    t.oracle.update(friction_width_rad=fr.width_rad, friction_law=law)
    return Case(sim.Bench(cmd_fn(rng, peak, 2000.0), 2000.0, rate, sim.Chain(ks), fr,
                          noisy(rng, ks[0], peak)), t)


def c_friction_elastoplastic_staircase(rng):
    return friction_case(rng, "elastoplastic", staircase, 500.0)


def c_friction_dahl_sines(rng):
    return friction_case(rng, "dahl", sines, 1000.0)


def c_delay_two_rates(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak, delay_s=float(rng.uniform(0.005, 0.03)))
    cmd = staircase(rng, peak, 2000.0, n_levels=3, speeds=(0.15, 0.6))
    t = lib(stack_truth(ks), "time_lag")
    t.oracle["delay_s"] = sen.delay_s
    return Case(sim.Bench(cmd, 2000.0, 500.0, sim.Chain(ks), sensors=sen), t)


def c_drift_levels(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    cmd = levels(rng, peak, 2000.0)
    dur = cmd.size / 2000.0
    sen = noisy(rng, ks[0], peak)
    sen.torque_drift_Nm_per_s = float(rng.choice([-1, 1]) * rng.uniform(0.015, 0.03)) * ks[0] * peak / dur
    t = lib(stack_truth(ks), "drift")
    t.optional.add("torque_offset")
    return Case(sim.Bench(cmd, 2000.0, 500.0, sim.Chain(ks), sensors=sen), t)


def c_torque_offset_backlash(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    sen = noisy(rng, k, peak)
    sen.torque_offset_Nm = float(rng.choice([-1, 1]) * rng.uniform(0.02, 0.05)) * k * peak
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, sim.Chain(ks, gap_rad=gs),
                          sensors=sen), lib(stack_truth(ks, gs), "backlash", "torque_offset"))


def c_angle_offset_backlash(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    centre = float(rng.choice([-1, 1]) * rng.uniform(0.006, 0.015))
    t = lib(stack_truth(ks, gs), "backlash", "angle_offset")
    t.oracle["centre_rad"] = centre
    chain = sim.Chain(ks, gap_rad=gs, gap_centre_rad=[centre, 0.0])
    return Case(sim.Bench(levels(rng, peak, 2000.0, 16), 2000.0, 500.0, chain,
                          sensors=noisy(rng, k, peak)), t)


def c_stiffening_sines(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.3, 0.45))
    chain = sim.Chain(ks, cubic_frac=float(rng.uniform(0.06, 0.15)), cubic_ref_rad=peak)
    return Case(sim.Bench(sines(rng, peak, 2000.0), 2000.0, 1000.0, chain,
                          sensors=noisy(rng, ks[0], peak)), lib(stack_truth(ks), "stiffening"))


def c_asymmetric_levels(rng):
    ks = springs(rng, 1)
    kneg = [ks[0] * float(rng.uniform(0.85, 0.92))]
    peak = float(rng.uniform(0.25, 0.45))
    t = lib(stack_truth(ks), "asymmetric_stiffness")
    t.k_true = [ks[0], kneg[0], 0.5 * (ks[0] + kneg[0])]
    return Case(sim.Bench(levels(rng, peak, 2000.0, 18), 2000.0, 500.0,
                          sim.Chain(ks, k_neg_Nm_per_rad=kneg), sensors=noisy(rng, ks[0], peak)), t)


def c_outliers_staircase(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    sen = noisy(rng, ks[0], peak, n_spikes=int(rng.integers(15, 40)))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 1000.0, sim.Chain(ks), sensors=sen),
                lib(stack_truth(ks), "outliers"))


def c_series_compliance_encoder(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    chain = sim.Chain(ks, shaft_Nm_per_rad=ks[0] * float(rng.uniform(5.0, 20.0)))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, chain,
                          sensors=noisy(rng, ks[0], peak), encoder_cols=True),
                lib(stack_truth(ks), "series_compliance"))


# ---------------------------------------------------------------------- pairs and triples
def c_backlash_friction_two_rates(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    fr = sim.Friction(float(rng.uniform(0.015, 0.035)) * k * peak, float(rng.uniform(0.003, 0.008)))
    t = lib(stack_truth(ks, gs), "backlash", "hysteresis")
    t.oracle.update(friction_width_rad=fr.width_rad, friction_law=fr.law)
    cmd = staircase(rng, peak, 2000.0, n_levels=3, speeds=(0.3, 1.0))
    return Case(sim.Bench(cmd, 2000.0, 1000.0, sim.Chain(ks, gap_rad=gs), fr, noisy(rng, k, peak)), t)


def c_backlash_friction_lag_two_rates(rng):
    """Issue 24's first class: friction, a 30 ms lag and backlash on two ramp rates."""
    case = c_backlash_friction_two_rates(rng)
    case.bench.sensors.delay_s = float(rng.uniform(0.02, 0.035))
    case.truth.oracle["delay_s"] = case.bench.sensors.delay_s
    lib(case.truth, "time_lag")
    return case


def c_drift_friction_staircase(rng):
    case = friction_case(rng, "elastoplastic", staircase, 500.0)
    T = case.truth.k_true[0] * np.max(np.abs(case.bench.command))
    dur = case.bench.command.size / case.bench.fine_rate_hz
    case.bench.sensors.torque_drift_Nm_per_s = float(rng.uniform(0.015, 0.03)) * T / dur
    lib(case.truth, "drift").optional.add("torque_offset")
    return case


def c_stiffening_offset_sines(rng):
    case = c_stiffening_sines(rng)
    T = case.truth.k_true[0] * np.max(np.abs(case.bench.command))
    case.bench.sensors.torque_offset_Nm = float(rng.choice([-1, 1]) * rng.uniform(0.02, 0.04)) * T
    lib(case.truth, "torque_offset")
    return case


def c_asymmetric_friction_staircase(rng):
    case = friction_case(rng, "dahl", staircase, 500.0)
    ks = case.bench.chain.k_Nm_per_rad
    case.bench.chain.k_neg_Nm_per_rad = [ks[0] * float(rng.uniform(0.85, 0.92))]
    kn = case.bench.chain.k_neg_Nm_per_rad[0]
    case.truth.k_true = [ks[0], kn, 0.5 * (ks[0] + kn)]
    lib(case.truth, "asymmetric_stiffness")
    return case


def c_lag_drift_sines(rng):
    ks = springs(rng, 1)
    peak = float(rng.uniform(0.25, 0.45))
    cmd = sines(rng, peak, 2000.0, (0.3, 0.8, 1.5))
    sen = noisy(rng, ks[0], peak, delay_s=float(rng.uniform(0.004, 0.015)))
    sen.torque_drift_Nm_per_s = float(rng.uniform(0.015, 0.03)) * ks[0] * peak / (cmd.size / 2000.0)
    t = lib(stack_truth(ks), "time_lag", "drift")
    t.optional.add("torque_offset")
    t.oracle["delay_s"] = sen.delay_s
    return Case(sim.Bench(cmd, 2000.0, 1000.0, sim.Chain(ks), sensors=sen), t)


def c_backlash_outliers_levels(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    sen = noisy(rng, k, peak, n_spikes=int(rng.integers(10, 30)))
    return Case(sim.Bench(levels(rng, peak, 2000.0, 16), 2000.0, 500.0, sim.Chain(ks, gap_rad=gs),
                          sensors=sen), lib(stack_truth(ks, gs), "backlash", "outliers"))


def c_backlash_series_compliance_encoder(rng):
    ks, gs = springs(rng, 2), gaps(rng, 2)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.5, 0.8))
    chain = sim.Chain(ks, gap_rad=gs, shaft_Nm_per_rad=k * float(rng.uniform(5.0, 15.0)))
    return Case(sim.Bench(staircase(rng, peak, 2000.0), 2000.0, 500.0, chain,
                          sensors=noisy(rng, k, peak), encoder_cols=True),
                lib(stack_truth(ks, gs), "backlash", "series_compliance"))


def c_stack3_four_effects(rng):
    ks, gs = springs(rng, 3), gaps(rng, 3)
    k = 1 / sum(1 / x for x in ks)
    peak = float(rng.uniform(0.7, 1.0))
    fr = sim.Friction(float(rng.uniform(0.015, 0.03)) * k * peak, float(rng.uniform(0.003, 0.008)), "dahl")
    sen = noisy(rng, k, peak, delay_s=float(rng.uniform(0.008, 0.02)))
    sen.torque_offset_Nm = float(rng.choice([-1, 1]) * rng.uniform(0.02, 0.04)) * k * peak
    cmd = staircase(rng, peak, 2000.0, n_levels=3, speeds=(0.3, 0.8, 1.6), hold=(0.4, 1.0))
    t = lib(stack_truth(ks, gs), "backlash", "hysteresis", "time_lag", "torque_offset")
    t.oracle.update(friction_width_rad=fr.width_rad, friction_law="dahl", delay_s=sen.delay_s)
    return Case(sim.Bench(cmd, 2000.0, 500.0, sim.Chain(ks, gap_rad=gs), fr, sen), t)


LIB_CASES = {name[2:]: fn for name, fn in list(globals().items()) if name.startswith("c_")}
