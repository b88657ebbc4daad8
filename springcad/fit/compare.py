"""Compare a fitted spring with its design (``design.json`` as a dict).

The design dict is what ``JobDesign.to_dict()`` returns: ``stack.stiffness_Nm_per_rad``
(beam theory), ``stack.target_stiffness_Nm_per_rad``, ``stack.backlash_rad`` with
``nominal``, ``worst_min``/``worst_max``, ``rss_min``/``rss_max`` and
``mc_p01``/``mc_p99`` (whole stack, rad), and per spring
``springs.<name>.stiffness_Nm_per_rad`` and optionally
``springs.<name>.stiffness_fea_Nm_per_rad``. Stiffness in N·m/rad, angles in rad.
"""

from __future__ import annotations

from springcad.errors import ConfigError, SpringcadError
from springcad.fit.models import stiffness_error_pct
from springcad.options import spell

#: (name, low key, high key) of the backlash ranges in ``stack.backlash_rad``
BACKLASH_RANGES = (
    ("worst_case", "worst_min", "worst_max"),
    ("rss", "rss_min", "rss_max"),
    ("monte_carlo_p01_p99", "mc_p01", "mc_p99"),
)


def _get(d: dict, path: str, required: bool = True):
    node = d
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            if required:
                raise ConfigError(path, None, "missing from the design result",
                                  "is the config a springcad job with a stack?")
            return None
        node = node[part]
    return node


def stack_fea_stiffness(design: dict) -> float | None:
    """FEA stiffness of the stack (N·m/rad) when the design carries one.

    ``stack.stiffness_fea_Nm_per_rad`` if present; otherwise, when every spring
    has ``stiffness_fea_Nm_per_rad``: the series sum over ``stack.sequence``
    (a list of spring names) if given, else, for a stack of one spring type,
    the beam stack stiffness scaled by that spring's FEA/beam ratio.
    """
    direct = _get(design, "stack.stiffness_fea_Nm_per_rad", required=False)
    if direct is not None:
        return float(direct)
    springs = design.get("springs") or {}
    if not springs or any("stiffness_fea_Nm_per_rad" not in s for s in springs.values()):
        return None
    sequence = _get(design, "stack.sequence", required=False)
    if isinstance(sequence, list) and all(name in springs for name in sequence):
        return 1.0 / sum(1.0 / float(springs[name]["stiffness_fea_Nm_per_rad"]) for name in sequence)
    if len(springs) == 1:
        (only,) = springs.values()
        ratio = float(only["stiffness_fea_Nm_per_rad"]) / float(only["stiffness_Nm_per_rad"])
        return float(_get(design, "stack.stiffness_Nm_per_rad")) * ratio
    return None


def compare_with_design(design: dict, stiffness_Nm_per_rad: float, backlash_rad: float,
                        method: str = "deadband model (as the paper)") -> dict:
    """Fitted stiffness and backlash against the design's predictions and ranges.

    Args:
        design: the design dict (see module docstring).
        stiffness_Nm_per_rad: fitted stack stiffness.
        backlash_rad: fitted stack backlash b.
        method: how the fitted values were obtained (for the report).

    Returns:
        ``{"measured", "stiffness", "backlash"}`` with percent errors against
        target, beam theory and FEA (when present), and for each backlash range
        its bounds and whether the measurement lies inside.

    Raises:
        ConfigError: the design dict lacks the stack stiffness, target or backlash.
    """
    target = float(_get(design, "stack.target_stiffness_Nm_per_rad"))
    beam = float(_get(design, "stack.stiffness_Nm_per_rad"))
    fea = stack_fea_stiffness(design)
    stiffness = {
        "target_stiffness_Nm_per_rad": target,
        "error_vs_target_pct": stiffness_error_pct(stiffness_Nm_per_rad, target),
        "beam_Nm_per_rad": beam,
        "error_vs_beam_pct": stiffness_error_pct(stiffness_Nm_per_rad, beam),
        "fea_Nm_per_rad": fea,
        "error_vs_fea_pct": None if fea is None else stiffness_error_pct(stiffness_Nm_per_rad, fea),
    }
    bl = _get(design, "stack.backlash_rad")
    ranges = {}
    for name, lo_key, hi_key in BACKLASH_RANGES:
        if lo_key in bl and hi_key in bl:
            lo, hi = float(bl[lo_key]), float(bl[hi_key])
            ranges[name] = {"min_rad": lo, "max_rad": hi, "inside": bool(lo <= backlash_rad <= hi)}
    nominal = float(bl["nominal"]) if "nominal" in bl else None
    return {
        "measured": {"stiffness_Nm_per_rad": stiffness_Nm_per_rad, "backlash_rad": backlash_rad,
                     "method": method},
        "stiffness": stiffness,
        "backlash": {"nominal_rad": nominal, "ranges": ranges,
                     "statement": _backlash_statement(backlash_rad, nominal, ranges)},
    }


def _backlash_statement(measured: float, nominal: float | None, ranges: dict) -> str:
    parts = [f"measured backlash {measured:.4g} rad"]
    if nominal is not None:
        parts.append(f"(nominal {nominal:.4g} rad)")
    if not ranges:
        return " ".join(parts) + "; the design gives no tolerance range to compare with"
    verdicts = []
    for name, r in ranges.items():
        where = "inside" if r["inside"] else ("above" if measured > r["max_rad"] else "below")
        verdicts.append(f"{where} the {name.replace('_', ' ')} range "
                        f"[{r['min_rad']:.4g}, {r['max_rad']:.4g}] rad")
    return " ".join(parts) + " is " + "; ".join(verdicts)


def design_from_config(path) -> dict:
    """Design a job config with the design core and return its design dict.

    The design core (``springcad.config``, ``springcad.design.job``) is imported
    here, so fitting works without it when no config is given.

    Raises:
        SpringcadError: the design core is not available in this installation.
        ConfigError: the config is invalid (raised by the design core).
    """
    try:
        from springcad.config import load_job
        from springcad.design.job import design_job
    except ModuleNotFoundError as err:
        if err.name not in ("springcad.config", "springcad.design.job", "springcad.design"):
            raise
        raise SpringcadError(
            f"{spell('design')} needs the design core ({err.name}), which this installation "
            f"does not have; use {spell('target_stiffness_Nm_per_rad')} to compare with a "
            "target instead") from None
    return design_job(load_job(path)).to_dict()
