"""Strength of the rim pins (ISO 8734 dowels or ISO 4762 screws) that carry a stack's
torque from one rim to the next.

Springs joined rim to rim pass the whole stack torque through the pins of that joint
(springs in series carry one torque). At the stack's largest deflection the torque is
``T = K_stack * theta_max`` (the eq. 10 limit). ``n`` pins on a circle of radius ``R``
carry ``F = k_share * T / (n R)`` each, ``k_share`` = :data:`UNEVEN_SHARE` (the pins sit
with different clearances in their holes; the retaining compound takes most of that
up, not all). Each pin spans the gap ``g`` between the rims (the rim spacer) held in
both rims, so it is sheared and bent: a beam guided at both ends, moment ``F g / 2``:

* shear ``tau = F / A`` on the pin section ``A`` (a screw: its thread's minor
  diameter ``d3 = d - 1.22687 P``, ISO 724; it may be threaded across the gap),
* bending ``sigma = 16 F g / (pi d^3)``,
* equivalent ``sqrt(sigma^2 + 3 tau^2) <= sqrt(3) tau_u / S`` with the pin's shear
  strength ``tau_u`` and ``S`` = :data:`PIN_SAFETY_FACTOR`,
* bearing of the pin on each rim's hole wall over its engagement ``e``:
  ``p = F / (d e) <= yield_rim / S``.

A joint that fails is refused (:class:`~springcad.errors.DesignError`) with the pins
it would need: how many at this diameter, or which diameter at this count. Units: mm,
N, N*mm, MPa.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from springcad.design import plans as pl
from springcad.design.catalogue import bolt_set, dowel_lengths
from springcad.design.hardware import FLANGE_THICKNESS_MM
from springcad.errors import DesignError, RemedyError, change_text
from springcad.units import NMM_PER_NM

#: shear strength of a hardened ISO 8734 dowel (MPa): ASME B18.8.5M (the metric hardened
#: ground dowel pins, ISO 8734's series) lists single shear strengths 7.4 kN at Ø3,
#: 13.2 kN at Ø4, 29.7 kN at Ø6: 1047-1050 MPa on the pin section
DOWEL_SHEAR_STRENGTH_MPA = 1047.0
#: shear strength of an ISO 4762 socket head screw, property class 12.9 (MPa): ISO 898-1
#: R_m >= 1220 MPa, shear 0.6 R_m (the usual ratio for quenched and tempered steel)
SCREW_SHEAR_STRENGTH_MPA = 0.6 * 1220.0
#: safety factor on the pin's shear strength and on the rims' yield in bearing; with it
#: the pin's allowable shear tau_u / 2 = 523 MPa is also the classical fully reversed
#: shear endurance 0.5 R_m / sqrt(3) for R_m = sqrt(3) tau_u (no size or surface factor)
PIN_SAFETY_FACTOR = 2.0
#: the most loaded pin carries this x the mean pin load (springcad's allowance for pins
#: with different clearances, E7/m6 0.006-0.022 mm; not a standard's value)
UNEVEN_SHARE = 1.5
#: ISO 724 minor diameter of an external thread: d3 = d - this x pitch
MINOR_DIAMETER_PER_PITCH = 1.22687


@dataclass(frozen=True)
class PinJointStrength:
    """How the pins of one rim-to-rim joint carry the stack torque.

    Attributes:
        name: the fastener component (e.g. ``dowels_1``).
        kind: "dowel" or "bolt".
        count: pins in the joint.
        diameter_mm: pin (screw) diameter.
        radius_mm: pin circle radius.
        gap_mm: free length of the pin between the two rims (the spacer).
        engagement_mm: the least length a pin bears on in one rim.
        torque_Nmm: stack torque at the largest deflection.
        force_N: load on the most loaded pin.
        shear_MPa, bending_MPa, equivalent_MPa: the pin's stresses.
        allowable_MPa: the pin's allowable equivalent stress.
        bearing_MPa, bearing_allowable_MPa: pressure on the rims' hole walls and its limit.
    """

    name: str
    kind: str
    count: int
    diameter_mm: float
    radius_mm: float
    gap_mm: float
    engagement_mm: float
    torque_Nmm: float
    force_N: float
    shear_MPa: float
    bending_MPa: float
    equivalent_MPa: float
    allowable_MPa: float
    bearing_MPa: float
    bearing_allowable_MPa: float

    @property
    def utilisation(self) -> float:
        """Largest of stress / allowable over the pin and the bearing (ok <= 1)."""
        return max(self.equivalent_MPa / self.allowable_MPa,
                   self.bearing_MPa / self.bearing_allowable_MPa)

    @property
    def ok(self) -> bool:
        return self.utilisation <= 1.0 + 1e-9

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__} | {
            "utilisation": self.utilisation, "ok": self.ok}


def _section(kind: str, diameter_mm: float) -> tuple[float, float]:
    """(shear diameter mm, shear strength MPa) of a dowel or a screw."""
    if kind == "dowel":
        return diameter_mm, DOWEL_SHEAR_STRENGTH_MPA
    pitch = float(re.search(r"-([\d.]+)$", bolt_set(diameter_mm).size).group(1))
    return diameter_mm - MINOR_DIAMETER_PER_PITCH * pitch, SCREW_SHEAR_STRENGTH_MPA


def pin_strength(name: str, kind: str, count: int, diameter_mm: float, radius_mm: float,
                 gap_mm: float, engagement_mm: float, torque_Nmm: float,
                 rim_yield_MPa: float) -> PinJointStrength:
    """Stresses of the most loaded pin of a joint (see the module text)."""
    force = UNEVEN_SHARE * torque_Nmm / (count * radius_mm)
    d_s, tau_u = _section(kind, diameter_mm)
    shear = force / (math.pi * d_s ** 2 / 4.0)
    bending = 16.0 * force * gap_mm / (math.pi * d_s ** 3)
    return PinJointStrength(
        name=name, kind=kind, count=count, diameter_mm=diameter_mm, radius_mm=radius_mm,
        gap_mm=gap_mm, engagement_mm=engagement_mm, torque_Nmm=torque_Nmm, force_N=force,
        shear_MPa=shear, bending_MPa=bending,
        equivalent_MPa=math.hypot(bending, math.sqrt(3.0) * shear),
        allowable_MPa=math.sqrt(3.0) * tau_u / PIN_SAFETY_FACTOR,
        bearing_MPa=force / (diameter_mm * engagement_mm),
        bearing_allowable_MPa=rim_yield_MPa / PIN_SAFETY_FACTOR)


def _joint_inputs(stack, comp) -> dict:
    """Geometry of one fastener component of a designed stack (mm, N*mm, MPa): the two
    plates it joins (two rims, or a rim flange and its ring: joint -1 / n - 1), the gap
    between them and the pin's engagement, the shorter of its lengths inside each."""
    plan = comp.plan
    springs, z = stack.springs, stack.layout.spring_z_mm
    j, n = plan.joint, len(springs)
    if 0 <= j < n - 1:
        a, b = springs[j], springs[j + 1]
        plates = ((z[j], z[j] + a.thickness_mm), (z[j + 1], z[j + 1] + b.thickness_mm))
    else:  # a rim flange on the first (j = -1) or the last spring, face to face
        a = b = springs[0 if j < 0 else -1]
        ring = (z[0], z[0] + a.thickness_mm) if j < 0 else (z[-1], z[-1] + a.thickness_mm)
        flange = ((ring[0] - FLANGE_THICKNESS_MM, ring[0]) if j < 0
                  else (ring[1], ring[1] + FLANGE_THICKNESS_MM))
        plates = (flange, ring) if j < 0 else (ring, flange)
    pin = (comp.z_mm, comp.z_mm + comp.length_mm)
    engagement = min(min(pin[1], hi) - max(pin[0], lo) for lo, hi in plates)
    return dict(name=comp.name, kind=plan.type, count=len(plan.hole_centres_mm),
                diameter_mm=plan.diameter_mm, radius_mm=plan.hole_circle_radius_mm,
                gap_mm=plates[1][0] - plates[0][1], engagement_mm=engagement,
                torque_Nmm=stack.stiffness_Nmm_per_rad * stack.max_deflection_rad,
                rim_yield_MPa=min(s.material.material.yield_strength_MPa for s in (a, b)))


