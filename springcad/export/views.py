"""The views of a part drawing: main view, side view, auxiliary end view, details.

First-angle projection (ISO 5456-2, symbol in the title block): the main view
looks down the part axis from +z (the face a stack's input side sees); the
view from above goes below it, so the part's +z face is at the bottom of that
side view and its axis runs down the sheet. The back of a part with a
second section (a camshaft hub, a shaft socket) is an arrow-labelled view B,
and small features get scaled details. Every loop is dimensioned from its
named features (:meth:`~springcad.design.curves.Loop.named`): circles on the
axis get a diameter, off-axis circles a hole callout, position circle and hole
table, D loops their diameter, flat and corners; lengths along the axis are
one chain (overall length and the steps but the first), never twice.
Units: mm (model), sheet mm, degrees on the drawing.
"""

from __future__ import annotations

import math
import numpy as np

from springcad.design.curves import Arc, Circle, Line, Loop, Profile
from springcad.design.processes import processes
from springcad.geometry.disk import HUB_COAXIALITY_MM
from springcad.export.sheet import (LABEL_FONT, NOTE_FONT, SCALES, THICK, THIN, Dimension,
                                    Sheet, View, fit_scale, fmt, scale_text)

#: the zone of the main and side views (sheet mm): x0, y0, x1, y1
LEFT_ZONE = (14.0, 14.0, 226.0, 262.0)
#: room kept around a view for its callouts and dimensions (sheet mm)
CALLOUT_MARGIN = 30.0
#: gap between the main view and the side view (sheet mm)
VIEW_GAP = 26.0
#: a dimension line keeps at least this from the extreme of the part's outline (sheet mm)
OUTLINE_GAP_MM = 2.0
#: hole centres on one circle closer than this to equal spacing are "EQ SP" (deg)
EQUAL_SPACING_TOL_DEG = 1e-6


# ------------------------------------------------------------------ helpers
def bbox(profile: Profile) -> tuple[float, float, float, float]:
    p = profile.outer.sample(0.05)
    return float(p[:, 0].min()), float(p[:, 1].min()), float(p[:, 0].max()), float(p[:, 1].max())


def draw_profile(sheet: Sheet, view: View, profile: Profile, lw=THICK, style="-") -> None:
    step = 0.25 / view.scale
    for loop in profile.loops:
        sheet.polyline(view(loop.sample(step)), lw=lw, closed=True, style=style)


def _out(angle_deg: float) -> np.ndarray:
    a = math.radians(angle_deg)
    return np.array([math.cos(a), math.sin(a)])


def _on_axis(c, tol=1e-6) -> bool:
    return math.hypot(*c) < tol


def hole_groups(profile: Profile) -> list[list[Circle]]:
    """Off-axis circles grouped by (radius, distance from the axis), in loop order."""
    groups: dict[tuple, list[Circle]] = {}
    for loop in profile.holes:
        if loop.is_circle and not _on_axis(loop.segments[0].center):
            c = loop.segments[0]
            groups.setdefault((round(c.radius, 6), round(math.hypot(*c.center), 6)), []).append(c)
    return list(groups.values())


def angle_from_y_deg(c) -> float:
    """Angle of a point from +Y, counter-clockwise, 0-360 (deg)."""
    return math.degrees(math.atan2(-c[0], c[1])) % 360.0


def is_d_loop(loop: Loop) -> bool:
    return any(f.kind == "flat" for f in loop.features)


# ------------------------------------------------------------------ tolerancing (ISO 1101)
def is_cut(part) -> bool:
    """A part cut from a DXF: its contour dimensions are theoretically exact (boxed) and
    toleranced by one profile frame (the DXF's contour tolerance)."""
    return part.info.cut_profile is not None


def profile_frames(part) -> tuple:
    """The profile frame of a cut part: every point of a cut contour within +-tolerance
    of the DXF, a zone 2 x tolerance wide; a camshaft's teeth located to its bore (datum
    A: bore and teeth are cut in one setup, and the bore centres the cam on its shaft)."""
    if not is_cut(part):
        return ()
    datum = ("A",) if _bore_is_datum(part) else ()
    return (("profile", fmt(2 * part.tolerance_mm)) + datum,)


