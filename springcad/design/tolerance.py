"""Backlash from the cam-tip gap and manufacturing tolerances (paper eqs. 1-3).

Per cam interface the tip-to-opposite-tooth distance is
d = 2 (w_gap + e_spring + e_shaft) with |e_spring| <= t_spring and
|e_shaft| <= t_shaft, and the backlash is b = 2 atan(d / (2 r_c)). A stack
of n springs has n cam interfaces; springs joined shaft-to-shaft share one
camshaft, so that camshaft's error enters both of their interfaces (the
RSS and the Monte Carlo keep that correlation; the worst case adds anyway).

D joints (a torque shaft's D in a camshaft's D bore, or a D socket over a D hub) add
their rotational play in series (:class:`DJoint`): the flats are toleranced
one-sided (bore flat +t_bore/0 away from the axis, shaft flat 0/-t_shaft towards it),
so the flat clearance is c = e_bore + e_shaft in [0, t_bore + t_shaft], and the shaft
turns until an end of its flat (half-chord h from the flat's middle) meets the bore's
flat: theta = atan(c / h) each way, a play of 2 atan(c / h) (first order in c / h; the
radial clearance of the round part is left out, it lets the shaft shift, not turn).

Rim pin joints (two rims, or a rim and a rim flange, joined by slip-fit dowels,
:class:`RimPinJoint`) add theirs in series too: a pin with diametral clearances c_a and c_b
in its two holes lets the rims turn by (c_a + c_b) / r_pins from one side to the other
(the pin with the least clearance bears first; hole-pattern errors only make the play
smaller, so the worst-case maximum and the nominal leave them out and the minimum is 0).
Units: mm and rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


def backlash_rad(gap_mm, contact_radius_mm):
    """b = 2 atan(d / (2 r_c)) (rad); negative d means interference. Eq. 3."""
    return 2.0 * np.arctan(np.asarray(gap_mm) / (2.0 * contact_radius_mm))


def gap_range_mm(w_gap_mm: float, t_spring_mm: float, t_shaft_mm: float) -> tuple[float, float, float]:
    """(d_min, d_nominal, d_max) in mm. Eqs. 1-2."""
    return (2.0 * (w_gap_mm - t_spring_mm - t_shaft_mm), 2.0 * w_gap_mm,
            2.0 * (w_gap_mm + t_spring_mm + t_shaft_mm))


@dataclass(frozen=True)
class Interface:
    """One cam-tip interface of a stack."""

    contact_radius_mm: float
    w_gap_mm: float
    t_spring_mm: float
    t_shaft_mm: float
    camshaft: int
    """Index of the camshaft part (shared by springs joined shaft-to-shaft)."""

    @property
    def range_rad(self) -> tuple[float, float, float]:
        d = gap_range_mm(self.w_gap_mm, self.t_spring_mm, self.t_shaft_mm)
        return tuple(float(backlash_rad(v, self.contact_radius_mm)) for v in d)


@dataclass(frozen=True)
class DJoint:
    """One D joint's flats (mm).

    Attributes:
        half_chord_mm: half the length of the inner (shaft or hub) part's flat, between its
            corner fillets.
        t_bore_mm: one-sided tolerance of the bore's (socket's) flat, away from the axis.
        t_shaft_mm: one-sided tolerance of the shaft's (hub's) flat, towards the axis.
        name: what it joins, for reports.
    """

    half_chord_mm: float
    t_bore_mm: float
    t_shaft_mm: float
    name: str = ""
    KIND = "D fit"

    def play_rad(self, clearance_mm):
        """Total free rotation 2 atan(c / h) for a flat clearance ``c`` (mm); rad."""
        return 2.0 * np.arctan(np.asarray(clearance_mm) / self.half_chord_mm)

    @property
    def range_rad(self) -> tuple[float, float, float]:
        """(min, mid-tolerance, max) play (rad)."""
        t = self.t_bore_mm + self.t_shaft_mm
        return tuple(float(self.play_rad(c)) for c in (0.0, 0.5 * t, t))

    def rss_var(self) -> float:
        """Variance term of the RSS: dplay/dc = 2 / h at mid-tolerance (first order) times
        each flat's band half-width (rad^2)."""
        g = 2.0 / self.half_chord_mm / (1.0 + (0.5 * (self.t_bore_mm + self.t_shaft_mm)
                                               / self.half_chord_mm) ** 2)
        return (g * 0.5 * self.t_bore_mm) ** 2 + (g * 0.5 * self.t_shaft_mm) ** 2

    def sample_rad(self, rng, samples: int, distribution: str) -> np.ndarray:
        """Monte Carlo plays (rad): one-sided deviations of both flats."""
        return self.play_rad(_one_sided(rng, self.t_bore_mm, samples, distribution)
                             + _one_sided(rng, self.t_shaft_mm, samples, distribution))


