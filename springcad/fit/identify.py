"""Identifiability: can this record tell one effect from another?

Two effects are told apart by the part of their residual signatures that the
rest of the model cannot absorb. For effects ``A`` and ``B`` of a model, take
the Jacobian columns of their size parameters, remove what every other
parameter (stiffness, the other effects, their shape parameters) can
reproduce, and correlate what is left: ``ρ``. The variance inflation factor
``VIF = 1/(1 - ρ²)`` says how much less precisely each is known because the
other is there; the usual collinearity rule reads ``VIF ≥ 10`` as "cannot be
separated". It is measured on all samples and on the samples away from the
reversals, and the larger is taken: a split that rests on the turns alone
rests on how each model draws a turn (friction's presliding shape, the corner
of the motion), which the models do not promise. An effect that needs a
feature of the model to be located (an angle offset needs a crossover or a
kink) is left to the held-out criterion.

On a record whose ramps all run at one speed, Coulomb friction (a torque set
by the direction of motion) and a late torque channel (a torque set by the
speed) differ only at the turns: away from them their signatures are the same
offset. A crossover separates them in part (inside the gap friction acts, a
lag of the elastic torque does not), and speeds that vary (cosine ramps,
several rates, sines, holds) separate them (``VIF`` 2-4).

A confounded pair is named as a group and no split is reported: the combined
torque is (the pair's terms stay in the model when the loop found both; the
one it found carries the pair when the other is an alternative from the
library), and
:func:`recommend_protocol` measures which bench protocol would separate it:
it rebuilds the record's signals for each candidate protocol and computes
the pair's VIF there, with the standard errors the record's noise would give.

Units: N·m, rad, s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.fit.data import make_record
from springcad.fit.effects import LIBRARY, Effect, get_effect
from springcad.fit.inference import Uncertainty, jacobian, report_intervals
from springcad.fit.other_laws import OTHER_LAWS
from springcad.fit.protocols import Protocol, SineSweep
from springcad.fit.search import State
from springcad.fit.segment import segment
from springcad.fit.signals import Signals, make_signals
from springcad.fit.torque_model import TorqueModel



def primary_index(model: TorqueModel, name: str) -> int:
    """Position of effect ``name``'s size parameter in the model's parameter vector."""
    e = next(e for e in model.effects if e.name == name)
    return model.slice_of(name).start + e.primary


def pair_correlation(J: np.ndarray, i: int, j: int) -> float:
    """Correlation of columns ``i`` and ``j`` of ``J`` after removing all other columns."""
    others = [k for k in range(J.shape[1]) if k not in (i, j)]
    a, b = J[:, i], J[:, j]
    if others:
        Q, _ = np.linalg.qr(J[:, others])
        a = a - Q @ (Q.T @ a)
        b = b - Q @ (Q.T @ b)
    na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if na == 0.0 or nb == 0.0:
        return 1.0
    return float(a @ b) / (na * nb)


def vif(rho: float) -> float:
    """Variance inflation factor of a correlation."""
    return math.inf if abs(rho) >= 1.0 else 1.0 / (1.0 - rho * rho)


def _alternatives(family: Effect) -> tuple[Effect, ...]:
    """The family's laws that may read as another family's effect: the library's and
    every other law but the refinements with more freedom (``reads_alone``)."""
    return (family,) + tuple(law for law in OTHER_LAWS.get(family.name, ()) if law.reads_alone)


def turn_window_s(model: TorqueModel, x: np.ndarray, sig: Signals) -> float:
    """How long (s) after a reversal the model's effects are still turning over.

    Friction swings over three presliding angles at the record's typical
    speed; a late channel over its lag; the deflection smoothing adds 20 ms.
    """
    speed = np.abs(sig.rate)
    typical = float(np.median(speed[speed > 0.2 * np.percentile(speed, 99)]))
    window = 0.0
    for e in model.effects:
        p = x[model.slice_of(e.name)]
        presliding = ("presliding", "elasto_plastic", "stribeck")
        if e.name == "hysteresis" and e.law in presliding and typical > 0:
            # three presliding angles (Dahl's) or the two of a full elasto-plastic swing
            window = max(window, 3.0 * float(p[1]) / typical)
        window = max(window, abs(e.time_shift_s(p)))
    return window + 0.02 if window > 0 else 0.0


def pair_vif(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray, a: str,
             b: str, J: np.ndarray | None = None) -> tuple[float, float]:
    """``(ρ, VIF)`` of effects ``a`` and ``b`` of ``model`` at ``x`` on samples ``idx``.

    Taken as the larger of the two found on all samples and on the samples
    away from reversals (see :func:`turn_window_s`): a split that rests on the
    turns alone rests on how each model draws a turn (the presliding shape,
    the corner of the motion), which the models do not promise.
    """
    J = jacobian(model, x, sig, idx) if J is None else J
    # the signatures, not the deflection noise a time shift carries into its column:
    # averaged over 50 ms (signatures vary slower than that, noise does not)
    step = float(np.median(np.diff(idx))) if idx.size > 1 else 1.0
    width = int(round(0.05 * sig.scales.sample_rate_hz / max(step, 1.0)))
    if width > 1:
        J = ndimage.uniform_filter1d(J, size=width, axis=0, mode="nearest")
    i, j = primary_index(model, a), primary_index(model, b)
    rho = pair_correlation(J, i, j)
    steady = sig.since_turn_s[idx] >= turn_window_s(model, x, sig)
    if 10 * J.shape[1] < steady.sum() < steady.size:
        rho_steady = pair_correlation(J[steady], i, j)
        if abs(rho_steady) > abs(rho):
            rho = rho_steady
    return rho, vif(rho)


def contribution(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                 name: str) -> np.ndarray:
    """Torque (N·m) the effect ``name`` adds to the model at samples ``idx``."""
    e = next(e for e in model.effects if e.name == name)
    x0 = x.copy()
    x0[model.slice_of(name).start + e.primary] = e.params(model.scales)[e.primary].null
    return model.predict(x, sig, idx) - model.predict(x0, sig, idx)


@dataclass(frozen=True)
class ProtocolAdvice:
    """A bench protocol that would separate a confounded pair, as measured on the fitted model.

    Attributes:
        effects: the pair.
        change: what changes against the record's protocol, in words.
        protocol: the protocol (``describe()`` gives its numbers).
        vif_record: the pair's VIF on the record.
        vif_protocol: the pair's VIF on the proposed protocol.
        predicted_ci: predicted 95 % half-widths of the pair's reported
            quantities with the record's noise level, on that protocol.
        command: the ``springcad simulate`` command line that writes it.
        alternatives: every candidate protocol tried, as ``(change, VIF, duration_s)``.
    """

    effects: tuple[str, str]
    change: str
    protocol: Protocol | SineSweep
    vif_record: float
    vif_protocol: float
    predicted_ci: dict[str, float]
    command: str
    alternatives: tuple[tuple[str, float, float], ...] = ()

    def to_dict(self) -> dict:
        return {"effects": list(self.effects), "change": self.change,
                "protocol": self.protocol.describe(), "vif_record": self.vif_record,
                "vif_protocol": self.vif_protocol, "predicted_ci_halfwidth": self.predicted_ci,
                "command": self.command,
                "alternatives": [{"change": c, "vif": v, "duration_s": d}
                                 for c, v, d in self.alternatives]}


@dataclass(frozen=True)
class Confounded:
    """Effects the record cannot separate, carried as one term.

    Attributes:
        effects: the group (the carried term first).
        carrier: the effect whose term stands for the group in the model.
        rho: correlation of the pair's signatures (see module docstring).
        vif: variance inflation factor.
        combined_Nm: typical size of the combined torque (median of its
            absolute value while the spring moves, N·m).
        signature: what the shared signature looks like.
        advice: the protocol that would separate them, if one was found.
        in_model: the group's terms that are in the model (all of them when
            the loop found each; only the carrier when the others are
            alternatives from the library).
    """

    effects: tuple[str, ...]
    carrier: str
    rho: float
    vif: float
    combined_Nm: float
    signature: str
    advice: ProtocolAdvice | None = None
    in_model: tuple[str, ...] = ()

    def statement(self) -> str:
        names = " and ".join(self.effects)
        held = (f"the model keeps the {' and '.join(self.in_model)} terms but reports only "
                "their sum" if len(self.in_model) > 1 else f"carried as {self.carrier}")
        text = (f"{names} are confounded on this record (signature correlation "
                f"{self.rho:+.3f}, variance inflation {self.vif:.3g}): both "
                f"read as {self.signature}; one combined term of typical size "
                f"{self.combined_Nm:.3g} N·m ({held}) and no split between them is claimed")
        if self.advice is not None:
            text += (f"; {self.advice.change} would separate them (variance inflation "
                     f"{self.advice.vif_protocol:.2g} there)")
        return text

    def to_dict(self) -> dict:
        return {"effects": list(self.effects), "carried_as": self.carrier, "rho": self.rho,
                "vif": self.vif, "combined_Nm": self.combined_Nm, "signature": self.signature,
                "terms_in_model": list(self.in_model),
                "statement": self.statement(),
                "advice": None if self.advice is None else self.advice.to_dict()}


# --- protocol advice -------------------------------------------------------------

def record_protocol(sig: Signals) -> tuple[tuple[float, ...], float]:
    """The record's amplitudes (rad, distinct to 5 %) and typical ramp speed (rad/s)."""
    runs = sig.runs
    labels, inv = np.unique(runs, return_inverse=True)
    amp = np.zeros(labels.size)
    np.maximum.at(amp, inv, np.abs(sig.theta_smooth))
    amp = np.sort(amp[amp > 0.05 * amp.max()])
    distinct: list[float] = []
    for a in amp:
        if not distinct or a > 1.05 * distinct[-1]:
            distinct.append(float(a))
    speed = np.abs(sig.rate)
    moving = speed > 0.2 * np.percentile(speed, 99)
    return tuple(distinct[-6:]), float(np.median(speed[moving]))