def _bore_is_datum(part) -> bool:
    """A camshaft's bore with an ISO fit is datum A when no hole pattern takes A (its outer
    diameter then); :func:`dim_profile` draws it."""
    prof = part.info.cut_profile
    return (part.info.kind == "camshaft" and bool(part.info.fits.get("bore"))
            and not (prof is not None and hole_groups(prof)))


def hole_frames(part) -> tuple:
    """Position frames of a part's hole pattern (datum A the outer diameter, B hole #1)
    from its process; holes with an ISO fit (the rim dowels' slip fit) get a second row,
    the holes to each other (ISO 5458 CZ), when the process holds that (one setup)
    tighter than to the datums: two rims' patterns then cannot jam their pins."""
    proc = processes().get(part.info.process)
    if proc is None or proc.position_tolerance_mm <= 0:
        return ()
    zone = 2 * proc.position_tolerance_mm
    upper = ("position", f"Ø{fmt(zone)}", "A", "B")
    if proc.pattern_zone < zone - 1e-12 and part.info.fits.get("holes", "")[:1].isalpha():
        return (upper, ("position", f"Ø{fmt(proc.pattern_zone)} CZ"))
    return (upper,)


def hub_frames(part, prefix: str) -> tuple:
    """The coaxiality frame of a camshaft's turned hub (view B) to its bore, datum A."""
    if prefix and part.info.kind == "camshaft":
        return (("coaxiality", f"Ø{fmt(HUB_COAXIALITY_MM)}", "A"),)
    return ()


# ------------------------------------------------------------------ loop dimensions
def dim_circle(sheet: Sheet, view: View, radius: float, label: str, feature: str,
               angle_deg: float, frames=(), boxed: bool = False) -> None:
    """Diameter callout to a circle on the axis, leader from outside or inside; tolerance
    frames under it, the value boxed when theoretically exact."""
    c = view((0.0, 0.0))
    u = _out(angle_deg)
    sheet.callout(c + radius * view.scale * u, label, u,
                  Dimension("diameter", 2 * radius, label, feature), frames=frames, boxed=boxed)


def flat_deviations(tol: float, outer: bool) -> str:
    """Deviations of a flat's distance from the axis: one-sided, so a D shaft (or hub) and
    the D bore it slides into, drawn at the same nominal flat, never interfere: the shaft's
    flat may only move towards the axis, the bore's only away from it."""
    return f"0/-{fmt(tol)}" if outer else f"+{fmt(tol)}/0"


def dim_d_loop(sheet: Sheet, view: View, loop: Loop, feature: str, fit: str, tol: float,
               outer: bool, clear_mm: float = 0.0, boxed: bool = False, frames=()) -> None:
    """A D loop: diameter of its arc (with the tolerance ``frames`` under it), distance of
    its flat from the axis, corner radii.

    The flat's dimension line goes beside the D, or beyond ``clear_mm`` (model mm from the
    axis: the outline of the part around a D bore) when the space beside it is taken.
    """
    arc, = loop.named("arc")
    flat, = loop.named("flat")
    y_flat = flat.start[1]
    d_label = f"Ø{fmt(2 * arc.radius)} {fit}".strip()
    dim_circle(sheet, view, arc.radius, d_label, feature, 60 if outer else 120, frames=frames)
    label = f"{fmt(abs(y_flat))} {flat_deviations(tol, outer)}"
    c = view((0.0, 0.0))
    # dimension line candidates beside the D, then beyond the outline; never one lying on
    # the outline's extreme (a line tangent to the outer circle reads as part of it)
    edge = clear_mm * view.scale
    offsets = tuple(off for off in (r * view.scale + o for r in (arc.radius, clear_mm)
                                    for o in (5.0, 10.0, 16.0))
                    if clear_mm <= 0 or abs(off - edge) > OUTLINE_GAP_MM)
    sheet.dim_linear(c, view((0.0, y_flat)), 1.0 if not outer else -1.0, label,
                     Dimension("flat", abs(y_flat), label, f"{feature} flat"), offsets=offsets)
    try:
        corners = loop.named("corner")
    except KeyError:
        return
    r = corners[0].radius
    # a corner radius under 0.5 mm has no ISO 2768-1 general tolerance: boxed (the DXF's
    # profile governs it) on a cut part, else a limit that lets the D fit its mate: a
    # shaft's rounded corner at least, a socket's fillet at most the mate's radius
    limit = "" if boxed else (" min" if outer else " max")
    label = f"{len(corners)}× R{fmt(r)}{limit}"
    mid = corners[-1].mid
    direction = np.asarray(mid) - np.asarray(corners[-1].center)
    sheet.callout(view(mid), label, direction / np.linalg.norm(direction),
                  Dimension("radius", r, label, f"{feature} corners"), boxed=boxed)


