"""What is left in a residual: noise level, noise correlation, leftover structure.

A residual that only holds sensor noise has no mean in any bin of deflection or
of time. :mod:`springcad.fit.noise` estimates the noise level and its correlation
time from the residual's fast variations (white or coloured), :func:`flicker_noise`
its 1/f part (a strain-gauge amplifier's flicker noise, whose slow wander is noise,
not a zero that moves); :func:`residual_structure` compares bin means against that noise
and says whether structure remains that the model does not explain. Torque in
N·m, time in s, deflection in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage, stats

from springcad.fit.models import rmse
from springcad.fit.noise import coloured_noise_model
from springcad.fit.signals import Signals


def run_features(r: np.ndarray, idx: np.ndarray, sig: Signals, min_samples: int = 20) -> dict:
    """Per run (stretch between reversals): the residual's mean and its slope against deflection.

    A stiffness that changes during the test leaves slopes that differ between
    runs; a torque zero that jumps leaves means that do. Runs with fewer than
    ``min_samples`` samples are left out.

    Returns:
        Arrays ``t_s`` (mid-time of each run), ``n`` (samples), ``mean_Nm``,
        ``slope_Nm_per_rad`` and the sums ``n`` and ``sxx_rad2`` (spread of the
        deflection in the run) that set their noise variances.
    """
    runs = sig.runs[idx]
    labels, inv = np.unique(runs, return_inverse=True)
    n = np.bincount(inv).astype(float)
    theta = sig.theta_smooth[idx]
    t_mid = np.bincount(inv, weights=sig.t[idx]) / n
    th_mean = np.bincount(inv, weights=theta) / n
    dth = theta - th_mean[inv]
    sxx = np.bincount(inv, weights=dth * dth)
    mean = np.bincount(inv, weights=r) / n
    sxy = np.bincount(inv, weights=dth * r)
    slope = np.where(sxx > 0, sxy / np.where(sxx > 0, sxx, 1.0), 0.0)
    ok = n >= min_samples
    return {"t_s": t_mid[ok], "n": n[ok], "mean_Nm": mean[ok], "slope_Nm_per_rad": slope[ok],
            "sxx_rad2": sxx[ok], "amplitude_rad": np.abs(th_mean[ok]) + np.sqrt(
                np.maximum(3.0 * sxx[ok] / n[ok], 0.0))}


def periodogram(x: np.ndarray, sample_rate_hz: float, min_cycles: float = 20.0) -> dict:
    """Amplitude spectrum of ``x`` against a local noise level, for periodic structure.

    Each Fourier bin's power is compared with the running median of the
    powers around it (±50 bins), so coloured noise (camera-rate deflection
    noise, say) does not pass for a peak; for noise, power over that level is
    exponentially distributed, which gives the p-value of the largest peak
    after a Bonferroni correction for the number of bins searched.
    Frequencies below ``min_cycles`` cycles per record are not searched (slow
    structure is the business of the time tests).

    Returns:
        ``frequency_hz``, ``amplitude`` (sine amplitude per bin), ``level``
        (local noise amplitude), ``peak_hz``, ``peak_amplitude``, ``p_value``.
    """
    n = x.size
    spec = np.fft.rfft(x - x.mean())
    power = np.abs(spec) ** 2
    freq = np.fft.rfftfreq(n, 1.0 / sample_rate_hz)
    lo = int(math.ceil(min_cycles))
    if power.size <= lo + 10:
        return {"frequency_hz": freq, "amplitude": np.zeros_like(freq), "level": np.zeros_like(freq),
                "peak_hz": 0.0, "peak_amplitude": 0.0, "p_value": 1.0, "line_ms": 0.0}
    level = ndimage.median_filter(power, size=101, mode="nearest") / math.log(2.0)
    ratio = power[lo:] / np.maximum(level[lo:], 1e-300)
    k = int(np.argmax(ratio))
    p = min(1.0, float(ratio.size) * math.exp(-float(ratio[k])))
    amp = 2.0 * np.sqrt(power) / n
    return {"frequency_hz": freq, "amplitude": amp, "level": 2.0 * np.sqrt(level) / n,
            "peak_hz": float(freq[lo + k]), "peak_amplitude": float(amp[lo + k]), "p_value": p,
            "line_ms": _line_ms(power[lo:], level[lo:], ratio, n)}


#: family-wise false-alarm rate of a spectral bin counted in the periodic structure
LINE_ALARM = 1e-3
#: a bin beside a counted one joins it (the skirt of a line that is not one bin wide)
#: when its power is this many times the local level (4.5 % of noise bins do)
SKIRT_RATIO = 3.0
#: bins either side of a counted bin searched for its skirt
SKIRT_BINS = 3


def _line_ms(power: np.ndarray, level: np.ndarray, ratio: np.ndarray, n: int) -> float:
    """Mean square (per sample) of the periodic structure a spectrum holds.

    A periodic structure that is not one steady sine spreads over several bins:
    a ripple whose phase restarts with every run is a line as wide as the
    inverse run length, and a sawtooth has harmonics. Its size is the power
    above the local noise level of every bin that stands out on its own
    (false-alarm rate ``LINE_ALARM`` over all bins) and of the bins beside them
    that stand out less (``SKIRT_RATIO``), not the one largest bin, which sees a
    fraction of it that depends on where the line falls between bins.
    """
    strong = ratio > math.log(ratio.size / LINE_ALARM)
    if not strong.any():
        return 0.0
    near = ndimage.binary_dilation(strong, iterations=SKIRT_BINS)
    keep = strong | (near & (ratio > SKIRT_RATIO))
    return float(np.sum(2.0 * np.maximum(power[keep] - level[keep], 0.0))) / float(n) ** 2


@dataclass(frozen=True)
class Flicker:
    """A 1/f (flicker) part of the residual's noise: power ``level/k`` at the k-th Fourier
    bin of an ``n``-sample record (periodogram units ``|FFT|²/n``, N·m²).

    Flicker noise (a strain-gauge bridge's, an amplifier's) has no time scale: its
    spectrum continues the same ``1/f`` law from the fast fluctuations down to the
    record's length, so the means of long stretches of it wander by as much as those of
    short ones (a flat Allan deviation). A torque zero that drifts or settles is a
    deterministic curve whose power sits at the lowest frequencies, far above that law
    measured higher up. The law is measured at frequencies above the time tests' scale
    and carried down to predict how much the bin and run means of noise alone vary.
    """

    level: float
    n: int

    def group_variance(self, key: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """Variance (N·m²) of ``Σ w·e`` over the samples of each group under the flicker
        part: ``key`` gives each residual sample's group (0 … G-1), ``weights`` its weight.

        The weights are summed in blocks onto ``FLICKER_FFT_POINTS`` points first: the
        flicker lives at the lowest frequencies, which the block sums keep.
        """
        groups = int(key.max()) + 1 if key.size else 0
        if self.level <= 0.0 or groups == 0:
            return np.zeros(groups)
        m = max(1, int(math.ceil(self.n / FLICKER_FFT_POINTS)))
        nb = int(math.ceil(self.n / m))
        block = np.arange(key.size) // m
        w = np.bincount(key * nb + block, weights=weights, minlength=groups * nb)
        spec = np.abs(np.fft.rfft(w.reshape(groups, nb), axis=1)) ** 2
        k = np.arange(1, spec.shape[1])
        return (2.0 / self.n) * (spec[:, 1:] @ (self.level / k))

    @property
    def total_variance(self) -> float:
        """Variance (N·m²) the flicker part adds to every sample."""
        if self.level <= 0.0:
            return 0.0
        k = np.arange(1, self.n // 2 + 1)
        return float((2.0 / self.n) * np.sum(self.level / k))


#: points of the short FFT on which the flicker part of a mean's variance is summed
FLICKER_FFT_POINTS = 4096
#: the 1/f law is measured from this many cycles per record up (above the time tests'
#: bins) to a sixteenth of the sampling rate
FLICKER_LOW_CYCLES = 80


#: the white + 1/f law fitted up to a sixteenth of the sampling rate must predict the mean power of the octave
#: above its band within this factor
FLICKER_CONTINUITY = 1.5


def _speed_groups(idx: np.ndarray, sig: Signals, min_share: float = 0.1) -> list[np.ndarray]:
    """Positions of the residual's samples at rest, moving slowly and moving fast (below
    and above the median speed in motion); groups under ``min_share`` of them are left out."""
    speed = np.abs(sig.rate_trace[idx])
    top = float(np.max(speed)) if speed.size else 0.0
    rest = speed <= 0.01 * top
    moving = np.flatnonzero(~rest)
    groups = [np.flatnonzero(rest)]
    if moving.size:
        mid = float(np.median(speed[moving]))
        groups += [moving[speed[moving] <= mid], moving[speed[moving] > mid]]
    return [g for g in groups if g.size >= min_share * idx.size]


def flicker_noise(r: np.ndarray, groups: list[np.ndarray] | None = None) -> Flicker:
    """The 1/f part of a residual's noise (see :class:`Flicker`), or a zero level.

    The periodogram's mean power in log-spaced bands from ``FLICKER_LOW_CYCLES`` cycles
    per record up to a sixteenth of the sampling rate is fitted with ``W + level/k``
    (white plus flicker; weighted least squares on the bands' relative errors). The level
    is kept when the flicker part at the lowest band is at least the white part there (a
    real 1/f rise, not the scatter of white or coloured noise), the law predicts the
    octave above its band and the top octave of the spectrum, and the band's power is
    alike in every group of ``groups`` (at rest, slow, fast: a sensor's noise does not
    know the speed), all within ``FLICKER_CONTINUITY``.
    """
    n = r.size
    hi = n // 16
    if hi <= 4 * FLICKER_LOW_CYCLES:
        return Flicker(0.0, n)
    power = np.abs(np.fft.rfft(r - r.mean())) ** 2 / n
    edges = np.unique(np.round(np.geomspace(FLICKER_LOW_CYCLES, hi, 13)).astype(int))
    k_mid = np.sqrt(edges[:-1] * edges[1:].astype(float))
    p_band = np.array([float(np.mean(power[a:b])) for a, b in zip(edges[:-1], edges[1:])])
    cnt = np.diff(edges).astype(float)
    w = np.sqrt(cnt) / np.maximum(p_band, 1e-300)
    design = np.column_stack([np.ones_like(k_mid), 1.0 / k_mid]) * w[:, None]
    (white, level), *_ = np.linalg.lstsq(design, p_band * w, rcond=None)
    if white <= 0.0 or level <= 0.0 or level / k_mid[0] < white:
        return Flicker(0.0, n)
    # the law must go on describing the octave above the band it was fitted on: structure
    # (a friction law's transient at every start) whose spectrum falls faster than 1/f is
    # not white plus flicker noise, and would be carried down as too much noise
    # a sensor's noise does not know the speed: the band's power must be alike at rest, at
    # low and at high speed (a relaxation in holds, a breakaway at low speed, a lag at
    # high speed are not); the band's part of the residual, by inverse FFT
    if groups and len(groups) > 1:
        spec = np.fft.rfft(r - r.mean())
        spec[:FLICKER_LOW_CYCLES] = 0.0
        spec[hi:] = 0.0
        band = np.fft.irfft(spec, n)
        ms = [float(np.mean(band[g] ** 2)) for g in groups]
        if max(ms) > FLICKER_CONTINUITY * min(ms):
            return Flicker(0.0, n)
    # and the top of the spectrum, where the white part alone is left
    for lo_k, hi_k in ((hi, 2 * hi), (n // 4, n // 2)):
        k_up = np.arange(lo_k, min(hi_k, power.size))
        above = float(np.mean(power[k_up])) / float(np.mean(white + level / k_up))
        if not 1.0 / FLICKER_CONTINUITY <= above <= FLICKER_CONTINUITY:
            return Flicker(0.0, n)
    return Flicker(float(level), n)


def residual_structure(r: np.ndarray, idx: np.ndarray, sig: Signals, bins: int = 40,
                       min_rms: float = 0.25, p_level: float = 1e-6,
                       excess_ratio: float = 1.25) -> tuple[dict, bool, float]:
    """Test a residual for structure beyond noise.

    Six tests, each against the noise level ``σ`` (from lagged differences of
    the residual at a lag where the noise no longer correlates), its
    correlation time ``τ`` and its 1/f part (:func:`flicker_noise`, carried
    down to the samples of each bin and run by :meth:`Flicker.group_variance`):

    * ``by_deflection_and_direction``: residual means in bins of deflection,
      separately for each direction of motion;
    * ``by_time``: residual means in bins of time;
    * ``by_protocol_phase``: residual means by phase of the protocol
      (:func:`phase_key`: what the bench does after every start, stop and turn);
    * ``by_run``: each run's residual mean and slope against deflection (a
      stiffness or zero that changes between cycles averages out of the two
      tests above);
    * ``periodic_in_time``: the largest peak of the residual's spectrum over
      its local noise level (an electrical or mechanical ripple);
    * ``periodic_with_direction``: the same for the residual times the direction of
      motion (a channel sampled and held between updates: a sawtooth at its update
      clock whose sign follows the motion).

    A test is significant when its p-value is below ``p_level`` and the
    structure it sees is at least ``min_rms``·σ (RMS over the samples).

    Args:
        r: residual (N·m) at samples ``idx``.
        idx: sample indices (glitches excluded).
        sig: record signals.
        bins: bins of deflection (per direction) and of time.
        min_rms: least structure RMS, in noise standard deviations, that counts.
        p_level: significance level of each test.
        excess_ratio: residual RMS over the noise level that counts as unexplained.

    Returns:
        ``(evidence, unexplained, σ)``: evidence dict, whether structure remains
        (a significant test, or residual RMS above ``excess_ratio``·σ), and σ (N·m).
    """
    # noise correlation from what a flexible description leaves; level from lagged
    # differences of the residual itself at the lag where that noise decorrelates
    noise = coloured_noise_model(r, idx, sig)
    sigma = noise.sigma
    var_noise = sigma ** 2 * noise.tau  # bin means of correlated noise vary as σ²·τ/n
    theta = sig.theta_smooth[idx]
    nb = bins
    edges = np.linspace(theta.min(), theta.max(), nb + 1)
    b_theta = np.clip(np.searchsorted(edges, theta, side="right") - 1, 0, nb - 1)
    key_theta = 2 * b_theta + (sig.direction[idx] > 0)
    t = sig.t[idx]
    key_time = np.clip(((t - t[0]) / (t[-1] - t[0]) * nb).astype(int), 0, nb - 1)
    # the residual with its means by deflection and direction taken out: for the 1/f part
    # of the noise and for periodic structure
    cnt = np.bincount(key_theta)
    flat = r - (np.bincount(key_theta, weights=r) / np.maximum(cnt, 1))[key_theta]
    flicker = flicker_noise(flat - _phase_means(flat, idx, sig), _speed_groups(idx, sig))
    ratio = (rmse(r) / math.sqrt(sigma ** 2 + flicker.total_variance)) if sigma > 0 else math.inf
    tests = {}
    unexplained = ratio > excess_ratio

    def verdict(name, chi2, dof, excess_ms, extra):
        p = float(stats.chi2.sf(chi2, dof)) if dof else 1.0
        struct_rms = math.sqrt(max(float(excess_ms), 0.0))
        significant = p < p_level and struct_rms > min_rms * sigma
        tests[name] = {"chi2": chi2, "bins": dof, "p_value": p, "structure_rms_Nm": struct_rms,
                       "structure_rms_over_noise": struct_rms / sigma if sigma > 0 else math.inf,
                       **extra, "significant": bool(significant)}
        return significant

    key_phase, since = phase_key(idx, sig)
    for name, key, centre in (("by_deflection_and_direction", key_theta, theta),
                              ("by_time", key_time, t),
                              ("by_protocol_phase", key_phase, since)):
        cnt = np.bincount(key)
        tot = np.bincount(key, weights=r)
        ok = cnt >= 20
        means = tot[ok] / cnt[ok]
        # what a bin's mean of noise alone varies by: white (σ²·τ/n) and the 1/f part
        # carried down to the times its samples span (a hold's level is one stretch)
        expect = var_noise / cnt[ok] + flicker.group_variance(key, 1.0 / cnt[key])[ok]
        chi2 = float(np.sum(means ** 2 / expect)) if sigma > 0 else math.inf
        dof = int(ok.sum())
        excess = np.sum(cnt[ok] * (means ** 2 - expect)) / max(np.sum(cnt[ok]), 1)
        worst = int(np.argmax(np.abs(means))) if dof else 0
        where = np.flatnonzero(ok)[worst] if dof else 0
        at = float(np.mean(centre[key == where])) if dof else 0.0
        unexplained |= verdict(name, chi2, dof, excess, {
            "largest_bin_mean_Nm": float(means[worst]) if dof else 0.0,
            {"by_deflection_and_direction": "largest_at_rad", "by_time": "largest_at_s",
             "by_protocol_phase": "largest_after_event_s"}[name]: at})

    feats = run_features(r, idx, sig)
    n_run, sxx = feats["n"], feats["sxx_rad2"]
    e_mean, e_slope = n_run * feats["mean_Nm"] ** 2, sxx * feats["slope_Nm_per_rad"] ** 2
    f_mean, f_slope = _run_flicker(flicker, idx, sig)
    # each run's mean and slope against what noise alone gives them (white, and 1/f)
    x_mean, x_slope = var_noise + n_run * f_mean, var_noise + sxx * f_slope
    dof = 2 * int(n_run.size)
    chi2 = float(np.sum(e_mean / x_mean + e_slope / x_slope)) if sigma > 0 else math.inf
    excess = float(np.sum(e_mean - x_mean + e_slope - x_slope)) / max(float(np.sum(n_run)), 1.0)
    unexplained |= verdict("by_run", chi2, dof, excess, {"runs": int(feats["n"].size)})

    rate_hz = sig.scales.sample_rate_hz / max(float(np.median(np.diff(idx))), 1.0)
    spec = periodogram(r, rate_hz)
    # the whole line (its skirt and harmonics), not the largest bin: a structure at the
    # threshold must not pass or fail with where its line falls between bins; measured
    # with the residual's means by deflection and direction taken out (the bins of the
    # test above), or on a periodic motion (a sine) every shape in deflection would
    # count again as harmonics of the drive
    plain_line_ms = periodogram(flat, rate_hz)["line_ms"]
    excess = max(0.5 * spec["peak_amplitude"] ** 2 - sigma ** 2 / max(r.size, 1), plain_line_ms)
    p = spec["p_value"]
    struct_rms = math.sqrt(excess)
    significant = p < p_level and struct_rms > min_rms * sigma
    tests["periodic_in_time"] = {
        "p_value": p, "structure_rms_Nm": struct_rms,
        "structure_rms_over_noise": struct_rms / sigma if sigma > 0 else math.inf,
        "peak_frequency_hz": spec["peak_hz"], "peak_amplitude_Nm": spec["peak_amplitude"],
        "significant": bool(significant)}
    unexplained |= significant
    # a line whose sign follows the direction of motion: a channel sampled and held between
    # updates errs by its rate times the time since its last update, a sawtooth at the
    # update clock that flips with the motion and so cancels out of the plain spectrum over
    # every cycle; the residual times the direction holds it as a line. A line that stands
    # in the residual itself (mains hum) smears over the direction's sidebands there, and
    # is counted only where the direction's line is the larger
    held = periodogram(flat * sig.direction[idx], rate_hz)
    struct_rms = math.sqrt(held["line_ms"])
    significant = (held["p_value"] < p_level and struct_rms > min_rms * sigma
                   and held["line_ms"] > plain_line_ms)
    tests["periodic_with_direction"] = {
        "p_value": held["p_value"], "structure_rms_Nm": struct_rms,
        "structure_rms_over_noise": struct_rms / sigma if sigma > 0 else math.inf,
        "peak_frequency_hz": held["peak_hz"], "peak_amplitude_Nm": held["peak_amplitude"],
        "significant": bool(significant)}
    unexplained |= significant
    evidence = {"noise_Nm": sigma, "noise_decorrelation_lag_samples": noise.lag,
                "flicker_noise_rms_Nm": math.sqrt(flicker.total_variance),
                "noise_correlation_samples": noise.tau, "residual_rms_Nm": rmse(r),
                "residual_rms_over_noise": ratio,
                "lag1_autocorrelation": _autocorr(r, 1),
                "tests": tests,
                "thresholds": {"p_value": p_level, "structure_rms_over_noise": min_rms,
                               "residual_rms_over_noise": excess_ratio}}
    return evidence, bool(unexplained), sigma


#: windows (in noise correlation times) over which a local departure is averaged
LOCAL_WINDOWS = (4, 16, 64)


def local_departure(d: np.ndarray, sigma: float, tau: float, p_level: float) -> dict:
    """Whether a difference between two models (N·m, every sample) stands out of the noise
    somewhere in the record, though too brief to count in the binned tests.

    A law that departs from another only at a few events (a sensor filter rounding the
    corners where a crossover is taken up at speed) leaves a difference whose RMS over the
    record is a small share of the noise, while at those events it stands several noise
    levels tall. Its moving average over ``w`` samples (``w`` = ``LOCAL_WINDOWS`` times
    the noise correlation ``tau``) is compared with what the noise's own moving average
    reaches anywhere in the record: ``σ·√(τ/w)`` times the normal quantile of
    ``p_level`` shared out over every window position and width (Bonferroni), and at
    least one noise level ``σ`` (a structure as tall as one sample's noise, not one that
    only a long record resolves).

    Returns:
        ``significant``, the ``peak_Nm`` of the moving average, its ``window_samples``,
        and the ``threshold_Nm`` it was judged against.
    """
    n = d.size
    best = {"significant": False, "peak_Nm": 0.0, "window_samples": 0, "threshold_Nm": math.inf}
    if sigma <= 0.0 or n == 0:
        return best
    widths = sorted({max(1, int(round(k * max(tau, 1.0)))) for k in LOCAL_WINDOWS})
    widths = [w for w in widths if w <= n]
    tries = sum(n / w for w in widths)
    z = float(stats.norm.isf(p_level / (2.0 * max(tries, 1.0))))
    for w in widths:
        mean = ndimage.uniform_filter1d(d, w, mode="nearest")
        peak = float(np.max(np.abs(mean)))
        bar = max(z * sigma * math.sqrt(max(tau, 1.0) / w), sigma)
        if peak / bar > best["peak_Nm"] / best["threshold_Nm"] or not best["window_samples"]:
            best = {"significant": peak > bar, "peak_Nm": peak, "window_samples": w,
                    "threshold_Nm": bar}
    return best


#: bins of the time since the motion last started, stopped or turned (log-spaced)
PHASE_BINS = 24


def phase_key(idx: np.ndarray, sig: Signals) -> tuple[np.ndarray, np.ndarray]:
    """Bin of each sample by phase of the protocol (holding or moving, direction of motion,
    and the time since the motion last started, stopped or turned, log-spaced), and that
    time (s)."""
    hold = sig.in_hold[idx]
    runs = sig.runs[idx]
    change = np.ones(idx.size, dtype=bool)
    change[1:] = (hold[1:] != hold[:-1]) | (runs[1:] != runs[:-1])
    seg = np.cumsum(change) - 1
    t = sig.t[idx]
    elapsed = t - t[np.flatnonzero(change)][seg]
    dt = 1.0 / sig.scales.sample_rate_hz
    edges = np.geomspace(dt, max(float(elapsed.max()), 2.0 * dt), PHASE_BINS)
    b = np.searchsorted(edges, elapsed)
    return (b * 2 + hold) * 2 + (sig.direction[idx] > 0), elapsed


#: flagged samples this close (samples) are one burst, one draw (the running median's
#: window of :func:`springcad.fit.signals.find_glitches`)
GLITCH_BURST = 9


def motion_locked_p(mask: np.ndarray, sig: Signals) -> float:
    """Probability that samples flagged at random (``mask``, every sample) would fall as
    near the protocol's events as those flagged do.

    A sensor glitch (an ADC spike, a lost frame) knows nothing of the motion: its time to
    the nearest instant the motion started, stopped or turned (the changes of
    :func:`phase_key`, before or after it: an event is placed a few samples late) is that
    of a sample drawn at random. With ``u_1 ≤ … ≤ u_n`` the shares of all samples no
    farther from an event than each flagged one (a burst of flagged samples within
    ``GLITCH_BURST`` samples of each other counts once), ``n`` random samples have their k-th
    smallest share at most ``u_k`` with probability ``P(Binomial(n, u_k) ≥ k)``; the least
    over k, times n (Bonferroni), is returned, so one glitch far from the events does not
    hide the rest gathered at them. Ringing after the steps of a protocol, or a friction
    that breaks away at every start, gathers there: a small probability says the flagged
    samples are the motion's doing, not isolated glitches.
    """
    flagged = np.flatnonzero(mask)
    hold, runs = sig.in_hold, sig.runs
    change = np.flatnonzero((hold[1:] != hold[:-1]) | (runs[1:] != runs[:-1])) + 1
    if flagged.size == 0 or change.size == 0:
        return 1.0
    # a burst of glitches is one draw: samples within ``GLITCH_BURST`` of each other, read
    # at the burst's middle sample
    bursts = np.split(flagged, np.flatnonzero(np.diff(flagged) > GLITCH_BURST) + 1)
    at = np.array([b[b.size // 2] for b in bursts])
    n = at.size
    t_event = sig.t[change]
    k = np.searchsorted(t_event, sig.t)
    after = np.abs(t_event[np.minimum(k, t_event.size - 1)] - sig.t)
    before = np.abs(sig.t - t_event[np.maximum(k - 1, 0)])
    near = np.minimum(after, before)
    u = np.sort(np.searchsorted(np.sort(near), near[at], side="right") / sig.n)
    # P(Binomial(n, u_k) >= k) for k = 1..n
    tail = stats.binom.sf(np.arange(n), n, u)
    return float(min(1.0, n * tail.min()))


def _phase_means(r: np.ndarray, idx: np.ndarray, sig: Signals) -> np.ndarray:
    """The residual's means by phase of the protocol: holding or moving, direction, and the
    time since the motion last started, stopped or turned (log-spaced bins); then by the
    speed.

    What the bench does after every start, stop and turn alike, or at every speed alike (a
    torque relaxing in each hold, a friction law's breakaway) repeats with the protocol and is taken out with
    these means before the noise's 1/f law is measured; flicker noise is not locked to
    the protocol and averages out of them.
    """
    key = phase_key(idx, sig)[0]
    cnt = np.bincount(key)
    phase = (np.bincount(key, weights=r) / np.maximum(cnt, 1))[key]
    # and by the speed (signed, log-spaced): a friction law's breakaway and Stribeck dip
    # follow the speed, which reaches a given value at a different time on every ramp
    rate = sig.rate_trace[idx]
    top = float(np.max(np.abs(rate)))
    if top <= 0.0:
        return phase
    mag = np.searchsorted(np.geomspace(1e-3 * top, top, PHASE_BINS), np.abs(rate))
    key = 2 * mag + (rate > 0)
    rest = r - phase
    cnt = np.bincount(key)
    return phase + (np.bincount(key, weights=rest) / np.maximum(cnt, 1))[key]


def _run_flicker(flicker: Flicker, idx: np.ndarray, sig: Signals,
                 min_samples: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Variance (N·m², N·m²/rad²) the 1/f part of the noise gives each run's mean and its
    slope against deflection (the runs of :func:`run_features`, in its order)."""
    runs = sig.runs[idx]
    _, inv = np.unique(runs, return_inverse=True)
    n = np.bincount(inv).astype(float)
    ok = n >= min_samples
    if flicker.level <= 0.0:
        return np.zeros(int(ok.sum())), np.zeros(int(ok.sum()))
    theta = sig.theta_smooth[idx]
    dth = theta - (np.bincount(inv, weights=theta) / n)[inv]
    sxx = np.bincount(inv, weights=dth * dth)
    w_slope = dth / np.where(sxx > 0, sxx, 1.0)[inv]
    return (flicker.group_variance(inv, 1.0 / n[inv])[ok],
            flicker.group_variance(inv, w_slope)[ok])


def _autocorr(r: np.ndarray, lag: int) -> float:
    r = r - r.mean()
    den = float(r @ r)
    return float(r[lag:] @ r[:-lag]) / den if den > 0 else 0.0
