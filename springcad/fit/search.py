"""The search machinery of the residual loop: models, folds, scores and candidates.

:class:`Search` holds what one run of :func:`springcad.fit.loop.run_loop`
needs: the cross-validation folds (whole excursions), the noise correlation
time, robust fits on chosen samples, the held-out criterion, the detectors
(score tests) and one round of candidate evaluation. A candidate whose fitted
values are physically impossible (see ``Effect.physical_problem``), or a
series compliance with a negative stiffness, is not proposed.

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np

from springcad.fit.effects import LIBRARY, Effect, get_effect
from springcad.fit.glitches import glitch_mask
from springcad.fit.other_laws import OTHER_LAWS
from springcad.fit.inference import jacobian
from springcad.fit.models import rmse
from springcad.fit.nuisance import nuisance_views
from springcad.fit.noise import noise_model
from springcad.fit.residual import motion_locked_p
from springcad.fit.signals import Signals, find_glitches
from springcad.fit.torque_model import TorqueModel
from springcad.options import spell


#: a family's law replaces the library's when it lowers the held-out criterion by this much
#: (log-likelihood units; the laws have equally many parameters or one fewer)
LAW_MARGIN = 6.0

#: candidate note of an effect judged beside structure it cannot describe
BESIDE_STRUCTURE = "judged with the structure it cannot describe taken out"


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
        agreement_p: an effect's size must agree between the two parts of every
            split of the record at this significance level (see ``evidence``).
        support_z: and the parts together must put it this many standard
            errors away from zero.
        max_audits: most rounds of "audit the model, drop the inconsistent
            effects, search again".
        vif_confounded: variance inflation at which two effects count as not
            separable on the record, on all samples or away from the
            reversals (see ``identify``).
        spring_z: the stiffness must be this many standard errors above zero
            for the record to hold a spring at all.
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
    agreement_p: float = 1e-3
    support_z: float = 3.0
    max_audits: int = 4
    vif_confounded: float = 10.0
    spring_z: float = 5.0


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


#: why glitches are not proposed as outliers when they gather at the motion's events
LOCKED = ("far from their neighbours where the motion starts, stops or turns (timing against "
          "random draws below agreement_p, residual.motion_locked_p): the motion's doing")


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
        note: why it was not proposed (physically impossible values, glitches that follow
            the motion).
    """

    effect: str
    z: float
    fitted: bool
    gain: float | None = None
    heldout_rmse: float | None = None
    note: str | None = None

    def to_dict(self) -> dict:
        return {"effect": self.effect, "detector": self.z, "fitted": self.fitted,
                "heldout_gain": self.gain, "heldout_rmse": self.heldout_rmse, "note": self.note}


