"""Held-out generator D: bench-record simulator and case list (physics only).

Written from /work/wt/FIT_PHYSICS.md alone, without reading springcad's code, tests or
other benches. The scoring rule is in the docstring of ``bench/heldout_fit_d.py``.

Laws (all torques in N·m, angles in rad; ``phi`` is the input (motor) angle the deflection
channel measures unless a case says otherwise):

* spring: ``K*u`` with ``u`` the spring's own deflection; optional cubic ``k3*u**3``,
  different ``K`` for ``u<0``, a two- or one-sided hard stop (``Kstop*(|u|-us)``), a
  contact-geometry power law ``K*u*(1+(|u|/uc)**p)``, a stiffness step at ``t_s``
  (crack/slip), a temperature-dependent ``K(t) = K*(1 - a*(1-exp(-t/tau)))``.
* gap (backlash): true mechanical free play of total width ``b`` centred on ``c``:
  ``u = deadzone(phi - c, b/2)`` (rigid contact), or a Hertzian contact in series
  (``delta = T/K + (T/kh)**(2/3)`` solved for T), or a dynamic impact: an intermediate body
  of inertia J, a Kelvin-Voigt contact (kc, damping) across the gap, the spring behind it,
  integrated with symplectic Euler (the sensor reads ``K*theta_body``).
* friction acts on the input shaft's motion (bearing/seal between the torque sensor and the
  spring, so it is in the load path seen by the sensor): Dahl (Coulomb with presliding
  stiffness, rate independent: ``dz/dphi = (1 - z*sign(dphi))/x0``, F*z), LuGre with
  Stribeck velocity weakening and viscous term (exact exponential update per sample),
  regularised Coulomb ``F*tanh(v/v0)`` (zero at rest), viscous ``c*v``, quasi-static
  stick-slip through a compliant drive (static > kinetic: a sawtooth; the deflection channel
  then reads the spring's own angle and the sensor the drive torque).
* viscoelastic (standard linear solid on the spring deflection): ``k1*(u - q)``,
  ``dq/dt = (u - q)/tau`` (relaxes during holds).
* cogging: ``A*sin(N*phi + psi)`` on the torque (periodic in the motor angle).
* torque channel: offset, linear drift, exponential settling zero ``A*(1-exp(-t/tau))``,
  first-order low-pass of time constant tau, transport delay d (torque at t is the physical
  torque at t - d), mains hum (50/60 Hz, optional 3rd harmonic), clipping at the sensor range,
  isolated spikes or bursts, white or AR(1) coloured noise, ADC quantisation.
* angle channel: zero offset, a ripple periodic in angle (encoder eccentricity), noise,
  encoder-count quantisation.

Protocols: the paper's staircase (growing amplitudes, holds, linear or cosine ramps), ramps at
1-3 rates (triangles, with or without holds), sine sweeps (several amplitudes and
frequencies), chirps, random levels; 200 Hz to 5 kHz.

``projection_residual`` fits the library's laws (as FIT_PHYSICS.md states them: dead band,
Dahl friction, pure delay, linear drift, offsets, cubic, asymmetric K; plus a viscous damper
in the time_lag family, which springcad's README declares within the lag's meaning) to the noiseless
record by least squares and returns the rms of what they cannot describe: the truth's
``unexplained`` label of out-of-library cases comes from it (rule in heldout_fit_d.py).
"""
from __future__ import annotations

import math

import numpy as np
from scipy import optimize, signal

LIB = ("backlash", "hysteresis", "time_lag", "drift", "torque_offset", "angle_offset",
       "stiffening", "asymmetric_stiffness", "outliers", "series_compliance")


