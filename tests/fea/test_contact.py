"""Cam-flexure contact sweep (fea.contact): the solver against closed forms and the linear
FEA, the straight reference ring clean, deliberately wrong cams flagged."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def straight_sweep(straight):
    """The straight radial flexure: no tangential-radial coupling, the design's own cam."""
    from fea.contact import contact_sweep

    return contact_sweep(straight)


def _sector(design, material, level=0):
    from fea.contact import _mesh

    return _mesh(design, None, level)[0]


# ------------------------------------------------------------------ building blocks
def test_hertz_line_contact_closed_form():
    """p0 and b balance the load (P = pi b p0 / 2) and the subsurface von Mises maximum is
    Johnson's 0.56 p0 at z = 0.70 b for nu = 0.3."""
    from fea.contact_solver import hertz_line_contact

    P, curv, E, nu = 100.0, 1 / 0.3 + 1 / 2.0, 200e3, 0.3
    h = hertz_line_contact(P, curv, E, nu)
    e_star = E / (2 * (1 - nu ** 2))
    assert h["p0_MPa"] == pytest.approx(math.sqrt(P * e_star * curv / math.pi), rel=1e-12)
    assert math.pi * h["half_width_mm"] * h["p0_MPa"] / 2 == pytest.approx(P, rel=1e-12)
    assert h["von_mises_max_MPa"] / h["p0_MPa"] == pytest.approx(0.557, abs=0.003)
    assert h["depth_mm"] / h["half_width_mm"] == pytest.approx(0.70, abs=0.02)
    assert hertz_line_contact(0.0, curv, E, nu)["p0_MPa"] == 0.0


@pytest.mark.parametrize("seed", range(4))
def test_min_distance_is_the_smallest_projection(seed):
    """_Segments.min_distance prunes the points that cannot come nearer: it returns the very
    number (==) of min(below, project(q)[0].min()) over all points, with and without a bound,
    for a dense curved polyline (the cam's) and a coarse one (a flexure boundary), points near
    and far."""
    from fea.contact_solver import _Segments

    rng = np.random.default_rng(seed)
    for n, step in ((4000, 1e-3), (300, 0.05)):
        s = np.cumsum(rng.uniform(0.5, 1.5, n + 1)) * step
        P = np.column_stack([s, 0.3 * np.sin(3 * s) + 0.05 * rng.standard_normal(n + 1) * step])
        segs = _Segments(P[:-1], P[1:], k=3 if n > 1000 else 8)
        q = np.column_stack([rng.uniform(-0.5, s[-1] + 0.5, 600), rng.uniform(-1.5, 1.5, 600)])
        q[:50, 1] = np.interp(q[:50, 0], P[:, 0], P[:, 1]) + rng.uniform(-1e-3, 1e-3, 50)
        full = float(segs.project(q)[0].min())
        assert segs.min_distance(q) == full
        for below in (0.5 * full, full, 2 * full, 0.3, math.inf, -0.2):
            assert segs.min_distance(q, below) == min(below, full)
        assert segs.min_distance(q[100:], full) == min(full, float(segs.project(q[100:])[0].min()))


def test_lcp_matches_enumeration_of_active_sets():
    from fea.contact_solver import lcp

    rng = np.random.default_rng(7)
    for _ in range(20):
        A = rng.normal(size=(5, 5))
        M = A @ A.T + 0.1 * np.eye(5)
        q = rng.normal(size=5)
        lam = lcp(M, q)
        ref = None
        for act in itertools.product((0, 1), repeat=5):
            a = np.flatnonzero(act)
            x = np.zeros(5)
            if len(a):
                x[a] = np.linalg.solve(M[np.ix_(a, a)], -q[a])
            w = q + M @ x
            if np.all(x >= -1e-12) and np.all(w >= -1e-10):
                ref = x
        assert np.allclose(lam, ref, atol=1e-8)


