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
* ``sheet_web``, ``sheet_hole_edge`` (wire-EDM parts cut from sheet stock,
  :data:`~springcad.design.processes.SHEET_STOCK_MAX_MM` or thinner): the wire-EDM web
  and hole-edge rules, and at least the sheet thickness
  (:func:`~springcad.design.processes.sheet_web_mm`);

  these four web rules hold at the worst case the drawing allows, not at nominal: a web
  between two contours less twice the process's contour tolerance, a web from a hole less
  half its hole tolerance, its position zone's radius and the contour tolerance
  (:meth:`~springcad.design.processes.Process.hole_web_loss_mm`; the result's ``loss_mm``);
* ``min_wall`` (turned parts): the wall between a bore or socket and the outer diameter
  of every section at least the process's minimum web (a thinner wall chatters, deforms
  in the chuck or breaks through);
* ``fits`` (every made part, any process): each ISO fit on the part is one its process
  finishes without a second operation (no H7 on a laser-cut hole), and no ± tolerance
  on a hole is tighter than every process of the part holds (no ±0.005 on a laser hole);
* ``internal_profile`` (every made part): each non-round hole or pocket (a D bore, a
  blind D socket: any inside corner a drill or a lathe cannot make) is made by a process
  of the part's chain that makes that kind (through or blind) with an inside-corner
  radius no larger than the feature's; a process that cuts soft steel only (broaching)
  comes before the hardening of a hardened part, and a secondary process that makes it
  is named in the drawing's notes (a blind D socket in a hardened shaft: sinker EDM).

Units: mm.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

from springcad.design.curves import Circle, Loop, Profile
from springcad.design.processes import SHEET_STOCK_MAX_MM, process, sheet_web_mm
from springcad.geometry.edm import (RuleResult, _location, gap_rules, hole_edge_rule,
                                    inside_corner_rule)

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


def _worst_case(result: RuleResult, loss_mm: float, limit_mm: float) -> RuleResult:
    """A web rule measured on the nominal profile against ``limit_mm + loss_mm``, restated
    as the worst case against ``limit_mm``: every value ``loss_mm`` lower (mm)."""
    def less(v):
        return None if v is None else v - loss_mm

    return replace(result, limit_mm=limit_mm, value_mm=less(result.value_mm),
                   searched_to_mm=less(result.searched_to_mm), loss_mm=loss_mm,
                   violations=tuple({**v, "value_mm": v["value_mm"] - loss_mm}
                                    for v in result.violations))


def worst_web_rules(profile, proc, web_mm: float, edge_mm: float,
                    describe=lambda x, y: "") -> tuple[RuleResult, RuleResult]:
    """``min_web`` between facing contours and ``hole_edge`` from every round hole of a
    sheet part that ``proc`` cuts, in the worst case: at least ``web_mm`` and ``edge_mm``
    once the process's contour, hole and position tolerances have taken their share
    (:meth:`~springcad.design.processes.Process.contour_web_loss_mm`,
    :meth:`~springcad.design.processes.Process.hole_web_loss_mm`)."""
    webs_loss, edge_loss = proc.contour_web_loss_mm(), proc.hole_web_loss_mm()
    webs, _slots = gap_rules(profile, web_mm + webs_loss, 0.0, describe)
    edge = hole_edge_rule(profile, edge_mm + edge_loss, describe)
    return _worst_case(webs, webs_loss, web_mm), _worst_case(edge, edge_loss, edge_mm)


def sheet_rules(profile, process_key: str, thickness_mm: float,
                describe=lambda x, y: "") -> list[RuleResult]:
    """Web, hole-edge (both in the worst case) and hole-size rules of a laser-cut or
    milled sheet profile."""
    proc = process(process_key)
    web = proc.min_web(thickness_mm)
    return [*worst_web_rules(profile, proc, web, web, describe),
            min_hole_rule(profile, proc.min_hole_per_thickness * thickness_mm, describe)]


