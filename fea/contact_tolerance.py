"""The contact at +-theta_max with the profile tolerances: ball stress and every clearance.

At each end of the contact sweep (:func:`fea.contact.contact_sweep`) two things
can stop a spring from being made as drawn:

Contact stress
    The tip ball bears on the cam flank as a Hertz line contact
    (:mod:`springcad.design.contact_stress`; force and flank curvature from the
    sweep). Its subsurface von Mises maximum is held against yield with the
    required safety factor; the fix reported is the smallest tip ball that
    carries the same force on the same flank.

Clearances
    Every gap between the deformed flexure and a cam surface other than the
    driving flank, by ring part (tooth tip to ball, to neck, ...), and to the
    neighbouring flexure. Profiles deviate by up to +-t_spring (ring) and
    +-t_shaft (cam) normal to their surface. Two kinds of deviation act:

    * of the two surfaces in contact (ball and driving flank), summed E = e_ball +
      e_flank: it moves where the ball sits on the flank. The sweep is repeated to
      theta_max against the cam dilated by E = -T, 0, +T (T = t_spring + t_shaft;
      :meth:`fea.contact_solver.CamCurve.dilated`, exact for a uniform offset of
      either part), which gives each gap to the *nominal* surfaces as a function
      g(E), interpolated quadratically in E;
    * of the two surfaces of the gap itself, which take it directly: at most
      t_spring + t_shaft for a ring-cam gap, 2 t_spring ring to ring.

    The driving half of the pocket continues the driving flank (one wire pass, tangent
    at the cusp), so locally it deviates as the flank does: a gap between the ball and
    that half ("driving_pocket/ball") is between the contact pair's own surfaces and
    takes E itself (q(E) - E); it closes only when the ball would bear on the pocket
    below the flank's start at that deviation (bottoming), and its nominal value is not
    held against a stack.

    Worst case: the smallest gap over every deviation the zones allow: E over
    [-T, T] and the gap's own surfaces at their limits, where a surface of the
    contact pair (the ball, the driving flank) keeps the deviation it has in E
    (each surface read as one offset locally; the other surfaces independent).
    It is at most the nominal gap minus the stack (t_spring + t_shaft, or 2
    t_spring ring to ring) when t_spring = t_shaft. Monte Carlo: every deviation
    drawn (the job's tolerance distribution, seeded, 20000 parts); reported are
    the fraction of parts whose gap closes and the 0.1 % quantile.
    A gap is accepted when its worst case stays open and its nominal value exceeds
    the plain stack.

:func:`assess` turns the per-offset reports into a :class:`ContactAtMax`; its
``failures()`` feed the release gate. Units: mm, N, MPa, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from springcad.design.contact_stress import ContactMargin, ball_advice, min_tip_radius_for_contact_mm
from springcad.design.tolerance import deviations
from springcad.units import UM_PER_MM

#: ring-to-ring gaps (the others are ring to cam)
RING_TO_RING = ("neighbour_flexure",)
#: cam surfaces cut with the driving flank (they take the flank's deviation)
PAIR_CAM = ("driving_flank", "driving_pocket")
#: Monte Carlo parts
MC_SAMPLES = 20000
#: the quantile reported of the Monte Carlo gaps
MC_QUANTILE = 0.001


@dataclass
class EndState:
    """The sweep's converged state at one end (+-theta_max) against one cam offset.

    Attributes:
        offset_mm: E, the cam dilation (sum of the deviations of ball and flank) (mm).
        converged: False when no contact state was found up to theta_max (then the rest
            is empty).
        force_N: normal force of the ball's heaviest contact (N).
        flank_curvature_per_mm: the cam's curvature there (1/mm, convex positive).
        hertz: that contact's Hertz dict (:func:`fea.contact_solver.hertz_line_contact`).
        clearances_mm: gap name -> smallest gap to the nominal surfaces (mm).
    """

    offset_mm: float
    converged: bool
    force_N: float = 0.0
    flank_curvature_per_mm: float = 0.0
    hertz: dict | None = None
    clearances_mm: dict = field(default_factory=dict)
    reason: str = ""


def _quadratic(E: np.ndarray, g: np.ndarray):
    """g(E) through the (1 to 3) offsets (constant, linear or quadratic)."""
    coef = np.polyfit(E, g, len(E) - 1) if len(E) > 1 else np.array([g[0]])
    return lambda e: np.polyval(coef, e)


@dataclass
class Clearance:
    """One gap at one end: nominal, per offset, worst case, Monte Carlo (mm)."""

    name: str
    nominal_mm: float
    stack_mm: float
    by_offset_mm: dict
    worst_case_mm: float
    mc_closed_fraction: float
    mc_quantile_mm: float
    largest_tolerance_fraction: float
    """Largest common scale of t_spring and t_shaft at which the gap passes (1 when the
    job's tolerances already do, 0 when the nominal gap itself is closed)."""

    @property
    def ok(self) -> bool:
        """The worst case stays open and the nominal gap exceeds the plain stack."""
        return self.worst_case_mm > 0 and self.nominal_mm > self.stack_mm

    def to_dict(self) -> dict:
        return {"nominal_mm": self.nominal_mm, "stack_mm": self.stack_mm,
                "by_offset_mm": {f"{e:+.4f}": g for e, g in self.by_offset_mm.items()},
                "worst_case_mm": self.worst_case_mm,
                "mc_closed_fraction": self.mc_closed_fraction,
                f"mc_q{MC_QUANTILE:g}_mm": self.mc_quantile_mm, "ok": self.ok}


@dataclass
class EndCheck:
    """Contact stress and clearances at one end of the sweep."""

    key: str
    angle_rad: float
    contact: dict
    margin: ContactMargin | None
    clearances: list
    notes: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"angle_deg": math.degrees(self.angle_rad), "contact": dict(self.contact),
                "contact_ok": self.margin is None or self.margin.ok,
                "clearances": {c.name: c.to_dict() for c in self.clearances},
                "clearances_ok": all(c.ok for c in self.clearances), "notes": list(self.notes)}


