"""Held-out generator C: protocols, rig laws and the record simulator.

Written from /work/wt/FIT_PHYSICS.md alone (plus issue 24's text, the README's
`springcad fit` section and `springcad fit --help`); nothing under springcad/fit/, no
other held-out generator and no fit test was read. Every law here is this file's own.

Units inside: time s, angle rad, torque N·m, stiffness N·m/rad. A record is the true
deflection across the assembly (the motor-side angle relative to the fixed end), the
torque the sensor would read, and the channels' sensor models (noise, quantisation,
clipping, delay or filter, zero errors).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


# --------------------------------------------------------------------------- protocols
@dataclass
class Protocol:
    """A commanded deflection history.

    Attributes:
        name: short protocol name (staircase, ramps, sines, chirp, triangle, levels).
        t_s: sample times (s).
        theta_rad: deflection across the assembly (rad).
        n_speeds: distinct ramp speeds (0 = speed varies continuously: sines, chirps).
        has_holds: whether the angle stands still for at least 0.3 s somewhere.
    """

    name: str
    t_s: np.ndarray
    theta_rad: np.ndarray
    n_speeds: int
    has_holds: bool


def _from_segments(fs_Hz: float, segs: list[tuple[float, float, str]], lead_s: float = 0.5) -> tuple:
    """Concatenate (target_rad, duration_s, shape) segments after a lead-in hold at 0.

    shape is "lin" (constant speed) or "cos" (cosine-shaped: zero speed at both ends).
    """
    pieces = [np.zeros(max(int(round(lead_s * fs_Hz)), 1))]
    a = 0.0
    for target, dur, shape in segs:
        n = max(int(round(dur * fs_Hz)), 1)
        u = np.arange(1, n + 1) / n
        if shape == "cos":
            u = 0.5 - 0.5 * np.cos(np.pi * u)
        pieces.append(a + (target - a) * u)
        a = target
    theta = np.concatenate(pieces)
    return np.arange(theta.size) / fs_Hz, theta


def staircase(fs_Hz: float, amps_rad: list[float], speed_rad_s: float, hold_s: float,
              shape: str = "lin") -> Protocol:
    """The paper's staircase: 0 -> +a -> 0 -> -a -> 0 for growing a, a hold after each ramp."""
    segs = []
    for a in amps_rad:
        for target, prev in ((a, 0.0), (0.0, a), (-a, 0.0), (0.0, -a)):
            segs.append((target, abs(target - prev) / speed_rad_s, shape))
            segs.append((target, hold_s, "lin"))
    t, th = _from_segments(fs_Hz, segs)
    return Protocol("staircase", t, th, 1, hold_s >= 0.3)


def ramps(fs_Hz: float, amp_rad: float, speeds_rad_s: list[float], cycles: int,
          hold_s: float, shape: str = "lin") -> Protocol:
    """Full cycles 0 -> +A -> -A -> 0 at each speed in turn (holds at the extremes)."""
    segs = []
    for v in speeds_rad_s:
        pos = 0.0
        for _ in range(cycles):
            for target in (amp_rad, -amp_rad):
                segs.append((target, abs(target - pos) / v, shape))
                if hold_s > 0:
                    segs.append((target, hold_s, "lin"))
                pos = target
        segs.append((0.0, abs(pos) / v, shape))
        if hold_s > 0:
            segs.append((0.0, hold_s, "lin"))
    t, th = _from_segments(fs_Hz, segs)
    return Protocol("ramps" if len(speeds_rad_s) > 1 else "triangle", t, th,
                    len(set(speeds_rad_s)), hold_s >= 0.3)


