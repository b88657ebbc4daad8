"""Checks of a designed job that need the chosen geometry (N, r_c, R_r, holes, cam).

:func:`check_hardware` raises :class:`DesignError` for parts that cannot exist
(rim holes crossing an edge or each other, a camshaft bore that eats the cam, a
component with no volume, a rim fastener reaching a part it does not join:
:mod:`springcad.design.fastener_room`, rim pins too weak for the stack torque:
:mod:`springcad.design.joint_strength`); :func:`design_warnings` lists legal but suspicious
results (flexures thinner than the wire, a stiffness the envelope cannot give,
fasteners cut to the number of flexure gaps). Config-only checks are in
:mod:`springcad.config.consistency`. Units: mm, N*mm/rad, kg.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from springcad.config.consistency import MIN_RIM_FRACTION, SHAFT_STEP_MM
from springcad.config.schema import keys
from springcad.design.fastener_room import check_fastener_room
from springcad.design.joint_strength import check_pin_strength
from springcad.design.plans import RimSpacerPlan
from springcad.design.rim_spacer import max_pin_mm, rim_spacer_fit
from springcad.errors import DesignError, RemedyError, change_text
from springcad.units import NMM_PER_NM, UM_PER_MM

#: beam-theory stiffness further than this from the target is reported (fraction)
STIFFNESS_WARN_FRACTION = 0.01
#: camshaft hub radius below the cam root (the EDM wire clears the hub), as in design.hardware
_HUB_CLEARANCE_MM = 0.1


def _holes(s) -> None:
    if not s.hole_centres_mm:
        return
    edge = s.manufacturing.min_hole_edge_mm
    r_hole = 0.5 * s.hole_diameter_mm
    centres = np.asarray(s.hole_centres_mm)
    radius = float(np.hypot(*centres[0]))
    inner = radius - r_hole - s.root_radius_mm
    outer = s.outer_radius_mm - radius - r_hole
    if min(inner, outer) < edge - 1e-9:
        raise DesignError(
            f"spring '{s.name}': rim holes of {s.hole_diameter_mm:g} mm do not fit its rim "
            f"({s.root_radius_mm:.3f} to {s.outer_radius_mm:.3f} mm, {s.rim_thickness_mm:.3f} mm "
            f"thick) with min_hole_edge_mm = {edge:g} on both sides; the rim needs "
            f"{s.hole_diameter_mm + 2 * edge:.3g} mm: use a smaller hardware.fastener_diameter_mm, "
            "fastener_count = 0, or a larger outer radius")
    if len(centres) > 1:
        gaps = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=-1)
        gaps[np.diag_indices(len(centres))] = np.inf
        ligament = float(gaps.min()) - 2 * r_hole
        if ligament < edge - 1e-9:
            raise DesignError(
                f"spring '{s.name}': {len(centres)} rim holes of {s.hole_diameter_mm:g} mm leave "
                f"{ligament:.3g} mm between neighbours (min_hole_edge_mm = {edge:g}); use fewer "
                "or smaller fasteners")


def _bore(s, shaft_diameter_mm: float, min_web_mm: float) -> None:
    if not s.cam_root_radius_mm:
        return
    wall = s.cam_root_radius_mm - _HUB_CLEARANCE_MM - 0.5 * shaft_diameter_mm
    if wall < min_web_mm:
        most = 2 * (s.cam_root_radius_mm - _HUB_CLEARANCE_MM - min_web_mm)
        # springcad's bore steps (the bore it chooses under a fixed contact radius)
        fit = math.floor(most / SHAFT_STEP_MM + 1e-9) * SHAFT_STEP_MM
        key = "hardware.shaft_diameter_mm"
        lowest = keys("hardware")["shaft_diameter_mm"].lo
        raise RemedyError(
            f"spring '{s.name}': {key} = {shaft_diameter_mm:g} leaves a camshaft wall of "
            f"{wall:.3g} mm under the cam teeth (cam root radius {s.cam_root_radius_mm:.3f} mm, "
            f"min_web_mm = {min_web_mm:g}; a bore of at most {max(most, 0):.3g} mm keeps it)",
            [({key: fit}, change_text(key, fit, shaft_diameter_mm))] if fit >= lowest else [],
            "a larger contact radius")


def check_hardware(job_design) -> None:
    """Raise :class:`DesignError` for designed parts that cannot be made.

    Args:
        job_design: a :class:`~springcad.design.job.JobDesign`.
    """
    hw = job_design.job.hardware
    for s in job_design.springs.values():
        _holes(s)
        _bore(s, hw.shaft_diameter_mm, s.manufacturing.min_web_mm)
        rim_min = max(s.manufacturing.min_web_mm, 2 * s.manufacturing.min_inside_radius_mm)
        if s.rim_thickness_mm < rim_min:
            raise DesignError(
                f"spring '{s.name}': the rim is {s.rim_thickness_mm:.3g} mm thick; the wire needs "
                f"{rim_min:.3g} mm (min_web_mm, inside radius): fewer flexures, a larger outer "
                "radius or a smaller root radius")
    for c in job_design.stack.components:
        if not (math.isfinite(c.volume_mm3) and c.volume_mm3 > 0):
            raise DesignError(
                f"stack part {c.name} ({c.kind}) has no material left (volume "
                f"{c.volume_mm3:.3g} mm^3): its holes or bore are larger than the part; check "
                "the hardware sizes against the spring radii")
    check_fastener_room(job_design.stack.layout, job_design.stack.springs)
    check_pin_strength(job_design.stack)
    check_rim_spacers(job_design)


#: rim spacer sheets (mm) a refused spacer is offered, thickest first (webs of at least the
#: sheet thickness: a thinner sheet needs less rim)
SPACER_SHEETS_MM = (0.6, 0.5, 0.4, 0.3, 0.2)


def check_rim_spacers(job_design) -> None:
    """Raise :class:`RemedyError` when a rim spacer cannot be made on its rim: no process
    keeps the worst-case webs of its pin holes (at least the sheet thickness) and clears
    the flexure roots (:func:`~springcad.design.rim_spacer.rim_spacer_fit`). The stack lays
    such a spacer out as well as the rim allows, which the build's sheet-web rule then
    refused after the FEA (held-out g10 with 7 bolts: 0.403 mm webs on 0.8 mm sheet); the
    remedy is the thickest thinner sheet that fits."""
    hw = job_design.job.hardware
    stack = job_design.stack
    pin_max = max_pin_mm(hw.fastener, hw.fastener_diameter_mm)
    for c in stack.components:
        plan = c.plan
        if not isinstance(plan, RimSpacerPlan) or not plan.hole_centres_mm:
            continue
        lower, upper = stack.springs[plan.joint], stack.springs[plan.joint + 1]
        root = max(lower.root_radius_mm, upper.root_radius_mm)
        r_hc = min(math.hypot(*p) for p in plan.hole_centres_mm)

        def shortfall(thickness_mm: float) -> str:
            """Why no process makes the spacer from this sheet, or ""."""
            try:
                rim_spacer_fit(root, plan.outer_radius_mm, r_hc, hw.fastener_diameter_mm,
                               pin_max, thickness_mm, lower.manufacturing.min_hole_edge_mm)
            except DesignError as err:
                return str(err).rstrip(". ")
            return ""

        why = shortfall(hw.rim_spacer_thickness_mm)
        if not why:
            continue
        key = "hardware.rim_spacer_thickness_mm"
        remedies = [({key: t}, change_text(key, t, hw.rim_spacer_thickness_mm))
                    for t in SPACER_SHEETS_MM
                    if t < hw.rim_spacer_thickness_mm and not shortfall(t)][:1]
        raise RemedyError(f"{c.name} (joint {plan.joint + 1}, {hw.rim_spacer_thickness_mm:g} mm "
                          f"sheet, holes on R{r_hc:.2f}): {why}", remedies,
                          "a larger outer radius or smaller rim fasteners")


def _webs_stiffen(spring) -> bool:
    """Whether the wire-EDM minimum web (the width kept near the tips) raises the spring's
    beam-theory stiffness by more than :data:`STIFFNESS_WARN_FRACTION`: the cause the
    stiffness warning names. A design whose beam stiffness differs from the target for
    another reason (the FEA correction's width scale, which sets the FEA's K on target) is
    not warned."""
    bare = replace(spring, manufacturing=replace(spring.manufacturing, min_web_mm=1e-9))
    return spring.beam_stiffness_Nmm_per_rad() > (1 + STIFFNESS_WARN_FRACTION) * \
        bare.beam_stiffness_Nmm_per_rad()


def design_warnings(job_design) -> list[str]:
    """Plausibility warnings of a designed job (shown on the console and in design.json)."""
    out = []
    hw = job_design.job.hardware
    for s in job_design.springs.values():
        mfg = s.manufacturing
        root_w = float(s.width_mm(s.root_radius_mm))
        if root_w < mfg.wire_diameter_mm:
            out.append(
                f"spring {s.name}: flexure root width {root_w * UM_PER_MM:.3g} um is thinner than the "
                f"EDM wire ({mfg.wire_diameter_mm:g} mm): the target stiffness "
                f"{s.target_stiffness_Nmm_per_rad / NMM_PER_NM:.3g} N*m/rad is too low for this "
                "disk; use a thinner or smaller disk, or fewer flexures")
        k, target = s.stiffness_beam_Nmm_per_rad, s.target_stiffness_Nmm_per_rad
        if abs(k / target - 1) > STIFFNESS_WARN_FRACTION and _webs_stiffen(s):
            out.append(
                f"spring {s.name}: beam-theory stiffness {k / NMM_PER_NM:.4g} N*m/rad is "
                f"{100 * (k / target - 1):+.1f} % from the target {target / NMM_PER_NM:.4g}: the "
                "envelope cannot give that stiffness with the wire-EDM minimum webs")
        if hw.fastener_count > s.n_flexures:
            out.append(f"spring {s.name}: hardware.fastener_count = {hw.fastener_count} cut to "
                       f"{len(s.hole_centres_mm)}: one rim hole per gap between its "
                       f"{s.n_flexures} flexures")
        if s.rim_thickness_mm < MIN_RIM_FRACTION * s.outer_radius_mm:
            out.append(f"spring {s.name}: the rim is only {s.rim_thickness_mm:.3g} mm thick "
                       f"({100 * s.rim_thickness_mm / s.outer_radius_mm:.2g} % of the outer "
                       "radius); it carries the whole torque")
    return out
