"""Cam tooth profile (the gear-like camshaft that pushes the flexure tips).

Kinematics: a cam rotation psi must move each ball centre tangentially by
r_c*psi with the contact normal perpendicular to the flexure (so the tip load is
tangential and the torque arm is r_c). In the cam frame the ball centre then
traces an involute of the contact circle, c(psi) = R(psi) (r_c psi, r_c), and
the flank is that path offset by rho = r_b + w_gap along its normal:

    p(psi) = R(psi) (r_c psi - rho, r_c),   psi in [rho / r_c, psi_end].

Below psi* = rho/r_c the offset curve would fold (its radius of curvature
r_c psi is smaller than rho), so the flank starts there, exactly on the pocket
arc of radius rho about the resting ball centre: the pocket keeps the gap
w_gap along the profile normal all around the lower half of the ball. The
flank runs to psi_end = psi* + f * theta_d (overtravel f = 1.25 when the tooth
fits, never below 1.0). Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Arc, Feature, Line, Loop, Profile, Spline, named
from springcad.design.driven import (ball_lift_mm, clearances_at_max, driven_psi,
                                     min_distance_mm)
from springcad.errors import DesignError
from springcad.units import UM_PER_MM

OVERTRAVELS = (1.25, 1.2, 1.15, 1.1, 1.05, 1.0)
#: longer flanks tried when the tooth tip would pass the ball closer than the tolerances allow
LONG_OVERTRAVELS = tuple(round(1.25 + 0.05 * k, 2) for k in range(1, 36))  # 1.3 ... 3.0
#: the tooth-tip clearance needed at full deflection over the profile tolerance stack
#: (t_spring + t_shaft): the rigid estimate below reads 7 % under the contact FEA's
#: (27.0 vs 29.1 um on the default at 14 deg, N 37); below it the design is warned
TIP_CLEARANCE_FACTOR = 1.25
#: the clearance the cam's flank length aims for where the tooth tip still fits: at 8 and
#: 6 deg on the default the same estimate reads 10 % and 28 % over the FEA's (27.3 vs 24.8
#: um, N 51; 25.3 vs 19.8 um, N 63: the FEA's contact lies further along the flank), so
#: 1.25 x left the 6 deg build 0.2 um short in the worst case
TIP_CLEARANCE_AIM = 1.5


@dataclass(frozen=True)
class CamInfo:
    tip_radius_mm: float
    root_radius_mm: float
    overtravel: float
    tooth_tip_width_mm: float
    clearance_at_rest_mm: float
    warnings: tuple[str, ...] = ()
    tip_clearance_mm: float = float("nan")
    """Estimated driving tooth tip to ball gap at full deflection (:func:`tip_clearance_mm`)."""


def _R(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def flank_point(psi: float, contact_radius_mm: float, offset_mm: float) -> np.ndarray:
    """Flank point p(psi) for cam rotation psi (mm)."""
    return _R(psi) @ np.array([contact_radius_mm * psi - offset_mm, contact_radius_mm])


#: the resolution of the cam-to-resting-ring gap check (mm): the design's rule and the
#: solids' measurement (:data:`springcad.geometry.checks.CLEARANCE_TOL_MM`, B-rep within
#: ~1 um of the design curves) judge the same gap to the same 1 um. The pocket arc through
#: the flank's cusp leaves the gap short by about rho psi*^2 / 24 (0.05 um at S1 sizes,
#: 0.7 um for a 1 mm ball at r_c 8 mm: held-out B 5507 016, refused for it at 0.5 um)
GAP_RESOLUTION_MM = 1e-3
#: the start of the warning a too-close tooth tip gives (the design search reads it)
TIP_CLEARANCE_SHORT = "driving tooth tip passes close to the ball"
#: the start of the warning a tooth passing the driven flexure's neck or edges too close gives
#: (:func:`~springcad.design.driven.clearances_at_max`; the design search reads it)
FLEXURE_CLEARANCE_SHORT = "driving tooth passes close to the flexure"
#: the warning when the flank covers less than the nominal overtravel beyond theta_max
OVERTRAVEL_REDUCED = "cam flank overtravel reduced"


def tip_clearance_mm(contact_radius_mm: float, tip_radius_mm: float, gap_mm: float,
                     deflection_rad: float, overtravel: float, root_radius_mm: float) -> float:
    """Gap between the driving tooth's tip corner and the ball at full deflection (mm).

    The tooth tip corner is the flank's end, psi* + f theta (psi* = (r_b + g) / r_c). The
    ball, driven with the gap closed, touches the flank at psi = theta (the cam's turn; its
    tangential travel is r_c theta - g) moved on by the flexure's foreshortening, which
    carries it outward along the flank (:func:`ball_lift_mm`, :func:`driven_psi`). The
    contact FEA at +-theta_max (``fea.contact``) is the check; this is the design's estimate
    of it. The flank between contact and corner is about r_c ((f theta + psi*)^2 - theta^2)
    / 2 less the lift: small deflections and long flexures with a large r_c theta need long
    flanks. Negative when the ball would touch the flank beyond its end (minus the flank
    length missing): it has run over the tooth tip (held-out g29, r_c theta 8.7 mm on 64 mm flexures: lifted 0.9 mm, the ball left
    a flank of overtravel 1.0 and the contact FEA found no contact at -27 deg).
    """
    rc, rb, g = contact_radius_mm, tip_radius_mm, gap_mm
    psi0 = (rb + g) / rc
    lift = ball_lift_mm(rc, root_radius_mm, g, deflection_rad)
    psi_corner, psi_ball = psi0 + overtravel * deflection_rad, driven_psi(rc, g, deflection_rad,
                                                                          lift)
    corner = flank_point(psi_corner, rc, rb + g)
    ball = flank_point(psi_ball, rc, g)
    if psi_ball >= psi_corner:  # minus the flank it would need beyond its end (continuous)
        return -0.5 * rc * ((psi_ball - psi0) ** 2 - (psi_corner - psi0) ** 2)
    return float(np.hypot(*(corner - ball))) - rb


def tip_clearance_need_mm(manufacturing, floor_mm: float = 0.0) -> float:
    """The tooth-tip-to-ball gap estimate the cam rule needs at full deflection (mm):
    :data:`TIP_CLEARANCE_FACTOR` x the profile tolerances t_spring + t_shaft, or the contact
    FEA's floor ``floor_mm`` when that is larger."""
    return max(TIP_CLEARANCE_FACTOR * (manufacturing.t_spring_mm + manufacturing.t_shaft_mm),
               floor_mm)


