"""The driven flexure tip at full deflection: where the ball sits on its flank, how the tip
region has moved, and its clearances to the turned cam, with the profile tolerances.

The cam turns by theta against the ring (outer rim held). The driving flank is an offset of
the involute of the contact circle (:mod:`springcad.design.cam`), so the ball, driven with
the gap closed, travels tangentially by delta = r_c theta - w_gap. The flexure carries it on
as a cantilever from the rim: with the constant-stress taper the width laws size (w^2 ~ the
moment, so the curvature ~ u^-1/2 at a distance u from the ball), its slope relative to the
root is phi(u) = phi_tip (1 - sqrt(u / L)) with phi_tip = 3 delta / L, its tangential
deflection w(u) = delta (1 - 3 u / L + 2 (u / L)^1.5), and its projection shortens by
v(u) = (1/2) integral_u^L phi^2, which moves the tip outward (towards the root) by
v(0) = 3/4 delta^2 / L (L = R_r - r_c). The region around the ball moves with the beam; the
ball itself rigidly with the tip.

These are the design's estimates of the contact FEA's (``fea.contact``: the same turn
against the 2D sector, total Lagrangian) and of its tolerance study
(``fea.contact_tolerance``): a cam dilated by E (the summed deviation of ball and flank,
-T..T with T = t_spring + t_shaft) moves where the ball sits, and each gap's own surfaces take
up to T more. Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.numeric import min_block_distance


#: the tip's outward shift over delta^2 / L (constant-stress taper; 3/5 for a uniform beam).
#: With it the tooth-tip-to-ball estimate reads the contact FEA's nominal gap at +theta_max
#: within -10 to +3 um on 16 held-out springs (contact assumed at psi* + theta and no shift,
#: as before: -72 to +71 um; held-out g26 read 51 um where the FEA found 0.9 um)
FORESHORTENING = 0.75


def ball_lift_mm(contact_radius_mm: float, root_radius_mm: float, gap_mm: float,
                 deflection_rad: float) -> float:
    """The driven ball centre's outward radial shift at ``deflection_rad`` (mm):
    :data:`FORESHORTENING` x delta^2 / L with delta = r_c theta - w_gap, L = R_r - r_c."""
    travel = contact_radius_mm * deflection_rad - gap_mm
    length = root_radius_mm - contact_radius_mm
    if travel <= 0 or length <= 0:
        return 0.0
    return FORESHORTENING * travel ** 2 / length


def driven_psi(contact_radius_mm: float, gap_mm: float, deflection_rad: float,
               lift_mm: float) -> float:
    """The flank parameter psi at which the driven ball touches its flank (rad).

    The ball centre lies on the involute offset by the gap, R(psi) (r_c psi - g, r_c) in the
    cam frame; in the ring's frame (the cam turned by theta) that is R(psi - theta)
    (r_c psi - g, r_c), whose tangential coordinate stays r_c theta - g to first order while
    the radial one grows with e = psi - theta. The flexure holds the ball at radius
    r_c + ``lift_mm``: Newton's method on e."""
    rc, g, theta = contact_radius_mm, gap_mm, deflection_rad
    e = 0.0
    for _ in range(8):
        arm = rc * (theta + e) - g
        y = arm * math.sin(e) + rc * math.cos(e) - (rc + lift_mm)
        dy = arm * math.cos(e)
        if dy <= 0:
            break
        step = y / dy
        e -= step
        if abs(step) < 1e-12:
            break
    return theta + e