@dataclass(frozen=True)
class BallLayout:
    """The layout the ball advice needs: r_c, the design gap w_gap, the disk thickness (mm)
    and the material (MPa, -)."""

    contact_radius_mm: float
    gap_mm: float
    thickness_mm: float
    youngs_modulus_MPa: float
    poisson_ratio: float

    def advice(self, force_N: float, angle_rad: float, allowable_MPa: float,
               min_flank_position_mm: float, tip_radius_mm: float) -> str:
        """:func:`springcad.design.contact_stress.ball_advice` at this layout."""
        return ball_advice(force_N, self.contact_radius_mm, self.gap_mm, angle_rad,
                           self.thickness_mm, self.youngs_modulus_MPa, self.poisson_ratio,
                           allowable_MPa, min_flank_position_mm, tip_radius_mm)


@dataclass
class ContactAtMax:
    """The contact rules at +-theta_max (see the module docstring)."""

    name: str
    t_spring_mm: float
    t_shaft_mm: float
    offsets_mm: tuple
    distribution: str
    seed: int
    ends: dict
    """"+" and "-": :class:`EndCheck`."""
    layout: "BallLayout | None" = None
    """with it, the ball advice follows the flank radius the ball leaves
    (:func:`springcad.design.contact_stress.ball_advice`)."""

    @property
    def ok(self) -> bool:
        return not self.failures()

    def failures(self) -> list[str]:
        """Why the contact at full deflection stops a release, each with the change that
        would fix it."""
        out = []
        tol = self.t_spring_mm + self.t_shaft_mm
        for key, end in self.ends.items():
            at = f"spring {self.name} at {math.degrees(end.angle_rad):+.1f} deg"
            m, c = end.margin, end.contact
            if m is None:
                out.append(f"{at}: no converged ball contact, contact stress not assessed")
            elif not m.ok:
                r_min = c.get("min_tip_radius_mm", math.nan)
                fix = (f"a tip ball of radius >= {r_min:.2f} mm (min_tip_radius_mm) carries "
                       "the same force on the same flank" if math.isfinite(r_min) else
                       "no tip ball is enough on this flank: lower the contact force (more "
                       "flexures, a larger contact radius) or the deflection")
                if self.layout is not None and c.get("force_N", 0.0) > 0:
                    fix = self.layout.advice(c["force_N"], abs(end.angle_rad),
                                             m.yield_strength_MPa / m.required_safety_factor,
                                             tol, c["ball_radius_mm"])
                out.append(
                    f"{at}: tip ball Hertz contact von Mises {m.von_mises_MPa:.0f} MPa "
                    f"(p0 {c['p0_MPa']:.0f} MPa, {c['force_N']:.0f} N on a ball of radius "
                    f"{c['ball_radius_mm']:.3f} mm, flank radius "
                    f"{_radius_text(c['flank_radius_mm'])}) gives a yield margin "
                    f"{m.margin:.3f} below the required {m.required_safety_factor:.3g} "
                    f"(yield {m.yield_strength_MPa:.0f} MPa): {fix}")
            for g in end.clearances:
                if g.ok:
                    continue
                what = g.name.replace("/", " to ").replace("_", " ")
                if g.largest_tolerance_fraction > 0:
                    fix = (f"profile tolerances t_spring_mm = "
                           f"{g.largest_tolerance_fraction * self.t_spring_mm:.3f} and "
                           f"t_shaft_mm = {g.largest_tolerance_fraction * self.t_shaft_mm:.3f}"
                           " would keep it open, or more clearance there in the design")
                else:
                    fix = "the nominal geometry itself touches: more clearance in the design"
                out.append(
                    f"{at}: clearance {what} {UM_PER_MM * g.nominal_mm:.1f} um nominal, "
                    f"{UM_PER_MM * g.worst_case_mm:.1f} um worst case with the profile tolerances "
                    f"(stack {UM_PER_MM * g.stack_mm:.0f} um, contact offsets +-{UM_PER_MM * tol:.0f} "
                    f"um), closed in {100 * g.mc_closed_fraction:.2g} % of Monte Carlo "
                    f"parts: {fix}")
        return out

    @property
    def contact_von_mises_MPa(self) -> float:
        """The larger end's contact von Mises (MPa)."""
        return max((e.margin.von_mises_MPa for e in self.ends.values() if e.margin),
                   default=math.nan)

    @property
    def min_worst_clearance_mm(self) -> float:
        return min((c.worst_case_mm for e in self.ends.values() for c in e.clearances),
                   default=math.nan)

    def to_dict(self) -> dict:
        return {"model": "ball contact: Hertz line contact (cylinder r_tip x thickness on the "
                         "flank's local radius) from the sweep's force; clearances: gaps to the "
                         "nominal surfaces with the cam dilated by E (ball + flank deviation) "
                         "in the sweep, minus the gap's own surface deviations",
                "t_spring_mm": self.t_spring_mm, "t_shaft_mm": self.t_shaft_mm,
                "contact_offsets_mm": list(self.offsets_mm),
                "distribution": self.distribution, "mc_samples": MC_SAMPLES, "seed": self.seed,
                "ends": {k: e.to_dict() for k, e in self.ends.items()},
                "contact_von_mises_max_MPa": self.contact_von_mises_MPa,
                "worst_case_clearance_min_mm": self.min_worst_clearance_mm,
                "ok": self.ok, "failures": self.failures()}


