"""Bench simulator of held-out generator F (issue 24): torsion springs and series stacks.

Written from the physics description alone (see ``bench/heldout_fit_f.md``); nothing here
comes from ``springcad``. SI inside: angles in rad, torques in N·m, times in s; the record
writer converts to the file's units at the boundary.

The motor imposes the total deflection ``theta`` across the stack (far end clamped); the
torque sensor sits on the motor side and reads the stack torque plus whatever is in parallel
between sensor and stack (bearing friction, a viscoelastic bushing, a hard stop, a tooth
ripple). Everything is computed on a fine grid (an integer multiple of the record rate,
>= 2 kHz) and then sampled.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

FINE_RATE_MIN_HZ = 2000.0


# ----------------------------------------------------------------------------- protocols
def _segments(points, rate_hz, start_rad=0.0):
    """Piecewise path from ``points`` = [(duration_s, target_rad, shape)], shape 'lin'|'cos'|'hold'.

    Returns (t_s, theta_rad) sampled at ``rate_hz``.
    """
    pieces = []
    now_rad = start_rad
    for duration_s, target_rad, shape in points:
        n = max(1, int(round(duration_s * rate_hz)))
        s = np.arange(1, n + 1) / n
        if shape == "hold":
            pieces.append(np.full(n, now_rad))
            continue
        w = s if shape == "lin" else 0.5 * (1.0 - np.cos(np.pi * s))
        pieces.append(now_rad + (target_rad - now_rad) * w)
        now_rad = target_rad
    theta = np.concatenate([[start_rad], *pieces])
    return np.arange(theta.size) / rate_hz, theta


def _ramp(points, target_rad, now_rad, rate_rad_s, shape):
    points.append((abs(target_rad - now_rad) / rate_rad_s, target_rad, shape))
    return target_rad


def staircase(rate_hz, amps_rad, rate_rad_s, hold_s, shape="lin", rest_s=0.5):
    """The paper's staircase: 0 -> +a -> 0 -> -a -> 0 for growing amplitudes, holds at each stop."""
    pts = [(rest_s, 0.0, "hold")]
    now = 0.0
    for a in amps_rad:
        for target in (a, 0.0, -a, 0.0):
            now = _ramp(pts, target, now, rate_rad_s, shape)
            pts.append((hold_s, now, "hold"))
    return _segments(pts, rate_hz)


def ramps(rate_hz, amp_rad, rates_rad_s, hold_s, cycles, shape="lin", rest_s=0.5):
    """Ramps between +/-amp at each of ``rates_rad_s`` (``cycles`` each), holds of ``hold_s`` at
    the peaks (0: triangles)."""
    pts = [(rest_s, 0.0, "hold")]
    now = 0.0
    for r in rates_rad_s:
        for _ in range(cycles):
            for target in (amp_rad, -amp_rad):
                now = _ramp(pts, target, now, r, shape)
                if hold_s > 0:
                    pts.append((hold_s, now, "hold"))
        now = _ramp(pts, 0.0, now, r, shape)
        pts.append((rest_s, 0.0, "hold"))
    return _segments(pts, rate_hz)


def random_levels(rate_hz, amp_rad, rate_rad_s, n_levels, hold_range_s, rng, shape="cos"):
    """Random targets in [-amp, amp] reached by ramps and held; the extremes are visited once."""
    targets = list(rng.uniform(-amp_rad, amp_rad, n_levels))
    targets[rng.integers(0, n_levels)] = amp_rad
    targets[rng.integers(0, n_levels)] = -amp_rad
    pts = [(0.5, 0.0, "hold")]
    now = 0.0
    for target in [*targets, 0.0]:
        now = _ramp(pts, target, now, rate_rad_s, shape)
        pts.append((rng.uniform(*hold_range_s), now, "hold"))
    return _segments(pts, rate_hz)


def sine_sweep(rate_hz, parts, rest_s=0.4):
    """Concatenated sines ``parts`` = [(amp_rad, freq_hz, n_cycles)], each from and to zero."""
    chunks = [np.zeros(int(rest_s * rate_hz))]
    for amp, f, n in parts:
        t = np.arange(int(round(n / f * rate_hz))) / rate_hz
        chunks += [amp * np.sin(2 * np.pi * f * t), np.zeros(int(rest_s * rate_hz))]
    theta = np.concatenate(chunks)
    return np.arange(theta.size) / rate_hz, theta


