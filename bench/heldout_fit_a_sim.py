"""Independent bench simulator for the held-out fit test A (``bench/heldout_fit_a.py``).

Written from the physics description alone (a torsion spring clamped in a bench: a motor
turns one end, a torque sensor reads the reaction, an encoder reads the deflection); it
shares no code with ``springcad.fit``. Everything is computed on a fine internal time grid
(at least 4 kHz) and then sampled at the record's rate.

Units: time s, angle rad, torque N·m, stiffness N·m/rad, friction torque N·m, speed rad/s.

Protocols (commanded angle): staircase with holds, triangles with or without holds, ramps
at one, two or three rates (linear or cosine-shaped), random level sequences, a sine.

Laws (own forms, not the library's):
- spring: linear, cubic, asymmetric, hard stop beyond an angle, standard-linear-solid
  viscoelastic relaxation (torque decays at constant angle with time constant tau_r);
- backlash: hard dead band of total width b, or a Hertzian contact (T = k_h * d^1.5 past
  the gap) in series with the spring, i.e. a smooth take-up;
- friction (parallel to the spring, driven by the motor angle): Jenkins elasto-plastic
  (Coulomb with a linear presliding stiffness), Dahl (exponential reversal), LuGre bristle
  with a Stribeck curve and viscous term, regularised Coulomb tanh(v/v0) (zero at rest),
  viscous c*v;
- sensor: pure delay of the torque channel (or of the deflection channel), or a first-order
  low-pass filter on the torque; torque zero
  offset, linear drift, exponentially settling (thermal) drift, clipping at the range;
  white or AR(1) coloured noise, isolated spikes; encoder quantisation and angle offset.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

FINE_RATE_HZ = 4000.0
SERVO_SMOOTH_S = 0.004  # the servo rounds command corners over ~4 ms


# ----------------------------------------------------------------------------- protocols
def path_from_levels(targets_rad, speeds_rad_per_s, holds_s, shape="linear", start_hold_s=0.5):
    """Knots of a level sequence: from 0, ramp to each target at its mean speed, then hold.

    Returns a list of (t0_s, t1_s, a0_rad, a1_rad, shape) segments (holds have a0 == a1).
    """
    segs, t, a = [], 0.0, 0.0
    segs.append((0.0, start_hold_s, 0.0, 0.0, "hold"))
    t = start_hold_s
    n = len(targets_rad)
    speeds = np.broadcast_to(np.asarray(speeds_rad_per_s, float), (n,))
    holds = np.broadcast_to(np.asarray(holds_s, float), (n,))
    for target, v, h in zip(targets_rad, speeds, holds):
        dur = abs(target - a) / v
        if dur > 0:
            segs.append((t, t + dur, a, target, shape))
            t += dur
        a = target
        if h > 0:
            segs.append((t, t + h, a, a, "hold"))
            t += h
    return segs


def eval_path(segs, t_s):
    """Commanded angle (rad) of the segments at times t_s (s); servo-smoothed corners."""
    theta = np.zeros_like(t_s)
    for t0, t1, a0, a1, shape in segs:
        m = (t_s >= t0) & (t_s < t1)
        s = (t_s[m] - t0) / (t1 - t0)
        if shape == "cosine":
            s = 0.5 * (1.0 - np.cos(np.pi * s))
        theta[m] = a0 + (a1 - a0) * s
    t_end, a_end = segs[-1][1], segs[-1][3]
    theta[t_s >= t_end] = a_end
    dt = t_s[1] - t_s[0]
    n = max(1, int(round(SERVO_SMOOTH_S / dt)))
    if n > 1:
        kernel = np.ones(n) / n
        theta = np.convolve(np.pad(theta, (n, n), mode="edge"), kernel, mode="same")[n:-n]
    return theta


def staircase(amps_rad, speed, hold_s, shape="linear"):
    targets = []
    for a in amps_rad:
        targets += [a, 0.0, -a, 0.0]
    return path_from_levels(targets, speed, hold_s, shape)


def multi_rate(amp_rad, speeds, n_cycles, shape="linear", hold_s=0.0):
    targets, sp = [], []
    for v in speeds:
        for _ in range(n_cycles):
            targets += [amp_rad, -amp_rad]
            sp += [v, v]
    targets.append(0.0)
    sp.append(speeds[-1])
    return path_from_levels(targets, sp, hold_s, shape)


def random_levels(rng, amp_rad, n, speed, hold_range_s, shape="linear"):
    targets = rng.uniform(-amp_rad, amp_rad, n)
    targets[np.argmax(targets)] = amp_rad  # reach the full range both ways
    targets[np.argmin(targets)] = -amp_rad
    holds = rng.uniform(*hold_range_s, n)
    return path_from_levels(list(targets) + [0.0], speed, list(holds) + [0.5], shape)


def sine_path(amp_rad, freqs_hz, n_cycles):
    """Sines one after the other (each n cycles from zero phase), 0.5 s rest between them."""
    return ("sine", amp_rad, tuple(freqs_hz), tuple(n_cycles))


def _sine_blocks(path):
    _, a, freqs, ns = path
    t0, blocks = 0.5, []
    for f, n in zip(freqs, ns):
        blocks.append((t0, t0 + n / f, f))
        t0 += n / f + 0.5
    return a, blocks, t0


def duration_of(path):
    """Record duration (s) of a protocol, with 0.5 s of rest at the end."""
    if isinstance(path, tuple):
        return _sine_blocks(path)[2] + 0.5
    return path[-1][1] + 0.5


def command(path, t_s):
    """Commanded angle (rad) of a protocol at times t_s (s)."""
    if isinstance(path, tuple):
        a, blocks, _ = _sine_blocks(path)
        th = np.zeros_like(t_s)
        for t0, t1, f in blocks:
            m = (t_s >= t0) & (t_s < t1)
            th[m] = a * np.sin(2 * np.pi * f * (t_s[m] - t0))
        return th
    return eval_path(path, t_s)


def resolve(spec, K, A_rad):
    """Turn the case's sizes given as fractions of the peak torque into N·m laws."""
    p = dict(spec)
    Tp = K * A_rad
    fr = p.get("friction")
    if fr is not None:
        fr = list(fr)
        if fr[0] in ("jenkins", "dahl", "tanh"):
            fr[1] = p["_fric_frac"] * Tp
        elif fr[0] == "lugre":  # (Fc, Fs/Fc -> Fs, vs, presliding, viscous frac -> sigma2)
            fr[1] = p["_fric_frac"] * Tp
            fr[2] = fr[2] * fr[1]
            fr[5] = p.get("_visc_frac", 0.0) * Tp / p.get("_visc_vmax", 1.0)
        elif fr[0] == "viscous":
            fr[1] = p["_visc_frac"] * Tp / p["_visc_vmax"]
        p["friction"] = tuple(fr)
    if "_k3_frac" in p:
        p["k3"] = p["_k3_frac"] * Tp / A_rad ** 3
    return p


