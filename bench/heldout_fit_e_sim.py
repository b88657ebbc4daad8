"""Generator E's bench simulator: protocols, the physics of the load path, the sensors.

Written from ``/work/wt/FIT_PHYSICS.md`` alone (no springcad code is imported here).
Angles in rad, torques in N·m, times in s inside; units change only when a record is
written (``write_record``).

Signal chain of one record (``simulate``):

1. the motor drives the deflection ``theta(t)`` (rad) of a protocol (``Protocol``);
2. the torque channel is sampled at ``t - lag_s`` (a pure delay between the channels);
3. the load path: a gap of total width ``backlash_rad`` (sharp, or taken up through a
   Hertzian contact in series), the spring (K, K on the negative side, a cubic, a hard
   stop, a stiffness step, a temperature-dependent K), a standard-linear-solid relaxation
   element, friction (elasto-plastic Coulomb with a presliding angle, Dahl, LuGre with
   Stribeck, regularised Coulomb ``H tanh(v/v0)``, stick-slip sawtooth) and a viscous
   damper, a ripple periodic in angle;
4. the torque zero: offset, linear drift, exponential settling;
5. the torque sensor: a first-order low-pass, mains hum, noise (white or AR(1)), clipping
   of the ADC, spikes;
6. the angle channel: zero error, drift, noise, encoder counts, spikes.

``simulate`` returns the noisy channels and the clean ones (everything but noise and
spikes), which the truth oracle (``heldout_fit_e_oracle``) reads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


# --------------------------------------------------------------------------- protocols
@dataclass
class Protocol:
    """A motor deflection programme as pieces ``(t0_s, t1_s, a0_rad, a1_rad, shape)``.

    ``shape`` is ``"lin"``, ``"cos"`` (half-cosine blend) or ``"sine"`` (then a0 is the
    amplitude (rad) and a1 the frequency (Hz), phase zero at t0) or ``"chirp"`` (a0 the
    amplitude, a1 = (f0_hz, f1_hz)).
    """

    pieces: list = field(default_factory=list)

    @property
    def duration_s(self) -> float:
        return self.pieces[-1][1] if self.pieces else 0.0

    def add(self, dur_s: float, a0: float, a1, shape: str) -> None:
        t0 = self.duration_s
        self.pieces.append((t0, t0 + dur_s, a0, a1, shape))

    def hold(self, dur_s: float) -> None:
        level = self.end_level()
        self.add(dur_s, level, level, "lin")

    def move(self, target_rad: float, rate_rad_per_s: float, shape: str) -> None:
        a0 = self.end_level()
        dur = abs(target_rad - a0) / rate_rad_per_s
        if shape == "cos":
            dur *= math.pi / 2  # same peak speed as the linear ramp
        self.add(max(dur, 1e-3), a0, target_rad, shape)

    def end_level(self) -> float:
        if not self.pieces:
            return 0.0
        t0, t1, a0, a1, shape = self.pieces[-1]
        return self(np.array([t1]))[0] if shape in ("sine", "chirp") else a1

    def __call__(self, t_s: np.ndarray) -> np.ndarray:
        """Deflection (rad) at times ``t_s`` (s); zero before the start, last level after."""
        t_s = np.asarray(t_s, float)
        out = np.zeros_like(t_s)
        starts = np.array([p[0] for p in self.pieces])
        idx = np.clip(np.searchsorted(starts, t_s, side="right") - 1, 0, len(self.pieces) - 1)
        for i, (t0, t1, a0, a1, shape) in enumerate(self.pieces):
            m = idx == i
            if not m.any():
                continue
            tau = np.clip(t_s[m] - t0, 0.0, t1 - t0)
            s = tau / (t1 - t0)
            if shape == "lin":
                out[m] = a0 + (a1 - a0) * s
            elif shape == "cos":
                out[m] = a0 + (a1 - a0) * 0.5 * (1 - np.cos(np.pi * s))
            elif shape == "sine":
                out[m] = a0 * np.sin(2 * np.pi * a1 * tau)
            elif shape == "chirp":
                f0, f1 = a1
                dur = t1 - t0
                out[m] = a0 * np.sin(2 * np.pi * (f0 * tau + (f1 - f0) * tau**2 / (2 * dur)))
            else:
                raise ValueError(f"unknown piece shape {shape!r}")
        out[t_s < 0] = 0.0
        return out


def staircase(amps_rad, rate_rad_per_s, hold_s, shape="cos") -> Protocol:
    """The paper's staircase: 0 -> +a, hold, -> 0, hold, -> -a, hold, -> 0, hold, per a."""
    p = Protocol()
    p.hold(hold_s)
    for a in amps_rad:
        for target in (a, 0.0, -a, 0.0):
            p.move(target, rate_rad_per_s, shape)
            p.hold(hold_s)
    return p


