"""The held-out harness's reading of a refusal (bench/heldout_fixes.py): every change
springcad printed is applied exactly, nothing else.

The messages are springcad's own (ho10's logs of the seed-2511 held-out specs, trimmed),
so a change of wording that the harness can no longer read fails here, not silently in a
held-out run.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
from heldout_fixes import apply_ops, parse_fixes  # noqa: E402


def _stack(seq, **a):
    spring = {"stiffness_Nm_per_rad": 970, "max_deflection_deg": 6, "outer_radius_mm": 40.0,
              "thickness_mm": 5.0, **a}
    springs = {n: dict(spring) for n in dict.fromkeys(seq)}
    return {"job": {"name": "t"}, "material": {"name": "420_ht"}, "springs": springs,
            "stack": {"sequence": list(seq), "input": "shaft"},
            "hardware": {"fastener": "bolt", "fastener_count": 6}}


FEWER = ("springcad design: error: spring 'A' cannot be made as specified; feasible with fewer "
         "disks: 'A' 1 times in stack.sequence where it is 3 times, each springs.A."
         "target_stiffness_Nm_per_rad = 323.3, max_deflection_deg = 18; or feasible with "
         "springs.A.n_flexures removed (now 39; springcad then chooses 51); or feasible with "
         "springs.A.thickness_mm = 6.2 (now 5) or material.name = \"maraging_300\" with "
         "material.design_stress_MPa = 1300 (each alone, other keys unchanged). Why: no tip "
         "ball carries the 200 N contact load at r_c = 13 mm")


def test_fewer_disks_changes_the_sequence_and_the_disk_together():
    cfg = _stack(["A", "A", "A", "B", "B", "B"], n_flexures=39)
    alts, note = parse_fixes(FEWER, cfg)
    assert note == "strict"
    new = apply_ops(cfg, alts[0], "_fix1")
    assert new["stack"]["sequence"] == ["A", "B", "B", "B"]
    a = new["springs"]["A"]
    assert a["target_stiffness_Nm_per_rad"] == 323.3 and "stiffness_Nm_per_rad" not in a
    assert a["max_deflection_deg"] == 18.0
    assert new["springs"]["B"] == cfg["springs"]["B"]          # B untouched
    # the other alternatives, in the order written
    assert apply_ops(cfg, alts[1], "")["springs"]["A"].get("n_flexures") is None
    assert apply_ops(cfg, alts[2], "")["springs"]["A"]["thickness_mm"] == 6.2
    mat = apply_ops(cfg, alts[3], "")["material"]
    assert mat == {"name": "maraging_300", "design_stress_MPa": 1300.0}
    assert len(alts) == 4


def test_disks_in_series_writes_each_copy_m_times():
    msg = ("springcad design: error: spring 'A' cannot be made as specified; feasible with "
           "2 disks in series in its place (each springs.A.target_stiffness_Nm_per_rad = 1920, "
           "max_deflection_deg = 14.5, and each 'A' in stack.sequence written 2 times) (each "
           "alone, other keys unchanged)")
    cfg = _stack(["A", "A", "A"])
    alts, _ = parse_fixes(msg, cfg)
    new = apply_ops(cfg, alts[0], "")
    assert new["stack"]["sequence"] == ["A"] * 6
    assert new["springs"]["A"]["target_stiffness_Nm_per_rad"] == 1920.0
    assert new["springs"]["A"]["max_deflection_deg"] == 14.5
    single = _stack(["A"])
    del single["stack"]["sequence"]                   # one spring: the sequence left out
    assert apply_ops(single, parse_fixes(msg, single)[0][0], "")["stack"]["sequence"] == \
        ["A", "A"]


def test_all_together_is_one_alternative_and_the_duty_clause_keeps_its_surface():
    msg = ("springcad design: error: spring 'A' cannot be made as specified; no change of "
           "thickness_mm (to 2.5x), outer_radius_mm (to 1.8x) alone: change several keys; it "
           "designs with the disk scaled by 1.38: springs.A.thickness_mm = 7.6 (now 5.5) and "
           "springs.A.outer_radius_mm = 38.5 (now 28) and springs.A.n_flexures removed (now 8), "
           "springs.A.contact_radius_mm removed (now 4.5 mm), all together; for springcad's "
           "default duty as well, the duty allows a peak of 606 MPa; with manufacturing.surface "
           "= \"shot_peened\" it is feasible with springs.A.outer_radius_mm = 112 (now 62) or "
           "springs.A.max_deflection_deg = 1.7 (now 6) (each alone, other keys unchanged). Why: "
           "raise contact_radius_mm to at least 5.78 mm")
    cfg = _stack(["A"], thickness_mm=5.5, outer_radius_mm=28.0, n_flexures=8,
                 contact_radius_mm=4.5)
    alts, note = parse_fixes(msg, cfg)
    assert note == "strict" and len(alts) == 3        # the "Why" clause is no change
    a = apply_ops(cfg, alts[0], "")["springs"]["A"]
    assert (a["thickness_mm"], a["outer_radius_mm"]) == (7.6, 38.5)
    assert "n_flexures" not in a and "contact_radius_mm" not in a
    for alt in alts[1:]:
        assert apply_ops(cfg, alt, "")["manufacturing"]["surface"] == "shot_peened"
    assert apply_ops(cfg, alts[2], "")["springs"]["A"]["max_deflection_deg"] == 1.7


def test_hardware_remedies_and_values_in_now_are_not_changes():
    msg = ("springcad design: error: bolts_2: 6 x Ø2 bolts on R53.69 carry 99.8 N*m; use "
           "hardware.fastener_count = 7 (now 6; Ø2 bolts) or hardware.fastener_diameter_mm = "
           "2.5 (now 2; 6 bolts) or a stack torque of at most 80 N*m")
    cfg = _stack(["A", "A"])
    alts, note = parse_fixes(msg, cfg)
    assert note == "strict"
    assert [apply_ops(cfg, a, "")["hardware"] for a in alts] == [
        {"fastener": "bolt", "fastener_count": 7},
        {"fastener": "bolt", "fastener_count": 6, "fastener_diameter_mm": 2.5}]


def test_a_message_without_a_change_gives_none():
    msg = ("springcad design: error: spring 'A' cannot be made as specified: no flexure "
           "count fits at any contact radius")
    assert parse_fixes(msg, _stack(["A"])) == ([], "no change in numbers named")
