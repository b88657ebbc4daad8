"""When no design meets a spec: the nearest values of the user's own keys that would.

A refusal must name a change that works. For each key a user sets on a spring
(thickness, outer radius, deflection, stiffness) the spec is probed with the other keys
fixed: first at the far end of a plausible range, then by bisection towards the
user's value; the boundary is rounded outward to a value a person would write
(0.1 mm, 0.5 mm, 0.1 deg, 1 %) and that rounded value is checked once more with the
full design search, so what is printed is a value that designs.

The probe is any function ``designs(spec) -> bool``; :func:`springcad.design.search`
passes the design search itself with a small candidate budget. Units: mm, deg, N*m/rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import replace as _replace
from typing import Callable

from springcad.config import SpringSpec
from springcad.units import NMM_PER_NM

#: bisection steps per key (the boundary to ~1/32 of the searched span before rounding)
STEPS = 5


@dataclass(frozen=True)
class KeyRange:
    """One user key probed: its name in the config, how to read and set it on a spec,
    the far end of its search as a factor on the user's value, and the rounding step."""

    key: str
    get: Callable[[SpringSpec], float]
    set: Callable[[SpringSpec, float], SpringSpec]
    far_factor: float
    step: float


def _keys() -> tuple[KeyRange, ...]:
    return (
        KeyRange("thickness_mm", lambda s: s.thickness_mm,
                 lambda s, v: _replace(s, thickness_mm=v), 2.5, 0.1),
        KeyRange("outer_radius_mm", lambda s: s.outer_radius_mm,
                 lambda s, v: _replace(s, outer_radius_mm=v), 1.8, 0.5),
        KeyRange("max_deflection_deg", lambda s: math.degrees(s.max_deflection_rad),
                 lambda s, v: _replace(s, max_deflection_rad=math.radians(v)), 0.3, 0.1),
        KeyRange("stiffness_Nm_per_rad", lambda s: s.stiffness_Nmm_per_rad / NMM_PER_NM,
                 lambda s, v: _replace(s, stiffness_Nmm_per_rad=v * NMM_PER_NM), 0.3, 0.0),
    )


def _rounded(value: float, step: float, up: bool) -> float:
    """``value`` rounded outward to a multiple of ``step`` (or to 3 significant figures)."""
    if step <= 0:
        q = 10 ** (math.floor(math.log10(abs(value))) - 2)
        return (math.ceil if up else math.floor)(value / q) * q
    return round((math.ceil if up else math.floor)(value / step - 1e-9) * step, 6)


def nearest_changes(spec: SpringSpec, designs: Callable[[SpringSpec], bool],
                    keys: tuple[str, ...] | None = None) -> list[tuple[str, float, float]]:
    """The nearest value of each user key at which the spec designs, other keys unchanged.

    Args:
        spec: the refused spring spec.
        designs: the probe (True when a spec designs).
        keys: config keys to probe (default thickness, outer radius, deflection, stiffness).

    Returns:
        (key, user value, suggested value) for every key whose change designs, in the
        order probed; the suggestion was itself checked by ``designs``.
    """
    out = []
    for kr in _keys():
        if keys is not None and kr.key not in keys:
            continue
        v0 = kr.get(spec)
        far = v0 * kr.far_factor
        if not designs(kr.set(spec, far)):
            continue
        lo, hi = v0, far  # lo fails, hi designs
        for _ in range(STEPS):
            mid = 0.5 * (lo + hi)
            if designs(kr.set(spec, mid)):
                hi = mid
            else:
                lo = mid
        up = kr.far_factor > 1
        value = _rounded(hi, kr.step, up)
        if not designs(kr.set(spec, value)):
            value = hi  # the bisection's own feasible end
        out.append((kr.key, v0, value))
    return out


def describe(spring_name: str, changes: list[tuple[str, float, float]]) -> str:
    """One clause naming the changes, e.g. "springs.A.thickness_mm = 6.3 (now 5)"."""
    if not changes:
        return ("no change of thickness_mm (to 2.5x), outer_radius_mm (to 1.8x), "
                "max_deflection_deg (to 0.3x) or stiffness_Nm_per_rad (to 0.3x) alone "
                "designs: put springs in series, choose a stronger material, or change "
                "several keys")
    return "feasible with " + " or ".join(
        f"springs.{spring_name}.{k} = {v:g} (now {v0:.4g})" for k, v0, v in changes) + \
        " (each alone, other keys unchanged)"