@pytest.mark.parametrize("which", ["straight", "s1"])
def test_flat_pad_reproduces_the_linear_fea(which, request, material):
    """A rigid flat pad normal to the push direction, turned about the ring axis, against
    the same mesh: the stiffness just after contact is the linear FEA's (traction patch),
    also for the coupled serpentine S1, and the onset is gap / r_c. The pad turns with the
    cam, tilting its normal by theta; with S1's coupling (c_xy / c_xx = -0.31) that
    changes K by ~2 x 0.31 x theta, so the check is made within 0.3 % of a degree of
    contact. The design cams differ from it only by their contact normal."""
    from fea.contact_path import AnglePath, onset_rad
    from fea.contact_solver import CamCurve, SectorContact
    from springcad.design.curves import Line

    design = request.getfixturevalue(which)
    rc, rb = design.contact_radius_mm, design.tip_radius_mm
    gap = 0.005
    x0 = rb + gap
    pad = Line((x0, rc + 0.12), (x0, rc - 0.12))  # running down: outward normal -x
    curve = CamCurve([("flank_ccw", 0, pad)], True, 0.0)
    fm = _sector(design, material)
    results = {}
    for nonlinear in (True, False):
        sc = SectorContact(fm, material, curve, rc + 1.0, nonlinear=nonlinear)
        on = onset_rad(sc, 1, design.max_deflection_rad)
        assert on == pytest.approx(gap / rc, rel=0.01)
        a = 0.002 * design.max_deflection_rad
        st = AnglePath(sc, 1, design.max_deflection_rad / 8).to(on + a)
        results[nonlinear] = sc.torque(st) / a
        if nonlinear:  # exact moment balance in the current configuration
            assert sc.reaction_torque(st) == pytest.approx(sc.torque(st), rel=1e-6)
    assert results[True] == pytest.approx(sc.stiffness_linear, rel=0.003)
    assert results[True] == pytest.approx(results[False], rel=5e-4)


def test_dilated_cam_moves_the_onset_by_the_offset(straight, material):
    """A flat pad w away from the ball, grown by E (the ball and cam profiles E larger
    together): contact starts at (w - E) / r_c; shrunk, at (w + |E|) / r_c."""
    from fea.contact_path import onset_rad
    from fea.contact_solver import CamCurve, SectorContact
    from springcad.design.curves import Line

    rc, rb = straight.contact_radius_mm, straight.tip_radius_mm
    w = 0.03
    pad = Line((rb + w, rc + 0.12), (rb + w, rc - 0.12))
    curve = CamCurve([("flank_ccw", 0, pad)], True, 0.0)
    sc = SectorContact(_sector(straight, material), material, curve, rc + 1.0)
    for E in (0.0, 0.012, -0.012):
        sc.cam = curve.dilated(E)
        assert onset_rad(sc, 1, straight.max_deflection_rad) == pytest.approx((w - E) / rc,
                                                                           rel=0.01)


def test_options_are_validated():
    from fea.contact_result import ContactOptions
    from springcad.errors import SolverError

    for bad in ({"steps": 4}, {"linearity_tolerance": 0.0}, {"gap_tolerance": 0.7}):
        with pytest.raises(SolverError):
            ContactOptions(**bad)


# ------------------------------------------------------------------ the straight reference
def test_straight_ring_sweep_is_clean(straight, straight_sweep):
    sw = straight_sweep
    theta = straight.max_deflection_rad
    assert sw.ok, sw.flags
    for key, sign in (("+", 1), ("-", -1)):
        steps = sw.steps[key]
        assert [s.angle_rad for s in steps] == pytest.approx([sign * theta * i / 8
                                                              for i in range(9)])
        # small-angle stiffness: the linear FEA of the same mesh within 0.5 %
        assert abs(sw.small_angle_error(key)) < 0.005
        # the designed gap: contact starts at w_gap / r_c
        w = straight.manufacturing.w_gap_mm
        assert sw.onset_rad[key] == pytest.approx(sign * w / straight.contact_radius_mm,
                                                  rel=0.01)
        end = steps[-1]
        assert end.torque_Nmm == pytest.approx(
            sw.stiffness_linear_Nmm_per_rad * (end.angle_rad - sw.onset_rad[key]), rel=0.01)
        assert all(s.equilibrium_error < 1e-5 for s in steps)
        (c,) = end.contacts
        assert c["intended"] and 0.0 < c["flank_fraction"] < 0.9
        assert c["hertz"]["p0_MPa"] > 0
        assert min(v for k, v in end.gaps_mm.items() if k != "driving_flank") > 0.005
    assert sw.rest_clearance_mm == pytest.approx(straight.manufacturing.w_gap_mm, rel=0.01)
    # mirror symmetry of the straight ring and its cam
    for p, m in zip(sw.steps["+"], sw.steps["-"]):
        assert p.torque_Nmm == pytest.approx(-m.torque_Nmm, rel=0.005, abs=1e-6)


