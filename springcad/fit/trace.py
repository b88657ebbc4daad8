"""The deflection trace: the smooth motion a time shift, a damper and friction's travel see.

The measured deflection carries the encoder's noise; a model term that shifts it in time
or differentiates it would read that noise as structure. The trace is a local cubic fitted
along each run of the motion, cut at the corners of holds and at sharp turns (a linear
ramp's), and cut again where it misses the measured deflection (a motion that changes
speed at once). :class:`DeflectionTrace` holds it, its pieces and holds, and its rate;
:class:`springcad.fit.signals.Signals` builds one per record and shares it with its views.
Units: s, rad.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import ndimage

from springcad.fit.segment import _sharp_turn


#: window of :attr:`DeflectionTrace.values`: this fraction of each run's duration...
TRACE_RUN_FRACTION = 0.15
#: ...within these bounds (s), and at most this fraction of the moving piece it smooths
TRACE_WINDOW_S = (0.06, 0.3)
TRACE_PIECE_FRACTION = 0.5
#: the trace is cut where the running median of what it misses of the deflection stands this
#: many of its noise levels out (``DeflectionTrace._fit_block``), at most this many times deep
TRACE_MISS_Z = 12.0
TRACE_MEND_DEPTH = 3
#: window of the smoothed deflection (``springcad.fit.segment.smooth``'s default), s
SMOOTH_WINDOW_S = 0.02
#: the motion has left a turn's angle where the smoothed deflection is this many
#: deflection noise levels away from it (see ``DeflectionTrace._pieces``)
HOLD_BAND_NOISE = 5.0
#: a cut is a jump of the trace where its step departs from the range of the two pieces'
#: rates over the sample by more than this share of the larger rate (``DeflectionTrace.rate``)
RATE_JUMP_SLACK = 0.25
#: sampling is irregular where an interval departs from the median by this share of it (the
#: round-off of timestamps written to a CSV is far below, a jitter or a dropped sample above)
IRREGULAR_SHARE = 0.01


class DeflectionTrace:
    """The trace of one record's deflection (see the module docstring).

    Args:
        t: sample times (s).
        theta: measured deflection (rad).
        theta_smooth: deflection smoothed over ``SMOOTH_WINDOW_S`` (rad).
        runs: per-sample index of the run between reversals of the motion.
        scales: the record's magnitudes (:class:`springcad.fit.signals.Scales`: sample
            rate, deflection noise and largest deflection are read).
    """

    def __init__(self, t: np.ndarray, theta: np.ndarray, theta_smooth: np.ndarray,
                 runs: np.ndarray, scales) -> None:
        self.t, self.theta, self.theta_smooth, self.runs, self.scales = (
            t, theta, theta_smooth, runs, scales)
        self.n = int(t.size)

    @functools.cached_property
    def values(self) -> np.ndarray:
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
        w_min = max(5, int(round(TRACE_WINDOW_S[0] * self.scales.sample_rate_hz)))
        out = self.theta_smooth.copy()
        blocks = self.blocks
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
        self.__dict__["mend_cuts"] = tuple(sorted(mended))
        return out

    @functools.cached_property
    def mend_cuts(self) -> tuple[int, ...]:
        """Samples where :attr:`values` was cut inside a moving block, at a corner it
        missed (:meth:`_fit_block`); the piece after the cut starts there."""
        self.values  # noqa: B018 (sets it)
        return self.__dict__["mend_cuts"]

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
                fits[wp] = self._local_cubic(lo, hi, wp)
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

    def _local_cubic(self, lo: int, hi: int, w: int) -> np.ndarray:
        """The local cubic over ``w`` samples of the deflection ``[lo, hi)`` (rad), read at
        each sample's own time.

        A Savitzky-Golay cubic runs over the samples' order, not their times. Where the
        sampling is irregular (timestamps jittered by a fraction of a period, samples
        dropped) the deflection at a sample read early or late by ``δ`` is off the smooth
        motion by its speed times ``δ``, and the cubic smooths that away as noise: the
        trace holds the deflection at the smoothed time ``t̄`` of each sample, not at its
        own. Read again at its own time, to first order, ``θ(t) ≈ θ(t̄) + θ'·(t − t̄)``
        (``t̄`` and ``θ'`` by the same cubic; a pure delay read on the index-smoothed trace
        lost to a first-order filter on the raw deflection by 248 of criterion on a
        record jittered by ±0.2 of a period). On regular sampling ``t = t̄`` and the
        cubic is used as it is.
        """
        from scipy.signal import savgol_filter

        y = savgol_filter(self.theta[lo:hi], w, 3, mode="interp")
        if not self.irregular:
            return y
        t = self.t[lo:hi]
        t_bar = savgol_filter(t, w, 3, mode="interp")
        slope = (savgol_filter(self.theta[lo:hi], w, 3, deriv=1, mode="interp")
                 / savgol_filter(t, w, 3, deriv=1, mode="interp"))
        return y + slope * (t - t_bar)

    @functools.cached_property
    def irregular(self) -> bool:
        """Whether the sampling is irregular and its timestamps are the samples' own: a
        sample interval departs from the median by more than ``IRREGULAR_SHARE`` of it,
        and the deflection reads the timestamps: the cubic over ``TRACE_WINDOW_S[0]``,
        read at each sample's time (:meth:`_local_cubic`), misses the measured deflection
        by less than read in sample order. Timestamps rounded when written (true times
        regular) depart from the smooth time by their rounding, which the deflection
        does not follow: read there, the cubic would miss it by more."""
        dt = np.diff(self.t)
        if dt.size < 16:
            return False
        step = float(np.median(dt))
        if not np.max(np.abs(dt - step)) > IRREGULAR_SHARE * step:
            return False
        from scipy.signal import savgol_filter

        w = max(5, int(round(TRACE_WINDOW_S[0] * self.scales.sample_rate_hz))) | 1
        if w > self.theta.size:
            return False
        y = savgol_filter(self.theta, w, 3, mode="interp")
        slope = (savgol_filter(self.theta, w, 3, deriv=1, mode="interp")
                 / savgol_filter(self.t, w, 3, deriv=1, mode="interp"))
        timed = y + slope * (self.t - savgol_filter(self.t, w, 3, mode="interp"))
        return bool(np.sum((self.theta - timed) ** 2) < np.sum((self.theta - y) ** 2))

    @functools.cached_property
    def in_hold(self) -> np.ndarray:
        """Per-sample flag: in a hold of :attr:`values` (its trace is the hold's mean)."""
        out = np.zeros(self.n, dtype=bool)
        for block in self.blocks:
            if block[0][2]:
                out[block[0][0]:block[-1][1]] = True
        return out

    @functools.cached_property
    def blocks(self) -> list:
        """Pieces ``(start, end, hold, window)`` of :attr:`values`, joined into blocks
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
    def rate(self) -> np.ndarray:
        """Deflection rate (rad/s) of :attr:`values`: the speed a damper or a
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
        trace = self.values
        out = np.gradient(trace, self.t)
        own = np.zeros(self.n)
        cuts = []
        mended = self.mend_cuts
        for block in self.blocks:
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
            # a cut the trace jumps across: its step over the cut's sample lies outside what
            # the two pieces' own rates carry over it (between the one and the other) by more
            # than ``RATE_JUMP_SLACK`` of the larger rate about it. A continuous trace, a V
            # turn (-v then +v) and a ramp leaving a hold (0 then v) step within that range
            # and keep their central differences; a cut inside a moving block (a corner the
            # cubic missed, :meth:`_fit_block`) leaves a step of a fraction of a mrad along or
            # against the motion, which the central differences read as two samples of a
            # speed neither piece has (0.2 rad/s at 0.45 rad/s on a manual jog: a damper's
            # torque put 5 noise levels there, taken for two glitches)
            dt = self.t[c] - self.t[c - 1]
            near = np.max(np.abs(np.stack([own[c - 2], own[c - 1], own[c], own[c + 1]])), axis=0)
            step = trace[c] - trace[c - 1]
            low = np.minimum(own[c - 1], own[c]) * dt
            high = np.maximum(own[c - 1], own[c]) * dt
            outside = np.maximum(low - step, step - high)
            c = c[outside > RATE_JUMP_SLACK * near * dt]
        if c.size:
            # the two samples either side read the mean of their neighbours' rates within
            # their own pieces (the central difference a continuous trace would give)
            out[c - 2], out[c + 1] = own[c - 2], own[c + 1]
            out[c - 1] = 0.25 * own[c - 2] + 0.5 * own[c - 1] + 0.25 * own[c]
            out[c] = 0.25 * own[c - 1] + 0.5 * own[c] + 0.25 * own[c + 1]
        return out



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