def random_levels(fs_Hz: float, rng: np.random.Generator, amp_rad: float,
                  speeds_rad_s: list[float], n_levels: int, hold_range_s=(0.5, 2.0)) -> Protocol:
    """Random targets in [-A, A] reached by linear ramps (speed drawn from the list), held."""
    segs, pos = [], 0.0
    for i in range(n_levels):
        target = float(rng.uniform(-amp_rad, amp_rad))
        if abs(target - pos) < 0.15 * amp_rad:
            target = -math.copysign(0.6 * amp_rad, pos) if pos else 0.6 * amp_rad
        v = speeds_rad_s[i % len(speeds_rad_s)]
        segs.append((target, abs(target - pos) / v, "lin"))
        segs.append((target, float(rng.uniform(*hold_range_s)), "lin"))
        pos = target
    if abs(pos) > 0.1 * amp_rad:
        segs.append((0.0, abs(pos) / speeds_rad_s[0], "lin"))
        segs.append((0.0, 0.5, "lin"))
    t, th = _from_segments(fs_Hz, segs)
    return Protocol("levels", t, th, len(set(speeds_rad_s)), True)


def sines(fs_Hz: float, parts: list[tuple[float, float, int]], gap_s: float = 0.0) -> Protocol:
    """Sine segments (amp_rad, freq_Hz, whole periods), each starting and ending at 0."""
    pieces = [np.zeros(int(0.3 * fs_Hz))]
    for amp, f, n in parts:
        m = int(round(n / f * fs_Hz))
        tt = np.arange(1, m + 1) / fs_Hz
        pieces.append(amp * np.sin(2 * np.pi * f * tt))
        if gap_s > 0:
            pieces.append(np.zeros(int(gap_s * fs_Hz)))
    th = np.concatenate(pieces)
    distinct = len({(a, f) for a, f, _ in parts})
    return Protocol("sines", np.arange(th.size) / fs_Hz, th, 0 if distinct > 1 else 1, gap_s >= 0.3)


def chirp(fs_Hz: float, amp_rad: float, f0_Hz: float, f1_Hz: float, dur_s: float) -> Protocol:
    """Linear chirp A·sin(2π(f0 t + (f1-f0) t²/2T)), ending at the nearest zero crossing."""
    t = np.arange(int(dur_s * fs_Hz)) / fs_Hz
    phase = 2 * np.pi * (f0_Hz * t + (f1_Hz - f0_Hz) * t ** 2 / (2 * dur_s))
    cut = int(np.searchsorted(phase, np.floor(phase[-1] / np.pi) * np.pi))
    th = amp_rad * np.sin(phase[:cut])
    th = np.concatenate([np.zeros(int(0.3 * fs_Hz)), th])
    return Protocol("chirp", np.arange(th.size) / fs_Hz, th, 0, False)


# --------------------------------------------------------------------------- laws
def dead_zone(theta_rad: np.ndarray, gap_rad: float, centre_rad: float = 0.0) -> np.ndarray:
    """Spring deflection behind a free play of total width gap_rad centred at centre_rad."""
    x = theta_rad - centre_rad
    h = gap_rad / 2
    return np.sign(x) * np.maximum(np.abs(x) - h, 0.0)


def hertz_take_up(theta_rad: np.ndarray, K: float, gap_rad: float, w_rad: float) -> np.ndarray:
    """Torque behind a play with a Hertzian take-up: T = (2/3)K d^1.5/sqrt(w) for a contact
    penetration d < w, then linear K(d - w/3) (value and slope continuous at d = w)."""
    d = np.maximum(np.abs(theta_rad) - gap_rad / 2, 0.0)
    soft = (2.0 / 3.0) * K * d ** 1.5 / math.sqrt(w_rad)
    return np.sign(theta_rad) * np.where(d < w_rad, soft, K * (d - w_rad / 3))


def dahl(theta_rad: np.ndarray, Fc_Nm: float, sigma_Nm_per_rad: float) -> np.ndarray:
    """Dahl (presliding Coulomb) friction: dF/dθ = σ(1 - F sgn(dθ)/Fc), exact per step."""
    F = np.empty_like(theta_rad)
    f = 0.0
    d = np.diff(theta_rad, prepend=theta_rad[0])
    k = sigma_Nm_per_rad / Fc_Nm
    for i, di in enumerate(d.tolist()):
        if di != 0.0:
            s = Fc_Nm if di > 0 else -Fc_Nm
            f = s + (f - s) * math.exp(-k * abs(di))
        F[i] = f
    return F


