"""A designed spring with other flexure widths or another root: profiles and predictions
rebuilt.

The design search (:mod:`springcad.design.search`) sizes the widths; the FEA stiffness
correction scales them (:func:`with_width_scale`), the tolerance study offsets their
edges (:func:`with_width`), and the stress passes and calibration change the root
(:func:`with_root`). Each returns a new :class:`~springcad.design.spring.SpringDesign`
(the record) with its beam stiffness, stress prediction, ring and cam profiles rebuilt
and the wire-EDM rules of the new flexures checked.

Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

from dataclasses import replace as _replace

import numpy as np

from springcad.design import flexure as fx
from springcad.design import stress
from springcad.design.cam import OVERTRAVEL_REDUCED, TIP_CLEARANCE_SHORT, cam_profile
from springcad.design.ring import RootFilletsOverlap, ring_profile
from springcad.design.spring import SpringDesign
from springcad.errors import DesignError


def _neighbour_clearance_mm(d: SpringDesign) -> float:
    """The narrowest gap between neighbouring flexures of ``d`` (mm), on 1201 stations from
    the contact circle to the root."""
    y = np.linspace(d.contact_radius_mm, d.root_station_mm, 1201)
    return fx.neighbour_clearance_mm(d.centreline, y, d.width_mm(y), d.n_flexures,
                                     d.tip_radius_mm)


#: :func:`onto_beam_stiffness` stops when beam theory is this close to the target (-)
ONTO_STIFFNESS_TOL = 1e-5
#: and after this many width updates at most
ONTO_STIFFNESS_PASSES = 12


def onto_beam_stiffness(design: SpringDesign, target_Nmm_per_rad: float) -> SpringDesign:
    """``design`` with the width scale whose beam stiffness is ``target_Nmm_per_rad``
    (N*mm/rad); profiles not rebuilt.

    K grows as scale^3 away from the tip web, which does not scale: where the web carries
    much of the stiffness the cube-root update alone stops short (a small disk kept 5.6 %
    stiff after two passes). A secant on log K against log scale converges in a few passes
    either way; when even flexures much narrower cannot reach the target (the web alone is
    too stiff) the narrowest tried, at most 4 x narrower, is returned and the caller's
    stiffness rule refuses it.
    """
    d = design
    k = d.beam_stiffness_Nmm_per_rad()
    log_s, log_k = [np.log(d.width_scale)], [np.log(k)]
    # the rules judge the design near its own widths: never more than x4 or /4 of them
    low, high = log_s[0] - np.log(4.0), log_s[0] + np.log(4.0)
    for _ in range(ONTO_STIFFNESS_PASSES):
        if abs(k / target_Nmm_per_rad - 1.0) <= ONTO_STIFFNESS_TOL:
            break
        slope = 3.0
        if len(log_s) > 1 and log_s[-1] != log_s[-2]:
            slope = (log_k[-1] - log_k[-2]) / (log_s[-1] - log_s[-2])
        # a web-dominated ring has a small, positive slope: never step more than x2
        step = np.clip((np.log(target_Nmm_per_rad) - log_k[-1]) / max(slope, 0.25),
                       -np.log(2.0), np.log(2.0))
        d = _replace(d, width_scale=float(np.exp(np.clip(log_s[-1] + step, low, high))))
        k = d.beam_stiffness_Nmm_per_rad()
        log_s.append(np.log(d.width_scale))
        log_k.append(np.log(k))
    return d


def with_width(design: SpringDesign, scale: float = 1.0, offset_mm: float = 0.0) -> SpringDesign:
    """The same spring with its flexure widths scaled and/or offset, profiles rebuilt.

    ``scale`` multiplies the current widths (K grows as scale^3 in beam theory,
    up to the fixed tip web): the FEA stiffness correction. ``offset_mm`` moves
    every flexure edge and the tip ball outward (a wire-EDM profile error): the
    tolerance study.

    Raises:
        DesignError: the new flexures break the neighbour clearance or the
            concave edge radius the wire can cut.
    """
    d = _replace(design, width_scale=design.width_scale * scale, width_offset_mm=offset_mm,
                 tip_radius_mm=design.tip_radius_mm - design.width_offset_mm + offset_mm)
    y = np.linspace(d.contact_radius_mm, d.root_station_mm, 1201)
    mfg = d.manufacturing
    d = _replace(d, root_fillet_radius_mm=_root_fillet_fit_mm(d))
    clearance = None
    # straight flexures too (many of them close together at the tips), on the nominal
    # profile; the tolerance study's offsets of a curved flexure are held to it as before
    if not d.centreline.is_straight or offset_mm == 0.0:
        clearance = _neighbour_clearance_mm(d)
        if clearance < mfg.min_slot_width_mm:
            wider = "" if scale == 1.0 else f" {scale:.4f} x wider"
            raise DesignError(
                f"spring '{d.name}': flexures{wider} leave {clearance:.3f} mm to their "
                f"neighbours (min_slot_width_mm {mfg.min_slot_width_mm:g}): fewer flexures")
    if not d.centreline.is_straight:
        edge = fx.concave_edge_radius_mm(d.centreline, y, d.width_mm(y))
        if edge < mfg.min_inside_radius_mm:
            raise DesignError(
                f"spring '{d.name}': flexures {scale:.4f} x wider have a concave edge radius "
                f"{edge:.3f} mm < wire radius + spark gap {mfg.min_inside_radius_mm:g} mm")
    return _with_fitting_root_fillet(_replace(d, min_neighbour_clearance_mm=clearance))


#: a root fillet that meets its neighbour's is lowered by this factor at a time, down to the
#: wire's inside radius
ROOT_FILLET_STEP = 0.7


def _with_fitting_root_fillet(d: SpringDesign) -> SpringDesign:
    """:func:`_predictions_and_profiles` of ``d``, its root fillet lowered by
    :data:`ROOT_FILLET_STEP` while the fillets of neighbouring flexures overlap on the rim
    (a swept or flared root reaches further round than its width), down to the wire's
    inside radius: the root fillet is springcad's choice, not the user's (held-out A 4242
    g18, N = 24 fixed: every layout was refused for overlapping fillets). The stress
    prediction and the FEA then see the smaller fillet's peak.

    Raises:
        RootFilletsOverlap: they overlap even at the wire's inside radius.
    """
    floor = d.manufacturing.min_inside_radius_mm
    while True:
        try:
            return _predictions_and_profiles(d)
        except RootFilletsOverlap:
            if d.root_fillet_radius_mm <= floor * (1.0 + 1e-9):
                raise
            d = _replace(d, root_fillet_radius_mm=max(floor, ROOT_FILLET_STEP
                                                      * d.root_fillet_radius_mm))


#: a root fillet takes at most this share of the rim arc between two flexure roots, so
#: wider flexures (the FEA stiffness correction, a flare) keep the neighbours' fillets apart
ROOT_FILLET_GAP_SHARE = 0.45


def _root_fillet_fit_mm(d: SpringDesign) -> float:
    """The design's root fillet radius, lowered where the flexures have grown so wide that
    it would take more than :data:`ROOT_FILLET_GAP_SHARE` of the arc between their roots
    at R_r (mm), never below the wire's inside radius (the stress prediction and the FEA
    then see the smaller fillet's peak)."""
    root_width = float(d.width_mm(np.array([d.root_station_mm]))[0])
    gap = 2.0 * np.pi * d.root_radius_mm / d.n_flexures - root_width
    fit = max(ROOT_FILLET_GAP_SHARE * gap, d.manufacturing.min_inside_radius_mm)
    return min(d.root_fillet_radius_mm, fit)


