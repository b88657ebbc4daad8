"""Structure an effect cannot describe, taken out before the effect is judged.

A record with structure outside the library (a hard stop, a zero that jumps,
a part that changes mid-test) still holds the library effects beside it; but
measured against a residual dominated by that structure, a true friction is
lost in it (its detector divides by the whole residual, its held-out gain is a
small share of a large error, its clustered standard errors take in the
structure) and is neither found nor kept. Each effect is therefore judged on
the record with the part of the residual removed that its signature is blind
to:

* **slow torque changes** (``slow``): the residual's mean over windows of
  whole cycles (deflection beyond half the window's largest value on both sides
  of zero). Friction, a crossover, stiffening and a lag average out over a
  whole cycle; a zero that jumps or wanders does not. Taken out for every
  effect that is not itself a torque of time (offset, drift).
* **the deflection profile common to both directions** (``profile``): the
  residual's mean in bins of deflection, averaged over the two directions of
  motion. Friction and a late channel flip with the direction and cancel in
  it; a hard stop, a ripple in angle, a crossover, stiffening do not. Taken
  out, besides the slow changes, for effects that follow the direction of
  motion.

Either part is removed only when it stands above noise (chi-squared against
the residual's noise level and correlation, at ``p_level``), so a record the
model explains is judged as measured.

Torque in N·m, deflection in rad.
"""

from __future__ import annotations


import numpy as np
from scipy import stats

from springcad.fit.noise import noise_model
from springcad.fit.signals import Signals

#: effects that are torques of time: judged on the record as measured
TIME_EFFECTS = ("torque_offset", "drift")

#: fewest whole-cycle windows for the slow part to be told from the effects
MIN_WINDOWS = 4

#: least RMS of a part, in noise levels, for it to be taken out (``structure_min_rms``)
MIN_RMS = 0.25

#: rounds of alternating between the slow part and the profile
BACKFIT_ROUNDS = 5

#: deflection bins of the common profile
PROFILE_BINS = 128


def nuisance_kind(effect) -> str:
    """``"none"``, ``"slow"`` or ``"direction"``: which view of the record judges ``effect``."""
    if effect.name in TIME_EFFECTS:
        return "none"
    return "direction" if effect.direction_signed else "slow"


def cycle_windows(sig: Signals, idx: np.ndarray) -> np.ndarray:
    """Per-sample window number (-1 where no run of ``idx`` lies): consecutive runs
    grouped until a window holds a whole cycle."""
    runs = sig.runs
    labels, inv = np.unique(runs[idx], return_inverse=True)
    th = sig.theta_smooth[idx]
    hi = np.full(labels.size, -np.inf)
    lo = np.full(labels.size, np.inf)
    np.maximum.at(hi, inv, th)
    np.minimum.at(lo, inv, th)
    window = np.zeros(labels.size, dtype=int)
    w, top, bottom = 0, 0.0, 0.0
    for k in range(labels.size):
        window[k] = w
        top, bottom = max(top, hi[k]), min(bottom, lo[k])
        big = max(top, -bottom)
        if big > 0 and top > 0.5 * big and bottom < -0.5 * big:
            w, top, bottom = w + 1, 0.0, 0.0
    if w > 0 and window[-1] == w:  # an unfinished last window joins the one before
        window[window == w] = w - 1
    lookup = np.full(int(runs.max()) + 1, -1, dtype=int)
    lookup[labels] = window
    return lookup[runs]


def significant_means(means: np.ndarray, counts: np.ndarray, var_noise: float,
                      p_level: float) -> bool:
    """Whether bin means stand above noise: significant at ``p_level`` and of an RMS
    of ``MIN_RMS`` noise levels at least (the rule that flags a residual unexplained)."""
    ok = counts > 0
    if var_noise <= 0.0 or not ok.any():
        return False
    energy = float(np.sum(counts[ok] * means[ok] ** 2))
    excess = (energy - int(ok.sum()) * var_noise) / float(np.sum(counts[ok]))
    return bool(stats.chi2.sf(energy / var_noise, int(ok.sum())) < p_level
                and excess > MIN_RMS ** 2 * var_noise)


def slow_part(r: np.ndarray, idx: np.ndarray, sig: Signals, var_noise: float,
              p_level: float) -> np.ndarray | None:
    """The residual's mean over each whole-cycle window (N·m, every sample), or ``None``."""
    win_all = cycle_windows(sig, idx)
    win = win_all[idx]
    n_win = int(win.max()) + 1 if win.size else 0
    if n_win < MIN_WINDOWS:
        return None
    cnt = np.bincount(win, minlength=n_win).astype(float)
    mean = np.bincount(win, weights=r, minlength=n_win) / np.maximum(cnt, 1.0)
    if not significant_means(mean, cnt, var_noise, p_level):
        return None
    return np.where(win_all >= 0, mean[np.maximum(win_all, 0)], 0.0)