def hole_id(k: int) -> str:
    """Label of the k-th hole (1-based): ``#k``, which cannot be read as a fit (an
    "H7" hole label beside "Ø1.5 H7" could)."""
    return f"#{k}"


def hole_rows(profile: Profile, fit: str) -> list[tuple[str, ...]]:
    """The hole table: header and one row per off-axis hole (angle from +Y, CCW; X, Y mm)."""
    rows = []
    for group in hole_groups(profile):
        for c in group:
            rows.append((hole_id(len(rows) + 1), f"{angle_from_y_deg(c.center):.3f}°",
                         fmt(c.center[0]), fmt(c.center[1]), f"Ø{fmt(2 * c.radius)} {fit}".strip()))
    return [("HOLE", "ANGLE FROM +Y (CCW)", "X", "Y", "SIZE")] + rows if rows else []


def dim_holes(sheet: Sheet, view: View, profile: Profile, fit: str, purpose: str,
              frames=()) -> None:
    """Hole callout (with the pattern's position ``frames``), position circle (its
    diameter theoretically exact when positions are framed), #1..#n labels of off-axis
    holes (see :func:`hole_rows`) and datum B on hole #1 when framed."""
    k = 0
    for group in hole_groups(profile):
        c0 = group[0]
        pcd = math.hypot(*c0.center)
        angles = [angle_from_y_deg(c.center) for c in group]
        steps = np.diff(sorted(angles) + [sorted(angles)[0] + 360.0])
        equal = np.ptp(steps) < EQUAL_SPACING_TOL_DEG
        label = f"{len(group)}× Ø{fmt(2 * c0.radius)} {fit} THRU".replace("  ", " ")
        if equal:
            label += " EQ SP"
        sheet.callout(view(c0.center) + c0.radius * view.scale * _out(60),
                      label + (f" {purpose}" if purpose else ""), _out(60),
                      Dimension("diameter", 2 * c0.radius, label, "holes"), frames=frames)
        centre = view((0.0, 0.0))
        sheet.circle(centre, pcd * view.scale)
        a_pcd = math.radians(angles[0] + 90.0 + 0.5 * (steps[0] if len(steps) else 30.0))
        pt = centre + pcd * view.scale * np.array([math.cos(a_pcd), math.sin(a_pcd)])
        lab = f"PCD Ø{fmt(2 * pcd)}"
        sheet.callout(pt, lab, (pt - centre) / np.linalg.norm(pt - centre),
                      Dimension("diameter", 2 * pcd, lab, "hole circle"), boxed=bool(frames))
        if frames and k == 0:  # datum B: hole #1
            u1 = np.asarray(c0.center) / pcd
            t1 = np.array([u1[1], -u1[0]])
            sheet.datum_feature(view(c0.center) + c0.radius * view.scale * t1, t1, "B")
        for c, a in zip(group, angles):
            k += 1
            name = hole_id(k)
            u = np.asarray(c.center) / pcd
            p = view(c.center)
            t = np.array([-u[1], u[0]])
            cands = [p + u * d + t * e - np.array([1.6, 1.2]) for d in (4.0, 6.0, 8.5, 11.0, 14.0)
                     for e in (0.0, 3.0, -3.0, 6.0, -6.0)]
            sheet.place_text(cands, name, size=NOTE_FONT)
            sheet.dims.append(Dimension("position", pcd, name, "holes", angle_deg=a))


