"""The paper's numbers and the reference tool's check values come out of springcad.

References: shared/paper/series-torsion-springs.md (Section II-B, Tables I and II),
shared/data/*.csv, shared/notes/design-method.md (S1 check value).
"""

import csv
import math

import pytest

from springcad.design.stack import eq10_limit, series_stiffness
from springcad.design.tolerance import backlash_rad, gap_range_mm
from tests.conftest import PAPER_DATA

TABLE1 = {row["configuration"]: row for row in csv.DictReader(
    open(PAPER_DATA / "paper_table1_configurations.csv"))}
TABLE2 = {row["manufacturer"]: row for row in csv.DictReader(
    open(PAPER_DATA / "paper_table2_manufacturers.csv"))}
TEMPLATE_OF = {"S1": "paper_S1", "S2": "paper_S2", "2xS1": "paper_2xS1", "2xS2": "paper_2xS2",
               "4xS1": "paper_4xS1", "S1+2xS2": "paper_S1_2xS2", "S2+3xS1": "paper_S2_3xS1"}


def test_backlash_range_of_section_2b():
    """t_spring = t_shaft = 0.03 mm, w_gap = 0.025 mm, r_c = 5.5 mm -> [-0.0127, 0.0309] rad."""
    d_min, d_nom, d_max = gap_range_mm(0.025, 0.03, 0.03)
    assert (d_min, d_max) == pytest.approx((-0.07, 0.17))
    assert float(backlash_rad(d_min, 5.5)) == pytest.approx(-0.0127, abs=5e-5)
    assert float(backlash_rad(d_max, 5.5)) == pytest.approx(0.0309, abs=5e-5)
    assert float(backlash_rad(d_nom, 5.5)) == pytest.approx(0.00909, abs=5e-6)  # design-method.md 13


@pytest.mark.parametrize("mfr", ["Mfr1", "Mfr2"])
def test_table2_max_expected_backlash(paper_designs, mfr):
    row = TABLE2[mfr]
    stack = paper_designs[f"paper_4xS1_{mfr.lower()}"].stack
    assert stack.springs[0].manufacturing.t_shaft_mm == float(row["t_shaft_mm"])
    assert stack.springs[0].manufacturing.t_spring_mm == float(row["t_spring_mm"])
    # the paper rounds to three significant figures
    assert stack.backlash.worst_max == pytest.approx(float(row["max_expected_backlash_rad"]), rel=2e-3)


@pytest.mark.parametrize("config", list(TEMPLATE_OF))
def test_series_targets_and_eq10(paper_designs, config):
    row = TABLE1[config]
    stack = paper_designs[TEMPLATE_OF[config]].stack
    target = stack.target_stiffness_Nmm_per_rad / 1000
    assert target == pytest.approx(float(row["target_stiffness_Nm_per_rad"]), rel=1e-9)
    # beam theory of the generated geometry meets the target
    assert stack.stiffness_Nmm_per_rad / 1000 == pytest.approx(target, rel=1e-3)
    # eq. 10 by hand from the springs' targets and limits
    limits = [s.max_deflection_rad for s in stack.springs]
    ks = [s.target_stiffness_Nmm_per_rad for s in stack.springs]
    by_hand = min(t * k for t, k in zip(limits, ks)) * sum(1 / k for k in ks)
    assert stack.max_deflection_rad == pytest.approx(by_hand, rel=1e-3)
    table = float(row["max_deflection_limit_rad"])
    if len(set(stack.sequence)) == 1:
        assert stack.max_deflection_rad == pytest.approx(table, abs=6e-4)
        assert not any("eq. 10" in n for n in stack.notes())
    else:
        # Table I lists the plain sum of the limits for the mixed stacks; eq. 10 is lower
        assert stack.sum_of_limits_rad == pytest.approx(table, abs=6e-4)
        assert stack.max_deflection_rad < table - 0.05
        assert any("eq. 10" in n and "S2 reaches its limit first" in n for n in stack.notes())


def test_series_stiffness_and_eq10_closed_forms():
    assert series_stiffness([150, 150]) == pytest.approx(75)
    assert series_stiffness([150, 75, 75]) == pytest.approx(30)
    limit, torque, shares = eq10_limit([0.279, 0.349, 0.349], [150, 75, 75])
    assert torque == pytest.approx(75 * 0.349)
    assert shares == pytest.approx((75 * 0.349 / 150, 0.349, 0.349))
    assert limit == pytest.approx(sum(shares))


def test_s1_check_values_of_design_method(paper_designs):
    """design-method.md: N = 28, R_r 30.99, w0 3.18, theta_s 0.242 (13.9 deg), s 1.238,
    F 272 N, peak torque 41.9 N*m, energy 5.85 J, 0.37 J/cm^3, 70 J/kg (within 1 %)."""
    s = paper_designs["paper_S1"].springs["S1"]
    assert s.n_flexures == 28
    assert s.root_radius_mm == pytest.approx(30.99, rel=1e-3)
    assert s.root_width_mm == pytest.approx(3.18, rel=1e-2)
    assert s.straight_limit_rad == pytest.approx(0.242, rel=1e-2)
    assert math.degrees(s.straight_limit_rad) == pytest.approx(13.9, rel=1e-2)
    assert s.serpentine_factor == pytest.approx(1.238, rel=1e-2)
    assert s.tip_load_N == pytest.approx(272, rel=1e-2)
    assert s.peak_torque_Nmm / 1000 == pytest.approx(41.9, rel=1e-2)
    assert s.energy_J == pytest.approx(5.85, rel=1e-2)
    assert s.energy_density_J_per_cm3 == pytest.approx(0.37, rel=1e-2)
    # the reference counts flexure law area + rim; springcad's mass is the exact profile
    # (root fillets, tip balls, neck fillets added, dowel holes removed): both within 1 %
    ref_mass = s.model_area_mm2 * s.thickness_mm * s.material.material.density_kg_per_mm3
    assert s.energy_J / ref_mass == pytest.approx(70, rel=1e-2)
    assert s.specific_energy_J_per_kg == pytest.approx(70, rel=1e-2)
    assert s.profile_area_mm2 == pytest.approx(s.model_area_mm2, rel=1e-2)


def test_s2_is_the_same_family(paper_designs):
    s1 = paper_designs["paper_S1"].springs["S1"]
    s2 = paper_designs["paper_S2"].springs["S2"]
    for attr in ("n_flexures", "contact_radius_mm", "outer_radius_mm", "tip_radius_mm"):
        assert getattr(s1, attr) == getattr(s2, attr)  # one camshaft and housing fit both
    assert s2.stiffness_beam_Nmm_per_rad == pytest.approx(75_000, rel=1e-3)