def triangles(amp_rad, rates_rad_per_s, cycles_per_rate, hold_s=0.0, shape="lin") -> Protocol:
    """Triangles between +-amp at each rate in turn (holds at the turns if hold_s > 0)."""
    p = Protocol()
    p.hold(0.5)
    for rate in rates_rad_per_s:
        for _ in range(cycles_per_rate):
            for target in (amp_rad, -amp_rad):
                p.move(target, rate, shape)
                if hold_s > 0:
                    p.hold(hold_s)
    p.move(0.0, rates_rad_per_s[-1], shape)
    p.hold(0.5)
    return p


def sine_sweep(blocks) -> Protocol:
    """Sine blocks ``(amp_rad, freq_hz, n_cycles)`` one after another (whole cycles)."""
    p = Protocol()
    p.hold(0.5)
    for amp, f, n in blocks:
        p.add(n / f, amp, f, "sine")
    p.hold(0.5)
    return p


def chirp(amp_rad, f0_hz, f1_hz, dur_s) -> Protocol:
    """One linear chirp from f0 to f1 (Hz) over dur_s (s)."""
    p = Protocol()
    p.hold(0.5)
    p.add(dur_s, amp_rad, (f0_hz, f1_hz), "chirp")
    p.move(0.0, amp_rad * 2 * math.pi * f1_hz / 4, "cos")
    p.hold(0.5)
    return p


def random_levels(rng, n_levels, amax_rad, rate_rad_per_s, hold_range_s, shape="cos") -> Protocol:
    """Random targets in +-amax reached by ramps and held (at least 20 % of amax apart)."""
    p = Protocol()
    p.hold(0.5)
    last = 0.0
    for _ in range(n_levels):
        while True:
            target = rng.uniform(-amax_rad, amax_rad)
            if abs(target - last) > 0.2 * amax_rad:
                break
        p.move(target, rate_rad_per_s, shape)
        p.hold(rng.uniform(*hold_range_s))
        last = target
    p.move(0.0, rate_rad_per_s, shape)
    p.hold(0.5)
    return p


# --------------------------------------------------------------------------- physics
@dataclass
class Physics:
    """Everything of one record (SI units; zero or None switches a part off)."""

    K: float  # N·m/rad on positive deflection
    K_neg: float | None = None  # N·m/rad on negative deflection (None: = K)
    k3: float = 0.0  # N·m/rad^3 cubic
    backlash_rad: float = 0.0  # total gap width
    hertz_contact_rad: float = 0.0  # Hertzian contact deflection at the peak torque (0: sharp)
    hardstop_rad: float | None = None  # |spring deflection| beyond which a stop engages
    hardstop_K: float = 0.0  # N·m/rad of the stop
    kstep: tuple | None = None  # (t_s, K ratio after)
    tempK: tuple | None = None  # (relative change, settling tau_s): K*(1+dk*(1-exp(-t/tau)))
    relax: tuple | None = None  # (K1 N·m/rad, tau_s) standard linear solid branch
    friction: str | None = None  # ep | dahl | lugre | tanh | stickslip
    fr: dict = field(default_factory=dict)  # friction parameters (see friction_torque)
    viscous: float = 0.0  # N·m·s/rad
    ripple: tuple | None = None  # (amplitude N·m, period rad)
    lag_s: float = 0.0  # torque channel delay
    filter_s: float = 0.0  # first-order torque sensor time constant
    torque_offset: float = 0.0  # N·m
    drift: float = 0.0  # N·m/s from t = 0
    settle: tuple | None = None  # (N·m, tau_s): A*(1-exp(-t/tau))
    angle_offset: float = 0.0  # rad, zero error of the angle channel
    angle_drift: float = 0.0  # rad/s of the angle channel's zero
    hum: tuple | None = None  # (amplitude N·m, frequency Hz)
    clip_Nm: float | None = None
    sigma_T: float = 0.0  # N·m
    rho_T: float = 0.0  # AR(1) coefficient of the torque noise
    sigma_th: float = 0.0  # rad
    counts_per_rev: int | None = None  # encoder quantisation
    spikes_T: tuple | None = None  # (n, amplitude N·m)
    spikes_th: tuple | None = None  # (n, amplitude rad)


