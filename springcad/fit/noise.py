"""The noise of a residual: its level and correlation, white or coloured.

:func:`noise_model` estimates the noise level and correlation time from a residual's
fast variations; :func:`flexible_remainder` takes a flexible description of any
structure out first (means in fine bins of deflection and short windows of time), and
:func:`coloured_noise_model` reads strongly coloured (AR(1)) sensor noise through that
remainder. Torque in N·m, time in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from springcad.fit.segment import noise_std
from springcad.fit.signals import Signals


@dataclass(frozen=True)
class NoiseModel:
    """Level and correlation of the noise in a residual.

    Attributes:
        sigma: white-equivalent standard deviation (N·m), from differences at
            ``lag`` samples, where the noise no longer correlates.
        lag: first lag (samples) at which the noise autocorrelation is below 0.05.
        tau: integrated autocorrelation time (samples, ≥ 1): each ``tau``
            samples carry one sample's worth of independent information.
    """

    sigma: float
    lag: int
    tau: float


def noise_model(r: np.ndarray, sample_rate_hz: float) -> NoiseModel:
    """Estimate the noise of a residual sampled at ``sample_rate_hz``.

    The residual is high-passed (minus its 0.2 s moving average) so slow
    structure does not pass for correlated noise; its autocorrelation over the
    first 50 ms gives the decorrelation lag and ``tau``. White noise gives
    ``lag = 1, tau = 1``; deflection noise interpolated from a 60 fps camera
    gives a lag of several samples at 500 Hz.
    """
    width = max(5, int(round(0.2 * sample_rate_hz)))
    hp = r - ndimage.uniform_filter1d(r, width, mode="nearest")
    hp = hp - hp.mean()
    den = float(hp @ hp)
    kmax = max(1, min(int(round(0.05 * sample_rate_hz)), r.size // 4))
    if den == 0.0:
        return NoiseModel(0.0, 1, 1.0)
    acf = np.array([float(hp[k:] @ hp[:-k]) / den for k in range(1, kmax + 1)])
    below = np.flatnonzero(acf < 0.05)
    lag = int(below[0]) + 1 if below.size else kmax
    tau = max(1.0, 1.0 + 2.0 * float(np.sum(acf[:lag - 1])))
    return NoiseModel(noise_std(r, lag), lag, tau)


#: time window (s) whose means :func:`flexible_remainder` takes out
REMAINDER_WINDOW_S = 0.1
#: AR(1) coefficients tried by :func:`coloured_noise_model` (denser towards 1)
AR1_GRID = tuple(1.0 - np.geomspace(0.7, 0.01, 10))
#: longest lag of the autocorrelation matched, and how many lags (log-spaced) up to it
AR1_MAX_LAG = 400
AR1_LAGS = 16
#: pseudo-random draws averaged for the remainder's autocorrelation of each model
AR1_DRAWS = 3
#: least share of the noise variance in the AR(1) part: a sensor's coloured noise is most
#: of its noise; a small share correlated over a long time is slow structure
AR1_MIN_SHARE = 0.5
#: the AR(1) + white model must predict the level of one-sample differences within this factor
AR1_LEVEL_RATIO = 1.25
#: AR(1) shares of the noise variance tried beside them
AR1_SHARES = np.linspace(0.0, 1.0, 41)
#: the AR(1) + white model must reproduce the remainder's autocorrelation this closely (RMS)
AR1_FIT_TOLERANCE = 0.05


def _autocov(x: np.ndarray, lags: np.ndarray) -> np.ndarray:
    """Autocovariance of ``x`` (mean removed) at lag 0 and at ``lags`` (≥ 1; per sample)."""
    x = x - x.mean()
    return np.array([float(x @ x)] + [float(x[k:] @ x[:-k]) for k in lags]) / x.size


def coloured_noise_model(r: np.ndarray, idx: np.ndarray, sig: Signals) -> NoiseModel:
    """The noise of a residual, with correlated (AR(1)-like) sensor noise read through the
    flexible description that separates it from structure.

    :func:`noise_model` measures the correlation on :func:`flexible_remainder`, which
    takes out the means in fine bins of deflection and 0.1 s windows of time: that keeps
    a ripple swept past at speed from passing for noise, but it also takes out the slow
    part of a strongly coloured noise (a torque amplifier's AR(1) noise with a
    coefficient of 0.9 decorrelates over tens of samples), so its decorrelation lag and
    correlation time come out short and its level low. Here the remainder's
    autocorrelation is matched with that of white plus AR(1) noise put through the same
    remainder (fixed pseudo-random draws on the record's own samples, ``AR1_DRAWS``
    averaged): the model of coefficient ``ρ`` and AR share ``s`` that reproduces it
    gives the noise's decorrelation lag (``s·ρ^k < 0.05``), its correlation time
    ``1 + 2·s·ρ/(1 - ρ)`` and the level's correction for what lagged differences at
    that lag still miss.
    Kept when the remainder's own lag is over two samples, the model reproduces its
    autocorrelation within ``AR1_FIT_TOLERANCE`` with at least ``AR1_MIN_SHARE`` of the
    variance in the AR(1) part, its correlation (``1/(1 - ρ)`` samples) is within half
    the remainder's time window (a longer one is slow structure the remainder kept, not
    noise it measures), and it predicts the level of the one-sample differences within ``AR1_LEVEL_RATIO`` (differences at the long lag that
    hold slow structure do not); otherwise :func:`noise_model`'s.

    Returns:
        The noise model; ``sigma`` is the white-equivalent level of the residual ``r``
        (its lagged differences at ``lag``, corrected for the correlation left at that lag).
    """
    rate = sig.scales.sample_rate_hz
    remainder = _remainder_keys(idx, sig)
    fr = remainder(r)
    base = noise_model(fr, rate)
    plain = NoiseModel(noise_std(r, base.lag), base.lag, base.tau)
    if base.lag <= 2 or r.size < 200:
        return plain
    kmax = int(min(max(4 * base.lag, 20), AR1_MAX_LAG, r.size // 8))
    lags = np.unique(np.round(np.geomspace(1, kmax, AR1_LAGS)).astype(int))
    data = _autocov(fr, lags)
    if data[0] <= 0.0:
        return plain
    data = data[1:] / data[0]
    draws = np.random.default_rng(20261126).standard_normal((AR1_DRAWS, r.size))
    white = sum(_autocov(remainder(z), lags) for z in draws)
    from scipy.signal import lfilter

    def fit(rho: float) -> tuple[float, float, float]:
        a = lfilter([math.sqrt(1.0 - rho * rho)], [1.0, -rho], draws, axis=1)
        ar = sum(_autocov(remainder(z), lags) for z in a)
        mix = AR1_SHARES[:, None] * ar[None, :] + (1.0 - AR1_SHARES[:, None]) * white[None, :]
        model = mix[:, 1:] / mix[:, :1]
        err = np.sqrt(np.mean((model - data[None, :]) ** 2, axis=1))
        j = int(np.argmin(err))
        return float(err[j]), rho, float(AR1_SHARES[j])

    # coarse grid in 1 - ρ (log-spaced), then finer about the best
    best = min(fit(rho) for rho in AR1_GRID)
    q = math.log(1.0 - best[1])
    step = math.log((1.0 - AR1_GRID[0]) / (1.0 - AR1_GRID[1]))
    fine = [1.0 - math.exp(q + f * step) for f in (-0.66, -0.33, 0.33, 0.66)]
    best = min([best] + [fit(rho) for rho in fine if 0.0 < rho < 0.999])
    err, rho, share = best
    # a correlation longer than half the remainder's time window is not one it measures:
    # slow structure (a stiffness that stepped, spread over the deflection bins) left in
    # the remainder, not noise
    window = REMAINDER_WINDOW_S * rate / max(float(np.median(np.diff(idx))), 1.0)
    if (err > AR1_FIT_TOLERANCE or share < AR1_MIN_SHARE or rho <= 0.0
            or 1.0 / (1.0 - rho) > 0.5 * window):
        return plain
    below = share * rho ** np.arange(1, 10 * kmax + 1) < 0.05
    lag = int(np.argmax(below)) + 1 if below.any() else 10 * kmax
    lag = max(lag, base.lag)
    tau = float(max(base.tau, 1.0 + 2.0 * share * rho / (1.0 - rho)))
    left = max(1.0 - share * rho ** lag, 0.5)
    sigma = noise_std(r, lag) / math.sqrt(left)
    # the model must also give the level of the differences between neighbours: where the
    # differences at the long lag hold slow structure, those at one sample do not
    ratio = noise_std(r, 1) / (sigma * math.sqrt(max(1.0 - share * rho, 1e-12)))
    if not 1.0 / AR1_LEVEL_RATIO <= ratio <= AR1_LEVEL_RATIO:
        return plain
    return NoiseModel(sigma, lag, tau)


def flexible_remainder(r: np.ndarray, idx: np.ndarray, sig: Signals, bins: int = 128,
                       window_s: float = REMAINDER_WINDOW_S) -> np.ndarray:
    """What is left of ``r`` after a flexible description of any structure.

    The residual's means in fine bins of deflection (per direction of motion)
    and then in short windows of time are removed. Structure that varies
    faster in time than the noise model's high-pass (a ripple in deflection
    swept past at speed) would otherwise read as correlated noise; what is
    left is noise, for the noise level and correlation time.
    """
    return _remainder_keys(idx, sig, bins, window_s)(r)


def _remainder_keys(idx: np.ndarray, sig: Signals, bins: int = 128,
                    window_s: float = REMAINDER_WINDOW_S):
    """:func:`flexible_remainder` for samples ``idx`` as a function of the residual (the
    bins worked out once, for many residuals on the same samples)."""
    theta = sig.theta_smooth[idx]
    edges = np.linspace(theta.min(), theta.max(), bins + 1)
    k1 = 2 * np.clip(np.searchsorted(edges, theta, side="right") - 1, 0, bins - 1)
    k1 = k1 + (sig.direction[idx] > 0)
    n1 = np.maximum(np.bincount(k1), 1)
    t = sig.t[idx]
    k2 = ((t - t[0]) / window_s).astype(int)
    n2 = np.maximum(np.bincount(k2), 1)

    def remainder(r: np.ndarray) -> np.ndarray:
        out = r - (np.bincount(k1, weights=r) / n1)[k1]
        return out - (np.bincount(k2, weights=out) / n2)[k2]

    return remainder
