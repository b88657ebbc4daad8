"""The residual loop: from ``τ = K·θ``, add the effect the residual asks for, repeat.

Each round:

1. compute the residual of the current model;
2. for every applicable effect of the library, run its detector: a score
   test of the effect's signature against the residual, after projecting out
   what the current parameters can already absorb (``z``, in standard errors);
   candidates with ``|z|`` below ``screen_z`` cannot pay for a parameter and
   are not fitted;
3. fit the current model plus the candidate on half of the cycles and score it
   on the other half, and vice versa (two-fold cross-validation over whole
   excursions). The criterion is ``N'·ln(SSE/N) + k·ln(N')`` over the N
   held-out samples, with ``N' = N/τ`` the number of independent samples for
   noise correlated over τ samples (Gaussian log-likelihood with a BIC
   parameter penalty), so an effect must both predict unseen cycles better
   and pay for its parameters;
4. add the effect with the largest drop of the criterion if the drop exceeds
   ``gain_threshold``, refit everything on all samples, record the step.

The loop stops when no candidate clears the threshold. A backward pass then
removes effects made redundant by later ones (an offset added before the
crossover was modelled, say); if it removed any, the path is derived again
over the surviving effects, so every reported step belongs to the final model.
Finally the residual is tested for structure left over: mean residual in bins
of deflection (per direction of motion) and of time, compared with the noise
level. Structure that is both statistically significant and larger than a
quarter of the noise level is reported as ``unexplained``, with its evidence
(see :mod:`springcad.fit.residual`).

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.fit.effects import LIBRARY, Effect
from springcad.fit.models import nrmse_pct, rmse
from springcad.fit.residual import noise_model, residual_structure
from springcad.fit.signals import Signals, find_glitches
from springcad.fit.torque_model import TorqueModel, single_threaded_blas


@dataclass(frozen=True)
class LoopSettings:
    """Knobs of the residual loop.

    Attributes:
        gain_threshold: least drop of the held-out criterion (log-likelihood
            units, after the parameter penalty) for an effect to be added.
        screen_z: candidates whose detector ``|z|`` is below this are not fitted.
        max_steps: most effects added.
        max_cv_samples: cross-validation uses every k-th sample to stay below this.
        glitch_threshold: glitch size in noise standard deviations.
        structure_bins: bins of deflection (per direction) and of time.
        structure_min_rms: least structure, in noise standard deviations, that
            counts as unexplained.
        structure_p: significance level of the binned-structure test.
        excess_ratio: residual RMS over the noise level that counts as unexplained.
    """

    gain_threshold: float = 25.0
    screen_z: float = 3.0
    max_steps: int = 10
    max_cv_samples: int = 8000
    glitch_threshold: float = 6.0
    structure_bins: int = 40
    structure_min_rms: float = 0.25
    structure_p: float = 1e-6
    excess_ratio: float = 1.25


@dataclass
class State:
    """A model of the record: torque model, parameters, glitch mask, encoder fit.

    Attributes:
        model: the torque model.
        x: its parameters.
        mask: True at samples excluded as glitches (``None`` without ``outliers``).
        series: ``(slope_rad_per_Nm, offset_rad)`` of encoder minus optical
            deflection against torque, or ``None`` without ``series_compliance``.
    """

    model: TorqueModel
    x: np.ndarray
    mask: np.ndarray | None = None
    series: tuple[float, float] | None = None

    @property
    def effects(self) -> tuple[str, ...]:
        names = list(self.model.names)
        if self.mask is not None:
            names.append("outliers")
        if self.series is not None:
            names.append("series_compliance")
        return tuple(e.name for e in LIBRARY if e.name in names)

    @property
    def label(self) -> str:
        return " + ".join(("linear",) + self.effects)

    def inliers(self, idx: np.ndarray) -> np.ndarray:
        return idx if self.mask is None else idx[~self.mask[idx]]

    def params(self) -> dict:
        """All fitted parameters with units in the names."""
        out = self.model.report(self.x)
        if self.mask is not None:
            out["n_outliers"] = int(self.mask.sum())
            out["outlier_fraction"] = float(self.mask.mean())
        if self.series is not None:
            slope, offset = self.series
            out["series_stiffness_Nm_per_rad"] = float(1.0 / slope) if slope else math.inf
            out["encoder_offset_rad"] = float(offset)
        return out


@dataclass(frozen=True)
class Candidate:
    """What one round found about one candidate effect.

    Attributes:
        effect: library name.
        z: detector statistic (score-test z, or glitch count for ``outliers``).
        fitted: whether it passed screening and was cross-validated.
        gain: drop of the held-out criterion (positive = better), if fitted.
        heldout_rmse: held-out RMS error with the effect (N·m; rad for the
            encoder channel), if fitted.
    """

    effect: str
    z: float
    fitted: bool
    gain: float | None = None
    heldout_rmse: float | None = None

    def to_dict(self) -> dict:
        return {"effect": self.effect, "detector": self.z, "fitted": self.fitted,
                "heldout_gain": self.gain, "heldout_rmse": self.heldout_rmse}


@dataclass(frozen=True)
class Step:
    """One accepted change of the model.

    Attributes:
        action: ``"add"`` or ``"remove"``.
        effect: library name.
        evidence: detector, held-out gain, penalty, runner-up, physical meaning.
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
        if self.action == "remove":
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