def stack_pin_strengths(stack) -> tuple[PinJointStrength, ...]:
    """The pins of every rim-to-rim joint of a designed stack
    (:class:`~springcad.design.stack.StackDesign`)."""
    return tuple(pin_strength(**_joint_inputs(stack, c)) for c in stack.components
                 if isinstance(c.plan, pl.FastenerPlan) and c.plan.hole_centres_mm)


#: ISO 262 coarse thread sizes tried for a screw (mm); those bd_warehouse's ISO 4762 table holds
SCREW_SIZES_MM = (1.6, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0)


def _diameters(kind: str) -> list[float]:
    """Catalogue diameters of a rim pin of this kind (mm)."""
    if kind == "dowel":
        return sorted(dowel_lengths())
    out = []
    for d in SCREW_SIZES_MM:
        try:
            bolt_set(d)
        except DesignError:
            continue
        out.append(d)
    return out


#: a remedy that needs more than this many times the pins lists a larger size first
MAX_COUNT_GROWTH = 1.5


def remedies(s: PinJointStrength, inputs: dict, max_count: int) -> list[tuple[dict, str]]:
    """The pins that would hold, most likely first: (hardware changes, text) for more of
    them at this diameter and for the larger catalogue diameters at this count (the first
    two that hold). A few more pins come first; many more (over :data:`MAX_COUNT_GROWTH`
    times) crowd the rim (their holes take the room the flexure roots and the rim web need),
    so the larger sizes come first then."""
    need = math.ceil(s.count * s.utilisation - 1e-9)
    count, diameter = "hardware.fastener_count", "hardware.fastener_diameter_mm"
    more = ([({count: need}, change_text(count, need, s.count, f"Ø{s.diameter_mm:g} "
                                          f"{s.kind}s"))] if need <= max_count else [])
    larger = [({diameter: d}, change_text(diameter, d, s.diameter_mm, f"{s.count} {s.kind}s"))
              for d in _diameters(s.kind)
              if d > s.diameter_mm and pin_strength(**{**inputs, "diameter_mm": d}).ok][:2]
    return more + larger if need <= MAX_COUNT_GROWTH * s.count else larger + more


