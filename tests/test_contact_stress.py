"""Hertz line contact of the tip ball (springcad.design.contact_stress) against closed forms
and an independent superposition of the Flamant line-load solution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from springcad.design import contact_stress as cs


def _flamant(x_over_b, z_over_b, n=4000):
    """Stresses / p0 under an elliptical pressure p0 sqrt(1 - s^2) on |s| < 1 (units of b),
    by superposing Flamant's point line load (Johnson eq. 2.15) over s with Gauss-Chebyshev
    quadrature of the second kind: independent of McEwen's closed form."""
    k = np.arange(1, n + 1)
    t = k * np.pi / (n + 1)
    s = np.cos(t)
    w = np.pi / (n + 1) * np.sin(t) ** 2  # weights of sqrt(1 - s^2) f(s)
    dx = x_over_b - s
    r2 = dx * dx + z_over_b ** 2
    c = -2.0 / np.pi
    sx = c * np.sum(w * dx * dx * z_over_b / r2 ** 2)
    sz = c * np.sum(w * z_over_b ** 3 / r2 ** 2)
    txz = c * np.sum(w * dx * z_over_b ** 2 / r2 ** 2)
    return sx, sz, txz


@pytest.mark.parametrize("x,z", [(0.0, 0.3), (0.0, 0.7), (0.5, 0.5), (-0.8, 0.4), (1.5, 0.6),
                                 (0.3, 2.0)])
def test_mcewen_field_matches_flamant_superposition(x, z):
    sx, _, sz, txz = cs.subsurface_stress(x, z, 0.3)
    fx, fz, ft = _flamant(x, z)
    assert float(sx) == pytest.approx(fx, abs=2e-4)
    assert float(sz) == pytest.approx(fz, abs=2e-4)
    assert abs(float(txz)) == pytest.approx(abs(ft), abs=2e-4)


def test_on_axis_field_is_johnsons_closed_form():
    """Johnson eq. 4.49 on the load axis: sigma_x = -((1 + 2 z^2) / sqrt(1 + z^2) - 2 z),
    sigma_z = -1 / sqrt(1 + z^2) (units p0, b), no shear; at the surface both are -p0."""
    z = np.linspace(0.0, 3.0, 31)
    sx, sy, sz, txz = cs.subsurface_stress(0.0, z, 0.3)
    root = np.sqrt(1 + z * z)
    assert np.allclose(sx, -((1 + 2 * z * z) / root - 2 * z), atol=1e-12)
    assert np.allclose(sz, -1 / root, atol=1e-12)
    assert np.allclose(sy, 0.3 * (sx + sz), atol=1e-12)
    assert np.allclose(txz, 0.0, atol=1e-12)


def test_von_mises_peak_is_the_maximum_of_the_whole_field():
    """The coefficient used for design is the maximum over the whole (x, z) field, derived
    here on a grid (Flamant-checked field), not only on the axis; nu = 0.3 gives the
    textbook 0.557 p0 at 0.70 b."""
    c_vm, zeta = cs.von_mises_peak(0.3)
    x, z = np.meshgrid(np.linspace(-2, 2, 401), np.linspace(1e-3, 3, 601))
    vm = cs.von_mises(*cs.subsurface_stress(x, z, 0.3))
    i = np.unravel_index(np.argmax(vm), vm.shape)
    assert vm[i] == pytest.approx(c_vm, abs=2e-4)
    assert abs(x[i]) < 0.011 and z[i] == pytest.approx(zeta, abs=0.01)
    assert c_vm == pytest.approx(0.557, abs=0.001) and zeta == pytest.approx(0.704, abs=0.003)
    # the independent superposition gives the same peak at that depth
    fx, fz, _ = _flamant(0.0, zeta)
    assert cs.von_mises(fx, 0.3 * (fx + fz), fz, 0.0) == pytest.approx(c_vm, abs=5e-4)


def test_max_shear_is_johnsons_030_at_0786():
    c, zeta = cs.shear_peak()
    assert c == pytest.approx(0.300, abs=5e-4) and zeta == pytest.approx(0.786, abs=2e-3)