def candidate_protocols(sig: Signals) -> list[tuple[str, Protocol | SineSweep]]:
    """Protocols that change one thing against the record's: speed, holds, or sines."""
    amps, v = record_protocol(sig)
    rate = sig.scales.sample_rate_hz
    a_max = max(amps)
    f = v / (2.0 * math.pi * a_max) * (math.pi / 2.0)  # sine peak speed = the ramp speed
    fs = tuple(sorted({round(f * k, 4) for k in (1 / 3, 1.0, 3.0)}))
    out = [
        ("the same staircase again at a third of the ramp speed (a second rate)",
         Protocol(amps, rates_rad_per_s=(v, v / 3.0), profile="linear", sample_rate_hz=rate)),
        ("holds of 2 s at every peak of the staircase",
         Protocol(amps, rates_rad_per_s=(v,), profile="linear", hold_s=2.0, sample_rate_hz=rate)),
    ]
    if max(fs) <= rate / 20:
        out.append((f"a stepped sine sweep at {a_max:.3g} rad over {', '.join(f'{x:g}' for x in fs)} Hz",
                    SineSweep((a_max,), fs, cycles=3, sample_rate_hz=rate)))
    return out


def protocol_signals(protocol: Protocol | SineSweep, stiffness: float) -> Signals:
    """Signals of a noiseless run of ``protocol`` (for signatures only)."""
    t = protocol.times()
    theta = protocol.deflection(t)
    wiggle = 1e-9 * np.cos(np.arange(t.size))  # channels must not be constant
    rec = make_record(t, stiffness * theta + wiggle, theta + wiggle, source="planned protocol")
    return make_signals(rec, segment(rec))