def tanh_friction(v_rad_s: np.ndarray, Fc_Nm: float, v0_rad_s: float) -> np.ndarray:
    """Regularised Coulomb friction Fc·tanh(v/v0): zero at rest."""
    return Fc_Nm * np.tanh(v_rad_s / v0_rad_s)


def lugre(v_rad_s: np.ndarray, dt_s: float, Fc_Nm: float, Fs_Nm: float, vs_rad_s: float,
          sigma0: float, sigma1: float = 0.0, sigma2: float = 0.0) -> np.ndarray:
    """LuGre friction with a Stribeck curve g(v) = Fc + (Fs-Fc)exp(-(v/vs)^2); bristle state
    integrated exactly for a frozen speed each step; F = σ0 z + σ1 dz/dt + σ2 v."""
    F = np.empty_like(v_rad_s)
    z = 0.0
    for i, v in enumerate(v_rad_s.tolist()):
        z_old = z
        if v != 0.0:
            g = Fc_Nm + (Fs_Nm - Fc_Nm) * math.exp(-(v / vs_rad_s) ** 2)
            zs = math.copysign(g / sigma0, v)
            z = zs + (z - zs) * math.exp(-sigma0 * abs(v) * dt_s / g)
        F[i] = sigma0 * z + sigma1 * (z - z_old) / dt_s + sigma2 * v
    return F


def maxwell_branch(theta_rad: np.ndarray, dt_s: float, k1: float, tau_s: float) -> np.ndarray:
    """Viscoelastic (standard linear solid) branch: dT/dt = k1 dθ/dt - T/τ, exact per step."""
    a = math.exp(-dt_s / tau_s)
    d = np.diff(theta_rad, prepend=theta_rad[0])
    out = np.empty_like(theta_rad)
    m = 0.0
    for i, di in enumerate(d.tolist()):
        m = a * m + k1 * di * (1 + a) / 2
        out[i] = m
    return out


def stick_slip(theta_rad: np.ndarray, amp_pp_Nm: float, period_rad: float) -> np.ndarray:
    """A stick-slip sawtooth: rises linearly with travel over period_rad then snaps back,
    sign of the current (or last) motion; frozen while the angle stands still."""
    d = np.diff(theta_rad, prepend=theta_rad[0])
    travel = np.cumsum(np.abs(d))
    sgn = np.sign(d)
    idx = np.where(sgn != 0, np.arange(sgn.size), 0)
    np.maximum.accumulate(idx, out=idx)
    sgn = sgn[idx]
    return sgn * amp_pp_Nm * ((travel / period_rad) % 1.0 - 0.5)


def first_order(x: np.ndarray, dt_s: float, tau_s: float) -> np.ndarray:
    """First-order low-pass (exact for a signal linear between samples), started settled."""
    from scipy.signal import lfilter
    a = math.exp(-dt_s / tau_s)
    y, _ = lfilter([1 - a], [1, -a], x, zi=[a * x[0]])
    return y


def delayed(t_s: np.ndarray, x: np.ndarray, d_s: float) -> np.ndarray:
    """x read d_s later than the time stamp says (pure delay), held at the ends."""
    return np.interp(t_s - d_s, t_s, x)


def smooth_peak(x: np.ndarray, fs_Hz: float, window_s: float = 0.01) -> float:
    """Largest |moving average| of x over window_s: how far a structure stands out."""
    n = max(int(round(window_s * fs_Hz)), 1)
    if n == 1:
        return float(np.max(np.abs(x)))
    return float(np.max(np.abs(np.convolve(x, np.ones(n) / n, mode="valid"))))