def test_textbook_line_contact_numbers():
    """Two steel cylinders R1 = R2 = 10 mm (R = 5 mm), 100 N/mm, E = 210 GPa, nu = 0.3:
    E* = E / (2 (1 - nu^2)) = 115.38 GPa, b = sqrt(4 P R / (pi E*)) = 0.07428 mm,
    p0 = 2 P / (pi b) = 857.1 MPa (worked by hand); the load balances pi b p0 / 2 = P."""
    c = cs.line_contact(100.0, 1 / 10 + 1 / 10, 210e3, 0.3)
    assert c.contact_modulus_MPa == pytest.approx(115384.6, rel=1e-6)
    assert c.half_width_mm == pytest.approx(0.07428, rel=1e-3)
    assert c.p0_MPa == pytest.approx(857.1, rel=1e-3)
    assert math.pi * c.half_width_mm * c.p0_MPa / 2 == pytest.approx(100.0, rel=1e-12)
    assert c.von_mises_max_MPa == pytest.approx(0.557 * 857.1, rel=2e-3)
    assert c.max_shear_MPa == pytest.approx(0.300 * 857.1, rel=2e-3)
    # E* of two different materials: steel on a 70 GPa, nu = 0.33 aluminium
    assert cs.contact_modulus_MPa(210e3, 0.3, 70e3, 0.33) == pytest.approx(
        1 / ((1 - 0.09) / 210e3 + (1 - 0.33 ** 2) / 70e3), rel=1e-12)


def test_flank_curvature_convex_concave_flat():
    args = dict(force_N=200.0, r_tip_mm=0.3, thickness_mm=5.0, E_MPa=200e3, nu=0.3)
    convex = cs.tip_contact_von_mises_MPa(flank_radius_mm=1.2, **args)
    flat = cs.tip_contact_von_mises_MPa(flank_radius_mm=math.inf, **args)
    concave = cs.tip_contact_von_mises_MPa(flank_radius_mm=-1.2, **args)
    assert convex > flat > concave
    # sigma ~ sqrt(1/R): the ratio is the square root of the curvature sums
    assert convex / flat == pytest.approx(math.sqrt((1 / 0.3 + 1 / 1.2) / (1 / 0.3)), rel=1e-12)
    with pytest.raises(ValueError, match="does not fit"):
        cs.tip_contact_von_mises_MPa(flank_radius_mm=-0.25, **args)
    with pytest.raises(ValueError):
        cs.tip_contact_von_mises_MPa(flank_radius_mm=0.0, **args)


@pytest.mark.parametrize("flank", [1.19, math.inf, -2.0])
def test_min_tip_radius_meets_the_allowable_exactly(flank):
    kw = dict(force_N=220.0, thickness_mm=5.0, E_MPa=200e3, nu=0.28)
    allowable = 1344 / 1.2
    r = cs.min_tip_radius_for_contact_mm(flank_radius_mm=flank, allowable_MPa=allowable, **kw)
    assert 0.3 < r < 5.0
    assert cs.tip_contact_von_mises_MPa(r_tip_mm=r, flank_radius_mm=flank, **kw) == \
        pytest.approx(allowable, rel=1e-9)
    assert cs.tip_contact_von_mises_MPa(r_tip_mm=1.05 * r, flank_radius_mm=flank, **kw) < \
        allowable


def test_min_tip_radius_is_infinite_when_the_flank_alone_is_too_sharp():
    r = cs.min_tip_radius_for_contact_mm(220.0, 0.05, 5.0, 200e3, 0.3, 1000.0)
    assert r == math.inf
    assert cs.min_tip_radius_for_contact_mm(0.0, 1.0, 5.0, 200e3, 0.3, 1000.0) == 0.0


def test_margin():
    m = cs.ContactMargin(1420.0, 1344.0, 1.2)
    assert m.margin == pytest.approx(1344 / 1420) and not m.ok
    assert cs.ContactMargin(1000.0, 1344.0, 1.2).ok
    assert cs.ContactMargin(0.0, 1344.0, 1.2).margin == math.inf


