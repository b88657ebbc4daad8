"""Wire-EDM manufacturability rules on a part's exact 2D cutting profile.

Rules (limits from ``[manufacturing]``):

* ``inside_corner_radius``: every corner that is concave for the material (the
  wire sits in the void outside it) needs a radius of at least wire radius +
  spark gap. Sharp concave joins count as radius 0. Convex (outside) corners
  may be sharp.
* ``min_slot_width``: the void between two boundary stretches that face each
  other (not neighbours along the contour) must be at least ``min_slot_width_mm``.
* ``min_web``: the material between two such stretches must be at least
  ``min_web_mm`` (flexure necks, ligaments, tooth tips).
* ``hole_edge``: a round hole keeps ``min_hole_edge_mm`` of material to every
  other contour.

"Facing each other" means: the straight line between the two boundary points
crosses only void or only material, and walking along the contour from one to
the other is more than twice as long as that line. A convex or concave arc never
faces itself (walk / chord <= pi/2), a slot or web with any parallel stretch does.
Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.curves import Profile
from springcad.design.planar import material_on_left, sample_profile

#: walk along the contour / straight distance above which two boundary points face each other
FACING_RATIO = 2.0
#: sampling step of the pair search (mm): parallel-edge distances are overestimated by
#: at most (step/2)^2 / (2 width) = 0.5 um at 0.4 mm
PAIR_STEP_MM = 0.04
#: pairs processed at once by the facing-pair search (bounds its arrays to a few MB)
PAIR_BLOCK = 2 ** 16
#: sampling step for curvature and hole distances (mm)
CURVE_STEP_MM = 0.01
#: a concave kink is a violation when the wire leaves more material in it than this
#: fraction of the part's profile tolerance (smaller kinks cannot show on the part)
KINK_TOLERANCE_FRACTION = 0.1


@dataclass(frozen=True)
class RuleResult:
    """One rule applied to one part: the measured extreme and every violation.

    Attributes:
        rule: rule name.
        limit_mm: the limit from the config (mm).
        value_mm: measured extreme over the part (mm); None when nothing was in range
            (then the true value exceeds ``searched_to_mm``).
        searched_to_mm: the search radius for pair rules (mm), else None.
        violations: tuple of dicts with value_mm, x_mm, y_mm, r_mm, angle_deg, feature.
        notes: findings that are not violations (e.g. slightly non-tangent joins).
        loss_mm: the values (and violations) are worst-case ones, this much below what
            was measured on the nominal profile (the tolerances' share, mm); 0: nominal.
    """

    rule: str
    limit_mm: float
    value_mm: float | None
    searched_to_mm: float | None
    violations: tuple
    notes: tuple = ()
    loss_mm: float = 0.0

    @property
    def passed(self) -> bool:
        return not self.violations


def _location(x, y, describe) -> dict:
    return {"x_mm": float(x), "y_mm": float(y), "r_mm": float(math.hypot(x, y)),
            "angle_deg": float(math.degrees(math.atan2(y, x))), "feature": describe(x, y)}


def _clusters(points: np.ndarray, radius: float) -> np.ndarray:
    """Connected-component label of each point (points closer than ``radius`` join)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(radius, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def _worst_per_cluster(values, xy, radius, describe, keep) -> tuple:
    """One violation (the worst sample) per spatial cluster of the samples with ``keep``."""
    idx = np.flatnonzero(keep)
    if not len(idx):
        return ()
    labels = _clusters(xy[idx], radius)
    out = []
    for lab in np.unique(labels):
        members = idx[labels == lab]
        k = members[np.argmin(values[members])]
        out.append({"value_mm": float(values[k]), **_location(*xy[k], describe)})
    return tuple(sorted(out, key=lambda v: ((v["angle_deg"] - 90.0) % 360.0, v["r_mm"])))


def inside_corner_rule(profile: Profile, min_radius_mm: float, kink_limit_mm: float,
                       describe) -> RuleResult:
    """Smallest radius of every material-concave stretch and concave kink.

    A join whose tangents differ by a turn delta is a sharp corner; if it is
    concave for the material, a wire of radius rho leaves rho (sec(delta/2) - 1)
    of material in it. Kinks leaving more than ``kink_limit_mm`` are violations
    (radius 0); smaller ones (a slightly non-tangent fillet) are listed as notes,
    since the part cannot show them within its tolerance.
    """
    samples = sample_profile(profile, CURVE_STEP_MM)
    radii, xy, notes = [], [], []
    for i, smp in enumerate(samples):
        side = 1.0 if material_on_left(smp, i == 0) else -1.0
        concave = side * smp.curvature < 0
        radii.append(np.where(concave, 1.0 / np.maximum(np.abs(smp.curvature), 1e-12), np.inf))
        xy.append(smp.points)
        for _, x, y, turn in smp.corners:
            inside = side * turn < 0
            left = min_radius_mm * (1.0 / math.cos(0.5 * abs(turn)) - 1.0) if inside else 0.0
            if inside and left > kink_limit_mm:
                radii.append(np.zeros(1))
                xy.append(np.array([[x, y]]))
            else:
                notes.append({"turn_deg": math.degrees(turn), "inside": bool(inside),
                              "uncut_mm": left, **_location(x, y, describe)})
    radii, xy = np.concatenate(radii), np.vstack(xy)
    bad = radii < min_radius_mm * (1 - 1e-9)
    value = float(radii.min()) if np.isfinite(radii.min()) else None
    return RuleResult("inside_corner_radius", min_radius_mm, value, None,
                      _worst_per_cluster(radii, xy, 0.05, describe, bad), tuple(notes))


def _facing_pairs(profile: Profile, search_mm: float):
    """Boundary point pairs closer than ``search_mm`` that face each other.

    A pair spans material when the line from each point to the other leaves
    that point into the material (positive dot product with the inward normal),
    and void when it leaves both into the void; mixed pairs are not a web or slot.

    Returns:
        (distance, midpoint xy, in_material mask) for every facing pair.
    """
    from scipy.spatial import cKDTree

    samples = sample_profile(profile, PAIR_STEP_MM)
    pts = np.vstack([s.points for s in samples])
    # unit normal pointing into the material: left normal when the material is on the left
    normals = np.vstack([
        (1.0 if material_on_left(s, i == 0) else -1.0)
        * np.column_stack([-s.tangents[:, 1], s.tangents[:, 0]])
        for i, s in enumerate(samples)])
    loop = np.concatenate([np.full(len(s.points), i) for i, s in enumerate(samples)])
    arc = np.concatenate([s.s for s in samples])
    length = np.array([s.length for s in samples])
    pairs = cKDTree(pts).query_pairs(search_mm, output_type="ndarray")
    if not len(pairs):
        return np.empty(0), np.empty((0, 2)), np.empty(0, dtype=bool)
    # in blocks of pairs: the default ring's 1.3 M pairs held a dozen arrays of that length
    # at once (~120 MB, the build's peak while the FEA outputs are written beside it); every
    # number is computed per pair, so the blocks give the same arrays
    parts = [_facing_block(pairs[k:k + PAIR_BLOCK], pts, normals, loop, arc, length)
             for k in range(0, len(pairs), PAIR_BLOCK)]
    return tuple(np.concatenate(x) for x in zip(*parts))


def _facing_block(pairs: np.ndarray, pts, normals, loop, arc, length):
    """:func:`_facing_pairs` on one block of pairs (index arrays into the samples)."""
    a, b = pairs[:, 0], pairs[:, 1]
    d = pts[b] - pts[a]
    dist = np.linalg.norm(d, axis=1)
    walk = np.abs(arc[a] - arc[b])
    walk = np.minimum(walk, length[loop[a]] - walk)
    facing = (loop[a] != loop[b]) | (walk > FACING_RATIO * dist)
    into_a = np.einsum("ij,ij->i", d, normals[a])
    into_b = -np.einsum("ij,ij->i", d, normals[b])
    material = facing & (into_a > 0) & (into_b > 0)
    void = facing & (into_a < 0) & (into_b < 0)
    keep = material | void
    a, b = a[keep], b[keep]
    return dist[keep], 0.5 * (pts[a] + pts[b]), material[keep]


def gap_rules(profile: Profile, min_web_mm: float, min_slot_mm: float, describe):
    """``min_web`` and ``min_slot_width`` results from one pair search."""
    search = 2.0 * max(min_web_mm, min_slot_mm)
    dist, mid, material = _facing_pairs(profile, search)
    out = []
    for rule, limit, mask in (("min_web", min_web_mm, material),
                              ("min_slot_width", min_slot_mm, ~material)):
        d, m = dist[mask], mid[mask]
        value = float(d.min()) if len(d) else None
        out.append(RuleResult(rule, limit, value, search,
                              _worst_per_cluster(d, m, 0.3, describe, d < limit * (1 - 1e-9))))
    return out


def hole_edge_rule(profile: Profile, min_edge_mm: float, describe) -> RuleResult:
    """Material between every round hole and every other contour."""
    from scipy.spatial import cKDTree

    loops = profile.loops
    holes = [i for i, lp in enumerate(loops) if i > 0 and lp.is_circle]
    if not holes:
        return RuleResult("hole_edge", min_edge_mm, None, None, ())
    pts = [lp.sample(CURVE_STEP_MM) for lp in loops]
    trees: dict[int, cKDTree] = {}  # one per loop, each built once (not per hole)
    values, xy = [], []
    for i in holes:
        # nearest point of every other loop: the nearest of their union
        d = np.full(len(pts[i]), np.inf)
        near = np.zeros_like(pts[i])
        for j, p in enumerate(pts):
            if j == i:
                continue
            if j not in trees:
                trees[j] = cKDTree(p)
            dj, kj = trees[j].query(pts[i])
            closer = dj < d
            d[closer], near[closer] = dj[closer], p[kj[closer]]
        j = int(np.argmin(d))
        values.append(float(d[j]))
        xy.append(0.5 * (pts[i][j] + near[j]))
    values, xy = np.asarray(values), np.asarray(xy)
    bad = values < min_edge_mm * (1 - 1e-9)
    viol = tuple({"value_mm": float(v), **_location(*p, describe)}
                 for v, p, b in zip(values, xy, bad) if b)
    return RuleResult("hole_edge", min_edge_mm, float(values.min()), None, viol)


def edm_rules(profile: Profile, manufacturing, tolerance_mm: float,
              describe=lambda x, y: "") -> list[RuleResult]:
    """Apply every wire-EDM rule of ``manufacturing`` to a cutting profile.

    Args:
        profile: the part's 2D cutting profile (mm).
        manufacturing: a :class:`~springcad.config.ManufacturingSpec`.
        tolerance_mm: the part's profile tolerance (mm); sets the kink limit.
        describe: ``(x, y) -> str`` naming the feature at a location (e.g. "flexure 3").
    """
    m = manufacturing
    return [inside_corner_rule(profile, m.min_inside_radius_mm,
                               KINK_TOLERANCE_FRACTION * tolerance_mm, describe),
            *gap_rules(profile, m.min_web_mm, m.min_slot_width_mm, describe),
            hole_edge_rule(profile, m.min_hole_edge_mm, describe)]
