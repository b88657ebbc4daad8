"""Layout of one spring: flexure count N, contact radius r_c, tip ball and root radius R_r.

The reference method's rules (``shared/notes/design-method.md``, eqs. 6-8) by exact
enumeration and bracketing, with springcad's deviation 1 (:mod:`springcad.design.spring`):
the tip ball is sized for the *peak* load at the target deflection, and a spec over the
torque cap pi r_c^2 z sigma / (6 sqrt 3) stops unless ``tip_radius_mm`` is fixed.

Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from springcad.config import SpringSpec
from springcad.config.consistency import CONTACT_SEARCH_FRACTION
from springcad.design import flexure as fx
from springcad.design.contact_fatigue import allowable_von_mises_MPa
from springcad.design.contact_stress import cusp_room_mm, tip_radius_window_mm
from springcad.design.numeric import find_root
from springcad.errors import DesignError, SpecInfeasible
from springcad.units import NMM_PER_NM

#: gap between flexure roots over rim thickness (reference rim rule, eq. 8)
RIM_GAP_RATIO = 1.5


def rim_root_radius(outer_radius_mm, n, contact_radius_mm, root_width_fn) -> float:
    """Solve R_o - R_r = (2 pi R_r / N - w0(R_r)) / 1.5 for R_r by bracketing (eq. 8)."""
    def f(rr):
        return (outer_radius_mm - rr
                - (2 * math.pi * rr / n - root_width_fn(rr - contact_radius_mm)) / RIM_GAP_RATIO)

    lo, hi = contact_radius_mm * (1 + 1e-6) + 1e-6, outer_radius_mm
    if f(lo) <= 0 or f(hi) >= 0:
        raise DesignError(
            f"{n} flexures do not fit between r_c = {contact_radius_mm:.3g} mm and "
            f"R_o = {outer_radius_mm:.3g} mm: the flexure roots are wider than the rim circle "
            "allows; use fewer flexures, a larger outer radius or a lower stiffness")
    return find_root(f, lo, hi, xtol=1e-10)


@dataclass(frozen=True)
class Layout:
    """One (N, r_c) layout: flexure count, contact radius (mm), tip ball and the radius the
    peak load needs (mm), root radius (mm), straight-flexure limit (rad), tip load (N)."""

    n: int
    rc: float
    rb: float
    rb_req: float
    rr: float
    theta_s: float
    load: float


@dataclass(frozen=True)
class ContactLimit:
    """What the tip ball's Hertz contact on the cam flank may reach at full deflection:
    Young's modulus (MPa), Poisson's ratio (-), the allowed von Mises stress, yield /
    required safety factor (MPa), the design gap w_gap between ball and flank (mm) and how
    far along the flank from its cusp the contact must lie, the profile tolerances
    t_spring + t_shaft (mm)."""

    youngs_modulus_MPa: float
    poisson_ratio: float
    allowable_MPa: float
    gap_mm: float = 0.0
    min_flank_position_mm: float = 0.0

    @classmethod
    def of(cls, material, theta_max_rad: float | None = None,
           manufacturing=None) -> "ContactLimit":
        """The limit of a :class:`~springcad.config.MaterialSpec`: yield / safety factor,
        and with ``theta_max_rad`` the contact fatigue of a declared duty too
        (:func:`springcad.design.contact_fatigue.allowable_von_mises_MPa`); the gap and the
        tolerances from a :class:`~springcad.config.ManufacturingSpec`."""
        m = material.material
        allowed = m.yield_strength_MPa / material.safety_factor
        if theta_max_rad is not None:
            allowed = min(allowed, allowable_von_mises_MPa(material, theta_max_rad))
        if manufacturing is None:
            return cls(m.youngs_modulus_MPa, m.poisson_ratio, allowed)
        return cls(m.youngs_modulus_MPa, m.poisson_ratio, allowed, manufacturing.w_gap_mm,
                   manufacturing.t_spring_mm + manufacturing.t_shaft_mm)

    def max_load_N(self, contact_radius_mm: float, deflection_rad: float,
                   thickness_mm: float) -> float:
        """The largest tip load some ball carries in contact at full deflection (N; 0 when
        the flank leaves no room for a ball): bisection on :meth:`ball_window_mm`."""
        def carried(load: float) -> bool:
            lo, hi = self.ball_window_mm(load, contact_radius_mm, deflection_rad, thickness_mm)
            return lo <= hi

        lo, hi = 0.0, 1.0
        if not carried(1e-9):
            return 0.0
        while carried(hi) and hi < 1e9:
            lo, hi = hi, 2.0 * hi
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if carried(mid) else (lo, mid)
        return lo

    def ball_window_mm(self, load_N: float, contact_radius_mm: float, deflection_rad: float,
                       thickness_mm: float) -> tuple[float, float]:
        """(smallest, largest) tip ball radius whose contact holds at full deflection (mm;
        :func:`springcad.design.contact_stress.tip_radius_window_mm`)."""
        return tip_radius_window_mm(load_N, contact_radius_mm, self.gap_mm, deflection_rad,
                                    thickness_mm, self.youngs_modulus_MPa, self.poisson_ratio,
                                    self.allowable_MPa, self.min_flank_position_mm)


def tip_ball(spec: SpringSpec, sigma, n, rc, contact: ContactLimit | None = None):
    """(tip load N, required ball radius mm, ball radius mm) at beam stress ``sigma`` (MPa).

    The ball carries the peak tip load in bending at the neck (eq. 5) and, with
    ``contact``, in Hertz contact on the cam flank at full deflection, whose radius there
    is r_c theta_max - r_b - w_gap (:func:`~springcad.design.contact_stress.
    flank_radius_at_contact_mm`): the ball must lie in the window of radii that contact
    allows. Required radius ``inf``: no ball is enough in contact, or the smallest ball
    bending needs lies beyond the window (a fixed ``tip_radius_mm`` outside the window
    too); then the free ball is ``inf`` as well.
    """
    load = fx.tip_load_N(spec.target_stiffness_Nmm_per_rad, spec.max_deflection_rad, n, rc)
    rb_req = fx.tip_ball_required_radius_mm(load, spec.thickness_mm, sigma)
    largest = math.inf
    if contact is not None:
        lo, largest = contact.ball_window_mm(load, rc, spec.max_deflection_rad,
                                             spec.thickness_mm)
        rb_req = max(rb_req, lo)
    if spec.tip_radius_mm is not None:
        rb = spec.tip_radius_mm
        return load, (rb_req if rb <= largest * (1 + 1e-9) else math.inf), rb
    rb = max(spec.min_tip_radius_mm, rb_req)
    if rb > largest * (1 + 1e-9):
        return load, math.inf, math.inf
    return load, rb_req, rb


def _contact_shortfall(contact: ContactLimit, spec: SpringSpec, rc: float) -> str:
    """Why no tip ball carries its load in contact at ``rc`` (text): the flank that full
    deflection leaves is too short for the profile tolerances, or too tight for the load."""
    theta, reach = spec.max_deflection_rad, rc * spec.max_deflection_rad - contact.gap_mm
    cusp = cusp_room_mm(rc, contact.min_flank_position_mm)
    if reach - cusp < spec.min_tip_radius_mm:
        return (f" (the flank full deflection leaves, r_c theta - w_gap = {reach:.3g} mm, holds "
                f"no ball of at least {spec.min_tip_radius_mm:g} mm whose contact stays "
                f"sqrt(2 r_c (t_spring + t_shaft)) = {cusp:.3g} mm from the flank's cusp, where "
                "toleranced parts can meet: the flank grows as r_c theta, the cusp room as "
                "sqrt(r_c): a larger contact radius or deflection, or tighter tolerances)")
    most = contact.max_load_N(rc, theta, spec.thickness_mm)
    return (f" (at most {most:.3g} N on the flank radius r_c theta - w_gap = {reach:.3g} mm "
            f"that full deflection leaves, within the contact von Mises "
            f"{contact.allowable_MPa:.0f} MPa; the load falls as 1/(N r_c) and the flank grows "
            "with r_c theta)")


def layout_at(spec: SpringSpec, sigma, E, n, rc, max_root_radius_mm: float = math.inf,
              contact: ContactLimit | None = None) -> Layout:
    """Tip ball, root radius (rim rule unless given) and straight limit for (N, r_c).

    ``max_root_radius_mm``: the largest root radius the rim allows (its holes, web and
    fillets need R_o - R_r; :func:`springcad.config.consistency.min_rim_mm`); the rim
    rule's root radius is lowered to it when it would leave a thinner rim. ``contact``:
    the ball is sized for Hertz contact too (:func:`tip_ball`).

    Raises:
        DesignError: the rim rule has no root, or no ball carries the contact.
    """
    return _layout_with_ball(spec, sigma, E, n, rc, tip_ball(spec, sigma, n, rc, contact),
                             max_root_radius_mm, contact)


def _layout_with_ball(spec: SpringSpec, sigma, E, n, rc, ball, max_root_radius_mm: float,
                      contact: ContactLimit | None) -> Layout:
    """:func:`layout_at` with the :func:`tip_ball` of (N, r_c) already at hand (``ball``)."""
    load, rb_req, rb = ball
    if not math.isfinite(rb):
        why = "" if contact is None else _contact_shortfall(contact, spec, rc)
        raise DesignError(f"spring '{spec.name}': no tip ball carries the {load:.3g} N contact "
                          f"load at r_c = {rc:.3g} mm{why}")
    z = spec.thickness_mm
    if spec.root_radius_mm is not None:
        rr = spec.root_radius_mm
    else:
        rr = min(max_root_radius_mm,
                 rim_root_radius(spec.outer_radius_mm, n, rc,
                                 lambda L: math.sqrt(6 * load * L / (z * sigma))))
    if rr <= rc:  # a fixed root radius too (held-out B 5507 029: r_c reached it, L = 0)
        what = "rim" if spec.root_radius_mm is None else f"root_radius_mm = {rr:g}"
        raise DesignError(f"spring '{spec.name}': the {what} leaves no room for flexures "
                          f"beyond r_c = {rc:.3g} mm")
    theta_s = fx.straight_limit_rad(n, z, sigma, rr - rc, E, spec.target_stiffness_Nmm_per_rad, rc)
    return Layout(n, rc, rb, rb_req, rr, theta_s, load)


def fits(spec: SpringSpec, lay: Layout) -> bool:
    """Whether N balls and equal cam teeth fit around the contact circle (eq. 6)."""
    return lay.n <= fx.max_flexures(lay.rb, lay.rc)


#: layouts the design search tries, best first, before it gives up on a spec
MAX_CANDIDATES = 12


def candidate_layouts(spec: SpringSpec, sigma, E, limit: int = MAX_CANDIDATES,
                      max_root_radius_mm: float = math.inf,
                      contact: ContactLimit | None = None) -> list[Layout]:
    """Every distinct flexure count N that fits, each at its best contact radius, best first.

    The free parameters are searched by exact enumeration (eqs. 6-7): for each N the
    contact radius r_c that maximises the straight-flexure limit on a 60-point grid
    (or the fixed ``contact_radius_mm``), the tip ball sized for the peak load (or the
    fixed ``tip_radius_mm``), the root radius by the rim rule (or the fixed
    ``root_radius_mm``), at most ``max_root_radius_mm`` so the rim keeps room for its
    holes (:func:`layout_at`), the ball sized for its Hertz contact as well as bending
    with ``contact``. Layouts are ranked by their straight limit (the deflection
    reachable without serpentine), so the first is the reference method's choice and
    the later ones are what a designer tries when a later rule (cam tooth, fillets,
    rim holes, serpentine reach) rejects it. A fixed ``tip_radius_mm`` with r_c free: the
    layouts whose load that ball carries come first. Deterministic.

    Raises:
        DesignError: no (N, r_c) fits at all (names the binding limit and what to change).
    """
    z = spec.thickness_mm
    cap = fx.torque_cap_Nmm
    peak = spec.target_stiffness_Nmm_per_rad * spec.max_deflection_rad
    ro = spec.outer_radius_mm

    def cap_error(rc):
        return SpecInfeasible(
            f"spring '{spec.name}': peak torque {peak / NMM_PER_NM:.3g} N*m exceeds the torque cap "
            f"{cap(rc, z, sigma) / NMM_PER_NM:.3g} N*m of tip balls sized for the peak load at "
            f"contact radius {rc:.3g} mm (cap = pi r_c^2 z sigma / (6 sqrt 3)); raise "
            f"contact_radius_mm to at least {float(fx.min_contact_radius_mm(peak, z, sigma)):.3g} "
            f"mm or thickness_mm to at least {z * peak / cap(rc, z, sigma):.3g} mm (the cap "
            "alone), lower the deflection, or fix tip_radius_mm to accept an undersized ball")

    if spec.contact_radius_mm is not None:
        rc = spec.contact_radius_mm
        if spec.tip_radius_mm is None and peak > cap(rc, z, sigma):
            raise cap_error(rc)
        radii = [rc]
    else:
        rc_min = max(ro / 30, fx.min_contact_radius_mm(peak, z, sigma) * 1.001
                     if spec.tip_radius_mm is None else ro / 30)
        rc_max = CONTACT_SEARCH_FRACTION * ro if spec.root_radius_mm is None else min(
            CONTACT_SEARCH_FRACTION * ro, spec.root_radius_mm)  # a fixed root: r_c below it
        if rc_min >= rc_max:
            raise cap_error(rc_max)
        radii = [float(r) for r in np.linspace(rc_min, rc_max, 60)]
    if spec.n_flexures is not None:
        ns = [spec.n_flexures]
    elif spec.tip_radius_mm is not None and spec.contact_radius_mm is not None:
        # the ball and r_c fixed: eq. 6's most flexures first, then fewer (N is still free:
        # fewer, wider-spaced flexures leave a serpentine the room to reach a deflection)
        ns = range(fx.max_flexures(spec.tip_radius_mm, spec.contact_radius_mm), 2, -1)
    else:
        ns = range(3, 200)
    best: dict[int, Layout] = {}
    reaches, fitting = _screen(spec, sigma, E, ns, max_root_radius_mm, contact)(np.array(radii))
    for rc, reach, may_fit in zip(radii, reaches, fitting):
        for i, n in enumerate(ns):
            if not may_fit[i] or (n in best and reach[i] < best[n].theta_s):
                continue  # the balls cannot fit, or it cannot beat the best at this N
            ball = tip_ball(spec, sigma, n, rc, contact)
            rb = ball[2]
            if not math.isfinite(rb) or n > fx.max_flexures(rb, rc):
                continue  # the balls do not fit (as fits() below), no rim rule to solve
            try:
                lay = _layout_with_ball(spec, sigma, E, n, rc, ball, max_root_radius_mm, contact)
            except DesignError:
                continue
            if fits(spec, lay) and (n not in best or lay.theta_s > best[n].theta_s):
                best[n] = lay
    if not best:
        if spec.contact_radius_mm is not None and spec.n_flexures is not None:
            lay = layout_at(spec, sigma, E, spec.n_flexures, spec.contact_radius_mm,
                            max_root_radius_mm, contact)  # raises when contact sizes no ball
            raise SpecInfeasible(
                f"spring '{spec.name}': n_flexures = {spec.n_flexures} do not fit: tip balls of "
                f"radius {lay.rb:.3g} mm and equal cam teeth leave room for at most "
                f"{fx.max_flexures(lay.rb, lay.rc)} flexures at contact radius {lay.rc:.3g} mm")
        if spec.tip_radius_mm is None and peak > cap(radii[-1], z, sigma):
            raise cap_error(radii[-1])
        try:  # what stops the widest contact radius with the most flexures (the least load)
            layout_at(spec, sigma, E, max(ns), radii[-1], max_root_radius_mm, contact)
            at_widest = ""
        except DesignError as err:
            at_widest = f" (at r_c = {radii[-1]:.3g} mm: {str(err).split(': ', 1)[-1]})"
        raise SpecInfeasible(
            f"spring '{spec.name}': no layout fits: for contact radii {radii[0]:.3g} to "
            f"{radii[-1]:.3g} mm and N = {ns[0]}{'' if len(ns) == 1 else f' to {ns[-1]}'} the tip "
            f"balls (sized for the peak torque {peak / NMM_PER_NM:.3g} N*m in bending and in "
            f"contact) or the flexure roots do not fit in R_o = {ro:.3g} mm; use a larger outer "
            f"radius, a thicker disk or a lower stiffness, or fewer n_flexures{at_widest}")
    if spec.contact_radius_mm is not None:  # r_c fixed: the most flexures first (eq. 6)
        ranked = sorted(best.values(), key=lambda lay: -lay.n)
    else:  # r_c free: the longest straight reach first (eq. 7); a fixed tip ball: the
        # layouts it is large enough for (bending and contact) before those it is not
        ranked = sorted(best.values(), key=lambda lay: (lay.rb < lay.rb_req * (1 - 1e-9),
                                                        -lay.theta_s, lay.n))
    return _spread(ranked, limit)


def toleranced_layouts(spec: SpringSpec, sigma, E, max_root_radius_mm: float,
                       contact: ContactLimit, nominal_fallback: bool = True
                       ) -> tuple[list[Layout], str]:
    """:func:`candidate_layouts` with ``contact``; when only the profile tolerances' cusp
    room stops every layout, the layouts for nominal parts with a warning (text) that names
    the tolerances that would keep the contact off the cusp, else "".

    The cusp room sqrt(2 r_c (t_spring + t_shaft)) is a tolerance rule, not a rule of the
    spring: a spring whose ball meets it only for nominal parts is made, and the release
    gate's worst-case clearances at full deflection stop its release (NOT FOR MANUFACTURE,
    with the tolerances that release it) instead of the design refusing the spec.
    ``nominal_fallback`` False (a search for releasable springs only): the refusal stands.

    Raises:
        DesignError: no layout fits even for nominal parts (the toleranced refusal).
    """
    try:
        return candidate_layouts(spec, sigma, E, max_root_radius_mm=max_root_radius_mm,
                                 contact=contact), ""
    except DesignError as toleranced:
        if contact.min_flank_position_mm <= 0 or not nominal_fallback:
            raise
        try:
            layouts = candidate_layouts(spec, sigma, E, max_root_radius_mm=max_root_radius_mm,
                                        contact=replace(contact, min_flank_position_mm=0.0))
        except DesignError:
            raise toleranced from None
    lay = layouts[0]
    theta, stack = spec.max_deflection_rad, contact.min_flank_position_mm
    room = lay.rc * theta - contact.gap_mm - lay.rb
    s_max = max(room, 0.0) ** 2 / (2.0 * lay.rc)

    def spare_mm(rc: float) -> float:  # the flank beyond the ball less the cusp room
        return rc * theta - contact.gap_mm - lay.rb - cusp_room_mm(rc, stack)

    rc_max = CONTACT_SEARCH_FRACTION * spec.outer_radius_mm
    wider = ""
    if spare_mm(rc_max) > 0:  # the contact radius at which the flank leaves the room
        rc_need = find_root(spare_mm, lay.rc, rc_max, xtol=1e-4) if spare_mm(lay.rc) < 0 \
            else lay.rc
        wider = (f", or with springs.{spec.name}.contact_radius_mm >= {math.ceil(rc_need * 10) / 10:g} "
                 f"mm (the flank then leaves that room; now {lay.rc:.3g} mm)")
    return layouts, (
        f"the tip ball's contact at full deflection stays off the cam flank's cusp only for "
        f"nominal parts: the profile tolerances t_spring_mm + t_shaft_mm = "
        f"{contact.min_flank_position_mm:.3g} mm need sqrt(2 r_c (t_spring + t_shaft)) = "
        f"{cusp_room_mm(lay.rc, contact.min_flank_position_mm):.3g} mm of flank beyond "
        f"the ball, the flank r_c theta - w_gap - r_b leaves {room:.3g} mm at r_c = "
        f"{lay.rc:.3g} mm: not for manufacture unless t_spring_mm + t_shaft_mm <= "
        f"{s_max:.3g} mm{wider}")


#: relative slack of :func:`_screen`'s contact bound: far beyond the rounding of its
#: array arithmetic (1e-15), far below a change of the window that matters
SCREEN_SLACK = 1e-6


def _screen(spec: SpringSpec, sigma, E, ns, max_root_radius_mm: float,
            contact: ContactLimit | None = None):
    """``screen(r_c)``: for the flexure counts ``ns``, (a straight limit no layout at (N, r_c)
    exceeds (rad), whether N balls may fit around r_c), so :func:`candidate_layouts`
    passes over the pairs that cannot be chosen without sizing their balls and rims.
    ``r_c`` a float: arrays over ``ns``; an array of radii: one row per radius (all the
    radii of the enumeration in one evaluation).

    :func:`~springcad.design.flexure.straight_limit_rad` grows with the flexure length
    R_r - r_c, and :func:`layout_at` never puts R_r beyond the fixed ``root_radius_mm``, nor
    else beyond R_o, ``max_root_radius_mm`` or the rim rule's bound
    (:func:`_rim_root_bound_mm`; no bound where that length is not positive).
    :func:`tip_ball` never gives a ball smaller than the fixed ``tip_radius_mm``, nor else
    than ``min_tip_radius_mm`` and the radius bending needs, and fewer balls fit as they
    grow (:func:`~springcad.design.flexure.max_flexures`). Both bounds are widened by 1e-9
    against rounding: a pair screened out fails the exact rules.

    With ``contact`` (a free ball), the ball's Hertz window of :func:`tip_ball` for all N at
    once, on arrays, with the allowed stress raised by :data:`SCREEN_SLACK` (a wider
    window: smaller least ball, larger largest) and the least ball lowered and the
    largest raised by the same slack: a pair this bound finds with no ball, or with balls
    too large to fit, has none in :func:`tip_ball`'s exact scalar arithmetic either. The
    design search screened out most (N, r_c) pairs this way: 42k scalar windows on the
    default job before, ~10k after.
    """
    z, K, theta = spec.thickness_mm, spec.target_stiffness_Nmm_per_rad, spec.max_deflection_rad
    ro = spec.outer_radius_mm
    rr = spec.root_radius_mm if spec.root_radius_mm is not None else min(max_root_radius_mm, ro)
    n = np.asarray(list(ns), float)

    def screen(rc) -> tuple[np.ndarray, np.ndarray]:
        rc = np.asarray(rc, float)[..., None]  # radii down, flexure counts across
        length = rr - rc
        if spec.root_radius_mm is None:  # the rim rule's root, at most its bound below
            length = np.minimum(length, _rim_root_bound_mm(
                ro, n, rc, fx.tip_load_N(K, theta, n, rc), z, sigma) - rc)
        with np.errstate(invalid="ignore"):
            reach = np.where(length > 0, fx.straight_limit_rad(
                n, z, sigma, np.maximum(length, 0.0), E, K, rc) * (1.0 + 1e-9), np.inf)
        if spec.tip_radius_mm is not None:
            rb = np.full(reach.shape, spec.tip_radius_mm)
        else:
            load = fx.tip_load_N(K, theta, n, rc)
            rb = np.maximum(spec.min_tip_radius_mm, fx.tip_ball_required_radius_mm(load, z, sigma))
        carried = True
        if contact is not None and spec.tip_radius_mm is None:
            lo, hi = tip_radius_window_mm(
                load, rc, contact.gap_mm, theta, z, contact.youngs_modulus_MPa,
                contact.poisson_ratio, contact.allowable_MPa * (1.0 + SCREEN_SLACK),
                contact.min_flank_position_mm)
            rb = np.maximum(rb * (1.0 - SCREEN_SLACK), lo * (1.0 - SCREEN_SLACK))
            with np.errstate(invalid="ignore"):  # inf balls: carried is False there
                carried = rb <= hi * (1.0 + SCREEN_SLACK)
        with np.errstate(invalid="ignore"):
            may_fit = carried & (n <= np.pi * np.hypot(rb, rc) / (2.0 * rb) * (1.0 + 1e-9))
        return reach, may_fit
    return screen


def _rim_root_bound_mm(outer_radius_mm, n, contact_radius_mm, load_N, thickness_mm, sigma):
    """A root radius the rim rule of :func:`rim_root_radius` never exceeds (mm; arrays).

    Its root R_r solves R_o - R_r = (2 pi R_r / N - w0(R_r - r_c)) / 1.5 with w0 rising, so
    w0(R_r - r_c) <= w0(R_o - r_c) gives R_r <= (R_o + w0(R_o - r_c) / 1.5) / (1 + 2 pi /
    (1.5 N)); raised by 1e-6 mm for the root's own tolerance (1e-10 mm) and rounding.
    """
    w_most = np.sqrt(6.0 * load_N * np.maximum(outer_radius_mm - contact_radius_mm, 0.0)
                     / (thickness_mm * sigma))
    return ((outer_radius_mm + w_most / RIM_GAP_RATIO)
            / (1.0 + 2.0 * np.pi / (RIM_GAP_RATIO * n)) + 1e-6)


#: later candidates differ from every earlier one by at least this factor in N, so that
#: the search reaches the few long flexures a large deflection needs as well as the many
#: short ones the straight reach prefers
N_SPREAD = 1.15


def _spread(ranked: list[Layout], limit: int) -> list[Layout]:
    """The first ``limit`` layouts, best first, N spread out: a layout whose N lies within
    :data:`N_SPREAD` of an already chosen one waits until the spread ones are taken; the
    waiting ones then come farthest in N (ratio) from those chosen first, ties by rank, so
    that a rule binding at one end of N (flexures too close to their neighbours at the
    most flexures, a fixed contact radius's order) still leaves the other end tried
    (held-out A 7311 g14: r_c fixed at 17.5 mm, N 69 to 91 fit, the spread took 91 and
    79 and the rank order then 90 to 81, all too close to their neighbours; 70 to 74
    design)."""
    chosen: list[Layout] = []
    for lay in ranked:
        if len(chosen) < limit and all(max(lay.n / c.n, c.n / lay.n) >= N_SPREAD for c in chosen):
            chosen.append(lay)
    waiting = [lay for lay in ranked if lay not in chosen]
    while waiting and len(chosen) < limit:
        def distance(lay: Layout) -> float:
            return min(abs(math.log(lay.n / c.n)) for c in chosen) if chosen else 0.0
        far = max(distance(lay) for lay in waiting)
        nxt = next(lay for lay in waiting if distance(lay) >= far - 1e-12)
        chosen.append(nxt)
        waiting.remove(nxt)
    return chosen


def choose_layout(spec: SpringSpec, sigma, E, max_root_radius_mm: float = math.inf) -> Layout:
    """The reference method's layout: the first of :func:`candidate_layouts`."""
    return candidate_layouts(spec, sigma, E, 1, max_root_radius_mm)[0]