# ----------------------------------------------------------------------------- laws
def deadband(theta, b_rad):
    return np.sign(theta) * np.maximum(np.abs(theta) - b_rad / 2, 0.0)


def hertz_backlash_torque(theta, b_rad, K, delta_peak_rad, T_peak):
    """Torque through a gap b then a Hertzian contact (T = k_h d^1.5) in series with K.

    k_h is set so the contact yields delta_peak_rad at T_peak. Solves
    |theta| - b/2 = T/K + (T/k_h)^(2/3) for T >= 0 by bisection.
    """
    kh = T_peak / delta_peak_rad ** 1.5
    x = np.maximum(np.abs(theta) - b_rad / 2, 0.0)
    lo, hi = np.zeros_like(x), K * x
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        f = mid / K + (mid / kh) ** (2.0 / 3.0) - x
        lo = np.where(f < 0, mid, lo)
        hi = np.where(f < 0, hi, mid)
    return np.sign(theta) * 0.5 * (lo + hi)


def spring_torque(phi, K, k3=0.0, K_neg=None, stop_rad=None, K_stop=0.0):
    """Static spring law on the spring angle phi (rad)."""
    Kp = np.where(phi >= 0, K, K if K_neg is None else K_neg)
    T = Kp * phi + k3 * phi ** 3
    if stop_rad is not None:
        T += K_stop * np.sign(phi) * np.maximum(np.abs(phi) - stop_rad, 0.0)
    return T


