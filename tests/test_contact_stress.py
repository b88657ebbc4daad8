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
