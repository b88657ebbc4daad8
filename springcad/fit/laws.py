"""Which law of an effect family describes the record best.

An effect family (friction, a late torque channel) is searched for with the
library's law (:data:`springcad.fit.effects.LIBRARY`). Once the loop has named
it, its other laws (:data:`springcad.fit.effects.OTHER_LAWS`: viscous damping
and a first-order filter for the lag family, velocity-regularised Coulomb
friction for the friction family) are fitted in its place, with the rest of
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
that it is not the library's physics. A viscous damper is within the time lag's
meaning (``K·θ(t + c/K) ≈ K·θ + c·dθ/dt``) and is not flagged.

A friction that fades at rest read with the library's presliding law (which
holds its torque through a hold) leaves structure in every hold and turn, and
a lag fitted beside it takes up part of it; a damper read as a delay leaves a
stiffness that changes with the frequency. With the right law the family's
size has its physical meaning (a friction torque in N·m, a damping in
N·m·s/rad, a filter time constant in s).

Units: N·m, rad, s.
"""

from __future__ import annotations

import numpy as np

from springcad.fit.effects import OTHER_LAWS, Effect, get_effect
from springcad.fit.search import LAW_MARGIN, Search, State
from springcad.fit.torque_model import TorqueModel



#: laws that describe their family beyond what the library effect's meaning covers, with
#: the kinds of cause that leave them
BEYOND_LIBRARY = {
    "first_order_filter": ("a low-pass filter in the torque channel (sensor, amplifier or "
                           "acquisition anti-alias filter), which rounds turns and attenuates "
                           "fast motion where a pure delay only shifts it"),
    "standard_linear_solid": ("viscoelastic relaxation (a polymer bushing or pad, a glued, "
                              "clamped or press-fitted joint creeping): the torque overshoots "
                              "while moving and relaxes toward K·θ in holds, which no library "
                              "effect does"),
    "regularised_coulomb": ("friction that fades with speed and lets go at rest (lubricated or "
                            "rolling contact, a velocity-regularised law), where the library's "
                            "presliding friction holds its torque through holds and turns"),
}


def beyond_library(laws: dict, threshold: float) -> list[dict]:
    """Localisation findings for families whose kept law is in :data:`BEYOND_LIBRARY` and
    beats every law within the library effect's meaning (the library's own, and a damper
    for the lag family) by more than ``threshold`` (held-out criterion units)."""
    out = []
    for family, info in laws.items():
        law = info["law"]
        library_law = get_effect(family).law
        # against the best law within the library effect's meaning (a damper is a lag)
        within = {k: v for k, v in info["criterion_vs_kept"].items() if k not in BEYOND_LIBRARY}
        if law not in BEYOND_LIBRARY or not within:
            continue
        nearest = min(within, key=within.get)
        margin = within[nearest]
        if margin <= threshold:
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
                scores[law.law], fits[law.law] = score, (model, x_fit, law)
        now = scores[effect.law]
        best = min(scores, key=scores.get)
        if best != effect.law and scores[best] < now - LAW_MARGIN:
            model, x_fit, law = fits[best]
            x = search.refit(model, x_fit, state.mask, f_scale)
            state = State(model, x, state.mask, state.series)
        kept = next(e for e in state.model.effects if e.name == name).law
        others = sorted(v - scores[kept] for k, v in scores.items() if k != kept)
        info[name] = {"law": kept,
                      "criterion_vs_kept": {k: v - scores[kept] for k, v in scores.items()},
                      "told_apart": bool(others and others[0] > search.s.gain_threshold)}
    return state, info
