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


# ============================================================ where the ball touches
def flank_radius_at_contact_mm(contact_radius_mm, tip_radius_mm, gap_mm, deflection_rad):
    """Radius of curvature of the cam flank where the ball touches it at ``deflection_rad``
    (mm; numpy broadcasting).

    Rigid kinematics of :mod:`springcad.design.cam`: at a cam rotation theta the ball centre
    sits on the involute at psi = theta, ``gap_mm`` off it towards the flank, so the contact
    is the flank point p(theta), whose radius is the involute's r_c theta less the offset
    rho = r_b + gap: ``r_c theta - r_b - gap``. Zero or less: the ball still rides the
    flank's start (its cusp on the pocket arc, radius 0), where no Hertz law holds. A ball
    larger than about half of r_c theta therefore presses a sharper flank, not a gentler
    one. The contact FEA (``fea.contact``) finds the contact a little further along on
    straight flexures (the tip's own rotation; 60 of 62 verified springs, 0.4-2.7 x this
    radius) and nearer the cusp only where this rigid contact lies within 20 um of it.
    """
    return contact_radius_mm * deflection_rad - tip_radius_mm - gap_mm


def flank_position_at_contact_mm(contact_radius_mm, tip_radius_mm, gap_mm, deflection_rad):
    """Arc length from the flank's cusp to the contact at ``deflection_rad`` (mm; 0 on the
    pocket): the involute flank's radius grows as sqrt(2 r_c s), so s = R^2 / (2 r_c)."""
    r = np.maximum(flank_radius_at_contact_mm(contact_radius_mm, tip_radius_mm, gap_mm,
                                              deflection_rad), 0.0)
    return r * r / (2.0 * contact_radius_mm)


def _c_vm(nu):
    """c_vm of :func:`von_mises_peak` for a Poisson's ratio or an array of them."""
    nu = np.asarray(nu, dtype=float)
    uniq, where = np.unique(np.round(nu, 6), return_inverse=True)
    return np.array([von_mises_peak(float(v))[0] for v in uniq])[where].reshape(nu.shape)


def _ball_window(reach_mm, k_allowed, max_ball_mm):
    """(smallest, largest) ball radius r with 1/r + 1/(reach - r) <= k_allowed and
    r <= max_ball_mm (mm; numpy broadcasting): the roots of k r^2 - k reach r + reach = 0;
    (inf, -inf) where none."""
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = reach_mm * reach_mm - 4.0 * reach_mm / k_allowed
        root = np.sqrt(np.where(disc >= 0, disc, np.nan))
        lo = 0.5 * (reach_mm - root)
        hi = np.minimum(0.5 * (reach_mm + root), max_ball_mm)
        ok = (reach_mm > 0) & (disc >= 0) & (hi >= lo)
    return np.where(ok, lo, np.inf), np.where(ok, hi, -np.inf)


def cusp_room_mm(contact_radius_mm: float, min_flank_position_mm: float) -> float:
    """The flank the ball's contact must keep from the cam flank's cusp (mm): the profile
    tolerances s_min = t_spring + t_shaft along a flank that leaves the cusp as the involute
    of the contact circle, sqrt(2 r_c s_min)."""
    return math.sqrt(2.0 * contact_radius_mm * min_flank_position_mm)


def _window_scalar(force_N, contact_radius_mm, gap_mm, deflection_rad, thickness_mm, E_MPa,
                   nu, allowable_MPa, min_flank_position_mm) -> tuple[float, float]:
    """:func:`tip_radius_window_mm` on floats (math, no arrays: a tenth of the time)."""
    reach = contact_radius_mm * deflection_rad - gap_mm
    max_ball = reach - cusp_room_mm(contact_radius_mm, min_flank_position_mm)
    if force_N <= 0:
        return 0.0, (max_ball if max_ball > 0 else -math.inf)
    c_vm = von_mises_peak(round(nu, 6))[0]
    k = math.pi * (allowable_MPa / c_vm) ** 2 / (force_N / thickness_mm
                                                 * (E_MPa / (2.0 * (1.0 - nu * nu))))
    disc = reach * reach - 4.0 * reach / k
    if reach <= 0 or disc < 0:
        return math.inf, -math.inf
    root = math.sqrt(disc)
    lo, hi = 0.5 * (reach - root), min(0.5 * (reach + root), max_ball)
    return (lo, hi) if hi >= lo else (math.inf, -math.inf)