def _tooth_tip(q: np.ndarray, pitch: float) -> Arc:
    """The tooth tip arc from the flank's end point ``q`` to the next tooth's (pitch
    2 pi / N; mm, rad)."""
    phi_q = math.atan2(q[1], q[0])
    return Arc((0.0, 0.0), float(np.hypot(*q)), phi_q, math.pi - phi_q + pitch)


def _tip_width_mm(tip: Arc) -> float:
    """The tooth tip's width along its arc (mm); negative when the flank runs past the
    next tooth's (a flank too long for the pitch: the contour would cross itself)."""
    return tip.radius * tip.sweep


def tooth_can_clear(contact_radius_mm: float, tip_radius_mm: float, gap_mm: float,
                    n_flexures: int, deflection_rad: float, min_web_mm: float,
                    need_mm: float, root_radius_mm: float) -> bool:
    """Whether some flank length :func:`cam_profile` tries leaves a tooth tip at least
    ``min_web_mm`` wide that passes the ball at full deflection at least ``need_mm`` away
    (:func:`tip_clearance_mm`; mm, rad). The cam's own check adds the gap to the resting
    ring; this one needs no profile, so the layout search can screen contact radii."""
    rc, rho = contact_radius_mm, tip_radius_mm + gap_mm
    pitch = 2 * math.pi / n_flexures
    return any(_tip_width_mm(_tooth_tip(flank_point(rho / rc + f * deflection_rad, rc, rho),
                                        pitch)) >= min_web_mm
               and tip_clearance_mm(rc, tip_radius_mm, gap_mm, deflection_rad, f,
                                    root_radius_mm) >= need_mm
               for f in OVERTRAVELS + LONG_OVERTRAVELS)