# --------------------------------------------------------------------------- the rig
@dataclass
class Rig:
    """Everything between the commanded deflection and the two recorded channels.

    Friction laws (``friction`` dict, key "law"): "dahl" (Fc, sigma), "tanh" (Fc, v0),
    "viscous" (c), "lugre" (Fc, Fs, vs, sigma0, sigma1, sigma2). All acting on the
    assembly's motion and adding to the sensed torque. Torque zero errors (offset,
    drift, settle) belong to the sensor and are not delayed; the delay or filter acts on
    the load torque.
    """

    K: float
    noise_T_frac: float = 0.003          # torque noise std as a fraction of the peak torque
    noise_theta_rad: float = 1e-4
    k3: float = 0.0
    K_neg_factor: float = 1.0
    gap_rad: float = 0.0
    gap_centre_rad: float = 0.0
    hertz_w_rad: float = 0.0
    stop_rad: float = 0.0
    stop_K_factor: float = 0.0
    K_step: tuple | None = None          # (time_s, factor)
    K_thermal: tuple | None = None       # (fractional change at the end, settling tau_s)
    friction: dict | None = None
    maxwell: tuple | None = None         # (k1, tau_s)
    stickslip: tuple | None = None       # (amp_pp_Nm, period_rad)
    ripple: tuple | None = None          # (amp_Nm, period_rad, phase_rad)
    hum: tuple | None = None             # (amp_Nm, freq_Hz)
    torque_offset_Nm: float = 0.0
    angle_offset_rad: float = 0.0
    drift_Nm_per_s: float = 0.0
    settle: tuple | None = None          # (amp_Nm, tau_s)
    delay_s: float = 0.0
    filter_tau_s: float = 0.0
    clip_frac: float = 0.0               # clip at this fraction of the peak torque
    colour: float = 0.0                  # share of AR(1) (phi 0.95) torque noise power
    counts_per_rev: int = 0              # encoder quantisation of the angle channel
    outliers: tuple | None = None        # (count, amp in noise std)
    extra: dict = field(default_factory=dict)


@dataclass
class Parts:
    """Noiseless components of a simulated record (for the truth labels) and the record."""

    t_s: np.ndarray
    theta_rad: np.ndarray
    v_rad_s: np.ndarray
    spring_Nm: np.ndarray
    friction_Nm: np.ndarray
    other_Nm: dict
    load_Nm: np.ndarray
    sensed_Nm: np.ndarray               # after delay/filter, before zero errors and noise
    sigma_T_Nm: float
    peak_Nm: float
    torque_meas_Nm: np.ndarray
    theta_meas_rad: np.ndarray


