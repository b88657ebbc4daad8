"""Library shapes beside structure in deflection the library cannot describe.

A record can hold structure in its deflection profile that no library effect
describes: torque that repeats with the motor angle (cogging), an angle
ripple, a stiffness that changed mid-test. Fitted beside it, a crossover, a
cubic or an asymmetry takes up the part of that structure that happens to
look like its own shape, and passes every other check: its held-out gain is
real (it does lower the error), and its size agrees between the parts of the
record (the structure is in every part). What tells such a patch from an
effect of the record is how much of the profile it describes against what the
profile still holds: a cubic fitted to a stiffening of 15 % describes tens of
times what a cogging ripple beside it leaves, a crossover fitted to the ripple
itself describes less than it leaves.

:func:`profile_patches` judges each effect shaped in deflection
(``Effect.deflection_shape``: backlash, stiffening, asymmetric stiffness, and the offsets
of the torque and of the angle, which a mean of the structure patches) of a final model
whose residual's deflection profile (common to both directions of motion, see
:func:`springcad.fit.nuisance.common_profile`) still stands above noise (chi-squared at
the loop's ``structure_p``, however small its RMS: the rule is relative): the
RMS of the effect's own term over that profile must be at least
``SHAPE_DOMINANCE`` times the RMS of the structure left in it (its excess over
noise), after the torque zero's motion over whole cycles is taken out (it is no
shape in deflection, see :mod:`springcad.fit.nuisance`). An effect that does not
is not named; the structure stays flagged ``unexplained`` and localised. A record the model explains (a profile within
noise) is judged as before.

Torque in N·m, deflection in rad.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from springcad.fit.inference import jacobian
from springcad.fit.nuisance import common_profile, cycle_windows, nuisance_parts
from springcad.fit.noise import noise_model
from springcad.fit.residual import residual_structure
from springcad.fit.signals import Signals
from springcad.fit.torque_model import TorqueModel

#: an effect shaped in deflection, named beside structure left in the deflection profile,
#: must describe at least this many times (RMS over the profile) what is left there
SHAPE_DOMINANCE = 3.0
#: phase bins of a held channel's update clock over which its lag is freed (the lag grows
#: from zero to one update along each; 16 leave a sawtooth of 1/16 of the update's)
HELD_PHASES = 16


def profile_patches(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                    p_level: float = 1e-6) -> dict[str, tuple[float, str]]:
    """Effects of ``model`` (parameters ``x``, judged on samples ``idx``) shaped in
    deflection that describe less of the residual's deflection profile than
    ``SHAPE_DOMINANCE`` times what it still holds (see the module docstring).

    Returns:
        ``{effect: (ratio, reason)}``, ``ratio`` the RMS of its term over that of the
        structure left (the smallest first is the worst).
    """
    shaped = [e for e in model.effects if e.deflection_shape]
    if not shaped:
        return {}
    r = model.residual(x, sig, idx)
    # the torque zero's motion over whole cycles is no shape in deflection, but it shows in
    # the profile where late cycles reach further than early ones (a zero that jumps
    # beside a staircase): taken out first, as the audit does (see fit.nuisance)
    slow = nuisance_parts(r, idx, sig, p_level)[0]
    if slow is not None:
        r = r - slow[idx]
    prof = common_profile(r, idx, sig)
    if prof is None:
        return {}
    _, common, n_eff, var_noise = prof
    ok = n_eff > 0
    w = n_eff[ok]
    energy = float(np.sum(w * common[ok] ** 2))
    if not ok.any() or stats.chi2.sf(energy / var_noise, int(ok.sum())) >= p_level:
        return {}
    left_ms = (energy - int(ok.sum()) * var_noise) / float(w.sum())
    full = model.predict(x, sig, idx)
    out = {}
    for e in shaped:
        m0 = model.without(e.name)
        term = full - m0.predict(m0.transfer(model, x), sig, idx)
        own = common_profile(term, idx, sig, var_noise=1.0)
        if own is None:
            continue
        term_ms = float(np.sum(w * own[1][ok] ** 2)) / float(w.sum())
        ratio = math.sqrt(term_ms / left_ms)
        if ratio < SHAPE_DOMINANCE:
            out[e.name] = (ratio, (
                f"the residual's deflection profile holds structure no library effect "
                f"describes ({math.sqrt(left_ms):.3g} N·m RMS), and {e.name} describes only "
                f"{ratio:.2g} times that ({math.sqrt(term_ms):.3g} N·m RMS; at least "
                f"{SHAPE_DOMINANCE:g} times is asked): it takes up a part of that structure "
                "that looks like its shape, and is not named"))
    return out


#: late-channel effects, which take up the part that follows the speed of structure the
#: library cannot describe beside them (a friction whose law the library does not have)
LAG_PATCHES = ("time_lag",)


def lag_patches(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                bins: int = 40, min_rms: float = 0.25, p_level: float = 1e-6,
                excess_ratio: float = 1.25) -> dict[str, tuple[float, str]]:
    """Late-channel effects of ``model`` that describe less than ``SHAPE_DOMINANCE`` times
    the structure the residual still holds.

    The counterpart of :func:`profile_patches` for a lag: a friction whose law the
    library does not have (a stick-slip sawtooth, whose mean over a slip period
    changes with the speed) leaves, fitted with the library's law, structure in the
    residual, and a late channel fitted beside it takes up the small part of it that
    follows the speed (a fraction of a millisecond, a fraction of the noise). A true lag
    describes many times what such structure leaves. When the residual holds structure
    (:func:`springcad.fit.residual.residual_structure` with the loop's ``bins``,
    ``min_rms``, ``p_level`` and ``excess_ratio``: the ``unexplained`` bar), a lag whose
    own term (RMS over the samples) is less than ``SHAPE_DOMINANCE`` times the largest
    structure a test finds (its RMS) is not named. A line periodic in time that the
    record holds in its holds as well (:func:`_stands_at_rest`: mains hum) is not locked
    to the motion and does not count: the lag's term is zero at rest, it takes up none of
    it (a stick-slip sawtooth slips only while the contact moves). Nor is a lag whose
    structure left is its own size changing along the record (:func:`_lag_free_per`: with
    the lag free per whole-cycle window nothing is left; clock skew), or with the phase
    of a clock (free per phase of the line whose sign follows the motion, nothing is left:
    a channel sampled and held between updates). A record the model explains is judged as
    before.

    Returns:
        ``{effect: (ratio, reason)}`` (the smallest ratio first is the worst).
    """
    lags = [e for e in model.effects if e.name in LAG_PATCHES]
    if not lags:
        return {}
    r = model.residual(x, sig, idx)
    structure, unexplained, _ = residual_structure(r, idx, sig, bins=bins, min_rms=min_rms,
                                                   p_level=p_level, excess_ratio=excess_ratio)
    found = {k: v["structure_rms_Nm"] for k, v in structure["tests"].items()
             if v.get("significant") and v.get("structure_rms_Nm", 0.0) > 0.0}
    periodic = structure["tests"]["periodic_in_time"]
    if "periodic_in_time" in found and _stands_at_rest(
            r, idx, sig, periodic["peak_frequency_hz"], structure["noise_Nm"],
            structure["noise_correlation_samples"], p_level):
        # a line the record holds at rest too (mains hum) is not locked to the motion: a
        # lag's term, zero at rest, takes up none of it
        del found["periodic_in_time"]
    if not unexplained or not found:
        return {}
    test = max(found, key=found.get)
    left = found[test]
    full = model.predict(x, sig, idx)
    out = {}
    for e in lags:
        m0 = model.without(e.name)
        term = full - m0.predict(m0.transfer(model, x), sig, idx)
        ratio = math.sqrt(float(term @ term) / term.size) / left
        if ratio < SHAPE_DOMINANCE and any(
                _lag_free_per(key, model, x, sig, idx, e, bins, min_rms, p_level, excess_ratio)
                for key in (_cycle_key(sig, idx), _held_clock_key(r, idx, sig, structure))):
            continue
        if ratio < SHAPE_DOMINANCE:
            out[e.name] = (ratio, (
                f"the residual holds structure no library effect describes ({left:.3g} N·m "
                f"RMS, {test.replace('_', ' ')}), and {e.name} describes only {ratio:.2g} "
                f"times that ({ratio * left:.3g} N·m RMS; at least {SHAPE_DOMINANCE:g} times "
                "is asked): it takes up the part of that structure that follows the speed, "
                "and is not named"))
    return out


def _cycle_key(sig: Signals, idx: np.ndarray) -> np.ndarray | None:
    """Window of whole cycles of each sample (``None``: fewer than ``MIN_WINDOWS``): the
    delay between two free-running clocks grows with the time (clock skew), a filter's
    time constant follows its temperature."""
    win = cycle_windows(sig, idx)[idx]
    return win if np.unique(win[win >= 0]).size >= MIN_WINDOWS else None


def _held_clock_key(r: np.ndarray, idx: np.ndarray, sig: Signals,
                    structure: dict) -> np.ndarray | None:
    """Phase bin (of ``HELD_PHASES``) of each sample on the clock of a line whose sign follows
    the motion (``None``: no such line stands out). A channel sampled and held between
    updates is late by the time since its last update: a lag that grows from zero to one
    update along every period of its clock, the rest of the residual a sawtooth at that
    clock (``periodic_with_direction``). The line's frequency is refined within one
    Fourier bin so that the phase holds over the record."""
    test = structure["tests"].get("periodic_with_direction", {})
    if not test.get("significant"):
        return None
    t = sig.t[idx] - sig.t[idx[0]]
    y = r * sig.direction[idx]
    bin_hz = 1.0 / max(float(t[-1]), 1e-12)
    grid = test["peak_frequency_hz"] + np.linspace(-bin_hz, bin_hz, 41)
    power = [abs(np.exp(-2j * np.pi * f * t) @ y) for f in grid]
    f = float(grid[int(np.argmax(power))])
    return np.floor((t * f) % 1.0 * HELD_PHASES).astype(int)


def _lag_free_per(key: np.ndarray | None, model: TorqueModel, x: np.ndarray, sig: Signals,
                  idx: np.ndarray, effect, bins: int, min_rms: float, p_level: float,
                  excess_ratio: float) -> bool:
    """Whether the structure left beside ``effect`` (a lag) is its own size changing with
    ``key`` (per sample of ``idx``; negative: no group): with its size free per value of
    ``key`` (one Gauss-Newton step, the rest of the model free), the residual holds no
    structure the ``unexplained`` tests find. A lag of the record that changes leaves
    structure one lag cannot describe, which is still the lag's."""
    if key is None:
        return False
    labels = np.unique(key[key >= 0])
    r = model.residual(x, sig, idx)
    J = jacobian(model, x, sig, idx)
    col = model.slice_of(effect.name).start + effect.primary
    per_group = np.column_stack([J[:, col] * (key == w) for w in labels])
    J2 = np.column_stack([per_group, np.delete(J, col, axis=1)])
    r2 = r - J2 @ np.linalg.lstsq(J2, r, rcond=None)[0]
    return not residual_structure(r2, idx, sig, bins=bins, min_rms=min_rms, p_level=p_level,
                                  excess_ratio=excess_ratio)[1]


