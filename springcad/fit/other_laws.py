"""Other laws of the effect families: the ways a family's physics may go beside the
library's own law (see :mod:`springcad.fit.effects` and :mod:`springcad.fit.laws`).

The loop searches with the library's law of each family; once a family is in the
model, its other laws are fitted in its place and the one the held-out criterion
prefers is kept (``springcad.fit.laws``). A law carries its family's name (the effect
named is the family) and reports parameters with the law's own meaning.

Units: N·m, rad, s.
"""

from __future__ import annotations

import numpy as np

from springcad.fit.effects import Backlash, Effect, Hysteresis, Param, TimeLag

class ViscousDamping(TimeLag):
    """Rate-proportional torque ``c·dθ/dt`` (N·m·s/rad): the time-lag family's damper law."""

    law = "viscous"
    meaning = ("rate-proportional (viscous) damping c: a torque c·dθ/dt that follows the speed "
               "of the motion (greases, eddy currents, a viscoelastic bushing at one rate); on "
               "this bench it reads as a torque channel early by c/K")
    stage = "torque"
    delayed = False

    def params(self, sc):
        c_max = 0.5 * sc.torque_ref / max(sc.theta_ref, 1e-12)
        return (Param("damping", -c_max, c_max, 0.0, -2.0 / sc.sample_rate_hz * c_max),)

    def time_shift_s(self, p):
        return 0.0

    def angle(self, theta, p, sig, idx):
        return theta

    def torque(self, p, sig, idx, fraction=None):
        return p[0] * sig.rate_trace[idx]

    def report(self, p, stiffness, sc):
        return {"viscous_damping_Nms_per_rad": float(p[0]),
                "equivalent_lag_s": float(-p[0] / stiffness) if stiffness else 0.0}


class FirstOrderLag(TimeLag):
    """Torque channel through a first-order low-pass of time constant T (s)."""

    law = "first_order_filter"
    meaning = ("a first-order low-pass in the torque channel (sensor or amplifier filter) of "
               "time constant T: slow motion is delayed by T, turns are rounded")

    def params(self, sc):
        return (Param("filter_time_constant", 0.0, 0.5, 0.0, 2.0 / sc.sample_rate_hz),)

    def starts(self, sc):
        return [np.array([f / sc.sample_rate_hz]) for f in (2.0, 10.0, 30.0)]

    def angle(self, theta, p, sig, idx):
        from scipy.signal import lfilter

        trace = sig.theta_trace
        if p[0] <= 0.0:
            return theta
        a = float(np.exp(-1.0 / (max(p[0], 1e-12) * sig.scales.sample_rate_hz)))
        low = lfilter([1.0 - a], [1.0, -a], trace - trace[0]) + trace[0]
        return theta + (low[idx] - trace[idx])

    def report(self, p, stiffness, sc):
        return {"filter_time_constant_s": float(p[0]), "lag_s": float(p[0])}


#: shortest torque-filter time constant a record can resolve, in sample periods
MIN_FILTER_SAMPLES = 2.0


class TorqueFilter(TimeLag):
    """The torque channel's reading through a first-order low-pass of time constant T (s):
    the whole torque the bench sees (spring, crossover, friction) is filtered, where
    :class:`FirstOrderLag` filters the deflection before the spring's law. The two are
    one on a linear spring; across a crossover or a friction's turn a filter in the
    sensor rounds the torque's own corners, which a filtered deflection put through the
    crossover keeps sharp."""

    law = "torque_filter"
    meaning = ("a first-order low-pass in the torque sensor or its amplifier, of time "
               "constant T: the measured torque follows the bench's torque late by T on "
               "slow motion, and its corners (a crossover taken up, a friction's turn) are "
               "rounded")
    stage = "output"
    delayed = False

    def params(self, sc):
        return FirstOrderLag.params(self, sc)

    def starts(self, sc):
        return FirstOrderLag.starts(self, sc)

    def physical_problem(self, p, stiffness, sc):
        # a filter within two sample periods rounds a step by what its sampling does
        # already: a fading friction's step at every start, read on the deflection trace,
        # took a 2.3 ms filter at 500 Hz beside it (the record cannot tell them apart)
        if p[0] < MIN_FILTER_SAMPLES / sc.sample_rate_hz:
            return (f"torque filter time constant {p[0]:.3g} s is within {MIN_FILTER_SAMPLES:g} "
                    "sample periods: no filter the sampling can tell from the steps it rounds")
        return Effect.physical_problem(self, p, stiffness, sc)

    def time_shift_s(self, p):
        return 0.0

    def angle(self, theta, p, sig, idx):
        return theta

    def output(self, torque, p, sig):
        from scipy.signal import lfilter

        if p[0] <= 0.0:
            return torque
        a = float(np.exp(-1.0 / (max(p[0], 1e-12) * sig.scales.sample_rate_hz)))
        return lfilter([1.0 - a], [1.0, -a], torque - torque[0]) + torque[0]

    def report(self, p, stiffness, sc):
        return {"torque_filter_time_constant_s": float(p[0]), "lag_s": float(p[0])}