# ----------------------------------------------------------------------------- protocols
def knots_path(knots, fs, profile="linear"):
    """Angle path through (time, angle) knots; linear or cosine-shaped between knots."""
    kt = np.array([k[0] for k in knots], float)
    ka = np.array([k[1] for k in knots], float)
    t = np.arange(0.0, kt[-1], 1.0 / fs)
    i = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 2)
    dt = kt[i + 1] - kt[i]
    s = np.where(dt > 0, (t - kt[i]) / np.where(dt > 0, dt, 1.0), 1.0)
    if profile == "cosine":
        s = 0.5 * (1.0 - np.cos(np.pi * s))
    return t, ka[i] + (ka[i + 1] - ka[i]) * s


def _seq(points, rate, hold, t0=0.5):
    """Knots visiting the angles in turn at a constant rate, holding at each."""
    knots = [(0.0, 0.0), (t0, 0.0)]
    t, a = t0, 0.0
    for p in points:
        r = rate(abs(p - a)) if callable(rate) else rate
        t += abs(p - a) / r if p != a else 0.0
        knots.append((t, p))
        a = p
        h = hold() if callable(hold) else hold
        if h > 0:
            t += h
            knots.append((t, p))
    knots.append((t + t0, a))
    return knots


def staircase(amps, rate, hold, fs, profile="linear"):
    pts = []
    for a in amps:
        pts += [a, 0.0, -a, 0.0]
    return knots_path(_seq(pts, rate, hold), fs, profile)


def ramps(amp, rates, cycles, fs, hold=0.0, profile="linear"):
    knots = [(0.0, 0.0), (0.4, 0.0)]
    t, a = 0.4, 0.0
    for r in rates:
        for _ in range(cycles):
            for p in (amp, -amp):
                t += abs(p - a) / r
                knots.append((t, p))
                a = p
                if hold > 0:
                    t += hold
                    knots.append((t, p))
    t += abs(a) / rates[-1]
    knots.append((t, 0.0))
    knots.append((t + 0.4, 0.0))
    return knots_path(knots, fs, profile)


def sines(parts, fs):
    """parts: (amplitude, frequency, whole cycles) in turn, each starting at 0."""
    ts, ps, t0 = [], [], 0.0
    for a, f, n in parts:
        d = n / f
        t = np.arange(0.0, d, 1.0 / fs)
        ts.append(t0 + t)
        ps.append(a * np.sin(2 * np.pi * f * t))
        t0 += d
    t = np.arange(0.0, t0, 1.0 / fs)
    return t, np.interp(t, np.concatenate(ts), np.concatenate(ps))


def chirp(amp, f0, f1, dur, fs):
    t = np.arange(0.0, dur, 1.0 / fs)
    ph = 2 * np.pi * (f0 * t + 0.5 * (f1 - f0) * t * t / dur)
    env = np.clip(np.minimum(t, dur - t) / 1.0, 0.0, 1.0)
    return t, amp * env * np.sin(ph)


def random_levels(amp, n, rate, fs, rng, hold=(0.5, 2.0), profile="linear"):
    pts = list(rng.uniform(-amp, amp, n))
    pts[int(rng.integers(n))] = amp * rng.choice([-1, 1])
    return knots_path(_seq(pts, rate, lambda: rng.uniform(*hold)), fs, profile)


# ----------------------------------------------------------------------------- laws
def deadzone(x, h):
    return np.where(x > h, x - h, np.where(x < -h, x + h, 0.0))


def dahl(path, x0):
    """Rate-independent Dahl state z in [-1, 1] along an angle path (exact per step)."""
    z = np.empty_like(path)
    zc = 0.0
    prev = path[0]
    d = np.diff(path, prepend=path[0])
    e = np.exp(-np.abs(d) / x0)
    for i in range(path.size):
        di = d[i]
        if di > 0:
            zc = 1.0 - (1.0 - zc) * e[i]
        elif di < 0:
            zc = -1.0 + (1.0 + zc) * e[i]
        z[i] = zc
    return z


