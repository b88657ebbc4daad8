"""Evidence that an effect is the record's, not a patch over something else.

An effect found by the residual loop stays in the model only if the record
supports it *consistently*: the model is fitted again, separately, on two
parts of the record, for each of three splits:

* ``time``: the runs (stretches between reversals) of the first and of the
  last third of the record (the gap between them makes a change anywhere in
  the middle third show in full);
* ``amplitude``: runs that reach small and large deflections (skipped when
  the record has one amplitude only);
* ``direction``: samples moving away from zero deflection (loading) and
  towards it (unloading). Effects whose torque follows the direction of
  motion (friction, a late torque channel) would read as a step at zero on
  one direction alone, so they are held at their full-record values there
  and not compared.

All other parameters (stiffness and the other effects) are fitted freely on
each part. For every effect the split applies to, its size parameter must

1. *agree* between the parts within their uncertainty (Wald test with the
   clustered covariance of :mod:`springcad.fit.inference`,
   ``p >= agreement_p``), and
2. be *supported* by the parts together: the inverse-variance mean of the two
   part values is at least ``support_z`` standard errors away from the value
   at which the effect vanishes.

A monotone effect, a drift, agrees and is supported when one part shows it at
``support_z`` and no part as strongly the other way: a zero that settles drifts at
a falling rate (and not at all once settled); what its linear law leaves is the
residual's to flag.

An effect no split applies to (a short record: too few runs in a part) must
still be supported, on the whole record with its clustered standard error: a
friction that a thermal loss of stiffness fakes on a staircase (unloading
later, at a lower K) is not one a run-by-run jackknife can tell from zero.

A patch over structure outside the library fails one of the two: a stiffness
that changes mid-test is "explained" by a crossover or an asymmetry only
because the stiffness is shared between early and late cycles; with its own
stiffness in each half, neither half wants the patch (not supported). A hard
stop at large deflection fitted as cubic stiffening gives a large cubic term
on large cycles and none on small ones (no agreement).

Units: those of each effect's parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from springcad.fit.effects import get_effect
from springcad.fit.identify import turn_window_s
from springcad.fit.inference import uncertainty, wald_p
from springcad.fit.nuisance import (common_profile, nuisance_kind, nuisance_parts,
                                     views_without)
from springcad.fit.signals import Signals
from springcad.fit.torque_model import TorqueModel

SPLITS = ("time", "amplitude", "direction")

#: the check of an effect no split applies to: its support on the whole record
WHOLE = "whole"
WHOLE_LABEL = "the whole record (too few runs to split)"

#: how strongly a patch fails (:attr:`EffectEvidence.strength`): below any disagreement
#: (-log10 p >= 3) or lack of support (10 - |z| > 7)
PATCH_STRENGTH = 1.0

#: a split part needs at least this many runs (clusters of the covariance)
MIN_RUNS = 4
#: amplitude split only when the parts' typical amplitudes differ by this factor
MIN_AMPLITUDE_RATIO = 1.25


@dataclass(frozen=True)
class Part:
    """One part of a split: a label and which of the given samples belong to it."""

    label: str
    mask: np.ndarray


def split_parts(sig: Signals, idx: np.ndarray) -> dict[str, tuple[Part, Part]]:
    """The applicable splits of samples ``idx`` into two parts each (see module docstring)."""
    runs = sig.runs[idx]
    t = sig.t[idx]
    labels, inv = np.unique(runs, return_inverse=True)
    mid_t = np.bincount(inv, weights=t) / np.bincount(inv)
    amp = np.zeros(labels.size)
    np.maximum.at(amp, inv, np.abs(sig.theta_smooth[idx]))
    out = {}
    t1, t2 = (float(v) for v in np.percentile(t, [100 / 3, 200 / 3]))
    run_t = mid_t[inv]
    out["time"] = (Part(f"the first third (t < {t1:.3g} s)", run_t < t1),
                   Part(f"the last third (t > {t2:.3g} s)", run_t > t2))
    cut = _amplitude_cut(amp, np.bincount(inv, minlength=labels.size))
    if cut is not None:
        small = amp[inv] <= cut
        out["amplitude"] = (Part(f"runs reaching at most {cut:.3g} rad", small),
                            Part(f"runs reaching beyond {cut:.3g} rad", ~small))
    loading = sig.loading[idx]
    out["direction"] = (Part("loading (|deflection| growing)", loading),
                        Part("unloading (|deflection| shrinking)", ~loading))
    return {k: v for k, v in out.items()
            if all(np.unique(runs[p.mask]).size >= MIN_RUNS for p in v)}


def _amplitude_cut(amp: np.ndarray, weight: np.ndarray) -> float | None:
    """The run amplitude below which the small part ends, or ``None``.

    Cuts go where consecutive run amplitudes differ by ``MIN_AMPLITUDE_RATIO``
    at least (a real gap, not noise about one amplitude) and leave a quarter of
    the samples or more on each side; of those, the most even split is taken.
    """
    order = np.argsort(amp)
    a, w = amp[order], weight[order].astype(float)
    share = np.cumsum(w) / w.sum()
    best = None
    for i in range(a.size - 1):
        if a[i] <= 0 or a[i + 1] / a[i] < MIN_AMPLITUDE_RATIO:
            continue
        if 0.25 <= share[i] <= 0.75 and (best is None or abs(share[i] - 0.5) < best[0]):
            best = (abs(share[i] - 0.5), float(a[i]))
    return None if best is None else best[1]


@dataclass(frozen=True)
class SplitCheck:
    """One effect on one split.

    Attributes:
        split: ``"time"``, ``"amplitude"``, ``"direction"``, or ``"whole"`` (no split
            applies: support on the whole record, nothing compared).
        parts: labels of the two parts.
        parameter: name of the size parameter compared.
        values: its value on each part.
        se: its standard error on each part.
        agreement_p: p-value of the difference (high = they agree).
        support_z: inverse-variance mean of the parts over its standard error,
            measured from the value where the effect vanishes.
        agrees: ``agreement_p`` clears the threshold.
        supported: ``support_z`` clears the threshold.
    """

    split: str
    parts: tuple[str, str]
    parameter: str
    values: tuple[float, float]
    se: tuple[float, float]
    agreement_p: float
    support_z: float
    agrees: bool
    supported: bool

    def to_dict(self) -> dict:
        return {"split": self.split, "parts": list(self.parts), "parameter": self.parameter,
                "values": list(self.values), "se": list(self.se),
                "agreement_p": self.agreement_p, "support_z": self.support_z,
                "agrees": self.agrees, "supported": self.supported}


@dataclass(frozen=True)
class EffectEvidence:
    """The consistency evidence of one effect of a model.

    Attributes:
        effect: library name.
        checks: one per applicable split.
        problem: why the fitted values are physically impossible, or ``None``.
        patch: why the effect is a patch over a structure of another kind
            (:func:`time_check`), or ``None``. It fails more weakly than any
            split (``PATCH_STRENGTH``): with another failing effect gone first,
            the patch is judged again.
    """

    effect: str
    checks: tuple[SplitCheck, ...] = ()
    problem: str | None = None
    patch: str | None = None

    @property
    def consistent(self) -> bool:
        return all(c.agrees for c in self.checks)

    @property
    def supported(self) -> bool:
        return all(c.supported for c in self.checks)

    @property
    def ok(self) -> bool:
        return self.problem is None and self.patch is None and self.consistent and self.supported

    @property
    def strength(self) -> float:
        """How badly it fails (larger = worse): used to drop the worst effect first."""
        if self.problem is not None:
            return math.inf
        bad = PATCH_STRENGTH if self.patch is not None else 0.0
        for c in self.checks:
            if not c.agrees:
                bad = max(bad, -math.log10(max(c.agreement_p, 1e-300)))
            if not c.supported:
                bad = max(bad, 10.0 - min(abs(c.support_z), 10.0))
        return bad

    def reason(self) -> str:
        """One sentence on why it failed (empty when it did not)."""
        if self.problem is not None:
            return self.problem
        out = [] if self.patch is None else [self.patch]
        for c in self.checks:
            if not c.agrees:
                out.append(f"{c.parameter} differs between {c.parts[0]} ({c.values[0]:.4g} ± "
                           f"{c.se[0]:.2g}) and {c.parts[1]} ({c.values[1]:.4g} ± {c.se[1]:.2g}), "
                           f"p = {c.agreement_p:.2g}")
            elif not c.supported and c.split == WHOLE:
                out.append(f"{c.parameter} is {c.values[0]:.4g} ± {c.se[0]:.2g} on "
                           f"{c.parts[0]}: only {abs(c.support_z):.2g} standard errors from zero")
            elif not c.supported:
                out.append(f"with the rest of the model fitted separately on {c.parts[0]} and "
                           f"{c.parts[1]}, {c.parameter} is {c.values[0]:.4g} ± {c.se[0]:.2g} and "
                           f"{c.values[1]:.4g} ± {c.se[1]:.2g}: only {abs(c.support_z):.2g} "
                           "standard errors from zero")
        return "; ".join(out)

    def short_reason(self) -> str:
        """The first failure only, in a few words."""
        if self.problem is not None:
            return self.problem
        if self.patch is not None:
            return self.patch
        for c in self.checks:
            if not c.agrees:
                return (f"{c.parameter} differs between {c.parts[0]} and {c.parts[1]} "
                        f"({c.values[0]:.3g} vs {c.values[1]:.3g}, p = {c.agreement_p:.2g})")
            if not c.supported and c.split == WHOLE:
                return (f"not supported on {c.parts[0]} ({c.parameter} {c.values[0]:.3g} ± "
                        f"{c.se[0]:.2g})")
            if not c.supported:
                return (f"not supported once the rest of the model is fitted separately on "
                        f"{c.parts[0]} and {c.parts[1]} ({c.parameter} {c.values[0]:.3g} ± "
                        f"{c.se[0]:.2g} and {c.values[1]:.3g} ± {c.se[1]:.2g})")
        return ""

    def to_dict(self) -> dict:
        return {"effect": self.effect, "ok": self.ok, "consistent": self.consistent,
                "supported": self.supported, "physical_problem": self.problem,
                "patch": self.patch,
                "reason": self.reason() or None, "splits": [c.to_dict() for c in self.checks]}


@dataclass
class Audit:
    """Consistency evidence of every torque-model effect of one model."""

    effects: dict[str, EffectEvidence] = field(default_factory=dict)
    splits: dict[str, tuple[str, str]] = field(default_factory=dict)

    def failed(self) -> list[EffectEvidence]:
        return sorted((e for e in self.effects.values() if not e.ok), key=lambda e: -e.strength)


def audit(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray, f_scale: float,
          agreement_p: float, support_z: float, max_nfev: int = 40) -> Audit:
    """Check every effect of ``model`` (fitted ``x``) across the splits of samples ``idx``.

    Args:
        model: the torque model.
        x: its parameters fitted on the whole record.
        sig: record signals.
        idx: samples to use (glitches excluded), sorted.
        f_scale: soft-L1 scale of the fits (N·m).
        agreement_p: least p-value for the parts to agree.
        support_z: least z for the parts together to support the effect.
        max_nfev: function evaluations per part fit.

    Returns:
        The audit (physically impossible values are reported even without splits).
    """
    out = Audit()
    shapes = shape_check(model, x, sig, idx)
    for e in model.effects:
        sl = model.slice_of(e.name)
        out.effects[e.name] = EffectEvidence(
            e.name, (), e.physical_problem(x[sl], float(x[0]), model.scales) or shapes.get(e.name))
    if not model.effects:
        return out
    checks: dict[str, list[SplitCheck]] = {e.name: [] for e in model.effects}
    rate = sig.scales.sample_rate_hz / max(float(np.median(np.diff(idx))), 1.0)
    full, x_full = model, x
    if "drift" in model.names and "torque_offset" not in model.names:
        # a drift is anchored at the record's start; on a part of the record it is
        # judged by its rate, with the part's own torque zero

        model = model.with_effect(get_effect("torque_offset"))
        x = model.transfer(full, x_full, use_null=True)
    # each effect is judged with the unexplained structure it cannot describe taken out
    # (see springcad.fit.nuisance), so a friction or a crossover is not rejected for a
    # zero jump or a hard stop beside it
    slow, profile, var_noise = nuisance_parts(full.residual(x_full, sig, idx), idx, sig)
    views = views_without(sig, slow, profile)
    patches = time_check(full, slow, idx, var_noise)
    patches.update(steady_check(full, x_full, sig, idx, f_scale, support_z, rate, max_nfev))
    for split, parts in split_parts(sig, idx).items():
        tested = [e for e in model.effects if split in e.splits and e.name in full.names]
        if not tested:
            continue
        free = np.ones(model.size, dtype=bool)
        if split == "direction":
            for e in model.effects:
                if e.direction_signed:
                    free[model.slice_of(e.name)] = False
        groups: dict[str, list] = {}
        for e in tested:
            groups.setdefault(nuisance_kind(e), []).append(e)
        out.splits[split] = (parts[0].label, parts[1].label)
        for kind, group in groups.items():
            signals = views.get(kind, sig)
            fits = []
            for part in parts:
                sub = idx[part.mask]
                xp = model.fit(signals, sub, x, f_scale, max_nfev=max_nfev, free=free)
                fits.append((xp, uncertainty(model, xp, signals, sub, sample_rate_hz=rate)))
            _compare(checks, model, group, split, parts, fits, agreement_p, support_z)
    unsplit = [e for e in full.effects if not checks[e.name]]
    if unsplit:
        # a record too short to split (too few runs in a part) still asks the same support
        # of each effect: on the whole record, with its clustered standard error
        unc = uncertainty(full, x_full, sig, idx, sample_rate_hz=rate)
        for e in unsplit:
            j = full.slice_of(e.name).start + e.primary
            q = e.params(full.scales)[e.primary]
            v, se = float(x_full[j]), float(unc.se[j])
            z = _support_z(((v, se),), q.null)
            checks[e.name].append(SplitCheck(WHOLE, (WHOLE_LABEL, WHOLE_LABEL), q.name, (v, v),
                                             (se, se), 1.0, z, True, abs(z) >= support_z))
    for name, cs in checks.items():
        out.effects[name] = EffectEvidence(name, tuple(cs), out.effects[name].problem,
                                           patches.get(name))
    return out


def _compare(checks: dict, model: TorqueModel, tested: list, split: str, parts, fits,
             agreement_p: float, support_z: float) -> None:
    """Agreement and support of each effect in ``tested`` from the two part fits."""
    for e in tested:
        j = model.slice_of(e.name).start + e.primary
        null = e.params(model.scales)[e.primary].null
        (xa, ua), (xb, ub) = fits
        va, vb = float(xa[j]), float(xb[j])
        sa, sb = float(ua.se[j]), float(ub.se[j])
        p = wald_p(np.array([va - vb]), np.array([[sa * sa + sb * sb]]),
                   min(ua.dof, ub.dof))
        z = _support_z(((va, sa), (vb, sb)), null)
        one_way = e.monotone and _one_way(((va, sa), (vb, sb)), null, support_z)
        checks[e.name].append(SplitCheck(
            split, (parts[0].label, parts[1].label),
            e.params(model.scales)[e.primary].name, (va, vb), (sa, sb), p, z,
            p >= agreement_p or one_way, abs(z) >= support_z or one_way))


def _one_way(parts: tuple[tuple[float, float], ...], null: float, support_z: float) -> bool:
    """Whether a part stands ``support_z`` standard errors from ``null`` and none stands
    as far on the other side (``(value, standard error)`` parts): a monotone effect (a
    torque zero drifting fast after taring, then settling) that the record shows one way,
    though by different amounts in its parts (and none in the last, once settled); what
    the linear law leaves is the residual's to flag."""
    z = [(v - null) / se for v, se in parts if se > 0 and math.isfinite(se)]
    if len(z) != len(parts):
        return False
    return ((max(z) >= support_z and min(z) > -support_z)
            or (min(z) <= -support_z and max(z) < support_z))