def test_paper_s1_ball_stays_on_its_flank(s1):
    """The serpentine S1 (designed uncoupled) against its own cam, both ways to 16 deg: the
    small-angle stiffness is the linear FEA's within 0.5 %, the ball stays on the driving
    flank with no second contact, and the flank it travels stays short of the tooth tip.
    With the lobes balanced on the root angle instead (the reference tool's shape) the
    same sweep gave -3 % / +11 % and the ball reached the tooth tip by 14 deg."""
    from fea.contact import contact_sweep

    sw = contact_sweep(s1)
    codes = {f["code"] for f in sw.flags}
    assert not codes & {"small_angle", "leaves_flank", "second_contact", "gap", "no_contact"}, \
        sw.flags
    for key in "+-":
        assert abs(sw.small_angle_error(key)) < 0.005
        (c,) = sw.steps[key][-1].contacts
        assert c["intended"] and c["flank_fraction"] < 0.9


def test_sweep_serialises(straight_sweep):
    doc = json.loads(json.dumps(straight_sweep.to_dict()))
    assert set(doc["torque_angle"]) == {"+", "-"}
    step = doc["torque_angle"]["+"][-1]
    for key in ("angle_deg", "torque_Nm", "secant_stiffness_Nm_per_rad",
                "tangent_stiffness_Nm_per_rad", "contacts", "gaps_mm", "peak_von_mises_MPa"):
        assert key in step
    assert {"pocket", "back_flank", "driving_tooth_tip", "neighbour_flexure"} <= set(
        step["gaps_mm"])
    assert doc["ok"] is True and doc["flags"] == []


def test_at_max_reads_the_sweeps_ends(straight):
    """The contact rules at +-theta_max: the nominal clearances by ring part are the sweep's
    own gaps at theta_max (their minimum over the parts), the ball stress is the closed
    form from the reported force and flank radius, and a cam grown by the tolerances brings
    the back flank nearer (the ball sits farther along the driving flank). Tolerances of
    10 um each, within the designed 25 um clearance."""
    from fea.contact import contact_sweep
    from springcad.design.contact_stress import tip_contact_von_mises_MPa

    m = dataclasses.replace(straight.manufacturing, t_spring_mm=0.01, t_shaft_mm=0.01)
    straight = dataclasses.replace(straight, manufacturing=m)
    sweep = contact_sweep(straight)
    at = sweep.at_max
    T = m.t_spring_mm + m.t_shaft_mm
    assert at.offsets_mm == pytest.approx((-T, 0.0, T))
    for key in "+-":
        end, step = at.ends[key], sweep.steps[key][-1]
        for cam_surface, gap in step.gaps_mm.items():
            parts = [c.nominal_mm for c in end.clearances
                     if c.name.split("/")[0] == cam_surface]
            if cam_surface == "driving_flank":
                continue  # the contact itself; its other parts are separate clearances
            if cam_surface == "neighbour_flexure":
                parts = [c.nominal_mm for c in end.clearances if c.name == cam_surface]
            assert min(parts) == pytest.approx(gap, abs=1e-9), cam_surface
        c = end.contact
        mat = straight.material.material
        assert c["von_mises_MPa"] == pytest.approx(tip_contact_von_mises_MPa(
            c["force_N"], straight.tip_radius_mm, c["flank_radius_mm"], straight.thickness_mm,
            mat.youngs_modulus_MPa, mat.poisson_ratio), rel=2e-3)
        back = next(g for g in end.clearances if g.name == "back_flank/ball")
        assert back.by_offset_mm[T] < back.nominal_mm < back.by_offset_mm[-T]
    doc = json.loads(json.dumps(sweep.to_dict()))["at_max_deflection"]
    assert doc["ok"] == at.ok and doc["failures"] == at.failures()


