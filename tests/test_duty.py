"""The duty: rainflow counting, Goodman and Miner against hand calculations, the config.

References: ASTM E1049-85 (reapproved 2017) sec. 5.4.4 and its Fig. 6 / Table 4 example
for the counting; Shigley's Mechanical Engineering Design (Eq. 6-13 to 6-15, 6-27,
Table 6-5) for the S-N line, the reliability factor and the modified Goodman line.
"""

import math
import tomllib
from collections import Counter

import pytest

from springcad.config import job_from_dict
from springcad.config.schema import DUTY_PRESETS, SURFACES
from springcad.config.specs import DutyBlock, DutySpec
from springcad.design import duty, fatigue
from springcad.errors import ConfigError
from tests.conftest import template


def test_rainflow_counts_the_astm_e1049_example():
    """ASTM E1049 Fig. 6: loads -2, 1, -3, 5, -1, 3, -4, 4, -2 give (Table 4) range 9: 0.5,
    8: 1.0, 6: 0.5, 4: 1.5, 3: 0.5 cycles (10, 7 and 5: none)."""
    counts = Counter()
    for rng, _, n in duty.rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2]):
        counts[rng] += n
    assert dict(counts) == {9.0: 0.5, 8.0: 1.0, 6.0: 0.5, 4.0: 1.5, 3.0: 0.5}


def test_rainflow_of_a_repeated_sine_is_its_cycles():
    """A sampled sine of 50 periods about 0.2: 49 full cycles + 2 half cycles of range 1.4."""
    xs = [0.2 + 0.7 * math.sin(2 * math.pi * k / 40) for k in range(50 * 40 + 1)]
    bl = duty.series_blocks(xs, "fraction", repeats=10)
    total = sum(b.cycles for b in bl if abs(b.amplitude - 0.7) < 1e-9)
    assert total == pytest.approx(10 * 50, abs=10 * 1.0)
    assert all(abs(b.mean - 0.2) < 1e-6 for b in bl if b.amplitude > 0.6)


def test_reliability_factor_is_shigley_table_6_5():
    for r, ke in ((0.5, 1.000), (0.9, 0.897), (0.95, 0.868), (0.99, 0.814), (0.999, 0.753)):
        assert fatigue.reliability_factor(r) == pytest.approx(ke, abs=1.5e-3)


def test_goodman_and_miner_of_a_spectrum_against_a_hand_calculation():
    """Two blocks on 420_ht with skim-cut faces at 99 % reliability, peak 800 MPa at
    theta_max, written out by hand from the handbook numbers (not from springcad's code).

    S_e = 700 MPa x 0.70 (skim cuts) x 1.0 (size) x 0.814 (99 %, Shigley Table 6-5)
        = 398.9 MPa;  f S_ut = 0.77 x 1720 = 1324.4 MPa at 1e3 cycles
    b = log10(398.9 / 1324.4) / (7 - 3) = -0.13026;  N(S) = 1e3 (S / 1324.4)^(1/b)
    block A, 1e6 cycles of 0.2 +- 0.6 theta_max: s_a = 480, s_m = 160 MPa,
        Goodman s_ar = 480 / (1 - 160/1720) = 529.23 MPa -> N_A = 1e3 x (529.23/1324.4)^(-7.677)
        = 1.142e6;  D_A = 0.8757
    block B, 1e4 cycles of +-1.0 theta_max: s_ar = 800 MPa -> N_B = 4.806e4, D_B = 0.2081
    Miner D = 1.0838 > 1: the duty fails at 800 MPa.
    """
    d = DutySpec(preset=None, blocks=(DutyBlock(1e6, 0.6, 0.2), DutyBlock(1e4, 1.0, 0.0)),
                 surface="edm_skim_cuts", reliability=0.99, safety_factor=1.2)
    c = duty.check(d, "420_ht", 800.0, math.radians(10))
    assert c.curve.endurance_limit_MPa == pytest.approx(398.9, rel=2e-3)
    a, b = c.blocks
    assert (a.amplitude_MPa, a.mean_MPa) == pytest.approx((480.0, 160.0))
    assert a.equivalent_amplitude_MPa == pytest.approx(529.23, rel=1e-4)
    assert a.life_cycles == pytest.approx(1.142e6, rel=0.02)
    assert b.life_cycles == pytest.approx(4.806e4, rel=0.02)
    assert c.miner_sum == pytest.approx(1.0838, rel=0.02)
    assert not c.met
    # the safety factor n: the stresses x n give D = 1; by hand, D(n) at the found n
    n = c.safety_factor
    se, f_sut = 700 * 0.70 * fatigue.reliability_factor(0.99), 0.77 * 1720
    bexp = math.log10(se / f_sut) / 4

    def life(s):
        return math.inf if s < se else 1e3 * (s / f_sut) ** (1 / bexp)
    hand = 1e6 / life(n * 480 / (1 - n * 160 / 1720)) + 1e4 / life(n * 800)
    assert hand == pytest.approx(1.0, rel=1e-6)
    assert n < 1.0
    # allowed peak: the same duty met with its factor 1.2; rated deflection scales alike
    assert c.allowed_peak_MPa == pytest.approx(800 * n / 1.2, rel=1e-6)
    assert c.rated_deflection_rad == pytest.approx(math.radians(10) * n / 1.2, rel=1e-9)
    # life at +-theta_max is block B's life per cycle
    assert c.life_at_max_cycles == pytest.approx(b.life_cycles)


