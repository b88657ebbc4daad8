"""Rules a sized layout is checked against before the search accepts it: its exact
contours (a ring or cam crossing itself, a hole cutting the rim, the bore cutting the
teeth), the tooth tip's clearance to the ball, and the yield margin the stress passes
reached. Milliseconds to a few tenths of a second per layout.

Units: mm, MPa.
"""

from __future__ import annotations

import math

from springcad.design.cam import FLEXURE_CLEARANCE_SHORT, TIP_CLEARANCE_SHORT
from springcad.design.planar import find_defect
from springcad.design.spring import SpringDesign


#: sample step of the design-time contour check: the solids' own check
#: (:func:`springcad.geometry.profile.check_loops`) uses the same, so a design that passes
#: here is not refused there (mm)
CONTOUR_STEP_MM = 0.02


def _folds(n_flexures: int) -> dict[str, int]:
    """The N-fold loops of the ring and the cam (:func:`~springcad.design.planar.find_defect`)."""
    return {"flexures": n_flexures, "teeth": n_flexures}


def profile_defect(d: SpringDesign) -> str:
    """Why the ring's or the cam's contours would not make a valid face, or "".

    The solids' check, run on the design's exact profiles, so a layout whose cam or ring
    crosses itself is passed over by the search, not refused after the FEA. The
    flexures and the teeth are searched by their N-fold symmetry (the solids and the
    mesher search every repeat: a second reader of the same rule).
    """
    for part, profile in (("ring", d.ring), ("camshaft", d.cam)):
        if profile is None:
            continue
        defect = find_defect(profile, CONTOUR_STEP_MM, folds=_folds(d.n_flexures))
        if defect is not None:
            x, y = defect.point_mm
            where = f"at ({x:.3f}, {y:.3f}) mm, r = {math.hypot(x, y):.3f} mm"
            if max(defect.loops) >= 2 or (part == "camshaft" and max(defect.loops) >= 1):
                what = ("a rim hole cuts the ring's contour" if part == "ring" else
                        "the camshaft's bore cuts its teeth")
                fix = ("smaller fasteners (hardware.fastener_diameter_mm) or a wider rim"
                       if part == "ring" else "a smaller hardware.shaft_diameter_mm")
                return f"{what} {where}; {fix}"
            verb = "crosses" if defect.kind == "cross" else f"{defect.kind}es"
            return (f"the {part}'s contour {verb} itself {where} (flexures or teeth too wide or "
                    "too curved for their pitch)")
    return ""


def margin_shortfall(d: SpringDesign, required: float) -> list[str]:
    """The yield margin (-) the stress passes left short of ``required`` (a layout whose
    passes ran out), as a shortfall the search tries the other layouts to avoid."""
    if d.yield_margin >= required * (1.0 - 1e-3):
        return []
    return [f"spring '{d.name}': the predicted peak {d.predicted_peak_stress_MPa:.0f} MPa "
            f"leaves a yield margin {d.yield_margin:.3f} < required {required:.3f} after the "
            f"stress passes (N = {d.n_flexures})"]


def soft_shortfalls(d: SpringDesign) -> list[str]:
    """Rules a design may break and still be drawn (a warning stops its release), which the
    search tries other layouts to avoid: the tooth tip too close to the ball, or the tooth too
    close to the driven flexure's neck or edges at full deflection."""
    return [w for w in d.warnings
            if w.startswith(TIP_CLEARANCE_SHORT) or w.startswith(FLEXURE_CLEARANCE_SHORT)]