def _stands_at_rest(r: np.ndarray, idx: np.ndarray, sig: Signals, freq_hz: float,
                    sigma: float, tau: float, p_level: float) -> bool:
    """Whether a sine at ``freq_hz`` stands in the residual ``r`` (samples ``idx``) in the
    holds of the record, beyond noise (``σ``, correlation ``τ`` samples) at ``p_level``.

    Each hold spanning at least two periods is fitted with its own mean and a sine of
    its own phase (the phase need not carry over from hold to hold, a frequency read from
    the spectrum's bin a little off would not); the chi-square of the sines' amplitudes
    against noise sums over the holds (2 degrees of freedom each).
    """
    if freq_hz <= 0.0 or sigma <= 0.0:
        return False
    rest = sig.in_hold[idx]
    t, y = sig.t[idx], r
    cuts = np.flatnonzero(np.diff(rest.astype(int)) != 0) + 1
    chi2, dof = 0.0, 0
    for seg in np.split(np.arange(idx.size), cuts):
        if not rest[seg[0]] or t[seg[-1]] - t[seg[0]] < 2.0 / freq_hz:
            continue
        w = 2.0 * np.pi * freq_hz * t[seg]
        X = np.column_stack([np.ones(seg.size), np.sin(w), np.cos(w)])
        coef, *_ = np.linalg.lstsq(X, y[seg], rcond=None)
        # a sine's coefficients over n samples of noise vary as 2·σ²·τ/n each
        chi2 += seg.size * float(coef[1] ** 2 + coef[2] ** 2) / (2.0 * sigma ** 2 * tau)
        dof += 2
    return dof > 0 and float(stats.chi2.sf(chi2, dof)) < p_level


