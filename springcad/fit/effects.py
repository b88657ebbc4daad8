"""The effect library: physical effects a bench record may show beyond ``τ = K·θ``.

Each effect is one small class with

* a physical meaning (``meaning``) and the signature its detector looks for
  in the residual (``looks_for``);
* a model term: a hook into the common torque model (see
  :mod:`springcad.fit.torque_model`), with parameters, bounds, the value where
  the term vanishes (``null``) and a small ``probe`` value from which the
  detector builds the term's signature;
* a report of its fitted parameters with units in the names.

The common model, in evaluation order::

    θ₁ = θ(t - δ) - θ₀                       angle stage   (time_lag, angle_offset)
    x  = θ_spring(θ₁; h, l)                   map stage     (backlash, eq. 9)
    τ  = K · x · (1 + a·sign x + α·(x/θ_ref)²)   factor stage (asymmetric_stiffness,
                                              stiffening: departures from 1 add)
       + H·d·(1 - 2·exp(-|θ - θ_rev|/θ_p))    torque stage  (hysteresis; 1·exp before the first reversal)
       + τ₀ + ṙ·(t - t₀)                      torque stage  (torque_offset, drift)

``outliers`` changes which samples are fitted and scored, and
``series_compliance`` models a second channel (encoder minus optical
deflection), so neither adds a torque term.

Units: N·m, rad, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from springcad.fit.models import spring_angle
from springcad.fit.signals import Scales, Signals

#: evaluation order of the stages of the torque model
STAGES = ("angle", "map", "factor", "torque", "output", "mask", "encoder")


@dataclass(frozen=True)
class Param:
    """One model parameter.

    Attributes:
        name: short internal name.
        lower: lower bound.
        upper: upper bound.
        null: value at which the effect vanishes.
        probe: small non-null value used to form the detector signature.
    """

    name: str
    lower: float
    upper: float
    null: float
    probe: float


class Effect:
    """Base class of one effect (see module docstring)."""

    name: str = ""
    meaning: str = ""
    looks_for: str = ""
    stage: str = "torque"
    order: int = 0
    #: applicable only when at least one of these effects is in the model
    needs_any: tuple[str, ...] = ()
    #: what it reads as beside those effects at their null (an effect of the library)
    reads_as_alone: str | None = None
    #: its term is a function of the deflection alone, the same in both directions of
    #: motion (judged against the residual's deflection profile, see ``fit.patches``)
    deflection_shape: bool = False
    #: index (within this effect's parameters) of the parameter that sets its size
    primary: int = 0
    #: splits of the record across which its parameters must agree (see ``evidence``)
    splits: tuple[str, ...] = ("time", "amplitude", "direction")
    #: its torque follows the direction of motion (held fixed on loading-only or
    #: unloading-only samples, where it would read as a step at zero deflection)
    direction_signed: bool = False
    #: what its residual signature looks like, in a few words
    signature: str = ""
    #: a torque of the spring itself, delayed with the torque channel (see ``time_shift_s``)
    delayed: bool = False
    #: its size is a rate along the record that may change without changing sign (a zero
    #: that drifts fast after taring, then settles): parts of the record that each support
    #: it with one sign show it, though their rates differ (the evidence audit)
    monotone: bool = False
    #: a law the search proposes and the confounding test tries as a reading of its own;
    #: ``False``: a refinement of the library's law (its special case plus freedom), only
    #: fitted in the library law's place once the family is named (:mod:`springcad.fit.laws`)
    reads_alone: bool = True
    #: a torque of the spring's material, acting on the spring's own deflection (after a
    #: crossover): evaluated by ``spring_torque`` on the whole smooth trace of it
    on_spring: bool = False

    def params(self, sc: Scales) -> tuple[Param, ...]:
        """Parameters of the term for a record with scales ``sc``."""
        return ()

    def applicable(self, active: set[str], sig: Signals) -> bool:
        """Whether the effect can be told apart from the current model."""
        return not self.needs_any or bool(active.intersection(self.needs_any))

    def starts(self, sc: Scales) -> list[np.ndarray]:
        """Initial values to try (each: one value per parameter)."""
        return [np.array([p.probe for p in self.params(sc)])]

    def report(self, p: np.ndarray, stiffness: float, sc: Scales) -> dict:
        """Fitted parameters with units in the key names."""
        return {}

    def physical_problem(self, p: np.ndarray, stiffness: float, sc: Scales) -> str | None:
        """Why these fitted values cannot describe a real bench, or ``None``.

        The default: the size parameter ran into a bound that is not its null
        value (the fit wanted more than any plausible bench shows, so the
        residual is not this effect's signature).
        """
        params = self.params(sc)
        if not params:
            return None
        q = params[self.primary]
        span = q.upper - q.lower
        for bound, name in ((q.lower, "lower"), (q.upper, "upper")):
            away_from_null = bound < q.null if name == "lower" else bound > q.null
            if away_from_null and abs(p[self.primary] - bound) <= 1e-4 * span:
                return (f"{q.name} = {p[self.primary]:.4g} rests on its {name} bound "
                        f"{bound:.4g}: the residual asks for more than this effect can be")
        return None

    def time_shift_s(self, p: np.ndarray) -> float:
        """How late (s) this effect makes the whole torque channel (0 for most)."""
        return 0.0

    def acts_within(self, p: np.ndarray, sc: Scales) -> tuple[float, float] | None:
        """The band of |deflection| (rad) where the term has its shape, or ``None`` when
        it acts everywhere alike (see ``springcad.fit.evidence.shape_check``)."""
        return None

    # hooks of the torque model; the defaults leave the torque unchanged
    def angle(self, theta: np.ndarray, p: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        return theta

    def map(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return x

    def factor(self, x: np.ndarray, p: np.ndarray, sc: Scales) -> np.ndarray | float:
        return 1.0

    def torque(self, p: np.ndarray, sig: Signals, idx: np.ndarray,
               fraction: np.ndarray | None = None) -> np.ndarray | float:
        """Additive torque (N·m) at samples ``idx``; ``fraction`` gives fractional
        sample positions for a ``delayed`` term (``idx`` is then the nearest sample)."""
        return 0.0

    def spring_torque(self, p: np.ndarray, spring: np.ndarray, sig: Signals,
                      idx: np.ndarray) -> np.ndarray:
        """Additive torque (N·m) at samples ``idx`` of an ``on_spring`` term, from the
        spring's deflection ``spring`` (rad) on every sample."""
        return np.zeros(idx.size)

    def output(self, torque: np.ndarray, p: np.ndarray, sig: Signals) -> np.ndarray:
        """The torque channel's reading (N·m, every sample) of the model torque ``torque``
        (every sample) for an ``output``-stage term (a filter in the sensor)."""
        return torque


#: widest logit transition of a crossover, as a fraction of the largest deflection
MAX_TRANSITION = 0.25


class Backlash(Effect):
    """Crossover of width b = 2h (rad) with a logit transition l (rad): paper eqs. 4, 9."""

    name = "backlash"
    meaning = ("air gap at the camshaft-flexure interfaces: no torque is transmitted across "
               "the gap, so the curve has a flat crossover of width b around zero torque "
               "(paper eqs. 4 and 9, with the logit transition l)")
    looks_for = ("residual of the opposite sign to the deflection, stepping across zero "
                 "deflection (torque overestimated near the crossover)")
    stage = "map"
    deflection_shape = True
    signature = "a torque step across zero deflection"

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)[1]
        if p[1] >= q.upper * (1 - 1e-4):
            return f"transition {p[1]:.4g} rad rests on its upper bound: not a crossover"
        return super().physical_problem(p, stiffness, sc)

    def params(self, sc):
        # a crossover narrower than the deflection noise cannot be told from it: with samples
        # resting at zero deflection, a tiny deadband would only shrink the noise there
        # a transition of a quarter of the deflection range or more is no crossover but a
        # curvature of the whole curve (stiffening reads so), so the bound stops it there
        return (Param("half_backlash", sc.theta_noise, 0.45 * sc.theta_ref, 0.0, 0.03 * sc.theta_ref),
                Param("transition", 0.0, MAX_TRANSITION * sc.theta_ref, 0.0, 0.01 * sc.theta_ref))

    def starts(self, sc):
        return [np.array([f * sc.theta_ref, 0.25 * f * sc.theta_ref])
                for f in (0.01, 0.03, 0.06, 0.1, 0.16)]

    def map(self, x, p):
        return spring_angle(x, p[0], p[1])

    def acts_within(self, p, sc):
        # the crossover and its transition with a margin as wide again, and never less
        # than a tenth of the range (a narrow crossover fitted to a wider feature)
        return 0.0, max(2.0 * float(p[0] + p[1]), 0.1 * sc.theta_ref)

    def report(self, p, stiffness, sc):
        return {"backlash_rad": 2.0 * float(p[0]), "transition_rad": float(p[1])}