def lugre(t, phi, Fc, Fs, vs, sigma0, sigma2):
    v = np.gradient(phi, t)
    dt = np.diff(t, prepend=t[0] - (t[1] - t[0]))
    F = np.empty_like(phi)
    z = 0.0
    for i in range(phi.size):
        vi = v[i]
        g = (Fc + (Fs - Fc) * math.exp(-(vi / vs) ** 2)) / sigma0
        if vi != 0.0:
            a = abs(vi) / g
            zss = vi / a
            z = zss + (z - zss) * math.exp(-a * dt[i])
        F[i] = sigma0 * z + sigma2 * vi
    return F


def hertz_series(x, K, kh):
    """Torque T >= 0 with x = T/K + (T/kh)**(2/3) (x >= 0), by Newton on s = (T/kh)**(1/3)."""
    x = np.asarray(x, float)
    T = np.zeros_like(x)
    pos = x > 0
    xp = x[pos]
    # s^3*kh/K + s^2 = x
    a = kh / K
    s = np.minimum(np.sqrt(xp), np.cbrt(xp / a))
    for _ in range(60):
        f = a * s ** 3 + s ** 2 - xp
        fp = 3 * a * s ** 2 + 2 * s
        s = np.maximum(s - f / np.maximum(fp, 1e-300), 0.0)
    T[pos] = kh * s ** 3
    return T


def impact_gap(t, phi, K, b, J, kc, zeta_c, zeta_b, substeps=8):
    """Body between a gap contact (Kelvin-Voigt kc) and the spring K; returns theta_body."""
    dt_out = t[1] - t[0]
    h = dt_out / substeps
    wc = math.sqrt((kc + K) / J)
    cc = 2 * zeta_c * J * wc
    cb = 2 * zeta_b * math.sqrt(K * J)
    half = b / 2
    th = 0.0
    om = 0.0
    out = np.empty_like(phi)
    dphi = np.diff(phi, append=phi[-1]) / substeps
    vphi = np.gradient(phi, t)
    for i in range(phi.size):
        p = phi[i]
        vp = vphi[i]
        for _ in range(substeps):
            dlt = p - th
            if dlt > half:
                Fc = kc * (dlt - half) + cc * (vp - om)
                Fc = max(Fc, 0.0)
            elif dlt < -half:
                Fc = kc * (dlt + half) + cc * (vp - om)
                Fc = min(Fc, 0.0)
            else:
                Fc = 0.0
            acc = (Fc - K * th - cb * om) / J
            om += acc * h
            th += om * h
            p += dphi[i]
        out[i] = th
    return out


def stick_slip(phi, K, kd, Fs, Fk):
    """Quasi-static stick-slip: spring angle x driven through compliance kd; returns x, drive torque."""
    x = np.empty_like(phi)
    xc = 0.0
    for i in range(phi.size):
        net = kd * (phi[i] - xc) - K * xc
        if abs(net) > Fs:
            s = 1.0 if net > 0 else -1.0
            xc = (kd * phi[i] - s * (2 * Fk - Fs)) / (kd + K)
        x[i] = xc
    return x, kd * (phi - x)


def sls(t, u, k1, tau):
    q = np.empty_like(u)
    qc = u[0]
    e = np.exp(-np.diff(t, prepend=t[0]) / tau)
    for i in range(u.size):
        qc = u[i] + (qc - u[i]) * e[i]
        q[i] = qc
    return k1 * (u - q)


def ar1_noise(n, sd, nc, rng):
    a = math.exp(-1.0 / nc)
    w = rng.normal(0.0, sd * math.sqrt(1 - a * a), n)
    return signal.lfilter([1.0], [1.0, -a], w)