def chirp(rate_hz, amp_rad, f0_hz, f1_hz, duration_s, taper_s=1.0):
    """Linear chirp from f0 to f1 with a cosine amplitude taper at both ends."""
    t = np.arange(int(duration_s * rate_hz)) / rate_hz
    phase = 2 * np.pi * (f0_hz * t + 0.5 * (f1_hz - f0_hz) * t**2 / duration_s)
    env = np.clip(np.minimum(t, duration_s - t) / taper_s, 0, 1)
    env = 0.5 * (1 - np.cos(np.pi * env))
    return t, amp_rad * env * np.sin(phase)


PROTOCOLS = {"staircase": staircase, "ramps": ramps, "random_levels": random_levels,
             "sine_sweep": sine_sweep, "chirp": chirp}


# ------------------------------------------------------------------------------ physics
def stack_torque_Nm(theta_rad, springs):
    """Torque of a series stack at total deflection ``theta_rad`` (bisection on theta(T)).

    ``springs``: dicts with k (N·m/rad), optional k_neg (negative side), gap_rad (total play of
    that spring's interface), gap_center_rad, hertz_k (N·m per rad^1.5: Hertzian take-up).
    """
    def theta_of_T(T):
        total = np.zeros_like(T)
        for s in springs:
            k_neg = s.get("k_neg") or s["k"]
            total += np.where(T >= 0, T / s["k"], T / k_neg)
            gap = s.get("gap_rad", 0.0)
            if gap > 0 or s.get("hertz_k"):
                take = gap / 2 * np.sign(T)
                if s.get("hertz_k"):
                    take = take + np.sign(T) * (np.abs(T) / s["hertz_k"]) ** (2 / 3)
                total += take + s.get("gap_center_rad", 0.0) * (T != 0)
        return total

    k_min = min(min(s["k"], s.get("k_neg") or s["k"]) for s in springs)
    lo = np.full_like(theta_rad, -k_min * (np.abs(theta_rad).max() + 0.1))
    hi = -lo
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        above = theta_of_T(mid) > theta_rad
        hi = np.where(above, mid, hi)
        lo = np.where(above, lo, mid)
    return 0.5 * (lo + hi)


def series_stiffness(springs, side="k"):
    """Series stiffness 1/sum(1/k_i) (N·m/rad) of the springs' ``side`` ('k' or 'k_neg')."""
    return 1.0 / sum(1.0 / (s.get(side) or s["k"]) for s in springs)


def friction_Nm(theta_rad, dt_s, law):
    """Friction torque (N·m) of a bearing between sensor and stack under the motion ``theta_rad``."""
    v = np.gradient(theta_rad, dt_s)
    kind = law["law"]
    if kind == "viscous":
        return law["c"] * v
    if kind == "tanh":
        return law["F"] * np.tanh(v / law["v0"])
    out = np.empty_like(theta_rad)
    if kind == "dahl":  # dF/dtheta = (Fc/x0)(1 - F sgn(v)/Fc): exact exponential in angle
        F, Fc, x0 = 0.0, law["F"], law["x0"]
        d_theta = np.diff(theta_rad, prepend=theta_rad[0])
        for i, d in enumerate(d_theta):
            if d != 0.0:
                s = Fc if d > 0 else -Fc
                F = s + (F - s) * math.exp(-abs(d) / x0)
            out[i] = F
        return out
    if kind == "lugre":
        z, Fc, Fs, vs = 0.0, law["F"], law["Fs"], law["vs"]
        s0, s1, s2 = Fc / law["x0"], law["s1"], law["s2"]
        for i, vi in enumerate(v):
            g = Fc + (Fs - Fc) * math.exp(-(vi / vs) ** 2)
            a = s0 * abs(vi) / g
            if a > 0:
                z_ss = vi / a
                z = z_ss + (z - z_ss) * math.exp(-a * dt_s)
            zdot = vi - a * z
            out[i] = s0 * z + s1 * zdot + s2 * vi
        return out
    if kind == "stickslip":  # a compliant contact sticks until |f| > Fs, slips back to Fk
        y, kd, Fs, Fk = 0.0, law["Fs"] / law["x_stick"], law["Fs"], law["Fk"]
        for i, th in enumerate(theta_rad):
            f = kd * (th - y)
            if abs(f) > Fs:
                y = th - math.copysign(Fk, f) / kd
                f = kd * (th - y)
            out[i] = f
        return out
    raise ValueError(f"unknown friction law {kind!r}")


