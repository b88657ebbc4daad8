"""Bench simulator: records like the paper's protocol, with effects injected on request.

The paper's testbed (Fig. 4) grounds one side of the stack and drives the
other from rest to +A, back to rest, to -A and back, with A = 4°, 8°, … 24°,
sampling torque at 500 Hz and measuring deflection optically. This module
produces such records for a spring of known stiffness (or a designed stack),
with Gaussian sensor noise and any of the effects of the library injected,
reproducibly from a seed. Users plan tests with it; the tests use it.

The physics here is written independently of the fitter's model terms where
that is natural: friction follows a Dahl model integrated along the motion,
the lag shifts the analytic trajectory, stiffening is a cubic term.

Units: N·m, rad, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from springcad.fit.data import BenchRecord, make_record
from springcad.fit.models import spring_angle
from springcad.fit.protocols import Protocol


@dataclass(frozen=True)
class BenchSpring:
    """The spring on the bench and the effects injected into its record.

    Attributes:
        stiffness_Nm_per_rad: K.
        backlash_rad: b (total crossover width, eq. 4), 0 for none.
        transition_rad: logit transition l (eq. 9), 0 for a sharp deadband.
        friction_torque_Nm: Dahl friction level H (hysteresis), 0 for none.
        presliding_rad: angle over which friction reverses after a turn.
        lag_s: torque channel delay relative to the deflection channel.
        drift_Nm_per_s: torque zero drift after taring at the start.
        torque_offset_Nm: untared torque zero.
        angle_offset_rad: optical deflection zero offset.
        cubic_stiffness_Nm_per_rad3: k3 in ``τ = K·x + k3·x³`` (stiffening > 0).
        asymmetry: K+ = K(1 + a), K- = K(1 - a).
        outlier_fraction: fraction of torque samples hit by glitches.
        outlier_size_Nm: typical glitch size (each is ±U(0.5, 1.5) times this).
        series_stiffness_Nm_per_rad: shaft and coupler stiffness between motor
            encoder and spring (encoder deflection = θ + τ/K_series); ``None`` = rigid.
    """

    stiffness_Nm_per_rad: float
    backlash_rad: float = 0.0
    transition_rad: float = 0.0
    friction_torque_Nm: float = 0.0
    presliding_rad: float = 0.005
    lag_s: float = 0.0
    drift_Nm_per_s: float = 0.0
    torque_offset_Nm: float = 0.0
    angle_offset_rad: float = 0.0
    cubic_stiffness_Nm_per_rad3: float = 0.0
    asymmetry: float = 0.0
    outlier_fraction: float = 0.0
    outlier_size_Nm: float = 1.0
    series_stiffness_Nm_per_rad: float | None = None

    @classmethod
    def from_design(cls, design: dict, **effects) -> "BenchSpring":
        """A bench spring from a design dict (``design.json``): the stack's beam
        stiffness and nominal backlash, plus any injected ``effects`` fields."""
        stack = design["stack"]
        kw = {"stiffness_Nm_per_rad": float(stack["stiffness_Nm_per_rad"]),
              "backlash_rad": float(stack.get("backlash_rad", {}).get("nominal", 0.0))}
        kw.update(effects)
        return cls(**kw)

    def injected(self) -> tuple[str, ...]:
        """Library names of the effects this spring injects."""
        out = []
        for name, field_name in _EFFECT_FIELDS:
            value = getattr(self, field_name)
            if value is not None and value != 0.0:
                out.append(name)
        return tuple(dict.fromkeys(out))

    def spring_torque(self, theta: np.ndarray) -> np.ndarray:
        """Elastic torque (N·m) at true deflection ``theta`` (rad), no friction."""
        x = spring_angle(theta, self.backlash_rad / 2.0, self.transition_rad)
        k = self.stiffness_Nm_per_rad * (1.0 + self.asymmetry * np.sign(x))
        return k * x + self.cubic_stiffness_Nm_per_rad3 * x ** 3


_EFFECT_FIELDS = (
    ("backlash", "backlash_rad"), ("hysteresis", "friction_torque_Nm"), ("time_lag", "lag_s"),
    ("drift", "drift_Nm_per_s"), ("torque_offset", "torque_offset_Nm"),
    ("angle_offset", "angle_offset_rad"), ("stiffening", "cubic_stiffness_Nm_per_rad3"),
    ("asymmetric_stiffness", "asymmetry"), ("outliers", "outlier_fraction"),
    ("series_compliance", "series_stiffness_Nm_per_rad"),
)


@dataclass(frozen=True)
class BenchNoise:
    """White Gaussian sensor noise (standard deviations).

    Attributes:
        torque_Nm: torque sensor and ADC noise.
        deflection_rad: optical deflection noise (the paper's calibrated error
            was about 1e-3 rad).
        encoder_rad: motor encoder noise.
        camera_fps: if set, the deflection noise is drawn once per camera frame
            and interpolated linearly to the sample times, as when optical
            deflection (60 fps in the paper) is resampled to the torque rate;
            the noise is then correlated over several samples.
    """

    torque_Nm: float = 0.03
    deflection_rad: float = 1e-3
    encoder_rad: float = 1e-4
    camera_fps: float | None = None


@dataclass(frozen=True)
class SimulatedRecord:
    """A simulated bench record and what was put into it.

    Attributes:
        record: the record, as the fitter would read it from a CSV.
        spring: the injected truth.
        noise: the noise levels.
        noise_floor_Nm: RMS torque error of a perfect model of the measured
            deflection: ``sqrt(mean(σ_τ² + (dτ/dθ)²·σ_θ²))`` over glitch-free
            samples (σ_θ² is the realised variance for camera-rate noise, which
            interpolation makes smaller than the per-frame variance).
        torque_half_range_Nm: half the noise-free torque range.
        glitch_mask: samples hit by a glitch.
    """

    record: BenchRecord
    spring: BenchSpring
    noise: BenchNoise
    noise_floor_Nm: float
    torque_half_range_Nm: float
    glitch_mask: np.ndarray

    @property
    def injected(self) -> tuple[str, ...]:
        return self.spring.injected()


def dahl_friction(theta: np.ndarray, level_Nm: float, presliding_rad: float) -> np.ndarray:
    """Dahl friction torque (N·m) along a deflection path, starting from zero.

    ``dF/dθ = (H·sign(dθ) - F)/θ_p``, integrated exactly step by step: the
    friction approaches ±H exponentially over ``θ_p`` after each reversal.
    """
    out = np.empty_like(theta)
    f = 0.0
    prev = theta[0]
    for i, th in enumerate(theta):
        d = th - prev
        if d != 0.0:
            target = level_Nm if d > 0 else -level_Nm
            f = target - (target - f) * np.exp(-abs(d) / presliding_rad)
        out[i] = f
        prev = th
    return out


def simulate(spring: BenchSpring, protocol: Protocol = Protocol(), noise: BenchNoise = BenchNoise(),
             seed: int = 0, encoders: bool | None = None) -> SimulatedRecord:
    """Simulate one bench record.

    Args:
        spring: the spring and the effects to inject.
        protocol: the ramp protocol.
        noise: sensor noise levels.
        seed: random seed (noise, glitch positions).
        encoders: add an encoder deflection channel (default: when
            ``spring.series_stiffness_Nm_per_rad`` is set).

    Returns:
        The record plus the truth and the noise floor.
    """
    rng = np.random.default_rng(seed)
    t = protocol.times()
    theta = protocol.deflection(t)
    theta_lag = protocol.deflection(t - spring.lag_s) if spring.lag_s else theta
    friction_lag = (dahl_friction(theta_lag, spring.friction_torque_Nm, spring.presliding_rad)
                    if spring.friction_torque_Nm else np.zeros_like(t))
    torque_lag = spring.spring_torque(theta_lag) + friction_lag
    sensor = spring.torque_offset_Nm + spring.drift_Nm_per_s * (t - t[0])
    torque_meas = torque_lag + sensor + rng.normal(0.0, noise.torque_Nm, t.size)
    glitch = np.zeros(t.size, dtype=bool)
    if spring.outlier_fraction > 0:
        n_glitch = max(1, int(round(spring.outlier_fraction * t.size)))
        where = rng.choice(t.size, size=n_glitch, replace=False)
        glitch[where] = True
        size = spring.outlier_size_Nm * rng.uniform(0.5, 1.5, n_glitch)
        torque_meas[where] += size * rng.choice([-1.0, 1.0], n_glitch)
    if noise.camera_fps:
        frames = np.arange(t[0], t[-1] + 2.0 / noise.camera_fps, 1.0 / noise.camera_fps)
        theta_noise = np.interp(t, frames, rng.normal(0.0, noise.deflection_rad, frames.size))
    else:
        theta_noise = rng.normal(0.0, noise.deflection_rad, t.size)
    theta_meas = theta + spring.angle_offset_rad + theta_noise
    if encoders is None:
        encoders = spring.series_stiffness_Nm_per_rad is not None
    encoder = None
    if encoders:
        torque_now = (spring.spring_torque(theta)
                      + (dahl_friction(theta, spring.friction_torque_Nm, spring.presliding_rad)
                         if spring.friction_torque_Nm else 0.0))
        wind_up = torque_now / spring.series_stiffness_Nm_per_rad if spring.series_stiffness_Nm_per_rad else 0.0
        encoder = theta + wind_up + rng.normal(0.0, noise.encoder_rad, t.size)
    eps = 1e-6
    slope = (spring.spring_torque(theta + eps) - spring.spring_torque(theta - eps)) / (2 * eps)
    theta_var = float(np.var(theta_noise)) if noise.camera_fps else noise.deflection_rad ** 2
    floor_sq = noise.torque_Nm ** 2 + slope ** 2 * theta_var
    floor = float(np.sqrt(np.mean(floor_sq[~glitch])))
    clean = torque_lag + sensor
    record = make_record(t, torque_meas, theta_meas, encoder, source="simulated")
    return SimulatedRecord(record, spring, noise, floor, 0.5 * float(np.ptp(clean)), glitch)

