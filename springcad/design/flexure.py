"""Flexure laws: constant-stress width, straight limit, tip ball, serpentine centreline.

Local flexure frame: the flexure axis is +y, the tip-ball centre sits at
``(0, r_c)`` and the root meets the rim at ``y = R_r``; the cam pushes the tip
along x. Units: mm, N, MPa, rad. Equations follow
``shared/notes/design-method.md`` (numbered there 1-9).
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass

import numpy as np

from springcad.design.numeric import (ClampedCubic, cumtrapz, cumtrapz_last, find_root,
                                      min_block_distance, trapz_last)

from springcad.errors import DesignError
from springcad.units import J_PER_NMM


# ----------------------------------------------------------------- closed forms
def tip_load_N(stiffness_Nmm_per_rad: float, deflection_rad: float, n_flexures: int,
               contact_radius_mm: float) -> float:
    """Tangential tip load per flexure F = K*theta/(N*r_c) (N). Eq. 1."""
    return stiffness_Nmm_per_rad * deflection_rad / (n_flexures * contact_radius_mm)


def constant_stress_width_mm(y_mm, load_N: float, contact_radius_mm: float,
                             thickness_mm: float, stress_MPa: float):
    """In-plane width w(y) = sqrt(6 F (y - r_c) / (z sigma)) (mm). Eq. 2."""
    arm = np.maximum(np.asarray(y_mm, dtype=float) - contact_radius_mm, 0.0)
    return np.sqrt(6.0 * load_N * arm / (thickness_mm * stress_MPa))


def root_flare_factor(y_mm, root_radius_mm: float, flare: float, flare_length_mm: float):
    """Width factor of the root flare: 1 below the flare zone, 1 + ``flare`` at the root (-).

    The flexure widens over the last ``flare_length_mm`` before the root circle with a
    smootherstep (C2: the edge keeps a continuous curvature, so the flare itself adds
    no stress raiser). The flare lowers the bending stress where the root fillet and
    the root-zone bend concentrate it.
    """
    y = np.asarray(y_mm, dtype=float)
    if flare <= 0.0 or flare_length_mm <= 0.0:
        return np.ones_like(y)
    q = np.clip((y - (root_radius_mm - flare_length_mm)) / flare_length_mm, 0.0, 1.0)
    return 1.0 + flare * q ** 3 * (10.0 + q * (6.0 * q - 15.0))


def straight_limit_rad(n_flexures: int, thickness_mm: float, stress_MPa: float,
                       length_mm: float, youngs_modulus_MPa: float,
                       stiffness_Nmm_per_rad: float, contact_radius_mm: float) -> float:
    """Largest deflection of a straight constant-stress flexure ring of stiffness K (rad). Eq. 3."""
    return (8.0 * n_flexures * thickness_mm * stress_MPa ** 3 * length_mm ** 3
            / (27.0 * youngs_modulus_MPa ** 2 * stiffness_Nmm_per_rad
               * contact_radius_mm)) ** (1.0 / 3.0)


def straight_root_width_for_stiffness_mm(stiffness_Nmm_per_rad: float, n_flexures: int,
                                         contact_radius_mm: float, length_mm: float,
                                         youngs_modulus_MPa: float, thickness_mm: float) -> float:
    """Root width w0 of a straight parabolic flexure ring with stiffness K (mm).

    From K = N r_c^2 E z w0^3 / (8 L^3).
    """
    return (8.0 * stiffness_Nmm_per_rad * length_mm ** 3
            / (n_flexures * contact_radius_mm ** 2 * youngs_modulus_MPa * thickness_mm)) ** (1 / 3)


def serpentine_factor(target_rad: float, straight_limit: float) -> float:
    """Required area ratio s = (theta_d / theta_s)^(3/2) (-). Eq. 4."""
    return (target_rad / straight_limit) ** 1.5


def tip_ball_required_radius_mm(load_N: float, thickness_mm: float, stress_MPa: float) -> float:
    """Tip-ball radius that carries the load at the design stress: 3*sqrt(3)*F/(z*sigma) (mm). Eq. 5."""
    return 3.0 * math.sqrt(3.0) * load_N / (thickness_mm * stress_MPa)


def max_flexures(tip_radius_mm: float, contact_radius_mm: float) -> int:
    """Most flexures whose balls and equal cam teeth fit around r_c. Eq. 6."""
    return int(math.floor(math.pi * math.hypot(tip_radius_mm, contact_radius_mm)
                          / (2.0 * tip_radius_mm)))


def torque_cap_Nmm(contact_radius_mm: float, thickness_mm: float, stress_MPa: float) -> float:
    """Peak torque a ring can carry with load-sized tip balls at r_c (N*mm). Eq. 6."""
    return math.pi * contact_radius_mm ** 2 * thickness_mm * stress_MPa / (6.0 * math.sqrt(3.0))


def min_contact_radius_mm(peak_torque_Nmm: float, thickness_mm: float, stress_MPa: float) -> float | np.ndarray:
    """Smallest r_c whose :func:`torque_cap_Nmm` carries ``peak_torque_Nmm`` (mm; arrays too)."""
    return np.sqrt(6.0 * math.sqrt(3.0) * np.asarray(peak_torque_Nmm)
                   / (math.pi * np.asarray(thickness_mm) * np.asarray(stress_MPa)))


def energy_bound_J_per_mm3(stress_MPa: float, youngs_modulus_MPa: float) -> float:
    """Bending energy per unit volume at uniform outer-fibre stress: sigma^2/(6E) (J/mm^3)."""
    return stress_MPa ** 2 / (6.0 * youngs_modulus_MPa) * J_PER_NMM  # MPa = N*mm/mm^3


# ----------------------------------------------------------------- centreline
@dataclass(frozen=True)
class Centreline:
    """Flexure centreline x(y): clamped cubic spline through stations.

    The tangent is radial at the tip (slope 0) and at the root (slope
    ``end_slopes[1]`` = x/y there, so the flexure meets the rim radially).

    Attributes:
        y_mm: stations from r_c to R_r (mm), increasing.
        x_mm: lateral offsets at the stations (mm); 0 at both ends.
    """

    y_mm: tuple[float, ...]
    x_mm: tuple[float, ...]
    end_slopes: tuple[float, float] = (0.0, 0.0)
    """dx/dy at the tip and at the root (the root may be tilted on a swept flexure)."""

    @classmethod
    def straight(cls, contact_radius_mm: float, root_radius_mm: float) -> "Centreline":
        return cls((contact_radius_mm, root_radius_mm), (0.0, 0.0))

    @functools.cached_property
    def is_straight(self) -> bool:
        return all(abs(x) < 1e-12 for x in self.x_mm)

    @functools.cached_property
    def _cs(self):
        return ClampedCubic(self.y_mm, self.x_mm, *self.end_slopes)

    def evaluate(self, y):
        """x, dx/dy, d2x/dy2 at y (arrays)."""
        y = np.asarray(y, dtype=float)
        if self.is_straight:
            z = np.zeros_like(y)
            return z, z, z
        cs = self._cs
        x, dx, ddx = cs.derivatives(y)
        # beyond the root station the flexure runs on straight along its root tangent
        y_end, x_end, slope = self.y_mm[-1], self.x_mm[-1], self.end_slopes[1]
        past = y > y_end
        if np.any(past):
            x = np.where(past, x_end + slope * (y - y_end), x)
            dx = np.where(past, slope, dx)
            ddx = np.where(past, 0.0, ddx)
        return x, dx, ddx


def edges(centreline: Centreline, y, width):
    """Right (+x) and left edges offset by +-w/2 along the centreline normal.

    Returns:
        (right, left, normal): arrays of shape (n, 2); ``normal`` points to +x.
    """
    x, dx, _ = centreline.evaluate(y)
    norm = np.sqrt(1.0 + dx ** 2)
    n = np.column_stack([1.0 / norm, -dx / norm])
    c = np.column_stack([x, y])
    half = 0.5 * np.asarray(width)[:, None]
    return c + half * n, c - half * n, n


@functools.lru_cache(maxsize=32)
def stations(centreline: Centreline, start_mm: float, stop_mm: float, n: int):
    """``np.linspace(start_mm, stop_mm, n)`` and the centreline's x, dx/dy and d2x/dy2 there
    (:meth:`Centreline.evaluate`), as read-only arrays kept per centreline and grid: the
    design search integrates one centreline at many widths (the width scale's secant, each
    root flare, the stress prediction of each), and the spline is evaluated once for all."""
    y = np.linspace(start_mm, stop_mm, n)
    out = (y, *centreline.evaluate(y))
    for a in out:
        a.flags.writeable = False
    return out


def compliance_mm_per_N(centreline: Centreline, y, width, thickness_mm: float,
                        youngs_modulus_MPa: float, contact_radius_mm: float,
                        slope=None) -> float:
    """Tangential tip compliance delta/F of one flexure by Castigliano (mm/N).

    delta/F = integral 12 (y - r_c)^2 / (E z w^3) ds along the centreline
    (Euler-Bernoulli bending only). ``slope``: dx/dy at ``y`` when the caller has it
    (:func:`stations`), else evaluated here.
    """
    dx = centreline.evaluate(y)[1] if slope is None else slope
    ds = np.sqrt(1.0 + dx ** 2)
    w = np.maximum(np.asarray(width), 1e-12)
    integrand = 12.0 * (y - contact_radius_mm) ** 2 / (youngs_modulus_MPa * thickness_mm * w ** 3) * ds
    return float(np.trapezoid(integrand, y))


def area_mm2(centreline: Centreline, y, width) -> float:
    """Flexure area integral w ds (mm^2)."""
    _, dx, _ = centreline.evaluate(y)
    return float(np.trapezoid(np.asarray(width) * np.sqrt(1.0 + dx ** 2), y))


def uncoupled_tilt(h0, budget, r, contact_radius_mm, width_mm):
    """Reshape a serpentine tilt shape so that a tangential tip load moves the tip ball
    tangentially only (rows along the last axis).

    A flexure whose centreline leaves the radial line by x(y) couples the two tip
    directions: by Castigliano the radial tip motion per tangential load is

        c_xy = integral 12 (y - r_c) x(y) / (E z w^3) ds,

    which makes the ball climb the cam flank pushed one way and sink into the pocket
    pushed the other (paper S1 with its lobes balanced on the root angle, as the
    reference tool does: c_xy / c_xx = 0.36, a radial ball motion at full deflection of
    the order of the ball radius). The tilt amplitude is ramped along the flexure,
    h = h0 (1 + c u) with u the station fraction from tip to root: smooth (no kink
    where the lobes change sign, so no curvature step and no stress spike there), and
    with theta(r) = integral tan(beta) / r dr linear in h and x ~ r theta, c_xy is
    linear in c; c makes it zero. The root then sits off the tip's radial line. The
    small-tilt x ~ r theta and the width law without flare leave c_xy / c_xx within
    0.01 of zero on the built designs (paper S1 +0.006, S2 +0.004, default -0.003).

    Args:
        h0: tilt shape with lobes of both signs, shape (..., n).
        budget: the tilt budget T(r) between neighbours, same shape.
        r: radial stations (mm), same shape or (n,).
        contact_radius_mm: r_c (mm), scalar or (..., 1).
        width_mm: flexure width at the stations (mm), same shape.

    Returns:
        The tilt shape with |h| <= 1 (peak 1).
    """
    weight = (r - contact_radius_mm) * r / np.maximum(width_mm, 1e-9) ** 3
    u = (r - r[..., :1]) / (r[..., -1:] - r[..., :1])
    ramp = h0 * u

    def coupling(h):
        return trapz_last(weight * cumtrapz_last(budget * h / r, r), r)

    c = -coupling(h0) / coupling(ramp)
    h = h0 + np.asarray(c)[..., None] * ramp
    return h / np.max(np.abs(h), axis=-1, keepdims=True)


def root_aligned_tilt(h0, budget, r):
    """Scale the reversed lobes so the root lines up with the tip (the reference tool's
    balance; rows along the last axis): theta(r_root) = integral tan(beta) / r dr = 0.
    Leaves the tip's tangential-radial coupling (:func:`uncoupled_tilt`); used only where
    no uncoupled shape fits."""
    pos, neg = np.maximum(h0, 0.0), np.minimum(h0, 0.0)
    scale = -trapz_last(budget * pos / r, r) / trapz_last(budget * neg / r, r)
    h = pos + np.asarray(scale)[..., None] * neg
    return h / np.max(np.abs(h), axis=-1, keepdims=True)


#: balance of a trial shape's lobes, in order of preference
BALANCES = ("uncoupled", "root", "swept")
#: a root-balanced (coupled) shape wins over an uncoupled one only when the uncoupled one's
#: curved-beam measure is this many times larger (a tight uncoupled shape can cost more in
#: flank stress than the coupling costs in contact; the contact sweep checks the result)
COUPLED_MEASURE_FACTOR = 1.5


def shape_rank(balance: str, measure):
    """Sort key of a feasible trial shape (smaller wins): swept arms last, then the
    curved-beam measure, a root-balanced shape's raised by :data:`COUPLED_MEASURE_FACTOR`."""
    return (balance == "swept") * 1e6 + np.round(measure, 4) * np.where(
        balance == "root", COUPLED_MEASURE_FACTOR, 1.0)

