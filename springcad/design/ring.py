"""Exact 2D profile of the flexure ring (the spring disk).

Flexure 0 lies along +y; flexure i is rotated by 2*pi*i/N counter-clockwise.
The inner contour runs counter-clockwise about the centre: rim arc, root
fillet, right flexure edge down to the tip, neck fillet, tip ball, neck fillet,
left edge up, root fillet, next rim arc. Rim holes sit midway between flexures.
Units: mm, rad.
"""

from __future__ import annotations

import math

import numpy as np

from springcad.design import flexure as fx
from springcad.design.catalogue import RIM_PIN_HOLE_FIT
from springcad.design.connections import rim_groups
from springcad.design.curves import Arc, Circle, Feature, Loop, Profile, Spline, named
from springcad.errors import DesignError


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def fillet_arc(center, radius, start_pt, end_pt) -> Arc:
    """Short arc about ``center`` from ``start_pt`` to ``end_pt``."""
    a1 = math.atan2(start_pt[1] - center[1], start_pt[0] - center[0])
    a2 = math.atan2(end_pt[1] - center[1], end_pt[0] - center[0])
    return Arc(tuple(center), radius, a1, a1 + _wrap(a2 - a1))


class _Edge:
    """One flexure edge as a function of y, with its void-side unit normal."""

    def __init__(self, design, side: int):
        self.d, self.side = design, side

    def point_normal(self, y: float):
        """Edge point at station y and the unit normal *of the edge curve* towards the void.

        The edge's own normal, not the centreline's: near the tip the width
        grows like sqrt(y - r_c) and the two differ by up to ~16 deg, which
        left the neck fillet meeting the edge at a re-entrant kink (a stress
        singularity found by the FEA convergence study).
        """
        p, n = self.point_normals(np.array([y], dtype=float))
        return p[0], n[0]

    def point_normals(self, ys, h: float = 1e-6):
        """:meth:`point_normal` at many stations: points and normals, shape (m, 2) each."""
        ys = np.asarray(ys, dtype=float)
        m = len(ys)
        p = self.points(np.concatenate([ys + h, ys - h, ys]))  # one call: the same numbers
        t = p[:m] - p[m:2 * m]
        t /= np.linalg.norm(t, axis=1)[:, None]
        return p[2 * m:], self.side * np.column_stack([t[:, 1], -t[:, 0]])

    def points(self, ys):
        ys = np.asarray(ys, dtype=float)
        right, left, _ = fx.edges(self.d.centreline, ys, self.d.width_mm(ys))
        return right if self.side > 0 else left

    def tangent_up(self, y: float, h: float = 1e-6):
        p = self.points([y - h, y + h])
        t = p[1] - p[0]
        return t / np.linalg.norm(t)


def _solve(f, start, stop, what, step=0.02):
    """First root of f met when scanning from ``start`` toward ``stop`` (mm).

    ``f`` takes an array of stations and returns an array. The first sign change on a
    grid of ``step`` is narrowed by three vectorised 64-point sweeps (bracket below
    1e-7 mm), then closed by linear interpolation: four array calls in all.
    """
    n = min(max(2, int(abs(stop - start) / step) + 1), 20001)
    grid = np.linspace(start, stop, n)
    for _ in range(4):
        vals = f(grid)
        if vals[0] == 0.0:
            return float(grid[0])
        change = np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)
        if not len(change):
            raise DesignError(what)
        k = change[0]
        a, b, fa, fb = grid[k], grid[k + 1], vals[k], vals[k + 1]
        grid = np.linspace(a, b, 64)
    return float(a if fb == fa else a - fa * (b - a) / (fb - fa))


def _root_station(d, edge: "_Edge") -> float:
    """Station y (mm) where the root fillet meets this flexure edge (tangent point)."""
    rc, rr, rf = d.contact_radius_mm, d.root_radius_mm, d.root_fillet_radius_mm

    def root(y):
        p, n = edge.point_normals(y)
        return np.linalg.norm(p + rf * n, axis=1) - (rr - rf)

    return _solve(root, rr + d.rim_thickness_mm, rc + 0.5 * (rr - rc),
                  f"spring '{d.name}': the root fillet (r = {rf:.3g} mm) between the flexure edge "
                  "and the rim cannot be placed")