class StandardLinearSolid(TimeLag):
    """A relaxing (Maxwell) branch beside the spring: stiffness ``k₂`` (N·m/rad) in series
    with a damper, relaxation time ``T`` (s) — the standard linear solid.

    Its torque is ``k₂·(x - x_T)``, with ``x`` the spring's own deflection (after a
    crossover: the flexures' material relaxes) and ``x_T`` it through a first-order
    low-pass of time constant ``T``: on motion much slower than ``T`` it is viscous
    damping ``c = k₂·T`` (the time-lag family's damper), on fast motion an extra stiffness
    ``k₂``, and at constant deflection it decays as ``exp(-t/T)`` (torque relaxing in a
    hold). ``K`` is then the relaxed (equilibrium) stiffness. A passive branch has
    ``k₂ ≥ 0``: a torque-sensor low-pass of time constant ``T`` would read as ``k₂ = -K``.
    """

    law = "standard_linear_solid"
    meaning = ("viscoelastic relaxation (a polymer bushing, a glued or clamped joint): a "
               "branch of stiffness k2 in series with a damper beside the spring, so the "
               "torque overshoots while moving and decays with time constant T toward K·θ "
               "at constant deflection; on slow motion it is viscous damping c = k2·T")
    stage = "torque"
    delayed = False
    on_spring = True

    def params(self, sc):
        k_ref = sc.torque_ref / max(sc.theta_ref, 1e-12)
        # from a few samples (below that it is the viscous law) to a fifth of the record
        # (beyond that a relaxation cannot be told from a stiffness change or a drift)
        t_lo = 3.0 / sc.sample_rate_hz
        t_hi = max(0.2 * sc.t_span, 2.0 * t_lo)
        return (Param("relaxing_stiffness", 0.0, k_ref, 0.0, 0.02 * k_ref),
                Param("relaxation_time", t_lo, t_hi, t_lo, min(max(0.3, t_lo), t_hi)))

    def starts(self, sc):
        p = self.params(sc)
        k_ref = sc.torque_ref / max(sc.theta_ref, 1e-12)
        lo, hi = p[1].lower, p[1].upper
        return [np.array([0.03 * k_ref, min(max(f, lo), hi)]) for f in (0.05, 0.3, 1.5)]

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)[1]
        if p[1] >= q.upper * (1 - 1e-4):
            return (f"relaxation time {p[1]:.4g} s rests on its upper bound: a torque that "
                    "never settles within the record is no relaxation")
        return Effect.physical_problem(self, p, stiffness, sc)

    def time_shift_s(self, p):
        return 0.0

    def angle(self, theta, p, sig, idx):
        return theta

    def spring_torque(self, p, spring, sig, idx):
        from scipy.signal import lfilter

        cached = getattr(self, "_cache", None)
        if cached is not None and cached[0] is spring and cached[1] == p[1]:
            high = cached[2]
        else:
            a = float(np.exp(-1.0 / (max(p[1], 1e-12) * sig.scales.sample_rate_hz)))
            high = spring - (lfilter([1.0 - a], [1.0, -a], spring - spring[0]) + spring[0])
            # the last trace and time constant (a Jacobian moves k2 and K with them fixed)
            self._cache = (spring, float(p[1]), high)
        return p[0] * high[idx]

    def report(self, p, stiffness, sc):
        return {"relaxing_stiffness_Nm_per_rad": float(p[0]),
                "relaxation_time_s": float(p[1]),
                "equivalent_viscous_damping_Nms_per_rad": float(p[0] * p[1]),
                "equivalent_lag_s": float(-p[0] * p[1] / stiffness) if stiffness else 0.0}


