"""Held-out generator G: the oracle that decides the ``unexplained`` label.

It fits, by linear least squares, what the library's laws could make of a record's
noise-free torque reading along its noise-free deflection reading, and measures what is
left against the noise: E = Σ r² / σ² (the excess chi-square the leftover adds to a fit at
the noise floor). The columns are the library's effects at the truth's clearance, centre
and delay, and their first-order changes (bench/heldout_fit_g.md, "The oracle"):

  1, t                       torque offset, drift
  e(θ)                       K · dead-band deflection (clearance b, centre a)
  ∂e/∂b, ∂e/∂a               a different clearance or centre (backlash, angle offset)
  e³, max(e, 0)              stiffening, asymmetric stiffness
  de/dt                      a time lag or a viscous damper (first order)
  z(θ)                       friction of unit level, elasto-plastic or Dahl, one width of
                             0.5-32 mrad or the truth's (the least E over the widths is kept)
"""

from __future__ import annotations

import numpy as np

import heldout_fit_g_sim as sim

WIDTHS_RAD = (0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 0.032)
LAWS = ("elastoplastic", "dahl")
FLAG_E = 2000.0
CLEAR_E = 200.0


def dead_band(x_rad: np.ndarray, half_rad: float) -> np.ndarray:
    """Deflection beyond a centred clearance of half-width ``half_rad`` (rad)."""
    return np.sign(x_rad) * np.maximum(np.abs(x_rad) - half_rad, 0.0)


def noise_variance(rec: sim.Record, sen: sim.Sensors, k_Nm_per_rad: float) -> float:
    """Variance (N·m²) of the record's noise in torque: torque and angle noise, ADC steps."""
    count_rad = 2 * np.pi / sen.encoder_counts if sen.encoder_counts else 0.0
    return (sen.torque_noise_Nm ** 2 + (k_Nm_per_rad * sen.angle_noise_rad) ** 2
            + sen.adc_step_Nm ** 2 / 12 + (k_Nm_per_rad * count_rad) ** 2 / 12)


def columns(time_s, theta_rad, oracle: dict) -> np.ndarray:
    """The library's columns (see the module docstring) along a deflection path."""
    d = oracle.get("delay_s", 0.0)
    th = np.interp(time_s - d, time_s, theta_rad) if d else theta_rad
    x = th - oracle.get("centre_rad", 0.0)
    h = oracle.get("gap_rad", 0.0) / 2
    e = dead_band(x, h)
    engaged = (np.abs(x) > h).astype(float)
    cols = [np.ones_like(x), time_s - time_s.mean(), e, -0.5 * np.sign(x) * engaged, -engaged,
            e ** 3, np.maximum(e, 0.0), np.gradient(e, time_s)]
    return np.column_stack(cols), th


def excess(rec: sim.Record, oracle: dict, sigma2_Nm2: float) -> dict:
    """Least E over the friction options, with the fitted coefficient of e (a K)."""
    base, th = columns(rec.time_s, rec.clean_deflection_rad, oracle)
    options = [None] + [(w, law) for w in WIDTHS_RAD for law in LAWS]
    if "friction_width_rad" in oracle:
        options.append((oracle["friction_width_rad"], oracle.get("friction_law", "elastoplastic")))
    y = rec.clean_torque_Nm
    best = None
    for opt in options:
        A = base
        if opt is not None:
            z = sim.friction_path(th, 1.0, sim.Friction(1.0, opt[0], opt[1]))
            A = np.column_stack([base, z])
        scale = np.maximum(np.abs(A).max(axis=0), 1e-300)
        coef, *_ = np.linalg.lstsq(A / scale, y, rcond=None)
        r = y - (A / scale) @ coef
        E = float(np.sum(r * r) / sigma2_Nm2)
        if best is None or E < best["E"]:
            best = {"E": E, "friction": opt, "k_fit_Nm_per_rad": float(coef[2] / scale[2]),
                    "leftover_rms_over_noise": float(np.sqrt(np.mean(r * r) / sigma2_Nm2))}
    return best


def label(E: float):
    """The unexplained label from E: True (must flag), False (must not), None (either)."""
    if E >= FLAG_E:
        return True
    if E <= CLEAR_E:
        return False
    return None
