"""Physics of a torsion-spring bench record, written from the physics alone (held-out generator B).

Independent of ``springcad.fit`` (nothing is imported from it): the laws below are this
generator's own, written from ``FIT_PHYSICS.md``. Units inside: s, rad, N·m.

A record is built in three layers:

* **protocol**: the angle the bench imposes, ``theta(t)`` (rad), an analytic function of time
  made of segments (holds, linear or cosine ramps, sines, chirps) so it can be evaluated at any
  time (delays and clock skew shift the torque channel's sampling times exactly);
* **specimen**: the torque (N·m) the load path carries for a deflection history: a series
  stack of 2-4 springs, each with its own stiffness and backlash gap (centred or not), a cubic
  hardening term, different stiffness for negative deflection, a stiffness that steps at some
  time, viscoelastic relaxation (standard linear solid), and a friction element in parallel
  (elastoplastic Coulomb with a presliding angle, Bouc-Wen, velocity-fading ``tanh(v/v0)``,
  viscous, stick-slip sawtooth);
* **measurement**: torque channel sampled at ``t - delay(t)`` (constant delay or clock skew),
  optional first-order torque-sensor filter, mains hum, angle-periodic ripple, offsets,
  linear drift, white and 1/f noise, isolated spikes, ADC clipping, encoder quantisation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

# ----------------------------------------------------------------------------- protocol


@dataclass(frozen=True)
class Segment:
    """One piece of a protocol, from ``t0_s`` to ``t1_s``.

    kind: ``hold`` (a_rad), ``ramp`` (a_rad -> b_rad, ``shape`` linear or cosine), ``sine``
    (amplitude a_rad, frequency f_hz, starts at 0 going up), ``chirp`` (amplitude a_rad,
    frequency f_hz -> f2_hz, cosine taper of ``taper_s`` at both ends).
    """

    kind: str
    t0_s: float
    t1_s: float
    a_rad: float = 0.0
    b_rad: float = 0.0
    f_hz: float = 0.0
    f2_hz: float = 0.0
    shape: str = "linear"
    taper_s: float = 0.0

    def value(self, t_s: np.ndarray) -> np.ndarray:
        """Imposed angle (rad) at times ``t_s`` inside the segment."""
        tau = t_s - self.t0_s
        dur = self.t1_s - self.t0_s
        if self.kind == "hold":
            return np.full_like(tau, self.a_rad)
        if self.kind == "ramp":
            u = np.clip(tau / dur, 0.0, 1.0)
            if self.shape == "cosine":
                u = 0.5 - 0.5 * np.cos(np.pi * u)
            return self.a_rad + (self.b_rad - self.a_rad) * u
        if self.kind == "sine":
            return self.a_rad * np.sin(2 * np.pi * self.f_hz * tau)
        if self.kind == "chirp":
            k = (self.f2_hz - self.f_hz) / dur
            phase = 2 * np.pi * (self.f_hz * tau + 0.5 * k * tau**2)
            w = np.ones_like(tau)
            if self.taper_s > 0:
                w = np.minimum(w, np.clip(tau / self.taper_s, 0, 1))
                w = np.minimum(w, np.clip((dur - tau) / self.taper_s, 0, 1))
                w = 0.5 - 0.5 * np.cos(np.pi * w)
            return self.a_rad * w * np.sin(phase)
        raise ValueError(f"unknown segment kind {self.kind!r}")


class Protocol:
    """A bench protocol: a list of contiguous segments, built with the ``add_*`` methods."""

    def __init__(self, rest_s: float = 0.5):
        self.segments: list[Segment] = []
        self.t_s = 0.0
        self.angle_rad = 0.0
        if rest_s > 0:
            self.hold(rest_s)

    def _push(self, seg: Segment, end_angle_rad: float) -> "Protocol":
        self.segments.append(seg)
        self.t_s = seg.t1_s
        self.angle_rad = end_angle_rad
        return self

    def hold(self, dur_s: float) -> "Protocol":
        """Stay at the current angle for ``dur_s`` s."""
        if dur_s <= 0:
            return self
        return self._push(Segment("hold", self.t_s, self.t_s + dur_s, a_rad=self.angle_rad), self.angle_rad)

    def ramp_to(self, target_rad: float, *, rate_rad_per_s: float | None = None, dur_s: float | None = None,
                shape: str = "linear") -> "Protocol":
        """Ramp from the current angle to ``target_rad`` at a mean rate or in a given time."""
        span = abs(target_rad - self.angle_rad)
        if dur_s is None:
            dur_s = span / rate_rad_per_s
        if dur_s <= 0:
            return self
        seg = Segment("ramp", self.t_s, self.t_s + dur_s, a_rad=self.angle_rad, b_rad=target_rad, shape=shape)
        return self._push(seg, target_rad)

    def sine(self, amp_rad: float, f_hz: float, cycles: int) -> "Protocol":
        """Whole sine cycles from zero (the current angle must be 0)."""
        assert abs(self.angle_rad) < 1e-12
        return self._push(Segment("sine", self.t_s, self.t_s + cycles / f_hz, a_rad=amp_rad, f_hz=f_hz), 0.0)

    def chirp(self, amp_rad: float, f0_hz: float, f1_hz: float, dur_s: float, taper_s: float = 2.0) -> "Protocol":
        """Linear chirp from zero back to zero (tapered)."""
        assert abs(self.angle_rad) < 1e-12
        return self._push(Segment("chirp", self.t_s, self.t_s + dur_s, a_rad=amp_rad, f_hz=f0_hz, f2_hz=f1_hz,
                                  taper_s=taper_s), 0.0)

    # composite protocols
    def staircase(self, amps_rad, *, ramp_s=None, rate_rad_per_s=None, hold_s=1.0, shape="cosine") -> "Protocol":
        """The paper's staircase: 0 -> +a -> 0 -> -a -> 0 for growing a, holds at every stop."""
        for a in amps_rad:
            for target in (a, 0.0, -a, 0.0):
                self.ramp_to(target, rate_rad_per_s=rate_rad_per_s, dur_s=ramp_s, shape=shape)
                self.hold(hold_s)
        return self

    def triangles(self, amp_rad, rate_rad_per_s, cycles, hold_s=0.0) -> "Protocol":
        """Symmetric triangles 0 -> +a -> -a -> 0 at one rate, optional holds at the peaks."""
        for _ in range(cycles):
            self.ramp_to(amp_rad, rate_rad_per_s=rate_rad_per_s)
            self.hold(hold_s)
            self.ramp_to(-amp_rad, rate_rad_per_s=rate_rad_per_s)
            self.hold(hold_s)
            self.ramp_to(0.0, rate_rad_per_s=rate_rad_per_s)
        return self

    def levels(self, rng, n, amp_rad, rate_rad_per_s, hold_s=(0.5, 2.0)) -> "Protocol":
        """Random target levels reached by linear ramps and held."""
        for _ in range(n):
            self.ramp_to(float(rng.uniform(-amp_rad, amp_rad)), rate_rad_per_s=rate_rad_per_s)
            self.hold(float(rng.uniform(*hold_s)))
        self.ramp_to(0.0, rate_rad_per_s=rate_rad_per_s)
        return self

    def duration_s(self) -> float:
        return self.t_s

    def theta(self, t_s: np.ndarray) -> np.ndarray:
        """Imposed angle (rad) at arbitrary times (clamped to the protocol's ends)."""
        t_s = np.asarray(t_s, float)
        starts = np.array([s.t0_s for s in self.segments])
        idx = np.clip(np.searchsorted(starts, t_s, side="right") - 1, 0, len(self.segments) - 1)
        out = np.empty_like(t_s)
        for i in np.unique(idx):
            m = idx == i
            seg = self.segments[i]
            out[m] = seg.value(np.clip(t_s[m], seg.t0_s, seg.t1_s))
        return out

    def velocity(self, t_s: np.ndarray, h_s: float = 1e-5) -> np.ndarray:
        """Angular velocity (rad/s) by a central difference of the analytic angle."""
        return (self.theta(t_s + h_s) - self.theta(t_s - h_s)) / (2 * h_s)