# ----------------------------------------------------------------------------- simulate
def simulate(t, phi, p, rng):
    """Returns dict(t, T, th, T_clean, th_clean, sigma_eff) for the parameter dict p."""
    K = p["K"]
    n = t.size
    th_meas = phi.copy()
    # mechanical path
    if "stickslip" in p:
        s = p["stickslip"]
        x, T = stick_slip(phi, K, s["kd"], s["Fs"], s["Fk"])
        th_meas = x.copy()
        u = x
    else:
        if "impact" in p:
            s = p["impact"]
            u = impact_gap(t, phi - p.get("gap_center", 0.0), K, p["gap"], s["J"], s["kc"],
                           s["zeta_c"], s["zeta_b"])
            T = K * u
        elif "hertz" in p:
            x = phi - p.get("gap_center", 0.0)
            h = p["gap"] / 2
            xm = np.abs(x) - h
            T = np.sign(x) * hertz_series(np.maximum(xm, 0.0), K, p["hertz"])
            u = T / K
        else:
            u = deadzone(phi - p.get("gap_center", 0.0), p.get("gap", 0.0) / 2)
            Kt = np.full(n, K)
            if "Kneg" in p:
                Kt = np.where(u < 0, p["Kneg"], Kt)
            if "kstep" in p:
                ts, f = p["kstep"]
                Kt = np.where(t >= ts, Kt * f, Kt)
            if "ktemp" in p:
                a, tau = p["ktemp"]
                Kt = Kt * (1 - a * (1 - np.exp(-t / tau)))
            T = Kt * u
            if "k3" in p:
                T = T + p["k3"] * u ** 3
            if "stop" in p:
                us, Ks, sides = p["stop"]
                T = T + Ks * np.maximum(u - us, 0.0)
                if sides == 2:
                    T = T - Ks * np.maximum(-u - us, 0.0)
            if "power" in p:
                uc, pw = p["power"]
                T = T + K * u * (np.abs(u) / uc) ** pw
        if "sls" in p:
            T = T + sls(t, u, *p["sls"])
    # parallel friction on the input shaft
    if "dahl" in p:
        F, x0 = p["dahl"]
        T = T + F * dahl(phi, x0)
    if "lugre" in p:
        T = T + lugre(t, phi, **p["lugre"])
    if "tanh" in p:
        F, v0 = p["tanh"]
        T = T + F * np.tanh(np.gradient(phi, t) / v0)
    if "visc" in p:
        T = T + p["visc"] * np.gradient(phi, t)
    if "cog" in p:
        A, N, ps = p["cog"]
        T = T + A * np.sin(N * phi + ps)
    # torque sensor chain
    if "lowpass" in p:
        a = math.exp(-(t[1] - t[0]) / p["lowpass"])
        T = signal.lfilter([1 - a], [1, -a], T, zi=[a * T[0]])[0]
    if p.get("delay", 0.0):
        T = np.interp(t - p["delay"], t, T)
    T = T + p.get("T_offset", 0.0) + p.get("drift", 0.0) * t
    if "expdrift" in p:
        A, tau = p["expdrift"]
        T = T + A * (1 - np.exp(-t / tau))
    if "hum" in p:
        A, f, h3 = p["hum"]
        ps = rng.uniform(0, 2 * np.pi)
        T = T + A * np.sin(2 * np.pi * f * t + ps) + h3 * A * np.sin(6 * np.pi * f * t + 2 * ps)
    # angle channel
    th_meas = th_meas + p.get("th_offset", 0.0)
    if "th_ripple" in p:
        e, m = p["th_ripple"]
        th_meas = th_meas + e * np.sin(m * th_meas)
    T_clean = T.copy()
    if "clip" in p:
        T_clean = np.clip(T_clean, -p["clip"], p["clip"])
    th_clean = th_meas.copy()
    # noise
    sT = p["noise_T"]
    if "ar" in p:
        T = T + ar1_noise(n, sT, p["ar"], rng)
    else:
        T = T + rng.normal(0.0, sT, n)
    if "clip" in p:
        T = np.clip(T, -p["clip"], p["clip"])
    if "outliers" in p:
        idx = rng.choice(np.arange(20, n - 20), p["outliers"], replace=False)
        T[idx] += rng.choice([-1, 1], idx.size) * rng.uniform(15, 40, idx.size) * sT
    if "bursts" in p:
        for _ in range(p["bursts"]):
            i0 = int(rng.integers(50, n - 50))
            L = int(rng.integers(3, 9))
            T[i0:i0 + L] += rng.choice([-1, 1]) * rng.uniform(15, 30) * sT * (1 + 0.2 * rng.normal(size=L))
    sth = p["noise_th"]
    th = th_meas + rng.normal(0.0, sth, n)
    qT = p.get("qT", 0.0)
    qth = p.get("qth", 0.0)
    if qT:
        T = np.round(T / qT) * qT
    if qth:
        th = np.round(th / qth) * qth
    sig = math.sqrt(sT ** 2 + (K * sth) ** 2 + (qT ** 2 + (K * qth) ** 2) / 12.0)
    return dict(t=t, T=T, th=th, T_clean=T_clean, th_clean=th_clean, sigma_eff=sig)