def sls_extra(phi, dt, K1, tau_r):
    """Standard-linear-solid branch: q' = K1 phi' - q/tau_r (exact for linear phi per step)."""
    e = np.exp(-dt / tau_r)
    dphi = np.diff(phi, prepend=phi[0])
    return lfilter([K1 * (tau_r / dt) * (1 - e)], [1.0, -e], dphi)


def jenkins(theta, Fc, k_pre):
    """Coulomb with a linear presliding stiffness k_pre (elasto-plastic, Jenkins element)."""
    out = np.empty_like(theta)
    f, prev = 0.0, theta[0]
    for i, th in enumerate(theta):
        f = min(Fc, max(-Fc, f + k_pre * (th - prev)))
        prev = th
        out[i] = f
    return out


def dahl(theta, Fc, sigma):
    """Dahl friction: dF/dtheta = sigma (1 - F sgn(dtheta)/Fc), exact per step."""
    out = np.empty_like(theta)
    f, prev = 0.0, theta[0]
    xc = Fc / sigma
    for i, th in enumerate(theta):
        d = th - prev
        if d != 0.0:
            s = Fc if d > 0 else -Fc
            f = s + (f - s) * np.exp(-abs(d) / xc)
        prev = th
        out[i] = f
    return out


def lugre(theta, dt, Fc, Fs, vs, sigma0, sigma2):
    """LuGre bristle: z' = v - sigma0 |v| z / g(v), g = Fc + (Fs-Fc) exp(-(v/vs)^2).

    F = sigma0 z + sigma2 v (no bristle damping); exact per step at constant v.
    """
    v = np.diff(theta, prepend=theta[0]) / dt
    g = Fc + (Fs - Fc) * np.exp(-(v / vs) ** 2)
    out = np.empty_like(theta)
    z, prev = 0.0, theta[0]
    for i, th in enumerate(theta):
        d = th - prev
        if d != 0.0:
            zs = (g[i] if d > 0 else -g[i]) / sigma0
            z = zs + (z - zs) * np.exp(-sigma0 * abs(d) / g[i])
        prev = th
        out[i] = sigma0 * z
    return out + sigma2 * v


def speed_of(theta, dt):
    return np.gradient(theta, dt)


def first_order_filter(x, dt, tau):
    e = np.exp(-dt / tau)
    return lfilter([1 - e], [1.0, -e], x)


def delayed(x, t, d):
    return np.interp(t - d, t, x, left=x[0])


