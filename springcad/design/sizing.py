"""One candidate layout's spring: flexure shape and widths at the design stress, the root
flare with the lowest predicted peak, and the stress passes that keep the yield margin.

:mod:`springcad.design.search` ranks the layouts and asks this module for each one's
design (:func:`_design_with_margin`); the synthesis screening follows the same steps on
arrays (:mod:`springcad.synthesis.screening`, :mod:`springcad.synthesis.peak`).
Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
from dataclasses import replace as _replace

from springcad.config import HardwareSpec, ManufacturingSpec, MaterialSpec, SpringSpec
from springcad.config.consistency import CONTACT_SEARCH_FRACTION, min_rim_mm
from springcad.design import duty, shapes, stress
from springcad.design import flexure as fx
from springcad.design.cam import tip_clearance_need_mm, tooth_can_clear
from springcad.design.layout import ContactLimit, Layout, fits, layout_at, toleranced_layouts
from springcad.design.resize import onto_beam_stiffness, with_width
from springcad.design.shapes.base import SizingContext
from springcad.design.spring import SpringDesign
from springcad.errors import DesignError, SpecInfeasible
from springcad.units import J_PER_NMM, NMM_PER_NM

#: the start of the warning that the design lowered its beam stress for the margin (the
#: FEA's yield margin checks the real geometry: a note where it ran)
STRESS_DERATED = "beam stress lowered"


#: within :func:`for_a_user`: a layout whose only shortfall is the profile tolerances' cusp
#: room is made for nominal parts (the release gate stops it); outside (the synthesis's yes
#: or no), it is no candidate
_FOR_A_USER: contextvars.ContextVar[bool] = contextvars.ContextVar("springcad_for_a_user",
                                                                   default=False)


@contextlib.contextmanager
def for_a_user():
    """Within it, the search makes the spring a user asked for even when only the profile
    tolerances keep it from release (:func:`~springcad.design.layout.toleranced_layouts`)."""
    token = _FOR_A_USER.set(True)
    try:
        yield
    finally:
        _FOR_A_USER.reset(token)


def designing_for_a_user() -> bool:
    """Whether the search runs within :func:`for_a_user`."""
    return _FOR_A_USER.get()


class _NoMoreLayouts(Exception):
    """The layout rank asked for is past the last candidate layout."""


# --------------------------------------------------------------------- one layout
def energy_bound(spec: SpringSpec, thickness_mm: float, sigma_MPa: float,
                 youngs_modulus_MPa: float, manufacturing: ManufacturingSpec,
                 hardware: HardwareSpec, max_root_radius_mm: float = math.inf
                 ) -> tuple[float, float, float]:
    """The energy no layout of ``spec`` at thickness ``thickness_mm`` (mm) can exceed at beam
    stress ``sigma_MPa``: (largest root radius R_r mm, smallest contact radius r_c mm, bound J).

    The flexures are bending beams between the contact circle and the root circle, and no
    beam stores more than sigma^2/(6E) per unit volume at outer-fibre stress sigma, so the
    annulus r_c..R_r bounds the energy of every layout: r_c no smaller than the tip balls'
    torque cap allows (load-sized balls) or the user's, R_r no larger than the rim (and the
    stack's hole circle, ``max_root_radius_mm``) allows.
    """
    rr_max = min(max_root_radius_mm,
                 spec.outer_radius_mm - min_rim_mm(spec.outer_radius_mm, manufacturing, hardware))
    peak_Nmm = spec.target_stiffness_Nmm_per_rad * spec.max_deflection_rad
    rc_min = (spec.contact_radius_mm if spec.contact_radius_mm is not None else
              fx.min_contact_radius_mm(peak_Nmm, thickness_mm, sigma_MPa)
              if spec.tip_radius_mm is None else 0.0)
    volume_mm3 = math.pi * max(rr_max ** 2 - rc_min ** 2, 0.0) * thickness_mm
    return rr_max, rc_min, fx.energy_bound_J_per_mm3(sigma_MPa, youngs_modulus_MPa) * volume_mm3


def _inner_bound_text(spec: SpringSpec) -> str:
    """Where :func:`energy_bound`'s inner radius comes from, for a refusal."""
    if spec.contact_radius_mm is not None:
        return "your contact_radius_mm"
    if spec.tip_radius_mm is None:
        return "the tip balls' torque cap"
    return "the centre: a fixed tip_radius_mm sets no torque cap"


