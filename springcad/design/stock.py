"""The disk thickness, when the user leaves it to springcad: the thinnest stock plate.

A spring's thickness z sets its stiffness per unit of flexure planform (K grows with z at
a fixed planform) and not its stress at a given deflection, so a thicker disk lets the
search use longer, more compliant flexures at a lower stress: the duty or the yield margin
that a thin disk cannot meet, a thick one can. When ``springs.<name>.thickness_mm`` is not
given, :func:`design_spring` searches the plate thicknesses of
``springcad/data/plate_stock.toml`` (up to ``max_thickness_mm``) for the thinnest one at
which the design search (:func:`springcad.design.search.design_spring`) finds a spring:
the lightest disk the envelope allows, cut from plate a stockist holds.

The search bisects the sorted list with the design search's feasibility probe
(:func:`springcad.design.search.probe_thickness`), which also says when a plate is too thick
(its minimum webs hold a low stiffness above the target): the chosen value designs, and the
next thinner one was probed and does not. Units: mm.
"""

from __future__ import annotations

import functools
import math
import re
import tomllib
from dataclasses import replace as _replace

from springcad.config import HardwareSpec, ManufacturingSpec, MaterialSpec, SpringSpec
from springcad.data import data_path
from springcad.design import duty, search
from springcad.design.shortfalls import soft_shortfalls
from springcad.design.sizing import energy_bound
from springcad.design.spring import SpringDesign
from springcad.errors import DesignError
from springcad.progress import report
from springcad.units import J_PER_NMM

STOCK_FILE = "plate_stock.toml"
#: thicker stock plates tried when the thinnest that designs has a soft shortfall (a
#: warning that stops the release, e.g. the driving tooth tip within the profile
#: tolerances of the ball): its layout changes with the thickness, so a thicker plate's
#: may avoid it (default at 20 deg: 35 mm has one, 40 mm not)
CLEAN_SCAN = 2
#: the share of the energy bound (:func:`springcad.design.sizing.energy_bound`: sigma^2/(6E)
#: of the annulus between the smallest contact radius and the largest root radius, at the
#: allowed peak) that the stock plate the search chooses needs: the first guess of the stock
#: search (:func:`_first_guess`) is the thinnest plate whose bound x this share holds the
#: spring's energy K theta^2 / 2. Measured (2026-11-27) on the default and the 26 springs
#: of held-out seed 2614's specs with thickness_mm removed that design: the chosen plate is
#: 2.0-22 x the bound's thickness, median 3.9, the default 3.5 (12 mm, its first guess at
#: 0.3). The guess only orders the probes (:func:`_thinnest`): replayed on those 27 springs
#: with a probe that designs costing 0.15-2 s and one refused 2-3 s, it saves 25-35 % of
#: the bisection's probe time at any share from 0.15 to 0.35
BOUND_SHARE = 0.3


@functools.cache
def plate_thicknesses_mm() -> tuple[float, ...]:
    """The stock plate thicknesses springcad chooses from, ascending (mm)."""
    with open(data_path(STOCK_FILE), "rb") as fh:
        return tuple(sorted(float(t) for t in tomllib.load(fh)["thickness_mm"]))


def _sizing_material(material: MaterialSpec) -> MaterialSpec:
    """The material whose yield margin and duty the thickness is chosen for: the declared
    duty, or springcad's default duty when the job declares none (as
    :func:`springcad.design.search.design_spring` sizes a fixed-thickness spring)."""
    if material.duty.declared:
        return material
    return duty.sized_for(material)


def _ceiling_mm(spec: SpringSpec) -> float:
    """The thickest plate the spec allows (mm): its ``max_thickness_mm``, else no bound."""
    return spec.max_thickness_mm if spec.max_thickness_mm is not None else math.inf


def _allowed_mm(spec: SpringSpec) -> list[float]:
    """The stock plates up to the spec's bound, ascending (mm)."""
    return [t for t in plate_thicknesses_mm() if t <= _ceiling_mm(spec) + 1e-9]


