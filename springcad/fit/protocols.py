"""Test protocols a torsion-spring bench runs: what the motor is told to do.

Two families, each a frozen dataclass with the same small interface
(``times()``, ``deflection(t)``, ``duration_s``, ``sample_rate_hz``,
``describe()`` and ``cli_args()``):

* :class:`Protocol`: the paper's staircase (Fig. 4): from rest to +A, back
  to rest, to -A and back, for A = 4°, 8°, … 24°. Either every ramp lasts
  ``ramp_s`` (the speed then grows with A), or the ramps run at constant
  mean speeds ``rates_rad_per_s``, the whole staircase once per rate; an
  optional hold at every peak.
* :class:`SineSweep`: stepped sines ``A·sin(2πft)``, a whole number of cycles
  at each frequency, for each amplitude, faded in and out over half a cycle.

Why several: friction (a torque set by the direction of motion) and a late
torque channel (a torque set by the speed) leave the same mark on ramps at one
speed; ramps at a second speed, holds (speed zero at a loaded angle) and sines
(speed changing along the cycle) tell them apart. :mod:`springcad.fit.identify`
measures, for a fitted record, which of these protocols would separate the
effects the record confounds, and ``springcad simulate`` writes them.

Units: rad, s, rad/s, Hz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.units import deg_to_rad

#: the paper's ramp targets: 4° to 24° in 4° steps (rad)
PAPER_AMPLITUDES_RAD = tuple(deg_to_rad(float(a)) for a in range(4, 25, 4))

PROFILES = ("cosine", "linear")


def _check_positive(name: str, values) -> None:
    if not len(values) or min(values) <= 0 or not all(math.isfinite(v) for v in values):
        raise ValueError(f"{name} must be positive and finite, got {tuple(values)}")


@dataclass(frozen=True)
class Protocol:
    """Staircase of ramps: rest, then 0 → +A → 0 → -A → 0 for each amplitude, then rest.

    Attributes:
        amplitudes_rad: ramp targets (rad), in order.
        ramp_s: duration of every ramp (s) when ``rates_rad_per_s`` is not
            given; the speed then grows with A.
        rates_rad_per_s: constant mean ramp speeds (rad/s): the staircase is
            run once per rate, in order, each ramp lasting ``A / rate``.
        profile: ``"cosine"`` (smooth start and stop, as a position controller
            with limited acceleration; peak speed π/2 × the mean) or
            ``"linear"`` (constant speed).
        sample_rate_hz: sample rate (Hz).
        rest_s: rest before and after the staircase (s).
        hold_s: hold at every peak ±A before returning (s).
    """

    amplitudes_rad: tuple[float, ...] = PAPER_AMPLITUDES_RAD
    ramp_s: float = 1.6
    profile: str = "cosine"
    sample_rate_hz: float = 500.0
    rest_s: float = 0.5
    rates_rad_per_s: tuple[float, ...] | None = None
    hold_s: float = 0.0

    def __post_init__(self):
        if self.profile not in PROFILES:
            raise ValueError(f"profile {self.profile!r} is not one of {PROFILES}")
        _check_positive("amplitudes_rad", self.amplitudes_rad)
        _check_positive("ramp_s", (self.ramp_s,))
        _check_positive("sample_rate_hz", (self.sample_rate_hz,))
        if self.rates_rad_per_s is not None:
            _check_positive("rates_rad_per_s", self.rates_rad_per_s)
        if self.rest_s < 0 or self.hold_s < 0:
            raise ValueError("rest_s and hold_s must not be negative")

    def _segments(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Segment start times, durations and end angles (the first starts at 0 rad)."""
        ends, durations = [], []
        rates = self.rates_rad_per_s or (None,)
        for rate in rates:
            for a in self.amplitudes_rad:
                ramp = self.ramp_s if rate is None else a / rate
                for target in (a, 0.0, -a, 0.0):
                    ends.append(target)
                    durations.append(ramp)
                    if target != 0.0 and self.hold_s > 0:
                        ends.append(target)
                        durations.append(self.hold_s)
        durations = np.asarray(durations)
        starts = self.rest_s + np.concatenate([[0.0], np.cumsum(durations)[:-1]])
        return starts, durations, np.asarray(ends)

    @property
    def duration_s(self) -> float:
        return 2 * self.rest_s + float(np.sum(self._segments()[1]))

    def times(self) -> np.ndarray:
        """Sample times (s)."""
        n = int(round(self.duration_s * self.sample_rate_hz)) + 1
        return np.arange(n) / self.sample_rate_hz

    def deflection(self, t: np.ndarray) -> np.ndarray:
        """Commanded (true) spring deflection (rad) at times ``t`` (s)."""
        starts, durations, ends = self._segments()
        begins = np.concatenate([[0.0], ends[:-1]])
        k = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, starts.size - 1)
        s = np.clip((t - starts[k]) / durations[k], 0.0, 1.0)
        shape = 0.5 * (1.0 - np.cos(np.pi * s)) if self.profile == "cosine" else s
        return begins[k] + (ends[k] - begins[k]) * shape

    def describe(self) -> dict:
        """The protocol as JSON-ready numbers."""
        out = {"kind": "staircase", "profile": self.profile,
               "amplitudes_rad": list(self.amplitudes_rad),
               "sample_rate_hz": self.sample_rate_hz, "rest_s": self.rest_s,
               "hold_s": self.hold_s, "duration_s": self.duration_s}
        if self.rates_rad_per_s is None:
            out["ramp_s"] = self.ramp_s
        else:
            out["rates_rad_per_s"] = list(self.rates_rad_per_s)
        return out

    def cli_args(self) -> str:
        """The ``springcad simulate`` options that produce this protocol."""
        parts = ["--protocol staircase", f"--profile {self.profile}",
                 "--amplitudes-deg " + ",".join(_deg(a) for a in self.amplitudes_rad)]
        if self.rates_rad_per_s is None:
            parts.append(f"--ramp-s {self.ramp_s:g}")
        else:
            parts.append("--rates-deg-per-s " + ",".join(_deg(r) for r in self.rates_rad_per_s))
        if self.hold_s:
            parts.append(f"--hold-s {self.hold_s:g}")
        return " ".join(parts + [f"--sample-rate-hz {self.sample_rate_hz:g}"])


