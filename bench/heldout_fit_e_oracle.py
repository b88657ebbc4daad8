"""Generator E's truth oracle: how far a record's clean channels lie from the library's laws.

For a record with physics outside the library, whether ``unexplained`` must be raised is
decided here, from the noise-free channels, before any fit runs: the library laws as
FIT_PHYSICS.md describes them (my own implementation, below) are fitted by least squares
to the clean torque given the clean angle, with the record's truth effects (required and
optional) free; what is left is the structure the library cannot describe. Its size
against the noise is

    E = (N / n) * sum_i r_i^2 / sigma_eff^2

(r on n evenly spaced samples of the N, sigma_eff^2 = sigma_T^2 (1+rho)/(1-rho) + (K
sigma_theta)^2: the long-run noise variance of an AR(1) torque noise plus the angle noise
through the spring), i.e. the excess chi-square the structure adds to a chi-square of N.
E >= 2000 (about 10 standard deviations of a chi-square of 20 000 samples and 4.5 of
100 000): structure clearly above noise, ``unexplained`` expected. E <= 200: not clearly
above noise, ``unexplained`` must not be raised. In between: either is accepted.

Library laws here: K g (g the deflection behind a sharp centred dead band of width b, K on
each side if asymmetric) + k3 g^3; friction: Coulomb with a presliding angle (elasto-plastic,
linear take-up over ``pre``), width 2H; a pure delay tau of the torque channel; a torque
zero c + d t; an angle zero error theta0.

Rule ``readme`` (amendment, see ``heldout_fit_e.md``): the laws the README puts inside a
library name are the library's too, so E is the least over them: friction's presliding law
is elasto-plastic or Dahl (exponential take-up over ``pre``), and ``time_lag`` is a pure
delay or a viscous damper c*dtheta/dt (the README: "a viscous damper is within the time lag's
meaning"). A Hertzian take-up, a first-order filter, LuGre/Stribeck and a friction that lets
go at rest stay outside (the README flags them when the library's laws leave structure).
"""

from __future__ import annotations

import numpy as np

from heldout_fit_e_sim import dead_zone

E_TRUE = 2000.0
E_FALSE = 200.0
N_ORACLE = 30000


def presliding_coulomb(u, H, pre, law="ep"):
    """Elasto-plastic Coulomb friction (N·m) of width 2H, linear take-up over ``pre`` (rad).

    Vectorised per monotone run of ``u``: within a run F moves from its value at the turn
    toward +-H at slope H/pre and stops there (a second implementation of the simulator's
    sample-by-sample law, so the oracle check compares two). ``law="dahl"``: Dahl's law,
    F = s H + (F_turn - s H) exp(-|u - u_turn| / pre) within a run of direction s.
    """
    du = np.diff(u, prepend=u[0])
    sgn = np.sign(du)
    moving = np.flatnonzero(sgn)
    F = np.zeros_like(u)
    if moving.size == 0 or H <= 0:
        return F
    s = sgn[moving]
    turns = moving[np.flatnonzero(np.diff(s, prepend=-s[0]) != 0)]
    bounds = list(turns) + [u.size]
    f = 0.0
    kp = H / pre
    for a, b in zip(bounds[:-1], bounds[1:]):
        seg = u[a - 1 if a > 0 else 0:b]
        u0 = seg[0]
        if law == "dahl":
            sH = H * sgn[a]
            vals = sH + (f - sH) * np.exp(-np.abs(seg - u0) / pre)
        elif sgn[a] > 0:
            vals = np.minimum(f + kp * (seg - u0), H)
        else:
            vals = np.maximum(f + kp * (seg - u0), -H)
        # holds inside the run keep the value; the run is monotone so the formula holds there too
        F[a:b] = vals[1:] if a > 0 else vals
        f = F[b - 1]
    if turns[0] > 0:
        F[: turns[0]] = 0.0
    return F


