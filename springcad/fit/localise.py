"""Where unexplained structure lives, and what kind of cause gives such a signature.

When the residual of the final model holds structure (see
:func:`springcad.fit.residual.residual_structure`), this module describes it
without naming a cause:

* **in time**: each run's residual mean (a torque zero) and slope against
  deflection (a stiffness) are fitted as constant, as one step (a change at
  one instant) and as a linear trend; the best by BIC, if it beats the
  constant clearly, is reported with its time and sizes;
* **in deflection**: residual means in bins of deflection, split into the
  part common to both directions of motion and the part that flips with the
  direction; the common part is placed at large deflection, near zero, or on
  one side of zero when most of its energy is there;
* **by direction of motion**: the share of the structure that flips with the
  direction (loading against unloading);
* **periodic in angle**: a peak in the spectrum of the common part against
  deflection, with its period;
* **periodic in time**: a peak in the spectrum of the residual after the
  deflection and direction pattern is removed, with its frequency;
* **periodic in time with the direction of motion**: the same for the residual
  times the direction (a channel held between updates: a sawtooth at its update
  rate that flips with the motion).

Each finding carries the share of the structure it accounts for and the kinds
of physical cause that produce such a signature. The arrays behind each
finding are kept for the plot (``springcad.report.fit_report``).

Torque in N·m, deflection in rad, time in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from springcad.fit.residual import periodogram, run_features
from springcad.fit.signals import Signals

#: kinds of finding and the causes that give such a signature (never claimed, only listed)
CAUSES = {
    "stiffness_change": "a part changing during the test: a screw or clamp loosening or settling, "
                        "a flexure yielding or cracking, a spacer or shaft slipping, a coupling "
                        "re-seating",
    "stiffness_trend": "a stiffness that wanders with time: temperature of the spring or the "
                       "sensor, creep, wear of the contacts",
    "zero_change": "a torque zero that jumps: sensor re-zeroed, a cable or coupling moved, an "
                   "amplifier range switched",
    "zero_trend": "a torque zero that wanders, not linearly in time: thermal drift of the sensor "
                  "or amplifier",
    "large_deflection": "extra stiffness or contact at large deflection: a hard stop, a flexure "
                        "touching the rim or its neighbour, a cam tooth tip, yield",
    "near_zero": "a crossover the backlash model does not describe: preload, uneven gaps at the "
                 "camshaft-flexure interfaces, stick-slip at the tips",
    "one_side": "a difference between the two sides of zero: one-sided contact, a damaged "
                "flexure or cam tooth",
    "by_direction": "a torque that depends on the direction of motion but not as dry friction "
                    "or a channel lag do: viscoelastic damping, friction that grows with load, "
                    "stick-slip",
    "periodic_angle": "something that repeats with the angle: cam teeth or flexure tips passing "
                      "(period 2π/N for N flexures), motor cogging or a gear mesh, an optical "
                      "fiducial or encoder tracking error",
    "periodic_time": "something that repeats in time: electrical pickup (mains or a switching "
                     "supply, or their aliases), a control-loop oscillation, a vibration of "
                     "the rig",
    "periodic_with_direction": "a channel sampled and held between updates (a sensor, "
                               "amplifier or bus slower than the logging): late by zero to "
                               "one update, a sawtooth at the update rate that follows the "
                               "speed; stick-slip at one speed",
}

def deflection_profile(r: np.ndarray, idx: np.ndarray, sig: Signals, bins: int) -> dict:
    """Residual means per deflection bin for each direction of motion (for the plot)."""
    theta = sig.theta_smooth[idx]
    edges = np.linspace(theta.min(), theta.max(), bins + 1)
    b = np.clip(np.searchsorted(edges, theta, side="right") - 1, 0, bins - 1)
    up = sig.direction[idx] > 0
    out = {"centre_rad": 0.5 * (edges[1:] + edges[:-1])}
    for name, sel in (("up", up), ("down", ~up)):
        cnt = np.bincount(b[sel], minlength=bins).astype(float)
        tot = np.bincount(b[sel], weights=r[sel], minlength=bins)
        out[f"n_{name}"] = cnt
        out[f"mean_{name}_Nm"] = np.where(cnt > 0, tot / np.maximum(cnt, 1), np.nan)
    return out


def _region(centre: np.ndarray, energy: np.ndarray, width: float) -> dict | None:
    """Where most of a non-negative ``energy`` over deflection bins sits, if anywhere."""
    total = float(energy.sum())
    if total <= 0:
        return None
    a = np.abs(centre)
    amax = float(a.max())
    for cut_frac in np.linspace(0.9, 0.4, 11):  # large deflection: |θ| beyond a cut
        cut = cut_frac * amax
        share = float(energy[a >= cut].sum()) / total
        if share >= 0.7:
            return {"where": "large_deflection", "beyond_rad": float(cut), "share": share,
                    "text": f"at large deflection, |deflection| beyond {cut:.3g} rad"}
    for cut_frac in np.linspace(0.1, 0.4, 7):  # near zero
        cut = max(cut_frac * amax, width)
        share = float(energy[a <= cut].sum()) / total
        if share >= 0.7:
            return {"where": "near_zero", "within_rad": float(cut), "share": share,
                    "text": f"near zero deflection, |deflection| below {cut:.3g} rad"}
    pos = float(energy[centre > 0].sum()) / total
    if pos >= 0.8 or pos <= 0.2:
        side = "positive" if pos >= 0.8 else "negative"
        return {"where": "one_side", "side": side, "share": max(pos, 1 - pos),
                "text": f"on the {side} side of zero only"}
    return None


def angle_period(centre: np.ndarray, profile: np.ndarray, p_level: float) -> dict | None:
    """A dominant period of ``profile`` (residual against deflection), if one stands out.

    A cubic in deflection is removed first (slow shapes are not periods); the
    largest spectral peak must stand above the running median of the others
    (exponential tail, Bonferroni over the bins) and carry at least a third
    of what is left.
    """
    if profile.size < 32:
        return None
    u = (centre - centre.mean()) / (np.ptp(centre) / 2)
    X = np.column_stack([u ** k for k in range(4)])
    coef, *_ = np.linalg.lstsq(X, profile, rcond=None)
    detr = profile - X @ coef
    step = float(centre[1] - centre[0])
    spec = periodogram(detr, 1.0 / step, min_cycles=5.0)
    total = float(np.sum(spec["amplitude"][1:] ** 2))
    if spec["p_value"] >= p_level or total <= 0:
        return None
    share = spec["peak_amplitude"] ** 2 / total
    if share < 1 / 3:
        return None
    period = 1.0 / spec["peak_hz"]
    return {"period_rad": period, "period_deg": math.degrees(period),
            "per_turn": 2.0 * math.pi / period, "amplitude_Nm": spec["peak_amplitude"],
            "p_value": spec["p_value"], "spectrum_share": share,
            "spectrum": {"cycles_per_rad": spec["frequency_hz"].tolist(),
                         "amplitude_Nm": spec["amplitude"].tolist()}}


#: a finding must account for at least this share of the structure to be listed
MIN_SHARE = 0.1


@dataclass
class _Pattern:
    kind: str
    component: np.ndarray
    n_params: int
    info: dict


def _step_search(x: np.ndarray, y: np.ndarray, N: np.ndarray, lo: int,
                 hi: int) -> tuple[int, np.ndarray]:
    """Best single step of the coefficient of ``x`` at a sample position in ``[lo, hi)``.

    Fits ``y ≈ N·c + δ·x·[i ≥ b]`` (``N`` nuisance columns: the stiffness
    shape and a constant, so that a step is not asked to carry a stiffness or
    a zero shared by the whole record) for every ``b`` at once, from suffix
    sums; returns the best ``b`` and its component.
    """
    ntn_inv = np.linalg.pinv(N.T @ N)
    y_full = y
    y = y - N @ (ntn_inv @ (N.T @ y))
    suf = lambda v: np.cumsum(v[::-1], axis=0)[::-1]  # noqa: E731
    uy = suf(x * y)[lo:hi]
    uu = suf(x * x)[lo:hi]
    un = suf(x[:, None] * N)[lo:hi]
    den = uu - np.einsum("ij,jk,ik->i", un, ntn_inv, un)
    ok = den > 1e-12 * max(float(uu.max()), 1e-300)
    gain = np.where(ok, uy * uy / np.where(ok, den, 1.0), -np.inf)
    k = int(np.argmax(gain))
    b = lo + k
    comp, _ = _lsq_component(np.column_stack([x * (np.arange(x.size) >= b), N]), y_full)
    return b, comp


def _lsq_component(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    return X @ coef, coef


def _binned(key: np.ndarray, y: np.ndarray, nbins: int, min_count: int = 10) -> np.ndarray:
    """Component ``y ≈ g[key]``: the mean of ``y`` per bin (bins with few samples left at 0)."""
    cnt = np.bincount(key, minlength=nbins)
    tot = np.bincount(key, weights=y, minlength=nbins)
    g = np.where(cnt >= min_count, tot / np.maximum(cnt, 1), 0.0)
    return g


def _candidates(work: np.ndarray, sig: Signals, idx: np.ndarray, bins: int, sigma: float,
                rate_hz: float, shape: np.ndarray) -> list[_Pattern]:
    t = sig.t[idx]
    theta = sig.theta_smooth[idx]
    d = sig.direction[idx]
    lo, hi = int(0.03 * idx.size), int(0.97 * idx.size)
    N = np.column_stack([shape, np.ones_like(shape)])  # a stiffness and a zero for the record
    out = []
    b, comp = _step_search(shape, work, N, lo, hi)
    out.append(_Pattern("stiffness_step", comp, 3, {"at_s": float(t[b])}))
    b, comp = _step_search(np.ones_like(work), work, N, lo, hi)
    out.append(_Pattern("zero_step", comp, 2, {"at_s": float(t[b])}))
    span = max(np.ptp(t), 1e-12)
    tc = (t - t.mean()) / span
    comp, coef = _lsq_component(np.column_stack([shape * tc, N]), work)
    out.append(_Pattern("stiffness_trend", comp, 1, {"per_s": float(coef[0] / span)}))
    nt = 40
    key_t = np.clip(((t - t[0]) / span * nt).astype(int), 0, nt - 1)
    onehot = np.zeros((t.size, nt))
    onehot[np.arange(t.size), key_t] = 1.0
    comp, _ = _lsq_component(np.column_stack([onehot, shape]), work)
    out.append(_Pattern("zero_wander", comp, nt - 1, {}))
    edges = np.linspace(theta.min(), theta.max(), bins + 1)
    key = np.clip(np.searchsorted(edges, theta, side="right") - 1, 0, bins - 1)
    g = _binned(key, work, bins)
    out.append(_Pattern("deflection", g[key], bins, {"centre_rad": 0.5 * (edges[1:] + edges[:-1]),
                                                     "profile_Nm": g}))
    h = _binned(key, work * d, bins)
    out.append(_Pattern("by_direction", d * h[key], bins, {"centre_rad": 0.5 * (edges[1:] + edges[:-1]),
                                                           "profile_Nm": h}))
    spec = periodogram(work, rate_hz)
    if spec["peak_hz"] > 0:
        f, comp, amp = sinusoid(t, work, spec["peak_hz"], 1.0 / span, N)
        out.append(_Pattern("periodic_time", comp, 3, {
            "frequency_hz": f, "amplitude_Nm": amp, "spectrum_p_value": spec["p_value"]}))
    spec = periodogram(work * d, rate_hz)
    if spec["peak_hz"] > 0:
        f, comp, amp = sinusoid(t, work * d, spec["peak_hz"], 1.0 / span, N)
        out.append(_Pattern("periodic_with_direction", d * comp, 3, {
            "frequency_hz": f, "amplitude_Nm": amp, "spectrum_p_value": spec["p_value"]}))
    return out


def sinusoid(t: np.ndarray, y: np.ndarray, f0: float, df: float,
             N: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Least-squares sinusoid of ``y`` (beside nuisance columns ``N``) with its frequency
    refined within ``f0 ± df`` (Hz).

    Returns:
        ``(frequency_hz, component, amplitude)``.
    """
    def fit(f):
        w = 2.0 * np.pi * f * (t - t[0])
        X = np.column_stack([np.sin(w), np.cos(w), N])
        coef, *_ = np.linalg.lstsq(X, y, rcond=None)
        return X @ coef, float(np.hypot(coef[0], coef[1]))

    res = optimize.minimize_scalar(lambda f: -float(np.sum(fit(f)[0] ** 2)),
                                   bounds=(f0 - df, f0 + df), method="bounded",
                                   options={"xatol": 1e-4 * df})
    f = float(res.x)
    comp, amp = fit(f)
    return f, comp, amp


