"""The contact sweep's result: how to sweep, what each step reports, and the flags.

:class:`ContactOptions` (steps, mesh level, kinematics, and the tolerances of the
flags), :class:`ContactStep` (one cam angle) and :class:`ContactSweep` (the
whole sweep; ``to_dict`` is the ``contact_sweep`` entry of ``fea.json``), and
:func:`direction_flags`, the judgement of one direction of the sweep. The sweep
that fills them is :func:`fea.contact.contact_sweep`.

Reported per step
    Torque (N*m: the moment of the contact forces about the axis at their
    current points, x N flexures), secant T / theta, engaged secant
    T / (theta - theta_onset) (the gap makes T / theta low near zero by
    design), tangent (slope over the last quarter step), each contact with its
    force, its point on the ball (angle from the design contact point,
    positive towards the root) and on the cam (feature, distance from the
    flank start, flank fraction and margin to the flank end), the smallest gap
    to every other surface (pocket arc, back flank, both tooth tips, the teeth
    beyond, the neighbouring flexure), and the peak stress including contact:
    the larger of the flexure's FE peak outside the contact zone (scaled to the
    verified peak through the linear FEA of the same mesh) and the Hertz line
    contact peak (subsurface von Mises, closed form) from the contact force and
    the curvatures of ball and cam. The contact half-width (~10 um) is far
    below the mesh size, so the FE value at the contact itself is a
    mesh-dependent point-load value, reported but not used.

Flags (tolerances in :class:`ContactOptions`)
    "leaves_flank": the contact reaches the end of the driving flank (within
    2 % of its length or the Hertz half-width), the tooth tip, another pocket
    (a tooth skipped), or the path jumps or stops. "second_contact": a contact
    other than ball - driving flank (pocket arc next to the flank start
    included: the cam drives there below the flank's first roll angle), or a
    gap to another surface closing. "nonlinear": the engaged secant departs
    from the linear FEA K by more than ``linearity_tolerance`` or the tangent by
    more than ``tangent_tolerance``. "small_angle": the engaged secant 1 % of
    theta_max past the onset misses the linear FEA of the same mesh by more
    than ``small_angle_tolerance``. "gap": the clearance at rest is below
    w_gap by more than ``gap_tolerance`` (negative: the cam interferes).
    "no_contact": the cam never reaches the ball.

Units: mm, N, MPa, N*mm, rad inside; JSON keys carry N*m and deg where they say so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from springcad.errors import SolverError
from springcad.units import NMM_PER_NM, UM_PER_MM

#: a gap to a surface other than the driving flank at or below this counts as closed (mm)
CLOSED_GAP_MM = 1e-4
#: a contact this close to the end of the driving flank (fraction of its length, or the
#: Hertz half-width if larger) has left it: the contact patch reaches the tooth-tip corner
FLANK_END_FRACTION = 0.02


@dataclass(frozen=True)
class ContactOptions:
    """How to sweep.

    Attributes:
        steps: rotation steps from 0 to +theta_max and from 0 to -theta_max (>= 8).
        level: 2D mesh level of the verification to use (clipped to those available).
        nonlinear: total Lagrangian kinematics (large rotations); False: linear elasticity
            with the contact on current positions.
        linearity_tolerance: accepted |K / K_linear - 1| of the engaged secant
            T / (theta - theta_onset), i.e. of the torque curve against the straight line
            K_linear (theta - theta_onset) (-).
        tangent_tolerance: accepted |K_tangent / K_linear - 1| of the local slope over the
            last quarter step (-); looser, because the contact moves along the ball in
            discrete points (1/8 of an element edge) and a transfer between two points
            shows in a quarter-step slope as up to ~3 % (straight-flexure reference).
        small_angle_tolerance: accepted |K_small / K_linear - 1| just after onset (-).
        gap_tolerance: accepted shortfall of the clearance at rest below w_gap (-).
    """

    steps: int = 8
    level: int = 0
    nonlinear: bool = True
    linearity_tolerance: float = 0.02
    tangent_tolerance: float = 0.05
    small_angle_tolerance: float = 0.005
    gap_tolerance: float = 0.05
    tolerances: bool = True
    """Also judge the ends with the profile tolerances (:mod:`fea.contact_tolerance`)."""
    seed: int = 1
    """Monte Carlo seed of the clearances."""

    def __post_init__(self):
        if self.steps < 8:
            raise SolverError(f"contact sweep needs at least 8 steps per direction, got "
                              f"{self.steps}")
        for name in ("linearity_tolerance", "tangent_tolerance", "small_angle_tolerance",
                     "gap_tolerance"):
            if not 0 < getattr(self, name) < 0.5:
                raise SolverError(f"contact option {name} = {getattr(self, name)} must be in "
                                  "(0, 0.5)")


@dataclass
class ContactStep:
    """One cam angle (ring torque N*mm, stiffness N*mm/rad, lengths mm, stress MPa)."""

    angle_rad: float
    torque_Nmm: float
    secant_Nmm_per_rad: float | None
    engaged_secant_Nmm_per_rad: float | None
    tangent_Nmm_per_rad: float | None
    contacts: list
    gaps_mm: dict
    peak_von_mises_MPa: float
    flexure_peak_MPa: float
    flexure_peak_scaled_MPa: float
    flexure_peak_region: str
    hertz: dict | None
    iterations: int
    equilibrium_error: float

    def to_dict(self) -> dict:
        nm = lambda v: None if v is None else v / NMM_PER_NM
        return {"angle_rad": self.angle_rad, "angle_deg": math.degrees(self.angle_rad),
                "torque_Nm": self.torque_Nmm / NMM_PER_NM,
                "secant_stiffness_Nm_per_rad": nm(self.secant_Nmm_per_rad),
                "engaged_secant_stiffness_Nm_per_rad": nm(self.engaged_secant_Nmm_per_rad),
                "tangent_stiffness_Nm_per_rad": nm(self.tangent_Nmm_per_rad),
                "contacts": self.contacts, "gaps_mm": dict(self.gaps_mm),
                "peak_von_mises_MPa": self.peak_von_mises_MPa,
                "flexure_peak_von_mises_MPa": self.flexure_peak_scaled_MPa,
                "flexure_peak_von_mises_this_mesh_MPa": self.flexure_peak_MPa,
                "flexure_peak_region": self.flexure_peak_region,
                "hertz": self.hertz, "iterations": self.iterations,
                "equilibrium_error": self.equilibrium_error}


@dataclass
class ContactSweep:
    """The cam turned from 0 to +-theta_max against the sector: curve, contacts, flags."""

    name: str
    max_deflection_rad: float
    n_flexures: int
    level: int
    dofs: int
    candidates: int
    stiffness_linear_Nmm_per_rad: float
    """Linear FEA (traction patch) K of the same 2D mesh (N*mm/rad)."""
    stiffness_verified_Nmm_per_rad: float | None
    design_gap_mm: float
    peak_linear_this_mesh_MPa: float
    """Linear FEA (traction) nodal peak of this mesh at theta_max (MPa)."""
    peak_verified_MPa: float | None
    """The verified (extrapolated, 3D-factored) peak at theta_max (MPa), or None."""
    rest_clearance_mm: float
    onset_rad: dict
    small_angle_Nmm_per_rad: dict
    steps: dict
    """"+" and "-": lists of :class:`ContactStep` from 0 to +-theta_max."""
    flags: list
    options: ContactOptions
    stopped: dict
    """Direction -> why the sweep stopped before theta_max (no converged state)."""
    jumps_rad: dict
    """Direction -> cam angles where the state jumped (a limit point: the ball snaps)."""
    timings_s: dict
    notes: list = field(default_factory=list)
    pictures: dict = field(default_factory=dict, repr=False)
    """Deformed geometry at +-theta_max for the PNG (not serialised)."""
    at_max: object | None = None
    """The contact rules at +-theta_max with the profile tolerances
    (:class:`~fea.contact_tolerance.ContactAtMax`), or None."""

    @property
    def ok(self) -> bool:
        return not self.flags

    def small_angle_error(self, sign: str) -> float:
        return self.small_angle_Nmm_per_rad[sign] / self.stiffness_linear_Nmm_per_rad - 1.0

    def to_dict(self) -> dict:
        o = self.options
        return {
            "model": "rigid cam turned about the ring axis against the 2D plane-stress sector "
                     "(outer rim held); frictionless point-to-surface contact (contact points "
                     "on the quadratic boundary, 8 per element edge), exact complementarity "
                     "per Newton iteration; designed gap in the geometry; "
                     + ("total Lagrangian kinematics (large rotations, small strains)"
                        if o.nonlinear else "linear elasticity, contact on current positions"),
            "level": self.level, "dofs": self.dofs, "candidate_nodes": self.candidates,
            "steps_per_direction": o.steps,
            "max_deflection_rad": self.max_deflection_rad,
            "stiffness_linear_fea_Nm_per_rad": self.stiffness_linear_Nmm_per_rad / NMM_PER_NM,
            "stiffness_linear_fea_note": "2D linear FEA (traction patch) on the same mesh",
            "stiffness_verified_Nm_per_rad": None if self.stiffness_verified_Nmm_per_rad is None
            else self.stiffness_verified_Nmm_per_rad / NMM_PER_NM,
            "small_angle_stiffness_Nm_per_rad": {k: v / NMM_PER_NM for k, v in
                                                 self.small_angle_Nmm_per_rad.items()},
            "small_angle_vs_linear_pct": {k: 100.0 * self.small_angle_error(k)
                                          for k in self.small_angle_Nmm_per_rad},
            "design_gap_mm": self.design_gap_mm, "rest_clearance_mm": self.rest_clearance_mm,
            "peak_linear_fea_this_mesh_MPa": self.peak_linear_this_mesh_MPa,
            "peak_verified_MPa": self.peak_verified_MPa,
            "peak_note": "flexure_peak_von_mises_MPa of a step is this mesh's FE peak outside "
                         "the contact zone times peak_verified / peak_linear_fea_this_mesh; "
                         "peak_von_mises_MPa is the larger of it and the Hertz contact peak",
            "onset_deg": {k: math.degrees(v) for k, v in self.onset_rad.items()},
            "tolerances_pct": {"linearity": 100 * o.linearity_tolerance,
                               "tangent": 100 * o.tangent_tolerance,
                               "small_angle": 100 * o.small_angle_tolerance,
                               "gap": 100 * o.gap_tolerance},
            "torque_angle": {k: [s.to_dict() for s in v] for k, v in self.steps.items()},
            "stopped": dict(self.stopped),
            "jumps_deg": {k: [math.degrees(a) for a in v] for k, v in self.jumps_rad.items()},
            "flags": list(self.flags), "ok": self.ok, "notes": list(self.notes),
            "at_max_deflection": None if self.at_max is None else self.at_max.to_dict(),
            "timings_s": dict(self.timings_s)}


# ============================================================ flags
def direction_flags(key, steps, th_on, k_small, k_lin, options, theta_max, stuck=None,
                    jumps=()) -> list[dict]:
    """Flags of one direction of the sweep (see the module docstring)."""
    deg = math.degrees
    if not math.isfinite(th_on):
        return [{"code": "no_contact", "message": f"{key}: the cam never touches the ball up to "
                 f"{deg(theta_max):.2f} deg"}]
    flags = []
    if k_small is not None and abs(k_small / k_lin - 1) > options.small_angle_tolerance:
        flags.append({"code": "small_angle", "message":
                      f"{key}: stiffness just after contact onset "
                      f"{k_small / NMM_PER_NM:.3f} N*m/rad "
                      f"differs from the linear FEA {k_lin / NMM_PER_NM:.3f} by "
                      f"{100 * (k_small / k_lin - 1):+.2f} % (tolerance "
                      f"{100 * options.small_angle_tolerance:g} %)"})
    off, second, nonlin = [], [], []
    step = theta_max / max(options.steps, 1)
    for s in steps:
        a = f"{deg(s.angle_rad):+.2f} deg"
        on_tip = False
        for c in s.contacts:
            kind, unit = c["feature"].split(":")
            # at the end of the flank when the contact patch (Hertz half-width) or 2 % of
            # the flank length reaches the corner with the tooth tip
            end = max(FLANK_END_FRACTION * c.get("flank_length_mm", 0.0),
                      c.get("hertz", {}).get("half_width_mm", 0.0))
            if kind == "tip" or (c["intended"] and "flank_margin_mm" in c
                                 and c["flank_margin_mm"] <= end):
                off.append(f"{a}: contact on {c['feature']}")
                on_tip = True
            elif int(unit) != 0:
                off.append(f"{a}: the ball has left its pocket (a tooth skipped): contact on "
                           f"{c['feature']}")
            elif not c["intended"]:
                second.append(f"{a}: {c['ring_feature']} touches {c['feature']} "
                              f"({c['force_N']:.1f} N)")
        for name, gap in s.gaps_mm.items():
            if name == "driving_flank" or (on_tip and name == "driving_tooth_tip"):
                continue
            if gap <= CLOSED_GAP_MM:
                second.append(f"{a}: {name.replace('_', ' ')} gap {UM_PER_MM * gap:.2f} um")
        if abs(s.angle_rad - th_on) > 0.99 * step:  # one step past the onset
            for what, k, tol in (("tangent", s.tangent_Nmm_per_rad, options.tangent_tolerance),
                                 ("engaged secant", s.engaged_secant_Nmm_per_rad,
                                  options.linearity_tolerance)):
                if k is not None and abs(k / k_lin - 1) > tol:
                    nonlin.append(f"{a}: {what} {k / NMM_PER_NM:.2f} N*m/rad "
                                  f"({100 * (k / k_lin - 1):+.1f} %)")
    more = lambda lst: "; ".join(lst[:4]) + (" ..." if len(lst) > 4 else "")
    off += [f"{deg(j):+.2f} deg: the ball snaps to a new position (no continuous "
            "equilibrium path)" for j in jumps]
    if stuck:
        off.append(f"the sweep stops: {stuck}")
    if off:
        flags.append({"code": "leaves_flank",
                      "message": f"{key}: the ball leaves the driving flank: {more(off)}"})
    if second:
        flags.append({"code": "second_contact",
                      "message": f"{key}: second contact: {more(second)}"})
    if nonlin:
        flags.append({"code": "nonlinear", "message":
                      f"{key}: stiffness departs from the linear FEA "
                      f"{k_lin / NMM_PER_NM:.2f} N*m/rad "
                      f"by more than {100 * options.linearity_tolerance:g} % (secant from the "
                      f"onset) or {100 * options.tangent_tolerance:g} % (tangent): "
                      f"{more(nonlin)}"})
    return flags