def common_profile(r: np.ndarray, idx: np.ndarray, sig: Signals, bins: int = PROFILE_BINS,
                   var_noise: float | None = None):
    """The residual's mean in bins of deflection, averaged over the two directions.

    Returns:
        ``(centre_rad, common_Nm, n_eff, var_noise)`` per bin (``n_eff`` 0 where a
        bin is visited in one direction only: a turn's own bin), with
        ``var_noise`` the variance of one sample's noise times its correlation
        time, or ``None`` when the residual has no noise to compare with.
    """
    if var_noise is None:
        nm = noise_model(r, sig.scales.sample_rate_hz / max(float(np.median(np.diff(idx))), 1.0))
        var_noise = nm.sigma ** 2 * nm.tau
    if var_noise <= 0.0:
        return None
    theta = sig.theta_smooth
    edges = np.linspace(theta[idx].min(), theta[idx].max(), bins + 1)
    b = np.clip(np.searchsorted(edges, theta[idx], side="right") - 1, 0, bins - 1)
    up = sig.direction[idx] > 0
    means, counts = [], []
    for sel in (up, ~up):
        c = np.bincount(b[sel], minlength=bins).astype(float)
        means.append(np.bincount(b[sel], weights=r[sel], minlength=bins) / np.maximum(c, 1.0))
        counts.append(c)
    both = (counts[0] > 0) & (counts[1] > 0)
    common = np.where(both, 0.5 * (means[0] + means[1]), 0.0)
    # a mean of two direction means: its noise variance is a quarter of the sum of theirs
    n_eff = np.where(both, 4.0 / (1.0 / np.maximum(counts[0], 1) + 1.0 / np.maximum(counts[1], 1)),
                     0.0)
    return 0.5 * (edges[1:] + edges[:-1]), common, n_eff, var_noise


def profile_part(r: np.ndarray, idx: np.ndarray, sig: Signals, var_noise: float,
                 p_level: float, bins: int = PROFILE_BINS) -> np.ndarray | None:
    """The residual's deflection profile common to both directions (N·m, every sample),
    or ``None`` when it is within noise."""
    centre, common, n_eff, _ = common_profile(r, idx, sig, bins, var_noise)
    both = n_eff > 0
    if not significant_means(common, n_eff, var_noise, p_level):
        return None
    # piecewise linear through the bin centres: a steep profile (a hard stop) changes a
    # lot within one bin
    return np.interp(sig.theta_smooth, centre[both], common[both])


def nuisance_parts(r: np.ndarray, idx: np.ndarray, sig: Signals, p_level: float = 1e-6
                   ) -> tuple[np.ndarray | None, np.ndarray | None, float]:
    """The slow part and the common deflection profile of residual ``r`` (see module docstring).

    Args:
        r: residual (N·m) of the current model at samples ``idx``.
        idx: sample indices (glitches excluded), sorted.
        sig: record signals.
        p_level: significance a part must reach to be kept.

    Returns:
        ``(slow, profile, var_noise)``: each part (N·m, every sample) or ``None`` when
        it is within noise, and the noise variance they were judged against
        (N·m², one sample's variance times its correlation time).
    """
    rate = sig.scales.sample_rate_hz / max(float(np.median(np.diff(idx))), 1.0)
    nm = noise_model(r, rate)
    var_noise = nm.sigma ** 2 * nm.tau
    if var_noise <= 0.0:
        return None, None, var_noise
    # the two parts are not orthogonal (a window of runs holds more of one side of a hard
    # stop than of the other; a zero jump has a mean over deflection): fitted jointly by
    # alternating between them (backfitting)
    slow = profile = None
    for _ in range(BACKFIT_ROUNDS):
        slow = slow_part(r if profile is None else r - profile[idx], idx, sig, var_noise, p_level)
        profile = profile_part(r if slow is None else r - slow[idx], idx, sig, var_noise,
                               p_level)
        if slow is None or profile is None:
            break
    return slow, profile, var_noise


def nuisance_views(r: np.ndarray, idx: np.ndarray, sig: Signals,
                   p_level: float = 1e-6) -> dict[str, Signals]:
    """The record as each kind of effect judges it (see module docstring).

    Args:
        r: residual (N·m) of the current model at samples ``idx``.
        idx: sample indices (glitches excluded), sorted.
        sig: record signals.
        p_level: significance a part must reach to be taken out.

    Returns:
        ``{"slow": ..., "direction": ...}`` signals with the torque cleaned, for
        the kinds whose nuisance stands above noise (a missing kind: judge on
        ``sig`` as measured).
    """
    slow, profile, _ = nuisance_parts(r, idx, sig, p_level)
    return views_without(sig, slow, profile)


def views_without(sig: Signals, slow: np.ndarray | None,
                  profile: np.ndarray | None) -> dict[str, Signals]:
    """:func:`nuisance_views` from parts already found by :func:`nuisance_parts`."""
    out: dict[str, Signals] = {}
    if slow is not None:
        out["slow"] = sig.with_torque(sig.torque - slow)
    if slow is not None or profile is not None:
        total = (0.0 if slow is None else slow) + (0.0 if profile is None else profile)
        out["direction"] = sig.with_torque(sig.torque - total)
    return out
