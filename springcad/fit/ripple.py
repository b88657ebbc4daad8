"""Structure periodic in deflection, taken out as a nuisance before the library is fitted.

A ripple that repeats with the angle (an encoder's eccentricity geared from the
motor, a tooth-passing ripple, cogging in the torque) is no effect of the library.
Over a deflection range of one or two of its periods it looks like a smooth shape
in deflection, and fitted beside it a cubic (or an asymmetry) takes up the part
that looks like its own shape; the friction and the lag beside it are then judged
against a residual the ripple dominates, and are lost or invented (a stick-slip's
sawtooth read as a relaxation, a friction rejected as too uncertain).

:func:`periodic_route` reads the first pass's residual, with the shapes in
deflection a ripple is patched with (a crossover, a cubic, an asymmetry, an angle
offset placing them) taken out of the model and the rest refitted,
against a sinusoid in the deflection, ``a·sin(ωθ) + b·cos(ωθ)``, with at least
``MIN_PERIODS`` periods over the deflection range (fewer would be a smooth shape,
the library's to describe; a sinusoid whose best period sits on that bound is one),
jointly with the model's own parameters (linearised).
The sinusoid is taken for a ripple when

* it describes the residual better than the shapes it replaces, by the
  loop's gain threshold (held-out criterion units, the sinusoid counted as three
  parameters): a cubic of the spring is described by a cubic exactly and by a
  sinusoid only to 1-3 %, so a true stiffening keeps its place;
* it is the same sinusoid on the inner and the outer half of the range and on either
  side of zero (``AGREEMENT``): a ripple repeats alike everywhere;
* and it describes at least ``DOMINANCE`` times what it leaves in the residual's
  deflection profile (common to both directions): a hard stop, a Hertzian take-up
  or a crossover are fitted by a sinusoid only in part and leave most of their
  shape.

The loop then runs again on the record with the ripple taken out of the torque;
what is left is judged on the record as measured, so the ripple stays flagged
``unexplained`` and is localised (a finding ``periodic_deflection`` with its period
and amplitude). The final model describes the record with the ripple as a nuisance
term: its NRMSE is of the record without it (``LoopResult.nuisance_Nm``), the
baseline's of the record as measured, and the route is kept only when that is no
worse than the baseline, and when it changes what the library names (a shape fitted
by a sinusoid that names the same effects is no ripple the library was lost beside:
the first pass, fitted with fewer assumptions, stands).

Torque in N·m, deflection in rad.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

from springcad.fit.inference import jacobian
from springcad.fit.localise import CAUSES
from springcad.fit.nuisance import common_profile
from springcad.fit.signals import Signals

#: fewest periods of a ripple over the deflection range (fewer: a smooth shape)
MIN_PERIODS = 1.2
#: the sinusoid must describe this many times (RMS over the deflection profile) what it leaves
DOMINANCE = 3.0
#: effects shaped in deflection that a ripple is patched with (a crossover invented at one of
#: its slopes, a cubic and an asymmetry over the range), and an angle offset placing them
PATCHES = ("backlash", "stiffening", "asymmetric_stiffness", "angle_offset")
#: deflection bins of the profile the period is scanned on
SCAN_BINS = 1024
#: a best period this close (periods over the range) to ``MIN_PERIODS`` asks for fewer
BOUND_PERIODS = 0.02
#: the sinusoid fitted on parts of the range (inner and outer, either side of zero) may differ
#: between them by at most this share of its size
AGREEMENT = 0.5
#: parameters of the sinusoid (amplitude, phase, period)
SINE_PARAMS = 3


@dataclasses.dataclass(frozen=True)
class Ripple:
    """A sinusoid in deflection found in a residual.

    Attributes:
        period_rad: its period in deflection (rad).
        amplitude_Nm: its amplitude (N·m).
        component: the sinusoid on every sample (N·m).
        criterion_gain: how much better (held-out criterion units) it describes the
            residual than the whole-range shapes it replaces.
        dominance: RMS of the sinusoid over the deflection profile over the RMS of the
            structure it leaves there (``inf``: it leaves nothing above the noise; reported
            as ``None``).
        replaces: the whole-range shapes of the first pass's model it stands in for.
    """

    period_rad: float
    amplitude_Nm: float
    component: np.ndarray
    criterion_gain: float
    dominance: float
    replaces: tuple[str, ...]

    def finding(self, share: float) -> dict:
        """A localisation finding for the report (``share`` of the structure)."""
        period = self.period_rad
        return {"share": share, "kind": "periodic_deflection", "period_rad": period,
                "period_deg": math.degrees(period), "per_turn": 2.0 * math.pi / period,
                "amplitude_Nm": self.amplitude_Nm,
                "text": (f"periodic in deflection with period {period:.3g} rad "
                         f"({math.degrees(period):.3g}°, {2 * math.pi / period:.3g} per turn), "
                         f"amplitude {self.amplitude_Nm:.2g} N·m: taken out of the torque "
                         "before the library effects were fitted"
                         + (f" (fitted beside it, {' and '.join(self.replaces)} took up part "
                            "of it)" if self.replaces else "")),
                "causes": CAUSES["periodic_angle"]}


def _project(Q: np.ndarray, y: np.ndarray) -> np.ndarray:
    return y - Q @ (Q.T @ y)


def _disagrees(rp: np.ndarray, Sp: np.ndarray, coef: np.ndarray, theta: np.ndarray) -> bool:
    """Whether the sinusoid's coefficients, fitted again on parts of the deflection range
    (the inner and outer halves of |θ|, the two sides of zero; columns ``Sp``, residual
    ``rp``), differ between the parts by more than ``AGREEMENT`` of their size: a ripple
    repeats alike over the whole range, a shape it patches (a take-up near zero, a stop at
    large deflection) does not."""
    size = float(np.hypot(*coef))
    a = np.abs(theta)
    for part in (a <= np.median(a), theta < 0.0):
        found = []
        for sel in (part, ~part):
            if sel.sum() < 32:
                return True
            found.append(np.linalg.lstsq(Sp[sel], rp[sel], rcond=None)[0])
        if float(np.hypot(*(found[0] - found[1]))) > AGREEMENT * size:
            return True
    return False


def find_ripple(sig: Signals, first, state, gain_threshold: float,
                max_samples: int) -> Ripple | None:
    """The sinusoid in deflection that the residual of ``state`` (a model of the loop's
    first pass) holds (see the module docstring), or ``None``.

    Args:
        sig: record signals.
        first: the loop's result on the record (``LoopResult``).
        state: the model read (``State``): the first pass's final model, or its search's.
        gain_threshold: the loop's gain threshold (held-out criterion units).
        max_samples: most samples used (every k-th above it).
    """
    model, x = state.model, state.x
    every = state.inliers(np.arange(sig.n) if first.keep is None else np.flatnonzero(first.keep))
    idx = every[::max(1, math.ceil(every.size / max_samples))]
    theta_all = sig.theta_smooth
    theta = theta_all[idx]
    span = float(np.ptp(theta))
    if span <= 0.0 or idx.size < 64:
        return None
    replaces = tuple(n for n in model.names if n in PATCHES)
    m0 = model
    for name in replaces:
        m0 = m0.without(name)
    x0 = m0.transfer(model, x)
    if replaces:
        r = m0.residual(x0, sig, idx)
        f_scale = 3.0 * max(1.4826 * float(np.median(np.abs(r - np.median(r)))), 1e-12)
        x0 = m0.fit(sig, idx, x0, f_scale, max_nfev=100)
    r0 = m0.residual(x0, sig, idx)
    Q, _ = np.linalg.qr(jacobian(m0, x0, sig, idx))
    rp = _project(Q, r0)
    # the period scanned on the residual's common deflection profile (fast), refined on samples
    prof = common_profile(rp, idx, sig, bins=SCAN_BINS, var_noise=1.0)
    if prof is None:
        return None
    centre, common, w, _ = prof
    ok = w > 0
    if ok.sum() < 32:
        return None
    c, y, wt = centre[ok], common[ok], w[ok]
    p_max = min(SCAN_BINS / 8.0, span / max(20.0 * sig.scales.theta_noise, 1e-9))
    if p_max <= MIN_PERIODS:
        return None

    # on the profile, beside a torque zero and a stiffness (what the model's own terms take)
    base = np.column_stack([np.ones_like(c), c]) * np.sqrt(wt)[:, None]
    yb = y * np.sqrt(wt)
    yb = yb - base @ np.linalg.lstsq(base, yb, rcond=None)[0]

    def on_profile(periods: float) -> float:
        om = 2.0 * math.pi * periods / span
        S = np.column_stack([np.sin(om * c), np.cos(om * c)]) * np.sqrt(wt)[:, None]
        S = S - base @ np.linalg.lstsq(base, S, rcond=None)[0]
        coef, *_ = np.linalg.lstsq(S, yb, rcond=None)
        return float(np.sum((S @ coef) ** 2))

    def on_samples(periods: float):
        # jointly with the model's parameters (linearised): the sinusoid's columns projected
        # off the Jacobian's span
        om = 2.0 * math.pi * periods / span
        Sp = np.column_stack([_project(Q, np.sin(om * theta)), _project(Q, np.cos(om * theta))])
        coef, *_ = np.linalg.lstsq(Sp, rp, rcond=None)
        return coef, Sp @ coef, Sp

    grid = np.arange(MIN_PERIODS, p_max, 0.05)
    gains = [on_profile(p) for p in grid]
    p0 = float(grid[int(np.argmax(gains))])
    res = optimize.minimize_scalar(lambda p: -float(np.sum(on_samples(p)[1] ** 2)),
                                   bounds=(max(MIN_PERIODS, p0 - 0.3), min(p_max, p0 + 0.3)),
                                   method="bounded", options={"xatol": 1e-3})
    periods = float(res.x)
    if periods < MIN_PERIODS + BOUND_PERIODS:
        return None  # wants fewer periods than a ripple has: a smooth shape, not a period
    coef, fitted, Sp = on_samples(periods)
    if _disagrees(rp, Sp, coef, theta):
        return None
    left = rp - fitted
    tau = max(1.0, float(first.structure.get("noise_correlation_samples", 1.0))
              * idx.size / max(every.size, 1))
    n_eff = idx.size / tau
    r_shape = model.residual(x, sig, idx)

    def crit(sse: float, k: int) -> float:
        return n_eff * math.log(max(sse, 1e-300) / idx.size) + k * math.log(n_eff)

    k_shape = sum(model.slice_of(n).stop - model.slice_of(n).start for n in replaces)
    gain = crit(float(r_shape @ r_shape), k_shape) - crit(float(left @ left), SINE_PARAMS)
    if gain <= gain_threshold:
        return None
    # what the sinusoid leaves in the deflection profile, against what it describes there
    prof_left = common_profile(left, idx, sig)
    own = common_profile(fitted, idx, sig, var_noise=1.0)
    if prof_left is None or own is None:
        return None
    _, common_left, n_left, var_noise = prof_left
    okl = n_left > 0
    if not okl.any():
        return None
    wl = n_left[okl]
    left_ms = (float(np.sum(wl * common_left[okl] ** 2)) - int(okl.sum()) * var_noise) \
        / float(wl.sum())
    own_ms = float(np.sum(wl * own[1][okl] ** 2)) / float(wl.sum())
    # nothing left above the noise: the sinusoid describes the whole profile
    dominance = math.sqrt(own_ms / left_ms) if left_ms > 0.0 else math.inf
    if dominance < DOMINANCE:
        return None
    om = 2.0 * math.pi * periods / span
    component = coef[0] * np.sin(om * theta_all) + coef[1] * np.cos(om * theta_all)
    return Ripple(span / periods, float(np.hypot(*coef)), component, float(gain), dominance,
                  replaces)


def periodic_route(sig: Signals, settings, first, run):
    """The loop again on the record with a ripple in deflection taken out of the torque,
    judged on the record as measured (see the module docstring), or ``None``.

    ``first`` is the loop's result on the record, ``run(sig, settings, keep, judge)`` the
    loop on signals ``sig`` whose residual is judged on ``judge``.
    """
    if not first.unexplained or first.no_spring:
        return None
    # the search's model holds every patch the ripple drew in (a cubic, an asymmetry, an
    # angle offset placing them); the final model may have lost the effects beside it
    ripple = None
    for state in (first.searched, first.final):
        if state is not None and ripple is None:
            ripple = find_ripple(sig, first, state, settings.gain_threshold,
                                 settings.max_cv_samples)
    if ripple is None:
        return None
    out = run(sig.with_torque(sig.torque - ripple.component), settings, first.keep, sig)
    out = dataclasses.replace(out, baseline=first.baseline, nuisance_Nm=ripple.component)
    if out.no_spring or out.nrmse_pct(out.final, sig) > out.nrmse_pct(out.baseline, sig):
        return None
    if set(out.final.effects) == set(first.final.effects):
        return None  # the library reads the record alike beside it: the first pass stands
    loc = out.localisation
    nuisance = {"kind": "periodic_deflection", "period_rad": ripple.period_rad,
                "amplitude_Nm": ripple.amplitude_Nm, "criterion_gain": ripple.criterion_gain,
                "dominance": ripple.dominance if math.isfinite(ripple.dominance) else None,
                "first_pass_model": first.final.label,
                "reason": ("the first pass's residual held a ripple periodic in deflection that "
                           "no library effect describes: taken out of the torque before the "
                           "library effects were fitted, and judged with the rest on the "
                           "record as measured")}
    if out.unexplained and loc is not None:
        own = loc["findings"]
        share = max(0.0, 1.0 - sum(f.get("share", 0.0) for f in own))
        found = [ripple.finding(max(share, 0.5))] + own
        loc = {**loc, "findings": found, "summary": "; ".join(f["text"] for f in found)}
    return dataclasses.replace(out, localisation=loc, nuisance=nuisance)

