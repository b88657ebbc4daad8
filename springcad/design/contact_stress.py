"""Hertz line contact of the flexure's tip ball against the cam flank.

The tip ball is a cylinder of radius ``r_tip`` and length the disk thickness; the
cam flank at the contact point has a local radius of curvature (convex positive,
concave negative, flat infinite). Both are the same steel, in plane strain
(the contact half-width, ~10 um, is far below the thickness).

Closed forms (Johnson, *Contact Mechanics*, 1985, sec. 4.2 and eq. 4.49-4.50):

* effective radius ``1/R = 1/r_tip + 1/R_flank``; contact modulus
  ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``;
* with the line load ``P = F / L``: half-width ``b = sqrt(4 P R / (pi E*))``,
  peak pressure ``p0 = sqrt(P E* / (pi R)) = 2 P / (pi b)``;
* the subsurface field of the elliptical pressure (McEwen, 1949) and its value
  on the load axis, where the von Mises maximum lies for frictionless contact.

The von Mises maximum ``c_vm(nu) p0`` at depth ``zeta(nu) b`` is found numerically
on the load axis (``c_vm = 0.557``, ``zeta = 0.70`` for nu = 0.3; the maximum
shear ``0.300 p0`` lies deeper, at ``0.786 b``). The design step sizes the ball
with :func:`min_tip_radius_for_contact_mm`, the verification reports
:func:`line_contact` at +-theta_max.

Pure functions on floats and arrays (numpy; scipy for a bounded 1-D maximum).
Units: mm, N, MPa.
"""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass

import numpy as np

from springcad.design.numeric import minimize_bounded


# ============================================================ the field
def _mn(x_over_b, z_over_b):
    """McEwen's m, n (in units of b) of points (x, z), z >= 0 into the body."""
    x = np.asarray(x_over_b, float)
    z = np.asarray(z_over_b, float)
    a = 1.0 - x * x + z * z
    root = np.sqrt(a * a + 4.0 * x * x * z * z)
    m = np.sqrt(np.maximum(0.5 * (root + a), 0.0))
    n = np.sqrt(np.maximum(0.5 * (root - a), 0.0)) * np.sign(x)
    return m, n


def subsurface_stress(x_over_b, z_over_b, nu: float):
    """Stresses under a frictionless Hertz line contact, in units of p0.

    McEwen's closed form (Johnson eq. 4.50): x along the surface across the
    contact, z into the body, y along the cylinder axis (plane strain:
    sigma_y = nu (sigma_x + sigma_z)). Compressive stresses are negative.

    Args:
        x_over_b, z_over_b: position over the half-width b (arrays broadcast), z >= 0.
        nu: Poisson's ratio (-).

    Returns:
        (sigma_x, sigma_y, sigma_z, tau_xz) / p0, arrays.
    """
    z = np.asarray(z_over_b, float)
    m, n = _mn(x_over_b, z)
    mn2 = np.maximum(m * m + n * n, 1e-300)
    q = (z * z + n * n) / mn2
    sx = -(m * (1.0 + q) - 2.0 * z)
    sz = -m * (1.0 - q)
    txz = n * (m * m - z * z) / mn2
    return sx, nu * (sx + sz), sz, txz


def von_mises(sx, sy, sz, txz):
    """Von Mises stress of a plane-strain state (same units as the input)."""
    return np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3.0 * txz ** 2)


def _axis_maximum(f) -> tuple[float, float]:
    """(max f(z), z) over z in [0, 3] (units of b): grid, then a bounded refinement."""
    z = np.linspace(0.0, 3.0, 301)
    i = int(np.argmax(f(z)))
    lo, hi = z[max(i - 1, 0)], z[min(i + 1, len(z) - 1)]
    if hi <= lo:
        return float(f(np.array([z[i]]))[0]), float(z[i])
    x, fx = minimize_bounded(lambda t: -float(f(np.array([t]))[0]), lo, hi, xatol=1e-10)
    return -float(fx), float(x)


@functools.lru_cache(maxsize=32)
def von_mises_peak(nu: float) -> tuple[float, float]:
    """(c_vm, zeta): the largest subsurface von Mises stress is c_vm p0 at depth zeta b.

    On the load axis (x = 0), where the frictionless maximum lies (the tests check
    this against the whole field). nu = 0.3: (0.557, 0.704).
    """
    return _axis_maximum(lambda z: von_mises(*subsurface_stress(0.0, z, nu)))


