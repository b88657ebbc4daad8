"""The contact FEA's clearance correction (fea.verify._correct_cam): when the driving tooth
tip passes the ball closer than the tolerances allow at +-theta_max, the cam's flanks are
lengthened by the shortfall the FEA measured, on the same ring."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from springcad.config import job_from_dict
from springcad.config.consistency import min_rim_mm
from springcad.design.cam import (TIP_CLEARANCE_FACTOR, _tip_width_mm, _tooth_tip, flank_point,
                                  tip_clearance_mm, tooth_can_clear)
from springcad.design.job import design_job
from springcad.design.layout import ContactLimit, toleranced_layouts
from springcad.design.resize import with_cam_clearance
from springcad.design.shortfalls import soft_shortfalls
from springcad.design.sizing import _design_at


@pytest.fixture(scope="module")
def s1():
    """The default template's disk at 8 deg on its 4 mm plate: a cam whose tooth has room
    for longer flanks (at 14 deg it has none)."""
    job = job_from_dict({"material": {"name": "420_ht", "design_stress_MPa": 780},
                         "duty": {"preset": "static"},
                         "springs": {"S1": {"target_stiffness_Nm_per_rad": 150,
                                            "max_deflection_deg": 8, "outer_radius_mm": 36,
                                            "thickness_mm": 4.0}}})
    return design_job(job, explain=False).springs["S1"]


def test_a_longer_flank_reaches_the_asked_estimate_on_the_same_ring(s1):
    want = s1.cam_tip_clearance_mm + 0.030
    d = with_cam_clearance(s1, want)
    assert d.cam_overtravel > s1.cam_overtravel
    assert d.cam_tip_clearance_mm >= want
    # the estimate is the closed form at the chosen overtravel (an independent evaluation)
    assert d.cam_tip_clearance_mm == pytest.approx(tip_clearance_mm(
        d.contact_radius_mm, d.tip_radius_mm, d.manufacturing.w_gap_mm, d.max_deflection_rad,
        d.cam_overtravel, d.root_radius_mm), abs=1e-12)
    # the ring, so K and the stresses, is the same part; the cam's flank is longer
    assert d.ring is s1.ring and d.stiffness_beam_Nmm_per_rad == s1.stiffness_beam_Nmm_per_rad
    assert d.predicted_peak_stress_MPa == s1.predicted_peak_stress_MPa
    assert d.cam is not s1.cam
    # the shortest flank that reaches it: the next shorter candidate does not
    assert all(tip_clearance_mm(d.contact_radius_mm, d.tip_radius_mm, d.manufacturing.w_gap_mm,
                                d.max_deflection_rad, f, d.root_radius_mm) < want
               for f in (d.cam_overtravel - 0.05,) if f > s1.cam_overtravel)


def test_an_estimate_no_tooth_can_reach_is_said(s1):
    d = with_cam_clearance(s1, 5.0)  # 5 mm: far beyond any flank that leaves a tooth tip
    assert any(w.startswith("driving tooth tip passes close to the ball") and "5000 um needed"
               in w for w in d.warnings), d.warnings


def _contact(*gaps):
    end = SimpleNamespace(clearances=[SimpleNamespace(
        name=n, nominal_mm=nom, worst_case_mm=worst, stack_mm=stack,
        ok=worst > 0 and nom > stack) for n, nom, worst, stack in gaps])
    return SimpleNamespace(at_max=SimpleNamespace(ends={"+": end, "-": end}))


def test_the_shortfall_is_what_the_worst_case_and_nominal_gap_miss():
    from fea.verify import TIP_GAP_AIM, _tip_gaps_short_mm

    # held-out elbow spring: 4.7 um nominal, -15.3 um worst case, stack 20 um
    short = _tip_gaps_short_mm(_contact(("driving_tooth_tip/ball", 0.0047, -0.0153, 0.020),
                                        ("driving_tooth_tip/neck", 0.0652, -0.0135, 0.040),
                                        ("back_tooth_tip/neck", 0.001, -0.03, 0.040)))
    assert short == pytest.approx({
        "driving_tooth_tip/ball": max(TIP_GAP_AIM * 0.020 + 0.0153,
                                      (1 + TIP_GAP_AIM) * 0.020 - 0.0047),
        "driving_tooth_tip/neck": max(TIP_GAP_AIM * 0.040 + 0.0135,
                                      (1 + TIP_GAP_AIM) * 0.040 - 0.0652)})
    # passing gaps, or gaps a longer driving flank does not open, ask nothing of it
    assert _tip_gaps_short_mm(_contact(("driving_tooth_tip/ball", 0.050, 0.010, 0.020))) == {}
    assert _tip_gaps_short_mm(_contact(("pocket/ball", 0.005, -0.01, 0.02))) == {}
    assert _tip_gaps_short_mm(SimpleNamespace(at_max=None)) == {}


def test_a_layout_without_room_for_the_flank_is_redesigned_to_one_with_room():
    """The default template's disk at 14 deg on 12 mm, asked a gap estimate beyond what
    even a 3 x flank would give this layout: no flank of its tooth reaches it, so the cam
    correction asks the search for a layout whose cam does; the search passes over the
    layouts that cannot, and the spring keeps its target."""
    from springcad.config import job_from_dict
    from springcad.design.cam import LONG_OVERTRAVELS, TIP_CLEARANCE_SHORT
    from springcad.design.job import design_job
    from springcad.design.redesign import redesign_for_cam

    job = job_from_dict({"material": {"name": "420_ht", "design_stress_MPa": 780},
                         "duty": {"preset": "static"},
                         "springs": {"S1": {"target_stiffness_Nm_per_rad": 150,
                                            "max_deflection_deg": 14, "outer_radius_mm": 36,
                                            "thickness_mm": 12.0}}})
    d = design_job(job, explain=False).springs["S1"]
    def estimate(f):
        return tip_clearance_mm(d.contact_radius_mm, d.tip_radius_mm, d.manufacturing.w_gap_mm,
                                d.max_deflection_rad, f, d.root_radius_mm)

    # the first longer flank this layout's tooth has no room for
    beyond = next(f for f in LONG_OVERTRAVELS if f > d.cam_overtravel
                  and with_cam_clearance(d, estimate(f)).cam_overtravel != f)
    want = estimate(beyond)
    assert with_cam_clearance(d, want).cam_overtravel < beyond  # no room
    r = redesign_for_cam(d, want)
    assert r.cam_tip_clearance_mm >= want
    assert not any(w.startswith(TIP_CLEARANCE_SHORT) for w in r.warnings)
    assert (r.n_flexures, r.contact_radius_mm) != (d.n_flexures, d.contact_radius_mm)
    assert r.target_stiffness_Nmm_per_rad == d.target_stiffness_Nmm_per_rad
    assert r.spec.cam_min_tip_clearance_mm == want  # later width corrections keep the floor
    assert r.cam_min_tip_clearance_mm == want


def test_the_tooth_tip_width_is_signed_and_is_the_closed_form():
    """Tooth tip width |q| (pi - 2 phi_q + 2 pi / N) at the flank's end q (the pocket's
    mirror image one pitch on): positive while the tooth has a tip, negative once the
    flank runs past the next tooth's (read as |width| before, a 2.4 mm "tip" on a cam
    whose contour crossed itself)."""
    rc, rho = 10.0, 0.35
    for n, psi_end, sign in ((40, rho / rc + 0.10, 1), (80, rho / rc + 0.60, -1)):
        q = flank_point(psi_end, rc, rho)
        phi = math.atan2(q[1], q[0])
        by_hand = float(np.hypot(*q)) * (math.pi - 2 * phi + 2 * math.pi / n)
        w = _tip_width_mm(_tooth_tip(q, 2 * math.pi / n))
        assert w == pytest.approx(by_hand, rel=1e-12)
        assert math.copysign(1, w) == sign


def test_a_layout_whose_tooth_cannot_clear_the_ball_moves_to_a_larger_contact_radius():
    """A 580 N*m/rad maraging disk at 14 deg, R_o 53, 3.5 mm: the ranked layout (N 59 at
    the r_c of the longest straight reach) leaves no flank length whose tooth tip is both
    min_web_mm wide and 1.25 x the tolerances clear of the ball at full deflection (kept
    with a 2 um gap before). The search moves the same N to the smallest larger r_c whose
    tooth can, and the design has no shortfall; the gap, by the closed form, clears."""
    job = job_from_dict({"material": {"name": "maraging_300", "design_stress_MPa": 1040},
                         "duty": {"preset": "static"},
                         "springs": {"B": {"target_stiffness_Nm_per_rad": 580,
                                           "max_deflection_deg": 14, "outer_radius_mm": 53,
                                           "thickness_mm": 3.5}}})
    spec, mat, mfg = job.springs["B"], job.material, job.manufacturing
    need = TIP_CLEARANCE_FACTOR * (mfg.t_spring_mm + mfg.t_shaft_mm)
    E = mat.material.youngs_modulus_MPa
    rr_max = spec.outer_radius_mm - min_rim_mm(spec.outer_radius_mm, mfg, job.hardware)
    ranked = toleranced_layouts(spec, mat.design_stress_MPa, E, rr_max,
                                ContactLimit.of(mat, spec.max_deflection_rad, mfg))[0][0]
    assert not tooth_can_clear(ranked.rc, ranked.rb, mfg.w_gap_mm, ranked.n,
                               spec.max_deflection_rad, mfg.min_web_mm, need, ranked.rr)
    d = _design_at(spec, mat, mfg, job.hardware)
    assert d.n_flexures == ranked.n
    assert ranked.rc < d.contact_radius_mm <= 1.3 * ranked.rc
    assert tooth_can_clear(d.contact_radius_mm, d.tip_radius_mm, mfg.w_gap_mm, d.n_flexures,
                           spec.max_deflection_rad, mfg.min_web_mm, need, d.root_radius_mm)
    full = design_job(job, explain=False).springs["B"]
    assert not soft_shortfalls(full), soft_shortfalls(full)
    assert tip_clearance_mm(full.contact_radius_mm, full.tip_radius_mm, mfg.w_gap_mm,
                            full.max_deflection_rad, full.cam_overtravel,
                            full.root_radius_mm) >= need


def test_the_pocket_gap_at_the_cusp_is_short_by_the_closed_form_and_within_the_resolution():
    """The pocket arc passes through the flank's cusp, R(psi*) (0, r_c) with psi* = rho / r_c:
    its radius about the ball centre is 2 r_c sin(psi* / 2), short of rho = r_b + w_gap by
    rho psi*^2 / 24 to leading order. A 1 mm ball at r_c 8 mm (held-out B 5507 016, both
    fixed by the user) leaves 0.73 um: within the 1 um the solids' B-rep check resolves
    (GAP_RESOLUTION_MM), where the design's old 0.5 um refused every layout of the spec."""
    from springcad.design.cam import GAP_RESOLUTION_MM, _unit
    from springcad.geometry.checks import CLEARANCE_TOL_MM

    rc, rb, g, n = 8.0, 1.0, 0.04, 20
    rho = rb + g
    psi0 = rho / rc
    segs, feats, _ = _unit(rc, rho, 2 * math.pi / n, psi0 + 0.1)
    pocket = next(s for s, f in zip(segs, feats) if f.kind == "pocket")
    deficit = rho - pocket.radius
    assert deficit == pytest.approx(rho - 2 * rc * math.sin(psi0 / 2), rel=1e-9)
    assert deficit == pytest.approx(rho * psi0 ** 2 / 24, rel=0.01)
    assert 0.5e-3 < deficit < GAP_RESOLUTION_MM == CLEARANCE_TOL_MM
    job = job_from_dict({"material": {"name": "maraging_300", "safety_factor": 1.5},
                         "duty": {"preset": "static"},
                         "springs": {"A": {"target_stiffness_Nm_per_rad": 238,
                                           "max_deflection_deg": 4.286, "outer_radius_mm": 60,
                                           "thickness_mm": 6.0, "tip_radius_mm": rb,
                                           "contact_radius_mm": rc}},
                         "manufacturing": {"w_gap_mm": g}})
    d = design_job(job, explain=False).springs["A"]
    assert (d.tip_radius_mm, d.contact_radius_mm) == (rb, rc)