#: an effect must keep at least this share of its size with the stiffness (or a friction's
#: level) free per whole cycle (when it does change between cycles)
KEEPS_SIZE = 0.5
#: ... unless the change is within this many of its standard errors
SIZE_CHANGE_Z = 3.0
#: fewest whole-cycle windows for the stiffness to be freed per window
MIN_WINDOWS = 3
#: effect families whose size may change along the record for a physical reason (a
#: friction's level follows the contact's temperature; a lag grows with the skew between two
#: free-running clocks), freed per window like the stiffness
CHANGING_SIZES = ("hysteresis", "time_lag")


def stiffness_patches(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                      rate_hz: float, p_level: float = 1e-6,
                      freed: tuple[str | None, ...] = (None,)) -> dict[str, tuple[float, str]]:
    """Effects of ``model`` that stand in for a stiffness (``None`` in ``freed``) or for the
    size of an effect named in ``freed`` (a friction's level) changing during the test.

    A stiffness that changes mid-test (a crack, a slip, a warming bench) on a
    protocol whose late cycles are also its large ones reads as a stiffening or a
    softening, and a change inside a cycle as friction; the record is too short for
    the evidence audit's time split. A friction whose level follows the contact's
    temperature (falling as the contact warms, faster on fast blocks) reads, fitted
    with one level, as a torque that falls with the speed: a late channel. Here the
    stiffness (or the size of ``freed``) is freed per window of whole
    cycles (:func:`springcad.fit.nuisance.cycle_windows`), one Gauss-Newton step from
    the fitted ``x`` on samples ``idx`` (sampled at ``rate_hz``). When the windows'
    values differ beyond noise (chi-squared at ``p_level``), every other effect must
    keep at least ``KEEPS_SIZE`` of its size there (or change by less than
    ``SIZE_CHANGE_Z`` standard errors): an effect of the record does not depend on the
    stiffness or the friction being one number, a patch over its change loses most of
    its size.

    Returns:
        ``{effect: (share kept, reason)}`` for the effects that fail, for the first of
        ``freed`` that finds any (one Jacobian for all).
    """
    win = cycle_windows(sig, idx)[idx]
    labels = np.unique(win[win >= 0])
    if labels.size < MIN_WINDOWS or not model.effects:
        return {}
    r = model.residual(x, sig, idx)
    J = jacobian(model, x, sig, idx)
    d1 = np.linalg.lstsq(J, r, rcond=None)[0]
    r1 = r - J @ d1
    for name in freed:
        if name is None:
            col, what = 0, "the stiffness"
        else:
            e_freed = next((e for e in model.effects if e.name == name), None)
            if e_freed is None:
                continue
            col = model.slice_of(name).start + e_freed.primary
            what = f"{name}'s {e_freed.params(model.scales)[e_freed.primary].name}"
        out = _freed_per_window(model, x, J, r, r1, win, labels, col, what, rate_hz, p_level)
        if out:
            return out
    return {}


