"""Structure outside the library in a band of deflection: fit the library where it is not.

A hard stop or a torque sensor that clips acts beyond some deflection. Fitted
on every sample, such a structure pulls the stiffness and hides the library
effects beside it (a crossover under a hard stop); patched, it invents effects.
:func:`outside_structure` fits the model again outside the band, and the loop
judges what is left on every sample, so the structure stays flagged and
localised. ``LoopResult.region`` (fit.json ``final.fitted_region``) says what
was left out and why.

Units: N·m, rad, s.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from springcad.fit.localise import structure_onset
from springcad.fit.search import LoopSettings
from springcad.fit.signals import Signals


#: a localised structure must carry this share of the final residual's structure for the
#: model to be fitted again without its band of deflection
REGION_SHARE = 0.5
#: and the band left out may hold at most this share of the samples
REGION_MAX_SAMPLES = 0.4


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
    if top["kind"] != "large_deflection" or top["share"] < REGION_SHARE:
        return None
    theta = sig.theta_smooth
    idx = first.final.inliers(np.arange(sig.n))
    r = first.final.model.residual(first.final.x, sig, idx)
    lo, hi = structure_onset(r, idx, sig, first.noise_Nm,
                             first.structure["noise_correlation_samples"])
    keep = (theta > lo) & (theta < hi)
    if keep.mean() < 1.0 - REGION_MAX_SAMPLES or keep.all():
        return None
    out = run(sig, settings, keep)
    if out.no_spring:
        return None
    sides = [f"deflection beyond {hi:.4g} rad" if np.isfinite(hi) else None,
             f"deflection below {lo:.4g} rad" if np.isfinite(lo) else None]
    region = {"left_out": " and ".join(x for x in sides if x),
              "low_rad": None if not np.isfinite(lo) else float(lo),
              "high_rad": None if not np.isfinite(hi) else float(hi),
              "samples_left_out": int((~keep).sum()),
              "fraction_left_out": float((~keep).mean()),
              "reason": (f"fitted on every sample, the residual held structure the effect "
                         f"library cannot describe, {top['text'][len('a shape in deflection '):]} "
                         f"({100 * top['share']:.0f} % of it): the model is fitted where that "
                         "structure is not, and the structure is judged on every sample"),
              "first_pass_model": first.final.label}
    return dataclasses.replace(out, region=region)