class RegularisedCoulomb(Hysteresis):
    """Friction ``F·tanh(v/v0)`` (N·m; v0 in rad/s): zero at rest, Coulomb in motion."""

    law = "regularised_coulomb"
    meaning = ("friction that follows the speed: F·tanh(v/v0), Coulomb friction F in motion, "
               "fading to zero below the speed v0 and at rest (no friction held in holds)")

    def params(self, sc):
        v_ref = sc.theta_ref * 2.0
        return (Param("friction", 0.0, 0.5 * sc.torque_ref, 0.0, 0.01 * sc.torque_ref),
                Param("fade_speed", 1e-4 * v_ref, v_ref, 0.01 * v_ref, 0.01 * v_ref))

    def starts(self, sc):
        return [np.array([0.02 * sc.torque_ref, f * sc.theta_ref]) for f in (0.003, 0.02, 0.1)]

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)[1]
        if p[1] >= q.upper * (1 - 1e-4):
            return f"fade speed {p[1]:.4g} rad/s rests on its upper bound: not a friction"
        return Effect.physical_problem(self, p, stiffness, sc)

    def torque(self, p, sig, idx, fraction=None):
        if fraction is not None:
            v = np.interp(fraction, np.arange(sig.n), sig.rate_trace)
        else:
            v = sig.rate_trace[idx]
        return p[0] * np.tanh(v / p[1])

    def report(self, p, stiffness, sc):
        return {"friction_torque_Nm": float(p[0]), "fade_speed_rad_per_s": float(p[1])}


class ElastoPlastic(Hysteresis):
    """Coulomb friction H (N·m) with a presliding stiffness ``H/θ_p``: after a turn the
    friction changes linearly with the travel (by H per θ_p rad) until it reaches H, then
    slides at H (an elasto-plastic, Coulomb-with-presliding-stiffness law).

    The library's presliding law (Dahl's) approaches H exponentially; this one takes it
    up at a constant stiffness and has a kink where sliding starts. Both are friction
    reversing over a presliding angle after each turn: the family's meaning."""

    law = "elasto_plastic"
    meaning = ("Coulomb friction H with a presliding stiffness H/θp: after each turn the "
               "friction torque changes linearly with the travel until it reaches H, then "
               "slides at H")

    @staticmethod
    def take_up(away, swing, presliding):
        return np.minimum(1.0, 1.0 - swing + away / presliding)

    def report(self, p, stiffness, sc):
        return {"friction_torque_Nm": float(p[0]), "presliding_rad": float(p[1]),
                "presliding_stiffness_Nm_per_rad": float(p[0] / p[1])}


#: largest breakaway friction of the Stribeck law, in sliding frictions above the sliding one
MAX_STRIBECK_RATIO = 5.0


class Stribeck(Hysteresis):
    """Presliding friction whose level falls with speed (the Stribeck effect): sliding
    friction ``H`` (N·m) at speed, rising to the breakaway level ``H·(1 + r)`` at rest
    below the Stribeck speed ``v_s`` (rad/s), ``H(v) = H·(1 + r·exp(-(v/v_s)²))``, taken
    up after each turn over the presliding angle θ_p as the library's law does.

    Breakaway friction above the sliding friction at speed: lubricated contacts,
    LuGre-like bristle friction. With ``r = 0`` it is the library's law; the friction
    then differs between slow and fast parts of a record, which one friction torque
    cannot describe. A refinement of the library's law (its special case plus two
    parameters), tried in its place once friction is named, not as another family's
    reading of an effect (``reads_alone``)."""

    law = "stribeck"
    meaning = ("friction with a Stribeck curve: a sliding level H at speed rising to the "
               "breakaway level H·(1 + r) below the Stribeck speed v_s, taken up over a "
               "presliding angle after each turn")
    reads_alone = False

    def params(self, sc):
        v_ref = sc.theta_ref * 2.0
        return Hysteresis.params(self, sc) + (
            Param("stribeck_ratio", 0.0, MAX_STRIBECK_RATIO, 0.0, 0.5),
            Param("stribeck_speed", 1e-4 * v_ref, v_ref, 0.01 * v_ref, 0.02 * v_ref))

    def starts(self, sc):
        return [np.array([0.02 * sc.torque_ref, 0.01 * sc.theta_ref, 0.5,
                          f * sc.theta_ref]) for f in (0.02, 0.1, 0.5)]

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)
        if p[2] > 0.0 and p[3] >= q[3].upper * (1 - 1e-4):
            return (f"Stribeck speed {p[3]:.4g} rad/s rests on its upper bound: a friction "
                    "that falls over every speed of the record is no Stribeck curve")
        if p[2] >= q[2].upper * (1 - 1e-4):
            return (f"breakaway {1 + p[2]:.3g} times the sliding friction rests on its upper "
                    "bound: no friction law the record supports")
        return super().physical_problem(p[:2], stiffness, sc)

    def torque(self, p, sig, idx, fraction=None):
        if fraction is not None:
            v = np.interp(fraction, np.arange(sig.n), sig.rate_trace)
        else:
            v = sig.rate_trace[idx]
        level = 1.0 + p[2] * np.exp(-np.square(v / p[3]))
        return Hysteresis.torque(self, p[:2], sig, idx, fraction) * level

    def report(self, p, stiffness, sc):
        return {"friction_torque_Nm": float(p[0]), "presliding_rad": float(p[1]),
                "breakaway_friction_Nm": float(p[0] * (1.0 + p[2])),
                "stribeck_speed_rad_per_s": float(p[3])}


