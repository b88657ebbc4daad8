"""Manufacturability rules of parts cut from sheet by laser or CNC milling, and the
process rules every cut part gets.

Limits come from the part's process (``springcad/data/processes.toml``,
:mod:`springcad.design.processes`); the geometry is measured with the wire-EDM rules'
pair search and hole distances (:mod:`springcad.geometry.edm`):

* ``min_web``: material between any two facing contours, at least
  ``max(process minimum, factor x sheet thickness)`` (a thermal or mechanical sheet
  process distorts or tears a thinner web);
* ``hole_edge``: the same web from every round hole to every other contour;
* ``min_hole``: every round hole at least ``factor x sheet thickness`` across;
* ``min_wall`` (turned parts): the wall between a bore or socket and the outer diameter
  of every section at least the process's minimum web (a thinner wall chatters, deforms
  in the chuck or breaks through);
* ``fits`` (every made part, any process): each ISO fit on the part is one its process
  finishes without a second operation (no H7 on a laser-cut hole).

Units: mm.
"""

from __future__ import annotations

from springcad.design.processes import process
from springcad.geometry.edm import RuleResult, _location, gap_rules, hole_edge_rule

#: fit keys of :attr:`springcad.geometry.base.PartInfo.fits` that name an ISO fit
FIT_FEATURES = ("holes", "bore", "outer")


def min_hole_rule(profile, min_diameter_mm: float, describe) -> RuleResult:
    """Smallest round hole against the process's smallest hole (mm)."""
    holes = [lp.segments[0] for lp in profile.loops[1:] if lp.is_circle]
    if not holes:
        return RuleResult("min_hole", min_diameter_mm, None, None, ())
    viol = tuple({"value_mm": 2 * c.radius, **_location(*c.center, describe)} for c in holes
                 if 2 * c.radius < min_diameter_mm * (1 - 1e-9))
    return RuleResult("min_hole", min_diameter_mm, min(2 * c.radius for c in holes), None, viol)


def sheet_rules(profile, process_key: str, thickness_mm: float,
                describe=lambda x, y: "") -> list[RuleResult]:
    """Web, hole-edge and hole-size rules of a laser-cut or milled sheet profile."""
    proc = process(process_key)
    web = proc.min_web(thickness_mm)
    webs, _slots = gap_rules(profile, web, 0.0, describe)
    return [webs, hole_edge_rule(profile, web, describe),
            min_hole_rule(profile, proc.min_hole_per_thickness * thickness_mm, describe)]


def wall_rule(slabs, process_key: str, describe=lambda x, y: "") -> RuleResult:
    """Thinnest wall (mm) between the outer contour and a bore or socket over every slab of
    a turned part, against the process's minimum web."""
    web = process(process_key).min_web(0.0)
    results = [gap_rules(s.region, web, 0.0, describe)[0] for s in slabs if s.region.holes]
    values = [r.value_mm for r in results if r.value_mm is not None]
    return RuleResult("min_wall", web, min(values) if values else None,
                      2.0 * web if results else None,
                      tuple(v for r in results for v in r.violations))


def iso_fits(info) -> dict[str, str]:
    """The features of a part that carry an ISO fit (not a ± tolerance): {feature: fit}."""
    return {f: info.fits[f] for f in FIT_FEATURES if info.fits.get(f, "").strip()[:1].isalpha()}


def fit_rule(info) -> RuleResult:
    """Every ISO fit of a part is one its process, or one of its secondary processes,
    can finish (``value_mm`` unused)."""
    procs = [process(k) for k in (info.process, *info.secondary_processes)]
    names = " / ".join(p.text for p in procs)
    bad = tuple({"value_mm": 0.0, "x_mm": 0.0, "y_mm": 0.0, "r_mm": 0.0, "angle_deg": 0.0,
                 "feature": f"{feature} {fit}: {names} cannot finish it (they hold "
                            f"{sorted({f for p in procs for f in p.fits}) or 'no fits'})"}
                for feature, fit in iso_fits(info).items()
                if not any(p.can_finish(fit) for p in procs))
    return RuleResult("fits", 0.0, None, None, bad)