def _neck_station(d, edge: "_Edge") -> float:
    """Station y (mm) where the neck fillet meets this flexure edge (tangent point)."""
    rc, rr, rb, rn = (d.contact_radius_mm, d.root_radius_mm, d.tip_radius_mm,
                      d.neck_fillet_radius_mm)
    ball = np.array([0.0, rc])

    def neck(y):
        p, n = edge.point_normals(y)
        return np.linalg.norm(p + rn * n - ball, axis=1) - (rb + rn)

    return _solve(neck, rc + 1e-9, rc + 0.5 * (rr - rc),
                  f"spring '{d.name}': the neck fillet (r = {rn:.3g} mm) between the tip ball and "
                  "the flexure edge cannot be placed")


def neck_tangent_stations_mm(d) -> tuple[float, float]:
    """Stations y (mm) of the right and left neck-fillet tangent points on flexure 0."""
    return _neck_station(d, _Edge(d, +1)), _neck_station(d, _Edge(d, -1))


def root_tangent_stations_mm(d) -> tuple[float, float]:
    """Stations y (mm) of the right and left root-fillet tangent points on flexure 0.

    The same solve the profile uses, without building the profile: the stress
    model (:mod:`springcad.design.stress`) evaluates the root there.
    """
    return _root_station(d, _Edge(d, +1)), _root_station(d, _Edge(d, -1))


def _flexure_unit(d) -> tuple:
    """Segments of flexure 0 from the right root fillet to the left root fillet, and their names.

    Returns:
        (segments, features, right root point on the rim, left root point on the rim).
    """
    rc, rr, rb = d.contact_radius_mm, d.root_radius_mm, d.tip_radius_mm
    rn, rf = d.neck_fillet_radius_mm, d.root_fillet_radius_mm
    ball = np.array([0.0, rc])
    parts = {}
    for side in (+1, -1):
        e = _Edge(d, side)

        y_n = _neck_station(d, e)
        y_r = _root_station(d, e)
        if y_r <= y_n:
            raise DesignError(f"spring '{d.name}': neck and root fillets overlap; the flexure is too short")
        p_n, n_n = e.point_normal(y_n)
        c_n = p_n + rn * n_n
        t_ball = ball + rb * (c_n - ball) / np.linalg.norm(c_n - ball)
        p_r, n_r = e.point_normal(y_r)
        c_r = p_r + rf * n_r
        t_rim = c_r * rr / np.linalg.norm(c_r)
        u = np.linspace(0.0, 1.0, 41 if not d.centreline.is_straight else 25)
        ys = y_n + (y_r - y_n) * u ** 1.6
        pts = e.points(ys)
        pts[0], pts[-1] = p_n, p_r
        parts[side] = dict(c_n=c_n, t_ball=t_ball, p_n=p_n, c_r=c_r, t_rim=t_rim, p_r=p_r,
                           pts=pts, tan_n=e.tangent_up(y_n), tan_r=e.tangent_up(y_r))
    R, Lf = parts[+1], parts[-1]
    right_edge = Spline(tuple(map(tuple, R["pts"][::-1])), tuple(-R["tan_r"]), tuple(-R["tan_n"]))
    left_edge = Spline(tuple(map(tuple, Lf["pts"])), tuple(Lf["tan_n"]), tuple(Lf["tan_r"]))
    a_r = math.atan2(R["t_ball"][1] - rc, R["t_ball"][0])
    a_l = math.atan2(Lf["t_ball"][1] - rc, Lf["t_ball"][0])
    ball_arc = Arc((0.0, rc), rb, a_r, a_l - 2 * math.pi)
    segs, feats = named(
        (Feature("root", 0, "right"), Feature("edge", 0, "right"), Feature("neck", 0, "right"),
         Feature("ball", 0), Feature("neck", 0, "left"), Feature("edge", 0, "left"),
         Feature("root", 0, "left")),
        (fillet_arc(R["c_r"], rf, R["t_rim"], R["p_r"]),
         right_edge,
         fillet_arc(R["c_n"], rn, R["p_n"], R["t_ball"]),
         ball_arc,
         fillet_arc(Lf["c_n"], rn, Lf["t_ball"], Lf["p_n"]),
         left_edge,
         fillet_arc(Lf["c_r"], rf, Lf["p_r"], Lf["t_rim"])))
    return segs, feats, R["t_rim"], Lf["t_rim"]


def hole_diameter_mm(hardware) -> float:
    """Hole for the rim fastener (:attr:`springcad.config.HardwareSpec.hole_diameter_mm`)."""
    return hardware.hole_diameter_mm