def dim_profile(sheet: Sheet, view: View, profile: Profile, part, skip_outer: bool = False,
                skip_bore: bool = False, prefix: str = "") -> None:
    """Dimensions of every circle and D loop of a profile (other loops are the caller's).

    Fits come from ``part.info.fits`` ("outer", "bore", "holes", "hole_purpose"). On a cut
    part a contour dimension without a fit is boxed (theoretically exact) and the outer
    contour carries the profile frame; with a hole pattern the outer diameter is datum A,
    without one a camshaft's bore is (its hub's coaxiality frame in view B refers to it).
    """
    fits = part.info.fits
    x0, y0, x1, y1 = bbox(profile)
    clear = max(abs(x0), abs(y0), x1, y1)
    frames = hole_frames(part) if hole_groups(profile) else ()
    cut = is_cut(part) and not prefix
    for k, loop in enumerate(profile.loops):
        outer = k == 0
        if (outer and skip_outer) or (not outer and skip_bore):
            continue
        feature = prefix + ("outer" if outer else "bore")
        fit = fits.get("outer" if outer else "bore", "")
        if loop.is_circle and _on_axis(loop.segments[0].center):
            r = loop.segments[0].radius
            extra = (profile_frames(part) if outer and cut else ()) + (
                hub_frames(part, prefix) if outer else ())
            dim_circle(sheet, view, r, f"Ø{fmt(2 * r)} {fit}".strip(), feature,
                       35 if outer else 215, frames=extra, boxed=cut and not fit)
            if outer and frames:
                sheet.datum_feature(view((0.0, 0.0)) + r * view.scale * _out(200), _out(200),
                                    "A")
        elif is_d_loop(loop):
            # a D hub (the flat drives the torque shaft) is as coaxial to the bore as a
            # round one
            dim_d_loop(sheet, view, loop, feature, fit, part.tolerance_mm, outer, clear,
                       boxed=cut, frames=hub_frames(part, prefix) if outer else ())
        if not outer and not prefix and not frames and _bore_is_datum(part):
            p = max((seg for seg in loop.segments if isinstance(seg, Arc | Circle)),
                    key=lambda seg: seg.radius)
            r = p.radius
            sheet.datum_feature(view((0.0, 0.0)) + r * view.scale * _out(135), _out(135), "A")
    dim_holes(sheet, view, profile, fits.get("holes", ""), fits.get("hole_purpose", ""),
              frames)


def _bore_extent(region: Profile) -> tuple[float, float] | None:
    """x extent (mm) of the hole loop around the axis (a bore or socket), or None."""
    for loop in region.holes:
        p = loop.sample(0.05)
        if p[:, 0].min() < 0 < p[:, 0].max() and p[:, 1].min() < 0 < p[:, 1].max():
            return (round(float(p[:, 0].min()), 6), round(float(p[:, 0].max()), 6))
    return None


def z_levels(part) -> list[float]:
    return sorted({round(z, 6) for s in part.slabs for z in (s.z0_mm, s.z1_mm)})


