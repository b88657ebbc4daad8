"""Which law of an effect family describes the record best.

An effect family (friction, a late torque channel) is searched for with the
library's law (:data:`springcad.fit.effects.LIBRARY`). Once the loop has named
it, its other laws (:data:`springcad.fit.other_laws.OTHER_LAWS`: viscous damping,
a first-order filter on the deflection or on the torque itself and a relaxing
standard-linear-solid branch for the lag family, velocity-regularised Coulomb friction for the friction family) are fitted in its place, with the rest of
the model free, and scored with the same held-out criterion. The law with the
lowest criterion is kept when it beats the one in the model by more than
``LAW_MARGIN``; the record tells the laws apart when the best beats every
other by the loop's gain threshold.

A law outside what the library's effects mean (:data:`BEYOND_LIBRARY`: a
first-order filter rounds the turns a delay keeps sharp; a friction that lets go
at rest is not the presliding friction that holds through a hold) which beats
the library's law by the gain threshold is physics the library was not written
with: the record is flagged ``unexplained`` with a finding that names the law
that describes it (:func:`beyond_library`), so the report says both what fits and
that it is not the library's physics. The bar is the one ``unexplained`` itself
uses: the library's law, fitted in the kept law's place, must leave structure the
residual tests find clearly above noise, or depart from the kept law somewhere by
more than the noise's own moving averages reach anywhere in the record
(:func:`springcad.fit.residual.local_departure`; a filter in the torque sensor
differs from a delay only where a crossover is taken up at speed). A viscous damper is within the time lag's
meaning (the library's lag names its negative values a damping, ``K·θ(t + c/K) ≈ K·θ +
c·dθ/dt``) and is never flagged: at starts, stops and sharp turns the damper's torque
follows the speed at once where a delayed channel's is shifted in time, which tells the
laws apart, not the library from physics outside it. A law outside the library's meaning
that another family's law within it describes as well (a friction that lets go at rest
and a damper, on ramps at one speed: ``F·tanh(v/v0) = c·v`` wherever ``|v|`` takes one
value) is not flagged either: the two are named as one confounded group
(:func:`springcad.fit.identify.find_confounded`).

A friction that fades at rest read with the library's presliding law (which
holds its torque through a hold) leaves structure in every hold and turn, and
a lag fitted beside it takes up part of it; a damper read as a delay leaves a
stiffness that changes with the frequency. With the right law the family's
size has its physical meaning (a friction torque in N·m, a damping in
N·m·s/rad, a filter time constant in s).

Units: N·m, rad, s.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from springcad.fit.effects import Effect, get_effect
from springcad.fit.other_laws import OTHER_LAWS
from springcad.fit.residual import local_departure, residual_structure
from springcad.fit.search import LAW_MARGIN, Search, State
from springcad.fit.torque_model import TorqueModel



#: laws that describe their family beyond what the library effect's meaning covers, with
#: the kinds of cause that leave them
BEYOND_LIBRARY = {
    "first_order_filter": ("a low-pass filter in the torque channel (sensor, amplifier or "
                           "acquisition anti-alias filter), which rounds turns and attenuates "
                           "fast motion where a pure delay only shifts it"),
    "torque_filter": ("a low-pass filter in the torque sensor or its amplifier, which rounds "
                      "the corners of the torque itself (a crossover taken up, a friction's "
                      "turn) where a pure delay only shifts them"),
    "standard_linear_solid": ("viscoelastic relaxation (a polymer bushing or pad, a glued, "
                              "clamped or press-fitted joint creeping): the torque overshoots "
                              "while moving and relaxes toward K·θ in holds, which no library "
                              "effect does"),
    "hertzian_contact": ("a gap closed through a Hertzian (point or line) contact in series "
                         "with the spring (a cam on a flexure tip, a ball or roller seat): "
                         "the torque is taken up as a power law and the contact stays "
                         "compliant at every load, where the library's crossover is taken "
                         "up over a transition and then runs parallel to K·θ"),
    "stribeck": ("friction whose level falls with speed (a Stribeck curve: lubricated or "
                 "bristle-like LuGre contacts), where the library's friction torque is one "
                 "level at every speed"),
    "regularised_coulomb": ("friction that fades with speed and lets go at rest (lubricated or "
                            "rolling contact, a velocity-regularised law), where the library's "
                            "presliding friction holds its torque through holds and turns"),
}


def beyond_library(laws: dict, threshold: float,
                   leaves_structure: Callable[[str, str, float], bool] | None = None
                   ) -> list[dict]:
    """Localisation findings for families whose kept law is in :data:`BEYOND_LIBRARY`,
    beats the best law within the library effect's meaning by more than ``threshold``
    (held-out criterion units), and where that library law, fitted in its place, leaves
    structure clearly above noise (``leaves_structure(family, law, margin)``; the same bar
    as ``unexplained`` itself): a law the record prefers but whose difference from the
    library's stays within the noise is not flagged."""
    out = []
    for family, info in laws.items():
        law = info["law"]
        library_law = get_effect(family).law
        within = {k: v for k, v in info["criterion_vs_kept"].items() if k not in BEYOND_LIBRARY}
        if law not in BEYOND_LIBRARY or not within:
            continue
        nearest = min(within, key=within.get)
        margin = within[nearest]
        if margin <= threshold:
            continue
        if leaves_structure is not None and not leaves_structure(family, nearest, margin):
            continue
        against = (f"the library's {library_law.replace('_', ' ')}" if nearest == library_law
                   else f"a {nearest.replace('_', ' ')} law within the library's meaning")
        out.append({"kind": "law_outside_library", "family": family, "law": law,
                    "library_law": library_law, "nearest_library_law": nearest,
                    "criterion_gain": float(margin), "share": 1.0,
                    "text": (f"the {family} follows a {law.replace('_', ' ')} law, not "
                             f"{against} (held-out criterion {margin:.0f} better), and is "
                             "fitted with it"),
                    "causes": BEYOND_LIBRARY[law]})
    return out