# ------------------------------------------------ the flank radius the ball leaves
def _flank_points(rc, rho, psi):
    """The cam flank p(psi) = R(psi) (r_c psi - rho, r_c) of springcad.design.cam's docstring,
    written out here (mm)."""
    x, y = rc * psi - rho, rc
    return np.array([x * np.cos(psi) - y * np.sin(psi), x * np.sin(psi) + y * np.cos(psi)])


def test_the_rigid_contact_lies_where_the_ball_touches_the_flank():
    """At cam rotation theta the ball (radius r_b, its centre r_c theta - gap along the
    flexure's normal, as cam.py's kinematics place it) is r_b from the flank point p(theta)
    and farther from every other flank point; the flank's radius of curvature there, from
    three points, is r_c theta - r_b - gap."""
    rc, rb, gap, theta = 6.0, 0.3, 0.04, 0.2
    rho = rb + gap
    psi = np.linspace(rho / rc, rho / rc + 1.5 * theta, 200001)
    flank = _flank_points(rc, rho, psi)
    c, s = math.cos(theta), math.sin(theta)
    u = rc * theta - gap
    centre = np.array([u * c - rc * s, u * s + rc * c])
    d = np.hypot(*(flank - centre[:, None]))
    i = int(np.argmin(d))
    assert d[i] == pytest.approx(rb, abs=1e-7)
    assert psi[i] == pytest.approx(theta, abs=2e-5)
    a, b, q = (_flank_points(rc, rho, theta + e) for e in (-1e-4, 0.0, 1e-4))
    cross = (b[0] - a[0]) * (q[1] - b[1]) - (b[1] - a[1]) * (q[0] - b[0])
    radius = np.linalg.norm(b - a) * np.linalg.norm(q - b) * np.linalg.norm(q - a) / (2 * abs(cross))
    assert radius == pytest.approx(cs.flank_radius_at_contact_mm(rc, rb, gap, theta), rel=1e-6)
    assert cs.flank_position_at_contact_mm(rc, rb, gap, theta) == pytest.approx(
        0.5 * rc * (theta - rho / rc) ** 2, rel=1e-12)


def test_the_ball_window_meets_the_allowable_at_both_ends_and_is_best_in_the_middle():
    """The window's ends give exactly the allowable on the flank radius each leaves; the
    middle r_b = (r_c theta - gap)/2 is the least stressed ball; outside, the stress exceeds
    it; a layout that leaves no window gives none."""
    kw = dict(force_N=150.0, thickness_mm=5.0, E_MPa=200e3, nu=0.3)
    rc, gap, theta, allow = 7.0, 0.04, 0.2, 1100.0
    lo, hi = cs.tip_radius_window_mm(kw["force_N"], rc, gap, theta, kw["thickness_mm"],
                                     kw["E_MPa"], kw["nu"], allow)

    def vm(r):
        return cs.tip_contact_von_mises_MPa(r_tip_mm=r, flank_radius_mm=cs.flank_radius_at_contact_mm(
            rc, r, gap, theta), **kw)

    assert 0 < lo < hi
    assert vm(lo) == pytest.approx(allow, rel=1e-9) and vm(hi) == pytest.approx(allow, rel=1e-9)
    mid = 0.5 * (rc * theta - gap)
    assert vm(mid) < allow and vm(0.9 * lo) > allow and vm(1.05 * hi) > allow
    assert vm(mid) < min(vm(0.95 * mid), vm(1.05 * mid))
    # the cusp rule: the contact at least s_min along the flank caps the ball
    s_min = 0.02
    _, capped = cs.tip_radius_window_mm(kw["force_N"], rc, gap, theta, kw["thickness_mm"],
                                        kw["E_MPa"], kw["nu"], allow, s_min)
    assert cs.flank_position_at_contact_mm(rc, capped, gap, theta) == pytest.approx(s_min)
    assert cs.tip_radius_window_mm(kw["force_N"], 2.0, gap, 0.1, kw["thickness_mm"],
                                   kw["E_MPa"], kw["nu"], allow) == (math.inf, -math.inf)


