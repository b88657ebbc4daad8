"""Segment a bench record into loading and unloading half-cycles.

The paper's protocol (Fig. 4) drives the spring from rest to +A, back to rest,
to -A and back, with A = 4°, 8°, … 24°. A *half-cycle* is a stretch where
``|θ|`` only grows (loading) or only shrinks (unloading) on one side of zero;
an *excursion* is a loading half-cycle followed by the unloading half-cycle on
the same side (0 → ±A → 0): one loading–unloading cycle of the energy-loss
definition in Table I.

Turning points are found on a smoothed deflection with a hysteresis threshold
well above the deflection noise, so noise near a turning point does not split
a ramp.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.errors import DataError
from springcad.fit.data import BenchRecord

#: A record must hold at least this many complete loading–unloading cycles.
MIN_CYCLES = 2

_trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has only trapz


@dataclass(frozen=True)
class HalfCycle:
    """Samples ``start:stop`` where ``|θ|`` grows (loading) or shrinks (unloading).

    Attributes:
        start: first sample index.
        stop: one past the last sample index.
        kind: ``"loading"`` or ``"unloading"``.
        sign: +1 for positive deflection, -1 for negative.
        amplitude_rad: largest ``|θ|`` in the half-cycle (smoothed, rad).
    """

    start: int
    stop: int
    kind: str
    sign: int
    amplitude_rad: float


@dataclass(frozen=True)
class Excursion:
    """One loading–unloading cycle on one side of zero (0 → ±A → 0)."""

    loading: HalfCycle
    unloading: HalfCycle

    @property
    def sign(self) -> int:
        return self.loading.sign

    @property
    def amplitude_rad(self) -> float:
        return max(self.loading.amplitude_rad, self.unloading.amplitude_rad)

    @property
    def start(self) -> int:
        return self.loading.start

    @property
    def stop(self) -> int:
        return self.unloading.stop


@dataclass(frozen=True)
class Segmentation:
    """Half-cycles of a record plus per-sample motion signals.

    Attributes:
        half_cycles: all half-cycles in time order.
        excursions: complete loading–unloading cycles in time order.
        turning_points: sample indices where the motion reverses.
        direction: per-sample direction of motion (+1 deflection growing, -1 shrinking).
        reversal_rad: per-sample smoothed deflection at the last reversal (rad).
        theta_smooth_rad: smoothed deflection (rad).
        rate_rad_per_s: smoothed deflection rate (rad/s).
        fold: per-sample cross-validation fold (0 or 1), assigned per excursion
            so that both folds hold both signs and a spread of amplitudes.
        virgin: per-sample flag, True before the first reversal (the motion
            starts from rest, not from a reversal).
        threshold_rad: reversal threshold used (rad).
    """

    half_cycles: tuple[HalfCycle, ...]
    excursions: tuple[Excursion, ...]
    turning_points: np.ndarray
    direction: np.ndarray
    reversal_rad: np.ndarray
    theta_smooth_rad: np.ndarray
    rate_rad_per_s: np.ndarray
    fold: np.ndarray
    virgin: np.ndarray
    threshold_rad: float

    @property
    def amplitudes_rad(self) -> list[float]:
        """Amplitude of each excursion (rad)."""
        return [e.amplitude_rad for e in self.excursions]


#: a reversal before the first cycle turn or after the last is a turn of the motion (friction
#: reverses there) when it moves the smoothed deflection by this many deflection noise levels,
#: or this share of its range if more (``_end_turns``)
END_TURN_NOISE = 5.0
END_TURN_RANGE = 1e-3
#: half window (s) over which a turn is judged sharp or smooth and a sharp one's vertex fitted
SHARP_TURN_WINDOW_S = 0.06


def noise_std(x: np.ndarray, lag: int = 1) -> float:
    """White-noise standard deviation from lagged differences, robust to glitches.

    ``d = x[i+lag] - x[i]`` removes slow structure; differences beyond five
    robust (MAD) standard deviations are dropped as glitches or steps, and the
    RMS of the rest over ``sqrt(2)`` is returned. The RMS (not the MAD) is kept
    so that noise whose level varies along the record is not underestimated.
    """
    if x.size <= lag + 1:
        return float(np.std(x))
    d = x[lag:] - x[:-lag]
    d = d - np.median(d)
    mad = 1.4826 * float(np.median(np.abs(d)))
    if mad == 0.0:
        return 0.0
    kept = d[np.abs(d) <= 5.0 * mad]
    return float(np.sqrt(np.mean(kept * kept) / 2.0))


def smooth(x: np.ndarray, sample_rate_hz: float, window_s: float = 0.02) -> np.ndarray:
    """Median (5 samples) then moving-average (``window_s``) smoothing."""
    width = max(3, int(round(window_s * sample_rate_hz)) | 1)
    y = ndimage.median_filter(x, size=5, mode="nearest")
    return ndimage.uniform_filter1d(y, size=width, mode="nearest")


def segment(record: BenchRecord) -> Segmentation:
    """Split a record into half-cycles and excursions.

    Args:
        record: validated bench record.

    Returns:
        The segmentation.

    Raises:
        DataError: fewer than :data:`MIN_CYCLES` complete loading–unloading cycles.
    """
    theta = record.deflection_rad
    t = record.time_s
    n = theta.size
    ts = smooth(theta, record.sample_rate_hz)
    sigma = noise_std(theta)
    threshold = max(10.0 * sigma, 0.02 * float(np.ptp(ts)))
    tps = _end_turns(ts, _turning_points(ts, threshold),
                     max(END_TURN_NOISE * sigma, END_TURN_RANGE * float(np.ptp(ts))))
    tps = _refine_sharp_turns(theta, tps,
                              max(8, int(round(SHARP_TURN_WINDOW_S * record.sample_rate_hz))))
    bounds = np.concatenate([[0], tps, [n - 1]])
    direction = np.ones(n, dtype=np.int8)
    reversal = np.empty(n)
    halves: list[HalfCycle] = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        d = 1 if ts[b] >= ts[a] else -1
        stop = b + 1 if b == n - 1 else b
        direction[a:stop] = d
        reversal[a:stop] = ts[a]
        halves.extend(_split_run(ts, a, stop, d, threshold))
    excursions = []
    i = 0
    while i < len(halves) - 1:
        h0, h1 = halves[i], halves[i + 1]
        if (h0.kind == "loading" and h1.kind == "unloading" and h0.sign == h1.sign
                and h0.stop == h1.start):
            excursions.append(Excursion(h0, h1))
            i += 2
        else:
            i += 1
    if len(excursions) < MIN_CYCLES:
        raise DataError(
            f"{record.source}: too few cycles: found {len(excursions)} complete loading-unloading "
            f"cycle(s) (0 -> +/-A -> 0 with A above {threshold:.3g} rad); need at least {MIN_CYCLES}")
    fold = _folds(excursions, n)
    rate = np.gradient(ts, t)
    virgin = np.arange(n) < (tps[0] if tps.size else n)
    return Segmentation(tuple(halves), tuple(excursions), tps, direction, reversal, ts, rate,
                        fold, virgin, threshold)


def _turning_points(x: np.ndarray, threshold: float) -> np.ndarray:
    """Indices of alternating extremes that are followed by a move of ``threshold``."""
    tps = []
    mode = 0  # +1 looking for a maximum, -1 for a minimum, 0 undecided
    ext_i = 0
    start = x[0]
    for i, v in enumerate(x):
        if mode == 0:
            if v - start > threshold:
                mode, ext_i = 1, i
            elif start - v > threshold:
                mode, ext_i = -1, i
        elif mode == 1:
            if v > x[ext_i]:
                ext_i = i
            elif x[ext_i] - v > threshold:
                tps.append(ext_i)
                mode, ext_i = -1, i
        else:
            if v < x[ext_i]:
                ext_i = i
            elif v - x[ext_i] > threshold:
                tps.append(ext_i)
                mode, ext_i = 1, i
    return np.asarray(tps, dtype=int)


def _end_turns(ts: np.ndarray, tps: np.ndarray, small: float) -> np.ndarray:
    """Turning points ``tps`` with the reversals smaller than the cycle threshold but
    larger than ``small`` (rad) added before the first and after the last of them.

    A cycle's turn must move the deflection by the cycle threshold, but friction
    reverses at every reversal it sees: a fade-in (a multisine or a jog starting with a
    few mrad of motion either way) that was read as one run from rest gave the friction
    the direction of the motion that followed, the wrong sign over the whole fade-in
    (0.8 N·m, ten noise levels, on a 5 mrad wiggle before a multisine's first cycle).
    Inside the record the runs between cycle turns stay as they are (a run there goes
    from one extreme to the next)."""
    if tps.size == 0:
        return tps
    head = _turning_points(ts[:tps[0] + 1], small)
    head = head[(head > 0) & (head < tps[0])]
    tail = _turning_points(ts[tps[-1]:], small) + tps[-1]
    tail = tail[(tail > tps[-1]) & (tail < ts.size - 1)]
    return np.concatenate([head, tps, tail]).astype(int)


def _sharp_turn(theta: np.ndarray, i: int, half: int) -> bool:
    """Whether the motion turns sharply at sample ``i``: over ``half`` samples either side,
    a V (two straight lines meeting near ``i``) fits ``theta`` better than a parabola.

    A linear ramp that reverses at once is a V; a sine's or a cosine ramp's turn is a
    parabola to within its curvature's change. Too few samples: sharp (cut, the safe
    side).
    """
    x, y = _window(theta, i, half)
    if y.size < 8:
        return True
    quad = np.column_stack([np.ones_like(x), x, x * x])
    sse_quad = float(np.sum((y - quad @ np.linalg.lstsq(quad, y, rcond=None)[0]) ** 2))
    # V with its vertex anywhere within a quarter window of i
    return bool(_v_sse(x, y, np.arange(-(half // 4), half // 4 + 1, dtype=float)).min() < sse_quad)


def _vertex(theta: np.ndarray, i: int, half: int, step: float = 0.25) -> float:
    """Sample position (fractional) of the vertex of the V fitting ``theta`` best over ``half``
    samples either side of ``i``, searched within half a window of ``i`` in ``step``s."""
    x, y = _window(theta, i, half)
    vertex = np.arange(-(half // 2), half // 2 + 1e-9, step)
    return i + float(vertex[int(np.argmin(_v_sse(x, y, vertex)))])


def _window(theta: np.ndarray, i: int, half: int) -> tuple[np.ndarray, np.ndarray]:
    """Sample offsets from ``i`` and values of ``theta`` within ``half`` samples of ``i``."""
    lo, hi = max(i - half, 0), min(i + half, theta.size)
    return np.arange(lo, hi, dtype=float) - i, theta[lo:hi]


def _v_sse(x: np.ndarray, y: np.ndarray, vertex: np.ndarray) -> np.ndarray:
    """Squared error of the least-squares V (a level and a slope either side) with its vertex
    at each of ``vertex`` (units of ``x``) fitted to ``y``, all at once."""
    left = np.minimum(x[None, :] - vertex[:, None], 0.0)
    right = np.maximum(x[None, :] - vertex[:, None], 0.0)
    basis = np.stack([np.ones_like(left), left, right], axis=2)        # (vertex, sample, 3)
    gram = np.einsum("vsi,vsj->vij", basis, basis) + 1e-9 * np.eye(3)
    coef = np.linalg.solve(gram, np.einsum("vsi,s->vi", basis, y)[..., None])[..., 0]
    return np.sum((y[None, :] - np.einsum("vsi,vi->vs", basis, coef)) ** 2, axis=1)


def _refine_sharp_turns(theta: np.ndarray, tps: np.ndarray, half: int) -> np.ndarray:
    """Turning points moved, at sharp turns, to the vertex of a V fitted across the turn.

    The extreme of the 20 ms moving average sits on the rounded top of a linear ramp's
    corner, where the noise moves it by a few samples; friction reverses at the corner
    itself, over a presliding angle that a ramp at 0.3 rad/s crosses in a few samples,
    so a turn a few samples off biased friction and a lag fitted with it by half a
    standard error and more (``bench/fit_coverage.py --heldout``). The V uses every
    sample within ``half`` of the turn on both sides. Smooth turns (a sine's, a cosine
    ramp's) keep the extreme: there the motion pauses and the instant matters little.
    """
    if tps.size == 0:
        return tps
    bounds = np.concatenate([[0], tps, [theta.size - 1]])
    out = tps.copy()
    for k, i in enumerate(tps):
        h = int(min(half, (i - bounds[k]) // 2, (bounds[k + 2] - i) // 2))
        if h >= 8 and _sharp_turn(theta, int(i), h):
            v = int(round(_vertex(theta, int(i), h)))
            out[k] = int(np.clip(v, bounds[k] + 1, bounds[k + 2] - 1))
    return out


def _split_run(ts: np.ndarray, a: int, b: int, d: int, threshold: float) -> list[HalfCycle]:
    """Split a monotone run ``a:b`` moving in direction ``d`` at its zero crossing."""
    seg = ts[a:b]
    if seg.size == 0:
        return []
    after = np.flatnonzero(d * seg >= 0)
    k = a + (int(after[0]) if after.size else seg.size)
    out = []
    if k > a:  # part on the side opposite to the motion: |θ| shrinks
        amp = float(np.max(np.abs(ts[a:k])))
        if amp > threshold:
            out.append(HalfCycle(a, k, "unloading", -d, amp))
    if b > k:  # part on the side of the motion: |θ| grows
        amp = float(np.max(np.abs(ts[k:b])))
        if amp > threshold:
            out.append(HalfCycle(k, b, "loading", d, amp))
    return out


def _folds(excursions: list[Excursion], n: int) -> np.ndarray:
    """Cross-validation fold per sample: excursions go A, B, B, A, A, B, …

    Both folds then hold positive and negative excursions and a spread of
    amplitudes. Samples outside any excursion take the fold of the next one.
    """
    label = np.full(n, -1, dtype=np.int8)
    for k, e in enumerate(excursions):
        label[e.start:e.stop] = (k // 2 + k % 2) % 2
    # fill gaps backwards (from the next excursion), then the tail forwards
    idx = np.where(label >= 0, np.arange(n), n)
    nxt = np.minimum.accumulate(idx[::-1])[::-1]
    filled = np.where(nxt < n, label[np.minimum(nxt, n - 1)], -1)
    prev = np.where(label >= 0, np.arange(n), -1)
    prev = np.maximum.accumulate(prev)
    filled = np.where(filled >= 0, filled, label[np.maximum(prev, 0)])
    return filled.astype(np.int8)


@dataclass(frozen=True)
class CycleEnergy:
    """Energy of one loading–unloading cycle (excursion).

    Attributes:
        sign: +1 or -1 (side of zero).
        amplitude_rad: largest |θ| (rad).
        stored_J: ``∫τ dθ`` over the loading half-cycle (J = N·m·rad).
        returned_J: ``-∫τ dθ`` over the unloading half-cycle (J).
        loss_pct: ``(stored - returned) / stored`` in percent (loop area over
            energy stored on loading, as in Table I).
    """

    sign: int
    amplitude_rad: float
    stored_J: float
    returned_J: float
    loss_pct: float


def cycle_energies(record: BenchRecord, seg: Segmentation) -> list[CycleEnergy]:
    """Stored and returned energy of every excursion, by trapezoidal integration."""
    th, tq = record.deflection_rad, record.torque_Nm
    out = []
    for e in seg.excursions:
        ld = slice(e.loading.start, e.loading.stop + 1)
        ul = slice(e.unloading.start, e.unloading.stop + 1)
        stored = float(_trapezoid(tq[ld], th[ld]))
        returned = -float(_trapezoid(tq[ul], th[ul]))
        loss = 100.0 * (stored - returned) / stored if stored > 0 else float("nan")
        out.append(CycleEnergy(e.sign, e.amplitude_rad, stored, returned, loss))
    return out


def energy_loss_pct(cycles: list[CycleEnergy], rel_tol: float = 0.1) -> float:
    """Energy loss (%) of the largest-amplitude cycles, averaged over them.

    Cycles within ``rel_tol`` of the largest amplitude count (both signs), as
    the paper reports the loss at the largest tested deflection.
    """
    a_max = max(c.amplitude_rad for c in cycles)
    sel = [c for c in cycles if c.amplitude_rad >= (1.0 - rel_tol) * a_max and c.stored_J > 0]
    stored = sum(c.stored_J for c in sel)
    returned = sum(c.returned_J for c in sel)
    return 100.0 * (stored - returned) / stored