def _freed_per_window(model: TorqueModel, x: np.ndarray, J: np.ndarray, r: np.ndarray,
                      r1: np.ndarray, win: np.ndarray, labels: np.ndarray, col: int, what: str,
                      rate_hz: float, p_level: float) -> dict[str, tuple[float, str]]:
    """:func:`stiffness_patches` with the parameter in column ``col`` of the Jacobian ``J``
    (residual ``r``, ``r1`` after one Gauss-Newton step) free per window ``win``."""
    per_window = np.column_stack([J[:, col] * (win == w) for w in labels])
    rest = [c for c in range(J.shape[1]) if c != col]
    J2 = np.column_stack([per_window, J[:, rest]])
    d2 = np.linalg.lstsq(J2, r, rcond=None)[0]
    r2 = r - J2 @ d2
    nm = noise_model(r2, rate_hz)
    var = float(r2 @ r2) / max(r2.size - J2.shape[1], 1) * nm.tau
    if var <= 0.0:
        return {}
    chi2 = (float(r1 @ r1) - float(r2 @ r2)) / var
    if stats.chi2.sf(chi2, labels.size - 1) >= p_level:
        return {}
    cov = np.linalg.pinv(J2.T @ J2) * var
    out = {}
    for e in model.effects:
        j = model.slice_of(e.name).start + e.primary
        if j == col:
            continue
        j2 = labels.size + rest.index(j)
        null = e.params(model.scales)[e.primary].null
        now, freed_value = float(x[j]) - null, float(x[j] + d2[j2]) - null
        se = math.sqrt(max(float(cov[j2, j2]), 0.0))
        kept = freed_value / now if now != 0.0 else 1.0
        if kept < KEEPS_SIZE and abs(freed_value - now) > SIZE_CHANGE_Z * se:
            q = e.params(model.scales)[e.primary].name
            out[e.name] = (kept, (
                f"{what} differs between whole cycles of the record beyond noise "
                f"(chi-squared {chi2:.3g} on {labels.size - 1} degrees of freedom), and with it "
                f"free per cycle {e.name} keeps {100 * kept:.0f} % of its size ({q} "
                f"{now + null:.4g} -> {freed_value + null:.4g} ± {se:.2g}): it stands in for "
                f"{what} changing during the test, and is not named"))
    return out


