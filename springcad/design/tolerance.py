"""Backlash from the cam-tip gap and manufacturing tolerances (paper eqs. 1-3).

Per cam interface the tip-to-opposite-tooth distance is
d = 2 (w_gap + e_spring + e_shaft) with |e_spring| <= t_spring and
|e_shaft| <= t_shaft, and the backlash is b = 2 atan(d / (2 r_c)). A stack
of n springs has n cam interfaces; springs joined shaft-to-shaft share one
camshaft, so that camshaft's error enters both of their interfaces (the
RSS and the Monte Carlo keep that correlation; the worst case adds anyway).
Units: mm and rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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
        }


def deviations(rng, tol, size, distribution):
    """``size`` profile deviations within +-``tol`` (mm): "uniform" in +-tol, or "normal"
    with tol = 3 sigma."""
    if distribution == "normal":  # tolerance read as 3 sigma
        return rng.normal(0.0, tol / 3.0, size=size)
    return rng.uniform(-tol, tol, size=size)


def stack_backlash(interfaces: list[Interface], samples: int = 20000, seed: int = 1,
                   distribution: str = "uniform") -> StackBacklash:
    """Nominal, worst case, RSS and seeded Monte Carlo backlash of a stack.

    Args:
        interfaces: one per spring, in stack order.
        samples: Monte Carlo stacks.
        seed: random seed (the result is reproducible).
        distribution: "uniform" (deviation uniform in +-t) or "normal" (t = 3 sigma).
    """
    ranges = [i.range_rad for i in interfaces]
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
    return StackBacklash(
        nominal=nominal, worst_min=worst_min, worst_max=worst_max,
        rss_min=nominal - half, rss_max=nominal + half,
        mc_mean=float(total.mean()), mc_std=float(total.std()),
        mc_p01=float(np.percentile(total, 1)), mc_p99=float(np.percentile(total, 99)),
        mc_interference_fraction=float(interfering.mean()), mc_samples=samples, mc_seed=seed,
        distribution=distribution, per_interface=tuple(ranges),
        mc_histogram=(tuple(map(float, edges)), tuple(map(int, counts))))
