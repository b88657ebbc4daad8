"""Structure outside the library in a band of deflection: fit the library where it is not.

A hard stop or a torque sensor that clips acts beyond some deflection. Fitted
on every sample, such a structure pulls the stiffness and hides the library
effects beside it (a crossover under a hard stop); patched, it invents effects.
:func:`outside_structure` fits the model again outside the band, and the loop
judges what is left on every sample, so the structure stays flagged and
localised. ``LoopResult.region`` (fit.json ``final.fitted_region``) says what
was left out and why.

Only a structure that engages at a deflection is left out so (a kink: the
residual beyond its onset is a hinge, :func:`springcad.fit.localise.onset_is_kink`);
a stiffness growing smoothly from zero (a contact whose area grows with the load)
acts in every band, and fitted inside one its curvature reads as a crossover.

Two patches hide such a band. A cubic fitted over a structure at large
deflection spreads it over the whole range (a clipping sensor read as a
softening spring): the structure is localised again on the model without the
cubic. And a cubic beside structure near zero that the crossover does not
describe (a Hertzian take-up) bends the line to patch it: the model is fitted
outside the band near zero, the crossover read from the offsets of the lines on
either side of it (``fitted_region.inside``: the band left out is the inner one).

Units: N·m, rad, s.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from springcad.fit.localise import localise, onset_is_kink, structure_onset
from springcad.fit.search import LoopSettings
from springcad.fit.segment import noise_std
from springcad.fit.signals import Signals


#: a localised structure must carry this share of the final residual's structure for the
#: model to be fitted again without its band of deflection
REGION_SHARE = 0.5
#: and the band left out may hold at most this share of the samples
REGION_MAX_SAMPLES = 0.4
#: a torque rail holds at least this many samples, and this share of them, and this many
#: times as many as lie within a noise level below it (:func:`at_rails`)
RAIL_MIN_SAMPLES = 10
RAIL_MIN_SHARE = 0.002
RAIL_PILE = 2.0


def outside_structure(sig: Signals, settings: LoopSettings, first, run):
    """The loop again on the samples outside a band of deflection that holds structure
    the library cannot describe (a hard stop, a clipping sensor), or ``None``.

    ``first`` is the loop's result on every sample, ``run(sig, settings, keep)`` the loop
    on the samples ``keep`` (:func:`springcad.fit.loop.run_loop`'s own pass).

    Fitted on every sample, such a structure pulls the stiffness and hides the
    library effects beside it (a crossover under a hard stop). When the final
    residual's structure sits mostly at large deflection (see
    :mod:`springcad.fit.localise`), the band beyond the localised cut is left
    out of the fit: its onset on each side is where a hinge fitted to the
    residual engages (:func:`springcad.fit.localise.structure_onset`), and the
    loop runs again outside it. What is left is still judged on every sample,
    so the structure stays flagged and localised.
    """
    loc = first.localisation
    if not first.unexplained or first.no_spring or not loc or not loc["findings"]:
        return None
    top = loc["findings"][0]
    idx = first.final.inliers(np.arange(sig.n))
    model, x = first.final.model, first.final.x
    if top["kind"] == "deflection_shape" and top["share"] >= REGION_SHARE:
        # a shape spread over the range may be a term shaped at large deflection (a cubic)
        # fitted over a structure there, which spreads it: localised again without that term
        model, x, top = _without_large_shapes(first, sig, idx) or (model, x, top)
    theta = sig.theta_smooth
    if top["share"] < REGION_SHARE:
        return None
    if top["kind"] == "large_deflection":
        r = model.residual(x, sig, idx)
        tau = first.structure["noise_correlation_samples"]
        lo, hi = structure_onset(r, idx, sig, first.noise_Nm, tau)
        if not onset_is_kink(r, idx, sig, first.noise_Nm, tau, (lo, hi),
                             first.settings.excess_ratio):
            # a stiffness growing smoothly from zero acts inside any band too: no band is
            # free of it, and a fit inside one reads its curvature as other effects
            return None
        keep = (theta > lo) & (theta < hi)
        sides = [f"deflection beyond {hi:.4g} rad" if np.isfinite(hi) else None,
                 f"deflection below {lo:.4g} rad" if np.isfinite(lo) else None]
        bounds = {"low_rad": None if not np.isfinite(lo) else float(lo),
                  "high_rad": None if not np.isfinite(hi) else float(hi)}
    elif top["kind"] == "near_zero" and _large_shapes(model, x):
        # a term shaped at large deflection (a cubic) beside structure near zero that the
        # crossover does not describe (a smooth take-up) bends the line to patch it: the
        # model is fitted where the structure is not, the crossover read from the lines'
        # offsets on either side
        cut = float(top["within_rad"])
        keep = np.abs(theta) > cut
        sides = [f"|deflection| below {cut:.4g} rad"]
        bounds = {"low_rad": -cut, "high_rad": cut, "inside": True}
    else:
        return None
    if keep.mean() < 1.0 - REGION_MAX_SAMPLES or keep.all():
        return None
    out = run(sig, settings, keep)
    if out.no_spring:
        return None
    region = {"left_out": " and ".join(x for x in sides if x), **bounds,
              "samples_left_out": int((~keep).sum()),
              "fraction_left_out": float((~keep).mean()),
              "reason": (f"fitted on every sample, the residual held structure the effect "
                         f"library cannot describe, {top['text'][len('a shape in deflection '):]} "
                         f"({100 * top['share']:.0f} % of it): the model is fitted where that "
                         "structure is not, and the structure is judged on every sample"),
              "first_pass_model": first.final.label}
    return dataclasses.replace(out, region=region)


def at_rails(torque: np.ndarray) -> np.ndarray:
    """Per-sample flag: the torque sits on a rail of its sensor (an ADC or amplifier that
    saturates), where it reads the rail's value whatever the spring's torque beyond it.

    A saturated channel repeats its extreme value exactly, sample after sample: a rail
    is the record's largest (or smallest) torque held by at least ``RAIL_MIN_SHARE`` of
    the samples, and by at least ``RAIL_PILE`` times as many as lie within one noise
    level below it. Noise on an unclipped signal never repeats a float; a quantised one
    repeats its top level only as the tail of the levels below it (fewer there than
    below), while at a rail every sample the noise or the load would carry beyond piles
    up on it."""
    n = torque.size
    out = np.zeros(n, dtype=bool)
    noise = noise_std(torque)
    for sign in (1.0, -1.0):
        edge = float(np.max(sign * torque))
        on = sign * torque == edge
        below = np.count_nonzero((sign * torque < edge) & (sign * torque >= edge - noise))
        if on.sum() >= max(RAIL_MIN_SAMPLES, RAIL_MIN_SHARE * n) and on.sum() >= RAIL_PILE * below:
            out |= on
    return out


def saturated(sig: Signals, settings: LoopSettings, run):
    """The loop on the samples off the torque sensor's rails (:func:`at_rails`), or ``None``
    when the torque never saturates.

    At a rail the measured torque is no longer the spring's: fitted there, a clipped
    top reads as a softening spring or a lost crossover, and the stiffness follows it.
    The model is fitted on the other samples and judged on every sample, so the clipping
    stays flagged and localised; ``LoopResult.region`` says what was left out."""
    rails = at_rails(sig.torque)
    if not rails.any() or rails.mean() > REGION_MAX_SAMPLES:
        return None
    out = run(sig, settings, ~rails)
    if out.no_spring:
        return None
    levels = sorted({float(v) for v in np.unique(sig.torque[rails])})
    region = {"left_out": "torque at the sensor's rails ("
                          + ", ".join(f"{v:.6g} N·m" for v in levels) + ")",
              "low_rad": None, "high_rad": None, "torque_rails_Nm": levels,
              "samples_left_out": int(rails.sum()),
              "fraction_left_out": float(rails.mean()),
              "reason": ("the torque repeats its extreme value exactly on "
                         f"{100 * rails.mean():.1f} % of the samples: the sensor saturates "
                         "there and reads its rail, not the spring's torque; the model is "
                         "fitted on the other samples, and the record is judged on every one"),
              "first_pass_model": None}
    return dataclasses.replace(out, region=region)


def _large_shapes(model, x: np.ndarray) -> list[str]:
    """The model's terms shaped at large deflection (a cubic): acting beyond some |θ|."""
    return [e.name for e in model.effects
            if (band := e.acts_within(x[model.slice_of(e.name)], model.scales)) is not None
            and np.isinf(band[1])]


def _without_large_shapes(first, sig: Signals, idx: np.ndarray):
    """The first pass's model without its terms shaped at large deflection (refitted) and
    the top finding of its residual's localisation, or ``None`` without such terms."""
    model, x = first.final.model, first.final.x
    names = _large_shapes(model, x)
    if not names:
        return None
    inner = model
    for name in names:
        inner = inner.without(name)
    x_in = inner.transfer(model, x)
    r = inner.residual(x_in, sig, idx)
    f_scale = 3.0 * max(1.4826 * float(np.median(np.abs(r - np.median(r)))), 1e-12)
    x_in = inner.fit(sig, idx, x_in, f_scale, max_nfev=200)
    r = inner.residual(x_in, sig, idx)
    x1, x0 = x_in.copy(), x_in.copy()
    x1[0], x0[0] = 1.0, 0.0
    shape = inner.predict(x1, sig, idx) - inner.predict(x0, sig, idx)
    loc = localise(r, idx, sig, first.noise_Nm, first.structure["noise_correlation_samples"],
                   shape, p_level=first.settings.structure_p)
    if not loc["findings"]:
        return None
    return inner, x_in, loc["findings"][0]