#: presliding angles after which a Dahl friction is settled to the last bit of a float64:
#: 2·exp(-40) = 8.5e-18 is below half the spacing of doubles under 1 (5.6e-17)
SETTLED = 40.0


class Hysteresis(Effect):
    """Friction torque H (N·m) that reverses over a presliding angle θ_p (rad)."""

    name = "hysteresis"
    meaning = ("friction at the flexure tips, spacers and bushings: the torque is higher "
               "while loading than while unloading at the same deflection, by 2H, with the "
               "friction reversing over a presliding angle after each turn (energy loss)")
    looks_for = "residual that follows the direction of motion and flips after each reversal"
    stage = "torque"
    splits = ("time", "amplitude")
    direction_signed = True
    delayed = True
    signature = "a torque offset that follows the direction of motion"

    def physical_problem(self, p, stiffness, sc):
        q = self.params(sc)[1]
        if p[1] >= q.upper * (1 - 1e-4):
            return (f"presliding angle {p[1]:.4g} rad rests on its upper bound: the friction "
                    "never settles, which is not what friction does")
        return super().physical_problem(p, stiffness, sc)

    def params(self, sc):
        return (Param("friction", 0.0, 0.5 * sc.torque_ref, 0.0, 0.01 * sc.torque_ref),
                Param("presliding", 1e-4 * sc.theta_ref, 0.3 * sc.theta_ref, 0.01 * sc.theta_ref,
                      0.01 * sc.theta_ref))

    def starts(self, sc):
        return [np.array([0.02 * sc.torque_ref, f * sc.theta_ref]) for f in (0.003, 0.02, 0.08)]

    def torque(self, p, sig, idx, fraction=None):
        # after a reversal friction swings from -H to +H; from rest it rises from 0
        away = sig.from_reversal[idx]
        if fraction is not None:
            # at a fractional sample position (a delayed channel): the travel since the
            # reversal interpolated within the run, the direction of the nearest sample
            i0 = np.minimum(fraction.astype(int), sig.n - 2)
            same = sig.runs[i0] == sig.runs[i0 + 1]
            w = fraction - i0
            inter = (1.0 - w) * sig.from_reversal[i0] + w * sig.from_reversal[i0 + 1]
            away = np.where(same, inter, away)
        return p[0] * sig.direction[idx] * self.take_up(away, self.swings(p, sig)[idx], p[1])

    def swings(self, p: np.ndarray, sig: Signals) -> np.ndarray:
        """Per-sample swing of the friction over H after the last turn: 1 from rest, and
        after a reversal one plus the friction (over H) the run before it ended at.

        The friction remembers where it stood: after a run long enough for it to settle
        it ends at H and swings by 2H (the swing of every long run), after a run shorter
        than a few presliding angles (a fade-in's or a jog's small reversal) it had not
        settled and swings by less. Each run's end is read from the law's own take-up
        (:meth:`take_up`) at the run's travel (:attr:`Signals.run_travel`), so Dahl's law
        and a linear presliding law keep their own memory.
        """
        travel = sig.run_travel
        per_run = np.full(travel.size, 2.0)
        per_run[0] = 1.0
        short = np.flatnonzero(travel[:-1] < SETTLED * p[1])
        for k in short:
            end = self.take_up(travel[k:k + 1], per_run[k:k + 1], p[1])
            per_run[k + 1] = 1.0 + float(end[0])
        return per_run[sig.runs]

    @staticmethod
    def take_up(away, swing, presliding):
        """Friction over H after ``away`` rad of travel since the turn (``swing`` 2 after a
        reversal, 1 from rest): an exponential approach (Dahl's law), ``-1`` → ``1``."""
        # beyond SETTLED presliding angles 1 - swing·exp(-away/presliding) rounds to 1.0
        # exactly: the exponential is taken where the friction still moves only
        out = np.ones(np.shape(away))
        moving = away < SETTLED * presliding
        out[moving] = 1.0 - np.asarray(swing)[moving] * np.exp(-away[moving] / presliding)
        return out

    def report(self, p, stiffness, sc):
        return {"friction_torque_Nm": float(p[0]), "presliding_rad": float(p[1])}