# ----------------------------------------------------------------------------- projection
def projection_residual(t, T, th, effects, max_pts=12000):
    """rms of T minus the best least-squares fit of the library laws in `effects`.

    Always a constant and K*u; u = deadzone(theta(t - d) - c, b/2). Linear terms: t (drift),
    u*[u<0] (asymmetric_stiffness), u**3 (stiffening), Dahl z (hysteresis), dtheta/dt
    (time_lag: springcad's README counts a viscous damper as a negative lag). Nonlinear: d
    (time_lag), b (backlash), c (angle_offset), x0 (hysteresis). Multi-start least squares.
    """
    effects = set(effects)
    step = max(1, int(math.ceil(t.size / max_pts)))
    ts, Ts = t[::step], T[::step]
    names, lo, hi, starts = [], [], [], []
    if "time_lag" in effects:
        names.append("d"); lo.append(-0.2); hi.append(0.2); starts.append([-0.02, 0.0, 0.02])
    if "backlash" in effects:
        names.append("b"); lo.append(0.0); hi.append(0.15); starts.append([0.002, 0.02])
    if "angle_offset" in effects:
        names.append("c"); lo.append(-0.05); hi.append(0.05); starts.append([0.0])
    if "hysteresis" in effects:
        names.append("lx0"); lo.append(math.log(1e-5)); hi.append(math.log(0.2))
        starts.append([math.log(5e-4), math.log(5e-3)])

    vel = np.gradient(th, t)

    def design(q):
        d = dict(zip(names, q))
        x = np.interp(t - d.get("d", 0.0), t, th) if "d" in d else th
        u = deadzone(x - d.get("c", 0.0), d.get("b", 0.0) / 2)
        cols = [np.ones_like(t), u]
        if "drift" in effects:
            cols.append(t)
        if "asymmetric_stiffness" in effects:
            cols.append(np.where(u < 0, u, 0.0))
        if "stiffening" in effects:
            cols.append(u ** 3)
        if "hysteresis" in effects:
            cols.append(dahl(x, math.exp(d["lx0"])))
        if "time_lag" in effects:
            cols.append(vel)
        return np.column_stack(cols)[::step]

    def resid(q):
        A = design(q)
        sc = np.linalg.norm(A, axis=0)
        sc[sc == 0] = 1.0
        coef = np.linalg.lstsq(A / sc, Ts, rcond=None)[0]
        return Ts - (A / sc) @ coef

    if not names:
        r = resid([])
        return float(np.sqrt(np.mean(r ** 2)))
    best = np.inf
    import itertools
    for x0 in itertools.product(*starts):
        try:
            sol = optimize.least_squares(resid, x0, bounds=(lo, hi), diff_step=1e-3,
                                         max_nfev=60 * len(names))
            r = float(np.sqrt(np.mean(sol.fun ** 2)))
        except Exception:  # noqa: BLE001 - a failed start is just skipped
            r = np.inf
        best = min(best, r)
    return best