#: the trial shapes of :func:`design_serpentine`, in its order: (k tilt reversals, turn
#: sharpness a, balance); k = 1 is the swept arm
SERPENTINE_SHAPES = tuple((k, a, "swept" if k == 1 else balance)
                          for k in (1, 2, 3, 4, 5, 6) for a in (1.0, 2.0, 3.0)
                          for balance in (("swept",) if k == 1 else ("uncoupled", "root")))


def trial_tilt(k: int, a: float, balance: str, u, taper, budget, r, contact_radius_mm,
               width_mm):
    """Tilt shape h (|h| <= 1) of one trial shape (rows along the last axis).

    h0 = tanh(a sin(k pi u)) / tanh(a) x taper, then balanced (:data:`BALANCES`).
    """
    h0 = np.tanh(a * np.sin(k * math.pi * u)) / math.tanh(a) * taper
    if balance == "uncoupled":
        return uncoupled_tilt(h0, budget, r, contact_radius_mm, width_mm)
    if balance == "root":
        return root_aligned_tilt(h0, budget, r)
    return h0


# ----------------------------------------------------------------- serpentine optimiser
@dataclass(frozen=True)
class SerpentineResult:
    centreline: Centreline
    area_ratio: float
    min_clearance_mm: float
    min_edge_radius_mm: float
    fairness: float
    start: int
    balance: str = "uncoupled"
    """How the lobes are balanced (:data:`BALANCES`): "uncoupled" unless no such shape fits."""