def _radius_text(r: float) -> str:
    if not math.isfinite(r):
        return "flat"
    return f"{abs(r):.2f} mm {'convex' if r > 0 else 'concave'}"


def _worst(q, kind: str, ts: float, tc: float) -> float:
    """The smallest gap over the tolerance zones (mm): ``q(E)`` the gap to the nominal
    surfaces with the contact pair's deviation E = e_ball + e_flank, ``kind`` which of the
    gap's surfaces is one of that pair ("ball": the ring side, "flank": the cam side,
    "ring": a ring-to-ring gap, "": neither), ts and tc the ring's and cam's tolerances."""
    T = ts + tc
    # a fine grid plus the kinks of min(ts, E + tc) and min(tc, E + ts)
    E = (np.union1d(np.linspace(-T, T, 2001), [ts - tc, tc - ts]) if T > 0 else np.zeros(1))
    if kind == "ball":  # e_ball is at most ts and at most E + tc (e_flank >= -tc)
        own = np.minimum(ts, E + tc) + tc
    elif kind == "flank":
        own = np.minimum(tc, E + ts) + ts
    elif kind == "ring":
        own = np.full_like(E, 2 * ts)
    elif kind == "pair":  # both surfaces are the contact pair: their deviations sum to E
        own = E
    else:
        own = np.full_like(E, ts + tc)
    return float(np.min(q(E) - own))


def _kind(name: str) -> str:
    if name in RING_TO_RING:
        return "ring"
    cam, _, part = name.partition("/")
    if cam == "driving_pocket" and part == "ball":
        return "pair"
    return "ball" if part == "ball" else "flank" if cam in PAIR_CAM else ""


def _clearance(name, states, t_spring, t_shaft, draws, rng, distribution) -> Clearance:
    """One gap: its response to the contact pair's deviation, worst case, Monte Carlo."""
    E = np.array([s.offset_mm for s in states])
    g = np.array([s.clearances_mm[name] for s in states])
    q = _quadratic(E, g)
    kind = _kind(name)
    # the plain stack a nominal gap must exceed (none between the contact pair's surfaces)
    stack = 2 * t_spring if kind == "ring" else 0.0 if kind == "pair" else t_spring + t_shaft
    nominal = float(q(0.0))
    worst = _worst(q, kind, t_spring, t_shaft)

    def passes(f):
        return _worst(q, kind, f * t_spring, f * t_shaft) > 0 and nominal > f * stack

    if passes(1.0):
        frac = 1.0
    elif nominal <= 0:
        frac = 0.0
    else:
        lo, hi = 0.0, 1.0
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if passes(mid) else (lo, mid)
        frac = lo
    n = len(draws["ball"])
    other = lambda tol: deviations(rng, tol, n, distribution)  # noqa: E731
    ring = (draws["ball"] if kind in ("ball", "pair") else other(t_spring))
    cam = (draws["flank"] if kind in ("flank", "pair") else
           other(t_spring if kind == "ring" else t_shaft))
    T = t_spring + t_shaft  # the worst case's range of E (extrapolated past a failed offset)
    e_contact = np.clip(draws["ball"] + draws["flank"], -T, T)
    mc = q(e_contact) - ring - cam
    return Clearance(name=name, nominal_mm=nominal, stack_mm=stack,
                     by_offset_mm={float(e): float(v) for e, v in zip(E, g)},
                     worst_case_mm=worst, mc_closed_fraction=float(np.mean(mc <= 0)),
                     mc_quantile_mm=float(np.quantile(mc, MC_QUANTILE)),
                     largest_tolerance_fraction=frac)