# ----------------------------------------------------------------------------- specimen


@dataclass
class Stack:
    """Springs in series, each with its own stiffness and backlash gap.

    stiffness_Nm_per_rad[i], gap_rad[i] (total free play of element i), gap_centre_rad[i]
    (where the middle of the gap sits: a non-zero sum shifts the dead band, an angle-zero
    error of the load path). With rigid contacts the gaps add and the compliances add.
    """

    stiffness_Nm_per_rad: list[float]
    gap_rad: list[float] = field(default_factory=list)
    gap_centre_rad: list[float] = field(default_factory=list)

    @property
    def k_series(self) -> float:
        return 1.0 / sum(1.0 / k for k in self.stiffness_Nm_per_rad)

    @property
    def total_gap_rad(self) -> float:
        return float(sum(self.gap_rad))

    @property
    def centre_rad(self) -> float:
        return float(sum(self.gap_centre_rad))


@dataclass
class Specimen:
    """The load path's torque law for a deflection history.

    k3_Nm_per_rad3: cubic hardening of the springs (on the spring deflection, after the gaps);
    neg_ratio: stiffness for negative spring deflection over that for positive;
    step_at_s / step_ratio: the stiffness is multiplied by ``step_ratio`` from ``step_at_s`` on;
    ve_stiffness_Nm_per_rad / ve_tau_s: a standard-linear-solid branch in parallel (torque
    relaxes during holds);
    friction: None or a dict {"law": ..., params} for the element in parallel.
    """

    stack: Stack
    k3_Nm_per_rad3: float = 0.0
    neg_ratio: float = 1.0
    step_at_s: float | None = None
    step_ratio: float = 1.0
    ve_stiffness_Nm_per_rad: float = 0.0
    ve_tau_s: float = 1.0
    friction: dict | None = None

    def spring_deflection(self, theta_rad: np.ndarray) -> np.ndarray:
        """Deflection the springs carry after the (series-summed) gaps are taken up (rad)."""
        x = theta_rad - self.stack.centre_rad
        half = 0.5 * self.stack.total_gap_rad
        return x - np.clip(x, -half, half)

    def elastic(self, theta_rad: np.ndarray, t_s: np.ndarray) -> np.ndarray:
        """Memoryless elastic torque (N·m)."""
        x = self.spring_deflection(theta_rad)
        k = self.stack.k_series * np.where(x < 0, self.neg_ratio, 1.0)
        if self.step_at_s is not None:
            k = k * np.where(t_s >= self.step_at_s, self.step_ratio, 1.0)
        return k * x + self.k3_Nm_per_rad3 * x**3

    def viscoelastic(self, theta_rad: np.ndarray, t_s: np.ndarray) -> np.ndarray:
        """Standard-linear-solid branch: K1 * (x - x_d), x_d relaxes towards x with tau (N·m)."""
        if self.ve_stiffness_Nm_per_rad == 0:
            return np.zeros_like(theta_rad)
        x = self.spring_deflection(theta_rad)
        xd = np.empty_like(x)
        xd[0] = x[0]
        dt = np.diff(t_s)
        a = np.exp(-dt / self.ve_tau_s)
        for k in range(1, len(x)):
            # exact for x linear over the step
            xm = 0.5 * (x[k] + x[k - 1])
            xd[k] = a[k - 1] * xd[k - 1] + (1 - a[k - 1]) * xm
        return self.ve_stiffness_Nm_per_rad * (x - xd)

    def torque(self, theta_rad: np.ndarray, vel_rad_per_s: np.ndarray, t_s: np.ndarray) -> dict[str, np.ndarray]:
        """Torque parts (N·m): elastic, viscoelastic, friction."""
        return {
            "elastic": self.elastic(theta_rad, t_s),
            "viscoelastic": self.viscoelastic(theta_rad, t_s),
            "friction": friction_torque(self.friction, theta_rad, vel_rad_per_s),
        }


