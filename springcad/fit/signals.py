"""Per-sample signals shared by the torque model, the effects and the loop.

Everything a model term may depend on is computed once per record: time,
measured and smoothed deflection, torque, direction of motion, the deflection
at the last reversal, the optional encoder deflection and the cross-validation
fold of each sample. Units: s, rad, N·m.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.fit.data import BenchRecord
from springcad.fit.segment import Segmentation, _sharp_turn, noise_std


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
    def rate_trace(self) -> np.ndarray:
        """Deflection rate (rad/s) of :attr:`theta_trace`: the speed a damper or a
        velocity-regularised friction sees.

        Central differences of the trace, but never across a cut where the trace
        jumps: a hold's trace is its mean and the cubic of a cosine ramp after it starts
        a fraction of a mrad away, so a difference across that cut read as a speed of
        0.2 rad/s for two samples at every start from rest (a damper put 8 noise levels
        there, taken for two glitches on cosine ramps). There each piece is
        differentiated on its own and the two samples beside the cut read the mean of
        the rates about them (a step there made a fading friction delayed by a lag a
        step in the lag).
        """
        trace = self.theta_trace
        out = np.gradient(trace, self.t)
        own = np.zeros(self.n)
        cuts = []
        mended = self._mend_cuts
        for block in self._trace_blocks:
            c0, d0 = block[0][0], block[-1][1]
            cuts.append(c0)
            if block[0][2]:
                continue
            # the trace is fitted on each side of a corner it was cut at on its own
            inner = [k for k in mended if c0 < k < d0]
            cuts.extend(inner)
            for a, b in zip([c0, *inner], [*inner, d0]):
                if b - a >= 2:
                    own[a:b] = np.gradient(trace[a:b], self.t[a:b])
        c = np.array(sorted(k for k in cuts if 2 <= k <= self.n - 2), dtype=int)
        if c.size:
            # a cut the trace jumps across: it moves there by more than twice what the
            # rates about it carry over a sample (a continuous trace, a V turn, a linear
            # ramp leaving a hold, keeps its central differences)
            dt = self.t[c] - self.t[c - 1]
            near = np.max(np.abs(np.stack([own[c - 2], own[c - 1], own[c], own[c + 1]])), axis=0)
            c = c[np.abs(trace[c] - trace[c - 1]) > 2.0 * near * dt]
        if c.size:
            # the two samples either side read the mean of their neighbours' rates within
            # their own pieces (the central difference a continuous trace would give)
            out[c - 2], out[c + 1] = own[c - 2], own[c + 1]
            out[c - 1] = 0.25 * own[c - 2] + 0.5 * own[c - 1] + 0.25 * own[c]
            out[c] = 0.25 * own[c - 1] + 0.5 * own[c] + 0.25 * own[c + 1]
        return out

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
    def theta_trace(self) -> np.ndarray:
        """Deflection smoothed for time shifts (rad): a local cubic over ``TRACE_RUN_FRACTION``
        of each run's duration (between ``TRACE_WINDOW_S`` bounds), fitted across the
        motion wherever it is smooth and cut only where it is not.

        The cuts are the corners of holds (:meth:`_pieces`; a hold's own trace is its
        mean) and *sharp* turns and corners, where a linear ramp reverses or stops at
        once (a V fits better than a parabola, :func:`_sharp_turn`; the corner may lie
        a few samples from the run's end, where :meth:`_pieces` finds it): a fit across either would
        round it off, and shifting a rounded turn biased a time lag by 1 % (many
        standard errors on a long record). A smooth turn (a sine's, a cosine ramp's)
        is fitted across, with samples on both sides: a fit cut there reads the turn
        angle at the end of a one-sided window, where its noise is largest, and the
        presliding friction, which starts at that angle, and a lag fitted with it were
        biased by up to 0.8 standard errors and their intervals covered 83 % of the
        time on sine sweeps (``bench/fit_coverage.py --heldout``).

        A cubic, not a quadratic: at the end of a cut piece the fit is one-sided, and
        a quadratic there missed the peak of a 2 Hz sine by 1.7 mrad (0.2 mrad for the
        cubic). A window that grows with the run: the noise the trace keeps sits in
        the regressor of a time lag and of friction's travel since the turn (errors in
        variables), and on slow ramps a fixed 60 ms window biased a lag and the
        friction fitted with it by 3 standard errors in the same direction; over 15 %
        of a run the cubic still follows a sine's curvature.
        """
        from scipy.signal import savgol_filter

        w_min = max(5, int(round(TRACE_WINDOW_S[0] * self.scales.sample_rate_hz)))
        out = self.theta_smooth.copy()
        blocks = self._trace_blocks
        mended: list[int] = []
        for block in blocks:
            c0, d0 = block[0][0], block[-1][1]
            if block[0][2]:
                out[c0:d0] = float(np.mean(self.theta[c0:d0]))
                continue
            # a ramp between holds inside a run (a staircase's step) is shorter than the
            # run: the cubic's window stays within a share of what is fitted
            cap = max(w_min, int(TRACE_PIECE_FRACTION * (d0 - c0))) | 1
            self._fit_block(out, block, c0, d0, cap, w_min, TRACE_MEND_DEPTH, mended)
        self.__dict__["_mend_cuts"] = tuple(sorted(mended))
        return out

    @functools.cached_property
    def _mend_cuts(self) -> tuple[int, ...]:
        """Samples where :attr:`theta_trace` was cut inside a moving block, at a corner it
        missed (:meth:`_fit_block`); the piece after the cut starts there."""
        self.theta_trace  # noqa: B018 (sets it)
        return self.__dict__["_mend_cuts"]

    def _fit_block(self, out: np.ndarray, block: list, lo: int, hi: int, cap: int, w_min: int,
                   depth: int, mended: list[int]) -> None:
        """Fill ``out[lo:hi]`` (rad) with the local cubic of the moving ``block``'s pieces
        (each its own window) fitted over ``[lo, hi)`` as one; then cut it where it misses
        the measured deflection and fit each side alone.

        A motion may change speed at once without turning or holding (a chirp that ends
        at 5 rad/s into a ramp from rest): a cubic fitted across that corner rounds it
        off (by 19 mrad, 500 noise levels of its 20 ms median), and a time lag shifts the
        rounded corner into a torque swing of 35 torque noise levels. The running
        median over ``w_min`` samples of what the trace misses, against its noise,
        finds such a corner (a median: a spike in the angle channel is no corner);
        the cut is the break of a parabola with a slope break fitted around it
        (:func:`_slope_break`), at most ``depth`` cuts deep, kept where the two sides
        fitted alone follow the deflection about it at least twice as closely (squared);
        each cut kept is appended to ``mended``.
        """
        from scipy.signal import savgol_filter

        fits: dict[int, np.ndarray] = {}
        longest = (hi - lo) if (hi - lo) % 2 else hi - lo - 1
        for c, d, _, w in block:
            c, d = max(c, lo), min(d, hi)
            if c >= d:
                continue
            wp = min(w, longest, cap)
            if wp < 5:
                out[c:d] = self.theta_smooth[c:d]
                continue
            if wp not in fits:
                fits[wp] = savgol_filter(self.theta[lo:hi], wp, 3, mode="interp")
            out[c:d] = fits[wp][c - lo:d - lo]
        sigma = self.scales.theta_noise
        if depth <= 0 or hi - lo < 4 * w_min or sigma <= 0.0:
            return
        dev = ndimage.median_filter(self.theta[lo:hi] - out[lo:hi], w_min | 1, mode="nearest")
        z = np.abs(dev) / (1.25 * sigma / math.sqrt(w_min))
        # within a window of the piece's ends the cubic is one-sided and the corners of holds
        # and turns are placed by their own fits (``_pieces``): a corner is sought inside
        z[:w_min] = 0.0
        z[-w_min:] = 0.0
        worst = int(np.argmax(z))
        if z[worst] < TRACE_MISS_Z:
            return
        cut = lo + _slope_break(self.theta[lo:hi], worst, 2 * w_min)
        if not lo + w_min <= cut <= hi - w_min:
            return
        near = slice(max(lo, cut - 2 * w_min), min(hi, cut + 2 * w_min))
        before, kept = float(np.sum((self.theta[near] - out[near]) ** 2)), list(mended)
        saved = out[lo:hi].copy()
        mended.append(cut)
        for a, b in ((lo, cut), (cut, hi)):
            self._fit_block(out, block, a, b, cap, w_min, depth - 1, mended)
        if float(np.sum((self.theta[near] - out[near]) ** 2)) >= 0.5 * before:
            # the sides fitted alone follow the deflection about the cut no better: no
            # corner there (a cubic starting at a cut placed off a corner misses by more)
            out[lo:hi] = saved
            mended[:] = kept

    @functools.cached_property
    def in_hold(self) -> np.ndarray:
        """Per-sample flag: in a hold of :attr:`theta_trace` (its trace is the hold's mean)."""
        out = np.zeros(self.n, dtype=bool)
        for block in self._trace_blocks:
            if block[0][2]:
                out[block[0][0]:block[-1][1]] = True
        return out

    @functools.cached_property
    def _trace_blocks(self) -> list:
        """Pieces ``(start, end, hold, window)`` of :attr:`theta_trace`, joined into blocks
        fitted as one."""
        rate = self.scales.sample_rate_hz
        w_min = max(5, int(round(TRACE_WINDOW_S[0] * rate)))
        w_max = max(w_min, int(round(TRACE_WINDOW_S[1] * rate)))
        bounds = np.concatenate([[0], np.flatnonzero(np.diff(self.runs) != 0) + 1, [self.n]])
        # pieces (start, end, hold, window), joined into blocks fitted as one
        blocks: list[list[tuple[int, int, bool, int]]] = []
        for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
            w = min(max(w_min, int(TRACE_RUN_FRACTION * (b - a))), w_max) | 1
            for c, d, hold in self._pieces(a, b, 2 * w_min):
                prev = blocks[-1][-1] if blocks else None
                joined = (prev is not None and not hold and not prev[2]
                          and not _sharp_turn(self.theta, c, min(w, prev[3])))
                if joined:
                    blocks[-1].append((c, d, hold, w))
                else:
                    blocks.append([(c, d, hold, w)])
        return blocks

    def _pieces(self, a: int, b: int, min_hold: int) -> list[tuple[int, int, bool]]:
        """Run ``[a, b)`` cut where the motion leaves the turn's angle after a hold, and
        where it arrives at the next turn's angle before one.

        A hold's corners are sharp (a motor stops and starts), and a fit across
        one rounds it off as a fit across a turn would; the turning point itself
        falls anywhere in the hold. The motion has left (or not yet reached) the
        turn's angle where the smoothed deflection is more than
        ``HOLD_BAND_NOISE`` noise levels from it; the corner is placed by a hinge
        fit (:func:`_corner`) within that stretch. Runs that start or end moving
        give corners at the run's own ends, and no cut. A piece cut off at the
        run's start or end is a hold (``True``: its trace is its mean, and the
        travel since the turn stays zero on it) when it lasts ``min_hold`` samples
        and its two halves agree within the noise; a slow turn (a cosine ramp's)
        drifts and stays a fitted piece.
        """
        if b - a < 4 * min_hold:
            return [(a, b, False)]
        ts = self.theta_smooth
        band = max(HOLD_BAND_NOISE * self.scales.theta_noise, 1e-3 * self.scales.theta_ref)
        reach = self._smooth_reach
        cuts = []
        left = np.flatnonzero(np.abs(ts[a:b] - ts[a]) > band)
        if left.size and left[0] >= 3:
            cuts.append(a + _corner(self.theta[a:b], int(left[0]), True, min_hold, reach))
        came = np.flatnonzero(np.abs(ts[a:b] - ts[b - 1]) > band)
        if came.size and b - a - 1 - came[-1] >= 3:
            cuts.append(a + _corner(self.theta[a:b], int(came[-1]), False, min_hold, reach))
        points = [a, *sorted(c for c in cuts if a + 2 < c < b - 2), b]
        out = []
        for k, (c, d) in enumerate(zip(points[:-1], points[1:])):
            first = k == 0 and c == a and d in cuts
            end = first or (d == b and c in cuts and k > 0)
            # judged away from its corner, which may fall within the motion's first (or
            # last) few slow samples of a ramp that starts (or stops) from rest
            core = (c, d - reach) if first else (c + reach, d)
            hold = bool(end and d - c >= min_hold and self._flat(*core, min_hold - reach))
            out.extend([(c, d, True)] if hold else self._inner_holds(c, d, min_hold, band))
        return out

    def _inner_holds(self, a: int, b: int, min_hold: int,
                     band: float) -> list[tuple[int, int, bool]]:
        """Moving piece ``[a, b)`` cut at the holds in it, each hold a piece of its own:
        a staircase stops between its steps without turning, and a turn found at the
        end of a ramp leaves the hold after it inside the next run. Corners by the
        hinge fit as at the ends of a run. A cubic fitted across a stop rounds both
        corners off (a 0.3 s window over a 0.15 s cosine step missed it by 20 mrad)."""
        from scipy.ndimage import maximum_filter1d, minimum_filter1d

        if b - a < 2 * min_hold:
            return [(a, b, False)]
        ts = self.theta_smooth[a:b]
        reach = self._smooth_reach
        spread = maximum_filter1d(ts, min_hold) - minimum_filter1d(ts, min_hold)
        still = spread < band
        edges = np.flatnonzero(np.diff(np.concatenate([[0], still.astype(int), [0]])))
        out, start = [], 0
        for s0, s1 in zip(edges[::2], edges[1::2]):
            if s1 - s0 < min_hold or s0 < start:
                continue
            # the motion arrives where it last stood farther than the band from the hold's
            # angle, and leaves where it first does again (as at the ends of a run)
            level = float(np.median(ts[s0:s1]))
            far = np.abs(ts - level) > band
            before = np.flatnonzero(far[start:s0]) + start
            after = np.flatnonzero(far[s1:]) + s1
            c = (_corner(self.theta[a:b], int(before[-1]), False, min_hold, reach)
                 if before.size else start)
            d = (_corner(self.theta[a:b], int(after[0]), True, min_hold, reach)
                 if after.size else b - a)
            if not start <= c < d <= b - a or not self._flat(a + s0, a + s1, min_hold):
                continue
            if c > start:
                out.append((a + start, a + c, False))
            out.append((a + c, a + d, True))
            start = d
        if start < b - a:
            out.append((a + start, b, False))
        return out

    @property
    def _smooth_reach(self) -> int:
        """Half the window of the smoothed deflection, in samples, and two more."""
        return int(round(0.5 * SMOOTH_WINDOW_S * self.scales.sample_rate_hz)) + 2

    def _flat(self, c: int, d: int, min_hold: int) -> bool:
        """Whether samples ``[c, d)`` hold still: long enough, halves equal within noise."""
        n = d - c
        if n < min_hold:
            return False
        h = n // 2
        diff = abs(float(np.mean(self.theta[c:c + h]) - np.mean(self.theta[c + h:d])))
        return diff < 4.0 * self.scales.theta_noise * math.sqrt(4.0 / n)

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


#: window of :attr:`Signals.theta_trace`: this fraction of each run's duration...
TRACE_RUN_FRACTION = 0.15
#: ...within these bounds (s), and at most this fraction of the moving piece it smooths
TRACE_WINDOW_S = (0.06, 0.3)
TRACE_PIECE_FRACTION = 0.5
#: the trace is cut where the running median of what it misses of the deflection stands this
#: many of its noise levels out (``Signals._mend_corners``), at most this many times deep
TRACE_MISS_Z = 12.0
TRACE_MEND_DEPTH = 3
#: window of the smoothed deflection (``springcad.fit.segment.smooth``'s default), s
SMOOTH_WINDOW_S = 0.02
#: the signals derived from the measured deflection (cached), shared by :attr:`Signals.on_trace`
_DERIVED = ("theta_trace", "_mend_cuts", "rate_trace", "_trace_blocks", "in_hold", "from_reversal",
            "since_turn_s", "swing", "near_turn")
#: the motion has left a turn's angle where the smoothed deflection is this many
#: deflection noise levels away from it (see ``Signals._pieces``)
HOLD_BAND_NOISE = 5.0
#: a residual may swing for this long (s) either side of a reversal for the model's reasons
TURN_GUARD_S = 0.025
#: ...and while the deflection is this close to the turn's, as a fraction of the largest
TURN_GUARD_BAND = 0.01


def _slope_break(theta: np.ndarray, near: int, half: int) -> int:
    """Index (into ``theta``) of the break of a cubic whose slope and curvature break at j,
    ``a + b x + c x² + d x³ + e·max(x - j, 0) + f·max(x - j, 0)²``, fitting ``theta`` best
    within ``half`` samples of
    ``near``: where a motion changes speed at once; the break's own sample (on both lines,
    so the piece after the break starts there)."""
    lo, hi = max(near - half, 0), min(near + half + 1, theta.size)
    js = np.arange(lo + 2, hi - 2)
    if js.size == 0:
        return near
    y = theta[lo:hi]
    i = np.arange(lo, hi, dtype=float)
    x = (i - float(near)) / max(half, 1)
    kink = np.maximum(i[None, :] - js[:, None].astype(float), 0.0) / max(half, 1)
    base = np.broadcast_to(np.stack([np.ones_like(x), x, x * x, x ** 3], axis=1), (js.size, x.size, 4))
    a = np.concatenate([base, kink[:, :, None], (kink * kink)[:, :, None]], axis=2)
    coef = np.linalg.pinv(a) @ y
    sse = np.sum((y[None, :] - np.einsum("cnk,ck->cn", a, coef)) ** 2, axis=1)
    return int(js[int(np.argmin(sse))])


def _corner(theta: np.ndarray, near: int, leaving: bool, half: int, reach: int = 0) -> int:
    """Index of the corner between a hold and motion at or before ``near + reach``
    (leaving a hold) or at or after ``near - reach`` (arriving at one): the break of
    the hinge (constant on the hold side, a quadratic on the other) fitting
    ``theta`` best within ``half`` samples; the first sample on the far side of the
    break. ``near`` found on the smoothed deflection (a centred moving average) is
    up to half its window early when leaving and late when arriving: ``reach``
    (samples) lets the break fall that far beyond it."""
    if leaving:
        lo, hi = max(near - 2 * half, 0), min(near + reach + half // 2, theta.size)
        candidates = range(lo + 2, min(near + reach + 1, hi - 2))
    else:
        lo, hi = max(near - reach - half // 2, 0), min(near + 2 * half, theta.size)
        candidates = range(max(near - reach, lo + 2), hi - 2)
    y = theta[lo:hi]
    i = np.arange(lo, hi, dtype=float)
    js = np.arange(candidates.start, candidates.stop)
    if js.size == 0:
        return near if leaving else near + 1
    # every break at once: a motion may start (or stop) at a finite speed (a linear ramp)
    # or from rest with a finite acceleration (a cosine ramp): a line and a parabola from
    # the break, least squares by the pseudo-inverse of each candidate's design
    x = i[None, :] - js[:, None].astype(float)
    x = np.maximum(x, 0.0) if leaving else np.minimum(x, 0.0)
    a = np.stack([np.ones_like(x), x, x * x], axis=2)
    coef = np.linalg.pinv(a) @ y
    sse = np.sum((y[None, :] - np.einsum("cnk,ck->cn", a, coef)) ** 2, axis=1)
    where = int(js[int(np.argmin(sse))])
    return where if leaving else where + 1


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
