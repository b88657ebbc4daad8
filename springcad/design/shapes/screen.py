"""The shapes' vectorised twin: what the synthesis screen asks a shape about many disks.

:func:`springcad.synthesis.screening.screen_disks` designs thousands of disks at once
on arrays, step by step as the design search does. Where the design asks a shape to
size one flexure (:meth:`~springcad.design.shapes.base.FlexureShape.size`), the screen
asks :meth:`~springcad.design.shapes.base.FlexureShape.screen_size` for the rows still
open, and for the centreline the stress model reads,
:meth:`~springcad.design.shapes.base.FlexureShape.screen_centreline`. A shape whose
screen is not implemented is not offered to the synthesis. Units: mm, N, MPa, rad.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from springcad.design.layout import RIM_GAP_RATIO


def _rim_residual(rr, ro, n, rc, w0_of_length):
    return ro - rr - (2 * np.pi * rr / n - w0_of_length(rr - rc)) / RIM_GAP_RATIO


def rim_root_radius_rows(ro, n, rc, w0_of_length, iterations=48):
    """R_r from the rim rule (eq. 8, :func:`springcad.design.layout.rim_root_radius`) by
    bisection on arrays (mm); NaN where there is no bracket."""
    lo = rc * (1 + 1e-6) + 1e-6
    hi = np.array(ro, dtype=float)
    f_lo = _rim_residual(lo, ro, n, rc, w0_of_length)
    f_hi = _rim_residual(hi, ro, n, rc, w0_of_length)
    ok = (f_lo > 0) & (f_hi < 0)
    a, b = np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)
    for _ in range(iterations):
        mid = 0.5 * (a + b)
        pos = _rim_residual(mid, ro, n, rc, w0_of_length) > 0
        a, b = np.where(pos, mid, a), np.where(pos, b, mid)
    return 0.5 * (a + b)


@dataclass(frozen=True)
class ScreenRows:
    """The open rows of a screen, each a disk with its layout (arrays of one length).

    Attributes:
        K: disk stiffness (N*mm/rad). theta: deflection (rad).
        ro, z, rc: outer radius, thickness, contact radius (mm).
        sigma, E: beam stress and Young's modulus (MPa).
        n: flexure count. load: tip load (N). rr: the layout's root radius (mm).
        theta_s: the layout's straight limit (rad). rim_max: largest root radius the rim
            allows (mm).
        clearance_mm: clearance to the neighbour in a serpentine's tilt budget (mm).
        min_inside_radius_mm: smallest concave radius the wire cuts (mm).
    """

    K: np.ndarray
    theta: np.ndarray
    ro: np.ndarray
    z: np.ndarray
    rc: np.ndarray
    sigma: np.ndarray
    E: np.ndarray
    n: np.ndarray
    load: np.ndarray
    rr: np.ndarray
    theta_s: np.ndarray
    rim_max: np.ndarray
    clearance_mm: float
    min_inside_radius_mm: float

    def take(self, i) -> "ScreenRows":
        """The rows ``i`` (an index array) only."""
        arrays = {k: getattr(self, k)[i] for k in ("K", "theta", "ro", "z", "rc", "sigma", "E",
                                                   "n", "load", "rr", "theta_s", "rim_max")}
        return ScreenRows(**arrays, clearance_mm=self.clearance_mm,
                          min_inside_radius_mm=self.min_inside_radius_mm)


@dataclass
class ScreenSizing:
    """A shape's answer for the rows it was given (arrays over those rows).

    Attributes:
        taken: rows this shape sizes (the others go to the next shape tried).
        rr, theta_s: root radius (mm) and straight limit (rad) of the taken rows.
        w0: root width of the width law (mm). s: required area ratio (-).
        width_coef: the width law w^2 = width_coef (y - r_c) (mm; the stress model of the
            screen takes parabolic laws).
        beam_stress_MPa: the width law's largest beam stress at the deflection (MPa).
        failures: rows refused, as (reason, mask, value, limit): the reason a name of
            :data:`springcad.synthesis.screening.REASONS`.
    """

    taken: np.ndarray
    rr: np.ndarray
    theta_s: np.ndarray
    w0: np.ndarray
    s: np.ndarray
    width_coef: np.ndarray
    beam_stress_MPa: np.ndarray
    failures: list = field(default_factory=list)


@dataclass
class ScreenCentreline:
    """The centreline the design would build for the rows given (rows x stations of
    :data:`springcad.design.shapes.serpentine_screen.U`): x, y (mm), dx/dy and curvature
    (1/mm) of the stored spline, and the rows refused as in :class:`ScreenSizing`."""

    x: np.ndarray
    y: np.ndarray
    slope: np.ndarray
    kappa: np.ndarray
    failures: list = field(default_factory=list)