def _point_polyline_distance(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance from each point to a polyline (mm)."""
    a, b = poly[:-1], poly[1:]
    ab = b - a
    t = ((points[:, None, :] - a[None]) * ab[None]).sum(-1) / (ab ** 2).sum(-1)[None]
    t = np.clip(t, 0.0, 1.0)
    foot = a[None] + t[..., None] * ab[None]
    return np.sqrt(((points[:, None, :] - foot) ** 2).sum(-1)).min(axis=1)


#: points and segments per block of :func:`_min_point_polyline_distance`
_CLEARANCE_BLOCK = 16


def _min_point_polyline_distance(points: np.ndarray, poly: np.ndarray) -> float:
    """Smallest distance from a set of points to a polyline (mm), exact: the all-pairs
    minimum of :func:`_point_polyline_distance` bit for bit, measured block pair by block
    pair, nearest bounding boxes first (:func:`~springcad.design.numeric.min_block_distance`;
    two curves of ~1200 points: 0.8 ms instead of 10 ms)."""
    points, poly = np.asarray(points, float), np.asarray(poly, float)
    size = _CLEARANCE_BLOCK
    if len(poly) < 2 or len(points) * (len(poly) - 1) <= 4 * size * size:
        return float(_point_polyline_distance(points, poly).min())
    return min_block_distance(points, poly, lambda p, q: float(_point_polyline_distance(p, q).min()),
                              size, b_overlap=1)


def neighbour_clearance_mm(centreline: Centreline, y, width, n_flexures: int,
                           tip_radius_mm: float) -> float:
    """Exact smallest gap between a flexure's edge and its neighbour's, above the tip ball (mm).

    The neighbour is the same flexure rotated by 2 pi / N about the centre.

    Raises:
        DesignError: the flexure is no longer than its tip ball is wide (nothing above it).
    """
    pitch = 2.0 * math.pi / n_flexures
    c, s = math.cos(-pitch), math.sin(-pitch)
    rot = np.array([[c, -s], [s, c]])
    right, left, _ = edges(centreline, y, width)
    m = np.asarray(y) > y[0] + 2.0 * tip_radius_mm
    if not m.any():
        raise DesignError(
            f"the flexures are {y[-1] - y[0]:.3g} mm long (contact to root radius), no longer "
            f"than their tip balls are wide ({2.0 * tip_radius_mm:.3g} mm): use a smaller "
            "tip_radius_mm or contact_radius_mm, or a larger outer radius")
    return _min_point_polyline_distance(right[m], left @ rot.T)


def concave_edge_radius_mm(centreline: Centreline, y, width) -> float:
    """Smallest radius of the concave flexure edge, 1/|kappa| - w/2 (mm); inf if straight."""
    _, dx, ddx = centreline.evaluate(y)
    kappa = np.abs(ddx) / (1.0 + dx ** 2) ** 1.5
    return float(np.min(1.0 / np.maximum(kappa, 1e-12) - 0.5 * np.asarray(width)))


#: what a trial shape of :func:`design_serpentine` failed on, in the order a refusal lists
#: them: (kind, how many fail so, how the closest one is quoted; None: not quoted)
_FAILURE_TEXT = (
    ("budget", "fall short of the tilt budget between neighbours at full tilt",
     "reaches {v:.3f}"),
    ("edge radius", "reach the area ratio with a concave edge radius below {e:g} mm",
     "keeps {v:.3f} mm"),
    ("clearance", "reach it leaving less than {c:g} mm to their neighbour", "keeps {v:.3f} mm"),
    ("turns back", "turn back on themselves", None),
    ("balance", "have no tilt budget where their lobes would balance", None),
    ("spline", "miss the area ratio on their stored spline", None))


def serpentine_failures(failures, min_clearance_mm: float, min_inside_radius_mm: float) -> str:
    """Why the trial shapes of :func:`design_serpentine` failed, rule by rule: how many
    failed on each and the closest (the largest area ratio, edge radius or clearance).

    Args:
        failures: (kind, value, shape name) of each shape tried, kind a key of
            :data:`_FAILURE_TEXT`.
        min_clearance_mm, min_inside_radius_mm: the rules, for the text (mm).
    """
    parts = []
    for kind, text, closest in _FAILURE_TEXT:
        these = [f for f in failures if f[0] == kind]
        if not these:
            continue
        part = f"{len(these)} " + text.format(c=min_clearance_mm, e=min_inside_radius_mm)
        if closest:
            _, v, name = max(these, key=lambda f: f[1])
            part += f" (closest {name}: " + closest.format(v=v) + ")"
        parts.append(part)
    return f"of {len(failures)} trial shapes, " + "; ".join(parts) if parts else "no trial shape"


#: the trial shapes' detail in a refusal of :func:`design_serpentine`
_SHAPE_DETAIL = re.compile(r" \(of \d+ trial shapes, .*?\)(?=; increase outer_radius_mm)")


def without_shape_detail(message: str) -> str:
    """``message`` without the trial shapes' detail of a :func:`design_serpentine` refusal
    (:func:`serpentine_failures`): two layouts refused by the curved-flexure rule are refused
    by the same rule whichever shapes came closest (the design search counts the layouts
    refused alike, :func:`springcad.design.search._alike`)."""
    return _SHAPE_DETAIL.sub("", message)


def design_serpentine(*, target_area_ratio: float, contact_radius_mm: float,
                      root_radius_mm: float, n_flexures: int, width_fn,
                      tip_radius_mm: float, min_clearance_mm: float,
                      min_inside_radius_mm: float, root_zone_mm: float = 0.0,
                      balances: tuple[str, ...] = BALANCES) -> SerpentineResult:
    """Find a curved (serpentine) centreline with a given area ratio, deterministically.

    Neighbouring flexures are copies rotated by the pitch 2 pi/N, so in polar
    coordinates (r, theta) they are exact angular translates and nest when each
    is tilted from radial by an angle beta(r) with

        r * pitch * cos(beta) - w(r) >= clearance,   i.e.   tan(beta) <= T(r).

    The centreline is built in closed form from that tilt budget,

        tan(beta(r)) = lam * T(r) * h_k(u),   h_k(u) = tanh(a sin(k pi u)) / tanh(a),

    u = (r - r_c)/L, with k tilt reversals (k = 1 a swept arm, k >= 2 a
    serpentine) and turn sharpness a. The tilt is zero at tip and root, so the
    flexure leaves the ball and meets the rim radially; within ``root_zone_mm``
    of the root the tilt fades out (smoothstep) so both root fillets sit
    evenly on the rim. For every (k, a) of a
    fixed list, lam follows from the area ratio by bracketing; the candidate is
    then held to the hard constraints on its stored spline: exact clearance to
    the neighbour >= ``min_clearance_mm``, concave edge radius
    1/|kappa| - w/2 >= ``min_inside_radius_mm`` (curvature vs half-width and
    what the wire can cut), y increasing along the flexure. The clearance
    margin used in T(r) is raised until the exact check holds. Among feasible
    candidates the smallest curved-beam measure integral (kappa w/2)^2 ds / L
    wins (inner-edge stress raise of a curved beam grows with w/(2R)). For
    k >= 2 the tilt amplitude is ramped along the flexure so that a tangential
    tip load moves the ball tangentially only (:func:`uncoupled_tilt`); the
    reference tool's balance, root lined up with the tip (which leaves the ball
    climbing the cam flank), wins only when no uncoupled shape fits or the best one
    curves 1.5 x more (:func:`shape_rank`), and the swept arm (k = 1) only when no
    serpentine fits (:data:`SERPENTINE_SHAPES`). ``balances`` limits the shapes tried
    (``("root", "swept")``: the reference tool's shapes). No random starts, no time budget.

    Raises:
        DesignError: no candidate meets all constraints.
    """
    rc, rr = contact_radius_mm, root_radius_mm
    L = rr - rc
    u = np.linspace(0.0, 1.0, 241) ** 1.3
    r = rc + L * u
    y_s = r  # straight flexure
    straight_area = float(np.trapezoid(width_fn(y_s), y_s))
    pitch = 2.0 * math.pi / n_flexures

    def build(lam, budget, h):
        tan_b = lam * budget * h
        theta = cumtrapz(tan_b / r, r)
        x, y = r * np.sin(theta), r * np.cos(theta)
        w = width_fn(y)
        area = float(np.trapezoid(w * np.sqrt(1.0 + tan_b ** 2), r))
        return x, y, w, theta, area / straight_area

    def check(x, y, theta):
        if np.any(np.diff(y) <= 0):
            return None, ("turns back", 0.0)
        st = slice(None, None, 4)
        ys, xs = y[st], x[st]
        if ys[-1] != y[-1]:
            ys, xs = np.append(ys, y[-1]), np.append(xs, x[-1])
        line = Centreline(tuple(map(float, ys)), tuple(map(float, xs)),
                          (0.0, float(math.tan(theta[-1]))))
        yy = np.linspace(rc, y[-1], 600)
        w = width_fn(yy)
        edge_r = concave_edge_radius_mm(line, yy, w)
        if edge_r < min_inside_radius_mm:
            return None, ("edge radius", edge_r)
        clear = neighbour_clearance_mm(line, yy, w, n_flexures, tip_radius_mm)
        ratio = area_mm2(line, yy, w) / straight_area
        _, dx, ddx = line.evaluate(yy)
        kappa = ddx / (1.0 + dx ** 2) ** 1.5
        ds = np.sqrt(1.0 + dx ** 2)
        measure = float(np.trapezoid((kappa * 0.5 * w) ** 2 * ds, yy)) / L
        return (line, ratio, clear, edge_r, measure), None

    def solve_lam(h, budget):
        """Tilt factor giving the target area ratio (None: out of reach at full tilt)."""
        if build(1.0, budget, h)[4] < target_area_ratio:
            return None
        return find_root(lambda v: build(v, budget, h)[4] - target_area_ratio, 0.0, 1.0,
                         xtol=1e-10)

    q = np.clip((rr - r) / root_zone_mm, 0.0, 1.0) if root_zone_mm > 0 else np.ones_like(r)
    taper = q * q * (3.0 - 2.0 * q)
    best, best_key, failures, start = None, None, [], 0
    for k, a, balance in SERPENTINE_SHAPES:
        start += 1
        if balance not in balances:
            continue
        margin = min_clearance_mm
        for _ in range(6):
            w_r = width_fn(r)
            budget = np.sqrt(np.maximum((r * pitch / (w_r + margin)) ** 2 - 1.0, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                h = trial_tilt(k, a, balance, u, taper, budget, r, rc, w_r)
            if not np.all(np.isfinite(h)):  # no budget where the lobes would balance
                result, why = None, ("balance", 0.0)
                break
            lam = solve_lam(h, budget)
            if lam is None:
                result, why = None, ("budget", build(1.0, budget, h)[4])
                break
            x, y, _, theta, _ = build(lam, budget, h)
            result, why = check(x, y, theta)
            if result is None or result[2] >= min_clearance_mm:
                break
            margin += min_clearance_mm - result[2] + 0.01
            why = ("clearance", result[2])
            result = None
        if result is None:
            failures.append((*why, f"k={k}, a={a:g}, {balance}"))
            continue
        line, ratio, clear, edge_r, measure = result
        if abs(ratio - target_area_ratio) > 2e-3:
            failures.append(("spline", ratio, f"k={k}, a={a:g}, {balance}"))
            continue
        key = float(shape_rank(balance, measure))
        if best is None or key < best_key:
            best, best_key = SerpentineResult(line, ratio, clear, edge_r, measure, start,
                                              balance), key
    if best is None:
        raise DesignError(
            f"no curved flexure between r_c = {rc:.3g} mm and R_r = {rr:.3g} mm with "
            f"{n_flexures} flexures reaches the area ratio {target_area_ratio:.3f} while keeping "
            f"{min_clearance_mm:g} mm to its neighbour and edge radii >= {min_inside_radius_mm:g} mm "
            f"({serpentine_failures(failures, min_clearance_mm, min_inside_radius_mm)}); "
            "increase outer_radius_mm or thickness_mm, lower the deflection, or put springs in "
            "series")
    return best