@dataclass(frozen=True)
class LoopResult:
    """Outcome of the residual loop.

    Attributes:
        baseline: the linear model state.
        steps: accepted steps in order.
        final: the final state.
        rounds: candidates evaluated in each round.
        structure: evidence of structure left in the final residual.
        unexplained: whether structure remains that no effect explains.
        noise_Nm: white-noise level of the final residual (N·m).
        half_range_Nm: NRMSE normaliser (N·m).
        settings: the settings used.
        search_log: every add and remove of the search, in order (the steps
            are re-derived without the removed effects when there were any).
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

    def nrmse_pct(self, state: State, sig: Signals) -> float:
        return _nrmse(state, sig, self.half_range_Nm)


def _nrmse(state: State, sig: Signals, half_range: float) -> float:
    idx = state.inliers(np.arange(sig.n))
    return nrmse_pct(state.model.residual(state.x, sig, idx), half_range)


class _Loop:
    """Working state of one run (kept private: the result is :class:`LoopResult`)."""

    def __init__(self, sig: Signals, settings: LoopSettings):
        self.sig = sig
        self.s = settings
        n = sig.n
        self.all = np.arange(n)
        stride = max(1, math.ceil(n / settings.max_cv_samples))
        self.cv = self.all[::stride]
        self.folds = (self.cv[sig.fold[self.cv] == 0], self.cv[sig.fold[self.cv] == 1])
        self.n_cv = self.cv.size
        self.cv_rate_hz = sig.scales.sample_rate_hz / stride
        self.tau = 1.0
        self.half_range = sig.scales.torque_ref

    @property
    def n_eff(self) -> float:
        """Independent held-out samples: CV samples over the noise correlation time."""
        return self.n_cv / self.tau

    @property
    def log_n(self) -> float:
        return math.log(self.n_eff)

    def update_noise(self, state: State) -> None:
        """Re-estimate the noise correlation from the residual of ``state``."""
        r = state.model.residual(state.x, self.sig, state.inliers(self.cv))
        self.tau = noise_model(r, self.cv_rate_hz).tau

    # --- fitting and scoring -------------------------------------------------
    def f_scale(self, state: State) -> float:
        r = state.model.residual(state.x, self.sig, state.inliers(self.cv))
        mad = 1.4826 * float(np.median(np.abs(r - np.median(r))))
        return 3.0 * max(mad, 1e-9 * self.half_range)

    def cv_score(self, model: TorqueModel, x0: np.ndarray, mask: np.ndarray | None,
                 f_scale: float) -> tuple[float, float]:
        """Two-fold held-out criterion and held-out RMSE (N·m).

        The mean of the two fold fits is kept in ``self.last_fit``: a close
        start for the fit on all samples.
        """
        sse, m = 0.0, 0
        fits = []
        for k in (0, 1):
            train, test = self.folds[k], self.folds[1 - k]
            if mask is not None:
                train, test = train[~mask[train]], test[~mask[test]]
            xk = model.fit(self.sig, train, fits[0] if fits else x0, f_scale)
            fits.append(xk)
            r = model.residual(xk, self.sig, test)
            sse += float(r @ r)
            m += r.size
        self.last_fit = 0.5 * (fits[0] + fits[1])
        n_masked = 0 if mask is None else int(mask[self.cv].sum())
        k_par = model.size + n_masked
        score = self.n_eff * math.log(max(sse, 1e-300) / self.n_cv) + k_par * self.log_n
        return score, math.sqrt(sse / max(m, 1))

    def refit(self, model: TorqueModel, x0: np.ndarray, mask: np.ndarray | None,
              f_scale: float) -> np.ndarray:
        idx = self.all if mask is None else self.all[~mask]
        return model.fit(self.sig, idx, x0, f_scale, max_nfev=200)

    # --- detectors -----------------------------------------------------------
    def jacobian(self, state: State, idx: np.ndarray) -> np.ndarray:
        model, x = state.model, state.x
        base = model.predict(x, self.sig, idx)
        lo, hi = model.bounds
        cols = []
        for j in range(model.size):
            h = 1e-6 * max(abs(x[j]), 1e-3 * (1.0 if not np.isfinite(hi[j] - lo[j]) else hi[j] - lo[j]))
            xp = x.copy()
            xp[j] = x[j] + h if x[j] + h <= hi[j] else x[j] - h
            cols.append((model.predict(xp, self.sig, idx) - base) / (xp[j] - x[j]))
        return np.column_stack(cols)

    def score_test(self, state: State, effect: Effect, residual: np.ndarray, jac: np.ndarray,
                   idx: np.ndarray) -> float:
        """Score-test z of ``effect``'s signature against the residual."""
        m2 = state.model.with_effect(effect)
        x_probe = m2.transfer(state.model, state.x)
        g = m2.predict(x_probe, self.sig, idx) - state.model.predict(state.x, self.sig, idx)
        coef, *_ = np.linalg.lstsq(jac, g, rcond=None)
        g_perp = g - jac @ coef
        norm = float(np.linalg.norm(g_perp))
        sigma = rmse(residual)
        if norm <= 1e-9 * float(np.linalg.norm(g)) or sigma == 0.0:
            return 0.0
        return float(g_perp @ residual) / (sigma * norm)

    # --- candidates ----------------------------------------------------------
    def try_torque_effect(self, state: State, effect: Effect, f_scale: float):
        """Best start and the cross-validated score of ``state`` plus ``effect``."""
        m2 = state.model.with_effect(effect)
        idx = state.inliers(self.cv)
        best_x, best_sse = None, np.inf
        for s in effect.starts(m2.scales):
            x_s = m2.solve_stiffness(m2.transfer(state.model, state.x, {effect.name: s}),
                                     self.sig, idx)
            r = m2.residual(x_s, self.sig, idx)
            sse = float(r @ r)
            if sse < best_sse:
                best_x, best_sse = x_s, sse
        score, heldout = self.cv_score(m2, best_x, state.mask, f_scale)
        return m2, self.last_fit, score, heldout

    def series_scores(self, state: State) -> tuple[float, float, float, float, float]:
        """Held-out criterion of the encoder channel without and with the slope.

        Returns:
            ``(score_without, score_with, z, rmse_without_rad, rmse_with_rad)``.
        """
        sig = self.sig
        e = sig.encoder - sig.theta
        tau = sig.torque
        keep = ~find_glitches(tau, self.s.glitch_threshold)
        idx = self.cv[keep[self.cv]]
        slope, offset = _line_fit(tau[idx], e[idx], True)
        r = e[idx] - offset - slope * tau[idx]
        corr = noise_model(r, self.cv_rate_hz).tau  # this channel's own noise correlation
        se = rmse(r) * math.sqrt(corr) / (float(np.std(tau[idx])) * math.sqrt(idx.size))
        z = slope / se if se > 0 else 0.0
        out = {}
        for with_slope in (False, True):
            sse, m = 0.0, 0
            for k in (0, 1):
                train, test = self.folds[k], self.folds[1 - k]
                train, test = train[keep[train]], test[keep[test]]
                coef = _line_fit(tau[train], e[train], with_slope)
                r = e[test] - (coef[1] + coef[0] * tau[test])
                sse += float(r @ r)
                m += r.size
            k_par = 2 if with_slope else 1
            m_eff = m / corr
            out[with_slope] = (m_eff * math.log(sse / m) + k_par * math.log(m_eff),
                               math.sqrt(sse / m))
        return out[False][0], out[True][0], z, out[False][1], out[True][1]

    # --- one round -----------------------------------------------------------
    def round(self, state: State, score_now: float, f_scale: float,
              allowed: set[str] | None = None):
        """Evaluate the candidates (all, or ``allowed``); return them and the proposals."""
        sig = self.sig
        idx = state.inliers(self.cv)
        residual = state.model.residual(state.x, sig, idx)
        jac = self.jacobian(state, idx)
        active = set(state.effects)
        cands, proposals = [], []
        for effect in LIBRARY:
            if effect.name in active or not effect.applicable(active, sig):
                continue
            if allowed is not None and effect.name not in allowed:
                continue
            if effect.stage == "mask":
                full_r = state.model.residual(state.x, sig, self.all)
                mask = find_glitches(full_r, self.s.glitch_threshold)
                n_glitch = int(mask.sum())
                if n_glitch == 0:
                    cands.append(Candidate(effect.name, 0.0, False))
                    continue
                score, heldout = self.cv_score(state.model, state.x, mask, f_scale)
                gain = score_now - score
                cands.append(Candidate(effect.name, float(n_glitch), True, gain, heldout))
                proposals.append((gain, effect, State(state.model, state.x, mask, state.series),
                                  float(n_glitch), heldout, 0))
                continue
            if effect.stage == "encoder":
                s0, s1, z, r0, r1 = self.series_scores(state)
                gain = s0 - s1
                fitted = abs(z) >= self.s.screen_z
                cands.append(Candidate(effect.name, z, fitted, gain if fitted else None, r1))
                if fitted:
                    keep = ~find_glitches(sig.torque, self.s.glitch_threshold)
                    coef = _line_fit(sig.torque[keep], (sig.encoder - sig.theta)[keep], True)
                    new = State(state.model, state.x, state.mask, (float(coef[0]), float(coef[1])))
                    proposals.append((gain, effect, new, z, (r0, r1), 1))
                continue
            z = self.score_test(state, effect, residual, jac, idx)
            if abs(z) < self.s.screen_z:
                cands.append(Candidate(effect.name, z, False))
                continue
            m2, x_start, score, heldout = self.try_torque_effect(state, effect, f_scale)
            gain = score_now - score
            cands.append(Candidate(effect.name, z, True, gain, heldout))
            proposals.append((gain, effect, State(m2, x_start, state.mask, state.series), z,
                              heldout, m2.size - state.model.size))
        proposals.sort(key=lambda p: -p[0])
        return cands, proposals