def hole_fits(hardware) -> dict:
    """How the rim holes are called out (every part they pass gets the same callout): a
    dowel hole is a slip fit (E7) over the m6 pin, never pressed
    (:mod:`springcad.design.catalogue`); a bolt hole is a plain clearance hole
    (:func:`hole_diameter_mm`)."""
    if hardware.fastener == "dowel":
        return {"holes": RIM_PIN_HOLE_FIT,
                "hole_purpose": f"slip fit for Ø{hardware.fastener_diameter_mm:g} m6 dowels"}
    return {"holes": "", "hole_purpose": f"clearance M{hardware.fastener_diameter_mm:g}"}


def hole_centres_mm(n_flexures: int, count: int, radius_mm: float) -> tuple:
    """Hole centres midway between flexures, spread evenly over the N gaps."""
    out = []
    for j in range(count):
        k = (j * n_flexures) // count
        a = math.pi / 2 + (k + 0.5) * 2 * math.pi / n_flexures
        out.append((radius_mm * math.cos(a), radius_mm * math.sin(a)))
    return tuple(out)


def shared_hole_angles_rad(n_flexures, count: int) -> tuple[float, ...]:
    """Angles (rad) of ``count`` rim holes that every spring of a stack can carry.

    Springs joined rim to rim are pinned through the same holes, so their holes must lie
    at the same angles, not only on the same circle. With one flexure count N the angles
    are those of :func:`hole_centres_mm` (midway between flexures). With several, hole j
    is put within a quarter of the even pitch 2 pi / count of its even place
    (pi / 2 + 2 pi j / count) where its distance to the nearest flexure axis of any of
    the springs, as a fraction of that spring's half pitch pi / N (1 = midway), is
    largest: the holes keep off the flexure roots, where the root moment enters the rim.

    Args:
        n_flexures: the flexure counts N of the springs.
        count: holes per spring.
    """
    ns = sorted(set(int(n) for n in n_flexures))
    if len(ns) == 1:
        return tuple(math.atan2(y, x) for x, y in hole_centres_mm(ns[0], count, 1.0))
    step = 2.0 * math.pi / count
    offset = np.linspace(-0.25 * step, 0.25 * step, ANGLE_SAMPLES)
    out = []
    for j in range(count):
        a = step * j + offset  # from the first flexure axis, at pi / 2
        score = np.full(len(a), np.inf)
        for n in ns:
            half = math.pi / n
            off = np.mod(a, 2.0 * half)
            score = np.minimum(score, np.minimum(off, 2.0 * half - off) / half)
        # the best score, the nearest to the even place among equals
        best = np.flatnonzero(score >= score.max() - 1e-12)
        out.append(math.pi / 2 + float(a[best[np.argmin(np.abs(offset[best]))]]))
    return tuple(out)


#: angle samples over half an even hole pitch in :func:`shared_hole_angles_rad`
ANGLE_SAMPLES = 4001


def common_hole_pattern(springs: dict, max_radius_mm: float = math.inf) -> dict:
    """Every spring's rim holes on one circle at the same angles, so any two rims can be
    pinned through them (spring name -> design; springs without holes unchanged).

    The circle is the middle of the thinnest rim: half way between the largest root
    radius and the smallest outer radius (mm), at most ``max_radius_mm`` (bolt heads and
    nuts inside the rims, :func:`springcad.design.hardware.bolt_circle_limit_mm`); the
    angles are
    :func:`shared_hole_angles_rad` of the springs' flexure counts. Applying it twice
    changes nothing.
    """
    with_holes = [s for s in springs.values() if s.hole_centres_mm]
    if len(with_holes) < 2 and all(math.hypot(*c) <= max_radius_mm + 1e-9
                                   for s in with_holes for c in s.hole_centres_mm):
        return springs
    radius = min(max_radius_mm, 0.5 * (max(s.root_radius_mm for s in with_holes)
                                       + min(s.outer_radius_mm for s in with_holes)))
    angles = shared_hole_angles_rad([s.n_flexures for s in with_holes],
                                    min(len(s.hole_centres_mm) for s in with_holes))
    want = tuple((radius * math.cos(a), radius * math.sin(a)) for a in angles)

    def placed(s) -> bool:  # already there (to 1 nm): keep the design as it is
        return (len(s.hole_centres_mm) == len(want)
                and all(math.dist(p, q) < 1e-6 for p, q in zip(s.hole_centres_mm, want)))

    return {name: with_hole_circle(s, radius, angles) if s.hole_centres_mm and not placed(s)
            else s for name, s in springs.items()}