class TimeLag(Effect):
    """Torque channel late by ``lag`` (s) relative to the deflection channel."""

    name = "time_lag"
    meaning = ("torque and deflection channels out of step (camera latency, filter delay, "
               "unsynchronised clocks): the torque at time t belongs to the deflection at t - lag; "
               "a negative lag (torque leading) is also what rate-proportional (viscous) damping "
               "c = -K·lag looks like, which this bench cannot tell apart")
    looks_for = "residual proportional to the deflection rate (largest mid-ramp, zero at turns)"
    stage = "angle"
    order = 0
    splits = ("time", "amplitude")
    direction_signed = True
    signature = "a torque offset proportional to the deflection rate"

    def params(self, sc):
        return (Param("lag", -0.5, 0.5, 0.0, 2.0 / sc.sample_rate_hz),)

    def time_shift_s(self, p):
        return float(p[0])

    def angle(self, theta, p, sig, idx):
        # shift the smooth motion only: the noise of each sample stays its own,
        # so a fractional lag cannot pose as noise averaging
        trace = sig.theta_trace
        shifted = np.interp(sig.t[idx] - p[0], sig.t, trace)
        return theta + (shifted - trace[idx])

    def report(self, p, stiffness, sc):
        return {"lag_s": float(p[0]),
                "equivalent_viscous_damping_Nms_per_rad": float(-stiffness * p[0])}