def _contact(state: EndState, r_tip_mm, thickness_mm, material) -> dict:
    h = state.hertz or {}
    k = state.flank_curvature_per_mm
    flank_r = 1.0 / k if k else math.inf
    allowable = material.yield_strength_MPa / material.safety_factor
    r_min = math.nan
    if state.force_N > 0:
        try:
            r_min = min_tip_radius_for_contact_mm(state.force_N, flank_r, thickness_mm,
                                                  material.youngs_modulus_MPa,
                                                  material.poisson_ratio, allowable)
        except ValueError:
            r_min = math.nan
    return {"force_N": state.force_N, "ball_radius_mm": r_tip_mm, "flank_radius_mm": flank_r,
            "p0_MPa": h.get("p0_MPa", 0.0), "half_width_mm": h.get("half_width_mm", 0.0),
            "von_mises_MPa": h.get("von_mises_max_MPa", 0.0), "depth_mm": h.get("depth_mm", 0.0),
            "yield_strength_MPa": material.yield_strength_MPa,
            "required_safety_factor": material.safety_factor,
            "margin": (material.yield_strength_MPa / h["von_mises_max_MPa"]
                       if h.get("von_mises_max_MPa") else math.inf),
            "min_tip_radius_mm": r_min}


@dataclass(frozen=True)
class ContactMaterial:
    """What the contact rules need of the material (MPa, -)."""

    youngs_modulus_MPa: float
    poisson_ratio: float
    yield_strength_MPa: float
    safety_factor: float


def assess(name: str, ends: dict, r_tip_mm: float, thickness_mm: float,
           material: ContactMaterial, t_spring_mm: float, t_shaft_mm: float,
           distribution: str = "uniform", seed: int = 1,
           layout: BallLayout | None = None) -> ContactAtMax:
    """Judge the ends of a contact sweep.

    Args:
        name: spring name.
        ends: key ("+", "-") -> (angle_rad, list of :class:`EndState`, one per offset,
            offset 0 first).
        r_tip_mm, thickness_mm: the tip ball and the disk (mm).
        material: :class:`ContactMaterial`.
        t_spring_mm, t_shaft_mm: profile tolerances of ring and cam (mm).
        distribution: "uniform" or "normal" (t = 3 sigma) for the Monte Carlo.
        seed: Monte Carlo seed.
        layout: :class:`BallLayout` for the ball advice of a failed contact.
    """
    rng = np.random.default_rng(seed)
    checks, offsets = {}, ()
    for key, (angle, states) in ends.items():
        nominal = states[0]
        notes = []
        if not nominal.converged:
            checks[key] = EndCheck(key, angle, {}, None, [], [nominal.reason])
            continue
        used = [s for s in states if s.converged]
        notes += [f"offset {UM_PER_MM * s.offset_mm:+.0f} um: {s.reason}; the worst case uses the "
                  "other offsets" for s in states if not s.converged]
        used.sort(key=lambda s: s.offset_mm)
        offsets = tuple(s.offset_mm for s in used)
        contact = _contact(nominal, r_tip_mm, thickness_mm, material)
        toleranced = [s.hertz["von_mises_max_MPa"] for s in used if s.hertz]
        contact["von_mises_toleranced_max_MPa"] = max(toleranced, default=math.nan)
        margin = (ContactMargin(contact["von_mises_MPa"], material.yield_strength_MPa,
                                material.safety_factor) if nominal.hertz else None)
        if margin is None:
            notes.append("no ball contact at theta_max")
        draws = {"ball": deviations(rng, t_spring_mm, MC_SAMPLES, distribution),
                 "flank": deviations(rng, t_shaft_mm, MC_SAMPLES, distribution)}
        clearances = [_clearance(gap, used, t_spring_mm, t_shaft_mm, draws, rng, distribution)
                      for gap in nominal.clearances_mm]
        checks[key] = EndCheck(key, angle, contact, margin, clearances, notes)
    return ContactAtMax(name=name, t_spring_mm=t_spring_mm, t_shaft_mm=t_shaft_mm,
                        offsets_mm=offsets, distribution=distribution, seed=seed, ends=checks,
                        layout=layout)