def _predictions_and_profiles(d: SpringDesign) -> SpringDesign:
    """Beam stiffness and stresses of the current widths, then the ring and cam profiles.

    The nominal (beam) stress 6 M / (z w^2) is uniform along a constant-stress flexure;
    the predicted peak of the real geometry adds curvature and the root fillet
    (:func:`springcad.design.stress.predict`). The cam is built last: it checks its gap
    against the ring.
    """
    k = d.beam_stiffness_Nmm_per_rad()
    d = _replace(d, stiffness_beam_Nmm_per_rad=k)
    prediction = stress.predict(d)
    d = _replace(d, peak_stress_MPa=prediction.nominal_MPa, stress=prediction)
    ring, holes, hole_d = ring_profile(d)
    d = _replace(d, ring=ring, hole_centres_mm=holes, hole_diameter_mm=hole_d)
    cam, info = cam_profile(d)
    return _replace(d, cam=cam, cam_tip_radius_mm=info.tip_radius_mm,
                    cam_root_radius_mm=info.root_radius_mm, cam_overtravel=info.overtravel,
                    cam_tip_clearance_mm=info.tip_clearance_mm,
                    warnings=tuple(dict.fromkeys(d.warnings + info.warnings)))


def with_cam_clearance(design: SpringDesign, min_tip_clearance_mm: float) -> SpringDesign:
    """The same ring with a cam whose flanks are long enough that the design's estimate of
    the tooth-tip-to-ball gap at full deflection reaches ``min_tip_clearance_mm`` (mm), when
    a tooth that long still fits (:func:`springcad.design.cam.cam_profile`; else the cam's
    warning says so). The ring, so K and the stresses, is unchanged: the contact FEA's
    clearance correction."""
    d = _replace(design, cam_min_tip_clearance_mm=min_tip_clearance_mm)
    cam, info = cam_profile(d)
    kept = tuple(w for w in d.warnings if not w.startswith((TIP_CLEARANCE_SHORT,
                                                             OVERTRAVEL_REDUCED)))
    return _replace(d, cam=cam, cam_tip_radius_mm=info.tip_radius_mm,
                    cam_root_radius_mm=info.root_radius_mm, cam_overtravel=info.overtravel,
                    cam_tip_clearance_mm=info.tip_clearance_mm,
                    warnings=tuple(dict.fromkeys(kept + info.warnings)))


