"""The steps of the residual loop's search: add the best candidate, remove what a later
effect made redundant, drop an effect the audit rejected.

:func:`forward` adds the best proposal of each round (:meth:`springcad.fit.search.Search.round`)
while its held-out gain clears the threshold; a proposal may hold two effects (an effect with
one that needs it, see ``Search._pairs``), each then recorded as a step. :func:`backward`
removes effects whose removal does not worsen the held-out criterion; :func:`drop` removes an
effect (and those that need it) and refits.

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from springcad.fit.effects import Effect, get_effect
from springcad.fit.models import nrmse_pct
from springcad.fit.nuisance import nuisance_views
from springcad.fit.glitches import glitch_mask
from springcad.fit.search import BESIDE_STRUCTURE, Search, State
from springcad.fit.signals import Signals


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


def nrmse_of(state: State, sig: Signals, half_range: float,
           keep: np.ndarray | None = None) -> float:
    """NRMSE (%) over the non-glitch samples (of the fitted region ``keep``, if given)."""
    idx = state.inliers(np.arange(sig.n) if keep is None else np.flatnonzero(keep))
    return nrmse_pct(state.model.residual(state.x, sig, idx), half_range)


def forward(state: State, lp: Search, steps: list[Step], rounds: list,
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
        nrmse = (nrmse_of(before, sig, lp.half_range, lp.keep),
                 nrmse_of(after, sig, lp.half_range, lp.keep))
        steps.append(Step("add", effect.name, evidence, before, after, *nrmse))
        for name in after.effects:
            if name in before.effects or name == effect.name:
                continue
            # added with ``effect`` as one candidate (an effect that needs it)
            together = [effect.name, name]
            evidence["added_with"] = together
            steps.append(Step("add", name, {
                **evidence, "meaning": get_effect(name).meaning,
                "reason": (f"{name} is a candidate only beside {effect.name}, and the record "
                           f"asks for the two together: the held-out gain of the pair, less "
                           f"the threshold of the second effect, clears the threshold")},
                before, after, *nrmse))
        added += 1
        state = after
        f_scale = lp.f_scale(state)
        lp.update_noise(state)
        score_now, heldout_now = lp.cv_score(state.model, state.x, state.mask, f_scale)
    return state, score_now, f_scale


def drop(state: State, name: str, lp: Search, f_scale: float, steps: list[Step],
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
                      nrmse_of(state, sig, lp.half_range, lp.keep),
                      nrmse_of(after, sig, lp.half_range, lp.keep)))
    return after


def _refresh_mask(state: State, lp: Search, f_scale: float) -> State:
    """Re-detect glitches on the new residual and refit if they changed."""
    mask = glitch_mask(state.model, state.x, lp.sig, lp.s.glitch_threshold, lp.s.agreement_p)
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


def backward(state: State, score_now: float, f_scale: float, lp: Search,
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
                          nrmse_of(state, sig, lp.half_range, lp.keep),
                          nrmse_of(after, sig, lp.half_range, lp.keep)))
        state = after
        score_now = score
    return state, score_now


