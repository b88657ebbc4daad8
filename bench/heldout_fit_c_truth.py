"""Held-out generator C: truth labels decided from the physics, before any fit is run.

Written from /work/wt/FIT_PHYSICS.md alone (no springcad/fit/ code, no other generator).

A record's truth is:
- ``required``: groups of library effect names; each group must be met by naming at least
  one of its members (a group of two is a confounded pair: either alone, or both).
- ``optional``: names that may be reported without being wrong (a law the library can
  only approximate with two of its effects, e.g. a Stribeck curve as friction + a lag).
- ``unexplained``: True / False / None (None = the structure outside the library stands
  between 1.5 and 4 noise std after its best library approximation: either answer is
  accepted, and the reason is written down).
- ``k_check``: K must be within 2 % (all effects in the library, K well defined).

How "outside the library" is decided: each out-of-library component (noiseless) is
approximated by the library law that comes nearest (Dahl presliding friction and/or
viscous damping for a friction law, a pure delay with a gain for a torque filter, a hard
dead band for a Hertzian take-up, offset + line for a settling zero, K, k3, viscous,
offset and drift for the rest), and the largest 10 ms moving average of what is left is
compared with the torque noise std: >= 4 -> unexplained, < 1.5 -> explained.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares, minimize_scalar

from heldout_fit_c_sim import (Parts, Protocol, Rig, dahl, dead_zone, delayed, smooth_peak,
                               thermal_K_factor)

TRUE_AT, FALSE_BELOW = 4.0, 1.5


def _decimate(parts: Parts, max_n: int = 4000):
    """Sample indices for the slow least-squares fits: a regular grid plus every sample
    where the motion turns, starts or stops (so a path-dependent law such as Dahl sees the
    same turning points), and the mean rate of what is kept (Hz)."""
    n = parts.t_s.size
    step = max(1, int(np.ceil(n / max_n)))
    sg = np.sign(np.diff(parts.theta_rad))
    turns = np.flatnonzero(sg[1:] != sg[:-1]) + 1
    idx = np.union1d(np.arange(0, n, step), np.union1d(turns, turns + 1)).astype(int)
    idx = idx[idx < n]
    fs = idx.size / float(parts.t_s[-1] - parts.t_s[0])
    return idx, fs


def departure(resid: np.ndarray, fs_Hz: float, sigma: float) -> float:
    """Largest 10 ms moving average of a residual, in torque noise std."""
    return smooth_peak(resid, fs_Hz) / sigma


def friction_departures(parts: Parts) -> dict:
    """How far the friction component stands from Dahl, from viscous and from both."""
    idx, fs = _decimate(parts)
    th, v, F = parts.theta_rad[idx], parts.v_rad_s[idx], parts.friction_Nm[idx]
    s = parts.sigma_T_Nm
    Fmax = max(float(np.percentile(np.abs(F), 95)), 1e-9)
    c_v = float(np.dot(v, F) / max(np.dot(v, v), 1e-30))
    out = {"viscous": departure(F - c_v * v, fs, s)}

    def res(p, with_c):
        model = dahl(th, p[0], p[0] / 10 ** p[1])
        if with_c:
            model = model + p[2] * v
        return model - F

    best = {}
    for with_c in (False, True):
        fits = []
        for log_travel in (-4.0, -3.0, -2.0):
            p0 = [Fmax, log_travel] + ([0.0] if with_c else [])
            lo = [1e-9, -6.0] + ([-np.inf] if with_c else [])
            hi = [np.inf, 0.0] + ([np.inf] if with_c else [])
            fits.append(least_squares(res, p0, args=(with_c,), bounds=(lo, hi), max_nfev=60))
        r = min(fits, key=lambda f: f.cost)
        best[with_c] = departure(r.fun, fs, s)
    out["dahl"], out["dahl+viscous"] = best[False], best[True]
    return out


def filter_departure(parts: Parts, tau_s: float) -> float:
    """How far a first-order torque filter stands from the best pure delay (with a gain)."""
    t, load, sensed = parts.t_s, parts.load_Nm, parts.sensed_Nm

    def cost(d):
        x = delayed(t, load, d)
        g = float(np.dot(x, sensed) / np.dot(x, x))
        return float(np.sum((sensed - g * x) ** 2)), g

    r = minimize_scalar(lambda d: cost(d)[0], bounds=(0.0, 5 * tau_s), method="bounded")
    g = cost(r.x)[1]
    fs = 1.0 / float(t[1] - t[0])
    return departure(sensed - g * delayed(t, load, r.x), fs, parts.sigma_T_Nm)


def hertz_departure(parts: Parts, rig: Rig) -> float:
    """How far a Hertzian take-up stands from the best hard dead band (K and gap free)."""
    th, T = parts.theta_rad - rig.gap_centre_rad, parts.spring_Nm
    idx, fs = _decimate(parts)
    th, T = th[idx], T[idx]
    r = least_squares(lambda p: p[0] * dead_zone(th, p[1]) - T,
                      [rig.K, rig.gap_rad + rig.hertz_w_rad / 1.5], bounds=([0, 0], [np.inf, 1.0]))
    return departure(r.fun, fs, parts.sigma_T_Nm)


def settle_departure(parts: Parts, amp_Nm: float, tau_s: float) -> float:
    """How far an exponentially settling zero stands from the best offset + linear drift."""
    t = parts.t_s
    y = amp_Nm * (1 - np.exp(-t / tau_s))
    A = np.column_stack([np.ones_like(t), t])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    return departure(y - A @ coef, 1.0 / float(t[1] - t[0]), parts.sigma_T_Nm)


def generic_departure(parts: Parts, comp: np.ndarray) -> float:
    """How far a component stands from what K, a cubic, viscous damping, an offset and a
    linear drift can absorb (least squares on those columns)."""
    t, th, v = parts.t_s, parts.theta_rad, parts.v_rad_s
    A = np.column_stack([th, th ** 3, v, np.ones_like(t), t])
    A = A / np.maximum(np.abs(A).max(axis=0), 1e-30)
    coef, *_ = np.linalg.lstsq(A, comp, rcond=None)
    return departure(comp - A @ coef, 1.0 / float(t[1] - t[0]), parts.sigma_T_Nm)


def _verdict(dep: float):
    return True if dep >= TRUE_AT else (False if dep < FALSE_BELOW else None)


def _merge(verdicts: list):
    if any(v is True for v in verdicts):
        return True
    if any(v is None for v in verdicts):
        return None
    return False


def decide(rig: Rig, proto: Protocol, parts: Parts) -> dict:
    """The truth of one record, from its rig, protocol and noiseless parts."""
    req: list[set] = []
    opt: set = set()
    outs: dict = {}
    why: list[str] = []
    in_lib = True
    linear_spring = (rig.gap_rad == 0 and rig.k3 == 0 and rig.K_neg_factor == 1
                     and rig.stop_rad == 0 and rig.hertz_w_rad == 0)
    fric_group = None
    lag_needed = False
    if rig.friction:
        deps = friction_departures(parts)
        outs["friction_vs_library"] = deps
        law = rig.friction["law"]
        if law == "viscous":
            fric_group = {"time_lag"}
            why.append("viscous damping = a lag (negative delay) on every protocol")
        elif deps["dahl"] < FALSE_BELOW and deps["viscous"] < FALSE_BELOW:
            fric_group = {"hysteresis", "time_lag"}
            why.append(f"{law} friction: presliding law and viscous both fit to noise on this "
                       "protocol: friction and lag confounded")
        elif deps["dahl"] < FALSE_BELOW:
            fric_group = {"hysteresis"}
        elif deps["viscous"] < FALSE_BELOW:
            fric_group = {"hysteresis", "time_lag"}
            why.append(f"{law} friction looks viscous on this protocol")
        elif deps["dahl+viscous"] < FALSE_BELOW:
            fric_group = {"hysteresis"}
            lag_needed = True
            why.append(f"{law} friction = presliding friction + viscous damping on this protocol")
        else:
            fric_group = {"hysteresis"}
            v = _verdict(deps["dahl+viscous"])
            if v is not False:
                in_lib = False
                outs["friction_law"] = v
            why.append(f"{law} friction: departure {deps['dahl+viscous']:.1f} std after "
                       "presliding + viscous")
        if law != "dahl":
            opt.add("time_lag")        # a law the library approximates with a lag's help
    if rig.delay_s or rig.filter_tau_s:
        if fric_group == {"hysteresis", "time_lag"}:
            pass                       # friction and lag confounded: either names both
        else:
            req.append({"time_lag"})
        if rig.filter_tau_s:
            dep = filter_departure(parts, rig.filter_tau_s)
            outs["filter_vs_delay"] = dep
            v = _verdict(dep)
            if v is not False:
                in_lib = False
                outs["lag_law"] = v
    if fric_group:
        req.append(fric_group)
    if lag_needed and not (rig.delay_s or rig.filter_tau_s):
        req.append({"time_lag"})
    if rig.gap_rad:
        req.append({"backlash"})
        if rig.hertz_w_rad:
            dep = hertz_departure(parts, rig)
            outs["hertz_vs_hard"] = dep
            v = _verdict(dep)
            if v is not False:
                in_lib = False
                outs["backlash_law"] = v
    if rig.k3:
        req.append({"stiffening"})
    k_check = True
    if rig.K_neg_factor != 1:
        req.append({"asymmetric_stiffness"})
        k_check = False
        why.append("two slopes: K not scored")
    if rig.angle_offset_rad:
        req.append({"angle_offset", "torque_offset"} if linear_spring else {"angle_offset"})
    if rig.torque_offset_Nm:
        req.append({"torque_offset", "angle_offset"} if linear_spring else {"torque_offset"})
    if rig.drift_Nm_per_s:
        req.append({"drift"})
    if rig.settle:
        req.append({"drift", "torque_offset"})
        opt.update({"drift", "torque_offset"})
        dep = settle_departure(parts, *rig.settle)
        outs["settle_vs_line"] = dep
        v = _verdict(dep)
        if v is not False:
            in_lib = False
            outs["settle"] = v
    if rig.outliers:
        req.append({"outliers"})
    comps = dict(parts.other_Nm)
    if rig.stop_rad:
        th = parts.theta_rad
        comps["hard_stop"] = rig.stop_K_factor * rig.K * np.sign(th) * np.maximum(np.abs(th) - rig.stop_rad, 0)
    if rig.clip_frac:
        lim = rig.clip_frac * parts.peak_Nm
        comps["clipping"] = np.clip(parts.sensed_Nm, -lim, lim) - parts.sensed_Nm
    if rig.K_step:
        comps["stiffness_step"] = parts.spring_Nm - parts.spring_Nm / np.where(
            parts.t_s >= rig.K_step[0], rig.K_step[1], 1.0)
    if rig.K_thermal:
        g = thermal_K_factor(parts.t_s, *rig.K_thermal)
        comps["thermal_K"] = parts.spring_Nm * g / (1 + g)
    if rig.hum:
        comps["hum"] = parts.other_Nm["hum"]
    if "maxwell" in comps:
        opt.add("time_lag")
        why.append("a viscoelastic branch damps like a lag on the ramps: time_lag allowed")
    for name, comp in comps.items():
        dep = generic_departure(parts, comp)
        outs[f"{name}_departure"] = dep
        v = _verdict(dep)
        if v is not False:
            in_lib = False
        outs[name] = v
    if rig.counts_per_rev:
        q = 2 * np.pi / rig.counts_per_rev
        qnoise = rig.K * q / np.sqrt(12) / parts.sigma_T_Nm
        outs["quantisation_rms_over_noise"] = float(qnoise)
        why.append("encoder counts: a noise, not structure")
    verdicts = [v for k, v in outs.items() if not isinstance(v, (dict, float))]
    unexplained = _merge(verdicts)
    if unexplained is not False:
        k_check = False
    required = [sorted(g) for g in req]
    named = set().union(*req) if req else set()
    return {"required": required, "optional": sorted(opt - named),
            "unexplained": unexplained, "k_check": k_check and in_lib,
            "K_Nm_per_rad": rig.K, "evidence": _round(outs), "why": why}


def _round(d):
    if isinstance(d, dict):
        return {k: _round(v) for k, v in d.items()}
    if isinstance(d, float):
        return round(d, 3)
    return d
