"""The driven flexure tip at full deflection (springcad.design.driven): the beam kinematics
against a numerical integration of the same beam, and the design's neck and edge clearances
against the contact FEA's (fea.contact and its tolerance study) on a held-out spring."""

import math

import numpy as np
import pytest

from springcad.config import job_from_dict
from springcad.design.cam import _unit
from springcad.design.driven import (FORESHORTENING, ball_lift_mm, clearances_at_max,
                                     deflected)
from springcad.design.job import design_job


def _taper_by_quadrature(length_mm: float, delta_mm: float, u_mm: np.ndarray):
    """Slope, tangential deflection and foreshortening at distances ``u_mm`` from the tip of
    a cantilever whose curvature is ~ u^-1/2 (a constant-stress taper under a tip force),
    integrated from the clamped root by the trapezoid rule in t = sqrt(u / L) (du = 2 L t dt
    takes the tip's singularity away), scaled to a tip travel delta."""
    t = np.linspace(1.0, 0.0, 200001)  # root -> tip
    du_dt = 2.0 * length_mm * t
    kappa_du_dt = 2.0 * np.sqrt(length_mm) * np.ones_like(t)  # u^-1/2 du/dt
    dt = -np.diff(t)

    def integral(f):
        return np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dt)])

    phi = integral(kappa_du_dt)
    w = integral(phi * du_dt)
    v = 0.5 * integral(phi ** 2 * du_dt)
    scale = delta_mm / w[-1]
    u = length_mm * t ** 2
    return tuple(np.interp(u_mm, u[::-1], a[::-1])
                 for a in (phi * scale, w * scale, v * scale ** 2))


def test_the_tip_kinematics_are_the_tapered_cantilevers():
    """Points on the centreline of flexure 0 move by the quadrature's deflection and
    foreshortening; a point off it turns with the slope there; the ball's lift is the
    foreshortening at the tip, 3/4 delta^2 / L."""
    rc, rr, delta = 8.0, 38.0, 1.3
    length = rr - rc
    u = np.array([0.0, 0.2, 1.0, 5.0, 15.0, 29.0])
    phi, w, v = _taper_by_quadrature(length, delta, u)
    assert v[0] == pytest.approx(FORESHORTENING * delta ** 2 / length, rel=1e-3)
    assert ball_lift_mm(rc, rr, 0.04, (delta + 0.04) / rc) == pytest.approx(v[0], rel=1e-3)
    centre = np.array([delta, rc + v[0]])
    on = deflected(np.column_stack([np.zeros_like(u), rc + u]), rc, rr, centre)
    assert on[:, 0] == pytest.approx(w, abs=3e-3 * delta)
    assert on[:, 1] - (rc + u) == pytest.approx(v, abs=3e-3 * v[0])
    off = deflected(np.column_stack([np.full_like(u, 0.3), rc + u]), rc, rr, centre)
    turned = np.arctan2(off[:, 1] - on[:, 1], off[:, 0] - on[:, 0])
    assert turned == pytest.approx(phi, abs=3e-3 * phi[0])
    # below the ball centre the tip moves as a rigid body: distances to the centre are kept
    ball = np.array([[0.3, rc], [0.0, rc - 0.3], [-0.2, rc - 0.1]])
    moved = deflected(ball, rc, rr, centre)
    assert np.hypot(*(moved - centre).T) == pytest.approx(np.hypot(*(ball - (0, rc)).T))


#: the contact FEA's gaps at +18 deg on held-out g26 (ti6al4v, 26 N*m/rad, R_o 46, 6 mm, r_c 11,
#: N 49, tolerances 0.02 + 0.02, gap 0.04), by overtravel: the smallest over the cam's
#: surfaces, to the neck and to the edges, (nominal, worst case) in um. 1.15: the ho11 build
#: (main d533b40); 1.35: the build of main cb8e7e1 plus the foreshortened tip estimate
G26_FEA_UM = {1.15: {"neck": (126.3, 70.5), "edge": (224.3, 168.6)},
              1.35: {"neck": (38.6, -1.4), "edge": (51.9, -27.1)}}


def _g26_job(**fixed):
    return job_from_dict({
        "job": {"name": "g26"}, "material": {"name": "ti6al4v"},
        "springs": {"A": {"target_stiffness_Nm_per_rad": 26, "max_deflection_deg": 18,
                          "outer_radius_mm": 46.0, "thickness_mm": 6.0,
                          "contact_radius_mm": 11.0, **fixed}},
        "manufacturing": {"process": "wire_edm", "t_spring_mm": 0.02, "t_shaft_mm": 0.02,
                          "w_gap_mm": 0.04},
        "hardware": {"fastener": "dowel", "fastener_diameter_mm": 2.5, "fastener_count": 6,
                     "shaft_diameter_mm": 6.0}})


@pytest.fixture(scope="module")
def g26():
    return design_job(_g26_job(n_flexures=49), explain=False).springs["A"]


@pytest.mark.parametrize("overtravel", sorted(G26_FEA_UM))
def test_neck_and_edge_gaps_against_the_contact_fea(g26, overtravel):
    """The estimate is never kinder than the FEA (by more than 3 um) and at most 45 um more
    careful: the tooth lengthened for the ball's sake (1.35) swings past the neck, which the
    tip's turn of 3 delta / L brings towards it."""
    d = g26
    assert (d.n_flexures, d.contact_radius_mm) == (49, 11.0)
    rc, rb, g = d.contact_radius_mm, d.tip_radius_mm, d.manufacturing.w_gap_mm
    pitch = 2 * math.pi / d.n_flexures
    unit, _, tip = _unit(rc, rb + g, pitch, (rb + g) / rc + overtravel * d.max_deflection_rad)
    est = clearances_at_max(d.ring.loop("flexures"), unit, pitch, rc, d.root_radius_mm, g,
                            d.max_deflection_rad, 0.04, tip.radius + 0.5)
    for part, (nominal_um, worst_um) in G26_FEA_UM[overtravel].items():
        got = 1000 * est[part].nominal_mm, 1000 * est[part].worst_case_mm
        assert nominal_um - 45 <= got[0] <= nominal_um + 3, (part, got)
        assert worst_um - 45 <= got[1] <= worst_um + 3, (part, got)


def test_the_design_warns_when_no_flank_clears_both_the_ball_and_the_neck(g26):
    """With r_c and N fixed, the flank the ball needs runs past the neck: the design keeps
    the flank that is drawable and says which rule it misses (the search reads it)."""
    from springcad.design.shortfalls import soft_shortfalls
    assert soft_shortfalls(g26), g26.warnings


def test_a_larger_tip_ball_is_searched_when_every_layout_falls_short():
    """The same spring with N free: with 0.3 mm balls no flexure count clears both the ball
    and the neck at 18 deg; the search tries larger balls (fewer then fit) and keeps the
    first design that passes every rule, saying why. (Built, held-out g26 was NOT FOR
    MANUFACTURE on its tooth-tip gap before and is RELEASED with it.)"""
    from springcad.design.shortfalls import soft_shortfalls
    d = design_job(_g26_job(), explain=False).springs["A"]
    assert not soft_shortfalls(d), d.warnings
    assert d.tip_radius_mm >= 1.25 * 0.3 - 1e-9
    assert "tip balls of at least" in d.design_choice and "fell short" in d.design_choice