def recommend_protocol(model: TorqueModel, x: np.ndarray, sig: Signals, pair: tuple[str, str],
                       vif_record: float, noise_Nm: float, tau: float,
                       limit: float) -> ProtocolAdvice | None:
    """The shortest candidate protocol that separates the pair (VIF below ``limit``).

    Args:
        model: a model holding both effects of ``pair``.
        x: its parameters (the pair at plausible values).
        sig: the record's signals (for its amplitudes, speed and sample rate).
        pair: the two effects.
        vif_record: their VIF on the record.
        noise_Nm: the record's torque noise (N·m), for the predicted intervals.
        tau: its correlation time (samples).
        limit: the VIF below which the pair counts as separated.

    Returns:
        The advice, with every protocol tried, or ``None`` if none separates them.
    """
    tried = []
    for change, protocol in candidate_protocols(sig):
        try:
            psig = protocol_signals(protocol, float(x[0]))
        except Exception:  # a protocol the segmenter cannot read is no advice
            continue
        pmodel = TorqueModel(model.effects, psig.scales)
        idx = np.arange(0, psig.n, max(1, psig.n // 8000))
        J = jacobian(pmodel, x, psig, idx)
        v = pair_vif(pmodel, x, psig, idx, pair[0], pair[1], J)[1]
        tried.append((change, protocol, v, pmodel, J, psig.n / idx.size))
    good = [c for c in tried if c[2] < limit]
    if not good:
        return None
    change, protocol, v, pmodel, J, stride = min(good, key=lambda c: (c[1].duration_s, c[2]))
    cov = noise_Nm ** 2 * tau * np.linalg.pinv(J.T @ J / stride)
    ci = report_intervals(pmodel, x, Uncertainty(cov, 10 ** 6, 10 ** 6))
    keys = set()
    for name in pair:
        keys |= set(pmodel.effect_report(name, x))
    half = {k: 0.5 * (ci[k]["ci_high"] - ci[k]["ci_low"]) for k in sorted(keys)}
    command = (f"springcad simulate --stiffness {float(x[0]):.4g} {protocol.cli_args()} "
               "--out planned_test.csv")
    return ProtocolAdvice(pair, change, protocol, vif_record, v, half, command,
                          tuple((c[0], c[2], c[1].duration_s) for c in tried))


# --- confounded effects of a fitted model ------------------------------------------

def find_confounded(state, search, f_scale: float, excluded: frozenset[str] = frozenset()):
    """Find the effect pairs the record cannot separate.

    Two kinds of pair are checked:

    * both effects in the model: their VIF at the fitted values. Both terms
      stay in the model (together they describe the record; what they share is
      not split between them in the report), named after the one whose removal
      costs more on held-out cycles;
    * an effect ``E`` of the model and a library effect ``F`` outside it: ``F``
      must be able to do ``E``'s job (the model with ``F`` in place of ``E``
      beats the model without ``E`` by the loop's gain threshold on held-out
      cycles, with physically possible values) and their VIF, with both fitted
      together, must reach the confounding level. ``E`` carries the combined
      term.

    Args:
        state: the fitted model (``springcad.fit.search.State``).
        search: the run's :class:`springcad.fit.search.Search`.
        f_scale: soft-L1 scale (N·m).
        excluded: effects the evidence audit rejected (not alternatives).

    Returns:
        A list of ``(carrier, other, rho, vif, joint_model, joint_x)``.
    """
    sig, s = search.sig, search.s
    groups = []
    idx = state.inliers(search.cv)
    names = state.model.names
    if len(names) >= 2:
        J = jacobian(state.model, state.x, sig, idx)
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                rho, v = pair_vif(state.model, state.x, sig, idx, a, b, J)
                if v < s.vif_confounded or any(get_effect(n).needs_any for n in (a, b)):
                    continue
                loss = {}
                for name in (a, b):
                    m = state.model.without(name)
                    loss[name] = search.cv_score(m, m.transfer(state.model, state.x),
                                                 state.mask, f_scale)[0]
                carrier, other = (a, b) if loss[a] >= loss[b] else (b, a)
                groups.append((carrier, other, rho, v, state.model, state.x.copy()))
    grouped = {g[0] for g in groups} | {g[1] for g in groups}
    active = set(state.effects)
    # an effect that needs a feature of the model to be located (an angle offset needs a
    # crossover or a kink) is no alternative: when it reads like another effect, the
    # feature does not locate it
    outside = [f for f in LIBRARY
               if f.stage not in ("mask", "encoder") and f.name not in active
               and f.name not in excluded and not f.needs_any and f.applicable(active, sig)]
    if not state.model.effects or not outside:
        return groups
    # screen with one Jacobian: each outside effect's signature at its probe against
    # each model effect's column, both freed of the other columns
    J = jacobian(state.model, state.x, sig, idx)
    base = state.model.predict(state.x, sig, idx)
    signatures = {}
    for f in outside:
        # every law of the family (a friction that lets go at rest reads like a damper
        # where a presliding one does not)
        signatures[f.name] = []
        for law in _alternatives(f):
            joint = state.model.with_effect(law)
            signatures[f.name].append(
                joint.predict(joint.transfer(state.model, state.x), sig, idx) - base)
    for e in state.model.effects:
        col = primary_index(state.model, e.name)
        for f in outside:
            if f.name in grouped:
                continue
            rho = max((pair_correlation(np.column_stack([J, g]), col, J.shape[1])
                       for g in signatures[f.name]), key=abs)
            if e.needs_any or vif(rho) < 0.5 * s.vif_confounded:
                continue
            rest = active - {e.name}
            if any(not o.applicable(rest - {o.name}, sig) for o in state.model.effects
                   if o.name != e.name):
                continue  # another effect needs e: no swap
            m_minus = state.model.without(e.name)
            minus = State(m_minus, m_minus.transfer(state.model, state.x), state.mask,
                          state.series)
            if not f.applicable(set(minus.effects), sig):
                continue
            score_minus = search.cv_score(minus.model, minus.x, minus.mask, f_scale)[0]
            # each law of the family that can do e's job, judged where the record puts
            # the pair: both fitted together; the pair is confounded when one law reads
            # like e (a damper like a friction that lets go at rest, on one speed)
            found = []
            for law in _alternatives(f):
                m_swap, x_swap, score_swap, _ = search.try_law(minus, law, f_scale)
                fx = x_swap[m_swap.slice_of(f.name)]
                if (score_minus - score_swap <= s.gain_threshold
                        or law.physical_problem(fx, float(x_swap[0]), m_swap.scales) is not None):
                    continue  # this law cannot do e's job
                joint = state.model.with_effect(law)
                xj = joint.fit(sig, idx, joint.transfer(state.model, state.x, {f.name: fx}),
                               f_scale)
                rho, v = pair_vif(joint, xj, sig, idx, e.name, f.name)
                if v >= s.vif_confounded:
                    found.append((v, rho, joint, xj, m_swap, x_swap))
            if found:
                v, rho, joint, xj, _, _ = max(found, key=lambda c: c[0])
                groups.append((e.name, f.name, rho, v, joint, xj))
                grouped |= {e.name, f.name}
                # the record read with f in e's place, with each law that reads like e (for
                # the unexplained test: a law outside the library that a law within it
                # describes as well is not flagged)
                search.swaps[e.name] = [(c[4], c[5]) for c in found]
    return groups