def sheet_stock_rules(profile, thickness_mm: float, manufacturing,
                      describe=lambda x, y: "") -> list[RuleResult]:
    """Webs and hole edges of a wire-EDM part cut from sheet stock (``thickness_mm`` at most
    :data:`~springcad.design.processes.SHEET_STOCK_MAX_MM`) in the worst case: at least the
    sheet thickness and the job's ``[manufacturing]`` web and hole-edge limits
    (``sheet_web``, ``sheet_hole_edge``); none for a thicker plate, which the wire-EDM
    rules alone cover."""
    if thickness_mm > SHEET_STOCK_MAX_MM:
        return []
    web = sheet_web_mm("wire_edm", thickness_mm, manufacturing.min_web_mm)
    edge = sheet_web_mm("wire_edm", thickness_mm, manufacturing.min_hole_edge_mm)
    webs, edges = worst_web_rules(profile, process("wire_edm"), web, edge, describe)
    return [replace(webs, rule="sheet_web"), replace(edges, rule="sheet_hole_edge")]


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
    bad = tuple(_at_origin(f"{feature} {fit}: {names} cannot finish it (they hold "
                           f"{sorted({f for p in procs for f in p.fits}) or 'no fits'})")
                for feature, fit in iso_fits(info).items()
                if not any(p.can_finish(fit) for p in procs))
    # a ± tolerance on the holes tighter than any of the part's processes holds
    holds = min(p.hole_tolerance_mm for p in procs)
    pm = info.fits.get("holes", "").strip()
    if pm.startswith("±") and float(pm[1:]) < holds * (1 - 1e-9):
        bad += (_at_origin(f"holes {pm}: {names} hold ±{holds:g} at best"),)
    return RuleResult("fits", 0.0, None, None, bad)


def _at_origin(feature: str) -> dict:
    """A violation that names a feature, not a place (x, y, r, angle 0)."""
    return {"value_mm": 0.0, "x_mm": 0.0, "y_mm": 0.0, "r_mm": 0.0, "angle_deg": 0.0,
            "feature": feature}


def _loop_key(loop) -> tuple:
    """The loop's segments as rounded numbers (the same hole in two slabs)."""
    return tuple(tuple(round(float(v), 6) for v in seg.sample(1.0).ravel())
                 for seg in loop.segments)


def internal_features(slabs) -> list[tuple]:
    """Every non-round hole or pocket of a part: ``(loop, kind, z0_mm, z1_mm)``.

    ``kind``: ``"through"`` when the run of slabs holding the loop reaches both end faces
    of the part, or opens into a hole of the next slab that contains it, at both ends;
    ``"blind"`` at one end only (a socket); ``"closed"`` at neither. Round holes (one
    circle) are left out: a drill, a reamer or a lathe makes them.
    """
    from matplotlib.path import Path

    order = sorted(slabs, key=lambda sl: sl.z0_mm)
    keys = [{_loop_key(h): h for h in sl.region.holes} for sl in order]

    def opens_into(k: int, loop) -> bool:
        """Slab k is beyond the part, or has a hole that contains ``loop``."""
        if k < 0 or k >= len(order):
            return True
        pts = loop.sample(0.05)
        return any(Path(h.sample(0.05)).contains_points(pts, radius=-1e-6).all()
                   or Path(h.sample(0.05)[::-1]).contains_points(pts, radius=-1e-6).all()
                   for h in order[k].region.holes)

    out, done = [], set()
    for k, found in enumerate(keys):
        for key, loop in found.items():
            if key in done or loop.is_circle:
                continue
            done.add(key)
            last = k
            while last + 1 < len(order) and key in keys[last + 1]:
                last += 1
            low = k == 0 or opens_into(k - 1, loop)
            high = last == len(order) - 1 or opens_into(last + 1, loop)
            kind = "through" if low and high else "blind" if low or high else "closed"
            out.append((loop, kind, order[k].z0_mm, order[last].z1_mm))
    return out


