"""Discretisation error, stated: Richardson extrapolation over nested mesh levels.

Meshes of :func:`fea.mesh.mesh_levels` are uniform refinements (every element
edge halves, ratio r = 2), so for a quantity f on levels 1 (coarse), 2, 3 (fine):

    observed order   p = ln((f2 - f1) / (f3 - f2)) / ln 2
    extrapolated     f_inf = f3 + (f3 - f2) / (2^p - 1)
    error estimate   GCI = 1.25 |f3 - f2| / (2^p - 1) / |f3|   (Roache's grid
                     convergence index, three-grid safety factor 1.25)

The order used for the error is the observed one clamped to
[``min_order``, formal order]: a rate above the formal one (4 for the energy /
stiffness of quadratic elements, 2 for their stresses) is luck, not a licence
to claim a smaller error. Oscillating sequences get no extrapolation: the
finest value is reported with the last change as its error. A sequence whose
changes grow is flagged "diverging": if its last change is below 1 % it is
nodal sampling noise of a peak and the spread is its error; above 1 % it is
taken as a stress singularity (a corner) and the error is not finite.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: formal convergence orders of quadratic elements: stiffness (energy) and stress
FORMAL_ORDER = {"stiffness": 4.0, "stress": 2.0}
SAFETY_FACTOR = 1.25
RATIO = 2.0
#: relative change on the finest level above which a non-converging sequence has no finite error
DIVERGENCE_LIMIT = 0.01


@dataclass(frozen=True)
class Extrapolation:
    """Richardson extrapolation of one quantity over three or more levels.

    Attributes:
        values: the quantity on each level, coarse to fine.
        extrapolated: the mesh-converged estimate (finest value when not monotone).
        observed_order: p from the last three levels (nan when not monotone).
        order_used: p used for the extrapolation and error.
        error: estimated relative discretisation error of ``extrapolated`` (-).
        behaviour: "monotone", "oscillatory", "converged" or "diverging".
    """

    values: tuple[float, ...]
    extrapolated: float
    observed_order: float
    order_used: float
    error: float
    behaviour: str

    def to_dict(self, unit_scale: float = 1.0) -> dict:
        return {"values": [v * unit_scale for v in self.values],
                "extrapolated": self.extrapolated * unit_scale,
                "observed_order": self.observed_order, "order_used": self.order_used,
                "error_pct": 100.0 * self.error, "behaviour": self.behaviour}


def richardson(values, formal_order: float, min_order: float = 0.5,
               ratio: float = RATIO) -> Extrapolation:
    """Extrapolate a sequence of values on uniformly refined meshes (coarse to fine).

    Raises:
        ValueError: fewer than three values.
    """
    v = [float(x) for x in values]
    if len(v) < 3:
        raise ValueError(f"Richardson extrapolation needs three mesh levels, got {len(v)}")
    f1, f2, f3 = v[-3:]
    e21, e32 = f2 - f1, f3 - f2
    scale = max(abs(f3), 1e-300)
    if abs(e32) <= 1e-13 * scale:
        return Extrapolation(tuple(v), f3, math.nan, formal_order, abs(e32) / scale, "converged")
    s = e21 / e32
    if s > 1.0:  # same sign, shrinking changes
        p = math.log(s) / math.log(ratio)
        pu = min(max(p, min_order), formal_order)
        ext = f3 + e32 / (ratio ** pu - 1.0)
        err = SAFETY_FACTOR * abs(e32) / (ratio ** pu - 1.0) / scale
        return Extrapolation(tuple(v), ext, p, pu, err, "monotone")
    # not monotone: no extrapolation; the spread of the last three levels is the error
    err = SAFETY_FACTOR * max(abs(e21), abs(e32)) / scale
    if s < 0.0 and abs(e32) < abs(e21):  # oscillating with shrinking amplitude
        return Extrapolation(tuple(v), f3, math.nan, math.nan, err, "oscillatory")
    # growing changes: a singularity if they are large, sampling noise if they are small
    return Extrapolation(tuple(v), f3, math.nan, math.nan,
                         err if abs(e32) / scale < DIVERGENCE_LIMIT else math.inf, "diverging")


@dataclass(frozen=True)
class ConvergenceStudy:
    """Stiffness and peak stress over the mesh levels of one model.

    Attributes:
        model: "2d" (plane stress) or "3d" (quadratic tets).
        levels: per level: dofs, elements, stiffness (N*mm/rad), nodal and
            integration-point peak von Mises (MPa), timings.
        stiffness: :class:`Extrapolation` of K (N*mm/rad).
        peak_stress: :class:`Extrapolation` of the nodal peak von Mises (MPa).
        results: the :class:`~fea.results.StaticResult` of every level.
    """

    model: str
    stiffness: Extrapolation
    peak_stress: Extrapolation
    results: tuple

    @property
    def finest(self):
        return self.results[-1]

    def to_list(self) -> list[dict]:
        """The ``convergence[]`` entries of ``fea.json`` (N*m/rad, MPa)."""
        return [{"model": self.model, "level": r.level, "dofs": r.dofs,
                 "n_elements": r.n_elements,
                 "stiffness_Nm_per_rad": r.stiffness_Nmm_per_rad / 1000.0,
                 "peak_von_mises_MPa": r.peak_von_mises_MPa,
                 "peak_ip_von_mises_MPa": r.peak_ip_von_mises_MPa,
                 "peak_location_mm": list(r.peak_location_mm), "peak_region": r.peak_region,
                 "residual": r.solve_info.residual, "solver": r.solve_info.method,
                 "timings_s": dict(r.timings_s)} for r in self.results]

    def to_dict(self) -> dict:
        return {"model": self.model,
                "stiffness_Nm_per_rad": self.stiffness.to_dict(1e-3),
                "peak_von_mises_MPa": self.peak_stress.to_dict()}


def study(results, model: str) -> ConvergenceStudy:
    """Richardson extrapolation of K and nodal peak stress over solved levels."""
    k = richardson([r.stiffness_Nmm_per_rad for r in results], FORMAL_ORDER["stiffness"])
    s = richardson([r.peak_von_mises_MPa for r in results], FORMAL_ORDER["stress"])
    return ConvergenceStudy(model=model, stiffness=k, peak_stress=s, results=tuple(results))