@functools.lru_cache(maxsize=32)
def shear_peak(nu: float = 0.3) -> tuple[float, float]:
    """(c_tau, zeta): the largest principal shear stress (sigma_x - sigma_z) / 2 on the
    load axis is c_tau p0 at depth zeta b (0.300, 0.786; independent of nu)."""
    def tau(z):
        sx, _, sz, _ = subsurface_stress(0.0, z, nu)
        return 0.5 * (sx - sz)

    return _axis_maximum(tau)


# ============================================================ one contact
def contact_modulus_MPa(youngs_modulus_MPa: float, poisson_ratio: float,
                        other_modulus_MPa: float | None = None,
                        other_poisson_ratio: float | None = None) -> float:
    """E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (MPa); the other body defaults to
    the same material."""
    e2 = youngs_modulus_MPa if other_modulus_MPa is None else other_modulus_MPa
    nu2 = poisson_ratio if other_poisson_ratio is None else other_poisson_ratio
    return 1.0 / ((1 - poisson_ratio ** 2) / youngs_modulus_MPa + (1 - nu2 ** 2) / e2)


def curvature_sum_per_mm(r_tip_mm: float, flank_radius_mm: float) -> float:
    """1/R = 1/r_tip + 1/R_flank (1/mm); R_flank > 0 convex, < 0 concave, inf flat."""
    if not r_tip_mm > 0:
        raise ValueError(f"tip ball radius {r_tip_mm!r} mm must be positive")
    if flank_radius_mm == 0:
        raise ValueError("flank radius 0 mm: a sharp corner has no Hertz contact")
    k = 1.0 / r_tip_mm + (0.0 if math.isinf(flank_radius_mm) else 1.0 / flank_radius_mm)
    if k <= 0:
        raise ValueError(f"a ball of radius {r_tip_mm:g} mm does not fit a concave flank of "
                         f"radius {-flank_radius_mm:g} mm (conformal contact, not Hertz)")
    return k


@dataclass(frozen=True)
class LineContact:
    """A Hertz line contact (mm, N/mm, MPa)."""

    line_load_N_per_mm: float
    radius_mm: float
    """effective radius R (1/R = sum of the curvatures)."""
    contact_modulus_MPa: float
    p0_MPa: float
    half_width_mm: float
    von_mises_max_MPa: float
    depth_mm: float
    """depth of the von Mises maximum below the surface."""
    max_shear_MPa: float

    def to_dict(self) -> dict:
        return asdict(self)


def line_contact(line_load_N_per_mm: float, curvature_sum: float, youngs_modulus_MPa: float,
                 poisson_ratio: float) -> LineContact:
    """Hertz line contact of two cylinders of the same material.

    Args:
        line_load_N_per_mm: normal force per unit length P (N/mm), >= 0.
        curvature_sum: 1/R, the sum of the curvatures (convex positive) (1/mm), > 0.
        youngs_modulus_MPa, poisson_ratio: the material of both bodies.
    """
    if line_load_N_per_mm < 0 or not math.isfinite(line_load_N_per_mm):
        raise ValueError(f"line load {line_load_N_per_mm!r} N/mm must be finite and >= 0")
    if not curvature_sum > 0:
        raise ValueError(f"curvature sum {curvature_sum!r} 1/mm must be positive")
    R = 1.0 / curvature_sum
    E = contact_modulus_MPa(youngs_modulus_MPa, poisson_ratio)
    P = line_load_N_per_mm
    p0 = math.sqrt(P * E / (math.pi * R))
    b = math.sqrt(4.0 * P * R / (math.pi * E))
    c_vm, zeta = von_mises_peak(round(float(poisson_ratio), 6))
    return LineContact(line_load_N_per_mm=P, radius_mm=R, contact_modulus_MPa=E, p0_MPa=p0,
                       half_width_mm=b, von_mises_max_MPa=c_vm * p0, depth_mm=zeta * b,
                       max_shear_MPa=shear_peak()[0] * p0)


def tip_contact(force_N: float, r_tip_mm: float, flank_radius_mm: float, thickness_mm: float,
                E_MPa: float, nu: float) -> LineContact:
    """The tip ball (cylinder r_tip x thickness) pressed on the cam flank by ``force_N``.

    Args:
        force_N: normal contact force (N).
        r_tip_mm: tip ball radius (mm).
        flank_radius_mm: flank radius of curvature at the contact (mm): > 0 convex,
            < 0 concave, ``math.inf`` flat.
        thickness_mm: disk thickness, the contact length (mm).
        E_MPa, nu: Young's modulus (MPa) and Poisson's ratio of ball and cam.
    """
    if not thickness_mm > 0:
        raise ValueError(f"thickness {thickness_mm!r} mm must be positive")
    return line_contact(force_N / thickness_mm, curvature_sum_per_mm(r_tip_mm, flank_radius_mm),
                        E_MPa, nu)