def test_below_the_endurance_limit_no_damage_and_the_allowed_peak_meets_the_duty():
    d = DutySpec()  # the default duty
    th = math.radians(14)
    allowed = duty.check(d, "420_ht", 1.0, th).allowed_peak_MPa
    at = duty.check(d, "420_ht", allowed, th)
    assert at.met and at.safety_factor == pytest.approx(d.safety_factor, rel=1e-6)
    above = duty.check(d, "420_ht", allowed * 1.01, th)
    assert not above.met
    low = duty.check(d, "420_ht", 100.0, th)
    assert low.miner_sum == 0.0 and math.isinf(low.life_at_max_cycles)


def test_required_margin_is_the_stricter_of_yield_and_duty():
    data = tomllib.loads(template("default").read_text())
    data.pop("duty", None)
    undeclared = job_from_dict(data).material
    th = math.radians(14)
    # springcad's default duty is reported and gates the release, but does not size
    assert not undeclared.duty.declared
    assert duty.required_margin(undeclared, th) == undeclared.safety_factor
    m = job_from_dict({**data, "duty": {"preset": "robot_joint"}}).material
    allowed = duty.allowed_peak_MPa(m, th)
    assert duty.required_margin(m, th) == pytest.approx(
        max(m.safety_factor, m.material.yield_strength_MPa / allowed))
    assert duty.required_margin(m, th) > 1.5 * m.safety_factor
    static = job_from_dict({**tomllib.loads(template("default").read_text()),
                            "duty": {"preset": "static"}}).material
    assert duty.required_margin(static, th) >= static.safety_factor


def test_presets_and_surfaces_are_declared_once():
    assert set(DUTY_PRESETS) == set(duty.PRESETS)
    assert set(SURFACES) == set(fatigue.surface_table())
    for name, (bl, src, _) in duty.PRESETS.items():
        assert src and all(abs(b.mean) + b.amplitude <= 1.0 for b in bl), name
    for s in fatigue.surface_table().values():
        assert 0.3 < s.factor <= 1.0 and s.source and s.drawing_note


def _job(**duty_table):
    data = tomllib.loads(template("paper_S1").read_text())
    data["duty"] = duty_table
    return job_from_dict(data)


def test_duty_config_blocks_preset_and_file(tmp_path):
    j = _job(blocks=[{"cycles": 1e7, "amplitude_fraction": 0.5},
                     {"cycles": 1e3, "amplitude_deg": 8.0, "mean_deg": 8.0}])
    assert j.material.duty.declared and len(j.material.duty.blocks) == 2
    bl = duty.blocks(j.material.duty, math.radians(16))
    assert bl[1].amplitude == pytest.approx(0.5) and bl[1].mean == pytest.approx(0.5)
    assert _job(preset="prosthesis").material.duty.preset == "prosthesis"
    f = tmp_path / "angle.csv"
    f.write_text("time_s,angle_deg\n0,0\n1,10\n2,-10\n3,10\n4,0\n")
    data = tomllib.loads(template("paper_S1").read_text())
    data["duty"] = {"file": "angle.csv", "file_repeats": 1e6}
    j = job_from_dict(data, source=str(tmp_path / "job.toml"))
    bl = duty.blocks(j.material.duty, math.radians(16))
    # by hand (ASTM 5.4.4): 0,10,-10 counts 0-10 as a half cycle; 10,-10,10 counts -10-10 as a
    # half; the residue -10,10,0 gives the halves -10-10 and 10-0: range 20 deg x 1 cycle and
    # range 10 deg x 1 cycle per record, x 1e6 records
    got = {round(b.amplitude * 16, 9): b.cycles for b in bl}
    assert got == {10.0: pytest.approx(1e6), 5.0: pytest.approx(1e6)}


@pytest.mark.parametrize("table,match", [
    ({"preset": "jogging"}, "duty.preset.*one of"),
    ({"preset": "static", "blocks": [{"cycles": 1, "amplitude_fraction": 1}]},
     "one of preset, blocks or file"),
    ({"blocks": [{"cycles": 10}]}, "exactly one of amplitude_fraction"),
    ({"blocks": [{"cycles": 10, "amplitude_fraction": 0.8, "mean_fraction": 0.5}]},
     "within \\+-theta_max"),
    ({"blocks": [{"cycles": 10, "amplitude_deg": 20}]}, "beyond spring S1's max_deflection 16"),
    ({"blocks": [{"cycles": 10, "amplitude_deg": 5, "mean_fraction": 0.1}]}, "mean_deg"),
    ({"blocks": []}, "at least one"),
    ({"file": "missing.csv"}, "duty.file.*cannot be read"),
    ({"preset": "static", "file_repeats": 3}, "only with duty.file"),
    ({"safety_factor": 0.5}, "duty.safety_factor.*from 1 to 5"),
    ({"reliability": 1.0}, "duty.reliability"),
    ({"cycles": 5}, "not a known key"),
])
def test_bad_duty_config_names_key_and_allowed(table, match):
    with pytest.raises(ConfigError, match=match):
        _job(**table)


