"""A layout whose wire-EDM minimum webs hold its stiffness above the target is passed over
by the design search, not left to the FEA correction (a held-out spring, 17-4PH, 26.5 x 7.7 mm,
96 N*m/rad at 7.8 deg, designed 10 % stiff with a warning and verified +5.8 % after four
corrections: a late failure)."""

import math
from dataclasses import replace

import pytest

from springcad.config import job_from_dict
from springcad.design.layout import MAX_CANDIDATES
from springcad.design.resize import (STIFFNESS_ROOM, WebsHoldStiffness, onto_beam_stiffness,
                                     stiffness_out_of_reach)
from springcad.design.search import _first_passing, design_spring, kept_layouts
from springcad.errors import DesignError


def _job(**spring):
    return job_from_dict({
        "job": {"name": "webs", "description": "stiff webs"},
        "material": {"name": "17-4ph_h900", "safety_factor": 1.3},
        "springs": {"S1": {"target_stiffness_Nm_per_rad": 96, "max_deflection_deg": 7.833,
                           "outer_radius_mm": 26.5, "thickness_mm": 7.7, **spring}},
        "manufacturing": {"process": "wire_edm", "t_spring_mm": 0.05, "t_shaft_mm": 0.02,
                          "w_gap_mm": 0.025, "surface": "shot_peened"},
        "stack": {"sequence": ["S1", "S1", "S1"], "input": "rim"},
        "hardware": {"fastener": "dowel", "fastener_diameter_mm": 2.0},
        "duty": {"preset": "static"}})


def _design(job):
    return design_spring(job.springs["S1"], job.material, job.manufacturing, job.hardware,
                         explain=False)


def test_a_design_with_room_passes_and_webs_that_carry_the_stiffness_do_not():
    """The default template's spring: on target, and 0.9 x the widths lower K by 27 % (beam
    theory, K ~ w^3 away from the webs): room. The same spring with webs as wide as its
    flexures' mid-span widths keeps K where it is: no room, and the reason names the web."""
    from pathlib import Path

    from springcad.config import load_job
    from springcad.design.job import design_job

    d = design_job(load_job(Path(__file__).parents[1] / "templates" / "default.toml"),
                   explain=False).springs["S1"]
    assert stiffness_out_of_reach(d) == ""
    narrower = replace(d, width_scale=0.9 * d.width_scale).beam_stiffness_Nmm_per_rad()
    assert narrower < (1 - STIFFNESS_ROOM) * d.target_stiffness_Nmm_per_rad
    mid = float(d.width_mm(0.5 * (d.contact_radius_mm + d.root_radius_mm)))
    webbed = replace(d, manufacturing=replace(d.manufacturing, min_web_mm=2.0 * mid))
    why = stiffness_out_of_reach(webbed)
    assert "minimum web" in why and "from the target" in why
    # the FEA correction's test of a rescale: the default's widths x0.9 move K as asked
    # (K ~ w^3), the webbed spring's barely (it is redesigned instead)
    from fea.verify import _web_bound

    def at(design, scale):  # the spring at a width scale, its beam stiffness recomputed
        s = replace(design, width_scale=scale * d.width_scale)
        return replace(s, stiffness_beam_Nmm_per_rad=s.beam_stiffness_Nmm_per_rad())

    asked = 0.9 ** 3
    assert not _web_bound(at(d, 1.0), at(d, 0.9), asked)
    assert _web_bound(at(webbed, 1.0), at(webbed, 0.9), asked)
    assert not _web_bound(at(webbed, 1.0), at(webbed, 1.0), 1.05)  # stiffening: never


def test_the_search_passes_over_layouts_the_webs_hold_stiff():
    """The held-out spec designs no layout: refused at design, and among the layouts passed
    over are ones whose webs hold the stiffness above the target (the others fall short of
    the stress or the area ratio once their widths are brought onto it); with a lower
    stiffness's room it designs, on target in beam theory."""
    job = _job()
    # the layouts designed once for both (search.kept_layouts: the same arguments give the
    # same design, tests/test_search_speedups.py): the refusal's search and the list of
    # layouts it passed over
    with kept_layouts():
        with pytest.raises(DesignError):
            _design(job)
        d, rejected, *_ = _first_passing(job.springs["S1"], job.material, job.manufacturing,
                                         job.hardware, math.inf, MAX_CANDIDATES)
    assert d is None
    assert any(isinstance(err, WebsHoldStiffness) for _, err, _ in rejected)
    d = _design(_job(outer_radius_mm=32.0))
    assert stiffness_out_of_reach(d) == ""
    assert d.beam_stiffness_Nmm_per_rad() == pytest.approx(d.target_stiffness_Nmm_per_rad,
                                                          rel=0.01)


