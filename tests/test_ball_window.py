"""The tip ball of a layout the user fixed (N and r_c) is searched between the ball that
leaves the driving tooth too close to the driven flexure's neck and the one whose tooth
tip passes the ball too close (:data:`springcad.design.balls.BALL_BISECTIONS`).

Held-out A 7311 g04 (17-4PH, 92 N*m/rad, 25 deg, R_o 85, 7.5 mm, N 41 and r_c 20.5 mm
fixed): balls of about 0.39 to 0.41 mm clear both at full deflection, the retry's factors
gave 0.375 mm (neck too close) and 0.45 mm (tooth tip too close), and the design kept its
0.3 mm balls short of the rule; its build was NOT FOR MANUFACTURE on that clearance."""

from __future__ import annotations

from dataclasses import replace

import pytest

from springcad.config import job_from_dict
from springcad.design import balls as tip_balls, search
from springcad.design.cam import FLEXURE_CLEARANCE_SHORT, TIP_CLEARANCE_SHORT
from springcad.design.shortfalls import soft_shortfalls

pytestmark = pytest.mark.slow  # five designs of a 41-flexure serpentine spring (20-30 s)

G04 = {"material": {"name": "17-4ph_h900", "design_stress_MPa": 700.0, "safety_factor": 1.1},
       # the static duty sizes for yield alone, as the default duty's fallback does, without
       # the default duty's probe (seconds)
       "duty": {"preset": "static"},
       "springs": {"A": {"target_stiffness_Nm_per_rad": 92, "max_deflection_deg": 25,
                         "outer_radius_mm": 85.0, "thickness_mm": 7.5,
                         "contact_radius_mm": 20.5, "n_flexures": 41}},
       "hardware": {"fastener": "dowel", "fastener_diameter_mm": 5.0, "fastener_count": 6,
                    "shaft_diameter_mm": 10.0, "rim_spacer_thickness_mm": 0.5}}


@pytest.fixture(scope="module")
def g04():
    job = job_from_dict(G04)
    spec, args = job.springs["A"], (job.material, job.manufacturing, job.hardware)
    return spec, args, search.design_spring(spec, *args, explain=False)


def _shortfalls_with_ball(spec, args, ball_mm: float) -> list[str]:
    """The soft shortfalls of the same layout with its tip ball fixed at ``ball_mm``."""
    d = search.design_for_margin(replace(spec, tip_radius_mm=ball_mm), *args, explain=False)
    return soft_shortfalls(d)


def test_the_search_finds_a_ball_that_clears_neck_and_tooth_tip(g04):
    spec, args, d = g04
    assert (d.n_flexures, d.contact_radius_mm) == (41, 20.5)  # the user's keys kept
    assert soft_shortfalls(d) == [], d.design_choice
    assert "kept although it falls short" not in d.design_choice
    # the same rules, evaluated again with the chosen ball fixed by the user: it clears
    assert _shortfalls_with_ball(spec, args, d.tip_radius_mm) == []


def test_the_window_lies_between_the_retry_factors(g04):
    """The reference the bisection is needed against: the smallest ball the layout designs
    with leaves the neck too close, and the balls of the retry's factors on either side of
    the chosen one fall short of the two rules, one each."""
    spec, args, d = g04
    small = search.design_for_margin(spec, *args, explain=False, candidates=1)
    base = small.tip_radius_mm
    assert soft_shortfalls(small)[0].startswith(FLEXURE_CLEARANCE_SHORT)
    balls = [round(f * base, 3) for f in tip_balls.BALL_FACTORS]
    assert min(balls) < d.tip_radius_mm < max(balls)  # the chosen ball is none of them
    below = max(b for b in balls if b < d.tip_radius_mm)
    above = min(b for b in balls if b > d.tip_radius_mm)
    assert _shortfalls_with_ball(spec, args, below)[0].startswith(FLEXURE_CLEARANCE_SHORT)
    assert _shortfalls_with_ball(spec, args, above)[0].startswith(TIP_CLEARANCE_SHORT)