def _thinnest(stock: list[float], designs, start: int | None = None
              ) -> tuple[float | None, float | None]:
    """(the thinnest of ``stock`` that designs, the next thinner value probed and refused or
    None); (None, None) when none does.

    ``designs(t)`` gives (whether thickness t designs, whether it is refused as too thick).
    A spring's feasibility need not be monotone in its thickness: a thin plate fails the
    stress or duty, a thick one can fail because its minimum webs hold a low stiffness above
    the target. So the stock list is read as [too thin ..., designs ..., too thick ...]: the
    thickest plate is probed first (it designs in the usual case), a plate refused as too
    thick moves the search thinner, one refused otherwise moves it thicker, until a plate
    designs; then the thinnest that does is bisected below it.

    ``start``: the index of a first guess (:func:`_first_guess`). It is probed first; when it
    designs, the plates below it are probed one by one down to the first that does not (a
    plate that designs costs one layout, the one refused near the boundary all the probe's
    layouts and stress passes: a bisection that lands below the boundary twice pays twice);
    when it does not, the search above runs as without a guess, on the plates above it.
    Read as that list, the answer is the same with or without a guess.
    """
    if start is not None and 0 <= start < len(stock):
        ok, too_thick = designs(stock[start])
        if ok:
            hi = start
            while hi > 0 and designs(stock[hi - 1])[0]:
                hi -= 1
            return stock[hi], (stock[hi - 1] if hi > 0 else None)
        if too_thick:  # the plates below
            return _thinnest(stock[:start], designs)
        t, thinner = _thinnest(stock[start + 1:], designs)
        return t, (stock[start] if t is not None and thinner is None else thinner)
    lo, hi, found = -1, len(stock), None  # stock[lo] too thin, stock[hi] too thick
    mid = len(stock) - 1
    while hi - lo > 1:
        ok, too_thick = designs(stock[mid])
        if ok:
            found = mid
            break
        lo, hi = (lo, mid) if too_thick else (mid, hi)
        mid = (lo + hi) // 2
    if found is None:
        return None, None
    hi = found  # stock[lo] refused as too thin (or none below), stock[hi] designs
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if designs(stock[mid])[0] else (mid, hi)
    return stock[hi], (stock[lo] if lo >= 0 else None)


def _first_guess(stock: list[float], spec: SpringSpec, material: MaterialSpec,
                 manufacturing: ManufacturingSpec, hardware: HardwareSpec,
                 max_root_radius_mm: float) -> int:
    """The index in ``stock`` of the thinnest plate whose energy bound at the allowed peak,
    x :data:`BOUND_SHARE`, holds the spring's energy K theta^2 / 2 (the last plate when
    none does): where the stock search starts (:func:`_thinnest`)."""
    theta = spec.max_deflection_rad
    sigma = min(material.design_stress_MPa, material.material.yield_strength_MPa
                / duty.required_margin(material, theta))
    need_J = 0.5 * spec.target_stiffness_Nmm_per_rad * theta ** 2 * J_PER_NMM
    for i, t in enumerate(stock):
        _, _, bound_J = energy_bound(spec, t, sigma, material.material.youngs_modulus_MPa,
                                     manufacturing, hardware, max_root_radius_mm)
        if BOUND_SHARE * bound_J >= need_J:
            return i
    return len(stock) - 1


def choose_thickness_mm(spec: SpringSpec, material: MaterialSpec,
                        manufacturing: ManufacturingSpec, hardware: HardwareSpec,
                        max_root_radius_mm: float = math.inf
                        ) -> tuple[float | None, float | None, str]:
    """The thinnest stock thickness up to ``spec.max_thickness_mm`` at which ``spec``
    designs, for its duty (springcad's default duty when the job declares none), else for
    the yield margin alone, by bisection (:func:`_thinnest`).

    Returns:
        (thickness, the next thinner stock value probed and refused or None, what the
        thickness was sized for); when no plate designs, (None, the plate nearest to
        designing for the yield margin (:func:`_nearest_plate`) or None, "").
    """
    stock = _allowed_mm(spec)
    report(f"spring {spec.name}: choosing the stock plate (bisection over {len(stock)} "
           f"thicknesses up to {stock[-1]:g} mm)" if stock else f"spring {spec.name}: no stock plate")
    sized = _sizing_material(material)
    tries = [(sized, "its duty" if sized is material else "springcad's default duty")]
    if sized is not material:
        tries.append((material, "the yield margin"))
    outcomes: dict[float, tuple[bool, bool]] = {}
    for mat, what in tries:
        probe = _prober(spec, mat, manufacturing, hardware, max_root_radius_mm)
        outcomes.clear()

        def designs(t: float, probe=probe) -> tuple[bool, bool]:
            outcomes[t] = probe(t)
            return outcomes[t]

        t, thinner = _thinnest(stock, designs,
                               _first_guess(stock, spec, mat, manufacturing, hardware,
                                            max_root_radius_mm) if stock else None)
        if t is None:
            continue
        return t, thinner, what
    return None, _nearest_plate(stock, outcomes), ""


