"""The screened peak stress against the full design's, and feasibility against design_spring.

Screening evaluates the design's FEA-calibrated stress model on arrays (serpentine
search, root flares, fillet stations, stress passes); these tests hold it to
``design_spring(..., explain=False)`` on seeded samples of disks:

- feasibility (the disk is designed and keeps the required yield margin) agrees on
  every disk of the sample;
- where both accept, the predicted peak and the yield margin agree within 2 % (measured
  with the uncoupled serpentines: 1.7 % at most, on a disk whose root zone bends sharply;
  0.2 % with the root-balanced ones), the layout exactly, the root flare but for knife-edge ties (two flares
  within FLARE_GAIN of each other), the beam-stress derating within
  1 %, the mass within 3 %.

Both sides use the design's Winkler-Bach factors (stable on nearly straight stretches,
tests/fea/test_stress_calibration.py).
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from springcad.config import load_job
from springcad.design import flexure as fx
from springcad.design.search import design_spring
from springcad.design.sizing import FLARE_GAIN
from springcad.design.resize import with_root
from springcad.errors import DesignError
from springcad.synthesis import peak
from springcad.synthesis.screening import (ENERGY, FLEXURE_FIT, OK, REASONS, RIM_RULE, TIP_BALLS,
                                          TORQUE_CAP, WEB_STIFFNESS, YIELD, screen_disks)
from springcad.design.shapes.serpentine_screen import DESIGN_SHAPES, serpentine_centrelines, spline_centreline
from synth_fixtures import TEMPLATES

JOB = load_job(TEMPLATES / "paper_S1.toml")
BASE = replace(JOB.springs["S1"], n_flexures=None, tip_radius_mm=None)
YIELD_MPA = JOB.material.material.yield_strength_MPa
TOL = 0.02
LAYOUT = {ENERGY, TORQUE_CAP, FLEXURE_FIT, RIM_RULE, TIP_BALLS}


def test_spline_is_the_designs_centreline():
    rng = np.random.default_rng(0)
    u = np.linspace(0, 1, 241) ** 1.3
    r = 6 + 20 * u
    for _ in range(3):
        theta = rng.uniform(0.05, 0.15) * np.sin(rng.integers(2, 5) * np.pi * u)
        x, y = r * np.sin(theta), r * np.cos(theta)
        slope_end = math.tan(theta[-1])
        xs, slope, ddx = spline_centreline(x[None], y[None], np.array([slope_end]))
        line = fx.Centreline(tuple(y[::4]), tuple(x[::4]), (0.0, slope_end))
        for ours, theirs in zip((xs[0], slope[0], ddx[0]), line.evaluate(y)):
            np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-12)


def test_serpentine_choice_is_the_designs():
    """Same trial shape and the same curvature (max |kappa| w within 1 %) as design_serpentine."""
    rng = np.random.default_rng(1)
    rows = []
    while len(rows) < 6:
        rc, rr, n = rng.uniform(5, 9), rng.uniform(25, 32), int(rng.integers(18, 34))
        z, load, s = rng.choice([3.0, 4.5, 6.0]), rng.uniform(100, 400), rng.uniform(1.05, 1.45)
        res = serpentine_centrelines(*(np.array([v]) for v in (s, rc, rr, n, load, z, 912.0)),
                                     0.35, np.array([2 * (33.5 - rr)]), 0.15)
        if res["ok"][0]:
            rows.append((s, rc, rr, n, load, z, res))
    for s, rc, rr, n, load, z, res in rows:
        width = lambda y: fx.constant_stress_width_mm(y, load, rc, z, 912.0)  # noqa: E731
        d = fx.design_serpentine(target_area_ratio=s, contact_radius_mm=rc, root_radius_mm=rr,
                                 n_flexures=n, width_fn=width, tip_radius_mm=0.4,
                                 min_clearance_mm=0.35, min_inside_radius_mm=0.15,
                                 root_zone_mm=2 * (33.5 - rr))
        assert DESIGN_SHAPES[res["shape"][0]] == DESIGN_SHAPES[d.start - 1]
        y = res["y"][0]
        _, dx, ddx = d.centreline.evaluate(y)
        theirs = np.max(np.abs(ddx / (1 + dx ** 2) ** 1.5) * width(y))
        assert np.max(np.abs(res["kappa"][0]) * width(y)) == pytest.approx(theirs, rel=TOL)


def _sample(seed: int, count: int) -> np.ndarray:
    """Disks (K, theta, R_o, z, r_c, N rule, required yield margin, design stress): a broad
    mix, and one in three near the paper's S1 (serpentine flexures near their margin)."""
    rng = np.random.default_rng(seed)
    broad = np.column_stack([
        rng.uniform(20e3, 400e3, count), rng.uniform(0.03, 0.35, count),
        rng.choice([20.0, 26.0, 33.5], count), rng.choice([2.0, 3.0, 4.5, 6.0], count),
        rng.choice([4.5, 5.5, 6.5, 7.5, 9.0], count), rng.choice([0, -2, -4], count),
        rng.uniform(1.0, 2.0, count), rng.uniform(500.0, 1200.0, count)])
    s1 = np.column_stack([
        rng.uniform(100e3, 200e3, count), rng.uniform(0.2, 0.3, count), np.full(count, 33.5),
        rng.choice([4.5, 5.0, 6.0], count), rng.choice([6.0, 6.5, 7.0, 7.5], count),
        rng.choice([0, -1, -2], count), rng.uniform(1.0, 1.1, count), np.full(count, 912.0)])
    return np.where((np.arange(count) % 3 == 2)[:, None], s1, broad)


