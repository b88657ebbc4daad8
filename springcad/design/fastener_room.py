"""Room for the rim fasteners of a stack: a pure axial / 2D check at design time.

Every rim fastener is a pile of coaxial cylinders about its hole centre (a dowel: one;
a bolt: the ISO 4762 head, the shank, the ISO 4032 nut as the circle through its
corners), every other part an annulus (or disc) along the axis with its axial holes,
a flexure ring the disc of its outer radius with its rim holes. A fastener piece and a
part clash when they share z (by more than :data:`TOL_MM`) and the piece's circle
reaches the part's material, unless the circle lies inside one of the part's holes;
two fasteners clash when their circles overlap where they share z. This is what the
solids' interference check (:mod:`springcad.geometry.interference`) measures on the
same sizes, the circles and discs erring on the safe side (a hex nut inside its
corner circle, a flexure ring as a full disc), so a layout that passes here passes
there. Microseconds per pair. Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from springcad.config.schema import BOLT_DIAMETERS_MM
from springcad.design import plans as pl
from springcad.design.catalogue import bolt_set, rim_dowel_length
from springcad.design.ring import shared_hole_angles_rad
from springcad.errors import DesignError, RemedyError, change_text

#: overlaps (axial, radial) up to this are contact, not a clash (mm): the solids' check
#: tolerance (springcad.geometry.interference.CONTACT_TOL_MM)
TOL_MM = 0.002


@dataclass(frozen=True)
class Piece:
    """One coaxial cylinder of a fastener (mm): ``what`` names it (head, shank, nut)."""

    owner: str
    what: str
    centre: tuple[float, float]
    radius_mm: float
    z0_mm: float
    z1_mm: float


def fastener_pieces(comp) -> list[Piece]:
    """The cylinders of every fastener of a fastener component (mm).

    Bolts as :class:`springcad.geometry.fasteners.RimScrew` places them: the head below
    the first rim, the shank the shortest ISO length that passes the grip and the nut,
    the nut on the far rim face.
    """
    plan: pl.FastenerPlan = comp.plan
    out = []
    for k, c in enumerate(plan.hole_centres_mm):
        name = f"{comp.name}_{k + 1}"
        z0, r = comp.z_mm, 0.5 * plan.diameter_mm
        if plan.type == "dowel":
            out.append(Piece(name, "pin", c, r, z0, z0 + comp.length_mm))
            continue
        b = bolt_set(plan.diameter_mm)
        z1 = z0 + comp.length_mm  # the far rim face
        out += [Piece(name, "head", c, 0.5 * b.head_diameter_mm, z0 - b.head_height_mm, z0),
                Piece(name, "shank", c, r, z0, z0 + b.screw_length_mm(comp.length_mm)),
                Piece(name, "nut", c, 0.5 * b.nut_across_corners_mm, z1, z1 + b.nut_height_mm)]
    return out


def _annulus(comp, springs):
    """(inner radius, outer radius, hole centres, hole radius) of a part's material (mm),
    None for fasteners."""
    p = comp.plan
    if isinstance(p, pl.FlexureRingPlan):
        s = springs[p.spring_index]
        return 0.0, p.outer_radius_mm, s.hole_centres_mm, 0.5 * s.hole_diameter_mm
    if isinstance(p, pl.AnnulusPlan):
        return p.inner_radius_mm, p.outer_radius_mm, p.hole_centres_mm, 0.5 * p.hole_diameter_mm
    if isinstance(p, pl.CamshaftPlan):
        return 0.0, max(p.tip_radius_mm, p.hub_radius_mm), (), 0.0
    if isinstance(p, pl.AlignmentShaftPlan | pl.DShaftPlan):
        return 0.0, 0.5 * p.diameter_mm, (), 0.0
    if isinstance(p, pl.HubSocketPlan):
        return 0.0, p.outer_radius_mm, (), 0.0
    return None


def _shared_z(a0, a1, b0, b1) -> float:
    return min(a1, b1) - max(a0, b0)


def _reaches(piece: Piece, r_in, r_out, holes, r_hole) -> bool:
    """The piece's circle reaches the annulus's material (not inside one of its holes)."""
    r = math.hypot(*piece.centre)
    if r + piece.radius_mm <= r_in + TOL_MM or r - piece.radius_mm >= r_out - TOL_MM:
        return False
    return not any(math.dist(piece.centre, h) + piece.radius_mm <= r_hole + TOL_MM
                   for h in holes)


@dataclass(frozen=True)
class Clash:
    """A fastener piece in another part's material (mm)."""

    piece: Piece
    other: str
    axial_mm: float
    fastener: bool = False
    """``other`` is a piece of another fastener (two heads or nuts side by side)."""

    def text(self) -> str:
        p = self.piece
        return (f"{p.owner} {p.what} (Ø{2 * p.radius_mm:.3g} mm, z {p.z0_mm:.3g} to "
                f"{p.z1_mm:.3g}) in {self.other} by {self.axial_mm:.3g} mm along the axis")


def fastener_clashes(layout, springs) -> list[Clash]:
    """Every fastener piece of a stack layout that reaches another part (see the module).

    Args:
        layout: the :class:`~springcad.design.hardware.StackLayout`.
        springs: its springs, input side first.
    """
    comps = layout.components
    pieces = [p for c in comps if isinstance(c.plan, pl.FastenerPlan) for p in fastener_pieces(c)]
    out = []
    for p in pieces:
        for c in comps:
            ann = _annulus(c, springs)
            if ann is None:
                continue
            shared = _shared_z(p.z0_mm, p.z1_mm, c.z_mm, c.z_mm + c.length_mm)
            if shared > TOL_MM and _reaches(p, *ann):
                out.append(Clash(p, c.name, shared))
    for i, p in enumerate(pieces):
        for q in pieces[i + 1:]:
            if p.owner == q.owner:
                continue
            shared = _shared_z(p.z0_mm, p.z1_mm, q.z0_mm, q.z1_mm)
            reach = p.radius_mm + q.radius_mm - TOL_MM
            if shared > TOL_MM and math.dist(p.centre, q.centre) < reach:
                out.append(Clash(p, f"{q.owner} {q.what}", shared, fastener=True))
    return out


