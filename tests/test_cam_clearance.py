"""The contact FEA's clearance correction (fea.verify._correct_cam): when the driving tooth
tip passes the ball closer than the tolerances allow at +-theta_max, the cam's flanks are
lengthened by the shortfall the FEA measured, on the same ring."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from springcad.design.cam import tip_clearance_mm
from springcad.design.resize import with_cam_clearance


@pytest.fixture(scope="module")
def s1():
    """The default template's disk at 8 deg on its 4 mm plate: a cam whose tooth has room
    for longer flanks (at 14 deg it has none)."""
    from springcad.config import job_from_dict
    from springcad.design.job import design_job

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
        d.cam_overtravel), abs=1e-12)
    # the ring, so K and the stresses, is the same part; the cam's flank is longer
    assert d.ring is s1.ring and d.stiffness_beam_Nmm_per_rad == s1.stiffness_beam_Nmm_per_rad
    assert d.predicted_peak_stress_MPa == s1.predicted_peak_stress_MPa
    assert d.cam is not s1.cam
    # the shortest flank that reaches it: the next shorter candidate does not
    assert all(tip_clearance_mm(d.contact_radius_mm, d.tip_radius_mm, d.manufacturing.w_gap_mm,
                                d.max_deflection_rad, f) < want
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
                                d.max_deflection_rad, f)

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
