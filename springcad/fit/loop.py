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
   redundant. Friction and a late channel, which flip with the direction of
   motion, are also judged with the structure they cannot describe taken out
   (:mod:`springcad.fit.nuisance`: the residual's whole-cycle means and its
   deflection profile common to both directions), and proposed that way only
   after every effect the record as measured asks for: a hard stop or a zero
   jump beside them does not hide them.
3. **Evidence audit** (:mod:`springcad.fit.evidence`). Each effect's size is
   fitted again on separate parts of the record (early and late, small and
   large amplitudes, loading and unloading) with the rest of the model free
   on each part; it must agree between the parts and be supported by them
   together, and its values must be physically possible; a shape effect
   (crossover, cubic) must not leave the residual's deflection profile standing
   above noise where it acts (``evidence.shape_check``). The worst failing
   effect is rejected and the search resumes without it, until all pass.
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

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from springcad.fit.effects import LIBRARY, Effect, get_effect
from springcad.fit.evidence import EffectEvidence, audit
from springcad.fit.identify import (Confounded, contribution, find_confounded,
                                    recommend_protocol)
from springcad.fit.joint import joint_sets
from springcad.fit.laws import choose_laws, flag_outside
from springcad.fit.inference import CONFIDENCE, report_intervals, sandwich, uncertainty
from springcad.fit.localise import localise
from springcad.fit.region import outside_structure
from springcad.fit.models import nrmse_pct
from springcad.fit.nuisance import nuisance_views
from springcad.fit.residual import residual_structure
from springcad.fit.search import (BESIDE_STRUCTURE, Candidate, LoopSettings, Search,  # noqa: F401
                                  State, line_fit, turn_guard)
from springcad.fit.signals import Signals, find_glitches
from springcad.fit.torque_model import TorqueModel
from springcad.parallel import single_threaded_blas

__all__ = ["Candidate", "LoopResult", "LoopSettings", "State", "Step", "run_loop"]


@dataclass(frozen=True)
class Step:
    """One accepted change of the model.

    Attributes:
        action: ``"add"``, ``"remove"`` (made redundant by a later effect) or
            ``"reject"`` (failed the evidence audit).
        effect: library name.
        evidence: detector, held-out gain, penalty, runner-up, physical
            meaning; for a rejection the audit's reason.
        before: state before the step.
        after: state after the step.
        nrmse_before_pct: NRMSE on all (non-glitch) samples before.
        nrmse_after_pct: same after.
    """

    action: str
    effect: str
    evidence: dict
    before: State
    after: State
    nrmse_before_pct: float
    nrmse_after_pct: float

    def effect_params(self) -> dict:
        """The fitted parameters of this step's effect (after the step)."""
        if self.action != "add":
            return {}
        if self.effect == "outliers":
            return {k: v for k, v in self.after.params().items()
                    if k in ("n_outliers", "outlier_fraction")}
        if self.effect == "series_compliance":
            return {k: v for k, v in self.after.params().items()
                    if k in ("series_stiffness_Nm_per_rad", "encoder_offset_rad")}
        return self.after.model.effect_report(self.effect, self.after.x)

    def to_dict(self) -> dict:
        return {"action": self.action, "effect": self.effect, "evidence": self.evidence,
                "params": self.effect_params(), "model": self.after.label,
                "model_params": self.after.params(),
                "nrmse_before_pct": self.nrmse_before_pct,
                "nrmse_after_pct": self.nrmse_after_pct}


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
        return _nrmse(state, sig, self.half_range_Nm, self.keep)


def _nrmse(state: State, sig: Signals, half_range: float,
           keep: np.ndarray | None = None) -> float:
    """NRMSE (%) over the non-glitch samples (of the fitted region ``keep``, if given)."""
    idx = state.inliers(np.arange(sig.n) if keep is None else np.flatnonzero(keep))
    return nrmse_pct(state.model.residual(state.x, sig, idx), half_range)


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
        first = _run_loop(sig, settings)
        return outside_structure(sig, settings, first, _run_loop) or first


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


