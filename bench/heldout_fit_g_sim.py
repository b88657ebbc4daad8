"""Held-out generator G: a torsion-spring test bench simulated from physics (issue 24).

Written without reading springcad/fit/, tests/fit/ or the other held-out generators; the
laws are stated in bench/heldout_fit_g.md. Units inside: rad, N·m, s. Every function is
pure (numpy arrays in, arrays out); only ``write_csv`` touches a file.

The chain, motor side to ground::

    motor (angle- or torque-controlled, rotor inertia) -- [upstream bearing friction]
      -- gear lash -- shaft (torsional compliance) / jaw coupling (stiffening)
      -- torque sensor -- hub inertia J_hub -- spring stack (1-3 disks, each K_i and a
      cam gap b_i) with friction in parallel -- ground

The optical channel reads the stack's deflection; the motor encoder reads the motor angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

TWO_PI = 2.0 * math.pi


# ----------------------------------------------------------------------------- protocols
def ramp_path(waypoints, fine_rate_hz: float, shape: str = "linear") -> np.ndarray:
    """Piecewise path through ``waypoints`` sampled at ``fine_rate_hz``.

    Args:
        waypoints: list of (target, move_s, hold_s): move from the current value to
            ``target`` in ``move_s`` seconds, then hold ``hold_s`` seconds. Starts at 0.
        fine_rate_hz: sample rate of the returned path (Hz).
        shape: "linear" (constant speed) or "cosine" (zero speed at both ends).

    Returns:
        The command at each fine sample (unit of the targets: rad or N·m).
    """
    pieces = [np.zeros(1)]
    current = 0.0
    for target, move_s, hold_s in waypoints:
        n_move = max(1, int(round(move_s * fine_rate_hz)))
        u = np.arange(1, n_move + 1) / n_move
        if shape == "cosine":
            u = 0.5 - 0.5 * np.cos(math.pi * u)
        pieces.append(current + (target - current) * u)
        pieces.append(np.full(int(round(hold_s * fine_rate_hz)), float(target)))
        current = float(target)
    return np.concatenate(pieces)


def paper_staircase(peak: float, speed: float, hold_s: float, n_levels: int = 6,
                    repeats: int = 1) -> list:
    """The paper's protocol (Sec. III-B1): 0 -> +A_k -> 0 -> -A_k -> 0, A_k = k/n·peak.

    Args:
        peak: largest amplitude (rad or N·m).
        speed: ramp speed (peak units per second).
        hold_s: hold at each extreme (s); the paper returns through zero without a hold.
        n_levels: number of amplitudes (the paper: 4° to 24° in 4° steps, 6 levels).
        repeats: how many times the whole staircase is run.

    Returns:
        Waypoints for :func:`ramp_path`.
    """
    wps = []
    for _ in range(repeats):
        for k in range(1, n_levels + 1):
            a = peak * k / n_levels
            for target in (a, 0.0, -a, 0.0):
                prev = wps[-1][0] if wps else 0.0
                hold = hold_s if target != 0.0 else 0.1 * hold_s
                wps.append((target, abs(target - prev) / speed, hold))
    return wps


def multi_rate(peak: float, speeds, hold_s: float, n_levels: int = 3) -> list:
    """The staircase run once per ramp speed (peak units per second)."""
    wps = []
    for speed in speeds:
        wps += paper_staircase(peak, speed, hold_s, n_levels)
    return wps


def random_levels(rng, peak: float, n: int, speed_range, hold_range) -> list:
    """Random targets in [-peak, peak], each reached at a random speed and held."""
    wps, prev = [], 0.0
    for _ in range(n):
        target = float(rng.uniform(-peak, peak))
        speed = float(rng.uniform(*speed_range))
        wps.append((target, max(abs(target - prev) / speed, 1e-3), float(rng.uniform(*hold_range))))
        prev = target
    wps.append((0.0, abs(prev) / speed_range[0], 0.5))
    return wps


def sine_blocks(blocks, fine_rate_hz: float, gap_s: float = 0.5) -> np.ndarray:
    """Sine blocks A·w(t)·sin(2π f t) of whole cycles, each starting and ending at rest.

    The envelope w rises and falls as a raised cosine over the first and last half cycle,
    so a motor can follow it (no step in speed where a block starts).

    Args:
        blocks: list of (amplitude, frequency_Hz, n_cycles).
        fine_rate_hz: sample rate (Hz).
        gap_s: rest at zero between blocks (s).
    """
    pieces = [np.zeros(int(gap_s * fine_rate_hz))]
    for amp, f_hz, n_cyc in blocks:
        t = np.arange(int(round(n_cyc / f_hz * fine_rate_hz))) / fine_rate_hz
        edge = 0.5 / f_hz
        w = np.clip(np.minimum(t, t[-1] - t) / edge, 0.0, 1.0)
        pieces.append(amp * (0.5 - 0.5 * np.cos(math.pi * w)) * np.sin(TWO_PI * f_hz * t))
        pieces.append(np.zeros(int(gap_s * fine_rate_hz)))
    return np.concatenate(pieces)


# ------------------------------------------------------------------------------- the chain
@dataclass
class Chain:
    """Elastic elements in series between the motor and ground (all memoryless).

    Attributes:
        k_Nm_per_rad: stiffness of each spring disk for positive torque (N·m/rad).
        k_neg_Nm_per_rad: stiffness for negative torque (None: same as positive).
        gap_rad: total cam-flexure clearance of each disk (rad).
        gap_centre_rad: where each clearance is centred (rad; 0 = centred).
        cubic_frac: hardening of a single disk, T = K·d·(1 + c·(d/d_ref)²).
        cubic_ref_rad: d_ref of the hardening (rad).
        shaft_Nm_per_rad: torsional stiffness of the shaft (inf: rigid).
        coupling_Nm_per_rad, coupling_ref_Nm: jaw coupling k0·(1 + (T/T_ref)²) (inf: none).
        gear_lash_rad: total clearance of the gearbox between motor encoder and shaft.
    """

    k_Nm_per_rad: list
    k_neg_Nm_per_rad: list | None = None
    gap_rad: list | None = None
    gap_centre_rad: list | None = None
    cubic_frac: float = 0.0
    cubic_ref_rad: float = 0.3
    shaft_Nm_per_rad: float = math.inf
    coupling_Nm_per_rad: float = math.inf
    coupling_ref_Nm: float = 1.0
    gear_lash_rad: float = 0.0

    def spring_deflection(self, torque_Nm: np.ndarray) -> np.ndarray:
        """Deflection of the stack (rad) carrying ``torque_Nm`` (T != 0 picks a gap side)."""
        T = np.asarray(torque_Nm, float)
        n = len(self.k_Nm_per_rad)
        kneg = self.k_neg_Nm_per_rad or self.k_Nm_per_rad
        gaps = self.gap_rad or [0.0] * n
        centres = self.gap_centre_rad or [0.0] * n
        theta = np.zeros_like(T)
        for k, kn, b, c in zip(self.k_Nm_per_rad, kneg, gaps, centres):
            kk = np.where(T >= 0, k, kn)
            d = T / kk
            if self.cubic_frac:
                # Newton on K d (1 + c d²/d_ref²) = T (monotone for c > -1/3 at d_ref)
                a = self.cubic_frac / self.cubic_ref_rad ** 2
                for _ in range(30):
                    d = d - (kk * d * (1 + a * d * d) - T) / (kk * (1 + 3 * a * d * d))
            theta += d + c + np.sign(T) * b / 2
        return theta

    def rig_deflection(self, torque_Nm: np.ndarray) -> np.ndarray:
        """Twist of shaft, coupling and gear lash (rad) carrying ``torque_Nm``."""
        T = np.asarray(torque_Nm, float)
        twist = T / self.shaft_Nm_per_rad
        if math.isfinite(self.coupling_Nm_per_rad):
            twist = twist + T / (self.coupling_Nm_per_rad * (1 + (T / self.coupling_ref_Nm) ** 2))
        return twist + np.sign(T) * self.gear_lash_rad / 2

    def table(self, peak_torque_Nm: float, include_rig: bool, n: int = 40001):
        """Monotone table (deflection, torque) for ``np.interp``; T = 0 appears twice.

        The two T = 0 rows carry the two edges of the total clearance, so interpolating
        inside the clearance gives zero torque (the deadband of paper eq. 4).
        """
        Tpos = np.linspace(0.0, 4.0 * peak_torque_Nm, n // 2)
        T = np.concatenate([-Tpos[::-1], Tpos])
        side = np.concatenate([-np.ones(n // 2), np.ones(n // 2)])
        theta = self._deflection_signed(T, side, include_rig)
        return theta, T

    def _deflection_signed(self, T, side, include_rig):
        """Deflection with the gap side chosen by ``side`` where T = 0."""
        n = len(self.k_Nm_per_rad)
        gaps = self.gap_rad or [0.0] * n
        base = self.spring_deflection(T) - np.sign(T) * sum(gaps) / 2
        theta = base + side * sum(gaps) / 2
        if include_rig:
            rig = self.rig_deflection(T) - np.sign(T) * self.gear_lash_rad / 2
            theta = theta + rig + side * self.gear_lash_rad / 2
        return theta

    def torque(self, deflection_rad: np.ndarray, peak_torque_Nm: float, include_rig: bool):
        """Torque (N·m) of the chain at ``deflection_rad`` (inverse of the table)."""
        theta, T = self.table(peak_torque_Nm, include_rig)
        return np.interp(deflection_rad, theta, T)

    def k_series_Nm_per_rad(self, include_rig: bool, negative: bool = False) -> float:
        """Small-torque stiffness of the stack (and of the rig's shaft and coupling)."""
        ks = self.k_neg_Nm_per_rad if (negative and self.k_neg_Nm_per_rad) else self.k_Nm_per_rad
        c = sum(1.0 / k for k in ks)
        if include_rig:
            c += 1.0 / self.shaft_Nm_per_rad + 1.0 / self.coupling_Nm_per_rad
        return 1.0 / c


# ------------------------------------------------------------------------------ friction
@dataclass
class Friction:
    """Friction in parallel with the stack, acting on its deflection.

    law "elastoplastic": f follows k_p·Δθ, k_p = F/w, clipped to ±F (linear take-up);
    law "dahl": df/dθ = (F/w)·(1 - f/F·sign θ̇), integrated exactly over each step.
    ``thermal_drop`` > 0 makes F = F0·(1 - ΔT/ΔT_ref) with ΔT the temperature rise of the
    contact, C dΔT/dt = |f·θ̇| - ΔT/R, time constant ``thermal_tau_s``; R is chosen so
    that ΔT/ΔT_ref would reach ``thermal_drop`` at the power F0·mean|θ̇| of the record;
    since F falls as it warms, sliding steadily at that speed F settles at F0/(1 + drop).
    """

    force_Nm: float
    width_rad: float
    law: str = "elastoplastic"
    thermal_drop: float = 0.0
    thermal_tau_s: float = 20.0


def friction_path(theta_rad: np.ndarray, dt_s: float, fr: Friction | None) -> np.ndarray:
    """Friction torque (N·m) along a deflection path sampled every ``dt_s`` seconds."""
    out = np.zeros(len(theta_rad))
    if fr is None or fr.force_Nm == 0.0:
        return out
    th = theta_rad.tolist()
    F0, w, law = fr.force_Nm, fr.width_rad, fr.law
    drop, tau = fr.thermal_drop, fr.thermal_tau_s
    p_mean = F0 * float(np.mean(np.abs(np.diff(theta_rad)))) / dt_s  # W, mean |f·θ̇|
    gain = drop / max(p_mean, 1e-12)  # fractional F drop per W at steady state
    f, heat, F = 0.0, 0.0, F0
    res = [0.0] * len(th)
    for i in range(1, len(th)):
        dth = th[i] - th[i - 1]
        if law == "dahl":
            s = 1.0 if dth > 0 else -1.0
            f = s * F + (f - s * F) * math.exp(-abs(dth) / w)
        else:
            f = min(max(f + F / w * dth, -F), F)
        if drop:
            heat += (abs(f * dth) / dt_s * gain - heat) * dt_s / tau
            F = F0 * (1.0 - heat)
            f = min(max(f, -F), F)
        res[i] = f
    out[:] = res
    return out


# ------------------------------------------------------------------------------- dynamics
@dataclass
class Dynamics:
    """Inertia of the hub and of the motor side, for benches where it matters.

    mode "torque": the motor applies the command torque through its rotor inertia J_motor;
    "shaft": the motor imposes the command angle on a shaft of stiffness k_shaft and
    damping c_shaft that drives the hub. The torque sensor sits between J_motor and the
    hub, so it reads T_spring + T_friction + J_hub·θ̈ (torque control) or the shaft's
    torque (shaft mode, J_motor = 0). ``upstream_friction_Nm`` is Coulomb friction on the
    rotor, before the sensor (implicit stick-slip update, no regularisation). The stack is linear with one total clearance (closed form in the loop).
    """

    mode: str
    J_hub_kgm2: float
    J_motor_kgm2: float = 0.0
    damping_Nms_per_rad: float = 0.0
    k_shaft_Nm_per_rad: float = 0.0
    c_shaft_Nms_per_rad: float = 0.0
    upstream_friction_Nm: float = 0.0


def integrate(command: np.ndarray, dt_s: float, k_Nm_per_rad: float, gap_rad: float,
              dyn: Dynamics, fr: Friction | None):
    """Semi-implicit Euler integration of the hub (spring deflection θ).

    Returns:
        (theta_rad, sensor_Nm): the stack's deflection and the torque sensor's true torque.
    """
    n = len(command)
    cmd = command.tolist()
    h = gap_rad / 2
    J = dyn.J_hub_kgm2 + (dyn.J_motor_kgm2 if dyn.mode == "torque" else 0.0)
    th = om = f = 0.0
    F = fr.force_Nm if fr else 0.0
    w = fr.width_rad if fr else 1.0
    dahl = bool(fr and fr.law == "dahl")
    theta, sensor = [0.0] * n, [0.0] * n
    prev_cmd = cmd[0]
    stick = dyn.upstream_friction_Nm * dt_s / J  # speed the rotor's friction removes per step
    for i in range(n):
        x = th - h if th > h else (th + h if th < -h else 0.0)
        t_el = k_Nm_per_rad * x
        if dyn.mode == "torque":
            drive = cmd[i] - dyn.damping_Nms_per_rad * om
        else:
            qdot = (cmd[i] - prev_cmd) / dt_s
            drive = dyn.k_shaft_Nm_per_rad * (cmd[i] - th) + dyn.c_shaft_Nms_per_rad * (qdot - om)
        prev_cmd = cmd[i]
        om_new = om + (drive - t_el - f) / J * dt_s
        if stick:  # implicit Coulomb update: stick if the friction can stop it within the step
            om_new = 0.0 if abs(om_new) <= stick else om_new - math.copysign(stick, om_new)
        acc = (om_new - om) / dt_s
        theta[i] = th  # the state the forces (and the sensor) are evaluated at
        sensor[i] = drive if dyn.mode == "shaft" else t_el + f + dyn.J_hub_kgm2 * acc
        om = om_new
        dth = om * dt_s
        th += dth
        if F:
            if dahl:
                s = 1.0 if dth > 0 else -1.0
                f = s * F + (f - s * F) * math.exp(-abs(dth) / w)
            else:
                f = min(max(f + F / w * dth, -F), F)
    return np.asarray(theta), np.asarray(sensor)


# -------------------------------------------------------------------------------- sensors
@dataclass
class Sensors:
    """What the channels add to the physics (defaults: ideal, noise-free).

    Torque: reading = g(T) + offset + drift·t, g(T) = T·(1 + a2·T/T_fs + a3·(T/T_fs)²)
    ·(1 + crosstalk·sin(θ_motor + phase)) + h·z(T) (a Dahl operator on T of width
    ``sensor_hyst_width_Nm``: magnetic hysteresis of the sensor), delayed by ``delay_s``
    plus ``clock_drift`` × t (a second clock), white noise, spikes, ADC steps.
    Angle: reading = θ + offset + slips (lost encoder counts), noise, encoder counts.
    """

    torque_noise_Nm: float = 0.0
    angle_noise_rad: float = 0.0
    torque_offset_Nm: float = 0.0
    torque_drift_Nm_per_s: float = 0.0
    angle_offset_rad: float = 0.0
    delay_s: float = 0.0
    clock_drift: float = 0.0
    full_scale_Nm: float = 1.0
    a2: float = 0.0
    a3: float = 0.0
    crosstalk: float = 0.0
    crosstalk_phase_rad: float = 0.0
    sensor_hyst_Nm: float = 0.0
    sensor_hyst_width_Nm: float = 1.0
    adc_step_Nm: float = 0.0
    encoder_counts: int = 0
    n_spikes: int = 0
    spike_sigma: float = 25.0
    slips: list = field(default_factory=list)  # (time_s, counts) of lost encoder counts


def sensor_reading(torque_Nm: np.ndarray, motor_rad: np.ndarray, sen: Sensors) -> np.ndarray:
    """The sensor's static transfer of the true torque (before delay, noise and ADC)."""
    T = torque_Nm
    x = T / sen.full_scale_Nm
    r = T * (1 + sen.a2 * x + sen.a3 * x * x)
    if sen.crosstalk:
        r = r * (1 + sen.crosstalk * np.sin(motor_rad + sen.crosstalk_phase_rad))
    if sen.sensor_hyst_Nm:
        r = r + sen.sensor_hyst_Nm * friction_path(T, 1.0, Friction(1.0, sen.sensor_hyst_width_Nm, "dahl"))
    return r


@dataclass
class Record:
    """One simulated record: sample times and the clean and noisy channels (rad, N·m)."""

    time_s: np.ndarray
    torque_Nm: np.ndarray
    deflection_rad: np.ndarray
    clean_torque_Nm: np.ndarray
    clean_deflection_rad: np.ndarray
    encoder_in_rad: np.ndarray | None = None
    noise_Nm: float = 0.0


def sample_times(duration_s: float, rate_hz: float, rng, jitter: float = 0.0,
                 drop_frac: float = 0.0, n_bursts: int = 0) -> np.ndarray:
    """Sample instants (s): a regular grid, optionally jittered (± jitter/rate, uniform)
    with a fraction of single samples and ``n_bursts`` bursts of 20-100 ms dropped."""
    t = np.arange(int(duration_s * rate_hz)) / rate_hz
    if jitter:
        t = t + rng.uniform(-jitter, jitter, t.size) / rate_hz
        t[0] = 0.0
    keep = np.ones(t.size, bool)
    if drop_frac:
        keep &= rng.uniform(size=t.size) > drop_frac
    for _ in range(n_bursts):
        start = rng.uniform(0.1, 0.9) * duration_s
        keep &= ~((t > start) & (t < start + rng.uniform(0.02, 0.1)))
    keep[0] = keep[-1] = True
    return np.sort(t[keep])


def measure(t_fine: np.ndarray, torque_Nm: np.ndarray, angle_rad: np.ndarray,
            motor_rad: np.ndarray, t_s: np.ndarray, sen: Sensors, rng) -> Record:
    """Read the fine-grid physics through the sensors at the sample instants ``t_s``."""
    reading = sensor_reading(torque_Nm, motor_rad, sen)
    t_read = t_s - sen.delay_s - sen.clock_drift * t_s
    clean_T = np.interp(t_read, t_fine, reading) + sen.torque_offset_Nm + sen.torque_drift_Nm_per_s * t_s
    clean_th = np.interp(t_s, t_fine, angle_rad) + sen.angle_offset_rad
    count_rad = TWO_PI / sen.encoder_counts if sen.encoder_counts else 0.0
    for slip_t, counts in sen.slips:
        clean_th = clean_th + (t_s >= slip_t) * counts * (count_rad or TWO_PI / 2 ** 17)
    T = clean_T + rng.normal(0.0, sen.torque_noise_Nm, t_s.size) if sen.torque_noise_Nm else clean_T.copy()
    if sen.n_spikes:
        idx = rng.choice(np.arange(10, t_s.size - 10), sen.n_spikes, replace=False)
        T[idx] += rng.choice([-1.0, 1.0], sen.n_spikes) * sen.spike_sigma * sen.torque_noise_Nm * rng.uniform(0.8, 1.6, sen.n_spikes)
    if sen.adc_step_Nm:
        T = np.round(T / sen.adc_step_Nm) * sen.adc_step_Nm
    th = clean_th + rng.normal(0.0, sen.angle_noise_rad, t_s.size) if sen.angle_noise_rad else clean_th.copy()
    if count_rad:
        th = np.round(th / count_rad) * count_rad
    return Record(t_s, T, th, clean_T, clean_th, noise_Nm=sen.torque_noise_Nm)


def write_csv(path, rec: Record, angle_unit: str = "rad", torque_unit: str = "Nm",
              names=("time_s", "torque_Nm", "deflection_rad")) -> None:
    """Write the record as the bench's CSV (angles in rad or deg, torque in N·m or N·mm)."""
    a = 180.0 / math.pi if angle_unit == "deg" else 1.0
    q = 1000.0 if torque_unit == "Nmm" else 1.0
    cols = [rec.time_s, rec.torque_Nm * q, rec.deflection_rad * a]
    header = list(names)
    if rec.encoder_in_rad is not None:
        cols += [rec.encoder_in_rad * a, np.zeros_like(rec.time_s)]
        header += ["encoder_in_rad", "encoder_out_rad"]
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header),
               comments="", fmt="%.9g")


