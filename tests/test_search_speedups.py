"""The design search's shortcuts (issue 22) give the same results as the work they skip.

- The layout enumeration's screen: the (N, r_c) pairs it passes over without sizing their
  balls and rims cannot change the ranked layouts. Reference: the brute-force enumeration,
  every pair through :func:`tip_ball` and :func:`layout_at` (the enumeration before the
  screen), on specs with and without the layout keys fixed, with and without the Hertz
  contact limit, at several beam stresses.
- The cam's clearance to the ring by blocks of points: the all-pairs minimum, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from springcad.config import job_from_dict
from springcad.design import flexure as fx
from springcad.design import layout
from springcad.design.layout import ContactLimit, candidate_layouts, layout_at, tip_ball
from springcad.errors import DesignError

BASE = {"stiffness_Nm_per_rad": 150, "max_deflection_deg": 14, "outer_radius_mm": 36,
        "thickness_mm": 5.0}


def _unscreened(spec, ns, *args):
    """A screen that passes every (N, r_c) pair: the enumeration without its shortcut."""
    return lambda rc: (np.full(np.shape(rc) + (len(ns),), np.inf),
                       np.ones(np.shape(rc) + (len(ns),), bool))


def _brute_force(spec, sigma, E, max_root_radius_mm, contact, limit=12):
    """Every pair through :func:`tip_ball` and :func:`layout_at`: the same enumeration with
    the screen replaced by one that passes every pair."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(layout, "_screen", lambda spec, sigma, E, ns, cap, contact: _unscreened(spec, ns))
        return candidate_layouts(spec, sigma, E, limit, max_root_radius_mm, contact)


CASES = [{}, {"thickness_mm": 12.0}, {"thickness_mm": 2.0, "outer_radius_mm": 50},
         {"max_deflection_deg": 25}, {"stiffness_Nm_per_rad": 20, "min_tip_radius_mm": 0.5},
         {"tip_radius_mm": 0.4}, {"contact_radius_mm": 9.0}, {"n_flexures": 24},
         {"root_radius_mm": 30.0}, {"tip_radius_mm": 0.35, "contact_radius_mm": 8.0}]


@pytest.mark.parametrize("over", CASES, ids=[",".join(c) or "free" for c in CASES])
def test_screened_layouts_are_the_brute_force_ones(over):
    job = job_from_dict({"springs": {"A": {**BASE, **over}}})
    spec = job.springs["A"]
    E = job.material.material.youngs_modulus_MPa
    contact = ContactLimit.of(job.material, spec.max_deflection_rad, job.manufacturing)
    compared = 0
    for sigma in (500.0, 780.0, 1100.0):
        for cap in (math.inf, spec.outer_radius_mm - 2.5):
            for lim in (None, contact):
                try:
                    want = _brute_force(spec, sigma, E, cap, lim)
                except DesignError:
                    want = None
                try:
                    got = candidate_layouts(spec, sigma, E, max_root_radius_mm=cap, contact=lim)
                except DesignError:
                    got = None
                if want:  # (the brute force has no refusal text: compare layouts only)
                    assert got == want
                    compared += 1
                else:
                    assert not got
    assert compared > 0


@pytest.mark.parametrize("over", CASES[:6] + CASES[8:9], ids=[",".join(c) or "free"
                                                              for c in CASES[:6] + CASES[8:9]])
def test_screen_bounds_every_pair(over):
    """Pair by pair: no layout reaches beyond the screen's straight-limit bound, and a pair
    screened as 'balls cannot fit' is one the exact rules refuse."""
    from springcad.design.layout import _screen

    job = job_from_dict({"springs": {"A": {**BASE, **over}}})
    spec = job.springs["A"]
    E = job.material.material.youngs_modulus_MPa
    contact = ContactLimit.of(job.material, spec.max_deflection_rad, job.manufacturing)
    ns = range(3, 200)
    laid, screened, by_contact = 0, 0, 0
    radii = np.linspace(1.5, 0.6 * spec.outer_radius_mm, 25)
    for sigma, cap in ((600.0, math.inf), (900.0, spec.outer_radius_mm - 3.0)):
        loose = _screen(spec, sigma, E, ns, cap)(radii)[1]
        screen = _screen(spec, sigma, E, ns, cap, contact)
        reaches, fitting = screen(radii)  # all radii at once: the float calls row by row
        for j, rc in enumerate(radii):
            reach, may_fit = screen(float(rc))
            assert np.array_equal(reach, reaches[j]) and np.array_equal(may_fit, fitting[j])
            for i, n in enumerate(ns):
                rb = tip_ball(spec, sigma, n, float(rc), contact)[2]
                ok = math.isfinite(rb) and n <= fx.max_flexures(rb, float(rc))
                if not may_fit[i]:
                    assert not ok
                    screened += 1
                    by_contact += bool(loose[j, i])
                if ok:
                    try:
                        lay = layout_at(spec, sigma, E, n, float(rc), cap, contact)
                    except DesignError:
                        continue
                    assert lay.theta_s <= reach[i]
                    laid += 1
    assert laid > 0 and screened > 0
    if spec.tip_radius_mm is None:  # the contact bound screens pairs the bending one passes
        assert by_contact > 0


def test_cam_clearance_is_the_all_pairs_minimum():
    """Point sets along nearby curves (a cam flank and a ring edge) and random clouds, small
    and large: the block search returns the all-pairs minimum distance bit for bit."""
    from springcad.design.driven import min_distance_mm as _min_distance

    rng = np.random.default_rng(11)
    for case in range(200):
        n, m = rng.integers(1, 900), rng.integers(1, 900)
        if case % 2:
            t, u = np.sort(rng.uniform(0, 3, n)), np.sort(rng.uniform(0, 3, m))
            a = np.c_[np.cos(t), np.sin(t)] * 5.0
            b = np.c_[np.cos(u), np.sin(u)] * (5.0 + rng.uniform(0.01, 0.2))
        else:
            a, b = rng.uniform(-3, 3, (n, 2)), rng.uniform(-1, 4, (m, 2))
        want = math.sqrt(float(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1).min()))
        assert _min_distance(a, b) == want


def test_kept_layouts_design_the_same_spring_with_less_work(monkeypatch):
    """The default job (thickness from stock): the design with each layout rank designed once
    per stock choice (:func:`search.kept_layouts`) is the design without it, field for field
    of design.json, and fewer layout designs ran (the chosen plate's probe and its search
    share theirs)."""
    import contextlib
    import json
    from pathlib import Path

    from springcad.config import load_job
    from springcad.design import search
    from springcad.design.job import design_job

    job = load_job(Path(__file__).resolve().parents[1] / "templates" / "default.toml")
    calls = []
    inner = search._design_with_margin

    def counted(*args):
        calls.append(args)
        return inner(*args)

    monkeypatch.setattr(search, "_design_with_margin", counted)
    kept = json.dumps(design_job(job, explain=False).to_dict(), sort_keys=True, default=str)
    n_kept = len(calls)
    calls.clear()
    monkeypatch.setattr(search, "kept_layouts", contextlib.nullcontext)
    fresh = json.dumps(design_job(job, explain=False).to_dict(), sort_keys=True, default=str)
    assert kept == fresh
    assert n_kept < len(calls)
