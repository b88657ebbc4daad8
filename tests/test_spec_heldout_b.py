"""The second held-out harness's build stages (bench/spec_heldout_b.py): a refusal's first
change is read from the full design log, applied exactly and built; a build that fails in its
design stage is a refusal, one that fails after it a late failure.

springcad is replaced by a stand-in package (run by the harness as ``python -m springcad``
with PYTHONPATH set to its folder) whose outcome is fixed by the config's numbers, so each
classification is known in advance.
"""

import json
import sys
import textwrap
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import spec_heldout_b as hb  # noqa: E402

# refuses below 3.8 mm (at design), fails its checks above R_o 30 mm (after design)
FAKE_MAIN = textwrap.dedent('''
    import json, sys, tomllib
    from pathlib import Path
    cmd, cfg_path, out = sys.argv[1], sys.argv[2], Path(sys.argv[4])
    spring = tomllib.loads(Path(cfg_path).read_text())["springs"]["S1"]
    print("[1/5] design ...")
    if spring["thickness_mm"] < 3.8:
        print("springcad build: error: spring 'S1' cannot be made as specified; feasible with "
              "springs.S1.thickness_mm = 3.8 (now 3) or springs.S1.outer_radius_mm = 40 "
              "(now 24) (each alone, other keys unchanged)")
        sys.exit(2)
    print("[2/5] verify ...")
    print("[4/5] checks ...")
    if spring["outer_radius_mm"] > 30:
        print("springcad build: failed: 3 checks: 2 passed, 1 manufacturability violation")
        sys.exit(1)
    out.mkdir(parents=True, exist_ok=True)
    (out / "build.json").write_text(json.dumps(
        {"release": {"status": "NOT FOR MANUFACTURE", "reasons": ["duty not met"]}}))
''')

REFUSAL_LOG = ("spring  K N*m/rad  target  theta_max deg    N  r_c mm\n"
               "springcad design: error: spring 'S1' cannot be made as specified; feasible "
               "with springs.S1.thickness_mm = 3.8 (now 3) or springs.S1.outer_radius_mm = "
               "40 (now 24) (each alone, other keys unchanged)\n")


def _spec(thickness_mm: float, r_o_mm: float, name: str) -> str:
    return hb.to_toml({"job": {"name": name}, "material": {"name": "420_ht"},
                       "springs": {"S1": {"target_stiffness_Nm_per_rad": 235.0,
                                          "max_deflection_deg": 7.5,
                                          "outer_radius_mm": r_o_mm,
                                          "thickness_mm": thickness_mm}},
                       "stack": {"sequence": ["S1"], "input": "shaft"}})


def _work(tmp_path: Path) -> tuple[Path, Path]:
    code = tmp_path / "code"
    (code / "springcad").mkdir(parents=True)
    (code / "springcad" / "__init__.py").write_text("")
    (code / "springcad" / "__main__.py").write_text(FAKE_MAIN)
    work = tmp_path / "work"
    for sub in ("specs", "design"):
        (work / sub).mkdir(parents=True)
    return code, work


def test_first_change_of_a_refusal_is_applied_exactly_and_built(tmp_path):
    code, work = _work(tmp_path)
    (work / "specs" / "a.toml").write_text(_spec(3.0, 24.0, "a"))
    (work / "design" / "a.log").write_text(REFUSAL_LOG)
    (work / "specs" / "c.toml").write_text(_spec(3.0, 24.0, "c"))
    (work / "design" / "c.log").write_text("springcad design: error: no change meets it\n")
    rows = [{"name": "a", "outcome": "REFUSED+NUMBERS"}, {"name": "b", "outcome": "DESIGNED"},
            {"name": "c", "outcome": "REFUSED"}]
    (work / "results.json").write_text(json.dumps(rows))
    hb.fix_loop(work, code, timeout_s=60.0, stop_at=None)
    builds = json.loads((work / "builds.json").read_text())
    assert set(builds) == {"a_fix", "c_fix"}                  # the designed spec is not touched
    assert builds["a_fix"]["change"] == "springs.S1.thickness_mm=3.8"   # the first, alone
    assert builds["a_fix"]["build_outcome"] == "NOT FOR MANUFACTURE"
    applied = tomllib.loads((work / "specs" / "a_fix.toml").read_text())
    assert applied["springs"]["S1"]["thickness_mm"] == 3.8
    assert applied["springs"]["S1"]["outer_radius_mm"] == 24.0         # the other key unchanged
    assert builds["c_fix"]["build_outcome"] == "NO CHANGE PARSED"
    assert "build_s" not in builds["c_fix"]                            # nothing was run


def test_build_outcome_follows_the_stage_that_failed(tmp_path):
    code, work = _work(tmp_path)
    (work / "specs" / "refused.toml").write_text(_spec(3.0, 24.0, "refused"))
    (work / "specs" / "late.toml").write_text(_spec(4.0, 40.0, "late"))
    refused = hb.build_case("refused", work, code, 60.0)
    late = hb.build_case("late", work, code, 60.0)
    assert (refused["build_outcome"], refused["stage"]) == ("REFUSED AT DESIGN", "design")
    assert (late["build_outcome"], late["stage"]) == ("LATE FAILURE", "checks")
    assert "manufacturability violation" in (work / "build" / "late.log").read_text()


def test_refusal_text_drops_the_progress_lines_before_the_message():
    text = hb.refusal_text(REFUSAL_LOG)
    assert text.startswith("springcad design: error:") and "theta_max" not in text


def test_capped_timeout_ends_runs_by_the_stop_time():
    assert hb._capped(480.0, None) == 480.0
    now = hb.time.time()
    assert abs(hb._capped(480.0, now + 200.0) - 200.0) < 5.0
    assert hb._capped(480.0, now + 30.0) is None
