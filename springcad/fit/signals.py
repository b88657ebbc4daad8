"""Per-sample signals shared by the torque model, the effects and the loop.

Everything a model term may depend on is computed once per record: time,
measured and smoothed deflection, torque, direction of motion, the deflection
at the last reversal, the optional encoder deflection and the cross-validation
fold of each sample. Units: s, rad, N·m.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.fit.data import BenchRecord
from springcad.fit.segment import Segmentation, noise_std


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
    def theta_trace(self) -> np.ndarray:
        """Deflection smoothed for time shifts (rad): a local quadratic over 60 ms,
        fitted within each run so a sharp turn is not rounded off.

        Shifting a rounded turn (a linear ramp's corner under a moving average)
        biased a time lag by 1 % (many standard errors on a long record); within
        a run the local quadratic follows linear and cosine motion alike.
        """
        from scipy.signal import savgol_filter

        width = max(5, int(round(0.06 * self.scales.sample_rate_hz)) | 1)
        out = self.theta_smooth.copy()
        runs = self.runs
        bounds = np.concatenate([[0], np.flatnonzero(np.diff(runs) != 0) + 1, [self.n]])
        for a, b in zip(bounds[:-1], bounds[1:]):
            w = min(width, (b - a) | 1 if (b - a) % 2 else b - a - 1)
            if w >= 5:
                out[a:b] = savgol_filter(self.theta[a:b], w, 2, mode="interp")
        return out

    @functools.cached_property
    def from_reversal(self) -> np.ndarray:
        """Per-sample |smoothed deflection - deflection at the last reversal| (rad).

        The reversal angle is read on a deflection averaged over 3 samples only: the
        20 ms smoothing cuts a sharp turn (a linear ramp's) short by a quarter of
        the speed times 20 ms, as much as friction's presliding angle at 0.3 rad/s;
        the noise left on it is one value per run, which the clustered intervals
        see.
        """
        runs = self.runs
        start = np.flatnonzero(np.diff(runs, prepend=runs[0] - 1) != 0)
        first = start[np.searchsorted(start, np.arange(self.n), side="right") - 1]
        light = ndimage.uniform_filter1d(self.theta, size=3, mode="nearest")
        turn = np.where(first > 0, light[first], self.reversal)
        return np.abs(self.theta_smooth - turn)

    @functools.cached_property
    def since_turn_s(self) -> np.ndarray:
        """Per-sample time since the motion last reversed (since the start before the first turn), s."""
        runs = self.runs
        start = np.flatnonzero(np.diff(runs, prepend=runs[0] - 1) != 0)
        first = start[np.searchsorted(start, np.arange(self.n), side="right") - 1]
        return self.t - self.t[first]

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


#: a residual may swing for this long (s) either side of a reversal for the model's reasons
TURN_GUARD_S = 0.025
#: ...and while the deflection is this close to the turn's, as a fraction of the largest
TURN_GUARD_BAND = 0.01


def find_glitches(x: np.ndarray, threshold: float = 6.0, width: int = 9,
                  guard: np.ndarray | None = None) -> np.ndarray:
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