def _screen(cases):
    m = len(cases)
    return screen_disks(*cases[:, :5].T, cases[:, 7], np.full(m, 2e5),
                        JOB.material.material.density_kg_per_mm3, cases[:, 5].astype(int),
                        min_tip_radius_mm=0.3, manufacturing=JOB.manufacturing,
                        hardware=JOB.hardware, allowed_peak_MPa=YIELD_MPA / cases[:, 6],
                        contact=(JOB.material.material.poisson_ratio, YIELD_MPA / cases[:, 6]))


def _compare(cases, res):
    """Full design of every disk (N as the screening wrote it into the job); the stats."""
    seen = {"both_ok": 0, "both_fail": 0, "derated": 0, "serpentine": 0, "flare_ties": 0}
    for j, (K, th, ro, z, rc, n_rule, margin, sigma) in enumerate(cases):
        code = int(res["code"][j])
        # N: the design's own choice, or |k| fewer (the N synthesis writes into the job);
        # a disk that fails before that N is known is not compared
        if n_rule < 0 and code in LAYOUT:
            continue
        spec = replace(BASE, target_stiffness_Nmm_per_rad=K, max_deflection_rad=th, outer_radius_mm=ro,
                       thickness_mm=z, contact_radius_mm=rc,
                       n_flexures=int(res["n"][j]) if n_rule < 0 else None)
        mat = replace(JOB.material, safety_factor=float(margin), design_stress_MPa=float(sigma))
        try:
            # the first (reference) layout, which the screen models
            d = design_spring(spec, mat, JOB.manufacturing, JOB.hardware, explain=False,
                              candidates=1)
            ok, why = d.yield_margin >= margin * (1 - 1e-3), f"yield margin {d.yield_margin:.4f}"
        except DesignError as err:
            d, ok, why = None, False, str(err)
        assert ok == (code == OK), (f"disk {j}: screening says {REASONS.get(code, 'ok')}, "
                                    f"the design {'accepts' if ok else 'rejects'} ({why})")
        if not ok:
            seen["both_fail"] += 1
            continue
        seen["both_ok"] += 1
        seen["derated"] += res["derating"][j] < 1
        seen["serpentine"] += d.flexure == "serpentine"
        assert res["n"][j] == d.n_flexures
        if res["root_flare"][j] != d.root_flare:
            # a knife-edge tie: the design's own peak with the screened flare is within
            # FLARE_GAIN (+ the 0.2 % the evaluations differ by) of its choice
            other = with_root(d, float(res["root_flare"][j])).predicted_peak_stress_MPa
            assert abs(other / d.predicted_peak_stress_MPa - 1) < FLARE_GAIN + 0.002
            seen["flare_ties"] += 1
            # the screened peak is that of its own flare
            assert res["peak_stress_MPa"][j] == pytest.approx(other, rel=TOL)
        else:
            assert res["peak_stress_MPa"][j] == pytest.approx(d.predicted_peak_stress_MPa,
                                                             rel=TOL)
            assert YIELD_MPA / res["peak_stress_MPa"][j] == pytest.approx(d.yield_margin,
                                                                         rel=TOL)
        assert res["derating"][j] == pytest.approx(d.stress_derating, rel=TOL)
        # K follows the beam stress the derating bisection lands on (within TOL on both
        # sides; the tip web does not scale): 0.23 % apart at 0.15 % apart in derating
        assert res["stiffness_Nmm_per_rad"][j] == pytest.approx(d.stiffness_beam_Nmm_per_rad,
                                                                 rel=1e-3 if res["derating"][j] == 1
                                                                 else 5e-3)
        assert res["mass_kg"][j] == pytest.approx(d.mass_kg, rel=0.03)
    return seen


