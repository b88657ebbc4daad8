"""Comparison of the fitted stack with its design dict (hand-made, as design.json)."""

import copy

import pytest

from springcad.errors import ConfigError
from springcad.fit.analysis import fit_record
from springcad.fit.bench import BenchSpring, simulate
from springcad.fit.compare import compare_with_design, stack_fea_stiffness
from fit_helpers import FAST

# 4xS1 as the paper's Mfr. 2 stack: target 37.5, per-interface backlash from eqs. 1-3
DESIGN = {
    "springs": {"S1": {"stiffness_Nm_per_rad": 150.0, "target_stiffness_Nm_per_rad": 150.0}},
    "stack": {
        "stiffness_Nm_per_rad": 37.5,
        "target_stiffness_Nm_per_rad": 37.5,
        "backlash_rad": {"nominal": 0.0364, "worst_min": -0.065, "worst_max": 0.138,
                         "rss_min": 0.0, "rss_max": 0.087, "mc_p01": 0.005, "mc_p99": 0.07},
    },
}


def test_stiffness_errors_and_backlash_ranges():
    out = compare_with_design(DESIGN, 39.21, 0.0598)
    st = out["stiffness"]
    assert st["error_vs_target_pct"] == pytest.approx(4.56, abs=0.01)
    assert st["error_vs_beam_pct"] == pytest.approx(4.56, abs=0.01)
    assert st["fea_Nm_per_rad"] is None and st["error_vs_fea_pct"] is None
    ranges = out["backlash"]["ranges"]
    assert set(ranges) == {"worst_case", "rss", "monte_carlo_p01_p99"}
    assert all(r["inside"] for r in ranges.values())
    assert "inside the worst case range [-0.065, 0.138] rad" in out["backlash"]["statement"]


def test_backlash_outside_a_range_says_above():
    out = compare_with_design(DESIGN, 36.09, 0.0996)  # Mfr. 1 measured 0.0996 rad
    ranges = out["backlash"]["ranges"]
    assert ranges["worst_case"]["inside"]
    assert not ranges["rss"]["inside"] and not ranges["monte_carlo_p01_p99"]["inside"]
    assert "above the rss range" in out["backlash"]["statement"]


def test_fea_used_when_present():
    d = copy.deepcopy(DESIGN)
    d["springs"]["S1"]["stiffness_fea_Nm_per_rad"] = 160.0
    assert stack_fea_stiffness(d) == pytest.approx(37.5 * 160 / 150)
    out = compare_with_design(d, 40.0, 0.05)
    assert out["stiffness"]["error_vs_fea_pct"] == pytest.approx(0.0, abs=1e-9)
    d["stack"]["stiffness_fea_Nm_per_rad"] = 41.0
    assert stack_fea_stiffness(d) == 41.0


def test_fea_stack_in_series_from_the_sequence():
    d = copy.deepcopy(DESIGN)
    d["springs"] = {"S1": {"stiffness_Nm_per_rad": 150.0, "stiffness_fea_Nm_per_rad": 160.0},
                    "S2": {"stiffness_Nm_per_rad": 75.0, "stiffness_fea_Nm_per_rad": 80.0}}
    d["stack"]["sequence"] = ["S1", "S2", "S2"]
    assert stack_fea_stiffness(d) == pytest.approx(1 / (1 / 160 + 2 / 80))
    del d["stack"]["sequence"]
    assert stack_fea_stiffness(d) is None  # two spring types, no sequence: not guessed


def test_missing_key_is_a_config_error():
    d = copy.deepcopy(DESIGN)
    del d["stack"]["backlash_rad"]
    with pytest.raises(ConfigError, match="'stack.backlash_rad'.*missing from the design result"):
        compare_with_design(d, 39.0, 0.05)


def test_fit_record_with_design_compares_deadband_and_final_model():
    sim = simulate(BenchSpring(39.21, backlash_rad=0.0598), protocol=FAST, seed=7)
    res = fit_record(sim.record, design=DESIGN)
    d = res.to_dict()
    assert d["target_stiffness_Nm_per_rad"] == 37.5  # taken from the design
    comp = d["design_comparison"]
    assert comp["measured"]["backlash_rad"] == pytest.approx(0.0598, rel=0.05)
    assert comp["stiffness"]["error_vs_target_pct"] == pytest.approx(4.56, abs=0.6)
    assert comp["backlash"]["ranges"]["worst_case"]["inside"]
    loop = comp["residual_loop"]
    assert loop["measured"]["backlash_rad"] == pytest.approx(0.0598, rel=0.03)
    assert "residual loop" in loop["measured"]["method"]