def _layout(effects, hints, lag_law="delay"):
    """Parameter names, start values and bounds for the library model with ``effects``.

    ``lag_law``: ``delay`` (a time shift tau, s) or ``damper`` (c, N·m·s/rad, started at
    -K tau from the hint) for ``time_lag``.
    """
    K = hints["K"]
    names, x0, lo, hi = ["K"], [K], [0.2 * K], [5 * K]

    def add(name, start, low, high):
        names.append(name)
        x0.append(start)
        lo.append(low)
        hi.append(high)

    if "asymmetric_stiffness" in effects:
        add("Kn", hints.get("Kn", K), 0.2 * K, 5 * K)
    if "stiffening" in effects:
        add("k3", hints.get("k3", 0.0), -50 * K, 50 * K)
    if "backlash" in effects:
        add("b", hints.get("b", 0.01), 0.0, 0.2)
    if "hysteresis" in effects:
        add("H", hints.get("H", 0.01 * K), 0.0, 5 * K)
        add("pre", hints.get("pre", 0.003), 1e-5, 0.1)
    if "time_lag" in effects and lag_law == "damper":
        add("cv", -K * hints.get("tau", 0.0), -0.2 * K, 0.2 * K)
    elif "time_lag" in effects:
        add("tau", hints.get("tau", 0.0), -0.2, 0.2)
    if "drift" in effects:
        add("d", hints.get("d", 0.0), -10 * K, 10 * K)
    if "torque_offset" in effects or "drift" in effects:
        add("c", hints.get("c", 0.0), -10 * K, 10 * K)
    if "angle_offset" in effects:
        add("th0", hints.get("th0", 0.0), -0.2, 0.2)
    x0 = np.clip(np.array(x0, float), np.array(lo) + 1e-12, np.array(hi) - 1e-12)
    return names, x0, np.array(lo, float), np.array(hi, float)


def library_model(p, t_full, th_full, idx, fric_law="ep", rate=None):
    """Library torque (N·m) on samples ``idx`` for parameters ``p`` (dict).

    ``fric_law``: the presliding law (``ep`` or ``dahl``); ``rate``: dtheta/dt (rad/s) on
    ``idx`` for a damper ``cv`` in ``p``.
    """
    ts = t_full[idx]
    u = np.interp(ts - p.get("tau", 0.0), t_full, th_full) - p.get("th0", 0.0)
    g = dead_zone(u, p.get("b", 0.0) / 2)
    T = np.where(g >= 0, p["K"], p.get("Kn", p["K"])) * g + p.get("k3", 0.0) * g**3
    if "H" in p:
        T = T + presliding_coulomb(u, p["H"], p["pre"], fric_law)
    if "cv" in p:
        T = T + p["cv"] * rate
    return T + p.get("c", 0.0) + p.get("d", 0.0) * ts


def structure(t, th_clean, T_clean, effects, hints, sigma_eff, rule="original"):
    """Fit the library model to the clean channels; return (E, rms_over_sigma, params).

    ``rule="readme"``: the least E over the README's library laws (friction elasto-plastic
    or Dahl, lag a delay or a damper; module docstring); params then carry ``laws``.
    """
    if rule == "original":
        return _structure_one(t, th_clean, T_clean, effects, hints, sigma_eff, "ep", "delay")
    fric = ("ep", "dahl") if "hysteresis" in effects else ("ep",)
    lags = ("delay", "damper") if "time_lag" in effects else ("delay",)
    best = None
    for fl in fric:
        for ll in lags:
            E, rms, params = _structure_one(t, th_clean, T_clean, effects, hints, sigma_eff, fl, ll)
            if best is None or E < best[0]:
                best = (E, rms, dict(params, laws=f"{fl}+{ll}"))
    return best


def _structure_one(t, th_clean, T_clean, effects, hints, sigma_eff, fric_law, lag_law):
    """``structure`` with one friction law and one lag law."""
    from scipy.optimize import least_squares

    N = t.size
    idx = np.unique(np.linspace(0, N - 1, min(N, N_ORACLE)).round().astype(int))
    y = T_clean[idx]
    rate = np.gradient(th_clean, t)[idx]
    names, x0, lo, hi = _layout(effects, hints, lag_law)

    def resid(x):
        return library_model(dict(zip(names, x)), t, th_clean, idx, fric_law, rate) - y

    best = None
    starts = [x0]
    for name in ("b", "pre", "tau", "cv"):  # the non-smooth ones: a few starts
        if name in names:
            k = names.index(name)
            for f in (0.5, 2.0):
                x = x0.copy()
                x[k] = np.clip(x[k] * f if x[k] != 0 else 0.005 * f, lo[k] + 1e-12, hi[k] - 1e-12)
                starts.append(x)
    for x in starts:
        sol = least_squares(resid, x, bounds=(lo, hi), x_scale="jac", max_nfev=400,
                            diff_step=1e-4)
        if best is None or sol.cost < best.cost:
            best = sol
    r = best.fun
    E = float(N / idx.size * np.sum(r**2) / sigma_eff**2)
    return E, float(np.sqrt(np.mean(r**2)) / sigma_eff), dict(zip(names, map(float, best.x)))


def expected_flag(E):
    """True / False / None (either) from the excess chi-square E (thresholds above)."""
    if E >= E_TRUE:
        return True
    if E <= E_FALSE:
        return False
    return None