def tip_radius_window_mm(force_N, contact_radius_mm, gap_mm, deflection_rad, thickness_mm,
                         E_MPa, nu, allowable_MPa, min_flank_position_mm=0.0):
    """The tip ball radii whose Hertz contact at full deflection stays within
    ``allowable_MPa`` on the flank radius those balls leave (mm; numpy broadcasting).

    The flank radius at the contact is r_c theta - r_b - gap
    (:func:`flank_radius_at_contact_mm`), so the curvature sum
    1/r_b + 1/(r_c theta - gap - r_b) is least at r_b = (r_c theta - gap) / 2 and the
    allowed balls form a window around it. ``min_flank_position_mm`` keeps the contact that
    far along the flank from its cusp (the profile tolerances: nearer, the toleranced parts
    can meet on the cusp): r_b <= r_c theta - gap - sqrt(2 r_c s_min).

    Args:
        force_N: normal contact force at full deflection (N); contact_radius_mm,
        gap_mm: r_c and the design gap w_gap (mm); deflection_rad: theta_max (rad);
        thickness_mm: contact length (mm); E_MPa, nu: material of ball and cam;
        allowable_MPa: allowed von Mises (MPa); min_flank_position_mm: s_min (mm).

    Returns:
        (smallest, largest) radius (mm): ``(inf, -inf)`` where no ball is enough; a smallest
        of 0 without load.
    """
    scalars = (force_N, contact_radius_mm, gap_mm, deflection_rad, thickness_mm, E_MPa, nu,
               allowable_MPa)
    if all(isinstance(v, (float, int)) for v in scalars):  # the design search: ~1e5 calls
        return _window_scalar(*scalars, min_flank_position_mm)
    c_vm = _c_vm(nu)
    reach = np.asarray(contact_radius_mm, float) * deflection_rad - gap_mm
    max_ball = reach - np.sqrt(2.0 * np.asarray(contact_radius_mm, float)
                               * min_flank_position_mm)
    force = np.asarray(force_N, float)
    with np.errstate(divide="ignore"):
        k = np.pi * (np.asarray(allowable_MPa, float) / c_vm) ** 2 / (
            np.maximum(force, 1e-300) / thickness_mm
            * (np.asarray(E_MPa, float) / (2.0 * (1.0 - np.asarray(nu, float) ** 2))))
    lo, hi = _ball_window(reach, k, max_ball)
    unloaded = force <= 0
    lo = np.where(unloaded, 0.0, lo)
    hi = np.where(unloaded, np.where(max_ball > 0, max_ball, -np.inf), hi)
    if lo.ndim == 0:
        return float(lo), float(hi)
    return lo, hi


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


def ball_advice(force_N: float, contact_radius_mm: float, gap_mm: float, deflection_rad: float,
                thickness_mm: float, E_MPa: float, nu: float, allowable_MPa: float,
                min_flank_position_mm: float, tip_radius_mm: float) -> str:
    """What tip ball meets ``allowable_MPa`` at this layout, in words with numbers: the window
    of :func:`tip_radius_window_mm` at this force, or, when it is empty, the reach
    r_c theta - w_gap a layout needs (the ball is then the window's middle).

    Args: as :func:`tip_radius_window_mm`; ``tip_radius_mm``: the ball now (mm).
    """
    lo, hi = tip_radius_window_mm(force_N, contact_radius_mm, gap_mm, deflection_rad,
                                  thickness_mm, E_MPa, nu, allowable_MPa, min_flank_position_mm)
    if lo <= hi:
        return (f"tip_radius_mm between {lo:.3f} and {hi:.3f} (now {tip_radius_mm:.3f}) at "
                f"this layout (the flank radius at the contact, r_c theta - r_b - w_gap, falls "
                "as the ball grows)")
    reach = contact_radius_mm * deflection_rad - gap_mm

    def opens(reach_mm: float) -> bool:
        return tip_radius_window_mm(force_N, (reach_mm + gap_mm) / deflection_rad, gap_mm,
                                    deflection_rad, thickness_mm, E_MPa, nu, allowable_MPa,
                                    min_flank_position_mm)[0] < math.inf

    short, need = reach, max(2.0 * reach, 1e-3)
    while not opens(need):
        short, need = need, 2.0 * need
        if need > 1e4:
            return ("no tip ball at any contact radius carries this force: lower it (more "
                    "flexures, a thicker disk)")
    for _ in range(40):  # bisection on the reach r_c theta - w_gap
        mid = 0.5 * (short + need)
        short, need = (short, mid) if opens(mid) else (mid, need)
    return (f"no tip ball at this layout: r_c theta - w_gap = {reach:.3f} mm must reach "
            f"{need:.3f} mm at this force (contact_radius_mm >= "
            f"{(need + gap_mm) / deflection_rad:.2f}, or fewer flexures, a larger contact "
            "radius or a larger deflection per disk)")