#: a standard error below this share of its value is round-off about a parameter resting on
#: a bound (no bench measures a size to a part in a billion): no information, as zero is
NO_INFORMATION = 1e-9


def _support_z(parts: tuple[tuple[float, float], ...], null: float) -> float:
    """Inverse-variance mean of ``(value, standard error)`` parts, in standard errors from
    ``null``. A part with no standard error carries no information on the effect (its
    parameter rests on a bound, where the fit cannot move it: a filter time constant of
    zero, a relaxing branch of no stiffness; a standard error of round-off,
    ``NO_INFORMATION`` of the value, is none) and does not count; with none left the
    effect is not supported (z = 0): a value nothing measures is no evidence."""
    w = [(v, 1.0 / (se * se)) for v, se in parts
         if se > NO_INFORMATION * abs(v) and se > 0 and math.isfinite(se)]
    if not w:
        return 0.0
    total = sum(wi for _, wi in w)
    pooled = sum(v * wi for v, wi in w) / total
    return (pooled - null) * math.sqrt(total)


def time_check(model: TorqueModel, slow: np.ndarray | None, idx: np.ndarray,
               var_noise: float) -> dict[str, str]:
    """A torque offset beside a torque zero that still moves.

    A torque offset says the torque zero stays put (a drift, if fitted with it,
    moves it at a steady rate). When, with the offset fitted, the residual's
    mean over whole cycles (:func:`springcad.fit.nuisance.slow_part`) still
    stands above noise, the zero moves in a way the model does not describe (it
    settles, jumps or wanders) and no single offset is the sensor's: the one
    fitted is the mean of that motion, a patch over it. A sensor that settles
    after switch-on reads as an offset equal to its mean, which the time split
    misses: the early part's own settling widens its interval. The offset is not
    named; the loop reports the motion as unexplained structure and localises it
    in time. A drift is not judged here: its rate can agree on both sides of a
    jump, which the time split checks.

    Args:
        model: the torque model.
        slow: the slow part of its residual (N·m, every sample), ``None`` when
            within noise.
        idx: the samples it was judged on.
        var_noise: the noise variance it was judged against (N·m² per sample,
            times the correlation time).

    Returns:
        ``{"torque_offset": reason}`` when it fails, else ``{}``.
    """
    if slow is None or "torque_offset" not in model.names:
        return {}
    rms = math.sqrt(float(np.mean(slow[idx] ** 2)))
    return {"torque_offset": (
        f"with torque_offset fitted, the torque zero still moves over the record: the "
        f"residual's mean over whole cycles varies by {rms:.3g} N·m RMS (sample noise "
        f"{math.sqrt(var_noise):.2g} N·m), so no single offset describes it (the zero settles, "
        "jumps or wanders)")}


