"""The verified stress at the critical points, region by region, for the duty (issue 21).

The verification's peak (:attr:`fea.study.ModelRun.peak_stress_MPa`) is the 2D
Richardson-extrapolated peak times the 3D factor of the peaks (3D peak / 2D peak on
the finer 3D check level). When the 2D peak and the 3D peak sit in different regions
(paper S2: the 2D peak at the root fillet on the fine levels, the 3D peak on the
flank), that product is the root's 2D stress times the flank's 3D factor: a stress at
no point of the part (1220 MPa where the flank is 1194 and the root 1183).

Fatigue is judged point by point, so :func:`region_peaks_MPa` gives every region of
the cut faces its own value: the Richardson extrapolation of the region's peak over
the 2D levels (:func:`fea.convergence.richardson`; the finest value when the region's
sequence does not converge monotonically) times the region's own 3D factor (its 3D
peak over its 2D peak on the finer 3D check level). The design-side stress model is
calibrated to the same values (:mod:`fea.calibrate`).

Units: MPa.
"""

from __future__ import annotations

from fea import convergence as cv


def _extrapolated(run, region: str) -> float:
    """Richardson extrapolation of one region's peak over the study's levels (MPa)."""
    results = run.study.results
    values = [r.peak_by_region_MPa.get(region, 0.0) for r in results]
    if len(values) < 3 or min(values) <= 0.0:
        return values[-1]
    ratios = None
    if not run.faces:  # not nested (pytetwild): ratios from the DOF counts, as the study
        n = [r.dofs for r in results[-3:]]
        ratios = ((n[1] / n[0]) ** (1 / 3), (n[2] / n[1]) ** (1 / 3))
    return cv.richardson(values, cv.FORMAL_ORDER["stress"], ratios=ratios).extrapolated


def _factor_3d(run, region: str) -> float:
    """The region's 3D factor: its 3D peak over its 2D peak on the finer 3D check level
    (1 without a 3D check)."""
    if not run.check3d:
        return 1.0
    level = len(run.check3d) - 1
    two = run.base2d[level].peak_by_region_MPa.get(region, 0.0)
    three = run.check3d[level].peak_by_region_MPa.get(region, 0.0)
    return three / two if two > 0.0 and three > 0.0 else 1.0


def region_peaks_MPa(run, skip: str = "sector cut") -> dict[str, float]:
    """Per region of the finest mesh, the von Mises peak at theta_max as verified (MPa):
    the region's 2D Richardson extrapolation x its own 3D factor. Regions whose name
    contains ``skip`` (the sector's artificial cut faces) are left out."""
    return {region: _extrapolated(run, region) * _factor_3d(run, region)
            for region in run.study.finest.peak_by_region_MPa if skip not in region}