def test_ball_advice_names_a_window_that_works_or_a_reach_that_opens_one():
    kw = dict(thickness_mm=2.0, E_MPa=190e3, nu=0.3, allowable_MPa=880.0,
              min_flank_position_mm=0.02, tip_radius_mm=0.41)
    text = cs.ball_advice(58.3, 5.4068, 0.04, 0.1222, **kw)
    assert "no tip ball at this layout" in text
    rc_new = float(text.split("contact_radius_mm >= ")[1].split(",")[0])
    lo, hi = cs.tip_radius_window_mm(58.3, rc_new * 1.001, 0.04, 0.1222, 2.0, 190e3, 0.3, 880.0,
                                     0.02)
    assert lo <= hi
    ok = cs.ball_advice(58.3, 14.0, 0.04, 0.1222, **kw)
    lo_t, hi_t = (float(v) for v in ok.split("between ")[1].split(" (now")[0].split(" and "))
    assert 0 < lo_t < hi_t


def test_the_ball_window_on_floats_is_the_window_on_arrays():
    """The design search's float path and the synthesis screen's array path agree (random
    layouts, loads and materials, feasible and not, with and without load)."""
    rng = np.random.default_rng(7)
    n = 400
    args = (rng.uniform(0, 400, n) * (rng.random(n) > 0.05), rng.uniform(2, 20, n),
            rng.uniform(0.01, 0.06, n), rng.uniform(0.03, 0.4, n), rng.uniform(1, 12, n),
            rng.uniform(110e3, 210e3, n), rng.uniform(0.28, 0.34, n), rng.uniform(500, 1800, n),
            rng.uniform(0, 0.05, n))
    lo, hi = cs.tip_radius_window_mm(*args[:-1], args[-1])
    for i in range(n):
        lo_i, hi_i = cs.tip_radius_window_mm(*(float(a[i]) for a in args))
        assert lo_i == pytest.approx(lo[i], rel=1e-12) and hi_i == pytest.approx(hi[i], rel=1e-12)
    assert np.isinf(lo).any() and np.isfinite(lo).any() and (lo == 0).any()


def test_largest_contact_load_by_hand():
    """The largest tip load any ball carries on the flank full deflection leaves: the best
    ball is half the reach r_c theta - w_gap, curvature sum 4 / reach, so Hertz line
    contact (p0 = sqrt(F E* / (pi z R)), von Mises 0.557 p0 at nu 0.3) allows
    F = pi (s_allow / 0.557)^2 z reach / (4 E*), E* = E / (2 (1 - nu^2)). 420 HT at
    1120 MPa, r_c 13 mm, 6 deg, w_gap 0.04 mm, z 5 mm: 186 N."""
    from springcad.design.layout import ContactLimit

    E, nu, allow, rc, theta, gap, z = 200e3, 0.3, 1120.0, 13.0, math.radians(6), 0.04, 5.0
    limit = ContactLimit(E, nu, allow, gap, 0.0)
    reach = rc * theta - gap
    by_hand = math.pi * (allow / 0.557) ** 2 * z * reach / (4 * E / (2 * (1 - nu ** 2)))
    assert limit.max_load_N(rc, theta, z) == pytest.approx(by_hand, rel=2e-3)
    lo, hi = limit.ball_window_mm(0.995 * by_hand, rc, theta, z)
    assert lo <= 0.5 * reach <= hi
    lo, hi = limit.ball_window_mm(1.01 * by_hand, rc, theta, z)
    assert lo > hi


