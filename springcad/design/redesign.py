"""The FEA corrections' redesigns: the design search run again with what the FEA measured.

:func:`fea.verify.verify_spring` corrects K by scaling the flexure widths; when that is
not enough it asks for one of these:

* :func:`redesign_for_margin`: the real geometry's peak is over the margin the design was
  sized for (yield, the duty): the search against a margin raised by the FEA's bias;
* :func:`redesign_for_stiffness`: the widths cannot be scaled under the rules: a layout
  with room for the beam stiffness the FEA asks;
* :func:`redesign_for_contact`: the tip balls are over-stressed at +-theta_max: the search
  with the smallest ball the contact FEA names.

Each keeps the user's spec (the target) and the stack's rim-hole circle. Units: mm, MPa, N*mm.
"""

from __future__ import annotations

import math
from dataclasses import replace as _replace

from springcad.config import MaterialSpec
from springcad.design import duty
from springcad.design.ring import with_hole_circle
from springcad.design.search import changes_for_margin, design_spring, short_reason
from springcad.design.shortfalls import soft_shortfalls
from springcad.design.spring import SpringDesign
from springcad.errors import DesignError


def _on_holes_of(design: SpringDesign, redesigned: SpringDesign) -> SpringDesign:
    """``redesigned`` with its rim holes on ``design``'s hole circle (a redesign keeps the
    circle the stack shares), or as it is when ``design`` has no holes."""
    if not design.hole_centres_mm:
        return redesigned
    return with_hole_circle(redesigned, math.hypot(*design.hole_centres_mm[0]))


#: thicker stock plates the FEA stress correction tries when the thickness is springcad's
MARGIN_PLATES = 3


def _meets(d: SpringDesign, material: MaterialSpec, default_sized: bool) -> bool:
    """Whether ``d``'s predicted peak keeps the margin of ``material`` (with springcad's
    default duty when the spring is sized for it)."""
    mat = duty.sized_for(material) if default_sized else material
    return d.yield_margin >= duty.required_margin(mat, d.max_deflection_rad) * (1.0 - 1e-3)


def redesign_for_margin(design: SpringDesign, model_bias: float) -> SpringDesign:
    """The spring redesigned so its predicted peak x ``model_bias`` keeps the required margin.

    The FEA stress correction: when FEA finds the peak ``model_bias`` times the design's
    prediction, the design's own stress passes (:func:`design_spring`) run against a
    required margin raised by that factor, so the new geometry is judged by the same
    model that missed, corrected by what the FEA measured. Tried in order, the first
    whose prediction keeps that margin is returned:

    1. the same layout (N, r_c, tip ball, so the cam): a correction is a small move, and
       the bias measured holds for that layout (another has other 3D factors and stress
       raisers: on the default at 20 deg a new layout's FEA peak came out higher);
    2. the full search, unless its layout brings the tooth tip near the ball where the
       old one did not;
    3. the same on the next :data:`MARGIN_PLATES` thicker stock plates, when springcad
       chose the thickness (``thicker_plates_mm``; default at 20 deg: the layout at 40 mm
       has no longer flexures to lower its stress).

    Rim holes stay on the design's hole circle.

    Raises:
        DesignError: none of them keeps the margin.
    """
    mat = design.material
    biased = duty.biased(mat, max(model_bias, 1.0))
    default_sized = design.sized_for_default_duty
    tried = []
    for t in (design.thickness_mm, *design.thicker_plates_mm[:MARGIN_PLATES]):
        spec = _replace(design.spec, thickness_mm=t)
        same = _replace(spec, n_flexures=design.n_flexures,
                        contact_radius_mm=design.contact_radius_mm,
                        tip_radius_mm=design.tip_radius_mm)
        for s, what in ((same, "the same layout"), (spec, "any layout")):
            try:
                d = design_spring(s, biased, design.manufacturing, design.hardware,
                                  explain=False, max_root_radius_mm=design.max_root_radius_mm)
            except DesignError as err:
                tried.append(f"{what} at {t:g} mm: {short_reason(err)}")
                continue
            if not _meets(d, biased, default_sized):
                tried.append(f"{what} at {t:g} mm: predicted yield margin {d.yield_margin:.3f}")
                continue
            if soft_shortfalls(d) and not soft_shortfalls(design):
                tried.append(f"{what} at {t:g} mm: {soft_shortfalls(d)[0].split(':')[0]}")
                continue
            thicker = tuple(u for u in design.thicker_plates_mm if u > t)
            # a note, not a warning: the redesign is verified again, and its verdict gates
            # the release
            d = _replace(d, spec=_replace(design.spec, thickness_mm=t), material=mat,
                         thicker_plates_mm=thicker, design_choice=(
                             f"{d.design_choice}; redesigned by the FEA stress correction "
                             f"(FEA peak {model_bias:.3f} x the design prediction; {what} at "
                             f"{t:g} mm): beam stress {d.beam_stress_MPa:.0f} MPa"))
            return _on_holes_of(design, d)
    changes = changes_for_margin(design.spec, mat, design.manufacturing, design.hardware,
                                 design.max_root_radius_mm, max(model_bias, 1.0))
    shared = design.spec.shared_camshaft
    held = (f"; {', '.join(shared)} held at the layout of the springs that share its camshaft"
            if shared else "")
    raise DesignError(f"spring '{design.name}': no redesign keeps the yield margin "
                      f"{duty.required_margin(biased, design.max_deflection_rad):.3f} for a "
                      f"peak {model_bias:.3f} x the prediction ({'; '.join(tried)}{held}); "
                      f"with that peak the spring is {changes}")