def _rotation(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def ball_centre_mm(contact_radius_mm: float, root_radius_mm: float, gap_mm: float,
                   deflection_rad: float) -> np.ndarray:
    """The driven ball centre in the ring's frame (ball at rest at (0, r_c)), mm."""
    rc, g, theta = contact_radius_mm, gap_mm, deflection_rad
    psi = driven_psi(rc, g, theta, ball_lift_mm(rc, root_radius_mm, g, theta))
    return _rotation(psi - theta) @ np.array([rc * psi - g, rc])


def deflected(points_mm: np.ndarray, contact_radius_mm: float, root_radius_mm: float,
              centre_mm: np.ndarray) -> np.ndarray:
    """Points of flexure 0 (on +y, ball at rest at (0, r_c)) moved with the flexure whose
    ball centre is driven to ``centre_mm`` (ring frame; module docstring): the beam's
    deflection above the ball centre, the tip's rigid motion below it (mm)."""
    rc = contact_radius_mm
    length = max(root_radius_mm - rc, 1e-9)
    delta, lift = float(centre_mm[0]), float(centre_mm[1]) - rc
    p = np.asarray(points_mm, float)
    s = np.sqrt(np.clip((p[:, 1] - rc) / length, 0.0, 1.0))  # sqrt(u / L)
    phi_tip = 3.0 * delta / length
    phi = phi_tip * (1.0 - s)
    w = delta * (1.0 - 3.0 * s ** 2 + 2.0 * s ** 3)
    # v(u) / v(0) = 12 (1/12 - s^2/2 + 2 s^3/3 - s^4/4)
    v = lift * (1.0 - 6.0 * s ** 2 + 8.0 * s ** 3 - 3.0 * s ** 4)
    x_local, y_local = p[:, 0], np.where(s > 0, 0.0, p[:, 1] - rc)
    c, sn = np.cos(phi), np.sin(phi)
    out = np.empty_like(p)
    out[:, 0] = w + c * x_local - sn * y_local
    out[:, 1] = np.where(s > 0, p[:, 1], rc) + v + sn * x_local + c * y_local
    return out


@dataclass(frozen=True)
class Clearance:
    """One gap at full deflection (mm): nominal, and worst case with the tolerances."""

    nominal_mm: float
    worst_case_mm: float


def min_distance_mm(a: np.ndarray, b: np.ndarray) -> float:
    """Smallest distance between two point sets (mm; inf when one is empty): the all-pairs
    minimum bit for bit, by blocks nearest first
    (:func:`~springcad.design.numeric.min_block_distance`)."""
    if len(a) == 0 or len(b) == 0:
        return math.inf
    return min_block_distance(np.asarray(a, float), np.asarray(b, float), lambda p, q: math.sqrt(
        float(((p[:, None, :] - q[None, :, :]) ** 2).sum(-1).min())))


#: the ring's parts of flexure 0 whose gaps to the cam are held against the tolerances
#: (the ball's, to the tooth tip, by :func:`springcad.design.cam.tip_clearance_mm`)
RING_PARTS = ("neck", "edge")
#: sampling of both contours for the gaps (mm): well under the tolerances it is held against
STEP_MM = 0.01


def clearances_at_max(ring_loop, cam_unit: tuple, pitch_rad: float,
                      contact_radius_mm: float, root_radius_mm: float, gap_mm: float,
                      deflection_rad: float, stack_mm: float, reach_mm: float
                      ) -> dict[str, Clearance]:
    """The gaps between the cam turned to ``deflection_rad`` and the deflected neck and
    edges of the flexure it drives (by symmetry every flexure's), nominal and worst case.

    Args:
        ring_loop: the ring's flexure loop (named features; flexure 0 on +y).
        cam_unit: one pocket and the tooth after it (segments, cam frame at rest, ball 0 on
            +y); the neighbouring units are this one turned by +-``pitch_rad``.
        stack_mm: T = t_spring + t_shaft: the cam is dilated by E in -T, 0, +T (the ball
            sits where the dilated flank puts it) and each gap's own surfaces take T more.
        reach_mm: only ring points within this radius count (the cam's tip radius and a
            margin: further up the flexure no tooth reaches).

    Returns:
        ring part -> :class:`Clearance`.
    """
    rc, theta = contact_radius_mm, deflection_rad
    cam = np.vstack([s.rotated(k * pitch_rad).sample(STEP_MM)
                     for k in (-1, 0, 1) for s in cam_unit])
    cam = cam[np.hypot(*cam.T) < reach_mm + stack_mm]  # no ring point further out counts
    parts = {}
    for kind in RING_PARTS:
        segs = [s for s, f in zip(ring_loop.segments, ring_loop.features)
                if f.kind == kind and f.index == 0]
        pts = np.vstack([s.sample(STEP_MM) for s in segs]) if segs else np.zeros((0, 2))
        parts[kind] = pts[np.hypot(*pts.T) < reach_mm] if len(pts) else pts
    turn = _rotation(theta)  # ring frame -> cam frame
    out = {}
    for kind, pts in parts.items():
        gaps = []
        for dilation in (-stack_mm, 0.0, stack_mm):
            centre = ball_centre_mm(rc, root_radius_mm, gap_mm - dilation, theta)
            moved = deflected(pts, rc, root_radius_mm, centre) @ turn.T
            gaps.append(min_distance_mm(moved, cam))
        out[kind] = Clearance(gaps[1], min(gaps) - stack_mm)
    return out