#: the offsets (of the torque and of the angle): what they claim is the torque read at zero
#: deflection, so that is where the record must show them
OFFSETS = ("torque_offset", "angle_offset")
#: half-width of the band about zero deflection, as a share of the largest |deflection|
ZERO_BAND = 0.15
#: an offset is a patch where the record shows less than this share of it at zero deflection
ZERO_SHARE = 0.5
#: both offsets together must claim at zero at least this share of what each claims alone
CANCEL_SHARE = 0.25
#: fewest runs (stretches between reversals) crossing that band for the check to apply
MIN_ZERO_RUNS = 4


def offset_patches(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                   agreement_p: float = 1e-3, support_z: float = 3.0
                   ) -> dict[str, tuple[float, str]]:
    """Offsets of ``model`` (parameters ``x``, samples ``idx``) that the record does not show
    at zero deflection.

    A torque offset is the torque read at zero deflection, an angle offset the
    deflection at which the spring's torque is zero: near zero deflection (within
    ``ZERO_BAND`` of the largest |deflection|, where the shapes of stiffness vanish)
    the record shows either in full. An offset fitted as a patch for a shape the
    library cannot describe (a torque sensor whose gain grows with the torque,
    ``T·(1 + a·T)``: even in deflection, zero at zero) takes up the mean of that shape
    over the whole range, where there is none at zero. Each offset's term ``d`` (the
    model less the model with that offset at its null) is set against what the record
    holds at zero deflection: the residual of the model without it, ``r + d``, is
    regressed over the band's samples on ``d`` and on a local slope in deflection, odd
    and even (``θ`` and ``|θ|``: the rest of a shape, fitted or not, that runs through
    zero); the coefficient ``β`` of ``d`` is the share of the offset the record shows
    at zero (1: in full, 0: not at all; a band's plain mean would read the slope of a
    shape beside it as an offset), with a standard error clustered on the runs crossing
    the band (a structure the model misses near zero, friction that flips with the
    direction, spreads the runs and widens it). A true offset beside structure the
    library cannot describe is fitted short or long of its value (the structure's mean
    takes a part), but the record shows most of it at zero; an offset the record does
    not show there (``β`` less than ``support_z`` standard errors above zero, the
    evidence audit's bar of support) or shows less than ``ZERO_SHARE`` of (one-sided
    Student t over the runs at ``agreement_p``) is a patch. Both offsets together must claim at zero at least
    ``CANCEL_SHARE`` of what each claims alone: a torque offset that cancels an angle
    offset there moves only a kink or a crossover off zero (each alone then reads as
    shown in full); the angle offset goes first and the torque offset is judged alone
    on the refit.

    Returns:
        ``{effect: (t, reason)}`` for the offsets that fail, ``t`` that of
        ``β - ZERO_SHARE`` (the smallest is the worst).
    """
    present = [e for e in model.effects if e.name in OFFSETS]
    if not present:
        return {}
    theta = sig.theta_smooth[idx]
    band = np.abs(theta) <= ZERO_BAND * float(np.max(np.abs(theta)))
    runs = sig.runs[idx][band]
    labels, inv = np.unique(runs, return_inverse=True)
    if labels.size < MIN_ZERO_RUNS:
        return {}
    near = idx[band]
    r = model.residual(x, sig, near)
    full = model.predict(x, sig, near)
    slope = np.column_stack([theta[band], np.abs(theta[band])])
    n = labels.size
    out = {}
    terms = {}
    for e in present:
        terms[e.name] = full - model.predict(_nulled(model, x, (e.name,)), sig, near)
    if len(present) > 1:
        both = full - model.predict(_nulled(model, x, OFFSETS), sig, near)
        claim = math.sqrt(float(both @ both) / both.size)
        alone = min(math.sqrt(float(d @ d) / d.size) for d in terms.values())
        if claim < CANCEL_SHARE * alone:
            return {"angle_offset": (-math.inf, (
                f"torque_offset and angle_offset claim {alone:.3g} N·m or more each at zero "
                f"deflection but {claim:.3g} N·m together: they cancel there and only move a "
                "kink or a crossover off zero; angle_offset is not named (the torque offset "
                "is judged alone once refitted)"))}
    for e in present:
        d = terms[e.name]
        X = np.column_stack([d, slope])
        xtx_inv = np.linalg.pinv(X.T @ X)
        coef = xtx_inv @ (X.T @ (r + d))
        score = X * (r + d - X @ coef)[:, None]
        per_run = np.column_stack([np.bincount(inv, weights=c, minlength=n) for c in score.T])
        cov = xtx_inv @ (per_run.T @ per_run) @ xtx_inv * n / (n - 1)
        beta, se = float(coef[0]), math.sqrt(max(float(cov[0, 0]), 0.0))
        if se <= 0.0 or not math.isfinite(beta):
            continue
        t = (beta - ZERO_SHARE) / se
        if beta >= support_z * se and stats.t.cdf(t, n - 1) >= agreement_p:
            continue
        out[e.name] = (t, (
            f"{e.name} claims {float(np.sqrt(d @ d / d.size)):.3g} N·m RMS at zero deflection "
            f"(|deflection| within {100 * ZERO_BAND:g} % of its largest), where the record "
            f"shows {100 * beta:.0f} % ± {100 * se:.0f} % of it ({n} runs): it takes up the "
            "mean of a shape over the whole range, not a zero, and is not named"))
    return out


def _nulled(model: TorqueModel, x: np.ndarray, names: tuple[str, ...]) -> np.ndarray:
    """``x`` with the size parameters of the effects ``names`` at their null values."""
    x0 = x.copy()
    for e in model.effects:
        if e.name in names:
            x0[model.slice_of(e.name).start + e.primary] = e.params(model.scales)[e.primary].null
    return x0
