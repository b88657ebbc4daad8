"""Truth labels of held-out generator B: the rules, the label record and the structure measure.

Labelling rules (fixed before any fit was run):

* ``required``: the library effects planted whose law the library's name describes; ``anyof``:
  groups of which at least one must be named (a pair the record cannot separate, e.g. Coulomb
  friction and a pure delay on one ramp rate; a torque offset and an angle offset on a linear
  spring); ``optional``: names that are physically defensible but not required (a torque
  offset beside a drift that starts from zero at t = 0, an offset beside 1/f noise whose
  realisation has a mean and a trend). Anything else named is a miss.
* ``may_confound``: groups the fit may report as confounded; a confounded group outside them
  (a pair this record was built to separate, e.g. friction and a lag on a sine sweep over 30x
  in frequency) is a miss.
* ``unexplained``: for structure outside the library, its torque component is reduced by least
  squares on what a library refit can absorb (stiffness, an offset and the library shape the
  structure resembles: a delay/damping term, a Coulomb friction with presliding, a cubic); the
  RMS left over the white torque noise SD is the structure ratio. Ratio >= 0.5: ``true``;
  < 0.15: ``false``; between: not scored. Library-only records and pure (coloured) noise:
  ``false``.
* K: the series stiffness 1/sum(1/K_i) of the springs after their gaps (the linear term
  under a cubic; K+ and K- for an asymmetric spring). Scored when every effect is in the
  library, and beside out-of-library structure whose least-squares projection on the
  deflection would bias K by less than 0.3 % (hum, angle ripple, stick-slip, 1/f noise); not
  scored for a stiffness step, clipping, creep, a first-order filter at speed, a skewed clock.
* unit mistakes: a refusal (exit 1 or 2) with a message and no traceback.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from heldout_fit_b_sim import Protocol, Record, elastoplastic_basis, orthogonal_rms, simulate


H, L, D, TO, AO, S, A, O = ("hysteresis", "time_lag", "drift", "torque_offset", "angle_offset", "stiffening",
                            "asymmetric_stiffness", "outliers")
B = "backlash"


@dataclass
class Label:
    """Truth of one record (see the module docstring)."""

    required: set = field(default_factory=set)
    anyof: list = field(default_factory=list)
    optional: set = field(default_factory=set)
    may_confound: list = field(default_factory=list)
    unexplained: bool | None = False
    k_true: float | tuple | None = None
    k_scored: bool = True
    in_library: bool = True
    refusal: bool = False
    structure_ratio: float = 0.0
    k_bias_pct: float = 0.0
    physics: str = ""


@dataclass
class Case:
    """A built record: CSV columns, CLI options and its label."""

    name: str
    columns: dict
    cli: list
    label: Label
    n_samples: int

# ------------------------------------------------------------------ helpers


def noise_sd(peak_Nm: float, pct: float) -> float:
    return peak_Nm * pct / 100


def sweep(amps, freqs, cycles=3, rest=0.5) -> Protocol:
    p = Protocol(rest)
    for a in amps:
        for f in freqs:
            p.sine(a, f, cycles)
            p.hold(0.3)
    p.hold(rest)
    return p


def derivative(x: np.ndarray, fs: float) -> np.ndarray:
    return np.gradient(x) * fs


def structure(rec: Record, comp: np.ndarray, bases: list, k_Nm_per_rad: float) -> tuple[float, float]:
    """(structure ratio, K bias %) of an out-of-library torque component."""
    th = rec.theta_torque_rad
    allb = [th, np.ones_like(th)] + bases
    ratio = orthogonal_rms(comp, allb) / rec.torque_noise_sd_Nm
    coef, *_ = np.linalg.lstsq(np.column_stack(allb), comp, rcond=None)
    return ratio, 100 * coef[0] / k_Nm_per_rad


def friction_like_bases(rec: Record, fs: float, deltas=(5e-4, 2e-3, 8e-3)) -> list[list[np.ndarray]]:
    """Alternative single library-shaped friction bases (Coulomb with one presliding angle each)."""
    return [[elastoplastic_basis(rec.theta_torque_rad, d)] for d in deltas]


def best_structure(rec, comp, basis_sets, k) -> tuple[float, float]:
    best = None
    for bs in basis_sets:
        r = structure(rec, comp, bs, k)
        if best is None or r[0] < best[0]:
            best = r
    return best

def bouc_wen_structure(rec, fs, k):
    return best_structure(rec, rec.parts["friction"], friction_like_bases(rec, fs, (5e-4, 1e-3, 2e-3, 4e-3, 8e-3)), k)

def delay_structure(rec: Record, comp: np.ndarray, signal: np.ndarray, taus, k: float) -> tuple[float, float]:
    """Structure left when ``comp`` is mimicked by an exact delay of ``signal`` (best tau of ``taus``, s)."""
    t = rec.t_s
    sets = [[np.interp(t - tau, t, signal) - signal] for tau in taus]
    return best_structure(rec, comp, sets, k)


def filter_structure(rec, k, tau):
    comp = rec.parts["sensed_minus_clean"]
    clean = rec.parts["elastic"] + rec.parts["viscoelastic"] + rec.parts["friction"]
    return delay_structure(rec, comp, clean, tau * np.linspace(0.5, 1.5, 41), k)


def make_case(name: str, builder: Callable, seed: int, index: int) -> tuple[Case, Record]:
    """Simulate one case (its own generator from (seed, index)) and finish its label."""
    rng = np.random.default_rng([seed, index])
    p, sp, bench, lab, fmt, struct = builder(rng)
    rec = simulate(p, sp, bench, rng)
    if struct is not None:
        ratio, bias = struct(rec)
        lab.structure_ratio, lab.k_bias_pct = ratio, bias
        if not lab.in_library:
            lab.unexplained = True if ratio >= 0.5 else (False if ratio < 0.15 else None)
            if lab.k_scored and abs(bias) >= 0.3:
                lab.k_scored = False
        elif ratio >= 0.15:  # a law the library name describes, but whose shape differs above noise
            lab.unexplained = True if ratio >= 0.5 else None
            lab.in_library = False
            lab.k_scored = abs(bias) < 0.3
    cols, cli = _format(rec, fmt)
    return Case(name, cols, cli, lab, len(rec.t_s)), rec


def _format(rec: Record, fmt: dict) -> tuple[dict, list]:
    """CSV columns and CLI unit options for a record."""
    ang, tq = rec.deflection_rad, rec.torque_Nm
    cli: list = []
    acol, tcol = "deflection_rad", "torque_Nm"
    if fmt.get("angle") == "deg":
        ang = np.degrees(ang)
        if not fmt.get("header_as_si"):
            acol = "deflection_deg"
            cli += ["--deflection-col", acol, "--angle-unit", "deg"]
    if fmt.get("torque") == "Nmm":
        tq = tq * 1000
        if not fmt.get("header_as_si"):
            tcol = "torque_Nmm"
            cli += ["--torque-col", tcol, "--torque-unit", "Nmm"]
    if fmt.get("claim_angle_deg"):
        cli += ["--angle-unit", "deg"]
    if "target" in fmt:
        cli += ["--target-stiffness", f"{fmt['target']:.6g}"]
    return {"time_s": rec.t_s, tcol: tq, acol: ang}, cli