class AngleOffset(Effect):
    """Deflection zero offset θ₀ (rad): the crossover sits at θ₀, not at zero."""

    name = "angle_offset"
    meaning = ("deflection zero not at the spring's rest position (optical calibration or "
               "mounting offset): the crossover is not centred on zero deflection")
    looks_for = ("residual shaped like the model's slope, visible where the crossover or a "
                 "kink sits off zero; indistinguishable from a torque offset without one")
    stage = "angle"
    deflection_shape = True
    order = 1
    needs_any = ("backlash", "asymmetric_stiffness")
    reads_as_alone = "torque_offset"
    signature = "a shift of the crossover along the deflection axis"

    def params(self, sc):
        return (Param("angle_offset", -0.2 * sc.theta_ref, 0.2 * sc.theta_ref, 0.0,
                      0.005 * sc.theta_ref),)

    def angle(self, theta, p, sig, idx):
        return theta - p[0]

    def report(self, p, stiffness, sc):
        return {"angle_offset_rad": float(p[0])}


class Stiffening(Effect):
    """Cubic stiffening or softening: factor ``1 + α·(x/θ_ref)²`` on K."""

    name = "stiffening"
    meaning = ("stiffness that changes with deflection (contact point moving along the "
               "flexure, large-deflection geometry): stiffening if positive, softening if negative")
    looks_for = "residual odd in deflection and growing faster than linearly (cubic) with it"
    stage = "factor"
    deflection_shape = True
    signature = "a torque error growing with the cube of the deflection"

    def physical_problem(self, p, stiffness, sc):
        if 1.0 + 3.0 * p[0] <= 0.0:
            return (f"softening alpha = {p[0]:.3g} makes the tangent stiffness negative at the "
                    "largest deflection: not a stable spring")
        return super().physical_problem(p, stiffness, sc)

    def params(self, sc):
        return (Param("alpha", -0.6, 2.0, 0.0, 0.02),)

    def factor(self, x, p, sc):
        return 1.0 + p[0] * np.square(x / sc.theta_ref)

    def acts_within(self, p, sc):
        # the cubic term is mostly at large deflection
        return 0.6 * sc.theta_ref, np.inf

    def report(self, p, stiffness, sc):
        return {"cubic_stiffness_Nm_per_rad3": float(stiffness * p[0] / sc.theta_ref ** 2),
                "tangent_stiffness_change_at_max_pct": float(300.0 * p[0])}


