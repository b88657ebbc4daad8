"""Candidate enumeration and stack evaluation: ids, the series law, constraints with numbers."""

import numpy as np
import pytest

from springcad.design.stack import eq10_limit, series_stiffness
from springcad.synthesis.candidates import CandidateSpace
from springcad.synthesis.evaluate import detail, evaluate_batch
from springcad.synthesis.requirements import requirements_from_dict
from synth_fixtures import small


@pytest.fixture(scope="module")
def space():
    return CandidateSpace.from_requirements(requirements_from_dict(small()))


def test_ids_are_a_partition(space):
    whole = space.decode(0, space.total)
    assert np.array_equal(whole["cid"], np.arange(space.total))
    assert space.total == sum(int(np.prod(space.shape(f))) for f in space.families)
    parts = [space.decode(a, a + 37) for a in range(0, space.total, 37)]
    for key in whole:
        assert np.array_equal(np.concatenate([p[key] for p in parts]), whole[key])


def test_every_disk_carries_the_stack_peak_torque(space):
    """Series stiffness and eq. 10 (design.stack) of the decoded disks give the targets back."""
    c = space.decode(0, space.total)
    K, th = c["target_stiffness_Nmm_per_rad"], c["deflection_rad"]
    for i in np.flatnonzero(c["n_b"] > 0)[::50]:
        n_a, n_b, f = c["n_a"][i], c["n_b"][i], c["split"][i]
        ks = [n_a * K[i] / f] * n_a + [n_b * K[i] / (1 - f)] * n_b
        limits = [f * th[i] / n_a] * n_a + [(1 - f) * th[i] / n_b] * n_b
        assert series_stiffness(ks) == pytest.approx(K[i], rel=1e-12)
        limit, torque, _ = eq10_limit(limits, ks)
        assert limit == pytest.approx(th[i], rel=1e-12)
        assert torque == pytest.approx(K[i] * th[i], rel=1e-12)


def test_envelope_radius_leaves_room_for_the_bushing(space):
    c = space.decode(0, space.total)
    r = evaluate_batch(space, 0, space.total)
    assert np.all(r["envelope_radius_mm"] <= space.max_outer_radius_mm + 1e-9)
    three = c["n_a"] + c["n_b"] >= 3
    assert np.all(c["outer_radius_mm"][three] < c["outer_radius_mm"][~three].max())


def test_feasible_rows_meet_every_limit(space):
    r = evaluate_batch(space, 0, space.total)
    f = r["feasible"]
    assert f.any() and (~f).any()
    assert np.all(r["axial_length_mm"][f] <= space.max_axial_length_mm + 1e-9)
    assert np.all(r["yield_margin"][f] >= space.yield_margin * (1 - 1e-9))
    assert np.all(np.isfinite(r["mass_kg"][f]))
    # every infeasible row says which constraint and by how much, in a sentence with numbers
    bad = ~f
    assert np.all(r["binding"][bad] != "")
    assert all(any(ch.isdigit() for ch in detail(r, i)) for i in np.flatnonzero(bad))
    rows = np.flatnonzero(bad & (r["binding"] == "axial_length"))
    assert len(rows)
    i = rows[0]
    assert r["violation"][i] == pytest.approx(r["axial_length_mm"][i] / 19.5 - 1)
    assert f"{r['axial_length_mm'][i]:.2f} mm > max_axial_length_mm 19.50 mm" in detail(r, i)
