"""The common parametric torque model: ``τ = K·θ`` plus any set of effect terms.

The model is a tuple of effects (see :mod:`springcad.fit.effects`) over one
parameter vector ``[K, effect params…]``. It is fitted by robust least squares
(``scipy.optimize.least_squares`` with a soft-L1 loss whose scale is a few
noise standard deviations, so Gaussian noise is fitted as by least squares and
isolated glitches barely pull the fit).

Torque in N·m, angles in rad, time in s, K in N·m/rad.
"""

from __future__ import annotations


import numpy as np
from scipy import optimize

from springcad.fit.effects import STAGES, Effect
from springcad.fit.signals import Scales, Signals

_TORQUE_STAGES = ("angle", "map", "factor", "torque", "output")


class TorqueModel:
    """``τ(θ, t, direction)`` built from the base spring and torque-stage effects.

    Args:
        effects: effects whose stage is a torque stage (angle, map, factor, torque).
        scales: record magnitudes (for bounds and normalisation).
    """

    def __init__(self, effects: tuple[Effect, ...], scales: Scales):
        for e in effects:
            if e.stage not in _TORQUE_STAGES:
                raise ValueError(f"effect {e.name!r} is not a torque-model term")
        self.effects = tuple(sorted(effects, key=lambda e: (STAGES.index(e.stage), e.order)))
        self.scales = scales
        self._params = {e.name: e.params(scales) for e in self.effects}
        self._slices = {}
        i = 1
        for e in self.effects:
            n = len(self._params[e.name])
            self._slices[e.name] = slice(i, i + n)
            i += n
        self.size = i
        lo = [1e-9] + [p.lower for e in self.effects for p in self._params[e.name]]
        hi = [np.inf] + [p.upper for e in self.effects for p in self._params[e.name]]
        self.bounds = (np.array(lo, float), np.array(hi, float))
        self._trace_cache = None
        self._output_cache = None

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(e.name for e in self.effects)

    @property
    def label(self) -> str:
        """``"linear"`` or ``"linear + backlash + …"`` in library order."""
        return " + ".join(("linear",) + self.names)

    def with_effect(self, effect: Effect) -> "TorqueModel":
        return TorqueModel(self.effects + (effect,), self.scales)

    def without(self, name: str) -> "TorqueModel":
        return TorqueModel(tuple(e for e in self.effects if e.name != name), self.scales)

    def transfer(self, other: "TorqueModel", x_other: np.ndarray,
                 fill: dict[str, np.ndarray] | None = None, use_null: bool = False) -> np.ndarray:
        """A parameter vector for this model from ``other``'s, filling new effects.

        Args:
            other: model whose vector ``x_other`` is known.
            x_other: its parameters.
            fill: values for effects not in ``other`` (default: their probe values).
            use_null: fill missing effects with their null values instead of probes.
        """
        x = np.empty(self.size)
        x[0] = x_other[0]
        fill = fill or {}
        for e in self.effects:
            sl = self._slices[e.name]
            if e.name in other._slices:
                x[sl] = x_other[other._slices[e.name]]
            elif e.name in fill:
                x[sl] = fill[e.name]
            else:
                x[sl] = [p.null if use_null else p.probe for p in self._params[e.name]]
        return x

    def _parts(self, x: np.ndarray) -> dict[str, np.ndarray]:
        return {e.name: x[self._slices[e.name]] for e in self.effects}

    def effective_angle(self, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        """Deflection (rad) after the angle stage (time lag, angle offset) at samples ``idx``."""
        theta = sig.theta[idx]
        parts = self._parts(x)
        for e in self.effects:
            if e.stage == "angle":
                theta = e.angle(theta, parts[e.name], sig, idx)
        return theta

    def torque_terms(self, x: np.ndarray, sig: Signals, idx: np.ndarray,
                     names: set[str] | None = None) -> np.ndarray:
        """Sum of the additive torque terms (N·m) of the effects in ``names`` (default all).

        Terms of the spring itself (``Effect.delayed``, friction) are evaluated
        ``lag`` seconds earlier when the model has a late torque channel: the
        channel delays the whole spring torque, not only its elastic part.
        """
        parts = self._parts(x)
        shift = sum(e.time_shift_s(parts[e.name]) for e in self.effects)
        out = np.zeros(idx.size)
        trace = None
        for e in self.effects:
            if e.stage == "torque" and (names is None or e.name in names):
                if e.on_spring:
                    if trace is None:
                        trace = self.spring_trace(x, sig)
                    term = e.spring_torque(parts[e.name], trace, sig, idx)
                elif e.delayed and shift != 0.0:
                    pos = np.clip(idx - shift * sig.scales.sample_rate_hz, 0, sig.n - 1)
                    term = e.torque(parts[e.name], sig, np.rint(pos).astype(int),
                                    fraction=pos)
                else:
                    term = e.torque(parts[e.name], sig, idx)
                out = out + term
        return out

    def spring_trace(self, x: np.ndarray, sig: Signals) -> np.ndarray:
        """The spring's own deflection (rad) on every sample, read on the smooth motion
        (:attr:`Signals.theta_trace`) through the angle and map stages: what a term of
        the spring's material (``Effect.on_spring``) acts on."""
        parts = self._parts(x)
        shaping = [e for e in self.effects if e.stage in ("angle", "map")]
        # a finite-difference Jacobian moves one parameter at a time: the trace depends on
        # the angle and map stages' only, and is kept for the last of them
        key = (id(sig), tuple(float(v) for e in shaping for v in parts[e.name]),
               tuple(e.name + e.law for e in shaping))
        cached = self._trace_cache
        if cached is not None and cached[0] == key and cached[1] is sig:
            return cached[2]
        every = np.arange(sig.n)
        spring = sig.theta_trace
        for e in self.effects:
            if e.stage == "angle":
                spring = e.angle(spring, parts[e.name], sig, every)
        for e in self.effects:
            if e.stage == "map":
                spring = e.map(spring, parts[e.name])
        self._trace_cache = (key, sig, spring)
        return spring

    def predict(self, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        """Model torque (N·m) at samples ``idx``."""
        out = x[0] * self.elastic(x, sig, idx) + self.torque_terms(x, sig, idx)
        if any(e.stage == "output" for e in self.effects):
            out = out + self._output_change(x, sig, idx)
        return out

    def elastic(self, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        """The elastic torque per unit K (rad) at samples ``idx``: the spring's deflection
        (after the angle and map stages) times the factors; ∂(model torque)/∂K where no
        output stage filters the torque."""
        parts = self._parts(x)
        spring = self.effective_angle(x, sig, idx)
        for e in self.effects:
            if e.stage == "map":
                spring = e.map(spring, parts[e.name])
        # the factors' departures from 1 add: an asymmetric K and a cubic are the sum
        # K±·θ + k3·θ³ of their two laws (the cubic is not scaled by each side's K)
        change = 0.0
        for e in self.effects:
            if e.stage == "factor":
                change = change + (e.factor(spring, parts[e.name], self.scales) - 1.0)
        return (1.0 + change) * spring

    def _output_change(self, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        """What the output stage (a filter in the torque sensor) changes in the model
        torque at samples ``idx`` (N·m).

        The torque of the rest of the model is computed on every sample of the smooth
        motion (:attr:`Signals.on_trace`; a filter's output depends on the whole past)
        and passed through each output term; the change is added to the torque at
        ``idx``, so a sample's own deflection noise stays its own, as in
        :class:`~springcad.fit.other_laws.FirstOrderLag`. The inner torque is kept for
        the last inner parameters (a finite-difference Jacobian moves one parameter at
        a time).
        """
        outer = [e for e in self.effects if e.stage == "output"]
        inner = TorqueModel(tuple(e for e in self.effects if e.stage != "output"), self.scales)
        x_in = inner.transfer(self, x)
        key = (id(sig), tuple(float(v) for v in x_in), inner.label,
               tuple(e.law for e in inner.effects))
        cached = self._output_cache
        if cached is not None and cached[0] == key and cached[1] is sig:
            every = cached[2]
        else:
            every = inner.predict(x_in, sig.on_trace, np.arange(sig.n))
            self._output_cache = (key, sig, every)
        parts = self._parts(x)
        read = every
        for e in outer:
            read = e.output(read, parts[e.name], sig)
        return read[idx] - every[idx]

    def residual(self, x: np.ndarray, sig: Signals, idx: np.ndarray) -> np.ndarray:
        """Measured minus model torque (N·m) at samples ``idx``."""
        return sig.torque[idx] - self.predict(x, sig, idx)

    def report(self, x: np.ndarray) -> dict:
        """Fitted parameters with units in the names (stiffness first)."""
        out = {"stiffness_Nm_per_rad": float(x[0])}
        for e in self.effects:
            out.update(self.effect_report(e.name, x))
        return out

    def effect_report(self, name: str, x: np.ndarray) -> dict:
        """Fitted parameters of one effect, with units in the names."""
        e = next(e for e in self.effects if e.name == name)
        return e.report(x[self._slices[name]], float(x[0]), self.scales)

    def solve_stiffness(self, x: np.ndarray, sig: Signals, idx: np.ndarray,
                        weights: np.ndarray | None = None) -> np.ndarray:
        """Return ``x`` with K re-solved by linear least squares, the rest fixed.

        The model is linear in K: ``τ = K·q + a`` with ``a`` the K-free terms.
        """
        x1, x0 = x.copy(), x.copy()
        x1[0], x0[0] = 1.0, 0.0
        a = self.predict(x0, sig, idx)
        q = self.predict(x1, sig, idx) - a
        w = 1.0 if weights is None else weights
        den = float(np.sum(w * q * q))
        out = x.copy()
        if den > 0:
            out[0] = max(float(np.sum(w * q * (sig.torque[idx] - a))) / den, 1e-9)
        return out

    def residual_jacobian(self, x: np.ndarray, sig: Signals, idx: np.ndarray,
                          f0: np.ndarray, free: np.ndarray | None = None) -> np.ndarray:
        """Forward-difference Jacobian of :meth:`residual` at ``x`` (N·m per parameter
        unit), on the columns ``free`` (default all), with scipy's ``2-point`` steps.

        Each column is the change of the residual when one parameter moves, as scipy's
        own difference; only the part of the model that parameter reaches is evaluated
        again: an additive torque term moves its own term only, K moves the elastic
        torque per unit K (the model is linear in K), and a parameter of the angle, map
        or factor stages moves the elastic torque only, unless it shifts the time of the
        delayed terms (a lag) or moves the spring trace that terms of the spring's
        material read. Under an output stage (a filter of the whole torque) every
        parameter moves the whole model. ``f0`` is the residual at ``x``.
        """
        lo, hi = self.bounds
        cols = np.flatnonzero(np.ones(self.size, bool) if free is None else free)
        h = forward_steps(x[cols], lo[cols], hi[cols])
        jac = np.empty((idx.size, cols.size))
        filtered = any(e.stage == "output" for e in self.effects)
        effect_of = {j: e for e in self.effects
                     for j in range(self._slices[e.name].start, self._slices[e.name].stop)}
        term_of = {} if filtered else {j: e.name for j, e in effect_of.items()
                                       if e.stage == "torque"}
        on_spring = any(e.on_spring for e in self.effects if e.stage == "torque")
        shift = {e.name: e.time_shift_s(x[self._slices[e.name]]) for e in self.effects}
        base_terms, base_elastic = {}, []

        def base(name):
            if name not in base_terms:
                base_terms[name] = self.torque_terms(x, sig, idx, {name})
            return base_terms[name]

        for c, j in enumerate(cols):
            xp = x.copy()
            xp[j] = x[j] + h[c]
            dx = xp[j] - x[j]
            if j == 0 and not filtered:
                # the model torque less its additive terms is K times the elastic torque
                terms = np.zeros(idx.size)
                for e in self.effects:
                    if e.stage == "torque":
                        terms = terms + base(e.name)
                if x[0] > 1e-6:
                    jac[:, c] = -(sig.torque[idx] - f0 - terms) / x[0]
                else:
                    jac[:, c] = -self.elastic(x, sig, idx)
            elif j in term_of:
                name = term_of[j]
                jac[:, c] = -(self.torque_terms(xp, sig, idx, {name}) - base(name)) / dx
            elif (not filtered and j > 0 and effect_of[j].stage in ("angle", "map", "factor")
                  and not (on_spring and effect_of[j].stage != "factor")
                  and effect_of[j].time_shift_s(xp[self._slices[effect_of[j].name]])
                  == shift[effect_of[j].name]):
                if not base_elastic:
                    base_elastic.append(self.elastic(x, sig, idx))
                jac[:, c] = -x[0] * (self.elastic(xp, sig, idx) - base_elastic[0]) / dx
            else:
                jac[:, c] = (self.residual(xp, sig, idx) - f0) / dx
        return jac

    def fit(self, sig: Signals, idx: np.ndarray, x0: np.ndarray, f_scale: float,
            max_nfev: int = 100, free: np.ndarray | None = None) -> np.ndarray:
        """Robust least-squares fit on samples ``idx`` from ``x0``.

        Args:
            sig: record signals.
            idx: sample indices to fit.
            x0: start (clipped into the bounds).
            f_scale: soft-L1 scale (N·m): residuals well below it count as squares.
            max_nfev: function evaluations allowed.
            free: boolean mask of the parameters to fit (default all); the
                others stay at their ``x0`` values.

        Returns:
            Fitted parameter vector.
        """
        lo, hi = self.bounds
        span = np.where(np.isfinite(hi - lo), hi - lo, np.abs(x0) + 1.0)
        x0 = np.clip(x0, lo + 1e-9 * span, hi - 1e-9 * span)
        free = np.ones(self.size, bool) if free is None else np.asarray(free, bool)
        full = x0.copy()
        last = {}  # the residual at the last point evaluated: the Jacobian's base

        def residual(z):
            full[free] = z
            r = self.residual(full, sig, idx)
            last["z"], last["r"] = z.copy(), r
            return r

        def jacobian(z):
            if "z" not in last or not np.array_equal(last["z"], z):
                residual(z)
            full[free] = z
            return self.residual_jacobian(full.copy(), sig, idx, last["r"], free)

        res = optimize.least_squares(residual, x0[free], jac=jacobian,
                                     bounds=(lo[free], hi[free]),
                                     loss="soft_l1", f_scale=f_scale, x_scale="jac",
                                     max_nfev=max_nfev, xtol=1e-8, ftol=1e-8)
        out = x0.copy()
        out[free] = res.x
        return out

    def slice_of(self, name: str) -> slice:
        """Positions of effect ``name``'s parameters in the parameter vector."""
        return self._slices[name]


def forward_steps(x: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Forward-difference steps as scipy's ``least_squares`` takes them (``2-point``):
    ``√eps·max(1, |x|)`` signed as ``x`` (positive at 0), turned back where the step
    would leave the bounds, and shortened to the room left where neither way fits."""
    sign = np.where(x >= 0, 1.0, -1.0)
    h = np.sqrt(np.finfo(float).eps) * sign * np.maximum(1.0, np.abs(x))
    below, above = x - lower, upper - x
    leaves = (x + h < lower) | (x + h > upper)
    fits = np.abs(h) <= np.maximum(below, above)
    h = np.where(leaves & fits, -h, h)
    h = np.where(~fits & (above >= below), above, h)
    return np.where(~fits & (above < below), -below, h)
