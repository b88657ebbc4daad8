"""Design splines as a few low-degree Bezier pieces, for a solid a downstream CAD can measure.

A flank spline of the design (:class:`springcad.design.curves.Spline`, a C2
cubic through ~40 fit points) extruded as one face holds ~40 knot spans. OCC's
volume integral (what FreeCAD's ``Shape.Volume`` and most OCC-based CAD call,
``BRepGProp::VolumeProperties`` without a tolerance) integrates each face
with one Gauss rule of 8 to 18 points over its whole parameter range, so on
such a face it was 0.2 % to 8 % off the true volume, and moved with the
tolerance asked. A single polynomial piece of degree ``d`` gives an integrand
of degree ``2 d - 1``, integrated exactly by 8 Gauss points for ``d <= 8``.

So each spline is replaced by pieces of degree :data:`BEZIER_DEGREE`, each
matching the spline's points and first derivatives at its ends (C1 joins, as
smooth to the eye and to a CAM as the spline) and fitted by least squares in
between; a piece runs over as many of the spline's knot spans as keep it
within :data:`FIT_TOL_MM` (measured at :data:`CHECK_SAMPLES` points at equal
parameter, which bounds the distance from above). A single knot span is a
cubic, so one span always fits exactly. Units: mm.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from springcad.design.curves import Spline

#: largest distance from the design spline to its Bezier pieces (mm): the DXF's biarc tolerance
FIT_TOL_MM = 5e-4
#: degree of each piece: <= 8, so an 8-point Gauss rule integrates a flank face exactly
BEZIER_DEGREE = 8
#: fit samples per knot span of the design spline
FIT_SAMPLES_PER_SPAN = 12
#: points at which each piece's deviation is checked
CHECK_SAMPLES = 400


def bernstein(degree: int, t: np.ndarray) -> np.ndarray:
    """(len(t), degree + 1) Bernstein basis at ``t`` in [0, 1]."""
    t = np.asarray(t, dtype=float)[:, None]
    i = np.arange(degree + 1)
    binom = np.array([math.comb(degree, k) for k in i], dtype=float)
    return binom * t ** i * (1.0 - t) ** (degree - i)


def fit_piece(cs, ua: float, ub: float, degree: int, n_fit: int) -> tuple[np.ndarray, float]:
    """Bezier control points (degree + 1, 2) of the spline ``cs`` on [ua, ub] and its
    largest deviation (mm).

    The two end points and end derivatives are kept (C1); the other control points
    fit ``n_fit`` equally spaced spline points by least squares.
    """
    span = ub - ua
    t = np.linspace(0.0, 1.0, n_fit)
    pts = cs(ua + span * t)
    d0, d1 = cs(np.array([ua, ub]), 1) * span  # d/dt of the spline at the ends
    fixed = {0: pts[0], 1: pts[0] + d0 / degree, degree - 1: pts[-1] - d1 / degree,
             degree: pts[-1]}
    basis = bernstein(degree, t)
    free = [i for i in range(degree + 1) if i not in fixed]
    rhs = pts - sum(basis[:, [i]] * p for i, p in fixed.items())
    ctrl = np.zeros((degree + 1, 2))
    for i, p in fixed.items():
        ctrl[i] = p
    ctrl[free] = np.linalg.lstsq(basis[:, free], rhs, rcond=None)[0]
    tc = np.linspace(0.0, 1.0, CHECK_SAMPLES)
    dev = float(np.max(np.linalg.norm(bernstein(degree, tc) @ ctrl - cs(ua + span * tc),
                                      axis=1)))
    return ctrl, dev


def _fit_spline(seg: Spline, tol_mm: float, degree: int) -> tuple[tuple[np.ndarray, ...], float]:
    """Pieces of one spline, each as long (in knot spans) as the tolerance allows."""
    knots, cs = seg._spline
    pieces, worst, a = [], 0.0, 0
    last = len(knots) - 1
    while a < last:
        lo, hi, best = a + 1, last, None
        while lo <= hi:  # the farthest knot a piece from knot a reaches within tolerance
            b = (lo + hi) // 2
            ctrl, dev = fit_piece(cs, knots[a], knots[b], degree,
                                  FIT_SAMPLES_PER_SPAN * (b - a) + degree + 1)
            if dev <= tol_mm:
                best, lo = (b, ctrl, dev), b + 1
            else:
                hi = b - 1
        if best is None:  # one span is a cubic: only round-off can get here
            raise ValueError(f"spline from {seg.start} cannot be matched by degree-{degree} "
                             f"pieces within {tol_mm:g} mm")
        a, ctrl, dev = best
        pieces.append(ctrl)
        worst = max(worst, dev)
    return tuple(pieces), worst


@functools.lru_cache(maxsize=256)
def _canonical_fit(seg: Spline, tol_mm: float, degree: int):
    return _fit_spline(seg, tol_mm, degree)


def _rotation(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def spline_beziers(seg: Spline, tol_mm: float = FIT_TOL_MM,
                   degree: int = BEZIER_DEGREE) -> tuple[list[np.ndarray], float]:
    """Bezier pieces of a design spline, in curve order.

    The spline is fitted in its own frame (first point at the origin, chord along
    +x; coordinates rounded to 1e-9 mm), so the N rotated copies of a flank on a
    ring are fitted once.

    Returns:
        (control points per piece, each (degree + 1, 2) in mm; largest deviation mm).
    """
    p = np.asarray(seg.points, dtype=float)
    origin = p[0]
    chord = p[-1] - origin
    rot = _rotation(-math.atan2(chord[1], chord[0]))  # world -> canonical

    def canon(v):
        return tuple(float(x) for x in np.round(rot @ np.asarray(v, dtype=float), 9))

    local = Spline(tuple(canon(q - origin) for q in p), canon(seg.start_tangent),
                   canon(seg.end_tangent))
    pieces, worst = _canonical_fit(local, tol_mm, degree)
    return [c @ rot + origin for c in pieces], worst  # canonical -> world: rot^T