def localise(r: np.ndarray, idx: np.ndarray, sig: Signals, sigma: float, tau: float,
             shape: np.ndarray | None = None, bins: int = 96, p_level: float = 1e-6,
             max_patterns: int = 4) -> dict:
    """Describe where the structure of residual ``r`` (samples ``idx``) lives.

    The residual is decomposed greedily into patterns of few kinds: a step of
    the stiffness or of the torque zero at one instant (between two runs), a
    stiffness trend, a wandering zero (bins of time), a shape in deflection
    common to both directions (bins of deflection), a part that flips with the
    direction of motion, a sinusoid in time. Each round takes the pattern with
    the best BIC (chi-square removed, with noise variance ``σ²τ``, minus its
    parameters times ``ln(N/τ)``), if it is significant at ``p_level``; the
    next round works on what is left. Competing descriptions therefore do not
    both claim the same structure: on the paper's staircase, where the late
    cycles are also the large ones, a stiffness change mid-test and a hard
    stop at large deflection are told apart by whether small deflections of
    late cycles share the change.

    Args:
        r: residual (N·m) of the final model at samples ``idx`` (glitches excluded).
        idx: sample indices, in time order.
        sig: record signals.
        sigma: noise level of the residual (N·m).
        tau: noise correlation time (samples).
        shape: the final model's torque per unit stiffness at ``idx`` (rad; the
            deflection itself for a linear spring): how a stiffness change shows.
        bins: deflection bins.
        p_level: significance of each pattern.
        max_patterns: most patterns taken.

    Returns:
        ``{"findings": [...], "summary": str, "data": {...}}``; each finding has
        ``kind``, ``text``, ``share`` (of the structure's energy), its numbers
        and ``causes``. ``data`` holds the arrays for the plot.
    """
    var0 = max(sigma ** 2 * tau, 1e-300)
    n_eff = max(r.size / tau, 2.0)
    rate = sig.scales.sample_rate_hz / max(float(np.median(np.diff(idx))), 1.0)
    total = max(float(r @ r) - r.size * sigma ** 2, 1e-300)
    k_mean = float(sig.scales.torque_ref / max(sig.scales.theta_ref, 1e-12))
    shape = sig.theta_smooth[idx] if shape is None else shape
    work = r.copy()
    chosen: list[tuple[_Pattern, float]] = []
    components = {}
    for _ in range(max_patterns):
        best = None
        for pat in _candidates(work, sig, idx, bins, sigma, rate, shape):
            rest = work - pat.component
            gain = (float(work @ work) - float(rest @ rest)) / var0
            score = gain - pat.n_params * math.log(n_eff)
            if (pat.kind in ("periodic_time", "periodic_with_direction")
                    and pat.info["spectrum_p_value"] >= p_level):
                continue
            if score <= 0 or stats.chi2.sf(gain, pat.n_params) >= p_level:
                continue
            if best is None or score > best[1]:
                best = (pat, score, gain)
        if best is None:
            break
        pat, _, gain = best
        work = work - pat.component
        chosen.append((pat, gain))
        components[pat.kind] = components.get(pat.kind, 0.0) + pat.component
    findings = []
    for pat, gain in chosen:
        share = min(1.0, gain * var0 / total)
        if share < MIN_SHARE:
            continue
        findings.extend(_describe(pat, share, k_mean, p_level, sig, idx, shape))
    findings.sort(key=lambda f: -f["share"])
    prof = deflection_profile(r, idx, sig, 64)
    feats = run_features(r, idx, sig)
    spec = periodogram(r, rate)
    keep = slice(None, None, max(1, spec["frequency_hz"].size // 4000))
    step = max(1, idx.size // 4000)
    data = {"deflection": {k: v.tolist() for k, v in prof.items()},
            "runs": {k: v.tolist() for k, v in feats.items()},
            "time_spectrum": {"frequency_hz": spec["frequency_hz"][keep].tolist(),
                              "amplitude_Nm": spec["amplitude"][keep].tolist(),
                              "level_Nm": spec["level"][keep].tolist()},
            "time_component": {"t_s": sig.t[idx][::step].tolist(),
                               "torque_Nm": sum((c for k, c in components.items()
                                                 if k in TIME_KINDS), np.zeros(idx.size))[::step].tolist()}}
    for f in findings:
        if f["kind"] == "periodic_angle":
            data["angle_spectrum"] = f.pop("spectrum")
    summary = ("; ".join(f["text"] for f in findings) if findings else
               "no single pattern (time, deflection, direction or period) accounts for it")
    return {"findings": findings, "summary": summary, "data": data}


TIME_KINDS = ("stiffness_step", "zero_step", "stiffness_trend", "zero_wander", "periodic_time",
              "periodic_with_direction")


def _describe(pat: _Pattern, share: float, k_mean: float, p_level: float, sig: Signals,
              idx: np.ndarray, shape: np.ndarray) -> list[dict]:
    info = pat.info
    base = {"share": share}
    comp = pat.component
    if pat.kind == "stiffness_step":
        after = sig.t[idx] >= info["at_s"]
        d = _slope(comp[after], shape[after]) - _slope(comp[~after], shape[~after])
        return [{**base, "kind": "time_step", "feature": "stiffness", "at_s": info["at_s"],
                 "change_Nm_per_rad": d, "change_pct": 100 * d / k_mean,
                 "text": (f"a change at t ≈ {info['at_s']:.3g} s: the stiffness is {d:+.3g} "
                          f"N·m/rad ({100 * d / k_mean:+.2g} %) different after it"),
                 "causes": CAUSES["stiffness_change"]}]
    if pat.kind == "zero_step":
        after = sig.t[idx] >= info["at_s"]
        d = float(comp[after].mean() - comp[~after].mean())
        return [{**base, "kind": "time_step", "feature": "zero", "at_s": info["at_s"],
                 "change_Nm": d,
                 "text": f"a jump of the torque zero by {d:+.3g} N·m at t ≈ {info['at_s']:.3g} s",
                 "causes": CAUSES["zero_change"]}]
    if pat.kind == "stiffness_trend":
        return [{**base, "kind": "time_trend", "feature": "stiffness",
                 "per_s": info["per_s"],
                 "text": (f"a stiffness that changes steadily with time, {info['per_s']:+.3g} "
                          "N·m/rad per s"),
                 "causes": CAUSES["stiffness_trend"]}]
    if pat.kind == "zero_wander":
        t = sig.t[idx]
        i = int(np.argmax(np.abs(comp)))
        return [{**base, "kind": "time_trend", "feature": "zero",
                 "largest_Nm": float(comp[i]), "largest_at_s": float(t[i]),
                 "text": (f"a torque zero that wanders with time (not linearly), by up to "
                          f"{comp[i]:+.3g} N·m at t ≈ {t[i]:.3g} s"),
                 "causes": CAUSES["zero_trend"]}]
    if pat.kind == "periodic_time":
        f = info["frequency_hz"]
        return [{**base, "kind": "periodic_time", "frequency_hz": f, "period_s": 1 / f,
                 "amplitude_Nm": info["amplitude_Nm"],
                 "text": (f"periodic in time at {f:.4g} Hz (period {1 / f:.3g} s), amplitude "
                          f"{info['amplitude_Nm']:.2g} N·m"),
                 "causes": CAUSES["periodic_time"]}]
    if pat.kind == "periodic_with_direction":
        f = info["frequency_hz"]
        return [{**base, "kind": "periodic_with_direction", "frequency_hz": f,
                 "period_s": 1 / f, "amplitude_Nm": info["amplitude_Nm"],
                 "text": (f"periodic in time at {f:.4g} Hz (period {1 / f:.3g} s), amplitude "
                          f"{info['amplitude_Nm']:.2g} N·m, its sign following the direction "
                          "of motion"),
                 "causes": CAUSES["periodic_with_direction"]}]
    centre, g = info["centre_rad"], info["profile_Nm"]
    width = float(centre[1] - centre[0])
    if pat.kind == "by_direction":
        region = _region(centre, g * g, width)
        where = f", mostly {region['text']}" if region else ""
        rms = float(np.sqrt(np.mean(g * g)))
        return [{**base, "kind": "by_direction", "rms_Nm": rms,
                 "text": (f"different for the two directions of motion (half the "
                          f"loading-unloading difference {rms:.2g} N·m RMS){where}"),
                 "causes": CAUSES["by_direction"]}]
    out = []
    period = angle_period(centre, g, p_level)
    if period is not None:
        out.append({"share": share * period["spectrum_share"], "kind": "periodic_angle",
                    **period,
                    "text": (f"periodic in deflection with period {period['period_rad']:.3g} rad "
                             f"({period['period_deg']:.3g}°, {period['per_turn']:.3g} per turn), "
                             f"amplitude {period['amplitude_Nm']:.2g} N·m"),
                    "causes": CAUSES["periodic_angle"]})
        share *= 1 - period["spectrum_share"]
    region = _region(centre, g * g, width)
    if region is not None and (period is None or share >= MIN_SHARE):
        out.append({"share": share * region["share"], "kind": region["where"],
                    **{k: v for k, v in region.items() if k not in ("text", "where")},
                    "text": f"a shape in deflection {region['text']}",
                    "causes": CAUSES[region["where"]]})
    elif period is None:
        i = int(np.argmax(np.abs(g)))
        out.append({"share": share, "kind": "deflection_shape", "largest_Nm": float(g[i]),
                    "largest_at_rad": float(centre[i]),
                    "text": (f"a shape in deflection spread over the range, largest "
                             f"{g[i]:+.3g} N·m at {centre[i]:+.3g} rad"),
                    "causes": CAUSES["large_deflection"] + "; or " + CAUSES["near_zero"]})
    return out


def _slope(y: np.ndarray, x: np.ndarray) -> float:
    den = float(x @ x)
    return float(x @ y) / den if den > 0 else 0.0


#: a hinge counts when it lowers the residual's chi-square by this much (noise variance σ²τ)
ONSET_CHI2 = 36.0


def _side(theta: np.ndarray, r: np.ndarray, side: float) -> tuple[np.ndarray, np.ndarray]:
    """|θ| and the residual on one side of zero (``side`` ±1)."""
    sel = side * theta > 0
    return side * theta[sel], r[sel]


def _best_hinge(a: np.ndarray, y: np.ndarray, grid: int,
                cubic: bool = False) -> tuple[float, float]:
    """Least squared error of a slope (and a cubic ``a³`` when ``cubic``) and a hinge
    ``β·(a - c)₊`` fitted to ``y`` over |θ| ``a``, the hinge position ``c`` over a grid from
    30 % to 98 % of ``max(a)``; and ``c``."""
    best = (math.inf, math.nan)
    base = _power_basis(a, 3.0) if cubic else a[:, None]
    for c in np.linspace(0.3, 0.98, grid) * float(a.max()):
        X = np.column_stack([base, np.maximum(a - c, 0.0)])
        coef, *_ = np.linalg.lstsq(X, y, rcond=None)
        e = y - X @ coef
        if float(e @ e) < best[0]:
            best = (float(e @ e), float(c))
    return best


def structure_onset(r: np.ndarray, idx: np.ndarray, sig: Signals, sigma: float, tau: float,
                    grid: int = 60, margin: float = 0.05) -> tuple[float, float]:
    """Where a structure at large deflection begins, on each side of zero.

    On each side the residual is fitted with a slope (what a stiffness pulled
    by the structure leaves everywhere) and a hinge ``β·(|θ| - c)₊`` (a stop
    that engages, a sensor that clips); the onset ``c`` is the hinge position
    of least squared error over a grid from 30 % to 98 % of the largest
    deflection. A side where the hinge lowers the chi-square (noise ``σ``,
    correlation ``τ`` samples) by less than ``ONSET_CHI2`` has no onset.

    Returns:
        ``(low_rad, high_rad)``: the band ``low < θ < high`` free of the
        structure, ``margin`` of the largest deflection inside the onsets
        (``-inf``/``inf`` on a side without one).
    """
    theta = sig.theta_smooth[idx]
    var0 = max(sigma ** 2 * tau, 1e-300)
    out = []
    for side in (-1.0, 1.0):
        a, y = _side(theta, r, side)
        if a.size < 100:
            out.append(side * math.inf)
            continue
        amax = float(a.max())
        base = float(y @ y) - float(a @ y) ** 2 / max(float(a @ a), 1e-300)
        sse, c = _best_hinge(a, y, grid)
        if (base - sse) / var0 < ONSET_CHI2:
            out.append(side * math.inf)
            continue
        out.append(side * max(c - margin * amax, 0.1 * amax))
    return out[0], out[1]


def _power_basis(a: np.ndarray, q: float) -> np.ndarray:
    """Columns ``1``, ``a`` and ``(a/max a)^q`` (scaled for conditioning)."""
    return np.column_stack([np.ones_like(a), a, (a / max(float(a.max()), 1e-300)) ** q])


#: share of the largest |deflection| from which a kink and a smooth power are weighed (where
#: :func:`structure_onset` searches the onset)
OUTER_SHARE = 0.3


#: exponents of the smooth power laws ``|θ|^q`` a kink is weighed against (q = 2: a contact
#: whose stiffness grows in proportion to the deflection; large q: a stiffening that
#: gathers at the largest deflections, as close to a kink as a smooth law comes)
SMOOTH_POWERS = np.linspace(1.5, 12.0, 43)


def onset_is_kink(r: np.ndarray, idx: np.ndarray, sig: Signals, sigma: float, tau: float,
                  onsets: tuple[float, float], fit_ratio: float = 1.25, grid: int = 60) -> bool:
    """Whether the structure beyond the onsets engages there (a kink), not smoothly from zero.

    A hard stop and a clipping sensor act beyond a deflection and not inside it: the
    residual beyond their onset is a hinge ``β·(|θ| - c)₊`` beside a line. A stiffness
    that grows smoothly with the deflection (a contact whose area grows with the load,
    ``K·θ·(|θ|/θc)^p``) acts at every deflection, most at the largest: a band left out at
    large deflection does not leave it out of the fit. On each side with a finite onset
    (``onsets`` as :func:`structure_onset` returns them) the hinge is weighed against a
    smooth power ``|θ|^q`` (q in :data:`SMOOTH_POWERS`), each with one free shape
    parameter, both beside a line and the library's cubic (the model the residual is of
    may hold a cubic fitted over the structure: what is judged is the structure beyond
    what the cubic describes), over |θ| from ``OUTER_SHARE`` of its largest, where the
    onset is searched. It is no kink when the power law describes that side to within
    ``fit_ratio`` of the noise (RMS; noise ``σ``, correlation ``τ`` samples: the
    ``unexplained`` bar) and lowers the chi-square below the hinge's by more than the
    ``ONSET_CHI2`` an onset itself needs. Where neither shape describes the side (a
    friction the clipping cuts differently in each direction), the two are not told
    apart and the onset is taken for a kink, as before this test.
    """
    theta = sig.theta_smooth[idx]
    var0 = max(sigma ** 2 * tau, 1e-300)
    for side, onset in zip((-1.0, 1.0), onsets):
        if not np.isfinite(onset):
            continue
        a, y = _side(theta, r, side)
        # the range the onset is searched over: below it a crossover's or a take-up's own
        # shape (left in the residual of a model without it) is no business of the stop's;
        # beyond its transition a crossover is an offset of the line (the constant column)
        outer = a >= OUTER_SHARE * float(a.max())
        a, y = a[outer], y[outer]
        hinge = _best_hinge(a, y, grid, cubic=True)[0]
        base = _power_basis(a, 3.0)
        smooth = math.inf
        for q in SMOOTH_POWERS:
            X = np.column_stack([base, _power_basis(a, q)[:, -1]])
            coef, *_ = np.linalg.lstsq(X, y, rcond=None)
            e = y - X @ coef
            smooth = min(smooth, float(e @ e))
        described = smooth / max(a.size, 1) <= fit_ratio ** 2 * sigma ** 2
        if described and (hinge - smooth) / var0 > ONSET_CHI2:
            return False
    return True