def maxwell_Nm(theta_rad, dt_s, k_m, tau_s):
    """Torque (N·m) of a Maxwell arm (stiffness k_m in series with a dashpot, time constant tau)."""
    u = np.empty_like(theta_rad)
    a = math.exp(-dt_s / tau_s)
    ui = theta_rad[0]
    for i, th in enumerate(theta_rad):
        ui = th + (ui - th) * a
        u[i] = ui
    return k_m * (theta_rad - u)


def first_order(x, dt_s, tau_s):
    """Exact discrete first-order low-pass of ``x`` (time constant ``tau_s``), starting at x[0]."""
    from scipy.signal import lfilter

    a = math.exp(-dt_s / tau_s)
    y, _ = lfilter([1 - a], [1, -a], x, zi=[a * x[0]])
    return y


def soft_clip(x, limit):
    """A sensor that reads true below 0.9*limit and saturates smoothly (C1) toward ``limit``."""
    knee = 0.9 * limit
    over = np.abs(x) - knee
    clipped = np.sign(x) * (limit - 0.1 * limit * np.exp(-over / (0.1 * limit)))
    return np.where(over > 0, clipped, x)


# ------------------------------------------------------------------------------ the rig
@dataclass
class Record:
    """A simulated record at its own rate, SI units, plus the noise-free channels."""

    t_s: np.ndarray
    torque_Nm: np.ndarray
    angle_rad: np.ndarray
    clean_torque_Nm: np.ndarray
    clean_angle_rad: np.ndarray
    true_theta_rad: np.ndarray
    noise_sigma_Nm: float
    peak_torque_Nm: float


def _motion(spec):
    fs = spec["fs"]
    m = max(1, math.ceil(FINE_RATE_MIN_HZ / fs))
    name, kw = spec["protocol"]
    kw = dict(kw)
    if name == "random_levels":
        kw["rng"] = np.random.default_rng(kw.pop("level_seed"))
    t, theta = PROTOCOLS[name](fs * m, **kw)
    return t, theta, m


def clean_channels(spec, without=()):
    """Noise-free (torque read, angle read, true deflection) on the fine grid and the decimation m.

    ``without``: names of spec entries switched off (to measure one component's contribution).
    """
    sp = {k: v for k, v in spec.items() if k not in without}
    t, theta_cmd, m = _motion(sp)
    dt = t[1] - t[0]
    theta = theta_cmd
    if sp.get("cogging"):  # the motor's position ripple: the spring follows its true deflection
        c = sp["cogging"]
        theta = theta_cmd + c["A"] * np.sin(c["n"] * theta_cmd * c.get("gear", 1.0))
    if sp.get("k3"):
        k = sp["springs"][0]["k"]
        T = k * theta + sp["k3"] * theta**3
    else:
        T = stack_torque_Nm(theta, sp["springs"])
    dur = t[-1]
    if sp.get("kstep"):
        T = T * np.where(t > sp["kstep"]["t_frac"] * dur, 1 + sp["kstep"]["frac"], 1.0)
    if sp.get("tempK"):
        T = T * (1 + sp["tempK"]["frac"] * (1 - np.exp(-t / (sp["tempK"]["tau_frac"] * dur))))
    if sp.get("friction"):
        T = T + friction_Nm(theta, dt, sp["friction"])
    if sp.get("maxwell"):
        T = T + maxwell_Nm(theta, dt, sp["maxwell"]["k"], sp["maxwell"]["tau"])
    if sp.get("stop"):
        over = np.abs(theta) - sp["stop"]["theta"]
        T = T + np.sign(theta) * sp["stop"]["k"] * np.clip(over, 0, None)
    if sp.get("tooth"):
        T = T + sp["tooth"]["A"] * np.sin(sp["tooth"]["n"] * theta + sp["tooth"].get("phi", 0.0))
    lag = sp.get("lag")
    if lag:
        if lag["law"] == "delay":
            T = np.interp(t - lag["d"], t, T)
        elif lag["law"] == "filter1":
            T = first_order(T, dt, lag["tau"])
        elif lag["law"] == "filter2":
            T = first_order(first_order(T, dt, lag["tau"]), dt, lag["tau"])
        elif lag["law"] == "angle_delay":
            pass
        else:
            raise ValueError(f"unknown lag law {lag['law']!r}")
    if sp.get("clip"):
        T = soft_clip(T, sp["clip"]["T"])
    T = T + sp.get("torque_offset", 0.0)
    if sp.get("drift"):
        T = T + sp["drift"]["rate"] * t
    if sp.get("settle"):
        T = T + sp["settle"]["A"] * (1 - np.exp(-t / (sp["settle"]["tau_frac"] * dur)))
    if sp.get("hum"):
        T = T + sp["hum"]["A"] * np.sin(2 * np.pi * sp["hum"]["f"] * t + 0.3)
    angle = theta + sp.get("angle_offset", 0.0)
    if lag and lag["law"] == "angle_delay":
        angle = np.interp(t - lag["d"], t, angle)
    if sp.get("ecc"):
        e = sp["ecc"]
        angle = angle + e["e"] * np.sin(e["G"] * theta + e["phi"])
    return t[::m], T[::m], angle[::m], theta[::m]