def side_view(sheet: Sheet, x_axis: float, y_top: float, scale: float, part) -> float:
    """View from above, placed below the main view (first angle): +z at the bottom.

    Silhouettes of the slabs, hidden bores (dashed), the axis, and the length
    chain. Returns the bottom of the view (sheet mm).
    """
    levels = z_levels(part)

    def ys(z):
        return y_top - (z - levels[0]) * scale

    def xs(x):
        return x_axis + x * scale

    slabs = sorted(part.slabs, key=lambda s: s.z0_mm)
    extents = [bbox(s.region)[::2] for s in slabs]  # (x min, x max) of each slab
    bores = [_bore_extent(s.region) for s in slabs]
    half_widths = [max(abs(a), abs(b)) for a, b in extents]
    for k, (sl, (x0, x1)) in enumerate(zip(slabs, extents)):
        ya, yb = ys(sl.z0_mm), ys(sl.z1_mm)
        for x in (x0, x1):  # outline sides
            sheet.polyline([(xs(x), ya), (xs(x), yb)], lw=THICK)
        if bores[k]:  # a bore or socket: hidden lines, and its blind end
            for x in bores[k]:
                sheet.polyline([(xs(x), ya), (xs(x), yb)], style="--")
            for j, z in ((k - 1, sl.z0_mm), (k + 1, sl.z1_mm)):
                if 0 <= j < len(slabs) and bores[j] != bores[k]:
                    sheet.polyline([(xs(bores[k][0]), ys(z)), (xs(bores[k][1]), ys(z))],
                                   style="--")
    # outline across the axis: the two ends, and the steps where the width changes
    sheet.polyline([(xs(extents[0][0]), ys(slabs[0].z0_mm)),
                    (xs(extents[0][1]), ys(slabs[0].z0_mm))], lw=THICK)
    sheet.polyline([(xs(extents[-1][0]), ys(slabs[-1].z1_mm)),
                    (xs(extents[-1][1]), ys(slabs[-1].z1_mm))], lw=THICK)
    for (a0, a1), (b0, b1), sl in zip(extents, extents[1:], slabs[1:]):
        for u, v in ((a0, b0), (a1, b1)):
            if abs(u - v) > 1e-9:
                sheet.polyline([(xs(u), ys(sl.z0_mm)), (xs(v), ys(sl.z0_mm))], lw=THICK)
    bottom, top = ys(levels[-1]), ys(levels[0])
    sheet.polyline([(x_axis, bottom - 3.0), (x_axis, top + 3.0)], style="-.")
    # length chain: overall, then every step but the first (a tree over the z levels)
    r_max = max(half_widths)
    pairs = [(levels[0], levels[-1])] + [(a, b) for a, b in zip(levels[1:-1], levels[2:])]
    for k, (za, zb) in enumerate(pairs):
        tol = f" ±{fmt(part.length_tolerance_mm)}" if getattr(part, "length_tolerance_mm",
                                                                0) else ""
        label = f"{fmt(zb - za)}{tol}"
        x_edge = xs(r_max if k == 0 else -r_max)
        sheet.dim_linear((x_edge, ys(za)), (x_edge, ys(zb)), 1.0 if k == 0 else -1.0, label,
                         Dimension("length", zb - za, label, "length", z=(za, zb)))
    return bottom


# ------------------------------------------------------------------ detail views
def detail(sheet: Sheet, profile: Profile, window, centre, box_mm: float, letter: str,
           caption: str) -> View:
    """Draw the part of ``profile`` inside a model window, scaled to fit ``box_mm``."""
    x0, y0, x1, y1 = window
    s = fit_scale(max(x1 - x0, y1 - y0), box_mm)
    v = View(np.asarray(centre) - s * np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)]), s)
    for loop in profile.loops:
        p = loop.sample(0.2 / s)
        keep = (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)
        q = v(p).copy()
        q[~keep] = np.nan
        sheet.polyline(q, lw=THICK)
    a, b = v((x0, y0)), v((x1, y1))
    sheet.rect(a[0], a[1], b[0] - a[0], b[1] - a[1])
    sheet.text(0.5 * (a[0] + b[0]), a[1] - 4.0, f"DETAIL {letter}  {caption}  {scale_text(s)}",
               size=NOTE_FONT)
    return v


def mark_detail(sheet: Sheet, view: View, centre, radius: float, letter: str) -> None:
    """Circle the region of a detail in the main view and letter it."""
    c = view(centre)
    sheet.circle(c, radius, style="-")
    u = np.asarray(c) - view((0.0, 0.0))
    u = u / np.linalg.norm(u) if np.linalg.norm(u) > 0 else np.array([0.0, 1.0])
    sheet.callout(c + radius * u, letter, u, turn=(0, 25, -25, 50, -50, 75, -75, 100, -100,
                                                   135, -135, 180))