class AsymmetricStiffness(Effect):
    """K(1 + a) for positive and K(1 - a) for negative spring deflection."""

    name = "asymmetric_stiffness"
    meaning = ("different stiffness for positive and negative deflection (flexure or cam "
               "teeth cut unevenly, one-sided contact)")
    looks_for = "residual even in deflection, proportional to |deflection|"
    stage = "factor"
    deflection_shape = True
    signature = "a torque error even in deflection, proportional to |deflection|"

    def params(self, sc):
        return (Param("asymmetry", -0.6, 0.6, 0.0, 0.01),)

    def factor(self, x, p, sc):
        return 1.0 + p[0] * np.sign(x)

    def report(self, p, stiffness, sc):
        return {"stiffness_pos_Nm_per_rad": float(stiffness * (1.0 + p[0])),
                "stiffness_neg_Nm_per_rad": float(stiffness * (1.0 - p[0]))}


class TorqueOffset(Effect):
    """Constant torque offset τ₀ (N·m)."""

    name = "torque_offset"
    meaning = "torque sensor zero not tared: a constant torque added to every sample"
    looks_for = "residual with a non-zero mean"
    stage = "torque"
    deflection_shape = True
    order = 0
    signature = "a constant torque"

    def params(self, sc):
        return (Param("torque_offset", -sc.torque_ref, sc.torque_ref, 0.0, 0.01 * sc.torque_ref),)

    def torque(self, p, sig, idx):
        return p[0]

    def report(self, p, stiffness, sc):
        return {"torque_offset_Nm": float(p[0])}


class Drift(Effect):
    """Torque zero drifting linearly from the record start (parameter: total drift, N·m)."""

    name = "drift"
    meaning = ("torque zero that moves with time (sensor or amplifier thermal drift after "
               "taring): an offset growing linearly from the start of the record")
    looks_for = "residual trending with time, independent of deflection"
    stage = "torque"
    order = 1
    signature = "a torque growing linearly with time"
    monotone = True

    def params(self, sc):
        # parameter: drift over the whole record (N·m)
        return (Param("drift", -sc.torque_ref, sc.torque_ref, 0.0, 0.01 * sc.torque_ref),)

    def torque(self, p, sig, idx):
        sc = sig.scales
        return p[0] * (sig.t[idx] - sc.t0) / sc.t_span

    def report(self, p, stiffness, sc):
        return {"drift_Nm_per_s": float(p[0] / sc.t_span)}


class Outliers(Effect):
    """Isolated glitches, excluded from fit and score (one parameter per glitch)."""

    name = "outliers"
    meaning = ("sensor glitches (ADC spikes, lost camera frames): isolated samples far from "
               "their neighbours; they are excluded from the fit and from the NRMSE")
    looks_for = ("isolated samples more than 6 noise standard deviations from the running "
                 "median of the residual")
    stage = "mask"
    splits = ()

    def report(self, p, stiffness, sc):
        return {}


class SeriesCompliance(Effect):
    """Encoder minus optical deflection = torque/K_series + offset (second channel)."""

    name = "series_compliance"
    meaning = ("compliance of shafts and couplers between the motors and the spring: the "
               "encoder deflection exceeds the optical deflection by torque/K_series")
    looks_for = "encoder minus optical deflection proportional to the torque"
    stage = "encoder"
    splits = ()

    def applicable(self, active, sig):
        return sig.encoder is not None


Effect.law = "library"
Backlash.law = "logit_crossover"
Hysteresis.law = "presliding"
TimeLag.law = "pure_delay"

#: the library, in the order candidates are listed
LIBRARY: tuple[Effect, ...] = (
    Backlash(), Hysteresis(), TimeLag(), Drift(), TorqueOffset(), AngleOffset(),
    Stiffening(), AsymmetricStiffness(), Outliers(), SeriesCompliance(),
)

EFFECT_NAMES = tuple(e.name for e in LIBRARY)


def get_effect(name: str) -> Effect:
    """The library effect called ``name``."""
    for e in LIBRARY:
        if e.name == name:
            return e
    raise KeyError(f"unknown effect {name!r}; known: {', '.join(EFFECT_NAMES)}")