def with_root(design: SpringDesign, flare: float, flare_length_mm: float | None = None,
              root_fillet_radius_mm: float | None = None) -> SpringDesign:
    """The spring with another root shape, its widths rescaled back onto the beam stiffness.

    Args:
        flare: relative width added at the root (:func:`flexure.root_flare_factor`).
        flare_length_mm: length of the flare zone (mm); default: the design's, or the
            root zone (twice the rim thickness) when it has none.
        root_fillet_radius_mm: root fillet radius (mm); default: unchanged.

    Raises:
        DesignError: the new flexures break the neighbour clearance or the concave
            edge radius (:func:`with_width`).
    """
    length = (flare_length_mm if flare_length_mm is not None
              else design.root_flare_length_mm or 2.0 * design.rim_thickness_mm)
    d = _replace(design, root_flare=flare, root_flare_length_mm=length,
                 root_fillet_radius_mm=(root_fillet_radius_mm if root_fillet_radius_mm is not None
                                        else design.root_fillet_radius_mm))
    d = onto_beam_stiffness(d, design.beam_stiffness_Nmm_per_rad())
    return with_width(d, 1.0, d.width_offset_mm)


def with_width_scale(design: SpringDesign, scale: float) -> SpringDesign:
    """The spring with ``width_scale`` set to ``scale`` (absolute): :func:`with_width`."""
    return with_width(design, scale / design.width_scale, design.width_offset_mm)


#: the FEA stiffness correction may need to lower the beam stiffness by this fraction (the
#: FEA and beam theory differ by a few % on curved and short flexures): a layout whose
#: minimum webs leave less room than this cannot be corrected onto its target
STIFFNESS_ROOM = 0.05
#: the width scale at which that room is measured, relative to the design's (-)
ROOM_SCALE = 0.9
#: the beam stiffness a design may keep above its target (-)
STIFFNESS_OVER = 0.01


def web_stiffness_excess(k_Nmm_per_rad, k_narrow_Nmm_per_rad, target_Nmm_per_rad):
    """How far the minimum webs hold the stiffness from the reach of the FEA correction
    (-, scalars or arrays): the larger of K / (target (1 + :data:`STIFFNESS_OVER`)) and
    K_narrow / (target (1 - :data:`STIFFNESS_ROOM`)), K_narrow the beam stiffness of flexures
    :data:`ROOM_SCALE` x as wide; above 1 the layout is out of reach. N*mm/rad in."""
    return np.maximum(k_Nmm_per_rad / (target_Nmm_per_rad * (1 + STIFFNESS_OVER)),
                      k_narrow_Nmm_per_rad / (target_Nmm_per_rad * (1 - STIFFNESS_ROOM)))