# ----------------------------------------------------------------------------- one record
def simulate(spec, rng):
    """Simulate one record from a spec dict (see ``heldout_fit_a.CASES``).

    Returns dict with t_s, torque_Nm, deflection_rad (measured, SI, before unit change),
    peak_torque_Nm, noise_Nm and ool_rms_over_noise: the RMS of the part of the noiseless
    torque that the case's out-of-library laws add over their library counterparts, after
    the best linear fit in angle, divided by the torque noise (0 when none).
    """
    fs = spec["fs"]
    path = spec["path"]
    T_end = duration_of(path)
    fine = max(FINE_RATE_HZ, fs)
    tf = np.arange(0.0, T_end, 1.0 / fine)
    dt = 1.0 / fine
    theta = command(path, tf)
    K = spec["K"]
    A = float(np.max(np.abs(theta)))
    Tp = K * A
    p = resolve(spec, K, A)

    def torque_chain(lib_equiv):
        # spring angle through backlash
        if "hertz" in p and not lib_equiv:
            Ts = hertz_backlash_torque(theta, p["hertz"][0], K, p["hertz"][1], Tp)
            phi = Ts / K
        else:
            b = p.get("backlash", p["hertz"][0] if "hertz" in p else 0.0)
            phi = deadband(theta, b)
            Ts = None
        if Ts is None:
            stop = p.get("stop")
            Ts = spring_torque(phi, K, p.get("k3", 0.0), p.get("K_neg"),
                               None if (stop is None or lib_equiv) else stop[0] * A,
                               0.0 if stop is None else stop[1] * K)
        if "sls" in p and not lib_equiv:
            Ts = Ts + sls_extra(phi, dt, p["sls"][0] * K, p["sls"][1])
        F = np.zeros_like(theta)
        fr = p.get("friction")
        if fr is not None:
            kind = fr[0]
            if kind == "jenkins":
                F = jenkins(theta, fr[1], fr[1] / fr[2])
            elif kind == "dahl":
                F = dahl(theta, fr[1], fr[1] / fr[2]) if not lib_equiv else jenkins(theta, fr[1], fr[1] / fr[2])
            elif kind == "lugre":  # (Fc, Fs, vs, presliding, sigma2)
                if lib_equiv:
                    F = jenkins(theta, fr[1], fr[1] / fr[4]) + fr[5] * speed_of(theta, dt)
                else:
                    F = lugre(theta, dt, fr[1], fr[2], fr[3], fr[1] / fr[4], fr[5])
            elif kind == "tanh":  # (Fc, v0)
                F = (fr[1] * np.tanh(speed_of(theta, dt) / fr[2]) if not lib_equiv
                     else jenkins(theta, fr[1], fr[1] / 1e-4))
            elif kind == "viscous":  # (c); counterpart: the spring torque read c/K earlier
                F = (fr[1] * speed_of(theta, dt) if not lib_equiv
                     else delayed(Ts, tf, -fr[1] / K) - Ts)
        T = Ts + F
        if "filter" in p:
            T = first_order_filter(T, dt, p["filter"]) if not lib_equiv else delayed(T, tf, p["filter"])
        if "delay" in p:
            T = delayed(T, tf, p["delay"])
        T = T + p.get("offset_frac", 0.0) * Tp
        if "drift_frac" in p:
            T = T + p["drift_frac"] * Tp * tf / T_end
        if "settle" in p:  # (fraction of peak, tau as a fraction of the record)
            z = p["settle"][0] * Tp * (1 - np.exp(-tf / (p["settle"][1] * T_end)))
            if lib_equiv:
                z = np.polyval(np.polyfit(tf, z, 1), tf)
            T = T + z
        if "clip_frac" in p and not lib_equiv:
            T = np.clip(T, -p["clip_frac"] * Tp, p["clip_frac"] * Tp)
        return T

    T_true = torque_chain(False)
    T_lib = torque_chain(True)
    t = np.arange(0.0, T_end, 1.0 / fs)
    torque = np.interp(t, tf, T_true)
    diff = np.interp(t, tf, T_true - T_lib)
    th_s = np.interp(t - p.get("angle_delay", 0.0), tf, theta, left=0.0)  # a late deflection channel
    basis = np.c_[th_s, np.ones_like(th_s)]
    diff = diff - basis @ np.linalg.lstsq(basis, diff, rcond=None)[0]
    sigma = p.get("noise_frac", 0.003) * Tp
    ool = float(np.sqrt(np.mean(diff ** 2)) / sigma)
    if p.get("ar1"):
        rho = p["ar1"]
        w = rng.normal(0.0, sigma * np.sqrt(1 - rho ** 2), t.size)
        noise = lfilter([1.0], [1.0, -rho], w)
    else:
        noise = rng.normal(0.0, sigma, t.size)
    torque = torque + noise
    defl = th_s + p.get("angle_offset", 0.0) + rng.normal(0.0, p.get("angle_noise", 3e-5), t.size)
    if "quant_counts" in p:
        q = 2 * np.pi / p["quant_counts"]
        defl = np.round(defl / q) * q
    if "outliers" in p:  # (channel, count, size as fraction of peak torque / of amplitude)
        ch, n, size = p["outliers"]
        idx = rng.choice(np.arange(50, t.size - 50), n, replace=False)
        signs = rng.choice([-1.0, 1.0], n)
        if ch == "torque":
            torque[idx] += signs * size * Tp * rng.uniform(0.7, 1.3, n)
        else:
            defl[idx] += signs * size * A * rng.uniform(0.7, 1.3, n)
    return dict(t_s=t, torque_Nm=torque, deflection_rad=defl, peak_torque_Nm=Tp,
                noise_Nm=sigma, amp_rad=A, ool_rms_over_noise=ool)
