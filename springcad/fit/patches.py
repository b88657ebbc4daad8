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
from springcad.fit.residual import noise_model
from springcad.fit.signals import Signals
from springcad.fit.torque_model import TorqueModel

#: an effect shaped in deflection, named beside structure left in the deflection profile,
#: must describe at least this many times (RMS over the profile) what is left there
SHAPE_DOMINANCE = 3.0


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


#: an effect must keep at least this share of its size with the stiffness free per whole
#: cycle (when the stiffness does change between cycles)
KEEPS_SIZE = 0.5
#: ... unless the change is within this many of its standard errors
SIZE_CHANGE_Z = 3.0
#: fewest whole-cycle windows for the stiffness to be freed per window
MIN_WINDOWS = 3


def stiffness_patches(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                      rate_hz: float, p_level: float = 1e-6) -> dict[str, tuple[float, str]]:
    """Effects of ``model`` that stand in for a stiffness changing during the test.

    A stiffness that changes mid-test (a crack, a slip, a warming bench) on a
    protocol whose late cycles are also its large ones reads as a stiffening or a
    softening, and a change inside a cycle as friction; the record is too short for
    the evidence audit's time split. Here the stiffness is freed per window of whole
    cycles (:func:`springcad.fit.nuisance.cycle_windows`), one Gauss-Newton step from
    the fitted ``x`` on samples ``idx`` (sampled at ``rate_hz``). When the windows'
    stiffnesses differ beyond noise (chi-squared at ``p_level``), every effect must
    keep at least ``KEEPS_SIZE`` of its size there (or change by less than
    ``SIZE_CHANGE_Z`` standard errors): an effect of the record does not depend on the
    stiffness being one number, a patch over its change loses most of its size.

    Returns:
        ``{effect: (share kept, reason)}`` for the effects that fail.
    """
    win = cycle_windows(sig, idx)[idx]
    labels = np.unique(win[win >= 0])
    if labels.size < MIN_WINDOWS or not model.effects:
        return {}
    r = model.residual(x, sig, idx)
    J = jacobian(model, x, sig, idx)
    per_window = np.column_stack([J[:, 0] * (win == w) for w in labels])
    J2 = np.column_stack([per_window, J[:, 1:]])
    d1 = np.linalg.lstsq(J, r, rcond=None)[0]
    d2 = np.linalg.lstsq(J2, r, rcond=None)[0]
    r1, r2 = r - J @ d1, r - J2 @ d2
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
        j2 = j - 1 + labels.size
        null = e.params(model.scales)[e.primary].null
        now, freed = float(x[j]) - null, float(x[j] + d2[j2]) - null
        se = math.sqrt(max(float(cov[j2, j2]), 0.0))
        kept = freed / now if now != 0.0 else 1.0
        if kept < KEEPS_SIZE and abs(freed - now) > SIZE_CHANGE_Z * se:
            q = e.params(model.scales)[e.primary].name
            out[e.name] = (kept, (
                f"the stiffness differs between whole cycles of the record beyond noise "
                f"(chi-squared {chi2:.3g} on {labels.size - 1} degrees of freedom), and with it "
                f"free per cycle {e.name} keeps {100 * kept:.0f} % of its size ({q} "
                f"{now + null:.4g} -> {freed + null:.4g} ± {se:.2g}): it stands in for a "
                "stiffness that changed during the test, and is not named"))
    return out