def test_offset_continuation_reaches_the_state_a_path_from_rest_does(straight, material):
    """The toleranced end states are continued from the nominal one in the cam dilation at
    theta_max (fea.contact_path.offset_path with ``end``). Where the path from rest with the
    dilated cam converges on the driving flank, the two routes reach the same equilibrium
    (frictionless elastic contact: one state): every clearance within 0.2 um, the same
    contact force within 0.1 %; and the gaps move smoothly with E (second difference over
    the +-20 um offsets under 2 um), as a part whose profiles deviate does."""
    from fea.contact import _end_state
    from fea.contact_path import AnglePath, offset_path
    from fea.contact_solver import CamCurve, SectorContact
    from fea.contact import _ball, _cam_features, _junction_mm

    d = straight
    feats = _cam_features(d.cam, d.n_flexures)
    curve = CamCurve(feats, d.cam.loop("teeth").signed_area() > 0, _junction_mm(feats, d))
    ball = _ball(d)
    sc = SectorContact(_sector(d, material), material, curve,
                       float(np.max(np.hypot(*curve.P.T))) + 2 * ball[1] + 0.5)
    th = d.max_deflection_rad
    groups = curve.groups("flank_ccw")
    end = AnglePath(sc, 1, th / 8).to(th)
    gaps = {}
    for E in (-0.02, 0.02):
        cont = _end_state(sc, offset_path(sc, curve, E, 1, th, 8, end=end), "flank_ccw", 1,
                          ball, material, groups)
        sc.cam = curve
        rest = _end_state(sc, offset_path(sc, curve, E, 1, th, 8), "flank_ccw", 1, ball,
                          material, groups)
        sc.cam = curve
        assert cont.offset_mm == pytest.approx(E) and rest.offset_mm == pytest.approx(E)
        assert cont.force_N == pytest.approx(rest.force_N, rel=1e-3)
        for name, g in rest.clearances_mm.items():
            assert cont.clearances_mm[name] == pytest.approx(g, abs=2e-4), name
        gaps[E] = cont.clearances_mm
    nominal = _end_state(sc, end, "flank_ccw", 1, ball, material, groups).clearances_mm
    for name, g0 in nominal.items():
        assert abs(gaps[-0.02][name] - 2 * g0 + gaps[0.02][name]) < 2e-3, name


def test_a_cam_grown_past_the_clearance_is_named(straight, straight_sweep):
    """Tolerances of 30 um each against a 25 um designed clearance: the cam grown by 60 um
    pinches the ball at rest; that offset is named, the others still judge the gaps."""
    at = straight_sweep.at_max
    assert 0.06 not in at.offsets_mm and 0.0 in at.offsets_mm
    for end in at.ends.values():
        assert any("pinched between both flanks" in n and "overlaps the ball at rest by 35 um"
                   in n for n in end.notes), end.notes
        assert end.clearances


def test_contact_png(straight_sweep, tmp_path):
    import matplotlib.image as mpimg

    from springcad.report.contact_png import render_contact

    path = render_contact(straight_sweep, tmp_path / "contact.png")
    img = mpimg.imread(path)
    assert img.shape[0] > 1000 and img.shape[1] > 1000
    assert img[..., :3].std() > 0.1  # not blank


# ------------------------------------------------------------------ wrong cams are flagged
def _wrong_cam(design, **change):
    from springcad.design.cam import cam_profile

    if "w_gap_mm" in change:
        design = dataclasses.replace(design, manufacturing=dataclasses.replace(
            design.manufacturing, w_gap_mm=change["w_gap_mm"]))
    if "max_deflection_rad" in change:  # a cam cut for a smaller deflection
        spec = dataclasses.replace(design.spec, max_deflection_rad=change["max_deflection_rad"])
        design = dataclasses.replace(design, spec=spec)
    return cam_profile(design)[0]


@pytest.mark.slow
@pytest.mark.parametrize("change, codes", [
    ({"max_deflection_rad": 0.35}, {"leaves_flank"}),  # flank ends at ~0.44 theta_max
    ({"w_gap_mm": 0.0}, {"gap", "second_contact"}),  # no clearance: ball bears on the pocket
    ({"w_gap_mm": 0.01}, {"gap"}),                      # gap below the designed 0.025 mm
])
def test_wrong_cam_is_flagged(straight, change, codes):
    from fea.contact import contact_sweep

    change = {k: v * straight.max_deflection_rad if k == "max_deflection_rad" else v
              for k, v in change.items()}
    sw = contact_sweep(straight, cam=_wrong_cam(straight, **change))
    assert codes <= {f["code"] for f in sw.flags}, sw.flags
    assert not sw.ok


# ------------------------------------------------------------------ inside the verification
def test_verification_runs_the_sweep_on_its_own_mesh(straight):
    from fea.verify import VerifyOptions, verify_spring

    v = verify_spring(straight, VerifyOptions(model="2d", correct=False, keep_fields=False))
    sw = v.contact
    assert sw is not None and sw.level == 0
    assert sw.stiffness_linear_Nmm_per_rad == pytest.approx(
        v.run.base2d[0].stiffness_Nmm_per_rad, rel=1e-9)
    assert sw.peak_verified_MPa == pytest.approx(v.peak_von_mises_MPa)
    doc = v.to_dict()["contact_sweep"]
    assert len(doc["torque_angle"]["+"]) == 9 and len(doc["torque_angle"]["-"]) == 9
    off = verify_spring(straight, VerifyOptions(model="2d", correct=False, keep_fields=False,
                                                contact=False))
    assert off.contact is None and "contact_sweep" not in off.to_dict()