@dataclass(frozen=True)
class RimPinJoint:
    """Two rims (or a rim and a rim flange) joined by slip-fit dowels (mm).

    Attributes:
        radius_mm: radius of the pin circle.
        clearance_min_mm, clearance_max_mm: diametral clearance of a pin in one hole
            (:func:`springcad.design.catalogue.rim_pin_fit`).
        name: what it joins, for reports.
    """

    radius_mm: float
    clearance_min_mm: float
    clearance_max_mm: float
    name: str = ""
    KIND = "rim pins"

    def play_rad(self, clearance_a_mm, clearance_b_mm):
        """Free rotation (c_a + c_b) / r of the two rims (rad)."""
        return (np.asarray(clearance_a_mm) + np.asarray(clearance_b_mm)) / self.radius_mm

    @property
    def range_rad(self) -> tuple[float, float, float]:
        """(0, mid-band, max) play (rad): the minimum is 0 (pattern errors may take the
        least clearance up)."""
        mid = 0.5 * (self.clearance_min_mm + self.clearance_max_mm)
        return 0.0, float(self.play_rad(mid, mid)), float(self.play_rad(self.clearance_max_mm,
                                                                          self.clearance_max_mm))

    def rss_var(self) -> float:
        """Variance term of the RSS: each hole's band half-width / r (rad^2)."""
        half = 0.5 * (self.clearance_max_mm - self.clearance_min_mm) / self.radius_mm
        return 2.0 * half ** 2

    def sample_rad(self, rng, samples: int, distribution: str) -> np.ndarray:
        """Monte Carlo plays (rad): each hole's clearance within its band."""
        band = self.clearance_max_mm - self.clearance_min_mm
        return self.play_rad(self.clearance_min_mm + _one_sided(rng, band, samples, distribution),
                             self.clearance_min_mm + _one_sided(rng, band, samples, distribution))


def d_half_chord_mm(radius_mm: float, flat_ratio: float, corner_radius_mm: float = 0.0) -> float:
    """Half-length of a D's flat between its corner fillets (mm): the flat at
    ``flat_ratio * r`` from the axis, fillets of ``corner_radius_mm`` tangent to flat and
    circle (the geometry of :func:`springcad.design.cam.d_bore`)."""
    a, rf = flat_ratio * radius_mm, corner_radius_mm
    return math.sqrt((radius_mm - rf) ** 2 - (a - rf) ** 2)


@dataclass(frozen=True)
class StackBacklash:
    """Backlash of a whole stack (rad)."""

    nominal: float
    worst_min: float
    worst_max: float
    rss_min: float
    rss_max: float
    mc_mean: float
    mc_std: float
    mc_p01: float
    mc_p99: float
    mc_interference_fraction: float
    """Share of Monte Carlo stacks with at least one interface in interference (d < 0)."""
    mc_samples: int
    mc_seed: int
    distribution: str
    per_interface: tuple[tuple[float, float, float], ...]
    """(min, nominal, max) per interface (rad)."""
    mc_histogram: tuple[tuple[float, ...], tuple[int, ...]] = ((), ())
    per_d_joint: tuple[tuple[float, float, float], ...] = ()
    """(min, mid-tolerance, max) play of each D joint and rim pin joint (rad)."""
    d_joint_names: tuple[str, ...] = ()
    d_joint_kinds: tuple[str, ...] = ()
    with_d_joints: dict = field(default_factory=dict)
    """The stack's backlash from input to output: the cam interfaces, the D joints and the
    rim pin joints in series (keys nominal, worst_min, worst_max, rss_min, rss_max, mc_mean, mc_p01,
    mc_p99; rad). The fields above are the cam interfaces alone (the paper's eqs. 1-3)."""

    @property
    def interference_possible(self) -> bool:
        return any(lo < 0 for lo, _, _ in self.per_interface)

    def to_dict(self) -> dict:
        return {
            "nominal": self.nominal, "worst_min": self.worst_min, "worst_max": self.worst_max,
            "rss": [self.rss_min, self.rss_max],
            "rss_min": self.rss_min, "rss_max": self.rss_max,
            "mc_mean": self.mc_mean, "mc_std": self.mc_std,
            "mc_p01": self.mc_p01, "mc_p99": self.mc_p99,
            "mc_interference_fraction": self.mc_interference_fraction,
            "mc_samples": self.mc_samples, "mc_seed": self.mc_seed,
            "distribution": self.distribution,
            "per_interface": [{"worst_min": a, "nominal": b, "worst_max": c}
                              for a, b, c in self.per_interface],
            "interference_possible": self.interference_possible,
            "mc_histogram": {"edges_rad": list(self.mc_histogram[0]),
                             "counts": list(self.mc_histogram[1])},
            "d_joints": [{"name": n, "kind": k, "min": a, "mid": b, "max": c}
                         for n, k, (a, b, c) in zip(self.d_joint_names, self.d_joint_kinds,
                                                    self.per_d_joint)],
            "with_d_joints": dict(self.with_d_joints),
        }