def _room() -> tuple[float, float]:
    """Top and bottom (sheet mm) between which the main and side views go."""
    return LEFT_ZONE[3] - CALLOUT_MARGIN + 12.0, LEFT_ZONE[1] + 10.0


def choose_scale(width_mm: float, height_mm: float, length_mm: float) -> float:
    """Largest standard scale at which the main view (width x height) and the side view
    (width x length) below it fit the left zone with room for their dimensions."""
    x0, y0, x1, y1 = LEFT_ZONE
    for s in SCALES:
        w = width_mm * s + 2 * CALLOUT_MARGIN
        h = (height_mm + length_mm) * s + VIEW_GAP
        if w <= x1 - x0 and h <= _room()[0] - _room()[1]:
            return s
    return SCALES[-1]


def choose_scale_of(part) -> float:
    """The scale of a part's main view (:func:`choose_scale` of its +z profile and length)."""
    x0, y0, x1, y1 = bbox(part.slabs[-1].region)
    lo, hi = part.z_range_mm
    return choose_scale(x1 - x0, y1 - y0, hi - lo)


def main_and_side(sheet: Sheet, part, profile: Profile) -> tuple[View, float]:
    """Place and draw the main view (``profile`` seen from +z) and the side view below it.

    Returns (main view, bottom of the side view).
    """
    x0, y0, x1, y1 = bbox(profile)
    lo, hi = part.z_range_mm
    s = choose_scale_of(part)
    zx0, zy0, zx1, zy1 = LEFT_ZONE
    block = (y1 - y0 + hi - lo) * s + VIEW_GAP
    room_top, room_bottom = _room()
    top = room_top - 0.5 * max(0.0, (room_top - room_bottom) - block)
    view = View((0.5 * (zx0 + zx1) - 0.5 * (x0 + x1) * s, top - y1 * s), s)
    draw_profile(sheet, view, profile)
    sheet.centre_mark(view((0, 0)), 0.5 * max(x1 - x0, y1 - y0) * s + 4)
    bottom = side_view(sheet, view((0, 0))[0], view((0, y0))[1] - VIEW_GAP, s, part)
    return view, bottom


# ------------------------------------------------------------------ part families
def _unit(p) -> np.ndarray:
    p = np.asarray(p, float)
    return p / np.linalg.norm(p)


def _halves(zone) -> tuple[tuple, tuple]:
    """The right-column zone split into a left and a right box (sheet mm)."""
    x0, y0, x1, y1 = zone
    xm = 0.5 * (x0 + x1)
    return (x0, y0, xm - 4.0, y1), (xm + 4.0, y0, x1, y1)


def _detail_in(sheet, profile, window, box, letter, caption) -> View:
    x0, y0, x1, y1 = box
    size = min(x1 - x0, y1 - y0 - 14.0) - 2 * 8.0  # callouts find room around it
    centre = (0.5 * (x0 + x1), 0.5 * (y0 + y1) + 4.0)
    return detail(sheet, profile, window, centre, size, letter, caption)