def _spec_and_limits(stiffness_Nm_per_rad):
    """A held-out spec's spring (r_c fixed at 8 mm, 5.5 deg: a flank r_c theta of 0.77 mm)
    with the paper's profile tolerances, its design stress (MPa) and modulus (MPa)."""
    from springcad.config import job_from_dict

    job = job_from_dict({
        "job": {"name": "cusp", "description": "short flank"},
        "material": {"name": "420_ht", "safety_factor": 1.5},
        "springs": {"S1": {"target_stiffness_Nm_per_rad": stiffness_Nm_per_rad,
                           "max_deflection_deg": 5.5, "outer_radius_mm": 33.5,
                           "thickness_mm": 6.0, "contact_radius_mm": 8.0}},
        "manufacturing": {"process": "wire_edm", "t_spring_mm": 0.05, "t_shaft_mm": 0.02,
                          "w_gap_mm": 0.025}})
    return job.springs["S1"], job.material, job.manufacturing


def test_a_cusp_only_the_tolerances_block_designs_for_nominal_parts_and_names_them():
    """sqrt(2 r_c (t_spring + t_shaft)) = 1.06 mm of cusp room exceeds the 0.74 mm flank
    r_c theta - w_gap: no layout for toleranced parts, so the layouts for nominal parts come
    with a warning naming t_spring + t_shaft <= s, and at that s the same rule admits a ball
    (the named tolerance works); a spec no layout fits even for nominal parts is refused
    with the toleranced reason."""
    from dataclasses import replace

    from springcad.design.layout import ContactLimit, candidate_layouts, toleranced_layouts
    from springcad.errors import DesignError

    spec, material, mfg = _spec_and_limits(165.0)
    sigma, E = material.design_stress_MPa, material.material.youngs_modulus_MPa
    limit = ContactLimit.of(material, spec.max_deflection_rad, mfg)
    assert limit.min_flank_position_mm == pytest.approx(0.07)
    with pytest.raises(DesignError, match="cusp"):
        candidate_layouts(spec, sigma, E, contact=limit)
    layouts, warning = toleranced_layouts(spec, sigma, E, math.inf, limit)
    assert layouts and "only for nominal parts" in warning
    s_max = float(warning.split("t_spring_mm + t_shaft_mm <= ")[1].split(" mm")[0])
    reach = 8.0 * spec.max_deflection_rad - 0.025
    assert 0 < s_max < 0.07 and math.sqrt(2 * 8.0 * s_max) < reach
    assert candidate_layouts(spec, sigma, E, contact=replace(limit,
                                                             min_flank_position_mm=0.98 * s_max))
    # a larger contact radius is named only where one (up to 0.6 R_o) leaves the cusp room
    # beyond the same ball (closed form): none here; with 0.03 mm of tolerances one does
    rb, theta = layouts[0].rb, spec.max_deflection_rad
    assert 0.6 * 33.5 * theta - 0.025 - rb < math.sqrt(2 * 0.6 * 33.5 * 0.07)
    assert "contact_radius_mm" not in warning
    _, closer = toleranced_layouts(spec, sigma, E, math.inf,
                                   replace(limit, min_flank_position_mm=0.03))
    rc_named = float(closer.split("contact_radius_mm >= ")[1].split(" mm")[0])
    assert 8.0 < rc_named <= 0.6 * 33.5
    assert rc_named * theta - 0.025 - rb >= math.sqrt(2 * rc_named * 0.03)
    assert (rc_named - 0.2) * theta - 0.025 - rb < math.sqrt(2 * (rc_named - 0.2) * 0.03)
    # tolerances that leave the cusp room: no warning, the same layouts as the rule alone
    loose = replace(limit, min_flank_position_mm=0.5 * s_max)
    assert toleranced_layouts(spec, sigma, E, math.inf, loose) == (
        candidate_layouts(spec, sigma, E, contact=loose), "")
    with pytest.raises(DesignError, match="cusp"):  # a search for releasable springs only
        toleranced_layouts(spec, sigma, E, math.inf, limit, nominal_fallback=False)
    heavy, *_ = _spec_and_limits(1.0e5)  # beyond the balls' torque cap for any tolerance
    with pytest.raises(DesignError) as toleranced:
        candidate_layouts(heavy, sigma, E, contact=limit)
    with pytest.raises(DesignError) as refused:
        toleranced_layouts(heavy, sigma, E, math.inf, limit)
    assert str(refused.value) == str(toleranced.value)