def redesign_for_stiffness(design: SpringDesign, k_ratio: float) -> SpringDesign:
    """The spring redesigned for a beam stiffness ``k_ratio`` x its target, target unchanged.

    The FEA stiffness correction when the widths cannot simply be scaled (the wider
    flexures would break the neighbour clearance or the edge radius): the design search
    runs for K_target x ``k_ratio`` (the FEA measured K_target / ``k_ratio`` for the
    beam's K_target), so it chooses a layout with room for those widths under every
    rule; the spec (and so the target) is then the user's again. Rim holes stay on the
    design's hole circle.

    Raises:
        DesignError: no layout carries that stiffness in the envelope.
    """
    spec = design.spec
    biased = _replace(spec, target_stiffness_Nmm_per_rad=spec.target_stiffness_Nmm_per_rad * k_ratio)
    d = design_spring(biased, design.material, design.manufacturing, design.hardware,
                      explain=False, max_root_radius_mm=design.max_root_radius_mm)
    d = _replace(d, spec=spec, warnings=d.warnings, design_choice=(
        f"{d.design_choice}; redesigned by the FEA stiffness correction for a beam stiffness "
        f"{k_ratio:.4f} x the target (the widths alone could not be scaled)"))
    return _on_holes_of(design, d)


def redesign_for_contact(design: SpringDesign, min_tip_radius_mm: float) -> SpringDesign:
    """The spring redesigned with tip balls of at least ``min_tip_radius_mm`` (mm).

    The FEA contact correction: the contact sweep found the balls' Hertz stress at
    +-theta_max above the allowable and named the smallest ball that carries the same
    force on the same flank; the search runs again with that floor (a larger ball may
    change N and r_c), the spec otherwise the user's. Rim holes stay on the design's
    hole circle.

    Raises:
        DesignError: no layout with balls that large meets the spec.
    """
    spec = design.spec
    floor = _replace(spec, min_tip_radius_mm=max(spec.min_tip_radius_mm, min_tip_radius_mm))
    d = design_spring(floor, design.material, design.manufacturing, design.hardware,
                      explain=False, max_root_radius_mm=design.max_root_radius_mm)
    d = _replace(d, spec=spec, design_choice=(
        f"{d.design_choice}; redesigned by the FEA contact correction for tip balls of at "
        f"least {min_tip_radius_mm:.3f} mm"))
    return _on_holes_of(design, d)


def redesign_for_cam(design: SpringDesign, min_tip_clearance_mm: float) -> SpringDesign:
    """The spring redesigned so its cam's tooth-tip-to-ball gap estimate at full deflection
    reaches ``min_tip_clearance_mm`` (mm) on every layout the search keeps.

    The contact FEA's cam correction, when the driving tooth tip passes the ball (its neck,
    its edge) closer than the tolerances allow and no longer flank fits this layout's tooth
    (:func:`springcad.design.resize.with_cam_clearance` could not): the search runs again
    with that floor, so it passes over layouts whose tooth has no room for the flank
    (fewer flexures, a larger contact radius give one; the layouts that keep a shortfall
    are its soft shortfalls). The spec is otherwise the user's; rim holes stay on the
    design's hole circle.

    Raises:
        DesignError: no layout meets the spec, or none without the shortfall.
    """
    spec = _replace(design.spec, cam_min_tip_clearance_mm=min_tip_clearance_mm)
    d = design_spring(spec, design.material, design.manufacturing, design.hardware,
                      explain=False, max_root_radius_mm=design.max_root_radius_mm)
    if soft_shortfalls(d):
        raise DesignError(f"spring '{design.name}': no layout's cam reaches a tooth-tip gap "
                          f"estimate of {1000 * min_tip_clearance_mm:.0f} um")
    d = _replace(d, material=design.material, design_choice=(
        f"{d.design_choice}; redesigned by the FEA cam correction for a tooth-tip gap estimate "
        f"of at least {1000 * min_tip_clearance_mm:.0f} um (layout {design.n_flexures} "
        f"flexures, r_c {design.contact_radius_mm:.3f} mm had no room for a longer flank)"))
    return _on_holes_of(design, d)


__all__ = ["redesign_for_margin", "redesign_for_stiffness", "redesign_for_contact",
           "redesign_for_cam"]