def spring_torque(rig: Rig, theta_rad: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """Spring (and stop) torque for the assembly deflection theta_rad."""
    if rig.hertz_w_rad > 0:
        T = hertz_take_up(theta_rad - rig.gap_centre_rad, rig.K, rig.gap_rad, rig.hertz_w_rad)
    else:
        th = dead_zone(theta_rad, rig.gap_rad, rig.gap_centre_rad) if rig.gap_rad > 0 else theta_rad
        K = np.where(th >= 0, rig.K, rig.K * rig.K_neg_factor)
        T = K * th + rig.k3 * th ** 3
    if rig.K_step is not None:
        T = np.where(t_s >= rig.K_step[0], T * rig.K_step[1], T)
    if rig.K_thermal is not None:
        T = T * (1 + thermal_K_factor(t_s, *rig.K_thermal))
    return T


def thermal_K_factor(t_s: np.ndarray, frac: float, tau_s: float) -> np.ndarray:
    """Fractional change of K as the spring warms: frac·(1 - exp(-t/τ)) (steel softens)."""
    return frac * (1 - np.exp(-t_s / tau_s))


def friction_torque(rig: Rig, theta_rad: np.ndarray, v_rad_s: np.ndarray, dt_s: float) -> np.ndarray:
    """Friction torque of the rig's law (zero without friction)."""
    f = rig.friction
    if not f:
        return np.zeros_like(theta_rad)
    law = f["law"]
    if law == "dahl":
        return dahl(theta_rad, f["Fc"], f["sigma"])
    if law == "tanh":
        return tanh_friction(v_rad_s, f["Fc"], f["v0"])
    if law == "viscous":
        return f["c"] * v_rad_s
    if law == "lugre":
        return lugre(v_rad_s, dt_s, f["Fc"], f["Fs"], f["vs"], f["sigma0"],
                     f.get("sigma1", 0.0), f.get("sigma2", 0.0))
    raise ValueError(f"friction law {law!r}: allowed dahl, tanh, viscous, lugre")


def simulate(rig: Rig, proto: Protocol, rng: np.random.Generator) -> Parts:
    """Simulate one record; returns the noiseless parts and the measured channels."""
    t, th = proto.t_s, proto.theta_rad
    dt = float(t[1] - t[0])
    v = np.diff(th, prepend=th[0]) / dt     # backward difference: constant on a linear ramp
    spring = spring_torque(rig, th, t)
    if rig.stop_rad > 0:
        spring = spring + rig.stop_K_factor * rig.K * np.sign(th) * np.maximum(np.abs(th) - rig.stop_rad, 0)
    fric = friction_torque(rig, th, v, dt)
    other = {}
    if rig.maxwell:
        th_s = dead_zone(th, rig.gap_rad, rig.gap_centre_rad) if rig.gap_rad > 0 else th
        other["maxwell"] = maxwell_branch(th_s, dt, *rig.maxwell)
    if rig.stickslip:
        other["stickslip"] = stick_slip(th, *rig.stickslip)
    if rig.ripple:
        a, p, ph = rig.ripple
        other["ripple"] = a * np.sin(2 * np.pi * th / p + ph)
    if rig.hum:
        other["hum"] = rig.hum[0] * np.sin(2 * np.pi * rig.hum[1] * t + 0.7)
    load = spring + fric + sum(other.values(), np.zeros_like(t))
    peak = float(np.max(np.abs(spring + fric)))
    sensed = load
    if rig.delay_s:
        sensed = delayed(t, sensed, rig.delay_s)
    if rig.filter_tau_s:
        sensed = first_order(sensed, dt, rig.filter_tau_s)
    zero = rig.torque_offset_Nm + rig.drift_Nm_per_s * t
    if rig.settle:
        zero = zero + rig.settle[0] * (1 - np.exp(-t / rig.settle[1]))
    sigma = rig.noise_T_frac * peak
    white = rng.standard_normal(t.size)
    if rig.colour > 0:
        from scipy.signal import lfilter
        ar = lfilter([1.0], [1.0, -0.95], rng.standard_normal(t.size)) * math.sqrt(1 - 0.95 ** 2)
        white = math.sqrt(1 - rig.colour) * white + math.sqrt(rig.colour) * ar
    T_meas = sensed + zero + sigma * white
    if rig.clip_frac:
        lim = rig.clip_frac * peak
        T_meas = np.clip(T_meas, -lim, lim)
    if rig.outliers:
        n, amp = rig.outliers
        idx = rng.choice(np.arange(t.size // 20, t.size - t.size // 20), size=n, replace=False)
        T_meas[idx] += amp * sigma * rng.choice([-1.0, 1.0], size=n)
    th_meas = th + rig.angle_offset_rad + rig.noise_theta_rad * rng.standard_normal(t.size)
    if rig.counts_per_rev:
        q = 2 * np.pi / rig.counts_per_rev
        th_meas = np.round(th_meas / q) * q
    return Parts(t, th, v, spring, fric, other, load, sensed, sigma, peak, T_meas, th_meas)


def write_csv(path, parts: Parts, angle_unit: str, torque_unit: str) -> dict:
    """Write the record; returns the CLI options that read it (column names and units)."""
    ang = parts.theta_meas_rad * (180 / np.pi if angle_unit == "deg" else 1.0)
    tq = parts.torque_meas_Nm * (1000.0 if torque_unit == "Nmm" else 1.0)
    tcol = "torque_Nmm" if torque_unit == "Nmm" else "torque_Nm"
    acol = "angle_deg" if angle_unit == "deg" else "deflection_rad"
    data = np.column_stack([parts.t_s, tq, ang])
    np.savetxt(path, data, delimiter=",", header=f"time_s,{tcol},{acol}", comments="", fmt="%.9g")
    opts = []
    if angle_unit == "deg":
        opts += ["--angle-unit", "deg", "--deflection-col", acol]
    if torque_unit == "Nmm":
        opts += ["--torque-unit", "Nmm", "--torque-col", tcol]
    return {"cli_options": opts, "angle_unit": angle_unit, "torque_unit": torque_unit}
