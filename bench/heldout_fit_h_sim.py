"""Held-out generator H for `springcad fit`: the simulated bench (physics, sensors, files).

Written from the paper, the README's `springcad fit` section and `--help` only (see
bench/heldout_fit_h.md); nothing of `springcad/fit/` or of another generator's code.

Units: time s, angles rad, torque N·m, stiffness N·m/rad, damping N·m·s/rad.

The motor imposes an angle q(t) across the rig (quasi-static angle control). Physics runs on
a fine grid (8 kHz, an integer multiple of the record's rate), the channels are read at the
record's sample instants. Chain, motor to ground: motor encoder -> [creeping coupling |
slipping hub] -> stack (springs in series, each with its clearance; parallel elements on the
stack's deflection: friction, bump stop, preloaded pair, viscoelastic bushing) -> torque
sensor -> ground. The optical channel reads the stack's deflection; records whose deflection
column is the motor encoder say so (``deflection_source='motor'``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import signal

# ----------------------------------------------------------------------------- protocols


def min_jerk(s: np.ndarray) -> np.ndarray:
    """Minimum-jerk blend 0 -> 1 for s in [0, 1] (zero speed and acceleration at both ends)."""
    s = np.clip(s, 0.0, 1.0)
    return s ** 3 * (10 - 15 * s + 6 * s ** 2)


def moves(levels, move_s, hold_s, dt: float, start_hold_s: float = 0.5) -> np.ndarray:
    """Angle through `levels` (rad), minimum-jerk moves of `move_s` (s), holds of `hold_s` (s)."""
    levels = np.asarray(levels, float)
    move_s = np.broadcast_to(np.asarray(move_s, float), levels.shape)
    hold_s = np.broadcast_to(np.asarray(hold_s, float), levels.shape)
    out = [np.zeros(int(round(start_hold_s / dt)))]
    prev = 0.0
    for lev, m, h in zip(levels, move_s, hold_s):
        n = max(int(round(m / dt)), 2)
        out.append(prev + (lev - prev) * min_jerk(np.arange(1, n + 1) / n))
        out.append(np.full(int(round(h / dt)), lev))
        prev = lev
    return np.concatenate(out)


def linear_moves(levels, speed, hold_s, dt: float, corner_s: float = 0.04) -> np.ndarray:
    """Constant-speed ramps (rad/s) between levels with short cosine-blended corners and holds."""
    levels = np.asarray(levels, float)
    speed = np.broadcast_to(np.asarray(speed, float), levels.shape)
    hold_s = np.broadcast_to(np.asarray(hold_s, float), levels.shape)
    v = [np.zeros(int(round(0.5 / dt)))]
    prev = 0.0
    for lev, sp, h in zip(levels, speed, hold_s):
        dist = lev - prev
        dur = abs(dist) / sp
        nc = int(round(corner_s / dt))
        n = max(int(round(dur / dt)), 2 * nc + 2)
        prof = np.ones(n)
        ramp = 0.5 - 0.5 * np.cos(np.pi * np.arange(1, nc + 1) / (nc + 1))
        prof[:nc] = ramp
        prof[-nc:] = ramp[::-1]
        prof *= dist / (prof.sum() * dt)
        v.append(prof)
        v.append(np.zeros(int(round(h / dt))))
        prev = lev
    return np.cumsum(np.concatenate(v)) * dt


def prbs_levels(rng: np.random.Generator, n_bits: int, amp: float, n_levels: int = 7):
    """Multi-level pseudo-random sequence from a 7-bit LFSR (x^7 + x^6 + 1), 3 bits a level."""
    reg = int(rng.integers(1, 127))
    out = []
    for _ in range(n_bits):
        word = 0
        for _b in range(3):
            bit = ((reg >> 6) ^ (reg >> 5)) & 1
            reg = ((reg << 1) | bit) & 0x7F
            word = (word << 1) | bit
        out.append(word % n_levels)
    lev = np.array(out, float) / (n_levels - 1) * 2 - 1
    for i in range(1, len(lev)):  # a repeated level is a longer hold; nudge to keep motion
        if lev[i] == lev[i - 1]:
            lev[i] = -lev[i] * 0.5 if lev[i] != 0 else 0.5
    lev[np.argmax(np.abs(lev))] = np.sign(lev[np.argmax(np.abs(lev))])  # reach the peak
    return amp * lev


def multisine(t: np.ndarray, amp: float, f0: float, harmonics, fade_s: float = 1.0):
    """Schroeder-phased multisine (harmonics of f0, Hz) scaled to peak `amp`, faded in and out."""
    k = np.asarray(harmonics, float)
    ph = -np.pi * k * (k - 1) / len(k)
    x = np.sum(np.sin(2 * np.pi * f0 * np.outer(t, k) + ph), axis=1)
    w = np.ones_like(t)
    fi = t < fade_s
    w[fi] = 0.5 - 0.5 * np.cos(np.pi * t[fi] / fade_s)
    fo = t > t[-1] - fade_s
    w[fo] = 0.5 - 0.5 * np.cos(np.pi * (t[-1] - t[fo]) / fade_s)
    x = x * w
    return amp * x / np.max(np.abs(x))


def log_chirp(t: np.ndarray, amp: float, f1: float, f2: float, fade_s: float = 1.0):
    """Exponential sine sweep f1 -> f2 (Hz) over the record, faded in and out."""
    T = t[-1]
    L = T / np.log(f2 / f1)
    x = np.sin(2 * np.pi * f1 * L * (np.exp(t / L) - 1))
    w = np.clip(np.minimum(t, T - t) / fade_s, 0, 1)
    return amp * x * (0.5 - 0.5 * np.cos(np.pi * w))


def jog(rng: np.random.Generator, t: np.ndarray, amp: float, speed_rms: float,
        corr_s: float = 0.4, stop_frac: float = 0.25) -> np.ndarray:
    """Manual-jog-like motion: an Ornstein-Uhlenbeck speed, gated off for random pauses,
    low-passed at 3 Hz (band-limited like a real motor's), kept within +-amp by a soft wall;
    ends back at zero."""
    dt = t[1] - t[0]
    n = t.size
    a = np.exp(-dt / corr_s)
    w = rng.normal(0, speed_rms * np.sqrt(1 - a * a), n)
    v = signal.lfilter([1.0], [1.0, -a], w)
    # pauses: a two-state gate with mean dwell 0.8 s (stop) / 2.4 s (go)
    gate = np.ones(n)
    i = 0
    while i < n:
        go = int(rng.exponential(2.4 * (1 - stop_frac) / 0.75) / dt)
        stop = int(rng.exponential(0.8) / dt)
        gate[i + go:i + go + stop] = 0.0
        i += go + stop
    k = max(int(0.15 / dt), 1)
    gate = np.convolve(gate, np.ones(k) / k, mode="same")
    v = v * gate
    # a motor's speed is band-limited (rotor inertia, the jog controller): a 3 Hz low-pass
    b, a2 = signal.butter(2, 3.0 * 2 * dt)
    v = signal.lfilter(b, a2, v)
    q = np.zeros(n)
    for j in range(1, n):  # soft wall: speed scaled down when pushing outward near the edge
        x = q[j - 1]
        vj = v[j]
        if x * vj > 0:
            vj *= max(0.0, 1 - (abs(x) / amp) ** 4)
        q[j] = x + vj * dt
    q = q / max(np.max(np.abs(q)), 1e-9) * amp
    ramp = np.clip((t[-1] - t) / 1.5, 0, 1)  # return to zero over the last 1.5 s
    return q * (0.5 - 0.5 * np.cos(np.pi * ramp))


# ----------------------------------------------------------------------------- stack


@dataclass
class Spring:
    """One disk: stiffness (N·m/rad) each way, clearance (rad, full width) centred at c (rad).

    ``spread`` (rad) > 0 spreads the flexure tips' gaps uniformly over [b/2, b/2 + spread]:
    the N flexures engage one by one (manufacturing tolerance per flexure), a smooth take-up.
    ``k3`` is a cubic hardening T = K d + k3 d^3 (N·m/rad^3).
    """

    k_pos: float
    k_neg: float | None = None
    b: float = 0.0
    c: float = 0.0
    spread: float = 0.0
    n_flex: int = 24
    k3: float = 0.0

    def deflection(self, T: np.ndarray) -> np.ndarray:
        """Own deflection carrying torque T (monotone, without the clearance's centre)."""
        kn = self.k_neg if self.k_neg is not None else self.k_pos
        k = np.where(T >= 0, self.k_pos, kn)
        if self.spread > 0:
            d = np.linspace(0, self.b / 2 + self.spread + 5 * np.max(np.abs(T)) / min(k.min(), kn), 20001)
            gaps = self.b / 2 + (np.arange(self.n_flex) + 0.5) / self.n_flex * self.spread
            torque = np.sum(np.maximum(d[:, None] - gaps[None, :], 0), axis=1) / self.n_flex
            out = np.empty_like(T)
            pos = T >= 0
            out[pos] = np.interp(T[pos] / self.k_pos, torque, d)
            out[~pos] = -np.interp(-T[~pos] / kn, torque, d)
            return out
        d = T / k
        if self.k3:
            for _ in range(40):  # Newton on K d + k3 d^3 = T
                f = k * d + self.k3 * d ** 3 - T
                d = d - f / (k + 3 * self.k3 * d ** 2)
        return d + np.sign(T) * self.b / 2


@dataclass
class Stack:
    """Disks in series: theta(T) = sum_i [d_i(T) + c_i] (paper: clearances and compliances add)."""

    springs: list

    @property
    def k_series(self) -> float:
        """Small-torque series stiffness beyond the clearances (N·m/rad), positive side."""
        return 1.0 / sum(1.0 / s.k_pos for s in self.springs)

    @property
    def k_series_neg(self) -> float:
        return 1.0 / sum(1.0 / (s.k_neg if s.k_neg is not None else s.k_pos) for s in self.springs)

    def table(self, t_max: float):
        """Tabulated theta(T) on each side of zero: (theta_neg, T_neg, theta_pos, T_pos)."""
        key = round(t_max, 12)
        if getattr(self, "_table_key", None) != key:
            Tp = np.geomspace(1e-9 * t_max, 3 * t_max, 20000)
            Tn = -Tp[::-1]
            thp = sum(s.deflection(Tp) + s.c for s in self.springs)
            thn = sum(s.deflection(Tn) + s.c for s in self.springs)
            self._table = (thn, Tn, thp, Tp)
            self._table_key = key
        return self._table

    def torque_of(self, theta: np.ndarray, t_max: float) -> np.ndarray:
        """Stack torque at deflection theta (rad), by inverting the tabulated theta(T);
        inside the clearance (between the two sides' zero-torque ends) the torque is zero."""
        thn, Tn, thp, Tp = self.table(t_max)
        theta = np.atleast_1d(np.asarray(theta, float))
        out = np.zeros_like(theta)
        up = theta > thp[0]
        dn = theta < thn[-1]
        out[up] = np.interp(theta[up], thp, Tp)
        out[dn] = np.interp(theta[dn], thn, Tn)
        return out


# ----------------------------------------------------------------------------- friction


def _segments(x: np.ndarray):
    """Monotone runs of x: (start, stop, sign) with stop exclusive; zero steps join the run."""
    dx = np.diff(x)
    s = np.sign(dx)
    # carry the last non-zero sign through zero steps
    idx = np.where(s != 0, np.arange(s.size), 0)
    np.maximum.accumulate(idx, out=idx)
    s = s[idx]
    s[s == 0] = 1
    change = np.flatnonzero(np.diff(s)) + 1
    starts = np.concatenate([[0], change])
    stops = np.concatenate([change, [s.size]])
    return [(a, b + 1, s[a]) for a, b in zip(starts, stops)]


def dahl(theta: np.ndarray, width: float, z0: float = 0.0) -> np.ndarray:
    """Unit Dahl friction (alpha = 1): dz/dtheta = (1 - z sign(dtheta))/width, exact per run."""
    z = np.empty_like(theta)
    z[0] = z0
    for a, b, s in _segments(theta):
        d = np.abs(theta[a:b] - theta[a])
        z[a:b] = s - (s - z[a]) * np.exp(-d / width)
    return z


def elasto_plastic(theta: np.ndarray, width: float, z0: float = 0.0) -> np.ndarray:
    """Unit Coulomb friction with a linear presliding take-up over `width` (rad)."""
    z = np.empty_like(theta)
    z[0] = z0
    for a, b, s in _segments(theta):
        d = np.abs(theta[a:b] - theta[a])
        z[a:b] = s * np.minimum(1.0, s * z[a] + d / width)
    return z


def iwan(theta: np.ndarray, width: float, n: int = 24) -> np.ndarray:
    """Unit Iwan (parallel Jenkins) friction: n elasto-plastic elements of equal share whose
    slip widths are uniform over (0, 2 width]: a parabolic (Masing) take-up, full slip at 2w."""
    widths = 2 * width * (np.arange(n) + 1) / n
    return sum(elasto_plastic(theta, w) for w in widths) / n


def stribeck_regularised(v: np.ndarray, f_c: float, f_s: float, v_s: float, v0: float):
    """Velocity law zero at rest: [Fc + (Fs - Fc) exp(-(v/vs)^2)] tanh(v/v0) (N·m)."""
    return (f_c + (f_s - f_c) * np.exp(-(v / v_s) ** 2)) * np.tanh(v / v0)


def atan_coulomb(v: np.ndarray, f: float, v0: float) -> np.ndarray:
    """Velocity-regularised Coulomb friction (2F/pi) atan(v/v0) (N·m), zero at rest."""
    return 2 * f / np.pi * np.arctan(v / v0)


# ----------------------------------------------------------------------------- bench


@dataclass
class Bench:
    """Everything one record needs. Sizes in SI (rad, N·m, s); see the module docstring."""

    stack: Stack
    fs: float                     # record sample rate (Hz)
    q: object                     # callable(t_fine, rng) -> motor angle (rad)
    duration_s: float = 0.0       # filled from q's length when 0
    friction: dict = field(default_factory=dict)   # {'law': ..., params}
    damper: float = 0.0           # viscous c (N·m·s/rad) on the stack's deflection
    bump: dict | None = None      # {'theta': rad, 'k2': N·m/rad^2}: progressive stop beyond theta
    preload: dict | None = None   # {'theta_p': rad}: antagonistic pair, 2K inside +-theta_p
    prony: list = field(default_factory=list)      # [(k N·m/rad, tau s), ...] Maxwell branches
    creep: dict | None = None     # {'k': N·m/rad, 'tau': s}: Kelvin coupling in series (motor read)
    hub_slip: float | None = None  # slip torque (N·m) of a clamped hub (motor read)
    deflection_source: str = "optical"
    # torque channel
    delay_s: float = 0.0
    torque_filter_s: float = 0.0  # first-order low-pass time constant on torque
    angle_filter_s: float = 0.0   # first-order low-pass time constant on angle
    aa_torque_hz: float = 0.0     # 2nd-order Butterworth anti-alias on torque (0: none)
    aa_angle_hz: float = 0.0      # 2nd-order Butterworth anti-alias on angle (0: none)
    zoh_hz: float = 0.0           # torque sensor update rate, held between updates (0: none)
    rail: float | None = None     # ADC rails +-rail (N·m), noise included
    torque_offset: float = 0.0
    angle_offset: float = 0.0
    drift_per_s: float = 0.0      # N·m/s
    spikes: int = 0
    spike_sigma: tuple = (15.0, 40.0)
    # noise
    sigma_T: float = 0.0
    sigma_th: float = 0.0
    noise: str = "white"          # white | pink | student3


FINE_HZ = 8000.0                                # physics grid (Hz)
RATES_HZ = (2000.0, 1000.0, 500.0, 250.0, 200.0)  # record rates: divisors of FINE_HZ
MAX_SAMPLES = 30000


def pink(rng: np.random.Generator, n: int) -> np.ndarray:
    """1/f noise of unit RMS (power ~ 1/f down to 1/n of the rate), by FFT shaping."""
    w = rng.normal(size=n)
    W = np.fft.rfft(w)
    f = np.arange(W.size, dtype=float)
    f[0] = 1.0
    W = W / np.sqrt(f)
    W[0] = 0.0
    x = np.fft.irfft(W, n)
    return x / x.std()


def first_order(x: np.ndarray, tau: float, dt: float) -> np.ndarray:
    """First-order low-pass y' = (x - y)/tau, exact for x linear over each step, y(0) = x(0)."""
    a = np.exp(-dt / tau)
    # first-order-hold exact discretisation
    b0 = 1 - tau / dt * (1 - a)
    b1 = tau / dt * (1 - a) - a
    y, _ = signal.lfilter([b0, b1], [1.0, -a], x, zi=[x[0] * (1 - b0)])
    return y


def butter2(x: np.ndarray, fc: float, fs: float) -> np.ndarray:
    """Second-order Butterworth low-pass at fc (Hz), started at rest at x[0]."""
    b, a = signal.butter(2, fc, fs=fs)
    zi = signal.lfilter_zi(b, a) * x[0]
    y, _ = signal.lfilter(b, a, x, zi=zi)
    return y


def simulate(bench: Bench, rng: np.random.Generator) -> dict:
    """Run the bench; return the record's channels (noisy and noise-free) at its sample times."""
    dt = 1.0 / FINE_HZ
    q = np.asarray(bench.q(dt, rng), float)
    duration = q.size * dt
    fs = bench.fs
    if duration * fs > MAX_SAMPLES:  # a long protocol is logged slower (a user keeps files small)
        fs = max([r for r in RATES_HZ if duration * r <= MAX_SAMPLES] or [min(RATES_HZ)])
        bench.fs = fs
    m = int(round(FINE_HZ / fs))
    n_f = q.size - (q.size - 1) % m
    q = q[:n_f]
    tf = np.arange(n_f) * dt
    stack = bench.stack
    peak = np.max(np.abs(q))
    t_max = stack.k_series * peak * 4 + 1.0
    # motor side: what the stack's deflection is
    theta = q.copy()
    if bench.creep is not None:  # Kelvin coupling: k_c phi + c phi' = T = K (q - phi), linear stack
        K = stack.k_series
        kc, tau = bench.creep["k"], bench.creep["tau"]
        c = kc * tau
        lam = (K + kc) / c
        a = np.exp(-lam * dt)
        phi = np.zeros(n_f)
        for i in range(1, n_f):
            phi[i] = phi[i - 1] * a + (1 - a) * K * q[i] / (K + kc)
        theta = q - phi
    T_el = stack.torque_of(theta, t_max)
    if bench.hub_slip is not None:  # the hub slips where the stack's torque would exceed it
        x_hi = _theta_at(stack, bench.hub_slip)
        x_lo = _theta_at(stack, -bench.hub_slip)
        slip = 0.0
        th = np.empty(n_f)
        for i in range(n_f):
            x = q[i] - slip
            if x > x_hi:
                slip, x = q[i] - x_hi, x_hi
            elif x < x_lo:
                slip, x = q[i] - x_lo, x_lo
            th[i] = x
        theta = th
        T_el = stack.torque_of(theta, t_max)
    v = np.gradient(theta, dt)
    T = T_el.copy()
    fr = bench.friction
    law = fr.get("law")
    if law == "dahl":
        T += fr["F"] * dahl(theta, fr["w"])
    elif law == "elasto_plastic":
        T += fr["F"] * elasto_plastic(theta, fr["w"])
    elif law == "iwan":
        T += fr["F"] * iwan(theta, fr["w"])
    elif law == "stribeck":
        T += stribeck_regularised(v, fr["Fc"], fr["Fs"], fr["vs"], fr["v0"])
    elif law == "atan":
        T += atan_coulomb(v, fr["F"], fr["v0"])
    elif law == "load_dahl":  # friction level grows with the transmitted torque (cam contact)
        T += (fr["F0"] + fr["mu"] * np.abs(T_el)) * dahl(theta, fr["w"])
    T += bench.damper * v
    if bench.bump is not None:
        over = np.maximum(np.abs(theta) - bench.bump["theta"], 0)
        T += np.sign(theta) * bench.bump["k2"] * over ** 2
    if bench.preload is not None:  # two springs pressed against each other by theta_p each
        tp = bench.preload["theta_p"]
        K = stack.k_series
        T += K * np.clip(theta, -tp, tp)  # the second spring acts while both touch
    for k, tau in bench.prony:
        x = np.zeros(n_f)
        a = np.exp(-dt / tau)
        for i in range(1, n_f):
            x[i] = x[i - 1] * a + (1 - a) * theta[i]
        T += k * (theta - x)
    # sensors, noise-free
    Tr = T
    if bench.delay_s:
        Tr = np.interp(tf - bench.delay_s, tf, Tr)
    if bench.torque_filter_s:
        Tr = first_order(Tr, bench.torque_filter_s, dt)
    if bench.aa_torque_hz:
        Tr = butter2(Tr, bench.aa_torque_hz, 1 / dt)
    if bench.zoh_hz:
        hold = 1.0 / bench.zoh_hz
        phase = rng.uniform(0, hold)
        ti = np.floor((tf - phase) / hold) * hold + phase
        Tr = np.interp(np.maximum(ti, 0), tf, Tr)
    Tr = Tr + bench.torque_offset + bench.drift_per_s * tf
    read = theta if bench.deflection_source == "optical" else q
    thr = read
    if bench.angle_filter_s:
        thr = first_order(thr, bench.angle_filter_s, dt)
    if bench.aa_angle_hz:
        thr = butter2(thr, bench.aa_angle_hz, 1 / dt)
    thr = thr + bench.angle_offset
    # sample
    sl = slice(0, n_f, m)
    t = tf[sl]
    T_clean, th_clean = Tr[sl].copy(), thr[sl].copy()
    n = t.size
    if bench.noise == "pink":
        nT = bench.sigma_T * pink(rng, n)
    elif bench.noise == "student3":
        nT = bench.sigma_T * rng.standard_t(3, n) / np.sqrt(3.0)
    else:
        nT = rng.normal(0, bench.sigma_T, n)
    T_meas = T_clean + nT
    if bench.spikes:
        idx = rng.choice(np.arange(n // 20, n - n // 20), bench.spikes, replace=False)
        T_meas[idx] += rng.choice([-1, 1], bench.spikes) * rng.uniform(*bench.spike_sigma, bench.spikes) * bench.sigma_T
    if bench.rail is not None:
        T_meas = np.clip(T_meas, -bench.rail, bench.rail)
        T_clean = np.clip(T_clean, -bench.rail, bench.rail)
    th_meas = th_clean + rng.normal(0, bench.sigma_th, n)
    return {"t": t, "T": T_meas, "theta": th_meas, "T_clean": T_clean, "theta_clean": th_clean,
            "theta_stack": theta[sl], "T_stack": T_el[sl], "dt_fine": dt, "m": m}


def _theta_at(stack: Stack, T: float) -> float:
    """Stack deflection carrying torque T (rad)."""
    return float(sum(s.deflection(np.array([T]))[0] + s.c for s in stack.springs))


# ----------------------------------------------------------------------------- files


@dataclass
class FileFormat:
    """How a record is written. Column names, units, order, extras, line ends, time origin."""

    time_col: str = "time_s"
    torque_col: str = "torque_Nm"
    deflection_col: str = "deflection_rad"
    angle_unit: str = "rad"
    torque_unit: str = "Nm"
    order: tuple = ("time", "torque", "deflection")
    extras: tuple = ()            # ('temp_C', 'current_A') written as extra columns
    comments: tuple = ()          # '# ...' lines before the header
    crlf: bool = False
    t0: float = 0.0               # absolute time origin (s), e.g. a Unix timestamp

    def cli_args(self) -> list:
        """The options a user gives `springcad fit` for this file."""
        args = []
        if self.time_col != "time_s":
            args += ["--time-col", self.time_col]
        if self.torque_col != "torque_Nm":
            args += ["--torque-col", self.torque_col]
        if self.deflection_col != "deflection_rad":
            args += ["--deflection-col", self.deflection_col]
        if self.angle_unit != "rad":
            args += ["--angle-unit", self.angle_unit]
        if self.torque_unit != "Nm":
            args += ["--torque-unit", self.torque_unit]
        return args


def write_csv(path: Path, rec: dict, fmt: FileFormat, rng: np.random.Generator) -> None:
    """Write the record's noisy channels as a CSV in the given format."""
    t = rec["t"] + fmt.t0
    T = rec["T"] * (1000.0 if fmt.torque_unit == "Nmm" else 1.0)
    th = rec["theta"] * (180.0 / np.pi if fmt.angle_unit == "deg" else 1.0)
    cols = {"time": (fmt.time_col, [f"{x:.6f}" for x in t]),
            "torque": (fmt.torque_col, [f"{x:.7g}" for x in T]),
            "deflection": (fmt.deflection_col, [f"{x:.9g}" for x in th])}
    names = [cols[k][0] for k in fmt.order]
    data = [cols[k][1] for k in fmt.order]
    for e in fmt.extras:
        names.append(e)
        base = 24.0 if "temp" in e else 1.5
        data.append([f"{x:.3f}" for x in base + 0.01 * np.cumsum(rng.normal(size=t.size))])
    nl = "\r\n" if fmt.crlf else "\n"
    lines = list(fmt.comments) + [",".join(names)]
    lines += [",".join(row) for row in zip(*data)]
    with open(path, "w", newline="") as f:
        f.write(nl.join(lines) + nl)