class PinStrengthError(RemedyError):
    """A rim joint's pins are over their allowable stress: ``remedies`` holds the
    (config changes, text) that would hold (:func:`remedies`), ``head`` the stresses,
    ``lower_torque`` (the ``fallback``) the stack torque these pins carry (text)."""

    def __init__(self, head: str, options: list[tuple[dict, str]], lower_torque: str):
        self.lower_torque = lower_torque
        super().__init__(head, options, lower_torque)


def check_pin_strength(stack) -> tuple[PinJointStrength, ...]:
    """Every rim-to-rim joint's pins, checked.

    Raises:
        PinStrengthError: a joint's pins or the rims' hole walls are over their
            allowable stress; names the stresses and the pins that would hold.
    """
    out = []
    for c in stack.components:
        if not (isinstance(c.plan, pl.FastenerPlan) and c.plan.hole_centres_mm):
            continue
        inputs = _joint_inputs(stack, c)
        s = pin_strength(**inputs)
        out.append(s)
        if s.ok:
            continue
        j = c.plan.joint
        max_count = min(sp.n_flexures for sp in stack.springs[max(j, 0):max(j, 0) + 2])
        raise PinStrengthError(
            f"{s.name}: {s.count} x Ø{s.diameter_mm:g} {s.kind}s on R{s.radius_mm:.2f} carry "
            f"{s.torque_Nmm / NMM_PER_NM:.3g} N*m at the stack's largest deflection: "
            f"{s.force_N:.0f} N on the most loaded pin (x{UNEVEN_SHARE:g} the mean), shear "
            f"{s.shear_MPa:.0f} MPa and bending {s.bending_MPa:.0f} MPa over the {s.gap_mm:g} mm "
            f"gap, equivalent {s.equivalent_MPa:.0f} MPa against {s.allowable_MPa:.0f} "
            f"(shear strength / {PIN_SAFETY_FACTOR:g}); bearing {s.bearing_MPa:.0f} MPa on "
            f"{s.engagement_mm:.3g} mm of rim against {s.bearing_allowable_MPa:.0f} (yield / "
            f"{PIN_SAFETY_FACTOR:g})", remedies(s, inputs, max_count),
            f"a stack torque of at most {s.torque_Nmm / s.utilisation / NMM_PER_NM:.3g} N*m "
            f"(stiffness x max deflection, now {s.torque_Nmm / NMM_PER_NM:.3g})")
    return tuple(out)