def _unit(rc, rho, pitch, psi_end):
    """Segments of one pocket (ball 0 on +y) and the following tooth tip arc, with their names.

    Returns:
        (segments, features, tooth tip arc).
    """
    psi0 = rho / rc
    s_end = 0.5 * rc * (psi_end - psi0) ** 2
    psis = psi0 + np.sqrt(2 * np.linspace(0.0, s_end, 24) / rc)  # uniform arc length
    pts = np.array([flank_point(p, rc, rho) for p in psis])
    t0 = _R(psi0) @ np.array([0.0, 1.0])
    t1 = _R(psi_end) @ np.array([0.0, 1.0])
    left = Spline(tuple(map(tuple, pts)), tuple(t0), tuple(t1))
    right = left.mirrored().reversed()
    cusp = pts[0]
    # the cusp lies on the circle of radius 2 r_c sin(psi*/2) = rho (1 - O(psi*^2)) about the
    # ball centre; the pocket passes exactly through it: the gap is short by 0.05 um at S1 sizes
    beta = math.atan2(cusp[1] - rc, -cusp[0])
    pocket = Arc((0.0, rc), float(np.hypot(cusp[0], cusp[1] - rc)), beta, -math.pi - beta)
    tip = _tooth_tip(pts[-1], pitch)
    segs, feats = named((Feature("flank", 0, "right"), Feature("pocket", 0),
                         Feature("flank", 0, "left"), Feature("tip", 0)),
                        (right, pocket, left, tip))
    return segs, feats, tip


def _ring_points_near_ball0(d) -> np.ndarray:
    """Samples of the ring's inner contour around flexures -1, 0 and 1 (mm)."""
    pitch = 2 * math.pi / d.n_flexures
    pts = []
    for s in d.ring.loop("flexures").segments:
        a = np.array([s.start, s.end])
        ang = np.abs(np.arctan2(a[:, 0], a[:, 1]))  # angle from +y
        if ang.min() < 1.6 * pitch:
            pts.append(s.sample(0.01))
    return np.vstack(pts)


def d_bore(radius_mm: float, flat_ratio: float = 0.8, corner_radius_mm: float = 0.0) -> Loop:
    """D-shaped shaft bore: circle with a flat at ``flat_ratio * r`` below the centre (mm).

    With ``corner_radius_mm`` > 0 the two corners between flat and arc are rounded
    (tangent fillets), so the wire can cut them.
    """
    R, h, rf = radius_mm, flat_ratio * radius_mm, corner_radius_mm
    if rf <= 0:
        a = math.acos(flat_ratio)
        arc = Arc((0.0, 0.0), R, -math.pi / 2 + a, 1.5 * math.pi - a)
        return Loop((arc, Line(arc.end, arc.start)), (Feature("arc"), Feature("flat")))
    cy = -h + rf  # fillet centres sit rf above the flat, rf inside the circle
    cx = math.sqrt((R - rf) ** 2 - cy ** 2)
    a_right = math.atan2(cy, cx)  # direction of the right fillet centre = its circle tangent point
    main = Arc((0.0, 0.0), R, a_right, math.pi - a_right)
    left = Arc((-cx, cy), rf, math.pi - a_right, 1.5 * math.pi)
    flat = Line((-cx, -h), (cx, -h))
    right = Arc((cx, cy), rf, -0.5 * math.pi, a_right)
    return Loop((main, left, flat, right),
                (Feature("arc"), Feature("corner", 0, "left"), Feature("flat"),
                 Feature("corner", 0, "right")))