class Search:
    """Working state of one residual-loop run: the cross-validation folds, the noise
    correlation, and the fitting and scoring of candidate models."""

    def __init__(self, sig: Signals, settings: LoopSettings, keep: np.ndarray | None = None):
        self.sig = sig
        self.s = settings
        n = sig.n
        #: samples fitted and scored: all, or those outside a region of structure the
        #: library cannot describe (``keep``, see ``springcad.fit.loop``)
        self.all = np.arange(n) if keep is None else np.flatnonzero(keep)
        self.keep = keep
        #: the signals the final residual is judged on: these, or the record as measured
        #: when a nuisance was taken out of them (see ``springcad.fit.ripple``)
        self.judge = sig
        stride = max(1, math.ceil(self.all.size / settings.max_cv_samples))
        self.cv = self.all[::stride]
        self.folds = (self.cv[sig.fold[self.cv] == 0], self.cv[sig.fold[self.cv] == 1])
        self.n_cv = self.cv.size
        self.cv_rate_hz = sig.scales.sample_rate_hz / stride
        self.tau = 1.0
        self.half_range = sig.scales.torque_ref
        #: per named family, each law's model and fitted parameters from the last
        #: :func:`springcad.fit.laws.choose_laws` (for :func:`springcad.fit.laws.beyond_library`)
        self.law_fits: dict[str, dict] = {}
        #: per model effect confounded with a family outside the model, ``(model, x)`` with
        #: each of that family's laws that reads like it in its place (from
        #: :func:`springcad.fit.identify.find_confounded`)
        self.swaps: dict[str, list] = {}

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
        idx = self.all if mask is None else self.all[~mask[self.all]]
        return model.fit(self.sig, idx, x0, f_scale, max_nfev=200)

    # --- detectors -----------------------------------------------------------
    def score_test(self, state: State, effect: Effect, residual: np.ndarray, jac: np.ndarray,
                   idx: np.ndarray) -> float:
        """Score-test z of ``effect``'s signature against the residual."""
        return self._score_of(state, state.model.with_effect(effect), residual, jac, idx)

    def _score_of(self, state: State, m2: TorqueModel, residual: np.ndarray, jac: np.ndarray,
                  idx: np.ndarray) -> float:
        """Score-test z of the signature of ``m2`` (``state``'s model with effects added, at
        their probe values) against the residual."""
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
        """Best start and the cross-validated score of ``state`` plus ``effect``.

        Of its family's laws (``OTHER_LAWS``) the one proposed is the one with the
        lowest held-out criterion, when it beats the library's by ``LAW_MARGIN`` and
        its values are physically possible: a friction that fades at rest is not
        first read as a presliding friction and a lag, which then keep each other in
        the model. Whether the family enters at all is judged on the library's law,
        or on another law's criterion plus the gain threshold: a law's extra freedom
        does not carry in an effect the library's law would not add (a 0.5 ms filter
        fitted to a friction's shape). A library law whose fitted values are impossible
        gives way to the family's best possible law, which enters on its criterion plus
        the gain threshold.
        """
        best = self.try_law(state, effect, f_scale)
        m1, x1 = best[0], best[1]
        # whether ``best`` is physically possible: a library law fitted to impossible values
        # (a presliding angle on its bound, a friction that never settles) is no reading of
        # the family, its criterion does not stand, and the family is proposed with its
        # best law that is possible
        best_ok = effect.physical_problem(x1[m1.slice_of(effect.name)], float(x1[0]),
                                          m1.scales) is None
        score = best[2] if best_ok else math.inf
        for law in OTHER_LAWS.get(effect.name, ()):
            if not law.reads_alone:
                continue  # a refinement: fitted in the library law's place once named
            m2, x2, s2, heldout = self.try_law(state, law, f_scale)
            if law.physical_problem(x2[m2.slice_of(law.name)], float(x2[0]), m2.scales):
                continue
            score = min(score, s2 + self.s.gain_threshold)
            if not best_ok or s2 < best[2] - LAW_MARGIN:
                best, best_ok = (m2, x2, s2, heldout), True
        if not math.isfinite(score):
            score = best[2]  # no law is possible: the library law's note says why
        return best[0], best[1], score, best[3]

    def try_law(self, state: State, effect: Effect, f_scale: float):
        """``state`` plus ``effect`` (one law of a family) from its best start: the model,
        its held-out fit, criterion and held-out RMSE (N·m)."""
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
        slope, offset = line_fit(tau[idx], e[idx], True)
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
                coef = line_fit(tau[train], e[train], with_slope)
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
              allowed: set[str] | None = None, excluded: frozenset[str] = frozenset()):
        """Evaluate the candidates (all, or ``allowed``, never ``excluded``); return them
        and the proposals, best first."""
        sig = self.sig
        idx = state.inliers(self.cv)
        residual = state.model.residual(state.x, sig, idx)
        jac = jacobian(state.model, state.x, sig, idx)
        active = set(state.effects)
        cands, proposals, pending = [], [], []
        for effect in LIBRARY:
            if effect.name in active or not effect.applicable(active, sig):
                continue
            if (allowed is not None and effect.name not in allowed) or effect.name in excluded:
                continue
            if effect.stage == "mask":
                mask = glitch_mask(state.model, state.x, sig, self.s.glitch_threshold,
                                   self.s.agreement_p)
                n_glitch = int(mask.sum())
                if n_glitch == 0:
                    cands.append(Candidate(effect.name, 0.0, False))
                    continue
                if motion_locked_p(mask, sig) < self.s.agreement_p:
                    # glitches know nothing of the motion (an agreement test, as the audit's)
                    cands.append(Candidate(effect.name, float(n_glitch), False, note=LOCKED))
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
                note = None
                if fitted and z < 0:
                    # a compliance winds the encoder up with the torque: a falling
                    # difference is a sign convention, not a negative stiffness
                    note = ("encoder minus optical deflection falls with torque (series stiffness "
                            "would be negative): check the encoder column order "
                            f"({spell('encoder_cols')}: input, output) and sign")
                cands.append(Candidate(effect.name, z, fitted, gain if fitted else None, r1, note))
                if fitted and note is None:
                    keep = ~find_glitches(sig.torque, self.s.glitch_threshold)
                    coef = line_fit(sig.torque[keep], (sig.encoder - sig.theta)[keep], True)
                    new = State(state.model, state.x, state.mask, (float(coef[0]), float(coef[1])))
                    proposals.append((gain, effect, new, z, (r0, r1), 1))
                continue
            found = self._try(state, effect, residual, jac, idx, score_now, f_scale)
            if (found is None or found[0] <= self.s.gain_threshold) and effect.direction_signed:
                pending.append(effect)
            if found is None:
                cands.append(Candidate(effect.name, self._last_z, False))
                continue
            gain, z, m2, x_start, heldout, note = found
            cands.append(Candidate(effect.name, z, True, gain, heldout, note))
            if note is None:
                proposals.append((gain, effect, State(m2, x_start, state.mask, state.series), z,
                                  heldout, m2.size - state.model.size))
        proposals += self._pairs(state, residual, jac, idx, score_now, f_scale, allowed, excluded)
        proposals.sort(key=lambda p: -p[0])
        if pending and not (proposals and proposals[0][0] > self.s.gain_threshold):
            # nothing the record as measured asks for is left: effects that flip with the
            # direction of motion are judged beside the structure they cannot describe, with
            # it taken out (a hard stop, a zero jump; see springcad.fit.nuisance)
            late = self._beside_structure(state, pending, residual, jac, idx, f_scale, cands)
            proposals = late + proposals
        return cands, proposals

    def _pairs(self, state: State, residual: np.ndarray, jac: np.ndarray, idx: np.ndarray,
               score_now: float, f_scale: float, allowed: set[str] | None,
               excluded: frozenset[str]) -> list:
        """Proposals of an effect together with one that needs it (``Effect.needs_any``).

        An angle offset shifts a crossover off zero, and is a candidate only once a
        crossover is in the model. When the record's crossover sits off zero, the
        crossover alone at zero describes little of it (a torque offset describes more,
        and is taken), and the offset is never proposed: the pair is fitted as one
        candidate, from every start of the two, and proposed with its held-out gain less
        the gain threshold of the second effect (``n_added`` counts both), when it beats by
        the gain threshold what the second reads as beside the first at its null
        (``Effect.reads_as_alone``: an offset angle beside a vanishing asymmetry is a torque
        offset), and never when that was rejected (a torque zero that moves is no offset,
        of the torque or of a crossover). The model of the proposal holds both; the loop
        names each.
        """
        sig = self.sig
        active = set(state.effects)

        def open_(name: str) -> bool:
            return name not in excluded and (allowed is None or name in allowed)

        out = []
        for dep in LIBRARY:
            if (not dep.needs_any or dep.name in active or dep.applicable(active, sig)
                    or not open_(dep.name)):
                continue
            for pre in LIBRARY:
                if (pre.name not in dep.needs_any or pre.name in active or not open_(pre.name)
                        or pre.stage in ("mask", "encoder") or not pre.applicable(active, sig)):
                    continue
                m2 = state.model.with_effect(pre).with_effect(dep)
                z = self._score_of(state, m2, residual, jac, idx)
                if abs(z) < self.s.screen_z:
                    continue
                best_x, best_sse = None, np.inf
                for s_pre in pre.starts(m2.scales):
                    for s_dep in dep.starts(m2.scales):
                        x_s = m2.solve_stiffness(m2.transfer(state.model, state.x, {
                            pre.name: s_pre, dep.name: s_dep}), sig, idx)
                        r = m2.residual(x_s, sig, idx)
                        if float(r @ r) < best_sse:
                            best_x, best_sse = x_s, float(r @ r)
                score, heldout = self.cv_score(m2, best_x, state.mask, f_scale)
                x = self.last_fit
                if any(e.physical_problem(x[m2.slice_of(e.name)], float(x[0]), m2.scales)
                       for e in (pre, dep)):
                    continue
                if dep.reads_as_alone in excluded:
                    continue  # what it reads as was rejected: the pair would bring it back
                if dep.reads_as_alone and score > self._twin_score(
                        state, pre, get_effect(dep.reads_as_alone), f_scale) - self.s.gain_threshold:
                    continue
                out.append((score_now - score - self.s.gain_threshold, pre,
                            State(m2, x, state.mask, state.series), z, heldout,
                            m2.size - state.model.size))
        return out

    def _twin_score(self, state: State, pre: Effect, twin: Effect, f_scale: float) -> float:
        """Held-out criterion of ``state`` with ``pre`` and ``twin`` (what an effect that
        needs ``pre`` reads as with ``pre`` at its null: an angle offset beside a vanishing
        asymmetry is a torque offset), each from its best start."""
        model, x = state.model, state.x
        idx = state.inliers(self.cv)
        for e in (pre, twin):
            if e.name in model.names:
                continue
            m2 = model.with_effect(e)
            starts = [m2.solve_stiffness(m2.transfer(model, x, {e.name: s}), self.sig, idx)
                      for s in e.starts(m2.scales)]
            x = min(starts, key=lambda xs: float(np.sum(m2.residual(xs, self.sig, idx) ** 2)))
            model = m2
        return self.cv_score(model, x, state.mask, f_scale)[0]

    def _beside_structure(self, state: State, effects: list[Effect], residual: np.ndarray,
                          jac: np.ndarray, idx: np.ndarray, f_scale: float,
                          cands: list[Candidate]) -> list:
        """Proposals of ``effects`` judged on the record with the residual's structure
        they cannot describe taken out (best first); their candidates are updated."""
        views = nuisance_views(residual, idx, self.sig)
        if "direction" not in views:
            return []
        alt = self.view(views["direction"])
        now = alt.cv_score(state.model, state.x, state.mask, f_scale)[0]
        r_alt = state.model.residual(state.x, alt.sig, idx)
        out = []
        for effect in effects:
            seen = alt._try(state, effect, r_alt, jac, idx, now, f_scale)
            if seen is None or seen[-1] is not None or seen[0] <= self.s.gain_threshold:
                continue
            gain, z, m2, x_start, heldout, _ = seen
            k = next(i for i, c in enumerate(cands) if c.effect == effect.name)
            cands[k] = Candidate(effect.name, z, True, gain, heldout, BESIDE_STRUCTURE)
            out.append((gain, effect, State(m2, x_start, state.mask, state.series), z, heldout,
                        m2.size - state.model.size))
        return sorted(out, key=lambda p: -p[0])

    def _try(self, state: State, effect: Effect, residual: np.ndarray, jac: np.ndarray,
             idx: np.ndarray, score_now: float, f_scale: float):
        """Screen and cross-validate one torque-model candidate.

        Returns:
            ``None`` when screened out (``self._last_z`` holds its detector), else
            ``(gain, z, model, x_start, heldout_rmse, physical_problem)``.
        """
        z = self.score_test(state, effect, residual, jac, idx)
        self._last_z = z
        if abs(z) < self.s.screen_z:
            return None
        m2, x_start, score, heldout = self.try_torque_effect(state, effect, f_scale)
        law = next(e for e in m2.effects if e.name == effect.name)  # the law proposed
        note = law.physical_problem(x_start[m2.slice_of(law.name)], float(x_start[0]), m2.scales)
        return score_now - score, z, m2, x_start, heldout, note

    def view(self, sig: Signals) -> "Search":
        """This search on other signals (the same folds, noise correlation and scales)."""
        other = copy.copy(self)
        other.sig = sig
        return other


def line_fit(x: np.ndarray, y: np.ndarray, with_slope: bool) -> tuple[float, float]:
    """``(slope, offset)`` of least squares ``y ≈ offset + slope·x``."""
    if not with_slope:
        return 0.0, float(np.mean(y))
    xm, ym = float(np.mean(x)), float(np.mean(y))
    dx = x - xm
    slope = float(dx @ (y - ym)) / float(dx @ dx)
    return slope, ym - slope * xm