@dataclass(frozen=True)
class SineSweep:
    """Stepped sine sweep: ``cycles`` whole cycles of ``A·sin(2πft)`` per frequency and amplitude.

    Each block fades in over its first half cycle and out over its last
    (raised cosine), so the motion starts and stops at rest.

    Attributes:
        amplitudes_rad: sine amplitudes (rad); the sweep runs once per amplitude.
        frequencies_hz: frequencies (Hz), in order.
        cycles: whole cycles at each frequency.
        sample_rate_hz: sample rate (Hz).
        rest_s: rest before and after (s).
    """

    amplitudes_rad: tuple[float, ...] = (deg_to_rad(20.0),)
    frequencies_hz: tuple[float, ...] = (0.1, 0.3, 1.0)
    cycles: int = 3
    sample_rate_hz: float = 500.0
    rest_s: float = 0.5

    def __post_init__(self):
        _check_positive("amplitudes_rad", self.amplitudes_rad)
        _check_positive("frequencies_hz", self.frequencies_hz)
        _check_positive("sample_rate_hz", (self.sample_rate_hz,))
        if int(self.cycles) != self.cycles or self.cycles < 1:
            raise ValueError(f"cycles must be a positive whole number, got {self.cycles}")
        if max(self.frequencies_hz) > self.sample_rate_hz / 20:
            raise ValueError(f"frequencies up to {max(self.frequencies_hz):g} Hz need a sample "
                             f"rate of at least 20 samples per cycle, not {self.sample_rate_hz:g} Hz")
        if self.rest_s < 0:
            raise ValueError("rest_s must not be negative")

    def _blocks(self) -> list[tuple[float, float, float]]:
        """``(amplitude, frequency, duration)`` of each block."""
        return [(a, f, self.cycles / f) for a in self.amplitudes_rad for f in self.frequencies_hz]

    @property
    def duration_s(self) -> float:
        return 2 * self.rest_s + sum(b[2] for b in self._blocks())

    def times(self) -> np.ndarray:
        n = int(round(self.duration_s * self.sample_rate_hz)) + 1
        return np.arange(n) / self.sample_rate_hz

    def deflection(self, t: np.ndarray) -> np.ndarray:
        out = np.zeros_like(np.asarray(t, float))
        start = self.rest_s
        for a, f, d in self._blocks():
            inside = (t >= start) & (t < start + d)
            u = t[inside] - start
            # fade in over the first half cycle and out over the last, so the motion
            # starts and stops at rest (a drive cannot jump in speed)
            half = 0.5 / f
            fade = np.minimum(np.minimum(u, d - u) / half, 1.0)
            envelope = 0.5 * (1.0 - np.cos(np.pi * fade))
            out[inside] = a * envelope * np.sin(2.0 * np.pi * f * u)
            start += d
        return out

    def describe(self) -> dict:
        return {"kind": "sine_sweep", "amplitudes_rad": list(self.amplitudes_rad),
                "frequencies_hz": list(self.frequencies_hz), "cycles": self.cycles,
                "sample_rate_hz": self.sample_rate_hz, "rest_s": self.rest_s,
                "duration_s": self.duration_s}

    def cli_args(self) -> str:
        return " ".join([
            "--protocol sine", "--amplitudes-deg " + ",".join(_deg(a) for a in self.amplitudes_rad),
            "--frequencies-hz " + ",".join(f"{f:g}" for f in self.frequencies_hz),
            f"--cycles {self.cycles}", f"--sample-rate-hz {self.sample_rate_hz:g}"])


def _deg(rad: float) -> str:
    return f"{math.degrees(rad):.4g}"
