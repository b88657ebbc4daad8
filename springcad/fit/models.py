"""The paper's torque–deflection models (Section II-B) and their fits.

* linear: ``τ = K·θ`` (least squares through the origin);
* deadband (eq. 4): zero torque for ``|θ| ≤ h``, ``K·(θ ∓ h)`` outside, with
  ``b = 2h``; fitted as the paper did: backlash centred on zero, one K for both
  directions, minimising the sum of absolute errors;
* logit (eqs. 5–9): the deadband with a smooth logit crossover of width ``l``
  on each side, continuous in value and slope; ``K``, ``h`` and ``l`` fitted
  together from the deadband solution with the same absolute-error objective.

Torque in N·m, angles in rad, stiffness in N·m/rad. NRMSE is RMSE over half
the measured torque range, in percent, as in Table I.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy import optimize

#: Below this ratio l/(h+l) the logit crossover is a sharp deadband.
_SHARP = 1e-9


def deadband(theta: np.ndarray, stiffness: float, half_backlash: float) -> np.ndarray:
    """Eq. 4: deadband torque (N·m) at deflection ``theta`` (rad).

    Args:
        theta: deflection (rad).
        stiffness: K (N·m/rad).
        half_backlash: h = b/2 (rad).
    """
    return stiffness * (theta - np.clip(theta, -half_backlash, half_backlash))


@functools.lru_cache(maxsize=256)  # fits evaluate the same (h, l) many times
def logit_coefficients(half_backlash: float, transition: float) -> tuple[float, float, float]:
    """Eqs. 6–7: the ``c`` (1/rad) and ``g`` (rad) of eq. 5 and the edge ``h + l``.

    With ``X = h + l`` and ``u = 2cX``, ``f(X) = l`` and ``f'(X) = 1`` give
    ``g = X(1 - u²)/(2u)`` and ``(1 - u²)·artanh(u)/u = l/X``, which has one
    root ``u ∈ (0, 1)`` for every ``0 < l/X < 1``.

    Args:
        half_backlash: h (rad), > 0.
        transition: l (rad), > 0.

    Returns:
        ``(c, g, X)``.
    """
    edge = half_backlash + transition
    ratio = transition / edge

    def phi(u):
        return (1.0 - u * u) * np.arctanh(u) / u - ratio

    hi = 1.0 - 1e-15
    if phi(hi) > 0:  # ratio below what float64 resolves: effectively sharp
        u = hi
    else:
        u = optimize.brentq(phi, 1e-12, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    c = u / (2.0 * edge)
    g = edge * (1.0 - u * u) / (2.0 * u)
    return c, g, edge


def spring_angle(theta: np.ndarray, half_backlash: float, transition: float) -> np.ndarray:
    """Eq. 9: spring deflection (rad) for a measured deflection across the backlash.

    ``θ - h`` above ``h + l``, ``θ + h`` below ``-(h + l)``, the logit of eq. 5
    in between. ``transition = 0`` gives the sharp deadband of eq. 4 and
    ``half_backlash = 0`` the identity.

    Args:
        theta: measured deflection (rad).
        half_backlash: h = b/2 (rad), ≥ 0.
        transition: l (rad), ≥ 0.
    """
    theta = np.asarray(theta, float)
    if half_backlash <= 0.0:
        return theta.copy()
    if transition <= _SHARP * (half_backlash + transition):
        return theta - np.clip(theta, -half_backlash, half_backlash)
    c, g, edge = logit_coefficients(half_backlash, transition)
    # θ - sign(θ)·h beyond the clearance (edge ≥ h): the clipped form in two passes; the
    # samples within it are overwritten below
    out = theta - np.clip(theta, -half_backlash, half_backlash)
    inside = np.abs(theta) <= edge
    x = theta[inside]
    out[inside] = 2.0 * g * np.arctanh(np.clip(2.0 * c * x, -1.0 + 1e-16, 1.0 - 1e-16))
    return out


def logit(theta: np.ndarray, stiffness: float, half_backlash: float,
          transition: float) -> np.ndarray:
    """Eq. 8: logit-model torque (N·m)."""
    return stiffness * spring_angle(theta, half_backlash, transition)


def rmse(residual: np.ndarray) -> float:
    """Root mean square (same unit as ``residual``)."""
    return float(np.sqrt(np.mean(np.square(residual))))


def nrmse_pct(residual: np.ndarray, half_range: float) -> float:
    """RMSE over half the measured torque range, in percent (Table I)."""
    return 100.0 * rmse(residual) / half_range


@dataclass(frozen=True)
class PaperModelFit:
    """One of the paper's models fitted to a record.

    Attributes:
        model: ``"linear"``, ``"deadband"`` or ``"logit"``.
        stiffness_Nm_per_rad: K.
        backlash_rad: b = 2h (0 for the linear model).
        transition_rad: l of the logit model (``None`` otherwise).
        rmse_Nm: RMS torque error over all samples.
        nrmse_pct: RMSE over half the measured torque range (%).
    """

    model: str
    stiffness_Nm_per_rad: float
    backlash_rad: float
    transition_rad: float | None
    rmse_Nm: float
    nrmse_pct: float

    def predict(self, theta: np.ndarray) -> np.ndarray:
        """Model torque (N·m) at deflection ``theta`` (rad)."""
        h = self.backlash_rad / 2.0
        if self.model == "logit":
            return logit(theta, self.stiffness_Nm_per_rad, h, self.transition_rad)
        return deadband(theta, self.stiffness_Nm_per_rad, h)

    def to_dict(self, target_stiffness_Nm_per_rad: float | None = None) -> dict:
        """The model's numbers, with the stiffness error against
        ``target_stiffness_Nm_per_rad`` (N*m/rad) when one is given."""
        out = {"stiffness_Nm_per_rad": self.stiffness_Nm_per_rad,
               "backlash_rad": self.backlash_rad,
               "nrmse_pct": self.nrmse_pct,
               "rmse_Nm": self.rmse_Nm}
        if self.transition_rad is not None:
            out["transition_rad"] = self.transition_rad
        if target_stiffness_Nm_per_rad:
            out["stiffness_error_pct"] = stiffness_error_pct(self.stiffness_Nm_per_rad,
                                                             target_stiffness_Nm_per_rad)
        return out


def stiffness_error_pct(measured: float, target: float) -> float:
    """Percent stiffness error of ``measured`` relative to ``target`` (Table I)."""
    return 100.0 * (measured - target) / target


def fit_linear(theta: np.ndarray, torque: np.ndarray, half_range: float) -> PaperModelFit:
    """Least-squares ``τ = K·θ`` through the origin."""
    k = float(np.dot(theta, torque) / np.dot(theta, theta))
    r = torque - k * theta
    return PaperModelFit("linear", k, 0.0, None, rmse(r), nrmse_pct(r, half_range))


def _l1_stiffness(theta_spring: np.ndarray, torque: np.ndarray) -> tuple[float, float]:
    """K minimising ``Σ|τ - K·s|`` (a weighted median) and that minimum."""
    nz = theta_spring != 0.0
    s, tau = theta_spring[nz], torque[nz]
    ratio = tau / s
    w = np.abs(s)
    order = np.argsort(ratio)
    cw = np.cumsum(w[order])
    k = float(ratio[order][np.searchsorted(cw, 0.5 * cw[-1])])
    return k, float(np.sum(np.abs(tau - k * s)) + np.sum(np.abs(torque[~nz])))


def fit_deadband(theta: np.ndarray, torque: np.ndarray, half_range: float) -> PaperModelFit:
    """Eq. 4 fitted as in the paper: centred backlash, one K, least absolute error.

    For a given h the best K is a weighted median, so the search is over h
    alone: a grid over ``[0, 0.45·max|θ|]`` refined by bounded Brent.
    """
    theta_max = float(np.max(np.abs(theta)))

    def cost(h):
        return _l1_stiffness(theta - np.clip(theta, -h, h), torque)[1]

    grid = np.linspace(0.0, 0.45 * theta_max, 46)
    costs = [cost(h) for h in grid]
    i = int(np.argmin(costs))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    best = optimize.minimize_scalar(cost, bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-7 * theta_max})
    h = float(best.x) if best.fun <= costs[i] else float(grid[i])
    k = _l1_stiffness(theta - np.clip(theta, -h, h), torque)[0]
    r = torque - deadband(theta, k, h)
    return PaperModelFit("deadband", k, 2.0 * h, None, rmse(r), nrmse_pct(r, half_range))


def fit_logit(theta: np.ndarray, torque: np.ndarray, half_range: float,
              start: PaperModelFit | None = None) -> PaperModelFit:
    """Eqs. 5–9: K, h and the transition l, least absolute error, from the deadband fit."""
    start = start or fit_deadband(theta, torque, half_range)
    theta_max = float(np.max(np.abs(theta)))
    k0, h0 = start.stiffness_Nm_per_rad, start.backlash_rad / 2.0

    def cost(z):
        k, h, l = k0 * np.exp(z[0]), theta_max * z[1] ** 2, theta_max * z[2] ** 2
        return float(np.sum(np.abs(torque - logit(theta, k, h, l))))

    best = None
    for l0 in (0.1 * h0, 0.5 * h0, h0):  # a few starts: the cost is not convex in l
        z0 = np.array([0.0, np.sqrt(h0 / theta_max), np.sqrt(max(l0, 1e-6 * theta_max) / theta_max)])
        res = optimize.minimize(cost, z0, method="Nelder-Mead",
                                options={"xatol": 1e-6, "fatol": 1e-9 * cost(z0), "maxiter": 600})
        if best is None or res.fun < best.fun:
            best = res
    k = k0 * float(np.exp(best.x[0]))
    h = theta_max * float(best.x[1]) ** 2
    l = theta_max * float(best.x[2]) ** 2
    r = torque - logit(theta, k, h, l)
    return PaperModelFit("logit", k, 2.0 * h, l, rmse(r), nrmse_pct(r, half_range))


def fit_paper_models(theta: np.ndarray, torque: np.ndarray,
                     half_range: float) -> dict[str, PaperModelFit]:
    """Fit the linear, deadband and logit models of Section II-B."""
    lin = fit_linear(theta, torque, half_range)
    dead = fit_deadband(theta, torque, half_range)
    return {"linear": lin, "deadband": dead, "logit": fit_logit(theta, torque, half_range, dead)}
