"""Rim pins carry the stack torque: shear, bending over the spacer gap and bearing, by hand."""

import math

import pytest

from springcad.design.joint_strength import (DOWEL_SHEAR_STRENGTH_MPA, PIN_SAFETY_FACTOR,
                                             UNEVEN_SHARE, pin_strength)
from springcad.errors import DesignError
from tests.geometry.cad_fixtures import design, job_data


def test_pin_stresses_by_hand():
    """10 N*m through 4 Ø2 dowels on R20 over a 0.5 mm gap, 3 mm engaged in 1000 MPa rims:
    F = 1.5 * 10000 / (4 * 20) = 187.5 N; shear 4F / (pi d^2) = 59.68 MPa; bending
    16 F g / (pi d^3) = 59.68 MPa (4 g / d = 1); equivalent sqrt(59.68^2 + 3 * 59.68^2) =
    119.37 MPa against sqrt(3) 1047 / 2 = 906.73; bearing F / (d e) = 31.25 against 500."""
    assert UNEVEN_SHARE == 1.5 and PIN_SAFETY_FACTOR == 2.0 and DOWEL_SHEAR_STRENGTH_MPA == 1047
    s = pin_strength("dowels_1", "dowel", 4, 2.0, 20.0, 0.5, 3.0, 10000.0, 1000.0)
    assert s.force_N == pytest.approx(187.5)
    assert s.shear_MPa == pytest.approx(750.0 / (4 * math.pi), rel=1e-12)
    assert s.bending_MPa == pytest.approx(s.shear_MPa, rel=1e-12)
    assert s.equivalent_MPa == pytest.approx(2 * 750.0 / (4 * math.pi), rel=1e-12)
    assert s.allowable_MPa == pytest.approx(906.7287, abs=1e-3)
    assert (s.bearing_MPa, s.bearing_allowable_MPa) == pytest.approx((31.25, 500.0))
    assert s.ok and s.utilisation == pytest.approx(119.3662 / 906.7287, rel=1e-6)


def test_screw_shears_on_its_minor_diameter():
    """M2.5 (pitch 0.45): d3 = 2.5 - 1.22687 * 0.45 = 1.94791 mm; 12.9 shear 0.6 * 1220."""
    s = pin_strength("bolts_1", "bolt", 4, 2.5, 20.0, 0.5, 3.0, 10000.0, 1000.0)
    d3 = 2.5 - 1.22687 * 0.45
    assert s.shear_MPa == pytest.approx(187.5 / (math.pi * d3 ** 2 / 4), rel=1e-9)
    assert s.allowable_MPa == pytest.approx(math.sqrt(3) * 732.0 / 2, rel=1e-12)
    assert s.bearing_MPa == pytest.approx(187.5 / (2.5 * 3.0))  # the nominal diameter bears


@pytest.mark.parametrize("job", ["default", "4xS1"])
def test_templates_pins_hold_with_their_numbers(job):
    """The templates' dowels carry their stack torque (design.json rim_pins), at the torque
    design.json reports at the stack's limit."""
    d = design(job)
    stack = d.stack.to_dict()
    pins = stack["rim_pins"]
    assert pins and all(p["ok"] for p in pins)
    for p in pins:
        assert p["torque_Nmm"] == pytest.approx(1000 * stack["torque_at_limit_Nm"], rel=1e-9)
        assert p["force_N"] == pytest.approx(
            1.5 * p["torque_Nmm"] / (p["count"] * p["radius_mm"]), rel=1e-12)
        assert p["gap_mm"] == pytest.approx(d.job.hardware.rim_spacer_thickness_mm)


def test_too_few_pins_are_refused_with_the_change():
    """2 x S1 (41.9 N*m) on two Ø1.5 dowels: 974 N a pin; over the 0.4 mm gap shear
    4 F / (pi d^2) = 551 MPa, bending 32 F (g / 2) / (pi d^3) = 588 MPa, equivalent
    sqrt(588^2 + 3 x 551^2) = 1122 MPa > 907; the refusal names 3 pins
    (ceil(2 x 1122 / 907)), which hold, and the stack torque two pins carry
    (41.9 x 907 / 1122 = 33.9 N*m). Two Ø2 dowels would hold the torque, but their wider
    rim leaves the paper's fixed layout (N, r_c and ball) no flexure: the refusal does not
    name them, and they do not design."""
    from springcad.config import job_from_dict
    from springcad.design.job import design_job

    with pytest.raises(DesignError) as err:
        design_job(job_from_dict(job_data(["S1", "S1"], hardware={"fastener_count": 2})))
    msg = str(err.value)
    assert "2 x Ø1.5 dowels" in msg and "equivalent 1122 MPa against 907" in msg, msg
    assert "use hardware.fastener_count = 3 (now 2; Ø1.5 dowels)" in msg, msg
    assert "a stack torque of at most 33.9 N*m" in msg, msg
    assert "fastener_diameter_mm" not in msg, msg
    ok = design_job(job_from_dict(job_data(["S1", "S1"], hardware={"fastener_count": 3})))
    assert 0.8 < ok.stack.to_dict()["rim_pins"][0]["utilisation"] < 1.0
    with pytest.raises(DesignError, match="spring 'S1'"):
        design_job(job_from_dict(job_data(
            ["S1", "S1"], hardware={"fastener_count": 2, "fastener_diameter_mm": 2.0})),
            explain=False)


def test_many_more_pins_name_a_larger_size_first_and_it_holds():
    """2 x S1 on three Ø1 dowels: 2188 MPa against 907 needs eight of them (the equivalent
    stress grows as 1/d^3); so many holes crowd the rim, so the refusal names a larger
    catalogue dowel first, and that change alone designs."""
    import re

    from springcad.config import job_from_dict
    from springcad.design.job import design_job

    hw = {"fastener_count": 3, "fastener_diameter_mm": 1.0}
    with pytest.raises(DesignError) as err:
        design_job(job_from_dict(job_data(["S1", "S1"], hardware=hw)))
    msg = str(err.value)
    first = re.search(r"use hardware\.(\w+) = ([\d.]+)", msg)
    assert first and first.group(1) == "fastener_diameter_mm", msg
    count = re.search(r"hardware\.fastener_count = (\d+)", msg)
    assert count is None or int(count.group(1)) > 1.5 * 3, msg
    ok = design_job(job_from_dict(job_data(
        ["S1", "S1"], hardware={**hw, "fastener_diameter_mm": float(first.group(2))})))
    assert all(p["ok"] for p in ok.stack.to_dict()["rim_pins"])
