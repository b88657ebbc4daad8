"""Contact rules at +-theta_max (fea.contact_tolerance): the worst case against a brute-force
search over the tolerance zones, the Monte Carlo against the closed-form probability, the
dilated cam against exact distances, and the verdicts with their fixes."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from fea.contact_tolerance import MC_SAMPLES, ContactMaterial, EndState, assess
from springcad.design.contact_stress import tip_contact_von_mises_MPa

MAT = ContactMaterial(youngs_modulus_MPa=200e3, poisson_ratio=0.28, yield_strength_MPa=1344.0,
                      safety_factor=1.2)


def _states(gaps: dict, T: float, force=100.0, kappa=0.8):
    """End states at E = 0, -T, +T with gaps linear in E: gaps[name] = (g0, slope)."""
    out = []
    for E in (0.0, -T, T):
        h = {"von_mises_max_MPa": 900.0, "p0_MPa": 1600.0, "half_width_mm": 0.01,
             "depth_mm": 0.007}
        out.append(EndState(offset_mm=E, converged=True, force_N=force,
                            flank_curvature_per_mm=kappa, hertz=h,
                            clearances_mm={n: g0 + a * E for n, (g0, a) in gaps.items()}))
    return out


def _brute_worst(g0, a, kind, ts, tc, n=41):
    """min over every deviation in the zones: e_ball, e_flank and the gap's own surfaces."""
    rs, cs = np.linspace(-ts, ts, n), np.linspace(-tc, tc, n)
    best = math.inf
    for eb, ef in itertools.product(rs, cs):
        g = g0 + a * (eb + ef)
        if kind == "ball":  # ring side is the ball itself, cam side independent
            best = min(best, g - eb - tc)
        elif kind == "flank":
            best = min(best, g - ef - ts)
        elif kind == "ring":
            best = min(best, g - 2 * ts)
        elif kind == "pair":  # the pocket's driving half deviates with the flank
            best = min(best, g - eb - ef)
        else:
            best = min(best, g - ts - tc)
    return best


@pytest.mark.parametrize("name,kind", [("driving_tooth_tip/ball", "ball"),
                                       ("driving_flank/neck", "flank"),
                                       ("driving_tooth_tip/neck", ""),
                                       ("neighbour_flexure", "ring"),
                                       ("driving_pocket/ball", "pair")])
@pytest.mark.parametrize("slope", [-1.2, -0.3, 0.0, 0.6, 1.5])
def test_worst_case_is_the_minimum_over_the_tolerance_zones(name, kind, slope):
    ts, tc, g0 = 0.05, 0.02, 0.06
    res = assess("S", {"+": (0.2, _states({name: (g0, slope)}, ts + tc))}, 0.3, 5.0, MAT, ts, tc)
    (c,) = res.ends["+"].clearances
    assert c.worst_case_mm == pytest.approx(_brute_worst(g0, slope, kind, ts, tc), abs=2e-5)
    assert c.nominal_mm == pytest.approx(g0, abs=1e-12)


def test_monte_carlo_closure_matches_the_closed_form():
    """A gap with no response to the contact offset closes when the two independent
    uniform deviations sum past it: P = (2t - g)^2 / (8 t^2) for equal tolerances t."""
    t, g = 0.03, 0.02
    res = assess("S", {"+": (0.2, _states({"back_flank/neck": (g, 0.0)}, 2 * t))}, 0.3, 5.0,
                 MAT, t, t, seed=5)
    (c,) = res.ends["+"].clearances
    p = (2 * t - g) ** 2 / (8 * t * t)
    assert c.mc_closed_fraction == pytest.approx(p, abs=4 * math.sqrt(p * (1 - p) / MC_SAMPLES))
    assert c.worst_case_mm == pytest.approx(g - 2 * t) and not c.ok
    assert c.mc_quantile_mm < 0
    # the largest common scale of the tolerances that keeps it open: g / (2 t)
    assert c.largest_tolerance_fraction == pytest.approx(g / (2 * t), rel=1e-6)
    assert res.failures() and "t_spring_mm = 0.010" in res.failures()[0]


def test_normal_distribution_is_three_sigma():
    t, g = 0.03, 0.02
    res = assess("S", {"+": (0.2, _states({"back_flank/neck": (g, 0.0)}, 2 * t))}, 0.3, 5.0,
                 MAT, t, t, distribution="normal", seed=5)
    (c,) = res.ends["+"].clearances
    sigma = math.hypot(t / 3, t / 3)
    p = 0.5 * math.erfc(g / sigma / math.sqrt(2))
    assert c.mc_closed_fraction == pytest.approx(p, abs=4 * math.sqrt(p * (1 - p) / MC_SAMPLES))


def test_open_clearances_and_a_safe_ball_pass():
    res = assess("S", {k: (s * 0.2, _states({"back_flank/ball": (0.2, -0.5)}, 0.04))
                       for k, s in (("+", 1), ("-", -1))}, 0.3, 5.0, MAT, 0.02, 0.02)
    assert res.ok and res.failures() == []
    d = res.to_dict()
    assert d["ok"] and set(d["ends"]) == {"+", "-"}
    assert d["ends"]["+"]["clearances"]["back_flank/ball"]["ok"]


