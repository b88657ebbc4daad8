"""The residual loop: name only the effects the record supports, consistently and separably.

1. **Is there a spring?** ``τ = K·θ`` by least squares; unless K is
   ``spring_z`` clustered standard errors above zero the record is reported
   as holding no stiffness above noise, and nothing else is fitted.
2. **Search** (:class:`springcad.fit.search.Search`). Each round tests every
   applicable library effect: a score test of its signature against the
   residual screens it (``screen_z``), then the model with it is fitted on
   half of the cycles and scored on the other half, and vice versa. The
   criterion is ``N'·ln(SSE/N) + k·ln(N')`` over the held-out samples, with
   ``N'`` the independent samples for noise correlated over ``τ`` samples; the
   best candidate is added if it lowers the criterion by more than
   ``gain_threshold``. A backward pass removes effects later ones made
   redundant. An effect that is a candidate only beside another (an angle
   offset beside a crossover) is also tried with it, as one candidate
   (``Search._pairs``): a crossover off zero is no crossover at zero. Friction
   and a late channel, which flip with the direction of
   motion, are also judged with the structure they cannot describe taken out
   (:mod:`springcad.fit.nuisance`: the residual's whole-cycle means and its
   deflection profile common to both directions), and proposed that way only
   after every effect the record as measured asks for: a hard stop or a zero
   jump beside them does not hide them. Samples far from their neighbours are
   proposed as ``outliers`` only where their timing agrees with random draws
   (:func:`springcad.fit.residual.motion_locked_p`): ringing after the protocol's
   steps gathers at its events, a sensor glitch does not.
3. **Evidence audit** (:mod:`springcad.fit.evidence`). Each effect's size is
   fitted again on separate parts of the record (early and late, small and
   large amplitudes, loading and unloading) with the rest of the model free
   on each part; it must agree between the parts and be supported by them
   together, and its values must be physically possible; a shape effect
   (crossover, cubic) must not leave the residual's deflection profile standing
   above noise where it acts (``evidence.shape_check``). The worst failing
   effect is rejected and the search resumes without it, until all pass.
   Effects the audit rejected one at a time, and the baseline's strong candidates the
   greedy path never took, are tried together (:mod:`springcad.fit.joint`), on the model
   and afresh from the linear model, each with the law its family fits best, and audited
   so; an effect of the model that fails beside the set only stood in for it and goes.
   Then effects that patch structure the library cannot describe are not named
   (:mod:`springcad.fit.patches`): a shape in deflection that describes less than
   three times what the residual's deflection profile still holds (a crossover
   fitted to cogging), an effect that loses most of its size when the
   stiffness or a friction's level is freed per whole cycle, where it does change
   between cycles (a cubic fitted to a stiffness that dropped mid-test, a lag to a
   friction that fades as the contact warms), a lag whose term is less than three
   times the structure the residual still holds (a sub-millisecond lag beside a
   stick-slip sawtooth), and an offset the record
   does not show at zero deflection (the mean of a torque sensor's even gain
   error over the range).
4. **Identifiability** (:mod:`springcad.fit.identify`). Pairs of effects the
   record cannot separate (variance inflation ≥ ``vif_confounded``, also
   away from the reversals) are
   named as a group and carried as one term, with the protocol that would
   separate them.
5. **Uncertainty** (:mod:`springcad.fit.inference`): every reported quantity
   with a 95 % confidence interval from the leave-one-run-out jackknife.
6. **What is left** (:mod:`springcad.fit.residual`, :mod:`springcad.fit.localise`):
   the final residual is tested for structure beyond noise (by deflection and
   direction, by time, by run, periodic in time); if any is found it is
   ``unexplained`` and localised.
7. **Structure outside the library beside it.** When what is left is
   unexplained, the pass is run again with that structure kept out of the fit:
   a ripple periodic in deflection taken out of the torque as a nuisance
   (:mod:`springcad.fit.ripple`), or a band of deflection a hard stop or a
   clipping sensor acts in left out (:mod:`springcad.fit.region`); what is left
   is still judged on the record as measured, so the structure stays flagged.

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from springcad.fit.effects import LIBRARY, get_effect
from springcad.fit.evidence import EffectEvidence, audit
from springcad.fit.identify import (Confounded, contribution, find_confounded,
                                    recommend_protocol)
from springcad.fit.joint import joint_sets
from springcad.fit.laws import choose_laws, flag_outside
from springcad.fit.inference import CONFIDENCE, report_intervals, sandwich, uncertainty
from springcad.fit.localise import localise
from springcad.fit.patches import (CHANGING_SIZES, lag_patches, offset_patches,
                                   profile_patches, stiffness_patches)
from springcad.fit.region import outside_structure, saturated
from springcad.fit.residual import residual_structure
from springcad.fit.ripple import periodic_route
from springcad.fit.search import Candidate, LoopSettings, Search, State, line_fit  # noqa: F401
from springcad.fit.steps import Step, backward, drop, forward, nrmse_of
from springcad.fit.signals import Signals, find_glitches
from springcad.fit.torque_model import TorqueModel
from springcad.parallel import single_threaded_blas

__all__ = ["Candidate", "LoopResult", "LoopSettings", "State", "Step", "run_loop"]


@dataclass(frozen=True, repr=False)
class LoopResult:
    """Outcome of the residual loop.

    Attributes:
        baseline: the linear model state.
        steps: accepted steps in order.
        final: the final state (confounded groups carried by one term each).
        rounds: candidates evaluated in each round.
        structure: evidence of structure left in the final residual.
        unexplained: whether structure remains that no effect explains.
        noise_Nm: white-noise level of the final residual (N·m).
        half_range_Nm: NRMSE normaliser (N·m).
        settings: the settings used.
        search_log: every add, remove and reject of the search, in order.
        spring: the linear stiffness with its standard error and z, and
            whether it is above noise.
        evidence: the final audit of each torque-model effect.
        rejected: effects the audit rejected, with the reason.
        confounded: groups the record cannot separate.
        intervals: every reported quantity with its confidence interval.
        localisation: where the unexplained structure lives (or ``None``).
        region: when the model was fitted outside a band of deflection that holds
            structure the library cannot describe: the band, why, and the first
            pass's model (``None`` when fitted on every sample).
        keep: the samples fitted (``None``: all); NRMSEs are over these.
        laws: per named family with several laws, the law kept and how the
            others scored (see :mod:`springcad.fit.laws`).
        nuisance: when a ripple periodic in deflection was taken out of the torque
            before the library was fitted (:mod:`springcad.fit.ripple`): its period,
            amplitude and why (``None`` otherwise).
        searched: the model of the first forward and backward search, before the
            evidence audit (what :mod:`springcad.fit.ripple` also reads).
        nuisance_Nm: the torque taken out as that nuisance (N·m, every sample), or
            ``None``: the final model describes the record with it, so its NRMSE is of
            the record without it (the baseline's of the record as measured).
    """

    baseline: State
    steps: tuple[Step, ...]
    final: State
    rounds: tuple[tuple[Candidate, ...], ...]
    structure: dict
    unexplained: bool
    noise_Nm: float
    half_range_Nm: float
    settings: LoopSettings
    search_log: tuple[dict, ...] = ()
    spring: dict = field(default_factory=dict)
    evidence: dict = field(default_factory=dict)
    rejected: tuple[dict, ...] = ()
    confounded: tuple[Confounded, ...] = ()
    intervals: dict = field(default_factory=dict)
    localisation: dict | None = None
    region: dict | None = None
    keep: np.ndarray | None = None
    laws: dict = field(default_factory=dict)
    nuisance: dict | None = None
    searched: State | None = None
    nuisance_Nm: np.ndarray | None = None

    def __repr__(self) -> str:
        # the states hold per-sample arrays: show the chain of steps only
        chain = " ".join(f"{s.action} {s.effect}" for s in self.steps) or "no steps"
        return f"LoopResult({chain}; unexplained={self.unexplained})"

    @property
    def no_spring(self) -> bool:
        """True when the record holds no stiffness above noise."""
        return not self.spring.get("above_noise", True)

    @property
    def identified(self) -> tuple[str, ...]:
        """Effects named on their own (not part of a confounded group)."""
        grouped = {n for g in self.confounded for n in g.effects}
        return tuple(e for e in self.final.effects if e not in grouped)

    def nrmse_pct(self, state: State, sig: Signals) -> float:
        """NRMSE (%) of ``state`` on ``sig`` (the record as measured); a state of the
        loop beside a nuisance (every one but the baseline) with the nuisance taken out."""
        if state is not self.baseline:
            sig = self.described(sig)
        return nrmse_of(state, sig, self.half_range_Nm, self.keep)

    def described(self, sig: Signals) -> Signals:
        """The record the final model describes: ``sig`` with the nuisance taken out."""
        if self.nuisance_Nm is None:
            return sig
        return sig.with_torque(sig.torque - self.nuisance_Nm)


def run_loop(sig: Signals, settings: LoopSettings = LoopSettings()) -> LoopResult:
    """Run the residual loop on one record (see the module docstring).

    Args:
        sig: signals of the segmented record.
        settings: loop settings.

    Returns:
        Baseline, steps, final model, evidence, confounded groups, intervals,
        and the structure left over with its localisation.
    """
    with single_threaded_blas():
        # a torque sensor on its rails reads them, not the spring: fitted off them
        clipped = saturated(sig, settings, _run_loop)
        if clipped is not None:
            return clipped
        first = _run_loop(sig, settings)
        # a ripple first: over a range of two or three of its periods it reads as structure
        # at large deflection, and a band left out of the fit there leaves it patched
        return (periodic_route(sig, settings, first, _run_loop)
                or outside_structure(sig, settings, first, _run_loop) or first)


def _spring(sig: Signals, lp: Search) -> tuple[State, dict]:
    """Linear least squares ``τ = K·θ`` and whether K stands above the noise."""
    theta, torque = sig.theta[lp.all], sig.torque[lp.all]
    k = float(theta @ torque / (theta @ theta))
    r = torque - k * theta
    unc = sandwich(theta[:, None], r, sig.runs[lp.all], sig.scales.sample_rate_hz)
    se = float(unc.se[0])
    z = k / se if se > 0 else math.inf
    above = bool(k > 0 and z >= lp.s.spring_z)
    t = unc.t_quantile()
    info = {"stiffness_Nm_per_rad": k, "se_Nm_per_rad": se, "z": z,
            "ci_low": k - t * se, "ci_high": k + t * se, "above_noise": above,
            "threshold_z": lp.s.spring_z}
    model = TorqueModel((), sig.scales)
    if not above:
        return State(model, np.array([max(k, 1e-9)])), info
    state = State(model, np.array([k]))
    return State(model, model.fit(sig, lp.all, state.x, lp.f_scale(state), max_nfev=200)), info


def _run_loop(sig: Signals, settings: LoopSettings, keep: np.ndarray | None = None,
              judge: Signals | None = None) -> LoopResult:
    """One pass of the loop on ``sig`` (the samples ``keep``), what is left judged on
    ``judge`` (default ``sig``: the record with a nuisance taken out is judged as measured)."""
    lp = Search(sig, settings, keep)
    if judge is not None:
        lp.judge = judge
    baseline, spring = _spring(sig, lp)
    if not spring["above_noise"]:
        return _finish(lp, baseline, baseline, (), (), (), spring, {}, (), ())
    search: list[Step] = []
    rounds: list = []
    excluded: set[str] = set()
    rejected: list[dict] = []
    state, score, f_scale = forward(baseline, lp, search, rounds, None, excluded)
    state, score = backward(state, score, f_scale, lp, search)
    searched = state
    state, laws = choose_laws(state, lp, f_scale)
    evidence: dict[str, EffectEvidence] = {}
    for attempt in range(settings.max_audits + 1):
        aud = audit(state.model, state.x, sig, state.inliers(lp.cv), f_scale,
                    settings.agreement_p, settings.support_z)
        evidence = aud.effects
        failed = aud.failed()
        if not failed:
            break
        # the worst goes, with every other clear failure (unsupported, or parts that
        # disagree beyond p = 1e-6); a marginal disagreement can be another effect's
        # doing, so it is audited again once the worst is gone
        clear = [ev for ev in failed[1:] if ev.strength >= 6.0]
        for ev in failed[:1] + clear:
            rejected.append({"effect": ev.effect, "reason": ev.reason(),
                             "short_reason": ev.short_reason(), "audit": ev.to_dict()})
            excluded.add(ev.effect)
            state = drop(state, ev.effect, lp, f_scale, search,
                          {"meaning": get_effect(ev.effect).meaning, "reason": ev.reason(),
                           "audit": ev.to_dict()})
        if attempt < settings.max_audits:
            # a law chosen beside a rejected effect may not do the family's job without it
            # (a filter, which only delays, beside a friction; once the friction is gone
            # the record asks the lag family for a damper): chosen again before the search
            state, laws = choose_laws(state, lp, f_scale)
            state, score, f_scale = forward(state, lp, search, rounds, None, excluded)
            state, score = backward(state, score, f_scale, lp, search)
            state, laws = choose_laws(state, lp, f_scale)
    if rejected:
        # effects rejected one at a time may be the record's together (see fit.joint)
        score_now = lp.cv_score(state.model, state.x, state.mask, f_scale)[0]
        # and the baseline's strong candidates the greedy path never took: beside an effect
        # that took up their structure first (a lag fitted before the friction) they lose
        # (tried only after the rejected effects alone: their sets, larger, would crowd out
        # a smaller set of rejected effects the record supports)
        pool = [r["effect"] for r in rejected]
        strong = [c.effect for c in (rounds[0] if rounds else ())
                  if c.gain is not None and c.gain > settings.gain_threshold
                  and c.effect not in state.effects and c.effect not in excluded
                  and c.effect not in pool]
        found = joint_sets(state, pool, lp, f_scale, score_now, baseline)
        if found is None and strong:
            found = joint_sets(state, pool + strong, lp, f_scale, score_now, baseline)
        if found is not None:
            before, (state, names, gain, laws, dropped) = state, found
            excluded -= set(names)
            evidence = audit(state.model, state.x, sig, state.inliers(lp.cv), f_scale,
                             settings.agreement_p, settings.support_z).effects
            rejected = [r for r in rejected if r["effect"] not in names]
            for name in dropped:
                reason = (f"it failed the evidence audit beside {', '.join(names)}, added as "
                          f"a set: it stood in for them, and the set without it is supported")
                rejected.append({"effect": name, "reason": reason,
                                 "short_reason": "stood in for effects added as a set",
                                 "audit": None})
                excluded.add(name)
                search.append(Step("reject", name, {"meaning": get_effect(name).meaning,
                                                    "reason": reason}, before, state,
                                   nrmse_of(before, sig, lp.half_range, lp.keep),
                                   nrmse_of(state, sig, lp.half_range, lp.keep)))
            for name in names:
                search.append(Step("add", name, {
                    "meaning": get_effect(name).meaning, "heldout_gain": gain,
                    "added_with": list(names), "reason": (
                        "rejected one at a time (or never added: an effect fitted before it "
                        "had taken up its structure), supported together: added as a set, "
                        "every effect of the model passes the evidence audit")}, before, state,
                    nrmse_of(before, sig, lp.half_range, lp.keep),
                    nrmse_of(state, sig, lp.half_range, lp.keep)))
    state = _drop_patches(state, lp, f_scale, search, rejected, excluded)
    evidence = {k: v for k, v in evidence.items() if k in state.model.names}
    pairs = find_confounded(state, lp, f_scale, frozenset(excluded))
    steps = search
    if any(s.action != "add" for s in search):
        # derive the path again over the surviving effects, so that every reported
        # step belongs to the final model
        derived: list[Step] = []
        d_state, d_score, d_scale = forward(baseline, lp, derived, [], set(state.effects),
                                             excluded)
        if set(d_state.effects) == set(state.effects):
            steps = derived
            rounds.append(tuple(lp.round(state, d_score, d_scale, None, frozenset(excluded))[0]))
    log = tuple({"action": s.action, "effect": s.effect,
                 "heldout_gain": s.evidence.get("heldout_gain",
                                                -s.evidence.get("heldout_loss_when_removed", 0.0)),
                 "reason": s.evidence.get("reason")}
                for s in search)
    laws = {k: v for k, v in laws.items() if k in state.model.names}
    if not state.effects:
        # every effect rejected or removed: the final model is the baseline itself (a refit
        # from another start lands a round-off away, above the baseline's error)
        state = baseline
    out = _finish(lp, baseline, state, tuple(steps), tuple(rounds), log, spring, evidence,
                  tuple(rejected), pairs, laws)
    return dataclasses.replace(out, searched=searched)


def _drop_patches(state: State, lp: Search, f_scale: float, search: list[Step],
                  rejected: list[dict], excluded: set[str]) -> State:
    """Drop, worst first, the effects shaped in deflection that patch structure the library
    cannot describe (:func:`springcad.fit.patches.profile_patches`), refitting after each."""
    while True:
        idx = state.inliers(lp.cv)
        found = profile_patches(state.model, state.x, lp.sig, idx, lp.s.structure_p)
        short = "a patch over structure in deflection the library cannot describe"
        if not found:
            found = stiffness_patches(state.model, state.x, lp.sig, idx, lp.cv_rate_hz,
                                      lp.s.structure_p, (None,) + CHANGING_SIZES)
            short = "a patch over a stiffness or a friction that changed during the test"
        if not found:
            found = lag_patches(state.model, state.x, lp.sig, idx, lp.s.structure_bins,
                                lp.s.structure_min_rms, lp.s.structure_p, lp.s.excess_ratio)
            short = "a late channel beside structure the library cannot describe"
        if not found:
            found = offset_patches(state.model, state.x, lp.sig, idx, lp.s.agreement_p,
                                   lp.s.support_z)
            short = "an offset the record does not show at zero deflection"
        if not found:
            return state
        name = min(found, key=lambda n: found[n][0])
        reason = found[name][1]
        rejected.append({"effect": name, "reason": reason, "short_reason": short,
                         "audit": None})
        excluded.add(name)
        state = drop(state, name, lp, f_scale, search,
                     {"meaning": get_effect(name).meaning, "reason": reason})


def _finish(lp: Search, baseline: State, state: State, steps, rounds, log, spring: dict,
            evidence: dict, rejected: tuple, pairs, laws: dict | None = None) -> LoopResult:
    """Intervals, confounded groups with advice, and the structure left over (and a law
    outside the library's, see :func:`springcad.fit.laws.beyond_library`: flagged when the
    library's law fitted in its place leaves structure the residual tests find)."""
    sig, settings = lp.sig, lp.s
    fitted = state.inliers(lp.all)
    if spring.get("above_noise", True):
        state, dilution = _undilute(state, sig, fitted)
        spring = {**spring, "regression_dilution_correction": dilution}
        # the baseline's stiffness was regressed on the same noisy deflection: corrected
        # alike, a final model with no effect is the baseline itself
        baseline = _undilute(baseline, sig, baseline.inliers(lp.all))[0]
    # what is left is judged on every sample, also those of a region left out of the fit, and
    # on the record as measured (``lp.judge``), also when a nuisance was taken out of it
    judge = lp.judge
    idx = state.inliers(np.arange(sig.n))
    r = state.model.residual(state.x, judge, idx)
    structure, unexplained, noise = residual_structure(
        r, idx, judge, bins=settings.structure_bins, min_rms=settings.structure_min_rms,
        p_level=settings.structure_p, excess_ratio=settings.excess_ratio)
    tau = structure["noise_correlation_samples"]
    outside = flag_outside(state, lp, laws or {}, idx, noise, tau)
    if outside:
        structure = {**structure, "laws_outside_library": outside}
        unexplained = True
    unc = uncertainty(state.model, state.x, sig, fitted)
    intervals = report_intervals(state.model, state.x, unc)
    if not spring.get("above_noise", True):
        intervals["stiffness_Nm_per_rad"] = {
            "value": spring["stiffness_Nm_per_rad"], "ci_low": spring["ci_low"],
            "ci_high": spring["ci_high"], "se": spring["se_Nm_per_rad"], "at_bound": False}
    intervals.update(_series_intervals(state, lp))
    confounded = _groups(pairs, state, lp, noise, tau)
    for g in confounded:
        for name in g.in_model:
            for key in state.model.effect_report(name, state.x):
                intervals[key]["confounded_with"] = [n for n in g.effects if n != name]
    loc = None
    if unexplained:
        x0, x1 = state.x.copy(), state.x.copy()
        x0[0], x1[0] = 0.0, 1.0
        shape = state.model.predict(x1, sig, idx) - state.model.predict(x0, sig, idx)
        loc = localise(r, idx, judge, noise, tau, shape, p_level=settings.structure_p)
        if outside:
            # after the residual's own patterns (the first decides a fitted region)
            own = loc["findings"]
            loc = {**loc, "findings": own + outside,
                   "summary": "; ".join(f["text"] for f in own + outside)}
    return LoopResult(baseline, steps, state, rounds, structure, unexplained, noise,
                      lp.half_range, settings, log, spring, evidence, rejected, confounded,
                      intervals, loc, keep=lp.keep, laws=laws or {})


def _undilute(state: State, sig: Signals, idx: np.ndarray) -> tuple[State, float]:
    """Correct the stiffness for the noise on the deflection it was regressed on.

    With ``τ = K·q(θ)`` fitted on a measured deflection ``θ + e`` (noise ``σ``),
    least squares returns ``K·Σq²/(Σq² + σ²·Σq'²)`` (regression dilution); the
    factor is small (1e-5 to 1e-4 here) but on a long record it is comparable
    with the standard error, and the intervals would miss the true stiffness.
    ``σ`` is the deflection's spread about its smoothed curve, ``q'`` the slope
    of the model's elastic shape.
    """
    sigma = sig.scales.theta_noise
    if sigma <= 0.0:
        return state, 0.0
    x0, x1 = state.x.copy(), state.x.copy()
    x0[0], x1[0] = 0.0, 1.0
    model = state.model
    h = 1e-3 * max(sig.scales.theta_ref, 1e-9)
    moved = sig.shifted(h)

    def shape(s):
        return model.predict(x1, s, idx) - model.predict(x0, s, idx)

    q = shape(sig)
    dq = (shape(moved) - q) / h
    den = float(q @ q)
    dilution = sigma ** 2 * float(dq @ dq) / den if den > 0 else 0.0
    x = state.x.copy()
    x[0] *= 1.0 + dilution
    return State(model, x, state.mask, state.series), dilution


def _groups(pairs, state: State, lp: Search, noise: float, tau: float) -> tuple[Confounded, ...]:
    """Merge confounded pairs sharing an effect and attach the protocol advice."""
    sig = lp.sig
    out: list[Confounded] = []
    idx = state.inliers(lp.cv)
    for carrier, other, rho, v, joint, xj in pairs:
        same = next((g for g in out if carrier in g.effects or other in g.effects), None)
        if same is not None:
            merged = same.effects + tuple(n for n in (carrier, other) if n not in same.effects)
            out[out.index(same)] = dataclasses.replace(same, effects=merged)
            continue
        held = carrier if carrier in state.model.names else other
        present = tuple(n for n in (carrier, other) if n in state.model.names)
        c = np.abs(sum(contribution(state.model, state.x, sig, idx, n) for n in present))
        moving = np.abs(sig.rate[idx]) > 0.2 * np.percentile(np.abs(sig.rate[idx]), 99)
        advice = recommend_protocol(joint, xj, sig, (carrier, other), v, noise, tau,
                                    lp.s.vif_confounded)
        out.append(Confounded((held,) + tuple(n for n in (carrier, other) if n != held), held,
                              rho, v, float(np.median(c[moving])),
                              get_effect(held).signature, advice, present))
    return tuple(out)


def _series_intervals(state: State, lp: Search) -> dict:
    """Confidence intervals of the series stiffness (clustered on runs)."""
    if state.series is None:
        return {}
    sig = lp.sig
    keep = ~find_glitches(sig.torque, lp.s.glitch_threshold)
    tau, e = sig.torque[keep], (sig.encoder - sig.theta)[keep]
    slope, offset = state.series
    J = np.column_stack([tau, np.ones_like(tau)])
    unc = sandwich(J, e - offset - slope * tau, sig.runs[keep], sig.scales.sample_rate_hz)
    t = unc.t_quantile()
    lo, hi = slope - t * unc.se[0], slope + t * unc.se[0]
    k = 1.0 / slope
    # 1/slope over the slope interval; unbounded when the interval reaches zero
    k_lo = 1.0 / hi if hi > 0 else math.inf
    k_hi = 1.0 / lo if lo > 0 else math.inf
    return {"series_stiffness_Nm_per_rad": {"value": k, "ci_low": min(k_lo, k_hi),
                                            "ci_high": max(k_lo, k_hi),
                                            "se": float(unc.se[0]) * k * k, "at_bound": False},
            "encoder_offset_rad": {"value": offset, "ci_low": offset - t * unc.se[1],
                                   "ci_high": offset + t * unc.se[1],
                                   "se": float(unc.se[1]), "at_bound": False}}


#: library effects in their listing order (re-exported for the report)
EFFECT_ORDER = tuple(e.name for e in LIBRARY)
__all__ += ["EFFECT_ORDER", "CONFIDENCE", "line_fit"]