class WebsHoldStiffness(DesignError):
    """No layout designs, and some were passed over by :func:`stiffness_out_of_reach`: the
    minimum webs hold the stiffness above the target, so a thinner disk may design (a spring's
    feasibility is then not monotone in its thickness: thin plates fail the stress, thick ones
    the webs)."""


def stiffness_out_of_reach(design: SpringDesign) -> str:
    """Why the widths cannot bring ``design``'s stiffness onto its target, or "".

    The wire-EDM minimum web near the tips does not scale with the widths: when the webs
    carry much of the stiffness, the design's beam stiffness stays above the target, or
    flexures :data:`ROOM_SCALE` x as wide do not lower it by :data:`STIFFNESS_ROOM`, the
    room the FEA correction needs (a held-out spring designed 10 % stiff verified +5.8 %
    after four corrections): :func:`web_stiffness_excess` > 1. Beam theory, milliseconds.
    """
    target = design.target_stiffness_Nmm_per_rad
    k = design.beam_stiffness_Nmm_per_rad()
    narrower = _replace(design, width_scale=design.width_scale * ROOM_SCALE)
    fillets = root_fillet_stiffening(narrower)
    k_narrow = narrower.beam_stiffness_Nmm_per_rad() * fillets
    if web_stiffness_excess(k, k_narrow, target) <= 1.0:
        return ""
    web = design.manufacturing.min_web_mm
    by_fillets = (f" with the root fillets (R{design.root_fillet_radius_mm:.3g} mm on "
                  f"{design.root_width_mm:.3g} mm wide roots, x{fillets:.3f})"
                  if fillets > 1.0 + STIFFNESS_ROOM else "")
    return (f"spring '{design.name}': the wire-EDM minimum web ({web:g} mm) near the flexure "
            f"tips keeps the beam stiffness at {k / 1e3:.4g} N*m/rad ({100 * (k / target - 1):+.1f} "
            f"% from the target), and flexures {ROOM_SCALE:g} x as wide only reach "
            f"{100 * (k_narrow / target - 1):+.1f} %{by_fillets}: fewer or longer flexures, a "
            "thinner disk or a higher stiffness")


def root_fillet_stiffening(design: SpringDesign) -> float:
    """How much the root fillets stiffen the flexures over the width law alone (-, >= 1):
    the beam compliance with and without the fillets' widening, 2 (rho - sqrt(rho^2 - d^2))
    at d = y - (R_r - rho) over the last rho before the root (two circular fillets of radius
    rho tangent to the flexure's edges and the rim). The beam stiffness and the FEA
    correction take the width law alone; a fillet as large as the root is wide, on a short
    flexure, stiffens it by tens of % the narrower widths do not remove where the tips sit
    at the minimum web (a 12.5 mm disk 6 mm thick: x1.37 by this integral, FEA +48 %;
    the default template x1.025, the paper's S1 x1.009)."""
    rho = design.root_fillet_radius_mm
    y, w, compliance = design.beam_integral()
    d = y - (design.root_station_mm - rho)
    widening = np.where(d > 0.0, 2.0 * (rho - np.sqrt(np.maximum(rho ** 2 - d ** 2, 0.0))), 0.0)
    return compliance(w) / compliance(w + widening)


#: the FEA stiffness correction may need flexures this much wider (-): K ~ w^3, so +12 %
#: (a held-out spring of 79 flexures 0.38 mm apart verified 10 % soft, and 1.037 x wider
#: flexures left 0.25 mm between them: the correction stopped)
WIDEN_ROOM = 1.04


def widening_room_short(design: SpringDesign) -> list[str]:
    """Why flexures :data:`WIDEN_ROOM` x as wide would break the neighbour clearance the
    wire needs (a shortfall the search tries other layouts to avoid), else []."""
    clearance = _neighbour_clearance_mm(
        _replace(design, width_scale=design.width_scale * WIDEN_ROOM))
    need = design.manufacturing.min_slot_width_mm
    if clearance >= need:
        return []
    return [f"spring '{design.name}': flexures {WIDEN_ROOM:g} x as wide (the room the FEA "
            f"stiffness correction may need) leave {clearance:.3f} mm to their neighbours "
            f"(min_slot_width_mm {need:g}; N = {design.n_flexures})"]