def _stem(proc) -> str:
    """The first word of a process's text without its ending ("broach" of "broached"), as a
    heat-treatment sequence names it ("after broaching")."""
    return re.sub(r"(ed|ing)$", "", proc.text.split()[0].lower())


def _is_hardened(info) -> bool:
    return "HRC" in info.hardness or "harden" in info.heat_treatment.lower()


def internal_profile_rule(info, slabs, min_inside_radius_mm: float | None = None,
                          describe=lambda x, y: "") -> tuple[str, RuleResult]:
    """Each non-round hole or pocket of a made part against the processes of its chain.

    The feature's smallest inside-corner radius (the wire-EDM corner rule on it alone) must
    be at least the radius of the process that makes it (``min_internal_radius_mm``; 0:
    ``min_inside_radius_mm``, the job's wire-EDM rule). The maker is the first process of
    the chain that makes the feature's kind with that radius; a ``before_hardening``
    maker on a hardened part needs a heat-treatment sequence that names it ("after
    broaching"); a maker that is not the main process is named in the notes.

    Returns:
        (check prefix: the maker's key, "edm" for wire EDM, or the main process's when no
        process makes a feature; the result: value the smallest feature radius, limit the
        maker's radius).
    """
    chain = [process(k) for k in (info.process, *info.secondary_processes)]
    names = " / ".join(p.text for p in chain)
    notes = " ".join(info.notes).lower()
    bad, radii, limits, makers = [], [], [], []
    for loop, kind, z0, z1 in internal_features(slabs):
        far = 2.0 + max(math.hypot(*p) for p in loop.sample(0.5))
        corner = inside_corner_rule(Profile(Loop((Circle((0.0, 0.0), far),)), (loop,)), 0.0,
                                    1e-4, describe)
        radius = corner.value_mm if corner.value_mm is not None else math.inf
        x, y = loop.sample(0.5).mean(axis=0)
        where = {**_location(x, y, describe), "value_mm": radius}
        what = (f"{kind} non-round {'hole' if kind == 'through' else 'pocket'} z {z0:g} to "
                f"{z1:g}, inside corners R{radius:.3g}")
        radii.append(radius)

        def limit_of(p):
            return p.min_internal_radius_mm or (min_inside_radius_mm or 0.0)

        able = [p for p in chain if p.makes_internal(kind)]
        maker = next((p for p in able if radius >= limit_of(p) * (1 - 1e-9)), None)
        if kind == "closed":
            bad.append({**where, "feature": f"{what}: closed at both ends, no process makes it"})
        elif not able:
            bad.append({**where, "feature": (
                f"{what}: {names} cannot make it; name sinker EDM"
                + (" (after hardening) or broaching before hardening" if _is_hardened(info)
                   else ", broaching or milling") + " in the process list and on the drawing, "
                "or make it round or through")})
        elif maker is None:
            p = able[0]
            bad.append({**where, "feature": f"{what}: {p.text} needs R{limit_of(p):g} or more"})
        else:
            makers.append(maker)
            limits.append(limit_of(maker))
            if maker.before_hardening and _is_hardened(info) and \
                    _stem(maker) not in info.heat_treatment_sequence.lower():
                bad.append({**where, "feature": (
                    f"{what}: {maker.text} cuts soft steel only; the heat-treatment sequence "
                    f"'{info.heat_treatment_sequence}' does not put it before the hardening")})
            if maker.key != info.process and maker.text.lower() not in notes:
                bad.append({**where, "feature": (
                    f"{what}: made by {maker.text}, which no drawing note names")})
    keys = {("edm" if p.key == "wire_edm" else p.key) for p in makers}
    prefix = keys.pop() if len(keys) == 1 else ("edm" if info.process == "wire_edm"
                                                else info.process)
    return prefix, RuleResult("internal_profile", max(limits) if limits else 0.0,
                              min(radii) if radii else None, None, tuple(bad))