# ------------------------------------------------------------------------------ a record
@dataclass
class Bench:
    """One bench run: the protocol, the rig, the physics and how it is recorded.

    Attributes:
        command: motor command on the fine grid (rad for angle control, N·m for torque).
        fine_rate_hz: rate of the physics grid (Hz).
        rate_hz: nominal sample rate of the record (Hz).
        chain, friction, sensors: see :class:`Chain`, :class:`Friction`, :class:`Sensors`.
        dynamics: None for a stiff angle-controlled motor (quasi-static), else :class:`Dynamics`.
        deflection_from: "optical" (the stack's deflection) or "motor" (the motor encoder:
            stack plus shaft, coupling and gear lash).
        encoder_cols: also write the motor encoder as encoder_in_rad (output clamped: 0).
        cogging_rad, cogging_per_rev: a ripple of the motor's position loop in the motion
            itself (the spring follows it; the channels read it).
        jitter, drop_frac, n_bursts: sampling irregularities (see :func:`sample_times`).
    """

    command: np.ndarray
    fine_rate_hz: float
    rate_hz: float
    chain: Chain
    friction: Friction | None = None
    sensors: Sensors = field(default_factory=Sensors)
    dynamics: Dynamics | None = None
    deflection_from: str = "optical"
    encoder_cols: bool = False
    cogging_rad: float = 0.0
    cogging_per_rev: int = 24
    jitter: float = 0.0
    drop_frac: float = 0.0
    n_bursts: int = 0


