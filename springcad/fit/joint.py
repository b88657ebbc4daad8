"""Joint model selection: effects the audit rejected one at a time, tried together.

The search adds one effect at a time, and the evidence audit judges each
effect of the model with the others fitted beside it. When several effects are
present and one of them is missing from the model, the others can fail their
audit for its sake (a lag whose size differs between the slow and the fast
third because the friction beside it is missing; a crossover whose width
differs between loading and unloading for the same reason), and once rejected
they are not proposed again. Here every set of up to ``MAX_SET`` rejected
effects is added to the final model together and scored with the loop's
held-out criterion; the sets that beat the model by the gain threshold per
effect are, best first, refitted on all samples, given the laws their families fit
best (:func:`springcad.fit.laws.choose_laws`) and audited as they would be reported;
the first whose effects all pass is taken. A set that passes with the library's laws
and fails with the law the record prefers is not taken: its family would be named
with a law whose size the record does not support (a lag that grows with time on
sine blocks of rising frequency, patched by a friction fading with speed that is
2.3 standard errors from zero on the early third).

Units: N·m, rad, s.
"""

from __future__ import annotations

import itertools

import numpy as np

from springcad.fit.effects import get_effect
from springcad.fit.evidence import audit
from springcad.fit.laws import choose_laws
from springcad.fit.search import Search, State

#: most effects added together
MAX_SET = 3
#: most rejected effects combined (the sets grow as 2^n)
MAX_POOL = 4
#: most sets audited
MAX_AUDITED = 3


def _with(state: State, names: tuple[str, ...], search: Search) -> State | None:
    """``state`` with the effects ``names`` added, each from its best start, or ``None``
    when one is not applicable beside the rest."""
    sig = search.sig
    model, x = state.model, state.x
    idx = state.inliers(search.cv)
    for name in names:
        effect = get_effect(name)
        active = set(model.names) | set(names)
        if not effect.applicable(active - {name}, sig) or effect.stage in ("mask", "encoder"):
            return None
        m2 = model.with_effect(effect)
        best, best_sse = None, np.inf
        for s in effect.starts(m2.scales):
            xs = m2.solve_stiffness(m2.transfer(model, x, {name: s}), sig, idx)
            r = m2.residual(xs, sig, idx)
            if float(r @ r) < best_sse:
                best, best_sse = xs, float(r @ r)
        model, x = m2, best
    return State(model, x, state.mask, state.series)


def joint_sets(state: State, rejected: list[str], search: Search, f_scale: float,
               score_now: float, baseline: State | None = None
               ) -> tuple[State, tuple[str, ...], float, dict, tuple[str, ...]] | None:
    """The best set of rejected effects that, added together with the laws the record
    prefers, is supported and passes the audit (see module docstring), as ``(state, names,
    held-out gain, laws, dropped)`` (``laws`` as :func:`springcad.fit.laws.choose_laws` gives
    them; ``dropped``: effects of ``state`` that failed the audit beside the set and were
    left out), or ``None``.

    With ``baseline`` (the linear model) each set is also fitted afresh: the model's
    effects and the set's, every one from its own starts on the baseline. An effect fitted
    alone takes up what the missing ones leave (a lag fitted before the friction beside it
    holds a third of its delay and the friction's step), and from there the set's fit can
    stay in that compromise, where from the baseline it does not."""
    s = search.s
    pool = [n for n in dict.fromkeys(rejected) if n not in state.model.names][:MAX_POOL]
    scored = []
    for k in range(1, min(MAX_SET, len(pool)) + 1):
        for names in itertools.combinations(pool, k):
            starts = [_with(state, names, search)]
            if baseline is not None:
                starts.append(_with(State(baseline.model, baseline.x, state.mask, state.series),
                                    state.model.names + names, search))
            best = None
            for trial in starts:
                if trial is None:
                    continue
                score, _ = search.cv_score(trial.model, trial.x, trial.mask, f_scale)
                if best is None or score < best[0]:
                    best = (score, State(trial.model, search.last_fit, trial.mask,
                                         trial.series))
            if best is None:
                continue
            gain = score_now - best[0]
            if gain > s.gain_threshold * k:
                scored.append((gain, names, best[1]))
    scored.sort(key=lambda c: -c[0])
    for gain, names, trial in scored[:MAX_AUDITED]:
        found, failed = _audited(trial, search, f_scale)
        if found is not None:
            return found[0], names, gain, found[1], ()
        # effects the model held before the set that fail beside it only stood in for the
        # set (a cubic fitted to the friction and lag a triangle's three speeds leave): the
        # set without them, fitted afresh, must still clear the threshold
        old = tuple(n for n in state.model.names if n not in failed)
        if (baseline is None or not failed or any(n in names for n in failed)
                or not set(failed) <= set(state.model.names)):
            continue
        lean = _with(State(baseline.model, baseline.x, state.mask, state.series), old + names,
                     search)
        if lean is None:
            continue
        score, _ = search.cv_score(lean.model, lean.x, lean.mask, f_scale)
        gain = score_now - score
        if gain <= s.gain_threshold * len(names):
            continue
        found, _ = _audited(State(lean.model, search.last_fit, lean.mask, lean.series), search,
                            f_scale)
        if found is not None:
            return found[0], names, gain, found[1], tuple(failed)
    return None


def _audited(trial: State, search: Search, f_scale: float
             ) -> tuple[tuple[State, dict] | None, list[str]]:
    """``trial`` refitted on all samples with the laws its families fit best, as ``((state,
    laws), [])`` when every effect passes the audit, else ``(None, names that failed)``
    (every effect's name when a fitted value is physically impossible)."""
    s = search.s
    model = trial.model
    x = search.refit(model, trial.x, trial.mask, f_scale)
    problems = [e.physical_problem(x[model.slice_of(e.name)], float(x[0]), model.scales)
                for e in model.effects]
    if any(p is not None for p in problems):
        return None, [e.name for e, p in zip(model.effects, problems) if p is not None]
    chosen, laws = choose_laws(State(model, x, trial.mask, trial.series), search, f_scale)
    aud = audit(chosen.model, chosen.x, search.sig, chosen.inliers(search.cv), f_scale,
                s.agreement_p, s.support_z)
    failed = [ev.effect for ev in aud.failed()]
    return (None, failed) if failed else ((chosen, laws), [])
