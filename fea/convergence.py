"""Discretisation error, stated: Richardson extrapolation over nested mesh levels.

Meshes of :func:`fea.mesh.mesh_face_levels` are uniform refinements (every element
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

from springcad.units import NMM_PER_NM

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


def _order(e21: float, e32: float, r21: float, r32: float) -> float:
    """Observed order from the changes e21 = f2 - f1, e32 = f3 - f2 (level 1 coarsest) and
    the refinement ratios r21 = h1/h2, r32 = h2/h3.

    Equal ratios: p = ln(e21/e32) / ln r. Otherwise the fixed-point iteration
    of Celik et al. (2008, J. Fluids Eng. 130 078001), written for coarse-to-fine
    numbering: p = |ln|e21/e32| + q(p)| / ln r32, q = ln((r32^p - s)/(r21^p - s)),
    s = sign(e21/e32).
    """
    ratio = e21 / e32
    p = math.log(abs(ratio)) / math.log(r32)
    if abs(r21 - r32) < 1e-12:
        return p
    sgn = 1.0 if ratio > 0 else -1.0
    for _ in range(200):
        q = math.log((r32 ** p - sgn) / (r21 ** p - sgn))
        p_new = abs(math.log(abs(ratio)) + q) / math.log(r32)
        if abs(p_new - p) < 1e-12:
            return p_new
        p = p_new
    return p


def richardson(values, formal_order: float, min_order: float = 0.5,
               ratio: float = RATIO, ratios: tuple[float, float] | None = None) -> Extrapolation:
    """Extrapolate a sequence of values on refined meshes (coarse to fine).

    Args:
        values: the quantity per level.
        formal_order: the discretisation's theoretical order for this quantity.
        min_order: the smallest order used for the error estimate.
        ratio: refinement ratio h_coarse / h_fine of nested uniform levels.
        ratios: (r21, r32) for non-nested meshes (e.g. (N2/N1)^(1/3) from DOF counts).

    Raises:
        ValueError: fewer than three values.
    """
    v = [float(x) for x in values]
    if len(v) < 3:
        raise ValueError(f"Richardson extrapolation needs three mesh levels, got {len(v)}")
    r21, r32 = ratios if ratios is not None else (ratio, ratio)
    f1, f2, f3 = v[-3:]
    e21, e32 = f2 - f1, f3 - f2
    scale = max(abs(f3), 1e-300)
    if abs(e32) <= 1e-13 * scale:
        return Extrapolation(tuple(v), f3, math.nan, formal_order, abs(e32) / scale, "converged")
    s = e21 / e32
    if s > 1.0 or (ratios is not None and s > 0 and abs(e32) < abs(e21)):  # shrinking changes
        p = _order(e21, e32, r21, r32)
        pu = min(max(p, min_order), formal_order)
        ext = f3 + e32 / (r32 ** pu - 1.0)
        err = SAFETY_FACTOR * abs(e32) / (r32 ** pu - 1.0) / scale
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
                 "stiffness_Nm_per_rad": r.stiffness_Nmm_per_rad / NMM_PER_NM,
                 "peak_von_mises_MPa": r.peak_von_mises_MPa,
                 "peak_ip_von_mises_MPa": r.peak_ip_von_mises_MPa,
                 "peak_location_mm": list(r.peak_location_mm), "peak_region": r.peak_region,
                 "residual": r.solve_info.residual, "solver": r.solve_info.method,
                 "timings_s": dict(r.timings_s)} for r in self.results]

    def to_dict(self) -> dict:
        return {"model": self.model,
                "stiffness_Nm_per_rad": self.stiffness.to_dict(1.0 / NMM_PER_NM),
                "peak_von_mises_MPa": self.peak_stress.to_dict()}


def study(results, model: str, nested: bool = True) -> ConvergenceStudy:
    """Richardson extrapolation of K and nodal peak stress over solved levels.

    Nested levels have ratio 2; otherwise (pytetwild meshes) the ratios are
    estimated from the DOF counts, h ~ DOFs^(-1/3).
    """
    ratios = None
    if not nested:
        n = [r.dofs for r in results[-3:]]
        ratios = ((n[1] / n[0]) ** (1 / 3), (n[2] / n[1]) ** (1 / 3))
    k = richardson([r.stiffness_Nmm_per_rad for r in results], FORMAL_ORDER["stiffness"],
                   ratios=ratios)
    s = richardson([r.peak_von_mises_MPa for r in results], FORMAL_ORDER["stress"],
                   ratios=ratios)
    return ConvergenceStudy(model=model, stiffness=k, peak_stress=s, results=tuple(results))