def simulate(spec, seed):
    """Simulate ``spec`` (see heldout_fit_f_cases) with noise from ``seed``; returns a Record."""
    rng = np.random.default_rng(seed)
    t, T, angle, theta = clean_channels(spec)
    nz = spec["noise"]
    peak = float(np.abs(T).max())
    sigma = nz["torque_pct"] / 100 * peak
    w = rng.standard_normal(t.size)
    rho = nz.get("rho", 0.0)
    if rho:
        from scipy.signal import lfilter

        w = lfilter([math.sqrt(1 - rho**2)], [1, -rho], w)
    Tm = T + sigma * w
    if spec.get("outliers"):
        o = spec["outliers"]
        idx = rng.choice(np.arange(50, t.size - 50), o["n"], replace=False)
        Tm[idx] += rng.choice([-1, 1], o["n"]) * o["frac"] * peak * rng.uniform(0.7, 1.3, o["n"])
    adc_q = 2.6 * peak / 2**16
    Tm = np.round(Tm / adc_q) * adc_q
    am = angle + nz["angle_sd"] * rng.standard_normal(t.size)
    if nz.get("enc_bits"):
        q = 2 * np.pi / 2 ** nz["enc_bits"]
        am = np.round(am / q) * q
    return Record(t + spec.get("t0", 0.0), Tm, am, T, angle, theta, sigma, peak)


def equivalent_noise_Nm(spec, rec, k):
    """Noise sigma (N·m) of torque - K*angle: torque noise and K times angle noise in quadrature."""
    nz = spec["noise"]
    q = 2 * np.pi / 2 ** nz["enc_bits"] if nz.get("enc_bits") else 0.0
    return math.sqrt(rec.noise_sigma_Nm**2 + k**2 * (nz["angle_sd"] ** 2 + q**2 / 12))


def remainder_ratio(spec, key, rec, k):
    """RMS of what component ``key`` adds to torque - K*angle after projecting out the basis
    [1, t, theta, max(theta,0), theta^3, sign(v), v], over the equivalent noise sigma."""
    t, T1, a1, th = clean_channels(spec)
    _, T0, a0, _ = clean_channels(spec, without=(key,))
    c = (T1 - T0) - k * (a1 - a0)
    v = np.gradient(th, t)
    basis = np.column_stack([np.ones_like(t), t, th, np.clip(th, 0, None), th**3,
                             np.sign(np.where(np.abs(v) > 1e-9, v, 0.0)), v])
    coef, *_ = np.linalg.lstsq(basis, c, rcond=None)
    rem = c - basis @ coef
    return float(np.sqrt(np.mean(rem**2)) / equivalent_noise_Nm(spec, rec, k))


FORMATS = {  # name: (columns, torque factor from N·m, angle factor from rad, CLI options)
    "si": (("time_s", "torque_Nm", "deflection_rad"), 1.0, 1.0, []),
    "deg": (("time_s", "torque_Nm", "deflection_deg"), 1.0, 180 / np.pi,
            ["--deflection-col", "deflection_deg", "--angle-unit", "deg"]),
    "nmm_deg": (("t_s", "T_Nmm", "angle_deg"), 1000.0, 180 / np.pi,
                ["--time-col", "t_s", "--torque-col", "T_Nmm", "--deflection-col", "angle_deg",
                 "--angle-unit", "deg", "--torque-unit", "Nmm"]),
}


def write_csv(path, rec, fmt):
    """Write ``rec`` in file format ``fmt``; returns the CLI options a user would pass."""
    cols, tf, af, opts = FORMATS[fmt]
    data = np.column_stack([rec.t_s, rec.torque_Nm * tf, rec.angle_rad * af])
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="", fmt="%.10g")
    return list(opts)