def friction_torque(spec: dict | None, theta_rad: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """Friction torque (N·m) of one element in parallel with the springs.

    Laws: ``elastoplastic`` (Coulomb force_Nm with a linear presliding stiffness over
    presliding_rad), ``bouc_wen`` (force_Nm, presliding_rad, exponent n, beta share),
    ``fading`` (force_Nm * tanh(v/v0_rad_per_s): zero at rest), ``viscous`` (c_Nms_per_rad * v),
    ``stickslip`` (static_Nm, kinetic_Nm, stick_Nm_per_rad: builds up while stuck, drops when
    it breaks away: a sawtooth in angle).
    """
    n = len(theta_rad)
    if spec is None:
        return np.zeros(n)
    law = spec["law"]
    if law == "viscous":
        return spec["c_Nms_per_rad"] * vel
    if law == "fading":
        return spec["force_Nm"] * np.tanh(vel / spec["v0_rad_per_s"])
    out = np.empty(n)
    th = theta_rad.tolist()
    if law == "elastoplastic":
        f, d = spec["force_Nm"], spec["presliding_rad"]
        z = 0.0
        for k in range(n):
            if k:
                z = min(d, max(-d, z + th[k] - th[k - 1]))
            out[k] = f * z / d
        return out
    if law == "bouc_wen":
        f, d, ex, beta = spec["force_Nm"], spec["presliding_rad"], spec["n"], spec.get("beta", 0.5)
        gamma = 1.0 - beta
        z = 0.0
        for k in range(n):
            if k:
                dth = th[k] - th[k - 1]
                sub = max(1, int(abs(dth) / (0.05 * d)) + 1)
                h = dth / sub
                for _ in range(sub):
                    s = 1.0 if h * z >= 0 else -1.0
                    z += (h / d) * (1.0 - (beta * s + gamma) * abs(z) ** ex)
            out[k] = f * z
        return out
    if law == "stickslip":
        fs, fk, ks = spec["static_Nm"], spec["kinetic_Nm"], spec["stick_Nm_per_rad"]
        anchor = th[0]
        for k in range(n):
            fr = ks * (th[k] - anchor)
            if fr > fs:
                anchor = th[k] - fk / ks
                fr = fk
            elif fr < -fs:
                anchor = th[k] + fk / ks
                fr = -fk
            out[k] = fr
        return out
    raise ValueError(f"unknown friction law {law!r}")


# ----------------------------------------------------------------------------- measurement


@dataclass
class Bench:
    """The measurement chain and sampling.

    delay_s: the torque channel samples the load path at ``t - delay`` (clock offset);
    skew: extra delay growing as ``skew * t`` (clock-rate mismatch, s/s);
    filter_tau_s: first-order low-pass of the torque sensor;
    hum: list of (amplitude_Nm, frequency_hz) added to torque (mains and harmonics);
    ripple_Nm / ripple_period_rad: torque ripple periodic in the true angle (tooth passing);
    torque_offset_Nm / angle_offset_rad: constant zero errors;
    torque_drift_Nm_per_s / angle_drift_rad_per_s: linear zero drift from 0 at t = 0;
    torque_noise_Nm / angle_noise_rad: white noise SDs;
    pink_Nm: SD of an added 1/f torque noise;
    spikes: number of isolated torque spikes, spike_Nm their size scale;
    clip_Nm: ADC clipping of the torque (symmetric);
    encoder_counts_per_rev: angle quantisation (0: none); torque_lsb_Nm: torque quantisation.
    """

    sample_rate_hz: float = 1000.0
    delay_s: float = 0.0
    skew: float = 0.0
    filter_tau_s: float = 0.0
    hum: list = field(default_factory=list)
    ripple_Nm: float = 0.0
    ripple_period_rad: float = 0.02
    torque_offset_Nm: float = 0.0
    angle_offset_rad: float = 0.0
    torque_drift_Nm_per_s: float = 0.0
    angle_drift_rad_per_s: float = 0.0
    torque_noise_Nm: float = 0.05
    angle_noise_rad: float = 1e-4
    pink_Nm: float = 0.0
    spikes: int = 0
    spike_Nm: float = 0.0
    clip_Nm: float | None = None
    encoder_counts_per_rev: int = 0
    torque_lsb_Nm: float = 0.0


def pink_noise(rng: np.random.Generator, n: int, fs_hz: float, sd: float) -> np.ndarray:
    """1/f (pink) noise of standard deviation ``sd``, flat below 0.01 Hz."""
    spec = rng.normal(size=n // 2 + 1) + 1j * rng.normal(size=n // 2 + 1)
    f = np.fft.rfftfreq(n, 1 / fs_hz)
    spec /= np.sqrt(np.maximum(f, 0.01))
    spec[0] = 0
    x = np.fft.irfft(spec, n)
    return sd * x / x.std()


def lowpass_foh(x: np.ndarray, dt_s: float, tau_s: float) -> np.ndarray:
    """First-order low-pass, exact for an input linear between samples (N·m in, N·m out)."""
    a = math.exp(-dt_s / tau_s)
    g = tau_s / dt_s * (1 - a)
    b0 = 1 - g
    b1 = g - a
    from scipy.signal import lfilter, lfilter_zi

    y, _ = lfilter([b0, b1], [1, -a], x, zi=lfilter_zi([b0, b1], [1, -a]) * x[0])  # at rest at x[0]
    return y


@dataclass
class Record:
    """A simulated record: arrays in SI and the torque parts for the truth bookkeeping."""

    t_s: np.ndarray
    torque_Nm: np.ndarray
    deflection_rad: np.ndarray
    parts: dict[str, np.ndarray]
    theta_true_rad: np.ndarray
    theta_torque_rad: np.ndarray
    torque_noise_sd_Nm: float


def simulate(protocol: Protocol, specimen: Specimen, bench: Bench, rng: np.random.Generator) -> Record:
    """Sample a record: angle channel at t, torque channel at t - delay(t)."""
    fs = bench.sample_rate_hz
    n = int(protocol.duration_s() * fs)
    t = np.arange(n) / fs
    theta = protocol.theta(t)
    tq_times = t - bench.delay_s - bench.skew * t
    th_q = protocol.theta(tq_times)
    v_q = protocol.velocity(tq_times)
    parts = specimen.torque(th_q, v_q, tq_times)
    clean = parts["elastic"] + parts["viscoelastic"] + parts["friction"]
    if bench.ripple_Nm:
        parts["ripple"] = bench.ripple_Nm * np.sin(2 * np.pi * th_q / bench.ripple_period_rad + 0.7)
        clean = clean + parts["ripple"]
    sensed = lowpass_foh(clean, 1 / fs, bench.filter_tau_s) if bench.filter_tau_s > 0 else clean.copy()
    parts["sensed_minus_clean"] = sensed - clean
    hum = np.zeros(n)
    for amp, f in bench.hum:
        hum += amp * np.sin(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi))
    parts["hum"] = hum
    torque = sensed + hum + bench.torque_offset_Nm + bench.torque_drift_Nm_per_s * t
    noise = rng.normal(0, bench.torque_noise_Nm, n)
    if bench.pink_Nm:
        noise = noise + pink_noise(rng, n, fs, bench.pink_Nm)
    torque = torque + noise
    if bench.spikes:
        idx = rng.choice(np.arange(20, n - 20), bench.spikes, replace=False)
        torque[idx] += rng.choice([-1, 1], bench.spikes) * bench.spike_Nm * rng.uniform(1, 2, bench.spikes)
    if bench.clip_Nm is not None:
        parts["clip"] = np.clip(torque, -bench.clip_Nm, bench.clip_Nm) - torque
        torque = np.clip(torque, -bench.clip_Nm, bench.clip_Nm)
    if bench.torque_lsb_Nm:
        torque = np.round(torque / bench.torque_lsb_Nm) * bench.torque_lsb_Nm
    angle = theta + bench.angle_offset_rad + bench.angle_drift_rad_per_s * t + rng.normal(0, bench.angle_noise_rad, n)
    if bench.encoder_counts_per_rev:
        q = 2 * np.pi / bench.encoder_counts_per_rev
        angle = np.round(angle / q) * q
    return Record(t, torque, angle, parts, theta, th_q, bench.torque_noise_Nm)


def orthogonal_rms(component: np.ndarray, bases: list[np.ndarray]) -> float:
    """RMS of ``component`` after least-squares removal of ``bases`` (what a refit can absorb)."""
    if not bases:
        return float(np.sqrt(np.mean(component**2)))
    a = np.column_stack(bases)
    coef, *_ = np.linalg.lstsq(a, component, rcond=None)
    r = component - a @ coef
    return float(np.sqrt(np.mean(r**2)))


def elastoplastic_basis(theta_rad: np.ndarray, presliding_rad: float) -> np.ndarray:
    """Unit Coulomb friction with a presliding angle (the shape the library's name describes)."""
    return friction_torque({"law": "elastoplastic", "force_Nm": 1.0, "presliding_rad": presliding_rad},
                           theta_rad, np.zeros_like(theta_rad))