def dead_zone(u, half_gap):
    """Spring deflection behind a centred sharp gap of half-width ``half_gap`` (rad)."""
    return np.sign(u) * np.maximum(np.abs(u) - half_gap, 0.0)


def hertz_take_up(delta, K, kh):
    """Torque (>= 0) through a Hertzian contact (T = kh c^1.5) in series with a spring K.

    Solves ``delta = T/K + (T/kh)^(2/3)`` for T with Newton on s = (T/kh)^(1/3).
    """
    delta = np.maximum(delta, 0.0)
    s = np.minimum(np.sqrt(delta), np.cbrt(K * delta / kh))
    for _ in range(60):
        f = kh * s**3 / K + s**2 - delta
        df = 3 * kh * s**2 / K + 2 * s
        s = np.maximum(s - f / np.maximum(df, 1e-300), 0.0)
    return kh * s**3


def friction_torque(law, u, t, fr):
    """Friction torque (N·m) on the motor-side deflection series ``u`` (rad) at ``t`` (s)."""
    n = u.size
    F = np.zeros(n)
    du = np.diff(u, prepend=u[0])
    if law == "ep":  # Coulomb with a presliding stiffness H/pre
        H, kp = fr["H"], fr["H"] / fr["pre"]
        f = 0.0
        for i in range(n):
            f = min(max(f + kp * du[i], -H), H)
            F[i] = f
    elif law == "dahl":  # dF/du = sigma (1 - F sgn(du)/H), exponential approach
        H, pre = fr["H"], fr["pre"]
        f = 0.0
        for i in range(n):
            if du[i] != 0.0:
                tgt = H if du[i] > 0 else -H
                f = tgt + (f - tgt) * math.exp(-abs(du[i]) / pre)
            F[i] = f
    elif law == "stickslip":  # presliding Coulomb whose level saws with travel
        Fc, dF, lam, kp = fr["Fc"], fr["dF"], fr["lam"], fr["Fc"] / fr["pre"]
        f, travel, direction = 0.0, 0.0, 0
        for i in range(n):
            d = du[i]
            if d != 0.0:
                sd = 1 if d > 0 else -1
                if sd != direction:
                    direction, travel = sd, 0.0
                travel += abs(d)
            level = Fc + dF * (1.0 - (travel / lam) % 1.0)
            f = min(max(f + kp * d, -level), level)
            F[i] = f
    elif law == "tanh":  # regularised Coulomb, zero at rest
        v = np.gradient(u, t)
        F = fr["H"] * np.tanh(v / fr["v0"])
    elif law == "lugre":
        s0, s1, s2 = fr["sigma0"], fr["sigma1"], fr["sigma2"]
        Fc, Fs, vs = fr["Fc"], fr["Fs"], fr["vs"]
        v = np.gradient(u, t)
        dt = np.diff(t, prepend=t[0] - (t[1] - t[0]))
        z = 0.0
        for i in range(n):
            vi = v[i]
            g = Fc + (Fs - Fc) * math.exp(-((vi / vs) ** 2))  # N·m: steady friction
            a = s0 * abs(vi) / g
            if a > 0:
                zss = vi / a
                z = zss + (z - zss) * math.exp(-a * dt[i])
            dz = vi - a * z
            F[i] = s0 * z + s1 * dz + s2 * vi
    elif law is not None:
        raise ValueError(f"unknown friction law {law!r}")
    return F


def first_order(x, dt_s, tau_s):
    """First-order low-pass (time constant tau_s) sampled every dt_s, starting at rest."""
    if tau_s <= 0:
        return x
    from scipy.signal import lfilter

    a = math.exp(-dt_s / tau_s)
    return lfilter([1 - a], [1, -a], x, zi=[a * x[0]])[0]


def ar1_noise(rng, n, sigma, rho):
    """Stationary AR(1) noise of standard deviation sigma."""
    e = rng.normal(0.0, sigma * math.sqrt(1 - rho**2), n)
    if rho == 0:
        return e
    from scipy.signal import lfilter

    x0 = rng.normal(0.0, sigma)
    return lfilter([1.0], [1.0, -rho], e, zi=[rho * x0])[0]