def _nearest_plate(stock: list[float], outcomes: dict[float, tuple[bool, bool]]
                   ) -> float | None:
    """The plate of ``stock`` nearest to designing, from the probes' ``outcomes`` (plate ->
    (designs, too thick)) when none designs: the thickest refused as too thin, else (every
    plate probed held stiff by its webs) the thinnest; None without plates. A refusal's
    changes are searched there: at the thickest plate (the stock bound), a small soft
    spring's webs hold it hundreds of times too stiff and no change of one key helps
    (held-out B 9041 009, R_o 12 mm at 15 N*m/rad: refused at the 100 mm plate)."""
    thin = [t for t, (_, too_thick) in outcomes.items() if not too_thick]
    if thin:
        return max(thin)
    return stock[0] if stock else None


def _prober(spec, material, manufacturing, hardware, max_root_radius_mm):
    """``designs(t)``: (whether the design search's probe designs ``spec`` at thickness t,
    whether it refuses it as too thick)."""
    def designs(t: float) -> tuple[bool, bool]:
        d, too_thick = search.probe_thickness(_replace(spec, thickness_mm=t), material,
                                              manufacturing, hardware, max_root_radius_mm)
        return d is not None, too_thick
    return designs


def design_spring(spec: SpringSpec, material: MaterialSpec, manufacturing: ManufacturingSpec,
                  hardware: HardwareSpec, explain: bool = True,
                  max_root_radius_mm: float = math.inf) -> SpringDesign:
    """:func:`springcad.design.search.design_spring`, with the thickness chosen from stock
    plate when the spec leaves it free (the design's ``spec`` then holds the choice and
    ``design_choice`` says why).

    Raises:
        DesignError: no stock thickness up to ``max_thickness_mm`` designs: the refusal
            names the ``max_thickness_mm`` that would (a thicker stock value that designs),
            then the design search's own refusal at the thickest allowed.
    """
    if spec.thickness_mm is not None:
        return search.design_spring(spec, material, manufacturing, hardware, explain=explain,
                                    max_root_radius_mm=max_root_radius_mm)
    with search.kept_layouts():  # the chosen plate's probe and its design share layouts
        return _design_on_stock(spec, material, manufacturing, hardware, explain,
                                max_root_radius_mm)


def _design_on_stock(spec, material, manufacturing, hardware, explain, max_root_radius_mm):
    """:func:`design_spring` with the thickness left free (mm)."""
    t, nearest, what = choose_thickness_mm(spec, material, manufacturing, hardware,
                                           max_root_radius_mm)
    if t is None:  # the full search (more layouts than the probe) at the nearest plate
        return _thickest(spec, material, manufacturing, hardware, explain, max_root_radius_mm,
                         nearest)
    thinner = nearest
    d = search.design_spring(_replace(spec, thickness_mm=t), material, manufacturing,
                             hardware, explain=explain, max_root_radius_mm=max_root_radius_mm)
    why = (f"thickness {t:g} mm chosen: the thinnest stock plate that carries {what}"
           + (f" (at {thinner:g} mm the search's probe finds no layout that does)"
              if thinner is not None else " (the thinnest in the stock list)"))
    short = soft_shortfalls(d)
    if short:  # a thicker plate whose layout avoids it, if one is near
        for u in [v for v in _allowed_mm(spec) if v > t][:CLEAN_SCAN]:
            try:
                du = search.design_spring(_replace(spec, thickness_mm=u), material,
                                          manufacturing, hardware, explain=False,
                                          max_root_radius_mm=max_root_radius_mm)
            except DesignError:
                continue
            if not soft_shortfalls(du):
                d = du
                why = (f"thickness {u:g} mm chosen: the thinnest stock plate that carries "
                       f"{what} without a soft shortfall ({t:g} mm carries it with one: "
                       f"{short[0].split(':')[0]})")
                break
    return _replace(d, design_choice=f"{why}; {d.design_choice}",
                    thicker_plates_mm=tuple(u for u in _allowed_mm(spec) if u > d.thickness_mm))


