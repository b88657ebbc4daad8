"""The rim spacer of a rim-to-rim joint: its process, pin holes and inner edge.

A thin sheet ring clamped between two rims (paper Fig. 2a), slipped over the rim
dowels (or bolts): its clearance holes must pass the largest pin at its worst position,
the webs from the largest hole to either edge must meet the process's rules, and its
inner edge, however the spacer shifts on its pins, must stay clear of the flexure roots.
Pure design math on the springs' numbers (:mod:`springcad.design.hardware` lays the
spacer into the stack). Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from springcad.design import plans as pl
from springcad.design.catalogue import m6_deviation_mm
from springcad.design.processes import process, sheet_web_mm
from springcad.errors import DesignError

#: radial clearance between the rim spacer / washer and the flexure roots (mm)
ROOT_CLEARANCE_MM = 0.3
#: rim spacer processes, cheapest first: the first whose webs fit is used
RIM_SPACER_PROCESSES = ("laser", "wire_edm")
#: radial margin between the flexure roots and the spacer's nominal inner edge after the
#: spacer has shifted by its play on the pins (mm); at least the spacer's contour
#: tolerance, so that the inner edge at its smallest never passes the roots
ROOT_MARGIN_MM = 0.02


def root_margin_mm(proc) -> float:
    """Margin (mm) between the flexure roots and a spacer's nominal inner edge, after its
    play on the pins, when ``proc`` (a :class:`~springcad.design.processes.Process`) cuts
    it: :data:`ROOT_MARGIN_MM`, or the contour tolerance if that is larger."""
    return max(ROOT_MARGIN_MM, proc.contour_tolerance_mm)


def max_pin_mm(fastener: str, diameter_mm: float) -> float:
    """Largest rim pin a clearance hole must pass (mm): an m6 dowel at its upper
    deviation, a bolt at its nominal size."""
    return diameter_mm + (m6_deviation_mm(diameter_mm)[1] if fastener == "dowel" else 0.0)


@dataclass(frozen=True)
class RimSpacerFit:
    """How a rim spacer fits its rim: process, hole, inner edge and the webs left (mm).

    Attributes:
        process: process key (``springcad/data/processes.toml``).
        hole_diameter_mm: nominal clearance hole for the pins (toleranced +- the
            process's hole tolerance).
        inner_radius_mm: the inner edge.
        inner_web_mm, outer_web_mm: material between the hole and the inner and outer
            edges in the worst case (the hole at its largest and off its true position by
            the position zone's radius, the edge off the drawing by the contour
            tolerance).
        min_web_mm: the process's limit for this sheet.
        root_clearance_mm: inner edge to the flexure roots, before the spacer's play.
        rejected: why each cheaper process was not used.
    """

    process: str
    hole_diameter_mm: float
    inner_radius_mm: float
    inner_web_mm: float
    outer_web_mm: float
    min_web_mm: float
    root_clearance_mm: float
    rejected: tuple[str, ...] = ()


def rim_spacer_rim_mm(hardware, manufacturing) -> float:
    """Thinnest spring rim (R_o - R_r, mm) on which a wire-EDM rim spacer fits its pin holes
    with the rules of :func:`rim_spacer_fit`, the holes on the circle midway in the rim: the
    largest clearance hole, the worst-case web on both sides (the hole-edge rule, and at
    least the sheet, ``hardware.rim_spacer_thickness_mm``:
    :func:`~springcad.design.processes.sheet_web_mm`, plus what the hole's position and
    the edge's contour tolerance take from it), the spacer's play on its pins and
    :func:`root_margin_mm` inside (the design search keeps this rim, so the spacer is not
    refused by the build's web rules)."""
    pin = hardware.fastener_diameter_mm
    pin_max = max_pin_mm(hardware.fastener, pin)
    wire = process("wire_edm")
    hole = wire.clearance_hole(pin_max, wire.position_tolerance_mm)
    r_hole = 0.5 * (hole + wire.hole_tolerance_mm)
    play = r_hole - 0.5 * pin
    web = sheet_web_mm("wire_edm", hardware.rim_spacer_thickness_mm,
                       manufacturing.min_hole_edge_mm)
    web += wire.position_tolerance_mm + wire.contour_tolerance_mm
    return 2.0 * (r_hole + web + play + root_margin_mm(wire))


def rim_spacer_fit(root_radius_mm: float, outer_radius_mm: float, hole_circle_radius_mm: float,
                   pin_diameter_mm: float, pin_max_mm: float, thickness_mm: float,
                   wire_min_web_mm: float) -> RimSpacerFit:
    """Process, clearance hole and inner edge of a rim spacer, webs within the process rules.

    For each process (cheapest first): the hole clears the largest pin at its smallest
    size and worst position, the pin located by the wire-cut rim holes
    (:meth:`~springcad.design.processes.Process.clearance_hole`); the web from the hole to
    either edge in the worst case (the hole at its largest, off its true position by the
    position zone's radius, the edge off the drawing by the contour tolerance:
    :meth:`~springcad.design.processes.Process.hole_web_loss_mm`) is at least the process
    minimum and the sheet thickness (:func:`~springcad.design.processes.sheet_web_mm`;
    wire EDM's minimum: ``wire_min_web_mm``, the job's hole-edge rule); the inner edge sits
    :data:`ROOT_CLEARANCE_MM` outside the flexure roots, or less where the web needs it,
    but never so close that the spacer, shifted by its play on the pins, comes within
    :func:`root_margin_mm` of the roots.

    Returns:
        the fit; its ``inner_web_mm`` and ``outer_web_mm`` are the worst-case webs.

    Raises:
        DesignError: no process fits; the message gives each process's shortfall.
    """
    rejected = []
    for key in RIM_SPACER_PROCESSES:
        proc = process(key)
        hole = proc.clearance_hole(pin_max_mm, process("wire_edm").position_tolerance_mm)
        r_hole = 0.5 * (hole + proc.hole_tolerance_mm)  # largest hole (mm)
        # what position and contour tolerances take from a web beyond the largest hole
        loss = proc.hole_web_loss_mm() - 0.5 * proc.hole_tolerance_mm
        web = sheet_web_mm(key, thickness_mm, wire_min_web_mm if key == "wire_edm" else 0.0)
        play = r_hole - 0.5 * pin_diameter_mm  # radial shift of the spacer on the pins
        outer_web = outer_radius_mm - hole_circle_radius_mm - r_hole - loss
        r_in = min(root_radius_mm + ROOT_CLEARANCE_MM,
                   hole_circle_radius_mm - r_hole - loss - web)
        margin = root_margin_mm(proc)
        lowest = root_radius_mm + play + margin
        tol = (f"Ø{hole:g} +-{proc.hole_tolerance_mm:g} hole at position Ø"
               f"{2 * proc.position_tolerance_mm:g}, contours +-{proc.contour_tolerance_mm:g}")
        if outer_web < web - 1e-9:
            rejected.append(f"{proc.text}: {outer_web:.3f} mm between a {tol} and the outer "
                            f"edge at worst, less than the {web:g} mm web it needs")
        elif r_in < lowest - 1e-9:
            rejected.append(f"{proc.text}: a {web:g} mm web at worst inside a {tol} puts the "
                            f"inner edge {r_in - root_radius_mm:+.4f} mm from the flexure "
                            f"roots; it needs {play + margin:.4f} mm (play on the pins "
                            f"{play:.4f} + margin {margin:g})")
        else:
            return RimSpacerFit(key, hole, r_in, hole_circle_radius_mm - r_hole - loss - r_in,
                                outer_web, web, r_in - root_radius_mm, tuple(rejected))
    raise DesignError("rim spacer: no process can make it. " + "; ".join(rejected)
                      + ". Widen the rim (outer radius), use smaller rim fasteners or a "
                      "thinner spacer (hardware.rim_spacer_thickness_mm).")


def rim_spacer_plan(lower, upper, outer_radius_mm: float, thickness_mm: float, joint: int,
                    centres) -> pl.RimSpacerPlan:
    """The rim spacer of joint ``joint`` between springs ``lower`` and ``upper`` (their
    :class:`~springcad.design.spring.SpringDesign`), ``thickness_mm`` thick, out to
    ``outer_radius_mm``, over pins at ``centres`` (mm): process, holes and inner edge from
    :func:`rim_spacer_fit` (a plain ring when the rims have no holes)."""
    hw = lower.hardware
    root = max(lower.root_radius_mm, upper.root_radius_mm)
    if not centres:
        return pl.RimSpacerPlan(inner_radius_mm=root + ROOT_CLEARANCE_MM,
                                outer_radius_mm=outer_radius_mm, joint=joint)
    pin = hw.fastener_diameter_mm
    pin_max = max_pin_mm(hw.fastener, pin)
    r_hc = min(math.hypot(*c) for c in centres)
    edge = lower.manufacturing.min_hole_edge_mm
    try:
        fit = rim_spacer_fit(root, outer_radius_mm, r_hc, pin, pin_max, thickness_mm, edge)
    except DesignError:
        # no process meets every rule: lay the spacer out for wire EDM as well as the
        # rim allows (inner edge no closer than the roots); the build's wire-EDM rules
        # then refuse it with the webs measured (or the spring's own rim check does),
        # and the design search can still weigh the stack
        # The hole shrinks to what the rim leaves (less clearance for the position
        # errors: a soft sheet spacer yields to a pin, a hardened ring does not) but
        # always slips over the largest pin.
        edm = process("wire_edm")
        tol = edm.hole_tolerance_mm
        edge += edm.position_tolerance_mm + edm.contour_tolerance_mm  # the worst case
        smallest = math.ceil(round((pin_max + tol + 0.01) * 100.0, 6)) / 100.0
        room = math.floor(round((2.0 * (r_hc - root - edge) - tol) * 100.0, 6)) / 100.0
        hole = max(smallest, min(edm.clearance_hole(pin_max, edm.position_tolerance_mm), room))
        r_in = max(root, min(root + ROOT_CLEARANCE_MM, r_hc - 0.5 * (hole + tol) - edge))
        return pl.RimSpacerPlan(inner_radius_mm=r_in, outer_radius_mm=outer_radius_mm,
                                hole_centres_mm=centres, hole_diameter_mm=hole, joint=joint,
                                process="wire_edm")
    return pl.RimSpacerPlan(inner_radius_mm=fit.inner_radius_mm, outer_radius_mm=outer_radius_mm,
                            hole_centres_mm=centres, hole_diameter_mm=fit.hole_diameter_mm,
                            joint=joint, process=fit.process)