#: a lag is judged away from the turns only where it is known there to this many times
#: its standard error on the whole record (beyond, the steady motion cannot tell it from
#: friction: the pair is the identifiability check's to name)
STEADY_SE_RATIO = 4.0


def steady_check(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                 f_scale: float, support_z: float, rate: float,
                 max_nfev: int = 40) -> dict[str, str]:
    """A time lag beside friction that lives at the turns only.

    Friction whose law is not the library's (a Dahl or LuGre turn, a
    regularised Coulomb law) differs from the library's presliding shape for a
    few milliseconds after each turn, and a lag of a fraction of a sample
    period takes up that difference. A channel delay or a damper acts through
    the whole motion: refitted (everything free) on the samples away from the
    turns (:func:`springcad.fit.identify.turn_window_s`), it must still stand
    ``support_z`` standard errors from zero. The check applies where the steady
    motion can tell a lag from friction (holds, speeds that vary: its standard
    error there within ``STEADY_SE_RATIO`` of the whole record's).

    Returns:
        ``{"time_lag": reason}`` when it fails, else ``{}``.
    """
    if "time_lag" not in model.names or "hysteresis" not in model.names:
        return {}
    steady = sig.since_turn_s[idx] >= turn_window_s(model, x, sig)
    if steady.sum() < 20 * model.size or steady.all():
        return {}
    sub = idx[steady]
    j = model.slice_of("time_lag").start
    full_se = float(uncertainty(model, x, sig, idx, sample_rate_hz=rate).se[j])
    xs = model.fit(sig, sub, x, f_scale, max_nfev=max_nfev)
    se = float(uncertainty(model, xs, sig, sub, sample_rate_hz=rate).se[j])
    if not (0.0 < se <= STEADY_SE_RATIO * full_se) or abs(xs[j]) >= support_z * se:
        return {}
    return {"time_lag": (
        f"away from the turns the lag is {xs[j]:.3g} ± {se:.2g} s (whole record "
        f"{x[j]:.3g} s): it describes the shape of the friction's turn, which is not the "
        "library's presliding law, not a delay or a damper acting through the motion")}