def ring_views(sheet: Sheet, part, zone) -> float:
    """Flexure ring: main view, thickness below, details C (tip) and D (root) at the right
    (the letters A and B are the datums)."""
    prof = part.info.cut_profile
    flex = prof.loop("flexures")
    v, _ = main_and_side(sheet, part, prof)
    # the detail circles first, so the datum symbols and callouts placed after keep clear of them
    rc, rb = part.contact_radius, part.tip_radius
    half = max(4.0 * rb, 0.6 * 2 * math.pi * rc / part.n_flexures)
    mark_detail(sheet, v, (0.0, rc), max(3.0, 1.5 * half * v.scale), "C")
    roots = flex.named("root", 0)
    rr = roots[0].radius
    mid = 0.5 * (np.asarray(roots[0].mid) + np.asarray(roots[-1].mid))
    span = max(abs(roots[0].mid[0] - roots[-1].mid[0]), 4 * rr) * 0.75
    mark_detail(sheet, v, tuple(mid), max(3.0, 1.2 * span * v.scale), "D")
    holes = [lp.segments[0].center for lp in prof.holes if lp.is_circle]
    rim = max(flex.named("rim"), key=lambda a: min((math.dist(a.mid, h) for h in holes),
                                                     default=-a.mid[1]))
    label = f"R{fmt(rim.radius)}"
    sheet.callout(v(rim.mid), label, _unit(rim.mid), Dimension("radius", rim.radius, label, "rim"),
                  boxed=True)
    dim_profile(sheet, v, prof, part)
    # detail C: the tip of flexure 0 (ball centre on +Y at the contact radius)
    box_a, box_b = _halves(zone)
    win = (-half, rc - 1.2 * half, half, rc + 0.8 * half)
    da = _detail_in(sheet, prof, win, box_a, "C", "flexure 0 tip")
    ball, = flex.named("ball", 0)
    label = f"R{fmt(ball.radius)}"
    sheet.callout(da(ball.mid), label, _unit(np.asarray(ball.mid) - ball.center),
                  Dimension("radius", ball.radius, label, "tip ball"), boxed=True)
    necks = flex.named("neck", 0)
    label = f"{len(necks)}× R{fmt(necks[0].radius)}"
    sheet.callout(da(necks[-1].mid), label, (-1.0, 0.3),
                  Dimension("radius", necks[0].radius, label, "neck fillets"), boxed=True)
    a = np.linspace(math.pi / 2 - 0.9 * half / rc, math.pi / 2 + 0.9 * half / rc, 60)
    arc_pts = np.column_stack([rc * np.cos(a), rc * np.sin(a)])
    sheet.polyline(da(arc_pts), style="-.")
    label = f"R{fmt(rc)} ball centres"
    sheet.callout(da(arc_pts[8]), label, (0.4, -1.0),
                  Dimension("radius", rc, label, "ball centres"), boxed=True)
    # detail D: the root of flexure 0
    win = (mid[0] - span, mid[1] - 1.3 * span, mid[0] + span, mid[1] + 0.5 * span)
    db = _detail_in(sheet, prof, win, box_b, "D", "flexure 0 root")
    label = f"{len(roots)}× R{fmt(rr)}"
    sheet.callout(db(roots[0].mid), label, _unit(np.asarray(roots[0].mid) - roots[0].center),
                  Dimension("radius", rr, label, "root fillets"), boxed=True)
    return v.scale


def _view_b(sheet: Sheet, part, region: Profile, box, scale: float, skip_bore: bool) -> View:
    """View B: the part seen from -z (from behind: x mirrored), with its own dimensions."""
    x0, y0, x1, y1 = bbox(region)
    bx0, by0, bx1, by1 = box
    s = min(scale, fit_scale(max(x1 - x0, y1 - y0), min(bx1 - bx0, by1 - by0 - 14.0) - 2 * 10.0))
    centre = np.array([0.5 * (bx0 + bx1), 0.5 * (by0 + by1) + 4.0])
    v = View(centre, s, mirror_x=True)
    draw_profile(sheet, v, region)
    sheet.centre_mark(centre, 0.5 * max(x1 - x0, y1 - y0) * s + 3)
    sheet.text(centre[0], centre[1] - 0.5 * (y1 - y0) * s - 9.0,
               f"VIEW B (from -Z)  {scale_text(s)}", size=NOTE_FONT)
    dim_profile(sheet, v, region, part, skip_bore=skip_bore, prefix="back ")
    return v


def _arrow_b(sheet: Sheet, main: View, part) -> None:
    """The viewing arrow of view B: above the side view (whose -z end is at its top),
    pointing down the axis."""
    top = part.slabs[-1].region
    x0, y0, x1, _ = bbox(top)
    half = max(max(abs(bbox(s.region)[0]), abs(bbox(s.region)[2])) for s in part.slabs)
    x = main((0.0, 0.0))[0] + half * main.scale + 8.0
    y_side_top = main((0.0, y0))[1] - VIEW_GAP
    sheet.arrow((x, y_side_top + 12.0), (x, y_side_top + 2.5))
    sheet.place_text([(x + 1.5, y_side_top + 6.0), (x - 6.0, y_side_top + 6.0)], "B",
                     size=NOTE_FONT, weight="bold")