def test_screening_and_design_agree_on_a_seeded_sample():
    cases = _sample(6, 36)  # (1, 24) before the balls were sized for contact: no margin failure left
    res = _screen(cases)
    seen = _compare(cases, res)
    # the sample holds accepted straight and serpentine disks and margin failures (8
    # accepted since the balls keep to the flank radius they leave at theta_max)
    assert seen["both_ok"] >= 7 and seen["serpentine"] >= 3 and seen["both_fail"] >= 5
    assert np.any(res["code"] == YIELD)


def test_stress_passes_agree():
    """Disks that need a lower beam stress (small disks, large r_c, margins 1.1-1.5):
    screening and design land on the same beam stress, or both give up. From a seeded
    sample, the first disks screening derates, accepts as they are, and rejects. (R_o 26 mm:
    at 20 mm every disk of this sample that passed the stress has tip webs that hold its
    low stiffness out of the correction's reach, ``web_stiffness``.)"""
    rng = np.random.default_rng(3)
    m = 400
    cases = np.column_stack([
        rng.uniform(20e3, 80e3, m), rng.uniform(0.1, 0.25, m), np.full(m, 26.0),
        rng.choice([2.0, 3.0, 4.5, 6.0], m), rng.choice([7.5, 9.0], m), rng.choice([0, -2, -4], m),
        rng.uniform(1.1, 1.5, m), rng.uniform(800.0, 1200.0, m)])
    res = _screen(cases)
    ok = res["code"] == OK
    pick = np.concatenate([np.flatnonzero(ok & (res["derating"] < 0.99))[:3],
                           np.flatnonzero(ok & (res["derating"] == 1))[:1],
                           np.flatnonzero(res["code"] == YIELD)[:2]])
    seen = _compare(cases[pick], {k: v[pick] for k, v in res.items()})
    derated = int(np.sum(ok & (res["derating"] < 0.99)).clip(max=3))
    assert derated == 3
    assert seen["derated"] == derated and seen["both_ok"] == derated + 1 \
        and seen["both_fail"] == 2


@pytest.mark.slow
def test_screening_and_design_agree_on_a_larger_sample():
    cases = _sample(8, 150)
    seen = _compare(cases, _screen(cases))
    assert seen["both_ok"] >= 30 and seen["serpentine"] >= 5


def test_disks_whose_webs_hold_the_stiffness_fail_as_the_design_does():
    """Small soft disks (R_o 20 mm, 20-80 N*m/rad): the disks screening fails on
    ``web_stiffness`` are refused by the design for the same reason, and the disk's excess
    is that of the design's own beam stiffness at its widths and 0.9 x them."""
    rng = np.random.default_rng(3)
    m = 400
    cases = np.column_stack([
        rng.uniform(20e3, 80e3, m), rng.uniform(0.1, 0.25, m), np.full(m, 20.0),
        rng.choice([2.0, 3.0, 4.5, 6.0], m), rng.choice([7.5, 9.0], m), np.zeros(m),
        rng.uniform(1.1, 1.5, m), rng.uniform(800.0, 1200.0, m)])
    res = _screen(cases)
    pick = np.flatnonzero(res["code"] == WEB_STIFFNESS)[:2]
    assert pick.size == 2 and np.all(res["value"][pick] > 1.0)
    for j in pick:
        K, th, ro, z, rc, _, margin, sigma = cases[j]
        spec = replace(BASE, target_stiffness_Nmm_per_rad=K, max_deflection_rad=th,
                       outer_radius_mm=ro, thickness_mm=z, contact_radius_mm=rc)
        mat = replace(JOB.material, safety_factor=float(margin), design_stress_MPa=float(sigma))
        with pytest.raises(DesignError, match="minimum web"):
            design_spring(spec, mat, JOB.manufacturing, JOB.hardware, explain=False,
                          candidates=1)