def tip_contact_von_mises_MPa(force_N: float, r_tip_mm: float, flank_radius_mm: float,
                              thickness_mm: float, E_MPa: float, nu: float) -> float:
    """Largest subsurface von Mises stress of the tip-ball contact (MPa); see
    :func:`tip_contact` for the arguments."""
    return tip_contact(force_N, r_tip_mm, flank_radius_mm, thickness_mm, E_MPa,
                       nu).von_mises_max_MPa


def min_tip_radius_for_contact_mm(force_N: float, flank_radius_mm: float, thickness_mm: float,
                                  E_MPa: float, nu: float, allowable_MPa: float) -> float:
    """Smallest tip ball radius whose contact von Mises is at most ``allowable_MPa`` (mm).

    sigma_vm = c_vm sqrt(P E* / (pi R)) is solved for 1/R, then
    1/r_tip = 1/R - 1/R_flank. Returns ``math.inf`` when no ball is enough (a convex
    flank so sharp that its curvature alone exceeds the allowed 1/R).

    Args:
        force_N: normal contact force (N); flank_radius_mm: as in :func:`tip_contact`
            (held fixed: the flank's own radius at the contact); thickness_mm: contact
            length (mm); E_MPa, nu: material; allowable_MPa: yield / safety factor (MPa).
    """
    if not allowable_MPa > 0:
        raise ValueError(f"allowable stress {allowable_MPa!r} MPa must be positive")
    if force_N <= 0:
        return 0.0
    P = force_N / thickness_mm
    E = contact_modulus_MPa(E_MPa, nu)
    c_vm = von_mises_peak(round(float(nu), 6))[0]
    k_allowed = math.pi * (allowable_MPa / c_vm) ** 2 / (P * E)  # the largest 1/R
    k_flank = 0.0 if math.isinf(flank_radius_mm) else 1.0 / flank_radius_mm
    k_ball = k_allowed - k_flank
    return 1.0 / k_ball if k_ball > 0 else math.inf


@dataclass(frozen=True)
class ContactMargin:
    """A contact von Mises stress against yield (MPa, -)."""

    von_mises_MPa: float
    yield_strength_MPa: float
    required_safety_factor: float

    @property
    def margin(self) -> float:
        """yield / contact von Mises (inf without load)."""
        return self.yield_strength_MPa / self.von_mises_MPa if self.von_mises_MPa > 0 \
            else math.inf

    @property
    def ok(self) -> bool:
        return self.margin >= self.required_safety_factor

    @property
    def allowable_MPa(self) -> float:
        return self.yield_strength_MPa / self.required_safety_factor


def tip_radius_for_contact_mm(force_N, flank_radius_mm, thickness_mm, E_MPa, nu, allowable_MPa):
    """:func:`min_tip_radius_for_contact_mm` on arrays (numpy broadcasting; ``nu`` may be an
    array too), for the synthesis screen (the design search's one layout at a time uses the
    scalar function) (mm; ``inf`` where no ball is enough, 0 without load).

    ``flank_radius_mm`` > 0 convex (the cam flank at the contact; r_c x theta at full
    deflection for the involute flank of :mod:`springcad.design.cam`), ``inf`` flat.
    """
    force = np.asarray(force_N, dtype=float)
    P = force / np.asarray(thickness_mm, dtype=float)
    nu = np.asarray(nu, dtype=float)
    uniq, where = np.unique(np.round(nu, 6), return_inverse=True)
    c_vm = np.array([von_mises_peak(float(v))[0] for v in uniq])[where].reshape(nu.shape)
    E = np.asarray(E_MPa, dtype=float) / (2.0 * (1.0 - nu ** 2))  # same material both sides
    with np.errstate(divide="ignore", invalid="ignore"):
        k_allowed = math.pi * (np.asarray(allowable_MPa, dtype=float) / c_vm) ** 2 / (P * E)
        k_ball = k_allowed - 1.0 / np.asarray(flank_radius_mm, dtype=float)
        r = np.where(k_ball > 0, 1.0 / k_ball, np.inf)
    return np.where(force > 0, r, 0.0)