def flag_outside(state: State, search: Search, laws: dict, idx: np.ndarray, noise: float,
                 tau: float) -> list[dict]:
    """Findings of :func:`beyond_library` for the final ``state`` (judged on samples
    ``idx``, noise ``noise`` N·m correlated over ``tau`` samples).

    A law within the library's meaning, fitted in the kept law's place on all fitted
    samples, leaves structure when the residual tests find it (the bar of
    ``unexplained`` itself), when it departs from the kept law, somewhere in the
    record, by more than the noise can (:func:`springcad.fit.residual.local_departure`:
    a sensor filter read as a delay differs only where a crossover is taken up at
    speed, too briefly for the binned tests), or when the held-out criterion by which
    it loses says what it leaves is as large as the residual tests' own bar
    (:func:`left_rms_over_noise`: a Hertzian take-up read with the library's crossover
    leaves 0.3 noise levels RMS spread over every crossing, below the binned tests'
    resolution on each bin but not on the record). When the family is confounded with
    another family whose law is within the library's meaning (a damper for a friction
    that lets go at rest, on one speed), the record read with that one in its place
    is judged alike.
    """
    sig, s = search.sig, search.s
    f_scale = search.f_scale(state)
    kept = state.model.predict(state.x, sig, idx)

    def left(model: TorqueModel, x: np.ndarray) -> bool:
        if residual_structure(model.residual(x, sig, idx), idx, sig, bins=s.structure_bins,
                              min_rms=s.structure_min_rms, p_level=s.structure_p,
                              excess_ratio=s.excess_ratio)[1]:
            return True
        d = model.predict(x, sig, idx) - kept
        return local_departure(d, noise, tau, s.structure_p)["significant"]

    def leaves_structure(family: str, law: str, margin: float) -> bool:
        for model, x_swap in search.swaps.get(family, ()):
            if not any(e.law in BEYOND_LIBRARY for e in model.effects) and not left(
                    model, search.refit(model, x_swap, state.mask, f_scale)):
                return False
        if left_rms_over_noise(margin, search.n_eff) >= s.structure_min_rms:
            return True
        found = fitted_in_place(state, search, family, law, f_scale)
        return True if found is None else left(*found)

    return beyond_library(laws, s.gain_threshold, leaves_structure)