def _run_loop(sig: Signals, settings: LoopSettings, keep: np.ndarray | None = None) -> LoopResult:
    lp = Search(sig, settings, keep)
    baseline, spring = _spring(sig, lp)
    if not spring["above_noise"]:
        return _finish(lp, baseline, baseline, (), (), (), spring, {}, (), ())
    search: list[Step] = []
    rounds: list = []
    excluded: set[str] = set()
    rejected: list[dict] = []
    state, score, f_scale = _forward(baseline, lp, search, rounds, None, excluded)
    state, score = _backward(state, score, f_scale, lp, search)
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
            state = _drop(state, ev.effect, lp, f_scale, search,
                          {"meaning": get_effect(ev.effect).meaning, "reason": ev.reason(),
                           "audit": ev.to_dict()})
        if attempt < settings.max_audits:
            state, score, f_scale = _forward(state, lp, search, rounds, None, excluded)
            state, score = _backward(state, score, f_scale, lp, search)
            state, laws = choose_laws(state, lp, f_scale)
    if rejected:
        # effects rejected one at a time may be the record's together (see fit.joint)
        score_now = lp.cv_score(state.model, state.x, state.mask, f_scale)[0]
        found = joint_sets(state, [r["effect"] for r in rejected], lp, f_scale, score_now)
        if found is not None:
            before, (state, names, gain) = state, found
            excluded -= set(names)
            state, laws = choose_laws(state, lp, f_scale)
            evidence = audit(state.model, state.x, sig, state.inliers(lp.cv), f_scale,
                             settings.agreement_p, settings.support_z).effects
            rejected = [r for r in rejected if r["effect"] not in names]
            for name in names:
                search.append(Step("add", name, {
                    "meaning": get_effect(name).meaning, "heldout_gain": gain,
                    "added_with": list(names), "reason": (
                        "rejected one at a time, supported together: added as a set, every "
                        "effect of the model passes the evidence audit")}, before, state,
                    _nrmse(before, sig, lp.half_range, lp.keep),
                    _nrmse(state, sig, lp.half_range, lp.keep)))
    evidence = {k: v for k, v in evidence.items() if k in state.model.names}
    pairs = find_confounded(state, lp, f_scale, frozenset(excluded))
    steps = search
    if any(s.action != "add" for s in search):
        # derive the path again over the surviving effects, so that every reported
        # step belongs to the final model
        derived: list[Step] = []
        d_state, d_score, d_scale = _forward(baseline, lp, derived, [], set(state.effects),
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
    return _finish(lp, baseline, state, tuple(steps), tuple(rounds), log, spring, evidence,
                   tuple(rejected), pairs, laws)


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
    # what is left is judged on every sample, also those of a region left out of the fit
    idx = state.inliers(np.arange(sig.n))
    r = state.model.residual(state.x, sig, idx)
    structure, unexplained, noise = residual_structure(
        r, idx, sig, bins=settings.structure_bins, min_rms=settings.structure_min_rms,
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
        loc = localise(r, idx, sig, noise, tau, shape, p_level=settings.structure_p)
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
    moved = dataclasses.replace(sig, theta=sig.theta + h)

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


def _forward(state: State, lp: Search, steps: list[Step], rounds: list,
             allowed: set[str] | None, excluded: set[str]) -> tuple[State, float, float]:
    """Add the best candidate while its evidence clears the threshold."""
    sig, settings = lp.sig, lp.s
    f_scale = lp.f_scale(state)
    lp.update_noise(state)
    score_now, heldout_now = lp.cv_score(state.model, state.x, state.mask, f_scale)
    added = 0
    while added < settings.max_steps:
        cands, proposals = lp.round(state, score_now, f_scale, allowed, frozenset(excluded))
        rounds.append(tuple(cands))
        if not proposals or proposals[0][0] <= settings.gain_threshold:
            break
        gain, effect, proposal, z, heldout, n_added = proposals[0]
        runner = ({"effect": proposals[1][1].name, "heldout_gain": proposals[1][0]}
                  if len(proposals) > 1 else None)
        before = state
        if effect.stage == "encoder":
            after = proposal
            r0, r1 = heldout
            evidence = _evidence(effect, z, gain, n_added, lp, runner,
                                 heldout_before=r0, heldout_after=r1, unit="rad")
        else:
            mask = proposal.mask
            x = lp.refit(proposal.model, proposal.x, mask, f_scale)
            after = State(proposal.model, x, mask, state.series)
            if mask is not None and effect.stage != "mask":
                after = _refresh_mask(after, lp, f_scale)
            evidence = _evidence(effect, z, gain, n_added, lp, runner,
                                 heldout_before=heldout_now, heldout_after=heldout, unit="Nm")
            if effect.stage == "mask":
                evidence["n_glitches"] = int(mask.sum())
            if any(c.effect == effect.name and c.note == BESIDE_STRUCTURE for c in cands):
                evidence["beside_structure"] = (
                    "found with the residual's structure it cannot describe (its whole-cycle "
                    "means and its deflection profile common to both directions) taken out: "
                    "the held-out gain and detector are measured there; on the record as "
                    "measured that structure dominates the error")
        steps.append(Step("add", effect.name, evidence, before, after,
                          _nrmse(before, sig, lp.half_range, lp.keep),
                          _nrmse(after, sig, lp.half_range, lp.keep)))
        added += 1
        state = after
        f_scale = lp.f_scale(state)
        lp.update_noise(state)
        score_now, heldout_now = lp.cv_score(state.model, state.x, state.mask, f_scale)
    return state, score_now, f_scale


def _drop(state: State, name: str, lp: Search, f_scale: float, steps: list[Step],
          evidence: dict) -> State:
    """Remove effect ``name`` (and effects that need it), refit, record a rejection."""
    sig = lp.sig
    model, mask, series = state.model, state.mask, state.series
    if name == "outliers":
        mask = None
    elif name == "series_compliance":
        series = None
    else:
        model = model.without(name)
        active = set(model.names)
        for e in list(model.effects):
            if not e.applicable(active - {e.name}, sig):
                model = model.without(e.name)
    x = lp.refit(model, model.transfer(state.model, state.x), mask, f_scale)
    after = State(model, x, mask, series)
    steps.append(Step("reject", name, evidence, state, after,
                      _nrmse(state, sig, lp.half_range, lp.keep),
                      _nrmse(after, sig, lp.half_range, lp.keep)))
    return after


def _refresh_mask(state: State, lp: Search, f_scale: float) -> State:
    """Re-detect glitches on the new residual and refit if they changed."""
    r = state.model.residual(state.x, lp.sig, np.arange(lp.sig.n))
    mask = find_glitches(r, lp.s.glitch_threshold,
                         guard=turn_guard(state.model, state.x, lp.sig),
                         model=lp.sig.torque - r)
    if np.array_equal(mask, state.mask):
        return state
    x = lp.refit(state.model, state.x, mask, f_scale)
    return State(state.model, x, mask, state.series)


def _evidence(effect: Effect, z: float, gain: float, n_added: int, lp: Search, runner,
              heldout_before: float, heldout_after: float, unit: str) -> dict:
    statistic = "glitch_count" if effect.stage == "mask" else "score_test_z"
    return {
        "meaning": effect.meaning,
        "detector": {"statistic": statistic, "value": z, "looks_for": effect.looks_for},
        "heldout_gain": gain,
        "gain_threshold": lp.s.gain_threshold,
        "n_params_added": n_added,
        "parameter_penalty": n_added * lp.log_n,
        "n_heldout_samples": lp.n_cv,
        "noise_correlation_samples": lp.tau,
        f"heldout_rmse_before_{unit}": heldout_before,
        f"heldout_rmse_after_{unit}": heldout_after,
        "runner_up": runner,
    }


def _backward(state: State, score_now: float, f_scale: float, lp: Search,
              steps: list[Step]) -> tuple[State, float]:
    """Remove torque-model effects whose removal does not worsen the held-out criterion."""
    sig = lp.sig
    while state.model.effects:
        names = set(state.effects)
        best = None
        for e in state.model.effects:
            rest = names - {e.name}
            if any(not o.applicable(rest - {o.name}, sig) for o in state.model.effects
                   if o.name != e.name):
                continue
            m_minus = state.model.without(e.name)
            x_minus = m_minus.transfer(state.model, state.x)
            score, heldout = lp.cv_score(m_minus, x_minus, state.mask, f_scale)
            loss = score - score_now
            if loss < 0.0 and e.direction_signed:
                # an effect found beside structure it cannot describe is judged as it was
                # found: with that structure taken out (see springcad.fit.nuisance)
                idx = state.inliers(lp.cv)
                views = nuisance_views(state.model.residual(state.x, sig, idx), idx, sig)
                if "direction" in views:
                    alt = lp.view(views["direction"])
                    loss = (alt.cv_score(m_minus, x_minus, state.mask, f_scale)[0]
                            - alt.cv_score(state.model, state.x, state.mask, f_scale)[0])
            if best is None or loss < best[0]:
                best = (loss, e, m_minus, x_minus, score, heldout)
        if best is None or best[0] >= 0.0:
            break
        loss, e, m_minus, x_minus, score, heldout = best
        x = lp.refit(m_minus, x_minus, state.mask, f_scale)
        after = State(m_minus, x, state.mask, state.series)
        evidence = {"meaning": e.meaning, "heldout_loss_when_removed": loss,
                    "reason": "a later effect explains what this one did; the held-out "
                              "criterion is better without it"}
        steps.append(Step("remove", e.name, evidence, state, after,
                          _nrmse(state, sig, lp.half_range, lp.keep),
                          _nrmse(after, sig, lp.half_range, lp.keep)))
        state = after
        score_now = score
    return state, score_now


#: library effects in their listing order (re-exported for the report)
EFFECT_ORDER = tuple(e.name for e in LIBRARY)
__all__ += ["EFFECT_ORDER", "CONFIDENCE", "line_fit"]