class HertzianTakeUp(Backlash):
    """A gap of width b = 2h (rad) closed through a Hertzian contact in series with the
    spring: past the gap the contact compresses as ``c = κ·u^(2/3)`` (κ in rad^(1/3))
    while the spring deflects by u (contact force ∝ c^(3/2), spring torque ``K·u``), so
    the measured deflection beyond the gap is ``u + c`` and the torque rises as a power
    law, not at once.

    The library's crossover is taken up over a transition and then runs parallel to
    ``K·θ``; a Hertzian contact stays compliant at every load (its stiffness grows as the
    torque's cube root), which reads as a stiffening of the whole curve. Fitted in the
    crossover's place once backlash is named (``reads_alone``)."""

    law = "hertzian_contact"
    reads_alone = False
    meaning = ("a gap of width b taken up through a Hertzian (point or line) contact in "
               "series with the spring: the torque rises as a power law past the gap, and "
               "the contact keeps compressing as the torque grows")

    def params(self, sc):
        kappa_max = 0.3 * sc.theta_ref ** (1.0 / 3.0)  # 0.3·θ_ref of contact at u = θ_ref
        return (Backlash.params(self, sc)[0],
                Param("contact_compliance", 0.0, kappa_max, 0.0, 0.03 * kappa_max))

    def starts(self, sc):
        kappa_ref = sc.theta_ref ** (1.0 / 3.0)
        return [np.array([f * sc.theta_ref, g * kappa_ref])
                for f in (0.01, 0.03, 0.06, 0.1) for g in (0.01, 0.05)]

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)[1]
        if p[1] >= q.upper * (1 - 1e-4):
            return (f"contact compliance {p[1]:.4g} rad^(1/3) rests on its upper bound: a "
                    "contact softer than the spring is no take-up")
        return Effect.physical_problem(self, p, stiffness, sc)

    def map(self, x, p):
        half, kappa = float(p[0]), max(float(p[1]), 0.0)
        d = np.maximum(np.abs(x) - half, 0.0)
        if kappa <= 0.0:
            return np.sign(x) * d
        # u + κ·u^(2/3) = d; with w = u^(1/3): w³ + κ·w² = d, solved by Newton's method
        # from above the root (the cubic is increasing and convex for w > 0)
        w = np.minimum(np.cbrt(d), np.sqrt(d / kappa))
        for _ in range(40):
            step = (w * w * (w + kappa) - d) / np.maximum(w * (3.0 * w + 2.0 * kappa), 1e-300)
            w = w - step
            if float(np.max(np.abs(step))) <= 1e-10 * max(float(np.max(w)), 1e-12):
                break
        return np.sign(x) * w ** 3

    def report(self, p, stiffness, sc):
        return {"backlash_rad": 2.0 * float(p[0]),
                "contact_compliance_rad_cbrt": float(p[1]),
                "contact_compression_at_max_rad": float(p[1] * sc.theta_ref ** (2.0 / 3.0))}


#: laws of each family other than the library's, tried in its place once it is named
OTHER_LAWS: dict[str, tuple[Effect, ...]] = {
    "time_lag": (ViscousDamping(), FirstOrderLag(), TorqueFilter(), StandardLinearSolid()),
    "hysteresis": (RegularisedCoulomb(), ElastoPlastic(), Stribeck()),
    "backlash": (HertzianTakeUp(),),
}