def _new_loops(region: Profile, top: Profile) -> bool:
    """Whether ``region`` has a loop ``top`` does not (by shape), i.e. needs its own view."""
    def key(loop):
        return tuple(sorted((type(s).__name__, round(getattr(s, "radius", 0.0), 6))
                            for s in loop.segments))
    return not {key(lp) for lp in region.loops} <= {key(lp) for lp in top.loops}


def cam_views(sheet: Sheet, part, zone) -> float:
    """Camshaft: teeth from +z, side view (hub above the teeth), pocket detail C, view B."""
    top = part.slabs[-1].region
    v, _ = main_and_side(sheet, part, top)
    teeth = top.loop("teeth")
    tip = teeth.named("tip")[0]
    label = f"Ø{fmt(2 * tip.radius)} tooth tips"
    sheet.callout(v(tip.mid), label, _unit(tip.mid),
                  Dimension("diameter", 2 * tip.radius, label, "tooth tips"),
                  frames=profile_frames(part), boxed=True)
    dim_profile(sheet, v, top, part, skip_outer=True)
    box_c, box_b = _halves(zone)
    pocket, = teeth.named("pocket", 0)
    rc = math.hypot(*pocket.center)
    half = 0.8 * 2 * math.pi * rc / part.n_teeth
    win = (-half, rc - 0.9 * half, half, rc + 0.7 * half)
    dc = _detail_in(sheet, top, win, box_c, "C", "pocket 0")
    label = f"R{fmt(pocket.radius)}"
    sheet.callout(dc(pocket.mid), label, _unit(np.asarray(pocket.mid) - pocket.center),
                  Dimension("radius", pocket.radius, label, "pockets"), boxed=True)
    a = np.linspace(math.pi / 2 - 0.8 * half / rc, math.pi / 2 + 0.8 * half / rc, 60)
    arc_pts = np.column_stack([rc * np.cos(a), rc * np.sin(a)])
    sheet.polyline(dc(arc_pts), style="-.")
    label = f"R{fmt(rc)} pocket centres"
    sheet.callout(dc(arc_pts[6]), label, (0.4, -1.0),
                  Dimension("radius", rc, label, "pocket centres"), boxed=True)
    mark_detail(sheet, v, (0.0, rc), max(3.0, 1.3 * half * v.scale), "C")
    if len(part.slabs) > 1 and _new_loops(part.slabs[0].region, top):
        _view_b(sheet, part, part.slabs[0].region, box_b, v.scale, skip_bore=True)
        _arrow_b(sheet, v, part)
    return v.scale


def plain_views(sheet: Sheet, part, zone) -> float:
    """Turned and sheet parts: main view from +z, side view below, view B when the back
    has loops the front does not."""
    top = part.slabs[-1].region
    v, _ = main_and_side(sheet, part, top)
    dim_profile(sheet, v, top, part)
    if len(part.slabs) > 1 and _new_loops(part.slabs[0].region, top):
        _view_b(sheet, part, part.slabs[0].region, _halves(zone)[1], v.scale, skip_bore=False)
        _arrow_b(sheet, v, part)
    return v.scale


VIEWS = {"flexure_ring": ring_views, "camshaft": cam_views}


def uses_right_column(part) -> bool:
    """Whether a part's views take the right column above the notes (details of a ring or
    a camshaft, a plain part's view B); the others leave it to the notes."""
    if part.info.kind in VIEWS:
        return True
    return len(part.slabs) > 1 and bool(_new_loops(part.slabs[0].region,
                                                   part.slabs[-1].region))


def part_views(sheet: Sheet, part, zone) -> float:
    """Draw every view of a part; ``zone`` is the free box of the right column. Returns the
    main view's scale."""
    return VIEWS.get(part.info.kind, plain_views)(sheet, part, zone)