#: leftover structure where a shape effect acts must be this many times (in mean square)
#: that elsewhere for the shape to count as not the record's
SHAPE_CONCENTRATION = 4.0
#: ... and at least this share (RMS) of what the effect's own term describes there: a
#: crossover whose take-up is softer than the library's (a Hertzian contact, a filtered
#: torque) leaves a tenth of its size, a crossover fitted to a torque-sensor dead band
#: leaves more than it describes
SHAPE_DESCRIBED = 0.5


def _term_ms(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray, name: str,
             inside: np.ndarray) -> float:
    """Mean square (N·m²) of effect ``name``'s own term, over the deflection bins
    ``inside`` of its profile common to both directions."""
    m0 = model.without(name)
    term = model.predict(x, sig, idx) - m0.predict(m0.transfer(model, x), sig, idx)
    prof = common_profile(term, idx, sig, var_noise=1.0)
    if prof is None:
        return 0.0
    return float(np.mean(prof[1][inside] ** 2))


def shape_check(model: TorqueModel, x: np.ndarray, sig: Signals, idx: np.ndarray,
                p_level: float = 1e-6, min_rms: float = 0.25) -> dict[str, str]:
    """Shape effects whose own band of deflection still holds the structure.

    A crossover fitted to a torque-sensor dead band, or a cubic fitted to a hard
    stop, takes a little off the error and leaves the rest where it acts: the
    residual's deflection profile (common to both directions, see
    :mod:`springcad.fit.nuisance`) stands above noise inside the effect's band
    (``Effect.acts_within``) and is concentrated there (``SHAPE_CONCENTRATION``
    times its mean square outside). Such an effect describes a structure of
    another shape, and is not named.

    Returns:
        ``{effect: reason}`` for the effects that fail.
    """
    bands = {}
    for e in model.effects:
        band = e.acts_within(x[model.slice_of(e.name)], model.scales)
        if band is not None:
            bands[e.name] = band
    if not bands:
        return {}
    r = model.residual(x, sig, idx)
    prof = common_profile(r, idx, sig)
    if prof is None:
        return {}
    centre, common, n_eff, var_noise = prof
    out = {}
    for name, (lo, hi) in bands.items():
        inside = (np.abs(centre) >= lo) & (np.abs(centre) <= hi) & (n_eff > 0)
        outside = ~inside & (n_eff > 0)
        if inside.sum() < 2 or outside.sum() < 2:
            continue
        chi2 = float(np.sum(n_eff[inside] * common[inside] ** 2)) / var_noise
        ms_in = max(float(np.mean(common[inside] ** 2)) - var_noise / float(np.mean(n_eff[inside])),
                    0.0)
        ms_out = max(float(np.mean(common[outside] ** 2))
                     - var_noise / float(np.mean(n_eff[outside])), 0.0)
        sigma2 = var_noise  # per-sample noise variance times its correlation
        if (stats.chi2.sf(chi2, int(inside.sum())) < p_level and ms_in > min_rms ** 2 * sigma2
                and ms_in > SHAPE_CONCENTRATION * ms_out
                and ms_in > SHAPE_DESCRIBED ** 2 * _term_ms(model, x, sig, idx, name, inside)):
            where = (f"|deflection| below {hi:.3g} rad" if lo == 0 else
                     f"|deflection| beyond {lo:.3g} rad")
            out[name] = (f"the residual still holds structure of RMS {math.sqrt(ms_in):.3g} N·m "
                         f"where {name} acts ({where}), {math.sqrt(ms_in / max(ms_out, 1e-300)):.2g} "
                         "times that elsewhere: the record's shape there is not this effect's")
    return out