def _line_fit(x: np.ndarray, y: np.ndarray, with_slope: bool) -> tuple[float, float]:
    """``(slope, offset)`` of least squares ``y ≈ offset + slope·x``."""
    if not with_slope:
        return 0.0, float(np.mean(y))
    xm, ym = float(np.mean(x)), float(np.mean(y))
    dx = x - xm
    slope = float(dx @ (y - ym)) / float(dx @ dx)
    return slope, ym - slope * xm


def run_loop(sig: Signals, settings: LoopSettings = LoopSettings()) -> LoopResult:
    """Run the residual loop on one record.

    A forward search adds effects greedily; a backward pass removes effects
    made redundant by later ones. If anything was removed, the path is derived
    again, forward, over the surviving effects only, so that every reported
    step adds an effect of the final model with its own fresh evidence; the
    search itself is kept in :attr:`LoopResult.search_log`.

    Args:
        sig: signals of the segmented record.
        settings: loop settings.

    Returns:
        Baseline, steps, final model, evidence of leftover structure.
    """
    with single_threaded_blas():
        return _run_loop(sig, settings)


def _run_loop(sig: Signals, settings: LoopSettings) -> LoopResult:
    lp = _Loop(sig, settings)
    model = TorqueModel((), sig.scales)
    k_ls = float(sig.theta @ sig.torque / (sig.theta @ sig.theta))
    state = State(model, np.array([k_ls]))
    baseline = State(model, model.fit(sig, lp.all, state.x, lp.f_scale(state), max_nfev=200))
    search: list[Step] = []
    rounds: list = []
    state, score_now, f_scale = _forward(baseline, lp, search, rounds, None)
    state, score_now = _backward(state, score_now, f_scale, lp, search)
    steps = search
    if any(s.action == "remove" for s in search):
        steps, rounds = [], []
        state, score_now, f_scale = _forward(baseline, lp, steps, rounds, set(state.effects))
        # the evidence that nothing else helps: one round over the whole library
        rounds.append(tuple(lp.round(state, score_now, f_scale)[0]))
    idx = state.inliers(np.arange(sig.n))
    structure, unexplained, noise = residual_structure(
        state.model.residual(state.x, sig, idx), idx, sig, bins=settings.structure_bins,
        min_rms=settings.structure_min_rms, p_level=settings.structure_p,
        excess_ratio=settings.excess_ratio)
    log = tuple({"action": s.action, "effect": s.effect,
                 "heldout_gain": s.evidence.get("heldout_gain",
                                                -s.evidence.get("heldout_loss_when_removed", 0.0))}
                for s in search)
    return LoopResult(baseline, tuple(steps), state, tuple(rounds), structure, unexplained,
                      noise, lp.half_range, settings, log)