def test_widths_are_brought_onto_the_target_where_the_webs_carry_much_of_the_stiffness():
    """With webs as wide as the mid-span flexure, K no longer grows as scale^3: the
    cube-root update of two passes stops short (+2.6 % here; the held-out 13.5 mm disk kept
    +5.6 %); the secant lands within 1e-5 with narrower flexures. Webs wider still carry
    more than the target alone: the narrowest scale tried (1/4) is returned, still stiff,
    for the search's web rule to refuse."""
    from pathlib import Path

    from springcad.config import load_job
    from springcad.design.job import design_job

    d = design_job(load_job(Path(__file__).parents[1] / "templates" / "default.toml"),
                   explain=False).springs["S1"]
    mid = float(d.width_mm(0.5 * (d.contact_radius_mm + d.root_radius_mm)))
    webbed = replace(d, manufacturing=replace(d.manufacturing, min_web_mm=mid))
    target = d.target_stiffness_Nmm_per_rad
    k0 = webbed.beam_stiffness_Nmm_per_rad()
    assert k0 > 1.02 * target  # the webs stiffen it
    cube = webbed
    for _ in range(2):  # the former update
        cube = replace(cube, width_scale=cube.width_scale
                       * (target / cube.beam_stiffness_Nmm_per_rad()) ** (1 / 3))
    assert abs(cube.beam_stiffness_Nmm_per_rad() / target - 1) > 1e-3
    on = onto_beam_stiffness(webbed, target)
    assert on.beam_stiffness_Nmm_per_rad() == pytest.approx(target, rel=1e-5)
    assert on.width_scale < webbed.width_scale
    walled = replace(d, manufacturing=replace(d.manufacturing, min_web_mm=1.5 * mid))
    on = onto_beam_stiffness(walled, target)
    assert on.width_scale == pytest.approx(walled.width_scale / 4)
    assert stiffness_out_of_reach(on) != ""


@pytest.mark.slow
def test_root_fillets_of_short_flexures_are_counted_against_the_correction_room(monkeypatch):
    """A small soft disk on a thick plate (R_o 12.5 mm, 6 mm, 9 N*m/rad, 8 deg): its first
    layout has 13 straight flexures 6.2 mm long, 0.55 mm wide at the root, with R1.23 root
    fillets. Beam theory puts it on target; the FEA (2D, plane stress) finds it tens of %
    stiffer, and narrower flexures leave the tips at the minimum web: the correction cannot
    bring it down (before: a build that failed after four corrections). The fillets' widening
    in the beam integral explains most of the FEA's excess, and with it the layout is passed
    over at design time."""
    from fea.calibrate import solve_2d
    from springcad.design import resize

    job = job_from_dict({
        "material": {"name": "420_ht", "safety_factor": 1.2},
        "springs": {"S1": {"target_stiffness_Nm_per_rad": 9, "max_deflection_deg": 8,
                           "outer_radius_mm": 12.5, "thickness_mm": 6.0, "tip_radius_mm": 0.3}},
        "stack": {"sequence": ["S1"], "input": "rim"},
        "hardware": {"fastener": "bolt", "fastener_diameter_mm": 2.5, "fastener_count": 6,
                     "shaft_diameter_mm": 3.0}})
    with monkeypatch.context() as m:  # the search as it was: the width law alone
        m.setattr(resize, "root_fillet_stiffening", lambda design: 1.0)
        old = _design(job)
    assert old.root_fillet_radius_mm > 1.5 * old.root_width_mm
    fea_over_beam = solve_2d(old, level=1).stiffness_Nmm_per_rad / old.stiffness_beam_Nmm_per_rad
    fillets = resize.root_fillet_stiffening(old)
    assert fea_over_beam > 1.25 and 1.0 < fillets < fea_over_beam
    assert fillets - 1.0 > 0.5 * (fea_over_beam - 1.0)
    why = stiffness_out_of_reach(old)
    assert "root fillets" in why and "minimum web" in why, why
    try:
        new = _design(job)
    except DesignError:
        return  # refused at design time
    assert stiffness_out_of_reach(new) == ""
    assert (new.n_flexures, new.contact_radius_mm) != (old.n_flexures, old.contact_radius_mm)
