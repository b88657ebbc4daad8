"""Parameter uncertainty of a fitted torque model: covariance, confidence intervals, Wald tests.

The covariance is the leave-one-run-out jackknife of the least-squares fit,
clustered on runs (the stretches between reversals of the motion)::

    C = (G-1)/G · Σ_c (d_c - d̄)(d_c - d̄)ᵀ,   d_c = (A - A_c)⁻¹ s_c,
    A = JᵀJ,   A_c = J_cᵀJ_c,   s_c = J_cᵀ r_c

with ``J`` the Jacobian of the model torque and ``r`` the residual; ``d_c`` is
how far the parameters move when run ``c`` is left out (exact for the
linearised fit). It stays honest when the residual holds more than white
noise (correlated sensor noise, or structure no effect describes): then the
runs disagree and the intervals widen. Unlike the plain sandwich
``A⁻¹ (Σ s_c s_cᵀ) A⁻¹`` it also stays honest when a few runs carry most of
what is known of a parameter (the fastest sweep for a time lag): a run's own
score shrinks where it pulls the fit towards itself, and leaving it out
undoes that (the plain sandwich covered a lag 82 % of the time on sine
sweeps where this covers 92 %, ``bench/fit_coverage.py --heldout``). Its
diagonal is floored at the model-based variance ``s²·τ·A⁻¹`` (``τ`` the noise
correlation time in samples), so a lucky agreement between few runs cannot
shrink an interval below what the noise alone allows. Intervals use Student's
t with ``G - 1`` degrees of freedom.

Torque in N·m; parameters in the units of the torque model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from springcad.fit.noise import noise_model
from springcad.fit.signals import Signals
from springcad.fit.torque_model import TorqueModel

#: confidence level of every reported interval
CONFIDENCE = 0.95


def jacobian(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
    """Forward-difference Jacobian (N·m per parameter unit) of the model torque at ``idx``.

    Steps go inward at an upper bound, so a parameter resting on a bound
    still gets its sensitivity.
    """
    base = model.predict(x, sig, idx)
    lo, hi = model.bounds
    cols = []
    for j in range(model.size):
        span = hi[j] - lo[j]
        h = 1e-6 * max(abs(x[j]), 1e-3 * (1.0 if not np.isfinite(span) else span))
        xp = x.copy()
        xp[j] = x[j] + h if x[j] + h <= hi[j] else x[j] - h
        cols.append((model.predict(xp, sig, idx) - base) / (xp[j] - x[j]))
    return np.column_stack(cols)


@dataclass(frozen=True)
class Uncertainty:
    """Covariance of a model's parameters on one set of samples.

    Attributes:
        cov: covariance (parameter units squared), clustered and floored.
        dof: degrees of freedom of the t reference (clusters - 1).
        n_clusters: runs that held samples.
        rank_deficient: the Jacobian did not have full column rank (some
            parameter combination is not determined by the samples).
    """

    cov: np.ndarray
    dof: int
    n_clusters: int
    rank_deficient: bool = False

    @property
    def se(self) -> np.ndarray:
        return np.sqrt(np.maximum(np.diag(self.cov), 0.0))

    def t_quantile(self, level: float = CONFIDENCE) -> float:
        return float(stats.t.ppf(0.5 + 0.5 * level, max(self.dof, 1)))

    def wald_p(self, d: np.ndarray, sel: list[int] | np.ndarray, extra_cov=None) -> float:
        """p-value of ``d`` (values of parameters ``sel``) against zero."""
        c = self.cov[np.ix_(sel, sel)]
        if extra_cov is not None:
            c = c + extra_cov
        return wald_p(np.asarray(d, float), c, self.dof)


def wald_p(d: np.ndarray, cov: np.ndarray, dof: int) -> float:
    """p-value of the Wald statistic ``dᵀ C⁻¹ d`` (F with ``q`` and ``dof`` degrees of freedom)."""
    q = d.size
    if q == 0:
        return 1.0
    w = float(d @ np.linalg.pinv(cov, rcond=1e-12) @ d)
    if not math.isfinite(w):
        return 0.0
    return float(stats.f.sf(w / q, q, max(dof, 1)))


def uncertainty(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                jac: np.ndarray | None = None, sample_rate_hz: float | None = None) -> Uncertainty:
    """Clustered sandwich covariance of ``x`` fitted on samples ``idx`` (see module docstring).

    Args:
        model: the torque model.
        x: its fitted parameters.
        sig: record signals.
        idx: the samples the parameters were fitted on (sorted).
        jac: the Jacobian at ``idx`` if already computed.
        sample_rate_hz: rate of ``idx`` (for the noise correlation; default:
            the record rate over the median index step).
    """
    J = jacobian(model, x, sig, idx) if jac is None else jac
    r = model.residual(x, sig, idx)
    return sandwich(J, r, sig.runs[idx], sample_rate_hz or _rate(sig, idx))


def sandwich(J: np.ndarray, r: np.ndarray, clusters: np.ndarray,
             sample_rate_hz: float) -> Uncertainty:
    """Clustered jackknife covariance of a least-squares fit with Jacobian ``J``, residual ``r``
    (see module docstring), floored at the model-based variance."""
    n, p = J.shape
    scale = np.sqrt(np.sum(J * J, axis=0))
    scale[scale == 0] = 1.0
    Js = J / scale
    u, s, vt = np.linalg.svd(Js, full_matrices=False)
    tol = s[0] * 1e-10 if s.size else 0.0
    keep = s > tol
    a_inv = (vt[keep].T / s[keep] ** 2) @ vt[keep]
    labels, inv = np.unique(clusters, return_inverse=True)
    g = labels.size
    scores = np.column_stack([np.bincount(inv, weights=Js[:, i] * r, minlength=g)
                              for i in range(p)]).reshape(g, p)
    grams = np.zeros((g, p, p))
    for i in range(p):
        for j in range(i, p):
            grams[:, i, j] = grams[:, j, i] = np.bincount(inv, weights=Js[:, i] * Js[:, j],
                                                          minlength=g)
    left_out = (Js.T @ Js)[None, :, :] - grams
    moves = np.einsum("cij,cj->ci", np.linalg.pinv(left_out, rcond=1e-10, hermitian=True), scores)
    moves -= moves.mean(axis=0)
    c_rob = ((g - 1) / max(g, 1)) * (moves.T @ moves) / np.outer(scale, scale)
    a_inv = a_inv / np.outer(scale, scale)
    nm = noise_model(r, sample_rate_hz)
    s2 = float(r @ r) / max(n - p, 1)
    c_mod = s2 * nm.tau * a_inv
    floor = np.maximum(np.diag(c_mod) - np.diag(c_rob), 0.0)
    return Uncertainty(c_rob + np.diag(floor), g - 1, g, bool(not keep.all()))


def _rate(sig: Signals, idx: np.ndarray) -> float:
    step = float(np.median(np.diff(idx))) if idx.size > 1 else 1.0
    return sig.scales.sample_rate_hz / max(step, 1.0)


def interval(value: float, se: float, t: float, lower: float = -math.inf,
             upper: float = math.inf) -> tuple[float, float]:
    """``value ± t·se`` clipped to ``[lower, upper]``."""
    return max(value - t * se, lower), min(value + t * se, upper)


def report_intervals(model: TorqueModel, x: np.ndarray, unc: Uncertainty,
                     level: float = CONFIDENCE) -> dict[str, dict]:
    """Confidence interval of every reported quantity (delta method on ``model.report``).

    Returns:
        ``{name: {"value", "ci_low", "ci_high", "se", "at_bound"}}`` for each key of
        ``model.report(x)``; ``at_bound`` is True when a parameter the quantity
        depends on rests on its bound (the interval is then one-sided at best).
        A quantity of one parameter has its interval clipped to what that
        parameter's bounds allow (a friction torque or a transition is never
        negative).
    """
    base = model.report(x)
    lo, hi = model.bounds
    grads = {k: np.zeros(model.size) for k in base}
    for j in range(model.size):
        span = hi[j] - lo[j]
        h = 1e-6 * max(abs(x[j]), 1e-3 * (1.0 if not np.isfinite(span) else span))
        xp = x.copy()
        xp[j] = x[j] + h if x[j] + h <= hi[j] else x[j] - h
        moved = model.report(xp)
        for k in base:
            grads[k][j] = (moved[k] - base[k]) / (xp[j] - x[j])
    span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x) + 1.0)
    on_bound = (x - lo <= 1e-6 * span) | (hi - x <= 1e-6 * span)
    t = unc.t_quantile(level)
    out = {}
    for k, v in base.items():
        g = grads[k]
        se = float(math.sqrt(max(g @ unc.cov @ g, 0.0)))
        at_bound = bool(np.any(on_bound & (g != 0)))
        low, high = v - t * se, v + t * se
        moved = np.flatnonzero(g != 0)
        if moved.size == 1:  # a quantity of one parameter stays within its bounds
            j = int(moved[0])
            ends = []
            for bound in (lo[j], hi[j]):
                if np.isfinite(bound):
                    xb = x.copy()
                    xb[j] = bound
                    ends.append(model.report(xb)[k])
            if ends:
                if g[j] > 0:
                    low = max(low, ends[0]) if np.isfinite(lo[j]) else low
                    high = min(high, ends[-1]) if np.isfinite(hi[j]) else high
                else:
                    high = min(high, ends[0]) if np.isfinite(lo[j]) else high
                    low = max(low, ends[-1]) if np.isfinite(hi[j]) else low
        out[k] = {"value": float(v), "ci_low": float(low), "ci_high": float(high), "se": se,
                  "at_bound": at_bound}
    return out