def _ring_gap_mm(unit, tip, pitch: float, ring_pts) -> float:
    """Smallest gap between one tooth with its two pockets (``unit`` and its copy one pitch
    back, sampled every 0.01 mm) and the resting ring's points near the ball (mm; inf when
    there is no ring): N-fold symmetric, so one tooth and its pockets suffice."""
    if ring_pts is None:
        return float("inf")
    cam_pts = np.vstack([s.sample(0.01) for s in (*unit, *(s.rotated(-pitch) for s in unit))])
    near = ring_pts[np.hypot(*ring_pts.T) < tip.radius + 0.5]
    return min_distance_mm(cam_pts, near)


def cam_profile(d) -> tuple[Profile, CamInfo]:
    """Cam profile for a :class:`~springcad.design.spring.SpringDesign`.

    Tries overtravel factors from 1.25 down to 1.0 and keeps the first whose
    tooth tip is at least ``min_web_mm`` wide and which keeps the gap to the
    resting flexure ring everywhere, among those whose tooth tip stays
    :data:`TIP_CLEARANCE_FACTOR` x the profile tolerance stack from the ball at full
    deflection (:func:`tip_clearance_mm`); when none of them does, the shortest longer
    flank (up to 3 x) that does.

    Raises:
        DesignError: no tooth covering the full deflection fits, or the bore
            leaves too thin a web.
    """
    rc, rb, n = d.contact_radius_mm, d.tip_radius_mm, d.n_flexures
    g = d.manufacturing.w_gap_mm
    rho = rb + g
    pitch = 2 * math.pi / n
    theta = d.max_deflection_rad
    min_web = d.manufacturing.min_web_mm
    ring_pts = _ring_points_near_ball0(d) if d.ring is not None else None
    mfg = d.manufacturing
    need = tip_clearance_need_mm(mfg)
    aim = need * TIP_CLEARANCE_AIM / TIP_CLEARANCE_FACTOR
    # the contact FEA's clearance correction asks more of the estimate (it read the FEA's
    # gap short of the tolerances by that much): both the rule and the aim rise to it
    need, aim = tip_clearance_need_mm(mfg, d.cam_min_tip_clearance_mm), max(
        aim, d.cam_min_tip_clearance_mm)
    rr = d.root_radius_mm
    gaps = {f: tip_clearance_mm(rc, rb, g, theta, f, rr) for f in OVERTRAVELS + LONG_OVERTRAVELS}
    clearing = [f for f in gaps if gaps[f] >= need]
    aimed = [f for f in clearing if gaps[f] >= aim]
    # the reference 1.25 and below where they clear by the aim, else the shortest flanks
    # that do; then the same for the clearance needed; else (a layout the user fixed, or
    # one the search will pass over) the reference flanks, with a warning that stops the
    # release
    overtravels = []
    for group in (aimed, clearing):
        overtravels += [f for f in ([f for f in group if f <= OVERTRAVELS[0]] or group[:6])
                        if f not in overtravels]
    overtravels += [f for f in OVERTRAVELS if f not in overtravels]
    tried, drawable, short = [], [], {}
    stack = mfg.t_spring_mm + mfg.t_shaft_mm
    for f in overtravels:
        psi_end = rho / rc + f * theta
        unit, unit_features, tip = _unit(rc, rho, pitch, psi_end)
        tip_w = _tip_width_mm(tip)
        # the gap to the ring only where the tooth tip is wide enough (most flanks tried
        # fail that first; the refusal below measures the gaps it names)
        clearance = _ring_gap_mm(unit, tip, pitch, ring_pts) if tip_w >= min_web else None
        tried.append((f, tip_w, clearance, unit, tip))
        if not (tip_w >= min_web and clearance >= g - GAP_RESOLUTION_MM):
            continue
        drawable.append((f, unit, unit_features, tip, tip_w, clearance))
        if d.ring is None or f not in clearing:
            break  # no ring to pass, or the ball's rule already unmet: the first drawable
        at_max = clearances_at_max(d.ring.loop("flexures"), unit, pitch, rc, d.root_radius_mm,
                                   g, theta, stack, tip.radius + 0.5)
        short[f] = {part: c for part, c in at_max.items() if c.worst_case_mm < 0}
        if not short[f]:
            break
    if not drawable:
        raise DesignError(
            f"spring '{d.name}': no cam tooth covers the full deflection {theta:.3g} rad: "
            + "; ".join(f"overtravel {f:g}: " + (f"tooth tip {w:.3f} mm wide" if w >= 0 else
                                                  f"the flanks cross by {-w:.3f} mm")
                        + f" (min_web_mm {min_web:g}), clearance "
                        f"{_ring_gap_mm(u, t, pitch, ring_pts) if c is None else c:.4f} mm "
                        f"(w_gap_mm {g:g})" for f, w, c, u, t in tried[:4])
            + "; use fewer flexures, a larger contact radius or a smaller tip radius")
    # the first flank that passes every rule, else the first drawable one (warned below)
    f, unit, unit_features, tip, tip_w, clearance = next(
        (c for c in drawable if c[0] in short and not short[c[0]]), drawable[0])
    segs = tuple(s.rotated(i * pitch) for i in range(n) for s in unit)  # the chosen tooth, N x
    loop = Loop(segs, tuple(f.reindexed(i) for i in range(n) for f in unit_features))
    root = rc - rho
    bore_r = 0.5 * d.hardware.shaft_diameter_mm
    if root - bore_r < min_web:
        raise DesignError(
            f"hardware.shaft_diameter_mm = {d.hardware.shaft_diameter_mm:g}: leaves "
            f"{root - bore_r:.3g} mm of cam below the pockets (root radius {root:.3g} mm); "
            f"needs at least min_web_mm = {min_web:g} mm")
    warnings = ()
    if f < OVERTRAVELS[0]:
        warnings = (f"{OVERTRAVEL_REDUCED} to {f:g} x max deflection to fit the tooth",)
    tip_gap = gaps[f]
    if f not in clearing:
        if tip_gap < 0:
            what = ("the ball runs past the tooth's tip at full deflection (estimate: the "
                    "flexure's foreshortening carries it beyond the flank's end)")
        else:
            what = (f"{UM_PER_MM * tip_gap:.0f} um at full deflection (estimate), below the "
                    f"{UM_PER_MM * need:.0f} um needed ({TIP_CLEARANCE_FACTOR:g} x the profile "
                    "tolerances t_spring_mm + t_shaft_mm, or what the contact FEA asked): the "
                    "toleranced parts can touch there")
        warnings += (f"{TIP_CLEARANCE_SHORT}: {what}; fewer flexures or a larger contact radius "
                     "give a longer flank, or tighten the tolerances",)
    if short.get(f):
        warnings += (f"{FLEXURE_CLEARANCE_SHORT} at full deflection: " + ", ".join(
            f"{part} {UM_PER_MM * c.nominal_mm:.0f} um nominal, {UM_PER_MM * c.worst_case_mm:.0f}"
            " um worst case" for part, c in short[f].items())
            + f" with the profile tolerances (stack {UM_PER_MM * stack:.0f} um; estimate): no "
            "flank length clears both it and the ball; fewer flexures or another contact radius "
            "move the tooth, or tighten the tolerances",)
    info = CamInfo(tip.radius, root, f, tip_w, clearance, warnings, tip_gap)
    corner = d.manufacturing.min_inside_radius_mm
    return Profile(loop, (d_bore(bore_r, corner_radius_mm=corner),), ("teeth", "bore")), info
