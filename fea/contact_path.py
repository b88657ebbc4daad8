"""Continuation paths of the contact sector (:mod:`fea.contact`): along the cam angle from
rest or a given state (:class:`AnglePath`, with the contact onset :func:`onset_rad`), and along
the cam's dilation at +-theta_max, the profile tolerances' offsets (:func:`offset_path`).
Units: mm, rad.
"""

from __future__ import annotations

import math

import numpy as np

from fea.contact_solver import CamCurve, SectorContact, State
from springcad.errors import SolverError


class Stuck(SolverError):
    """No converged contact state beyond some cam angle."""


class AnglePath:
    """Solves along increasing |theta| in one direction with a linear predictor, halving a
    step that fails (a deep first penetration can push the ball out on the wrong side).
    Past a limit point (the ball snapping over a tooth tip) the state jumps: a step that
    fails down to 1/16 of a step is retried from the last state without predictor and
    with more iterations; if that fails too the path is stuck (:class:`Stuck`)."""

    def __init__(self, sc: SectorContact, sign: int, max_step_rad: float,
                 start: State | None = None):
        self.sc, self.sign, self.max_step = sc, sign, max_step_rad
        # not the rest state when the cam interferes
        self.state = start if start is not None else sc.solve(0.0, sc.rest())
        self.rate = None  # du / dtheta of the last increment
        self.jumps: list[float] = []

    def to(self, theta: float) -> State:
        while abs(theta - self.state.theta) > 1e-15:
            h = theta - self.state.theta
            h = math.copysign(min(abs(h), self.max_step), h)
            for _ in range(5):
                try:
                    st = self._try(self.state.theta + h, predict=True)
                    break
                except SolverError:
                    h *= 0.5
            else:
                try:
                    st = self._try(self.state.theta + h, predict=False, max_iter=80)
                except SolverError as err:
                    raise Stuck(f"no converged contact state beyond "
                                 f"{math.degrees(self.state.theta):+.3f} deg ({err})") from err
                self.jumps.append(st.theta)
                self.rate = None
                self.state = st
                continue
            self.rate = (st.u - self.state.u) / (st.theta - self.state.theta)
            self.state = st
        return self.state

    def _try(self, theta: float, predict: bool, max_iter: int = 40) -> State:
        pred = self.rate * (theta - self.state.theta) if predict and self.rate is not None \
            else None
        st = self.sc.solve(theta, self.state, pred, max_iter=max_iter)
        if self.sc.torque(st) * self.sign < -1e-3 * self.sc.stiffness_linear * abs(theta):
            raise SolverError("the contact solution pushes the ball against the cam rotation")
        return st


#: the cam dilation grows from 0 in steps of at most this (mm): a cam that interferes by
#: tens of um pinches the ball between both flanks, which Newton's method does not reach
#: from the undeformed ring in one step
OFFSET_STEP_MM = 0.005
#: halvings of a dilation step that fails before the continuation gives up
OFFSET_HALVINGS = 4


def dilated_rest(sc: SectorContact, curve: CamCurve, offset_mm: float) -> State:
    """The converged state at rest against the cam dilated by ``offset_mm``, the dilation
    applied in steps of at most :data:`OFFSET_STEP_MM`. Leaves ``sc.cam`` dilated."""
    st = sc.solve(0.0, sc.rest())
    m = max(1, math.ceil(abs(offset_mm) / OFFSET_STEP_MM)) if offset_mm > 0 else 1
    for k in range(1, m + 1):
        sc.cam = curve.dilated(offset_mm * k / m)
        st = sc.solve(0.0, st)
    return st


def continued_offset(sc: SectorContact, curve: CamCurve, offset_mm: float, theta: float,
               end: State) -> State | None:
    """The state at cam angle ``theta`` against the cam dilated by ``offset_mm``, continued
    from ``end`` (the nominal state there) in dilation steps of at most
    :data:`OFFSET_STEP_MM`, each Newton solve from the last state; None when a step fails
    :data:`OFFSET_HALVINGS` halvings in a row. Leaves ``sc.cam`` dilated."""
    st, done = end, 0.0
    h = math.copysign(OFFSET_STEP_MM, offset_mm)
    halvings = 0
    while abs(offset_mm - done) > 1e-12:
        step = math.copysign(min(abs(h), abs(offset_mm - done)), offset_mm)
        sc.cam = curve.dilated(done + step)
        try:
            st = sc.solve(theta, st)
        except SolverError:
            halvings += 1
            if halvings > OFFSET_HALVINGS:
                return None
            h *= 0.5
            continue
        done += step
    return st


def offset_path(sc: SectorContact, curve: CamCurve, offset_mm: float, sign: int,
                 theta_max: float, steps: int, end: State | None = None,
                 rest: dict | None = None) -> State:
    """The converged state at sign * theta_max against the cam dilated by ``offset_mm``.

    From the nominal end state ``end`` the dilation is continued at theta_max
    (:func:`continued_offset`), so the ball stays on the flank it is pushed by, as in a part
    whose profiles deviate: the state a path from rest reaches when it does not lose its
    way (default at 10 deg: from rest against the cam shrunk by 20 um, the ball was found
    one tooth on, with every gap off by up to 1 mm). Without ``end``, or when the
    continuation fails, the dilation is applied at rest (:func:`dilated_rest`) and the
    cam turned to the contact onset and on in ``steps`` steps, like the nominal sweep.
    Leaves ``sc.cam`` dilated.

    ``rest``: the states at rest by offset (or the SolverError their ramp raised) of the
    paths solved before: the ramp does not depend on the direction, so the two directions
    of one offset share it."""
    if end is not None:
        st = continued_offset(sc, curve, offset_mm, sign * theta_max, end)
        if st is not None:
            return st
    if rest is None:
        rest = {}
    if offset_mm not in rest:
        try:
            rest[offset_mm] = dilated_rest(sc, curve, offset_mm)
        except SolverError as err:
            rest[offset_mm] = err
            raise
    st = rest[offset_mm]
    if isinstance(st, SolverError):
        raise st
    sc.cam = curve.dilated(offset_mm)
    path = AnglePath(sc, sign, theta_max / steps, start=st)
    on = onset_rad(sc, sign, theta_max)
    if math.isfinite(on) and on != 0.0:
        path.to(on)
    return path.to(sign * theta_max)


def onset_rad(sc: SectorContact, sign: int, theta_max: float) -> float:
    """Cam angle (rad, signed) at which the undeformed flexure first touches the cam;
    0 when it touches at rest, NaN when it never does within theta_max."""
    u = np.zeros(2 * sc.basis.N)

    def gmin(a):
        return float(np.min(sc._gaps(u, a)[0]))

    if gmin(0.0) <= 0.0:
        return 0.0
    prev = 0.0
    for a in np.linspace(0.0, theta_max, 161)[1:]:
        if gmin(sign * a) <= 0.0:
            lo, hi = prev, a
            for _ in range(50):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if gmin(sign * mid) <= 0.0 else (mid, hi)
            return sign * hi
        prev = a
    return math.nan