def torque_physics(ph: Physics, u, t):
    """Torque (N·m) at the sensor before its filter: load path + zero, as a function of u."""
    half = ph.backlash_rad / 2
    g = dead_zone(u, half)
    K_neg = ph.K if ph.K_neg is None else ph.K_neg
    Kt = np.full_like(t, ph.K)
    Kn = np.full_like(t, K_neg)
    if ph.kstep is not None:
        Kt = np.where(t >= ph.kstep[0], Kt * ph.kstep[1], Kt)
        Kn = np.where(t >= ph.kstep[0], Kn * ph.kstep[1], Kn)
    if ph.tempK is not None:
        dk, tau = ph.tempK
        fac = 1 + dk * (1 - np.exp(-t / tau))
        Kt, Kn = Kt * fac, Kn * fac
    if ph.hertz_contact_rad > 0:
        # kh: the contact takes up hertz_contact_rad at the peak spring torque
        T_peak = ph.K * max(np.max(np.abs(g)), 1e-9)
        kh = T_peak / ph.hertz_contact_rad**1.5
        mag = hertz_take_up(np.abs(u) - half, ph.K, kh)
        g = np.sign(u) * mag / ph.K  # spring deflection behind the contact
    spring = np.where(g >= 0, Kt * g, Kn * g) + ph.k3 * g**3
    if ph.hardstop_rad is not None:
        spring = spring + ph.hardstop_K * np.sign(g) * np.maximum(np.abs(g) - ph.hardstop_rad, 0)
    if ph.relax is not None:
        K1, tau = ph.relax
        dt = np.diff(t, prepend=t[0])
        dg = np.diff(g, prepend=g[0])
        Tr = np.zeros_like(g)
        r = 0.0
        for i in range(g.size):
            a = math.exp(-dt[i] / tau)
            rate = dg[i] / dt[i] if dt[i] > 0 else 0.0
            r = r * a + K1 * rate * tau * (1 - a)
            Tr[i] = r
        spring = spring + Tr
    T = spring + friction_torque(ph.friction, u, t, ph.fr)
    if ph.viscous:
        T = T + ph.viscous * np.gradient(u, t)
    if ph.ripple is not None:
        amp, period = ph.ripple
        T = T + amp * np.sin(2 * np.pi * u / period)
    T = T + ph.torque_offset + ph.drift * t
    if ph.settle is not None:
        T = T + ph.settle[0] * (1 - np.exp(-t / ph.settle[1]))
    return T


@dataclass
class Record:
    t: np.ndarray
    torque: np.ndarray
    angle: np.ndarray
    torque_clean: np.ndarray
    angle_clean: np.ndarray


def simulate(ph: Physics, protocol: Protocol, fs_hz: float, rng) -> Record:
    """Sample the record at fs_hz over the protocol's duration (see the module docstring)."""
    n = int(round(protocol.duration_s * fs_hz)) + 1
    t = np.arange(n) / fs_hz
    u = protocol(t - ph.lag_s)
    T = torque_physics(ph, u, t)
    T = first_order(T, 1.0 / fs_hz, ph.filter_s)
    if ph.hum is not None:
        T = T + ph.hum[0] * np.sin(2 * np.pi * ph.hum[1] * t + 0.7)
    T_clean = T.copy()
    T = T + ar1_noise(rng, n, ph.sigma_T, ph.rho_T)
    if ph.clip_Nm is not None:
        T = np.clip(T, -ph.clip_Nm, ph.clip_Nm)
        T_clean = np.clip(T_clean, -ph.clip_Nm, ph.clip_Nm)
    if ph.spikes_T is not None:
        k, amp = ph.spikes_T
        idx = rng.choice(np.arange(10, n - 10), k, replace=False)
        T[idx] += amp * rng.choice([-1, 1], k) * rng.uniform(0.6, 1.0, k)
    th_clean = protocol(t) + ph.angle_offset + ph.angle_drift * t
    th = th_clean + rng.normal(0.0, ph.sigma_th, n) if ph.sigma_th > 0 else th_clean.copy()
    if ph.counts_per_rev:
        q = 2 * math.pi / ph.counts_per_rev
        th = np.round(th / q) * q
    if ph.spikes_th is not None:
        k, amp = ph.spikes_th
        idx = rng.choice(np.arange(10, n - 10), k, replace=False)
        th[idx] += amp * rng.choice([-1, 1], k) * rng.uniform(0.6, 1.0, k)
    return Record(t, T, th, T_clean, th_clean)


def write_record(path, rec: Record, cols=("time_s", "torque_Nm", "deflection_rad"),
                 angle_unit="rad", torque_unit="Nm") -> None:
    """Write the CSV in the record's units and column names."""
    ang = np.degrees(rec.angle) if angle_unit == "deg" else rec.angle
    tq = rec.torque * 1000.0 if torque_unit == "Nmm" else rec.torque
    data = np.column_stack([rec.t, tq, ang])
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="",
               fmt=["%.6f", "%.7g", "%.8g"])