def _forward(state: State, lp: _Loop, steps: list[Step], rounds: list,
             allowed: set[str] | None) -> tuple[State, float, float]:
    """Add the best candidate while its evidence clears the threshold."""
    sig, settings = lp.sig, lp.s
    f_scale = lp.f_scale(state)
    lp.update_noise(state)
    score_now, heldout_now = lp.cv_score(state.model, state.x, state.mask, f_scale)
    while len(steps) < settings.max_steps:
        cands, proposals = lp.round(state, score_now, f_scale, allowed)
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
        steps.append(Step("add", effect.name, evidence, before, after,
                          _nrmse(before, sig, lp.half_range), _nrmse(after, sig, lp.half_range)))
        state = after
        f_scale = lp.f_scale(state)
        lp.update_noise(state)
        score_now, heldout_now = lp.cv_score(state.model, state.x, state.mask, f_scale)
    return state, score_now, f_scale


def _refresh_mask(state: State, lp: _Loop, f_scale: float) -> State:
    """Re-detect glitches on the new residual and refit if they changed."""
    r = state.model.residual(state.x, lp.sig, lp.all)
    mask = find_glitches(r, lp.s.glitch_threshold)
    if np.array_equal(mask, state.mask):
        return state
    x = lp.refit(state.model, state.x, mask, f_scale)
    return State(state.model, x, mask, state.series)


def _evidence(effect: Effect, z: float, gain: float, n_added: int, lp: _Loop, runner,
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


def _backward(state: State, score_now: float, f_scale: float, lp: _Loop,
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
                          _nrmse(state, sig, lp.half_range), _nrmse(after, sig, lp.half_range)))
        state = after
        score_now = score
    return state, score_now