def _design_at(spec: SpringSpec, material: MaterialSpec, manufacturing: ManufacturingSpec,
               hardware: HardwareSpec, derating: float = 1.0,
               balances: tuple[str, ...] = fx.BALANCES, rank: int = 0,
               max_root_radius_mm: float = math.inf) -> SpringDesign:
    """Layout, flexure shape and width calibration at beam stress ``derating`` x design stress.

    No root flare, no profiles yet (:func:`design_spring` adds both). ``balances``: the
    serpentine balances tried (:func:`flexure.design_serpentine`); ``rank``: which of the
    ranked candidate layouts (:func:`~springcad.design.layout.candidate_layouts`, 0 = the
    reference method's choice); ``max_root_radius_mm``: a root radius cap from outside the
    spring (a stack's common rim-hole circle), besides the spring's own rim.

    Raises:
        DesignError: the spec cannot be met in its envelope (the message says why
            and what to change).
        _NoMoreLayouts: ``rank`` is past the last candidate.
    """
    sigma = material.design_stress_MPa * derating
    E = material.material.youngs_modulus_MPa
    z, K, theta_d = spec.thickness_mm, spec.target_stiffness_Nmm_per_rad, spec.max_deflection_rad
    warnings: list[str] = []

    rr_max, rc_min, bound_J = energy_bound(spec, z, sigma, E, manufacturing, hardware,
                                           max_root_radius_mm)
    need_J = 0.5 * K * theta_d ** 2 * J_PER_NMM
    if need_J > bound_J:
        raise SpecInfeasible(
            f"spring '{spec.name}': storing {need_J:.3g} J at {theta_d:.3g} rad needs more than "
            f"the flexures can hold at the design stress {sigma:.0f} MPa in the annulus between "
            f"r_c = {rc_min:.3g} mm ({_inner_bound_text(spec)}) and R_r = {rr_max:.3g} mm (the "
            f"rim): sigma^2/(6E) x pi (R_r^2 - r_c^2) z = {bound_J:.3g} J; no flexure geometry in "
            "this envelope reaches that deflection: lower the stiffness or deflection, enlarge "
            "or thicken the disk, or put springs in series")

    contact = ContactLimit.of(material, spec.max_deflection_rad, manufacturing)
    layouts, cusp_warning = toleranced_layouts(spec, sigma, E, rr_max, contact,
                                               nominal_fallback=_FOR_A_USER.get())
    warnings += [cusp_warning] if cusp_warning else []
    if rank >= len(layouts):
        raise _NoMoreLayouts(rank)
    lay = _tooth_cleared(spec, layouts[rank], sigma, E, rr_max, manufacturing, _replace(
        contact, min_flank_position_mm=0.0) if cusp_warning else contact)
    n, rc, rb, rr = lay.n, lay.rc, lay.rb, lay.rr
    if rb < lay.rb_req:
        need = (f"tip ball {rb:.3f} mm is below the {lay.rb_req:.3f} mm the peak load "
                f"{lay.load:.1f} N needs in bending at the neck and in Hertz contact (yield; "
                "a declared duty's contact fatigue)" if math.isfinite(lay.rb_req) else
                f"no tip ball carries the peak load {lay.load:.1f} N in Hertz contact on this "
                "flank (the flank radius at full deflection, r_c theta - r_b - w_gap, is too "
                "small for yield or a declared duty's contact fatigue, or leaves the contact "
                f"within the profile tolerances of the flank's cusp; the ball is {rb:.3f} mm)")
        warnings.append(
            f"{need}; torque cap at r_c = {rc:g} mm is "
            f"{fx.torque_cap_Nmm(rc, z, sigma) / NMM_PER_NM:.2f} N*m vs peak "
            f"{K * theta_d / NMM_PER_NM:.2f} N*m: expect higher stress at the tip neck")

    sizing, shape_warnings = shapes.size_flexure(spec.flexure, SizingContext(
        spec, lay, sigma, E, manufacturing, rr_max, balances))
    warnings += shape_warnings
    lay, rr, w0 = sizing.layout, sizing.layout.rr, sizing.record.root_width_mm

    t_rim = spec.outer_radius_mm - rr
    gap_root = 2 * math.pi * rr / n - w0
    if gap_root <= 2 * manufacturing.min_inside_radius_mm:
        raise DesignError(f"spring '{spec.name}': flexure roots ({w0:.3g} mm wide) leave "
                          f"{gap_root:.3g} mm between them at R_r = {rr:.3g} mm; the wire needs "
                          f"{2 * manufacturing.min_inside_radius_mm:.3g} mm")
    root_fillet = max(min(0.5 * t_rim, gap_root / 3.0), manufacturing.min_inside_radius_mm)
    neck_fillet = max(0.5 * rb, manufacturing.min_inside_radius_mm)

    design = SpringDesign(
        name=spec.name, spec=spec, material=material, manufacturing=manufacturing,
        hardware=hardware, n_flexures=n, contact_radius_mm=rc, root_radius_mm=rr,
        outer_radius_mm=spec.outer_radius_mm, thickness_mm=z, tip_radius_mm=rb,
        tip_radius_required_mm=lay.rb_req, shape=sizing.record, tip_load_N=lay.load,
        straight_limit_rad=lay.theta_s, min_neighbour_clearance_mm=sizing.clearance_mm,
        rim_thickness_mm=t_rim,
        root_fillet_radius_mm=root_fillet, neck_fillet_radius_mm=neck_fillet,
        torque_cap_Nmm=fx.torque_cap_Nmm(rc, z, sigma), stiffness_beam_Nmm_per_rad=float("nan"),
        peak_stress_MPa=float("nan"), warnings=tuple(warnings), stress_derating=derating,
        cam_min_tip_clearance_mm=spec.cam_min_tip_clearance_mm)
    # beam prediction of the generated centreline (Castigliano). The web kept at the tip
    # stiffens the ring (~0.1-0.3 % on the templates, far more on small soft disks): a
    # width factor brings beam theory back onto the target
    return onto_beam_stiffness(design, K)


