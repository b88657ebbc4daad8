"""D-fit play in the backlash stack: the formula against a hand calculation and against
a geometric search (the D shaft turned inside the D bore until it touches)."""

import math

import numpy as np
import pytest

from springcad.design.tolerance import DJoint, Interface, d_half_chord_mm, stack_backlash


def test_half_chord_by_hand():
    # Ø4 D, flat at 0.8 r = 1.6: sharp corners h = sqrt(2^2 - 1.6^2) = 1.2 (issue 26);
    # R0.15 corners: h = sqrt(1.85^2 - 1.45^2) = sqrt(1.32) = 1.14891
    assert d_half_chord_mm(2.0, 0.8) == pytest.approx(1.2)
    assert d_half_chord_mm(2.0, 0.8, 0.15) == pytest.approx(math.sqrt(1.32))


def test_d_joint_play_by_hand():
    """Bore flat +0.02/0, shaft flat 0/-0.02 over a 1.2 mm half-chord (issue 26): at
    mid-tolerance c = 0.02, play 2 atan(0.02 / 1.2) = 0.0333302 rad; at the band's far
    edge c = 0.04, 2 atan(0.04 / 1.2) = 0.0666420 rad; none at its near edge."""
    j = DJoint(1.2, 0.02, 0.02)
    lo, mid, hi = j.range_rad
    assert lo == 0.0
    assert mid == pytest.approx(0.0333302, abs=1e-7)
    assert hi == pytest.approx(0.0666420, abs=1e-7)


def test_stack_adds_d_play_worst_rss_and_monte_carlo():
    """One cam interface and two D joints: worst case and nominal add; RSS by hand; the
    Monte Carlo mean of the D play is the mean of 2 atan((u1 + u2) / h). The cam-only
    fields stay the paper's eqs. 1-3."""
    iface = Interface(10.0, 0.02, 0.01, 0.01, 0)
    j = DJoint(1.2, 0.02, 0.02)
    b = stack_backlash([iface], samples=200000, seed=3, d_joints=(j, j))
    b0 = stack_backlash([iface], samples=200000, seed=3)
    assert (b.nominal, b.worst_max, b.mc_mean) == (b0.nominal, b0.worst_max, b0.mc_mean)
    t = b.with_d_joints
    assert t["nominal"] == pytest.approx(b0.nominal + 2 * 2 * math.atan(0.02 / 1.2))
    assert t["worst_max"] == pytest.approx(b0.worst_max + 2 * 2 * math.atan(0.04 / 1.2))
    assert t["worst_min"] == pytest.approx(b0.worst_min)
    # RSS: each flat's band half-width 0.01 with sensitivity 2/h/(1 + (c/h)^2) at c = 0.02
    g = 2 / 1.2 / (1 + (0.02 / 1.2) ** 2)
    half0 = b0.rss_max - b0.nominal
    half = math.sqrt(half0 ** 2 + 4 * (g * 0.01) ** 2)
    assert t["rss_max"] - t["nominal"] == pytest.approx(half, rel=1e-9)
    # Monte Carlo: the D play of uniform one-sided deviations has mean
    # E[2 atan((u1+u2)/h)] ~= 2 atan(0.02/1.2) (nearly linear); the totals differ by it
    rng = np.random.default_rng(0)
    c = rng.uniform(0, 0.02, 10 ** 6) + rng.uniform(0, 0.02, 10 ** 6)
    expect = 2 * np.mean(2 * np.arctan(c / 1.2))
    assert t["mc_mean"] - b0.mc_mean == pytest.approx(expect, abs=3e-4)
    assert b.to_dict()["d_joints"][0]["mid"] == pytest.approx(2 * math.atan(0.02 / 1.2))
    assert b.to_dict()["with_d_joints"]["nominal"] == t["nominal"]


