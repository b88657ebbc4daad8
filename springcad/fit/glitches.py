"""Which samples of a record are glitches, given a model: turns and steps guarded.

A model whose direction-following terms (a friction) switch at a turn, placed a
sample early or late, leaves a residual swing there for its own reasons; these
functions guard such samples so that :func:`springcad.fit.signals.find_glitches`
does not take them for spikes (used by the search's ``outliers`` candidate and by
the loop's final mask).

Torque in N·m, angles in rad, time in s.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d

from springcad.fit.residual import motion_locked_p
from springcad.fit.signals import Signals, find_glitches
from springcad.fit.torque_model import TorqueModel


def turn_guard(model: TorqueModel, x: np.ndarray, sig: Signals) -> np.ndarray:
    """Samples where the residual may swing at a turn (``Signals.near_turn``), also as
    late as the model makes the torque channel: with a 30 ms lag the torque turns 30 ms
    after the deflection, and so do the residual's swings there."""
    guard = sig.near_turn | _term_steps(model, x, sig)
    shift = sum(e.time_shift_s(x[model.slice_of(e.name)]) for e in model.effects)
    k = int(round(shift * sig.scales.sample_rate_hz))
    if k == 0 or abs(k) >= sig.n:
        return guard
    late = np.zeros_like(guard)
    if k > 0:
        late[k:] = guard[:-k]
    else:
        late[:k] = guard[-k:]
    return guard | late


def glitch_mask(model: TorqueModel, x: np.ndarray, sig: Signals, threshold: float,
                agreement_p: float) -> np.ndarray:
    """Samples of the record (every sample) the residual of ``model`` holds as glitches.

    :func:`springcad.fit.signals.find_glitches` with the model's turns guarded
    (:func:`turn_guard`, :func:`direction_terms`). Where the residual's excursions beyond
    ``threshold`` (guarded or not) gather at the motion's events
    (:func:`springcad.fit.residual.motion_locked_p` below ``agreement_p``), the model errs
    at its turns (a friction whose law switches sharper than the model's, within a sample
    or two): a spike among those errors cannot be told from them, and no guarded sample is
    a glitch; glitches elsewhere still are.
    """
    r = model.residual(x, sig, np.arange(sig.n))
    guard = turn_guard(model, x, sig)
    mask = find_glitches(r, threshold, guard=guard, model=direction_terms(model, x, sig))
    if mask.any() and (mask & guard).any():
        if motion_locked_p(find_glitches(r, threshold), sig) < agreement_p:
            mask &= ~guard
    return mask


def direction_terms(model: TorqueModel, x: np.ndarray, sig: Signals) -> np.ndarray:
    """The model's direction-following torque terms (N·m) on every sample (zeros without).

    What a glitch at a guarded turn must exceed (``find_glitches``'s ``model``): a friction
    that flips at the turn, placed a sample early or late, leaves a one-sample error as
    large as its step. The elastic part is not among them: it steps only where the
    deflection sample itself jumps, and a spike in the angle channel (K times a 30 mrad
    jump in a hold) is a glitch, not a step of the model to excuse.
    """
    names = {e.name for e in model.effects if e.stage == "torque" and e.direction_signed}
    if not names:
        return np.zeros(sig.n)
    return model.torque_terms(x, sig, np.arange(sig.n), names)


def _term_steps(model: TorqueModel, x: np.ndarray, sig: Signals, half: int = 4) -> np.ndarray:
    """Samples within ``half`` of a step of the model's direction-following torque terms
    (a friction that takes hold when a hold ends): a step of more than a quarter of the
    term's size in one sample, placed a sample early or late on the deflection trace,
    leaves a residual swing there for the model's reasons, as at a turn."""
    term = direction_terms(model, x, sig)
    size = float(np.max(np.abs(term)))
    if size == 0.0:
        return np.zeros(sig.n, dtype=bool)
    step = np.abs(np.diff(term, prepend=term[0])) > 0.25 * size
    return maximum_filter1d(step.astype(np.uint8), 2 * half + 1) > 0