# --------------------------------------------------------------------- stress-aware root
#: root flares the design chooses from (the range the stress model is calibrated on)
ROOT_FLARES = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3)
#: a flare must lower the predicted peak by more than this to be preferred to a smaller one
FLARE_GAIN = 0.005
#: design passes at lower beam stress before the stress correction gives up
STRESS_PASSES = 5


#: contact radii, as factors on a layout's own, tried for its flexure count when no flank
#: length leaves its cam tooth wide enough and clear of the ball at full deflection: 1 %
#: steps up to 30 % larger (the flank between ball and tooth tip grows as r_c theta^2)
TOOTH_RC_FACTORS = tuple(1.0 + 0.01 * k for k in range(1, 31))


def _tooth_cleared(spec: SpringSpec, lay: Layout, sigma: float, E: float, rr_max: float,
                   manufacturing: ManufacturingSpec, contact: ContactLimit) -> Layout:
    """``lay``, or, when its cam tooth cannot both keep ``min_web_mm`` at its tip and pass
    the ball at full deflection :data:`~springcad.design.cam.TIP_CLEARANCE_FACTOR` x the
    profile tolerances (or the contact FEA's floor, ``spec.cam_min_tip_clearance_mm``)
    away (:func:`~springcad.design.cam.tooth_can_clear`), the same
    flexure count at the smallest larger contact radius (:data:`TOOTH_RC_FACTORS`, within
    the layout search's range) whose tooth can. The layout ranking picks each N's contact
    radius for the longest straight reach; a few percent more leaves the flank room for
    the tooth (held-out g02: N 59 at r_c 11.36 mm kept a 2 um tooth-tip gap, at 11.8 mm
    it designs clean). A contact radius the user fixed is kept."""
    need_mm = tip_clearance_need_mm(manufacturing, spec.cam_min_tip_clearance_mm)

    def clears(candidate: Layout) -> bool:
        return tooth_can_clear(candidate.rc, candidate.rb, manufacturing.w_gap_mm, candidate.n,
                               spec.max_deflection_rad, manufacturing.min_web_mm, need_mm,
                               candidate.rr)

    if spec.contact_radius_mm is not None or clears(lay):
        return lay
    rc_max = CONTACT_SEARCH_FRACTION * spec.outer_radius_mm
    if spec.root_radius_mm is not None:
        rc_max = min(rc_max, spec.root_radius_mm)
    for factor in TOOTH_RC_FACTORS:
        rc = lay.rc * factor
        if rc > rc_max:
            break
        try:
            wider = layout_at(spec, sigma, E, lay.n, rc, rr_max, contact)
        except DesignError:
            continue
        if fits(spec, wider) and clears(wider):
            return wider
    return lay