def left_rms_over_noise(margin: float, n_eff: float) -> float:
    """RMS, in noise levels, of what a law leaves that another describes, from the held-out
    criterion ``margin`` by which it loses (``n_eff`` independent held-out samples): the
    criterion is ``n_eff·ln(SSE)``, so its SSE is ``exp(margin/n_eff)`` times the other's,
    and the excess over the noise's own sum of squares is the structure it leaves."""
    if margin <= 0.0 or n_eff <= 0.0:
        return 0.0
    return math.sqrt(math.expm1(margin / n_eff))


def fitted_in_place(state: State, search: Search, family: str, law: str,
                    f_scale: float) -> tuple[TorqueModel, np.ndarray] | None:
    """``family``'s ``law`` (as :func:`choose_laws` last fitted it) put in place of the
    state's law, the rest of the state's model as fitted, refitted on every fitted
    sample; ``None`` when that law was not fitted."""
    fit = search.law_fits.get(family, {}).get(law)
    if fit is None:
        return None
    model_law, x_law = fit
    effect = next(e for e in model_law.effects if e.name == family)
    model = _swap(state.model, effect)
    x = np.empty(model.size)
    x[0] = state.x[0]
    for e in model.effects:
        src = x_law[model_law.slice_of(family)] if e.name == family else \
            state.x[state.model.slice_of(e.name)]
        x[model.slice_of(e.name)] = src
    return model, search.refit(model, x, state.mask, f_scale)


def _swap(model: TorqueModel, law: Effect) -> TorqueModel:
    return TorqueModel(tuple(law if e.name == law.name else e for e in model.effects),
                       model.scales)


def _start(search: Search, state: State, model: TorqueModel, law: Effect,
           idx: np.ndarray) -> np.ndarray:
    """The best of the law's starts (others at their fitted values, K re-solved)."""
    rest = state.model.without(law.name)
    x_rest = rest.transfer(state.model, state.x)
    best, best_sse = None, np.inf
    for s in law.starts(model.scales):
        x = model.solve_stiffness(model.transfer(rest, x_rest, {law.name: s}), search.sig, idx)
        r = model.residual(x, search.sig, idx)
        sse = float(r @ r)
        if sse < best_sse:
            best, best_sse = x, sse
    return best


def choose_laws(state: State, search: Search, f_scale: float) -> tuple[State, dict]:
    """Fit each named family's other laws in its place; keep the best (see module docstring).

    Returns:
        The state (with the chosen laws, refitted) and, per family, ``law`` (the
        one kept), ``criterion_vs_kept`` (held-out criterion of each law minus
        the kept one's: positive is worse) and ``told_apart``.
    """
    info = {}
    for effect in list(state.model.effects):
        name = effect.name
        if name not in OTHER_LAWS:
            continue
        laws = (get_effect(name),) + OTHER_LAWS[name]
        idx = state.inliers(search.cv)
        scores, fits = {}, {}
        for law in laws:
            if law.law == effect.law:
                model, x0 = state.model, state.x
            else:
                model = _swap(state.model, law)
                x0 = _start(search, state, model, law, idx)
            score, _ = search.cv_score(model, x0, state.mask, f_scale)
            x_fit = search.last_fit
            problem = law.physical_problem(x_fit[model.slice_of(name)], float(x_fit[0]),
                                           model.scales)
            if problem is None or law.law == effect.law:
                scores[law.law], fits[law.law] = score, (model, x_fit.copy(), law)
        now = scores[effect.law]
        best = min(scores, key=scores.get)
        if best != effect.law and scores[best] < now - LAW_MARGIN:
            model, x_fit, law = fits[best]
            x = search.refit(model, x_fit, state.mask, f_scale)
            state = State(model, x, state.mask, state.series)
        search.law_fits[name] = {k: (m, x) for k, (m, x, _) in fits.items()}
        kept = next(e for e in state.model.effects if e.name == name).law
        others = sorted(v - scores[kept] for k, v in scores.items() if k != kept)
        info[name] = {"law": kept,
                      "criterion_vs_kept": {k: v - scores[kept] for k, v in scores.items()},
                      "told_apart": bool(others and others[0] > search.s.gain_threshold)}
    return state, info
