"""The refusal's nearest changes (springcad.design.feasibility) against probes whose feasible
set is known exactly, and the contact correction's redesign (balls at least the FEA's)."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from springcad.config.load import job_from_dict
from springcad.config.schema import keys
from springcad.design.feasibility import (as_material, describe, fewer_disks, in_series,
                                          larger_disk, material_changes, nearest_changes,
                                          reshaped_envelope, series_change)
from springcad.design.redesign import redesign_for_contact
from springcad.design.search import design_spring
from springcad.errors import DesignError
from springcad.parallel import each_on_two_cores

BASE = {"stiffness_Nm_per_rad": 150, "max_deflection_deg": 14, "outer_radius_mm": 36,
        "thickness_mm": 5.0}


def _spec(**over):
    return job_from_dict({"springs": {"A": {**BASE, **over}}}).springs["A"]


def test_nearest_value_is_the_boundary_rounded_outward_and_checked():
    """Feasible exactly when z >= 6.23 mm: the suggestion is within 1/32 of the searched span
    (5 -> 12.5 mm) above the boundary, rounded up to 0.1 mm, it designs, and keys whose far
    end does not design are not named."""
    calls = []

    def designs(s):
        calls.append(s)
        return s.thickness_mm >= 6.23

    (key, now, value), = nearest_changes(_spec(), designs)
    assert (key, now) == ("thickness_mm", 5.0)
    assert 6.23 <= value <= 6.23 + 7.5 / 32 + 0.1 and value == pytest.approx(round(value, 1))
    assert designs(replace(_spec(), thickness_mm=value))


def test_far_end_stays_inside_the_schema_range():
    """R_o = 200 mm: 1.8 x would be 360 mm, past the schema's 250; the probe stops at 250 and
    the suggestion is inside the range."""
    hi = keys("springs.<name>")["outer_radius_mm"].hi
    seen = []

    def designs(s):
        seen.append(s.outer_radius_mm)
        return s.outer_radius_mm >= 231.0

    (key, _, value), = nearest_changes(_spec(outer_radius_mm=200.0), designs,
                                       keys=("outer_radius_mm",))
    assert max(seen) == hi and 231.0 <= value <= hi and value == pytest.approx(231.0, abs=0.5)


def test_a_past_deadline_still_gives_every_key_two_steps_and_a_value_that_designs():
    def designs(s):
        return s.thickness_mm >= 6.23 or s.max_deflection_rad <= math.radians(11.1)

    changes = dict((k, v) for k, _, v in nearest_changes(_spec(), designs,
                                                         deadline=-1))
    assert set(changes) == {"thickness_mm", "max_deflection_deg"}
    # two steps of the span 5 -> 12.5 mm: within 1/4 of it, on the feasible side
    assert 6.23 <= changes["thickness_mm"] <= 6.23 + 7.5 / 4
    assert 11.1 - 9.8 / 4 <= changes["max_deflection_deg"] <= 11.1
    # and rounded outward to the key's step (0.1 mm, 0.1 deg) where that designs too: the
    # bisection alone gives 6.875 mm here (a user buys 6.9 mm, not 6.875)
    assert changes["thickness_mm"] == pytest.approx(round(changes["thickness_mm"], 1), abs=1e-9)
    assert changes["max_deflection_deg"] == pytest.approx(
        round(changes["max_deflection_deg"], 1), abs=1e-9)


def test_larger_disk_is_the_smallest_scale_that_designs_and_frees_fixed_layout_keys():
    """Feasible exactly when thickness x outer radius >= 400 mm^2 (scale s: 180 s^2 at
    5 x 36): the scale found is within 1/32 of the span (1 -> 2.5) above sqrt(400/180) =
    1.491, both values rounded up to their steps and checked; a spec whose fixed contact
    radius forbids every size gets the scale with that key removed; one that no size up
    to 2.5x designs gets nothing."""
    def designs(s):
        return s.thickness_mm * s.outer_radius_mm >= 400.0

    text, big = larger_disk(_spec(), designs)
    z = float(text.split("thickness_mm = ")[1].split(" ")[0])
    ro = float(text.split("outer_radius_mm = ")[1].split(" ")[0])
    assert z * ro >= 400.0 and z / 5.0 <= 1.491 + 1.5 / 32 + 0.02, text
    assert "all together" in text and "removed" not in text
    assert (big.thickness_mm, big.outer_radius_mm) == (z, ro) and designs(big)

    def free_only(s):
        return s.contact_radius_mm is None and designs(s)

    text, big = larger_disk(_spec(contact_radius_mm=7.0), free_only)
    assert "springs.A.contact_radius_mm removed (now 7 mm)" in text, text
    assert big.contact_radius_mm is None and free_only(big)
    assert larger_disk(_spec(), lambda s: False) == ("", None)


def test_a_deflection_bound_spec_gets_a_larger_disk_where_no_scale_designs():
    """Feasible exactly when R_o >= 79.2 mm (2.2 x, longer flexures) and z <= 6 mm (thicker
    webs too stiff): no uniform scale designs (at s = 2.2 the plate is 11 mm) and no single
    key's probe reaches 2.2 x; the reshaped search finds the radius alone, within 1/32 of
    its bisected span (72 -> 108 mm) plus the 0.5 mm step, and says so as one key."""
    def designs(s):
        return s.outer_radius_mm >= 79.2 and s.thickness_mm <= 6.0

    assert nearest_changes(_spec(), designs) == []
    text, big = larger_disk(_spec(), designs)
    assert designs(big) and big.thickness_mm == 5.0, text
    assert 79.2 <= big.outer_radius_mm <= 79.2 + 36 / 32 + 0.5, text
    assert text == f"a larger disk: springs.A.outer_radius_mm = {big.outer_radius_mm:g} (now 36)"


def test_the_reshaped_disk_is_the_lightest_of_its_grid_and_bisected_in_thickness():
    """Feasible exactly when z >= 9 mm, R_o >= 90 mm and z / R_o <= 0.12 (the user's
    proportions, 5 / 36 = 0.139, never design): the lightest envelope of the grid that
    designs is 2.5 x 5 mm at 3 x 36 mm; its thickness is bisected down towards the refused
    1.5 x plate (7.5 -> 12.5 mm, 1/32 of the span) and rounded up to 0.1 mm. A probe that
    nothing designs gets None."""
    def designs(s):
        return (s.thickness_mm >= 9.0 and s.outer_radius_mm >= 90.0
                and s.thickness_mm / s.outer_radius_mm <= 0.12)

    big = reshaped_envelope(_spec(), designs)
    assert designs(big) and big.outer_radius_mm == 108.0
    assert 9.0 <= big.thickness_mm <= 9.0 + 5.0 / 32 + 0.1
    text, same = larger_disk(_spec(), designs)
    assert same == big and text.startswith("a disk of other proportions: ") and \
        text.endswith(", all together"), text
    assert reshaped_envelope(_spec(), lambda s: False) is None


def test_fewer_disks_merges_the_fewest_that_design_and_keeps_the_torque():
    """Six disks of 342 N*m/rad at 4 deg, feasible exactly from 10 deg per disk: two merges
    (8 deg) do not design, three (12 deg: two disks of 114 N*m/rad) do; the torque
    K theta is the same; a count with no divisor that designs gives nothing."""
    spec = _spec(stiffness_Nm_per_rad=342, max_deflection_deg=4)

    def designs(s):
        return math.degrees(s.max_deflection_rad) >= 10.0 - 1e-9

    text = fewer_disks(spec, 6, designs)
    assert text.startswith("'A' 2 times in stack.sequence where it is 6 times"), text
    assert "target_stiffness_Nm_per_rad = 114," in text and "max_deflection_deg = 12" in text
    assert fewer_disks(spec, 2, designs) == ""  # 8 deg does not design
    assert fewer_disks(spec, 1, designs) == ""


def test_series_and_materials_are_named_only_when_they_design():
    spec = _spec()
    assert in_series(spec, 3).target_stiffness_Nmm_per_rad == pytest.approx(3 * spec.target_stiffness_Nmm_per_rad)
    assert in_series(spec, 3).max_deflection_rad == pytest.approx(spec.max_deflection_rad / 3)
    assert series_change(spec, lambda s: s.max_deflection_rad < spec.max_deflection_rad / 2.5) == 3
    assert series_change(spec, lambda s: False) is None
    mat = job_from_dict({"springs": {"A": BASE}}).material
    maraging = as_material(mat, "maraging_300")
    assert maraging.design_stress_MPa % 10 == 0 and maraging.safety_factor == mat.safety_factor
    assert maraging.design_stress_MPa == pytest.approx(
        mat.design_stress_MPa * maraging.material.yield_strength_MPa
        / mat.material.yield_strength_MPa, abs=10)
    found = material_changes(mat, lambda m: m.material.name == "maraging_300")
    assert [m.material.name for m in found] == ["maraging_300"]
    # a weaker material is never probed
    probed = []
    material_changes(mat, lambda m: probed.append(m.material.name) or False)
    assert "pom" not in probed and "6061_t6" not in probed
    text = describe("A", [], found, 2, spec)
    assert 'material.name = "maraging_300" with material.design_stress_MPa' in text
    assert "2 disks in series" in text


def test_contact_correction_redesigns_with_balls_at_least_the_floor():
    job = job_from_dict({"material": {"design_stress_MPa": 780, "safety_factor": 1.2},
                         "springs": {"A": BASE}})
    d = design_spring(job.springs["A"], job.material, job.manufacturing, job.hardware,
                      explain=False)
    floor = d.tip_radius_mm * 1.15
    r = redesign_for_contact(d, floor)
    assert r.tip_radius_mm >= floor - 1e-12
    assert r.spec == d.spec  # the user's spec, not the floor
    assert "contact correction" in r.design_choice


def test_a_fixed_flexure_count_that_cannot_work_is_named_with_the_count_that_does():
    """70 flexures on the default (12 mm) disk leave no room to lower the stress to its duty; the refusal
    names removing n_flexures and the count the search then chooses, and that count
    designs."""
    from pathlib import Path

    from springcad.config import load_job
    from springcad.design.search import _freed_choices

    job = load_job(Path(__file__).parents[1] / "templates" / "default.toml")  # its duty
    spec = replace(job.springs["S1"], n_flexures=70, thickness_mm=12.0)  # the plate it chooses
    mat, mfg, hw = job.material, job.manufacturing, job.hardware
    with pytest.raises(DesignError):
        design_spring(spec, mat, mfg, hw, explain=False)
    text = _freed_choices(spec, mat, mfg, hw, math.inf)
    assert "springs.S1.n_flexures removed (now 70; springcad then chooses " in text
    n = int(text.split("chooses ")[1].split(")")[0])
    d = design_spring(replace(spec, n_flexures=n), mat, mfg, hw, explain=False)
    assert d.n_flexures == n and d.yield_margin >= d.required_yield_margin * (1 - 1e-3)


def test_stiff_webs_probe_a_thinner_disk_and_a_higher_stiffness_inside_their_window():
    """Layouts held stiff by their minimum webs (``webs``): feasible only for 3.6 <= z <=
    4.6 mm (thinner fails the stress) or K >= 240 N*m/rad. The thickness is found below the
    user's 5 mm by the nearer stop (0.85 x), the stiffness above 150, each the boundary
    within the bisection's resolution and checked; without ``webs`` neither is found (the
    far ends 12.5 mm and 45 N*m/rad fail)."""
    def designs(s):
        return 3.6 <= s.thickness_mm <= 4.6 or s.target_stiffness_Nmm_per_rad >= 240e3

    changes = {k: v for k, _, v in nearest_changes(_spec(), designs, webs=True)}
    assert set(changes) == {"thickness_mm", "target_stiffness_Nm_per_rad"}
    assert 4.6 - 0.75 / 32 - 0.1 <= changes["thickness_mm"] <= 4.6
    # 1.3 x fails, 1.8 x designs: bisected on 150..270
    assert 240 <= changes["target_stiffness_Nm_per_rad"] <= 240 + 120 / 32 + 1
    assert designs(_spec(thickness_mm=changes["thickness_mm"]))
    assert designs(_spec(stiffness_Nm_per_rad=changes["target_stiffness_Nm_per_rad"]))
    assert nearest_changes(_spec(), designs) == []
    assert "thickness_mm (to 0.4x)" in describe("A", [], webs=True)


@pytest.mark.parametrize("webs", [False, True])
def test_the_probes_of_a_round_on_two_cores_find_what_one_core_finds(webs):
    """The keys' probes of one round (far ends, a bisection step, the rounding) do not
    depend on each other: run on two cores (parallel.each_on_two_cores, a forked child for
    every other probe) they give the same changes as one after another, from as many
    probes (the refusal's deadline counts them). Feasible set known exactly: a thicker or
    larger disk, or less deflection."""
    def designs(s):
        return (s.thickness_mm >= 6.23 or s.outer_radius_mm >= 41.3
                or s.max_deflection_rad <= math.radians(11.1))

    counted = []

    def each(specs):
        answers, beside = each_on_two_cores(designs, specs)
        counted.append((len(specs), beside))
        return answers

    serial = []
    one = nearest_changes(_spec(), lambda s: serial.append(s) or designs(s), webs=webs)
    two = nearest_changes(_spec(), designs, webs=webs, designs_each=each)
    assert one == two and len(one) == (2 if webs else 3)  # webs: the thickness probed down
    assert sum(n for n, _ in counted) == len(serial)
    assert sum(b for _, b in counted) > 0  # the child ran some (fork is there on Linux)