def _max_turn_rad(radius_mm, ratio, corner_mm, c_bore_mm, c_shaft_mm, step_mm=0.002,
                  bisections=20):
    """Largest turn of the D shaft about the axis that keeps it inside the D bore
    (bisection on point-in-polygon; the shaft's round part 1 um smaller so that only
    the flats limit the turn). The outlines sampled every 2 um and 20 bisections of
    0-0.2 rad (2e-7 rad): the turns agree with 1 um and 30 bisections within 5e-5
    relative on the three cases below (2 % allowed), at a sixth of the cost (the
    point-in-polygon test is samples x samples)."""
    from matplotlib.path import Path

    from springcad.design.cam import d_bore

    a = ratio * radius_mm
    bore = Path(d_bore(radius_mm, (a + c_bore_mm) / radius_mm, corner_mm).sample(step_mm))
    r_s = radius_mm - 0.001
    shaft = d_bore(r_s, (a - c_shaft_mm) / r_s, corner_mm).sample(step_mm)
    lo, hi = 0.0, 0.2
    for _ in range(bisections):
        th = 0.5 * (lo + hi)
        rot = np.array([[math.cos(th), math.sin(th)], [-math.sin(th), math.cos(th)]])
        lo, hi = (th, hi) if bore.contains_points(shaft @ rot).all() else (lo, th)
    return lo


@pytest.mark.parametrize("radius,corner,c_bore,c_shaft", [(2.0, 0.15, 0.01, 0.01),
                                                          (2.0, 0.0, 0.02, 0.0),
                                                          (5.1, 0.15, 0.005, 0.015)])
def test_d_play_matches_the_geometry(radius, corner, c_bore, c_shaft):
    j = DJoint(d_half_chord_mm(radius, 0.8, corner), 0.0, 0.0)
    geometric = 2 * _max_turn_rad(radius, 0.8, corner, c_bore, c_shaft)
    assert geometric == pytest.approx(float(j.play_rad(c_bore + c_shaft)), rel=0.02)


def test_default_stack_reports_its_d_joints():
    from pathlib import Path

    from springcad.config import load_job
    from springcad.design.job import design_job

    d = design_job(load_job(Path(__file__).resolve().parents[1] / "templates" / "default.toml"),
                   explain=False)  # the same design without the duty advice search
    b = d.stack.backlash
    # input and output torque shafts, and the dowelled rim-to-rim joint of the two rings
    assert b.d_joint_kinds == ("D fit", "D fit", "rim pins")
    cams = sum(r[1] for r in b.per_interface)
    assert b.nominal == pytest.approx(cams)
    assert b.with_d_joints["nominal"] == pytest.approx(cams + sum(r[1] for r in b.per_d_joint))
    assert all(mid > 0.01 for _, mid, _ in b.per_d_joint[:2])  # not negligible against the cams
    # the rim pins: the hand numbers of test_rim_pin_play_by_hand on this pin circle
    r = math.hypot(*d.stack.springs[0].hole_centres_mm[0])
    assert b.per_d_joint[2][1] == pytest.approx(0.028 / r, rel=1e-12)


def test_rim_pin_play_by_hand():
    """Ø1.5 m6 dowels (+0.002/+0.008) in E7 holes (+0.014/+0.024, ISO 286-2) on a Ø69.53
    pin circle: clearance 0.006-0.022 mm per hole; two holes per pin, so the rims turn
    by (c_a + c_b) / r: mid 0.028 / 34.765 = 8.054e-4 rad, max 0.044 / 34.765 =
    1.2657e-3 rad, min 0 (pattern errors may take the least clearance up)."""
    from springcad.design.catalogue import rim_pin_fit
    from springcad.design.tolerance import RimPinJoint

    fit = rim_pin_fit(1.5, 0.006)
    assert (fit.clearance_min_mm, fit.clearance_max_mm) == pytest.approx((0.006, 0.022))
    j = RimPinJoint(34.765, fit.clearance_min_mm, fit.clearance_max_mm)
    lo, mid, hi = j.range_rad
    assert lo == 0.0
    assert mid == pytest.approx(0.028 / 34.765, rel=1e-12)
    assert hi == pytest.approx(0.044 / 34.765, rel=1e-12)
    # in series with a cam interface: nominal and worst case add; Monte Carlo mean of
    # uniform clearances is the mid play
    iface = Interface(10.0, 0.02, 0.01, 0.01, 0)
    b0 = stack_backlash([iface], samples=200000, seed=3)
    b = stack_backlash([iface], samples=200000, seed=3, d_joints=(j,))
    t = b.with_d_joints
    assert t["nominal"] == pytest.approx(b0.nominal + 0.028 / 34.765)
    assert t["worst_max"] == pytest.approx(b0.worst_max + 0.044 / 34.765)
    assert t["mc_mean"] - b0.mc_mean == pytest.approx(0.028 / 34.765, abs=2e-6)
    assert b.to_dict()["d_joints"][0]["kind"] == "rim pins"