def _with_flare(d: SpringDesign, flare: float) -> SpringDesign:
    """``d`` with a root flare, widths rescaled back onto its beam stiffness; no profiles."""
    target = d.beam_stiffness_Nmm_per_rad()
    c = _replace(d, root_flare=flare, root_flare_length_mm=2.0 * d.rim_thickness_mm if flare else 0.0)
    return _replace(onto_beam_stiffness(c, target), stiffness_beam_Nmm_per_rad=target)


def _choose_root(d: SpringDesign) -> SpringDesign:
    """The root flare with the lowest predicted peak, with its profiles built.

    Each flare of :data:`ROOT_FLARES` is rescaled to the same beam stiffness and its
    peak predicted by the FEA-calibrated model (:mod:`springcad.design.stress`); a
    larger flare must gain at least :data:`FLARE_GAIN`. Candidates whose profile
    breaks a wire-EDM rule (neighbour clearance, fillets) fall back to the next best.
    Deterministic; about 0.1 s per candidate.
    """
    scored = []
    for flare in ROOT_FLARES:
        c = _with_flare(d, flare)
        try:
            scored.append((stress.predict(c).peak_MPa, flare, c))
        except DesignError:
            continue
    if not scored:
        return with_width(d, 1.0, d.width_offset_mm)
    best = min(p for p, _, _ in scored)
    order = sorted(scored, key=lambda s: (s[0] > best * (1 + FLARE_GAIN), s[1] if s[0] <= best * (
        1 + FLARE_GAIN) else s[0]))
    error = None
    for _, _, c in order:
        try:
            return with_width(c, 1.0, c.width_offset_mm)
        except DesignError as err:
            error = err
    raise error


def _design_with_margin(spec: SpringSpec, material: MaterialSpec,
                        manufacturing: ManufacturingSpec, hardware: HardwareSpec,
                        rank: int, max_root_radius_mm: float = math.inf
                        ) -> tuple[SpringDesign | None, list, DesignError | None]:
    """One candidate layout through the stress passes.

    Returns:
        (design, history, error): the design, or None with the error that stopped it;
        ``history`` holds (derating, predicted peak MPa, region) of every pass.

    Raises:
        _NoMoreLayouts: ``rank`` is past the last candidate.
    """
    required = duty.required_margin(material, spec.max_deflection_rad)  # yield and the duty
    derating, history = 1.0, []
    d = None
    for _ in range(STRESS_PASSES):
        try:
            d = _choose_root(_design_at(spec, material, manufacturing, hardware, derating,
                                        rank=rank, max_root_radius_mm=max_root_radius_mm))
        except DesignError as err:
            return None, history, err
        history.append((derating, d.predicted_peak_stress_MPa, d.stress.region))
        if d.yield_margin >= required * (1.0 - 1e-3):
            break
        # the raisers scale with the beam stress: aim 0.5 % inside the margin
        derating *= d.yield_margin / required * 0.995
    else:
        d = _replace(d, warnings=d.warnings + (
            f"predicted peak {d.predicted_peak_stress_MPa:.0f} MPa ({d.stress.region}) leaves a "
            f"yield margin {d.yield_margin:.3f} < required {required:.3f} after {STRESS_PASSES} "
            "stress passes",))
    if d.peak_torque_Nmm > d.torque_cap_Nmm * (1 + 1e-3) and not any("tip ball" in w for w in d.warnings):
        d = _replace(d, warnings=d.warnings + (
            f"peak torque {d.peak_torque_Nmm / NMM_PER_NM:.2f} N*m exceeds the tip-ball torque cap "
            f"{d.torque_cap_Nmm / NMM_PER_NM:.2f} N*m at r_c = {d.contact_radius_mm:.3g} mm",))
    if derating < 1.0:
        d = _replace(d, warnings=d.warnings + (
            f"{STRESS_DERATED} from {material.design_stress_MPa:.0f} to {d.beam_stress_MPa:.0f} "
            f"MPa so the predicted peak ({d.predicted_peak_stress_MPa:.0f} MPa at the "
            f"{d.stress.region}) keeps the yield margin {required:g}",))
    return d, history, None