def _side_by_side_fit(radius_mm: float, hole_circle_mm: float, n_flexures,
                      count: int) -> bool:
    """Whether ``count`` fasteners whose widest piece has radius ``radius_mm``, on the hole
    circle at the angles the stack gives them (:func:`~springcad.design.ring.shared_hole_angles_rad`),
    keep their pieces apart (mm)."""
    a = shared_hole_angles_rad(n_flexures, count)
    pts = [(hole_circle_mm * math.cos(t), hole_circle_mm * math.sin(t)) for t in a]
    return all(math.dist(p, q) >= 2.0 * radius_mm - TOL_MM
               for i, p in enumerate(pts) for q in pts[i + 1:])


def _side_by_side_remedies(plan: pl.FastenerPlan, springs) -> list[tuple[dict, str]]:
    """Changes under which the fasteners' heads and nuts no longer overlap each other: the
    most fasteners that keep them apart on the same hole circle, the largest smaller ISO
    screw whose head and nut do at this count, and flush dowels (each is then checked with
    the whole job's design search)."""
    count, d = len(plan.hole_centres_mm), plan.diameter_mm
    r_hc = math.hypot(*plan.hole_centres_mm[0])
    ns = [s.n_flexures for s in springs]

    def widest_mm(diameter_mm: float) -> float:
        b = bolt_set(diameter_mm)
        return 0.5 * max(b.head_diameter_mm, b.nut_across_corners_mm)

    out = []
    fewer = [m for m in range(count - 1, 1, -1) if _side_by_side_fit(widest_mm(d), r_hc, ns, m)]
    if fewer:
        key = "hardware.fastener_count"
        out.append(({key: fewer[0]}, change_text(key, fewer[0], count,
                                                 "heads and nuts apart on the hole circle")))
    smaller = [v for v in sorted(BOLT_DIAMETERS_MM, reverse=True) if v < d
               and _side_by_side_fit(widest_mm(v), r_hc, ns, count)]
    if smaller:
        key = "hardware.fastener_diameter_mm"
        out.append(({key: smaller[0]}, change_text(key, smaller[0], d,
                                                   f"{bolt_set(smaller[0]).size} screws")))
    key = "hardware.fastener"
    out.append(({key: "dowel"}, change_text(key, "dowel", "bolt", "flush pins")))
    return out


def check_fastener_room(layout, springs) -> None:
    """Raise :class:`DesignError` when a rim fastener reaches a part it does not join.

    A bolt's head and nut stand proud of the rims it clamps; next to a shaft-to-shaft
    joint they would run into the neighbouring spring, its rim washer and the bushing,
    which turn against them. Dowels (ISO 8734, flush or recessed in the two rims) need
    no room beside the rims.
    """
    clashes = fastener_clashes(layout, springs)
    if not clashes:
        return
    shown = "; ".join(c.text() for c in clashes[:4])
    more = f" (and {len(clashes) - 4} more)" if len(clashes) > 4 else ""
    fasteners = [c for c in layout.components if isinstance(c.plan, pl.FastenerPlan)]
    plan = fasteners[0].plan
    if plan.type == "bolt" and all(c.fastener for c in clashes):
        b = bolt_set(plan.diameter_mm)
        raise RemedyError(
            f"rim fasteners: the {b.size} ISO 4762 heads (Ø{b.head_diameter_mm:g} mm) and "
            f"ISO 4032 nuts ({b.nut_across_corners_mm:.3g} mm across corners) of "
            f"{len(plan.hole_centres_mm)} screws on the "
            f"R{math.hypot(*plan.hole_centres_mm[0]):.4g} hole circle overlap each other, "
            f"{len(clashes)} clash(es) of neighbouring fasteners: {shown}{more}",
            _side_by_side_remedies(plan, springs))
    fix = "check the rim holes of the joined springs"
    if plan.type == "bolt" and any(c.piece.what in ("head", "nut") for c in clashes):
        b = bolt_set(plan.diameter_mm)
        s0 = springs[0]
        try:  # the flush alternative, sized for the thinnest pair of rims and the gap
            t = min(s.thickness_mm for s in springs)
            gap = min(f.length_mm for f in fasteners) - 2 * t
            pin = (f"ISO 8734 Ø{plan.diameter_mm:g} x "
                   f"{rim_dowel_length(plan.diameter_mm, t, gap, t):g}")
            fix = (f"use hardware.fastener = \"dowel\" (flush pins, {pin}), or a stack of at "
                   "most two springs")
        except DesignError:
            fix = ("use hardware.fastener = \"dowel\" with an ISO 8734 diameter that fits the "
                   "rims, or a stack of at most two springs")
        fix = (f"the {b.size} ISO 4762 head (Ø{b.head_diameter_mm:g} x {b.head_height_mm:g} mm) "
               f"and ISO 4032 nut ({b.nut_across_corners_mm:.3g} mm across corners x "
               f"{b.nut_height_mm:g} mm) stand proud of the rims they clamp, and the "
               f"{s0.hardware.rim_spacer_thickness_mm:g} mm gap to a spring that turns against "
               f"them has no room for them: {fix}")
    raise DesignError(f"rim fasteners: {len(clashes)} clash(es) with parts they do not join: "
                      f"{shown}{more}; {fix}")
