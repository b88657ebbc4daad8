"""Per-sample signals shared by the torque model, the effects and the loop.

Everything a model term may depend on is computed once per record: time,
measured and smoothed deflection, torque, direction of motion, the deflection
at the last reversal, the optional encoder deflection and the cross-validation
fold of each sample. Units: s, rad, N·m.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.fit.data import BenchRecord
from springcad.fit.segment import Segmentation, noise_std
from springcad.fit.trace import DeflectionTrace


@dataclass(frozen=True)
class Scales:
    """Magnitudes of a record, used to bound and start parameters.

    Attributes:
        theta_ref: largest |deflection| (rad, 99.9th percentile of the smoothed signal).
        torque_ref: half the measured torque range, glitches excluded (N·m).
        t0: first sample time (s).
        t_span: record duration (s).
        sample_rate_hz: median sample rate (Hz).
        theta_noise: deflection noise (rad): robust spread of the deflection
            about its smoothed curve. Features narrower than this (a backlash,
            say) cannot be resolved.
    """

    theta_ref: float
    torque_ref: float
    t0: float
    t_span: float
    sample_rate_hz: float
    theta_noise: float = 0.0


@dataclass(frozen=True)
class Signals:
    """Full-length per-sample arrays of one record (see module docstring).

    ``run`` numbers the stretches between reversals of the motion (a run goes
    from one turning point to the next); runs are the clusters of the
    parameter uncertainties, since model errors correlate along a run.
    """

    t: np.ndarray
    theta: np.ndarray
    theta_smooth: np.ndarray
    torque: np.ndarray
    direction: np.ndarray
    reversal: np.ndarray
    rate: np.ndarray
    encoder: np.ndarray | None
    fold: np.ndarray
    virgin: np.ndarray
    scales: Scales
    run: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.t.size)

    @property
    def runs(self) -> np.ndarray:
        """Per-sample index of the run between reversals (0 before the first turn)."""
        return self.run if self.run is not None else np.zeros(self.n, dtype=int)

    @functools.cached_property
    def _trace(self) -> DeflectionTrace:
        """The deflection trace of this record (:mod:`springcad.fit.trace`)."""
        return DeflectionTrace(self.t, self.theta, self.theta_smooth, self.runs, self.scales)

    @functools.cached_property
    def theta_trace(self) -> np.ndarray:
        """Deflection smoothed for time shifts (rad): the local cubic along each run, cut at
        holds, sharp turns and corners (:attr:`springcad.fit.trace.DeflectionTrace.values`)."""
        return self._trace.values

    @functools.cached_property
    def rate_trace(self) -> np.ndarray:
        """Deflection rate (rad/s) of :attr:`theta_trace`: the speed a damper or a
        velocity-regularised friction sees (:attr:`springcad.fit.trace.DeflectionTrace.rate`)."""
        return self._trace.rate

    @functools.cached_property
    def in_hold(self) -> np.ndarray:
        """Per-sample flag: in a hold of :attr:`theta_trace` (its trace is the hold's mean)."""
        return self._trace.in_hold

    @functools.cached_property
    def on_trace(self) -> "Signals":
        """These signals with the measured deflection replaced by its trace (the smooth
        motion), every derived signal shared: what a filter in the torque channel acts
        on. The noise of each sample's deflection is the encoder's, not the bench's
        torque: a model that filtered it would gain from averaging it away."""
        out = dataclasses.replace(self, theta=self.theta_trace)
        for name in _DERIVED:
            out.__dict__[name] = getattr(self, name)
        return out

    def with_torque(self, torque: np.ndarray) -> "Signals":
        """These signals with another torque (N·m, every sample): the signals derived from
        the deflection alone are computed once, here, and shared (the trace's corner search
        is most of a view's cost; every fit asks for them)."""
        out = dataclasses.replace(self, torque=torque)
        for name in _DERIVED:
            out.__dict__[name] = getattr(self, name)
        return out

    def shifted(self, h_rad: float) -> "Signals":
        """These signals with the measured deflection moved by ``h_rad`` (rad): the trace
        moves with it, every other signal derived from the deflection (turns, holds, travel
        since a turn) stays; shared, not computed again."""
        out = dataclasses.replace(self, theta=self.theta + h_rad)
        for name in _DERIVED:
            out.__dict__[name] = getattr(self, name)
        out.__dict__["theta_trace"] = self.theta_trace + h_rad
        return out

    @functools.cached_property
    def from_reversal(self) -> np.ndarray:
        """Per-sample travel since the last reversal (rad): |deflection - deflection at the turn|.

        After the first turn both are read on :attr:`theta_trace`, the local fit
        within the run: the 20 ms moving average cuts a sharp turn (a linear
        ramp's) short by a quarter of the speed times 20 ms, as much as
        friction's presliding angle at 0.3 rad/s, and read the travel as 2.6 mrad
        at the turn itself; that mismatch biased friction and a time lag fitted
        together by 1 to 2 standard errors (``bench/fit_coverage.py``). The noise
        left on the turn angle is one value per run, which the clustered intervals
        see. Before the first turn: the smoothed deflection from the rest angle.

        The turn's angle is the trace's farthest point against the run's motion:
        a turn found a few samples before a ramp arrives at a hold (the motion stops,
        then comes back) would otherwise put the turn short of the hold's angle, and
        the friction would flip only once the motion came back past it (a 1.7 mrad
        shortfall read as a 9 mrad presliding angle on a staircase with holds).
        """
        runs = self.runs
        start = np.flatnonzero(np.diff(runs, prepend=runs[0] - 1) != 0)
        k = np.searchsorted(start, np.arange(self.n), side="right") - 1
        first = start[k]
        trace = self.theta_trace
        end = np.concatenate([start[1:], [self.n]]) - 1
        moving = np.sign(trace[end] - trace[start])
        back = np.maximum.reduceat(-moving[k] * trace, start)
        turn = np.where(moving != 0, -moving * back, trace[start])
        # a run that starts in a hold turned at the hold's angle: the cubic fitted to the
        # ramp after it may overshoot it by a fraction of a mrad at its one-sided end, and
        # read as the turn that put a small travel (friction swung part-way) into the hold
        held = self.in_hold[start]
        turn = np.where(held, trace[start], turn)
        after = first > 0
        out = np.abs(self.theta_smooth - self.reversal)
        out[after] = np.abs(trace[after] - turn[k[after]])
        return out

    @functools.cached_property
    def since_turn_s(self) -> np.ndarray:
        """Per-sample time since the motion last reversed (since the start before the first turn), s."""
        runs = self.runs
        start = np.flatnonzero(np.diff(runs, prepend=runs[0] - 1) != 0)
        first = start[np.searchsorted(start, np.arange(self.n), side="right") - 1]
        return self.t - self.t[first]

    @functools.cached_property
    def run_travel(self) -> np.ndarray:
        """Per run (:attr:`runs`), the travel since its turn at its last sample (rad,
        :attr:`from_reversal` there): how far the friction was carried along before the
        next turn."""
        runs = self.runs
        last = np.flatnonzero(np.diff(runs, append=runs[-1] + 1) != 0)
        out = np.full(int(runs[-1]) + 1, np.inf)
        out[runs[last]] = self.from_reversal[last]
        return out

    @functools.cached_property
    def swing(self) -> np.ndarray:
        """Per-sample friction swing after the last turn: 1 from rest, 2 after a reversal."""
        return np.where(self.virgin, 1.0, 2.0)

    @functools.cached_property
    def near_turn(self) -> np.ndarray:
        """Per-sample flag: at a reversal of the motion, where the instant of the turn is
        uncertain: within ``TURN_GUARD_S`` of a detected reversal, or while the smoothed
        deflection is within ``TURN_GUARD_BAND`` of the largest deflection (or
        five deflection noise levels, if more) of the angle the run starts or ends at
        (a slow, rounded turn)."""
        runs = self.runs
        bounds = np.flatnonzero(np.diff(runs) != 0) + 1
        if bounds.size == 0:
            return np.zeros(self.n, dtype=bool)
        starts = self.t[bounds]
        k = np.clip(np.searchsorted(starts, self.t), 1, max(starts.size - 1, 1))
        gap = np.abs(self.t - starts[np.minimum(k, starts.size - 1)])
        gap = np.minimum(gap, np.abs(self.t - starts[k - 1]))
        first = np.concatenate([[0], bounds])
        last = np.concatenate([bounds - 1, [self.n - 1]])
        th = self.theta_smooth
        label = np.searchsorted(bounds, np.arange(self.n), side="right")
        band = max(TURN_GUARD_BAND * self.scales.theta_ref, 5.0 * self.scales.theta_noise)
        flat = ((np.abs(th - th[first][label]) < band) & (label > 0)) | (
            (np.abs(th - th[last][label]) < band) & (label < bounds.size))
        return (gap < TURN_GUARD_S) | flat

    @property
    def loading(self) -> np.ndarray:
        """Per-sample flag: |deflection| growing (moving away from zero)."""
        return self.direction * np.sign(self.theta_smooth) > 0


#: the signals derived from the measured deflection (cached), shared by the views of
#: :class:`Signals` (:attr:`Signals.on_trace`, :meth:`Signals.with_torque`, :meth:`Signals.shifted`)
_DERIVED = ("_trace", "theta_trace", "rate_trace", "in_hold", "from_reversal", "since_turn_s",
            "swing", "near_turn", "run_travel")
#: a residual may swing for this long (s) either side of a reversal for the model's reasons
TURN_GUARD_S = 0.025
#: ...and while the deflection is this close to the turn's, as a fraction of the largest
TURN_GUARD_BAND = 0.01


def find_glitches(x: np.ndarray, threshold: float = 6.0, width: int = 9,
                  guard: np.ndarray | None = None,
                  model: np.ndarray | None = None) -> np.ndarray:
    """Isolated spikes: samples far from the median of their neighbours.

    A sample is a glitch when it differs from the running median over ``width``
    samples by more than ``threshold`` noise standard deviations (noise from
    lagged differences). Slow structure, steps and the model's shortcomings
    follow the running median, so only short sensor glitches are flagged.

    Args:
        x: a signal or a residual, sampled uniformly.
        threshold: in noise standard deviations.
        width: running-median window (samples).
        guard: samples where a residual may swing for a few samples for a
            model's reasons (at a reversal of the motion, whose instant the model
            reads on a smoothed deflection): there a glitch must also stand out
            from both its neighbours by the threshold, as a one-sample spike does.
        model: the model torque behind residual ``x`` (N·m): at a guarded sample
            a glitch must also exceed the model's own step to its neighbours (a
            friction that flips at the turn, placed one sample early or late,
            leaves a one-sample error as large as its step).

    Returns:
        Boolean mask, True at glitches.
    """
    local = ndimage.median_filter(x, size=width, mode="nearest")
    dev = x - local
    sigma = noise_std(dev)
    if sigma == 0.0:
        return np.zeros(x.size, dtype=bool)
    out = np.abs(dev) > threshold * sigma
    if guard is not None and out.any():
        prev = np.concatenate([[x[0]], x[:-1]])
        nxt = np.concatenate([x[1:], [x[-1]]])
        sign = np.sign(dev)
        spike = np.minimum((x - prev) * sign, (x - nxt) * sign) > threshold * sigma
        if model is not None:
            step = np.maximum(np.abs(np.diff(model, prepend=model[0])),
                              np.abs(np.diff(model, append=model[-1])))
            spike &= np.abs(dev) > threshold * sigma + step
        out &= ~guard | spike
    return out


def torque_half_range(torque: np.ndarray) -> float:
    """Half the measured torque range (N·m), ignoring isolated glitches (NRMSE normaliser)."""
    clean = torque[~find_glitches(torque)]
    return 0.5 * float(np.ptp(clean))


def make_signals(record: BenchRecord, seg: Segmentation) -> Signals:
    """Collect the per-sample signals of a segmented record."""
    scales = Scales(
        theta_ref=float(np.percentile(np.abs(seg.theta_smooth_rad), 99.9)),
        torque_ref=torque_half_range(record.torque_Nm),
        t0=float(record.time_s[0]),
        t_span=record.duration_s,
        sample_rate_hz=record.sample_rate_hz,
        theta_noise=1.4826 * float(np.median(np.abs(record.deflection_rad - seg.theta_smooth_rad))),
    )
    run = np.searchsorted(seg.turning_points, np.arange(record.n_samples), side="right")
    return Signals(record.time_s, record.deflection_rad, seg.theta_smooth_rad, record.torque_Nm,
                   seg.direction.astype(float), seg.reversal_rad, seg.rate_rad_per_s,
                   record.encoder_deflection_rad, seg.fold, seg.virgin, scales, run)