def _thickest(spec, material, manufacturing, hardware, explain, max_root_radius_mm,
              nearest_mm: float | None = None) -> SpringDesign:
    """No stock thickness up to the bound passed the probe: the full search (more layouts
    than the probe) at the plate nearest to designing (``nearest_mm``,
    :func:`_nearest_plate`), then at the thickest allowed; or the refusal naming the
    ``max_thickness_mm`` that would design, and the changes found at the nearest plate.

    Raises:
        DesignError: neither plate designs.
    """
    ceiling, allowed = _ceiling_mm(spec), _allowed_mm(spec)
    thickest = allowed[-1] if allowed else ceiling
    nearest = nearest_mm if nearest_mm is not None else thickest
    refusal = None
    for t in dict.fromkeys((nearest, thickest)):
        try:
            d = search.design_spring(_replace(spec, thickness_mm=t), material, manufacturing,
                                     hardware, explain=explain and t == thickest,
                                     max_root_radius_mm=max_root_radius_mm)
        except DesignError as err:
            refusal = refusal or err
            continue
        why = ("the thickest stock plate allowed" if t == thickest else
               "the stock plate nearest to carrying it (the probe's layouts do not; the full "
               "search's do)")
        return _replace(d, design_choice=f"thickness {t:g} mm chosen: {why}; "
                        f"{d.design_choice}")
    change = ""
    if explain and spec.max_thickness_mm is not None:  # the bound that would design
        above = [t for t in plate_thicknesses_mm() if t > ceiling + 1e-9]
        t, _ = _thinnest(above, _prober(spec, _sizing_material(material), manufacturing,
                                        hardware, max_root_radius_mm))
        if t is not None:
            change = (f"feasible with springs.{spec.name}.max_thickness_mm = {t:g} (now "
                      f"{ceiling:g}; springcad then chooses {t:g} mm plate); or ")
    if explain and nearest != thickest:  # the changes, searched at the nearest plate
        try:
            search.design_spring(_replace(spec, thickness_mm=nearest), material,
                                 manufacturing, hardware, explain=True,
                                 max_root_radius_mm=max_root_radius_mm)
        except DesignError as err:
            refusal = err
    text = str(refusal).split("': ", 1)[-1].removeprefix(
        f"spring '{spec.name}' cannot be made as specified; ")
    where = ""
    if nearest == thickest:
        text = _as_bound(text, spec)
    else:
        where = (" (the plate nearest to carrying it: thinner plates fall short of a rule, "
                 "thicker ones are held too stiff by their minimum webs)")
    raise DesignError(f"spring '{spec.name}' cannot be made as specified; {change}no stock "
                      f"plate up to {thickest:g} mm carries it; at {nearest:g} mm{where} (the "
                      f"changes that follow are found on that plate; with thickness_mm left "
                      f"free springcad then chooses the thinnest plate that carries them): "
                      f"{text}") from refusal


def _as_bound(text: str, spec: SpringSpec) -> str:
    """A refusal found at the thickest plate ``spec.max_thickness_mm`` allows, with its
    thickness changes named as that bound's (``springs.A.thickness_mm = 50 (now 20)`` ->
    ``springs.A.max_thickness_mm = 50 (now 20)``): the spec leaves the thickness free, and a
    config giving both keys is refused. Without a bound the text is kept (the plate list's
    thickest is named as "now")."""
    if spec.max_thickness_mm is None:
        return text
    return re.sub(rf"springs\.{re.escape(spec.name)}\.thickness_mm = ([\d.]+) \(now [\d.]+",
                  rf"springs.{spec.name}.max_thickness_mm = \1 (now {spec.max_thickness_mm:g}",
                  text)