def test_overstressed_ball_names_the_radius_that_fixes_it():
    states = _states({"back_flank/ball": (0.2, 0.0)}, 0.04, force=220.0, kappa=0.84)
    for s in states:
        s.hertz = dict(s.hertz, von_mises_max_MPa=1417.0)
    res = assess("S1", {"+": (0.24, states)}, 0.3, 5.0, MAT, 0.02, 0.02)
    (msg,) = res.failures()
    assert "von Mises 1417 MPa" in msg and "below the required 1.2" in msg
    r = res.ends["+"].contact["min_tip_radius_mm"]
    assert f">= {r:.2f} mm" in msg
    assert tip_contact_von_mises_MPa(220.0, r, 1 / 0.84, 5.0, 200e3, 0.28) == pytest.approx(
        1344 / 1.2, rel=1e-9)


def test_an_end_without_contact_is_not_assessed():
    res = assess("S", {"+": (0.2, [EndState(0.0, False, reason="the sweep stopped")])}, 0.3,
                 5.0, MAT, 0.02, 0.02)
    assert not res.ok and "not assessed" in res.failures()[0]


def test_dilated_cam_is_the_minkowski_offset():
    """Gap to the cam grown by E is the distance minus E, round at a sharp corner (normal
    along the radius from the corner), for points outside; shrunk (E < 0) likewise."""
    from fea.contact_solver import CamCurve
    from springcad.design.curves import Line

    # a square tooth corner at the origin, the cam in x < 0, y > 0 (contour clockwise):
    # the flank down the y axis, the tip along -x
    flank = Line((0.0, 1.0), (0.0, 0.0))
    tip = Line((0.0, 0.0), (-1.0, 0.0))
    cam = CamCurve([("flank_ccw", 0, flank), ("tip", 0, tip)], False, 0.0)
    q = np.array([[0.05, 0.5], [0.03, -0.04], [0.2, -0.2], [-0.5, -0.1]])
    exact = np.array([0.05, 0.05, math.hypot(0.2, 0.2), 0.1])
    g0 = cam.project(q)[0]
    assert np.allclose(g0, exact, atol=1e-6)
    for E in (0.03, -0.02):
        g, n, *_ = cam.dilated(E).project(q)
        assert np.allclose(g, g0 - E, atol=1e-12)
        assert np.allclose(n[2], [math.sqrt(0.5), -math.sqrt(0.5)], atol=1e-6)  # radial
    assert cam.offset_mm == 0.0  # the original is untouched


def test_the_pockets_driving_half_is_the_contact_pairs_own_surface():
    """The driving half of the pocket is cut with the driving flank and deviates with it:
    a ball 6 um from it whose gap follows the contact offset one to one (it rides the same
    smooth surface) is open at every deviation, though 6 um is under the 40 um stack; a
    gap shrinking twice as fast as the offset (the ball bottoming below the flank's
    start) closes, and says so."""
    ts = tc = 0.02
    T = ts + tc
    ok = assess("S", {"+": (0.1, _states({"driving_pocket/ball": (0.006, 1.0)}, T))}, 0.3,
                5.0, MAT, ts, tc)
    (c,) = ok.ends["+"].clearances
    assert c.ok and c.worst_case_mm == pytest.approx(0.006, abs=1e-9)
    assert c.mc_closed_fraction == 0.0 and not ok.failures()
    # the same gap against an independent surface (the back half) is closed in the worst case
    back = assess("S", {"+": (0.1, _states({"pocket/ball": (0.006, 1.0)}, T))}, 0.3, 5.0,
                  MAT, ts, tc)
    assert not back.ends["+"].clearances[0].ok
    bottoming = assess("S", {"+": (0.1, _states({"driving_pocket/ball": (0.006, 2.0)}, T))},
                       0.3, 5.0, MAT, ts, tc)
    (b,) = bottoming.ends["+"].clearances
    assert b.worst_case_mm == pytest.approx(0.006 - T, abs=2e-5) and not b.ok
    assert bottoming.failures()


def test_verify_asks_the_redesign_for_the_ball_the_contact_fea_names():
    """An over-stressed ball at either end: the verification's contact correction asks for
    the larger of the two smallest balls the ends name (the closed form of the Hertz
    sizing); a ball within the margin asks for nothing."""
    from types import SimpleNamespace

    from fea.verify import _ball_needed_mm
    from springcad.design.contact_stress import min_tip_radius_for_contact_mm

    def at_max(force_plus, force_minus):
        ends = {}
        for key, force in (("+", force_plus), ("-", force_minus)):
            st = _states({}, 0.04, force=force, kappa=0.8)
            vm = tip_contact_von_mises_MPa(force, 0.3, 1 / 0.8, 5.0, MAT.youngs_modulus_MPa,
                                           MAT.poisson_ratio)
            for s in st:  # the Hertz stress of that force on a 0.3 mm ball
                s.hertz = {**s.hertz, "von_mises_max_MPa": vm}
            ends[key] = (0.2, st)
        return assess("S", ends, 0.3, 5.0, MAT, 0.02, 0.02)

    high = at_max(400.0, 300.0)
    need = _ball_needed_mm(SimpleNamespace(at_max=high))
    allow = MAT.yield_strength_MPa / MAT.safety_factor
    expect = max(min_tip_radius_for_contact_mm(f, 1 / 0.8, 5.0, MAT.youngs_modulus_MPa,
                                               MAT.poisson_ratio, allow) for f in (400, 300))
    assert need == pytest.approx(expect, rel=1e-6) and need > 0.3
    assert _ball_needed_mm(SimpleNamespace(at_max=at_max(20.0, 20.0))) is None
    assert _ball_needed_mm(SimpleNamespace(at_max=None)) is None