def simulate(b: Bench, rng) -> Record:
    """Run the bench: physics on the fine grid, then the channels at the sample instants."""
    dt_s = 1.0 / b.fine_rate_hz
    t_fine = np.arange(b.command.size) * dt_s
    ch = b.chain
    if b.dynamics is None:
        q = b.command + b.cogging_rad * np.sin(b.cogging_per_rev * b.command)
        peak_T = ch.k_series_Nm_per_rad(False) * (np.max(np.abs(q)) + 0.1)
        T = ch.torque(q, peak_T, include_rig=True)
        if ch.gear_lash_rad:
            theta = ch.spring_deflection(T)  # inside the lash the stack rests where it is
        else:
            theta = q - ch.rig_deflection(T)
        rigid = not (math.isfinite(ch.shaft_Nm_per_rad) or math.isfinite(ch.coupling_Nm_per_rad) or ch.gear_lash_rad)
        if b.friction is not None and not rigid:
            raise ValueError("friction needs a rigid rig in the quasi-static bench")
        torque = T + friction_path(theta, dt_s, b.friction)
        motor = q
    else:
        gap = sum(ch.gap_rad or [0.0])
        theta, torque = integrate(b.command, dt_s, ch.k_series_Nm_per_rad(False), gap,
                                  b.dynamics, b.friction)
        motor = theta if b.dynamics.mode == "torque" else b.command
    duration = t_fine[-1]
    t_s = sample_times(duration, b.rate_hz, rng, b.jitter, b.drop_frac, b.n_bursts)
    channel = motor if b.deflection_from == "motor" else theta
    rec = measure(t_fine, torque, channel, motor, t_s, b.sensors, rng)
    if b.encoder_cols:
        enc = np.interp(t_s, t_fine, motor)
        counts = b.sensors.encoder_counts or 2 ** 17
        rec.encoder_in_rad = np.round(enc / (TWO_PI / counts)) * (TWO_PI / counts)
    return rec