def deviations(rng, tol, size, distribution):
    """``size`` profile deviations within +-``tol`` (mm): "uniform" in +-tol, or "normal"
    with tol = 3 sigma."""
    if distribution == "normal":  # tolerance read as 3 sigma
        return rng.normal(0.0, tol / 3.0, size=size)
    return rng.uniform(-tol, tol, size=size)


def _one_sided(rng, tol, size, distribution):
    """A one-sided deviation in [0, tol]: uniform, or normal about the middle (3 sigma =
    half the band, clipped to it)."""
    if distribution == "normal":
        return np.clip(rng.normal(0.5 * tol, tol / 6.0, size=size), 0.0, tol)
    return rng.uniform(0.0, tol, size=size)


def stack_backlash(interfaces: list[Interface], samples: int = 20000, seed: int = 1,
                   distribution: str = "uniform", d_joints: tuple = ()) -> StackBacklash:
    """Nominal, worst case, RSS and seeded Monte Carlo backlash of a stack.

    The cam-interface results keep the paper's eqs. 1-3 (what its Table II compares);
    ``with_d_joints`` adds the D joints in series. The nominal of a D joint is its play
    at mid-tolerance (its nominal clearance is 0, but a one-sided tolerance band is never
    made at its edge on purpose).

    Args:
        interfaces: one per spring, in stack order.
        d_joints: the stack's :class:`DJoint` (torque shafts on the end camshafts) and
            :class:`RimPinJoint` (dowelled rim joints), in any order.
        samples: Monte Carlo stacks.
        seed: random seed (the result is reproducible).
        distribution: "uniform" (deviation uniform in +-t) or "normal" (t = 3 sigma).
    """
    ranges = [i.range_rad for i in interfaces]
    d_ranges = [j.range_rad for j in d_joints]
    nominal = sum(r[1] for r in ranges)
    worst_min = sum(r[0] for r in ranges)
    worst_max = sum(r[2] for r in ranges)
    # RSS: linearised sensitivities db/de = 2 * db/dd, shared camshafts correlated
    sens = [2.0 / i.contact_radius_mm / (1.0 + (i.w_gap_mm / i.contact_radius_mm) ** 2)
            for i in interfaces]
    var = sum((g * i.t_spring_mm) ** 2 for g, i in zip(sens, interfaces))
    for cam in sorted({i.camshaft for i in interfaces}):
        t = max(i.t_shaft_mm for i in interfaces if i.camshaft == cam)
        var += (t * sum(g for g, i in zip(sens, interfaces) if i.camshaft == cam)) ** 2
    half = math.sqrt(var)
    var_d = sum(j.rss_var() for j in d_joints)
    half_total = math.sqrt(var + var_d)
    rng = np.random.default_rng(seed)
    cams = sorted({i.camshaft for i in interfaces})
    e_cam = {c: deviations(rng, max(i.t_shaft_mm for i in interfaces if i.camshaft == c),
                            samples, distribution) for c in cams}
    total = np.zeros(samples)
    interfering = np.zeros(samples, dtype=bool)
    for i in interfaces:
        e_spring = deviations(rng, i.t_spring_mm, samples, distribution)
        d = 2.0 * (i.w_gap_mm + e_spring + e_cam[i.camshaft])
        interfering |= d < 0
        total += backlash_rad(d, i.contact_radius_mm)
    counts, edges = np.histogram(total, bins=40)
    with_d = total.copy()
    for j in d_joints:
        with_d += j.sample_rad(rng, samples, distribution)
    d_nom = sum(r[1] for r in d_ranges)
    totals = {"nominal": nominal + d_nom, "worst_min": worst_min + sum(r[0] for r in d_ranges),
              "worst_max": worst_max + sum(r[2] for r in d_ranges),
              "rss_min": nominal + d_nom - half_total, "rss_max": nominal + d_nom + half_total,
              "mc_mean": float(with_d.mean()), "mc_p01": float(np.percentile(with_d, 1)),
              "mc_p99": float(np.percentile(with_d, 99))}
    return StackBacklash(
        nominal=nominal, worst_min=worst_min, worst_max=worst_max,
        rss_min=nominal - half, rss_max=nominal + half,
        mc_mean=float(total.mean()), mc_std=float(total.std()),
        mc_p01=float(np.percentile(total, 1)), mc_p99=float(np.percentile(total, 99)),
        mc_interference_fraction=float(interfering.mean()), mc_samples=samples, mc_seed=seed,
        distribution=distribution, per_interface=tuple(ranges),
        mc_histogram=(tuple(map(float, edges)), tuple(map(int, counts))),
        per_d_joint=tuple(d_ranges), d_joint_names=tuple(j.name for j in d_joints),
        d_joint_kinds=tuple(j.KIND for j in d_joints),
        with_d_joints=totals)