def test_surface_setting_is_checked():
    data = tomllib.loads(template("paper_S1").read_text())
    data["manufacturing"]["surface"] = "sandblasted"
    with pytest.raises(ConfigError, match="manufacturing.surface.*polished"):
        job_from_dict(data)
    data["manufacturing"]["surface"] = "polished"
    assert job_from_dict(data).material.duty.surface == "polished"


def test_contact_fatigue_of_the_ball_against_agma_by_hand():
    """robot_joint duty, p0 = 1505 MPa at theta_max on 420_ht (S_c = 1170 MPa, AGMA 2001-D04
    Table 3 at 50 HRC). Z_N (Shigley Fig. 14-15): 2.466 N^-0.056 from 1e4 to 1e7 cycles,
    1.4488 N^-0.023 beyond (Shigley's Example 14-5: 0.948 at 1e8). By hand: block 1, 1e7
    cycles at 0.5 theta_max: p0 = 1505 sqrt(0.5) = 1064.2 MPa, p0/S_c = 0.9096 < Z_N(1e7) = 1:
    N = (0.9096/1.4488)^(-1/0.023) = 6.2e8, damage 0.016; block 2, 1e5 cycles at theta_max:
    p0/S_c = 1.2863, between Z_N(1e7) and Z_N(1e4) = 1.472: N = (1.2863/2.466)^(-1/0.056) =
    1.115e5, damage 0.897."""
    from springcad.design import contact_fatigue

    assert contact_fatigue.contact_life_factor(1e4) == pytest.approx(1.47, abs=0.005)
    assert contact_fatigue.contact_life_factor(1e7) == pytest.approx(1.0, abs=1e-3)
    assert contact_fatigue.contact_life_factor(1e8) == pytest.approx(0.948, abs=1e-3)
    c = contact_fatigue.contact_check(DutySpec(), "420_ht", 1505.0, math.radians(14))
    n1 = (1505 * math.sqrt(0.5) / 1170 / 1.4488) ** (-1 / 0.023)
    n2 = (1505 / 1170 / 2.466) ** (-1 / 0.056)
    assert n1 == pytest.approx(6.2e8, rel=0.05) and n2 == pytest.approx(1.115e5, rel=0.01)
    assert c.miner_sum == pytest.approx(1e7 / n1 + 1e5 / n2, rel=1e-9)
    assert c.met is False and c.judged and c.strength_MPa == 1170
    assert contact_fatigue.contact_check(DutySpec(), "ti6al4v", 1505.0, 0.2) is None
    # the allowable meets the duty with its factor exactly
    at = contact_fatigue.contact_check(DutySpec(), "420_ht", c.allowable_MPa, math.radians(14))
    assert at.safety_factor == pytest.approx(1.2, rel=1e-6)
    assert contact_fatigue.allowable_p0_MPa(DutySpec(), "420_ht", 0.2) == pytest.approx(
        c.allowable_MPa, rel=1e-9)


def test_contact_fatigue_is_judged_from_1e4_cycles_and_sizes_only_a_declared_duty():
    """A bench duty of 100 cycles (paper templates) and the static preset are left to the
    static contact rule; springcad's default duty is judged but sizes no ball unless
    declared; a declared one allows c_vm p0 as the ball's von Mises (c_vm = 0.557 at nu 0.3)."""
    from dataclasses import replace

    from springcad.config.specs import DutyBlock, MaterialSpec
    from springcad.design import contact_fatigue
    from springcad.design.contact_stress import von_mises_peak
    from springcad.materials import material_table

    bench = DutySpec(blocks=(DutyBlock(100, 1.0, 0.0, "fraction", "bench"),), preset=None,
                     declared=True)
    assert not contact_fatigue.judged(bench, 0.2)
    assert not contact_fatigue.judged(DutySpec(preset="static", declared=True), 0.2)
    assert contact_fatigue.judged(DutySpec(), 0.2)
    assert contact_fatigue.contact_check(bench, "420_ht", 3000.0, 0.2).judged is False
    mat = MaterialSpec(material=material_table()["420_ht"], design_stress_MPa=780,
                       safety_factor=1.2)
    assert not mat.duty.declared and math.isinf(
        contact_fatigue.allowable_von_mises_MPa(mat, 0.2))
    declared = replace(mat, duty=replace(mat.duty, declared=True))
    p0 = contact_fatigue.allowable_p0_MPa(declared.duty, "420_ht", 0.2)
    c_vm = von_mises_peak(mat.material.poisson_ratio)[0]  # 0.557 at nu = 0.3 (its own test)
    assert 0.55 < c_vm < 0.58
    assert contact_fatigue.allowable_von_mises_MPa(declared, 0.2) == pytest.approx(
        c_vm * p0, rel=1e-9)