def pinned_hole_patterns(springs: dict, sequence, input_connection: str,
                         max_radius_mm: float = math.inf) -> dict:
    """:func:`common_hole_pattern` over each set of springs whose rims are pinned to each
    other (:func:`~springcad.design.connections.rim_groups` of the stack ``sequence`` with
    this input); a rim pinned only to an end flange keeps its own circle (spring name ->
    design)."""
    out = dict(springs)
    for group in rim_groups(tuple(sequence), input_connection):
        out.update(common_hole_pattern({n: springs[n] for n in group}, max_radius_mm))
    return out


def with_hole_circle(d, radius_mm: float, angles_rad=None):
    """The design with its rim holes moved onto a circle of ``radius_mm`` (mm), at
    ``angles_rad`` (rad; default: midway between its own flexures, :func:`hole_centres_mm`).

    Springs joined rim to rim are pinned through the same holes, so every spring
    of a stack puts them on one circle at the same angles
    (:func:`springcad.design.job.common_hole_circle`).

    Raises:
        DesignError: the holes would not fit in this spring's rim.
    """
    import dataclasses

    if not d.hole_centres_mm:
        return d
    r_hole = 0.5 * d.hole_diameter_mm
    edge = d.manufacturing.min_hole_edge_mm
    tol = 1e-9  # the design search puts the holes exactly at the edge distance (mm)
    if (radius_mm - r_hole - d.root_radius_mm < edge - tol
            or d.outer_radius_mm - radius_mm - r_hole < edge - tol):
        raise DesignError(
            f"spring '{d.name}': rim holes on the stack's common circle R{radius_mm:.3f} mm do not "
            f"fit its rim ({d.root_radius_mm:.3f} to {d.outer_radius_mm:.3f} mm) with "
            f"min_hole_edge_mm = {edge:g}; give the springs of a stack the same outer radius and "
            "similar rims, or smaller fasteners")
    if angles_rad is None:
        holes = hole_centres_mm(d.n_flexures, len(d.hole_centres_mm), radius_mm)
    else:
        holes = tuple((radius_mm * math.cos(a), radius_mm * math.sin(a)) for a in angles_rad)
    ring = d.ring.with_loops("hole", _hole_loops(holes, r_hole))
    return dataclasses.replace(d, ring=ring, hole_centres_mm=holes)


def _hole_loops(centres, radius_mm: float) -> tuple[Loop, ...]:
    return tuple(Loop((Circle(c, radius_mm),), (Feature("hole", j),)) for j, c in enumerate(centres))


class RootFilletsOverlap(DesignError):
    """The root fillets of neighbouring flexures meet on the rim arc between them."""


def ring_profile(d) -> tuple[Profile, tuple, float]:
    """Build the flexure-ring profile of a :class:`~springcad.design.spring.SpringDesign`.

    Loops are named ``"outer"``, ``"flexures"`` and ``"hole:j"``; the segments of
    the flexure loop are named per flexure ``i``: ``root``, ``edge``, ``neck`` (each
    with side ``right``/``left``), ``ball``, and ``rim`` (the root-circle arc from
    flexure ``i`` to flexure ``i + 1``).

    Returns:
        (profile, hole centres (mm), hole diameter (mm)).
    """
    unit, unit_features, t_right, t_left = _flexure_unit(d)
    n = d.n_flexures
    pitch = 2 * math.pi / n
    a_left = math.atan2(t_left[1], t_left[0])
    a_right_next = math.atan2(t_right[1], t_right[0]) + pitch
    if a_right_next <= a_left:
        raise RootFilletsOverlap(
            f"spring '{d.name}': root fillets of neighbouring flexures overlap at R_r = "
            f"{d.root_radius_mm:.3g} mm (R{d.root_fillet_radius_mm:.3g} mm fillets); use fewer "
            "flexures")
    rim_arc = Arc((0.0, 0.0), d.root_radius_mm, a_left, a_right_next)
    segs, feats = [], []
    for i in range(n):
        segs.extend(s.rotated(i * pitch) for s in (*unit, rim_arc))
        feats.extend(f.reindexed(i) for f in (*unit_features, Feature("rim", 0)))
    inner = Loop(tuple(segs), tuple(feats))
    hw = d.hardware
    holes = ()
    hd = 0.0
    if hw.fastener_count > 0:
        hd = hole_diameter_mm(hw)
        holes = hole_centres_mm(n, min(hw.fastener_count, n),
                                0.5 * (d.root_radius_mm + d.outer_radius_mm))
    hole_loops = _hole_loops(holes, 0.5 * hd)
    profile = Profile(Loop((Circle((0.0, 0.0), d.outer_radius_mm),), (Feature("outer"),)),
                      (inner, *hole_loops),
                      ("outer", "flexures", *(f"hole:{j}" for j in range(len(hole_loops)))))
    return profile, holes, hd
