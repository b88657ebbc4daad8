"""Interference and cam-to-tip clearance of an assembled stack.

Every part is a pile of z-prism slabs (:mod:`springcad.geometry.base`), so two
placed parts overlap exactly when two of their slabs overlap both along z and
in the plane. The plane test uses dense boundary samples of the exact profiles:
a boundary point of one region lying inside the other region's material by more
than :data:`CONTACT_TOL_MM` is a penetration; boundaries closer than that are a
contact. For prism parts the slabs are the solid (their volumes are checked
against each other); for catalogue screws and nuts they are enclosing
cylinders and prisms, so the test errs on the safe side. The cam-to-tip
clearance is measured twice: on the sampled profiles over every flexure, and
with the kernel's exact B-rep distance on a few sectors of the placed solids.
Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.design.planar import inside_region, region_contains, sample_profile

#: boundaries closer than this touch; penetration deeper than this is an overlap (mm).
#: Covers the sampling error (h^2 / 8R = 0.05 um at h = 0.02 mm, R = 1 mm) and the
#: kernel's spline fit (~1 um).
CONTACT_TOL_MM = 0.002
#: boundary sampling step for the plane test (mm)
STEP_MM = 0.02
#: finer step near the cam-tip interface (mm): distance error < 0.1 um
TIP_STEP_MM = 0.002
#: in-plane distances are exact up to this (mm); larger ones are reported as this bound
NEAR_MM = 1.0
#: inset of the probe points that tell coincident regions from touching neighbours (mm)
PROBE_MM = 5 * CONTACT_TOL_MM


@dataclass(frozen=True)
class PairResult:
    """How two placed parts meet.

    Attributes:
        a, b: instance names.
        relation: "clear", "axial_contact" (faces touch along z), "radial_contact"
            (side faces touch), or "overlap".
        clearance_mm: smallest in-plane boundary distance where the parts share z
            (mm; None when they share no z).
        depth_mm: deepest in-plane penetration where they share z (mm; at most
            :data:`NEAR_MM`, a lower bound beyond it).
        location: (x, y, z) of the worst point (mm) or None.
    """

    a: str
    b: str
    relation: str
    clearance_mm: float | None
    depth_mm: float
    location: tuple | None


class _Region:
    """Sampled boundary polyline of one slab of a placed part.

    Keeps, per sample, the next sample on its loop and the unit normal of the
    polyline edge to it, pointing into the material; the side a point lies on
    follows from its nearest boundary edge.
    """

    def __init__(self, slab, placement):
        from scipy.spatial import cKDTree

        pts, nxt, nrm = [], [], []
        offset = 0
        for i, smp in enumerate(sample_profile(slab.region, STEP_MM)):
            p = placement.map_xy(smp.points)
            n = len(p)
            q = np.roll(p, -1, axis=0)
            t = q - p
            t /= np.linalg.norm(t, axis=1)[:, None]
            ccw = 0.5 * float(np.sum(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0])) > 0
            left = np.column_stack([-t[:, 1], t[:, 0]])
            # material inside the outer loop and outside the holes
            nrm.append(left if ccw == (i == 0) else -left)
            pts.append(p)
            nxt.append(offset + (np.arange(n) + 1) % n)
            offset += n
        self.points = np.vstack(pts)
        self.next = np.concatenate(nxt)
        self.prev = np.empty_like(self.next)
        self.prev[self.next] = np.arange(len(self.next))
        self.normals = np.vstack(nrm)
        self.tree = cKDTree(self.points)
        self.bbox = (self.points.min(axis=0), self.points.max(axis=0))
        self.slab, self.placement, self._coarse = slab, placement, None
        # points just inside the material: they tell coincident regions from neighbours
        self.probes = self.points + PROBE_MM * self.normals

    def side_distance(self, xy: np.ndarray):
        """(distance to the boundary polyline, True where inside the material) per point.

        Distances beyond :data:`NEAR_MM` are reported as NEAR_MM; the side of such
        far points comes from a coarse point-in-polygon test, which is exact that far
        from the boundary.
        """
        d0, k = self.tree.query(xy, distance_upper_bound=NEAR_MM)
        far = ~np.isfinite(d0)
        best_d = np.full(len(xy), NEAR_MM)
        best_in = np.zeros(len(xy), dtype=bool)
        if far.any():
            best_in[far] = self._inside_far(xy[far])
        near = np.flatnonzero(~far)
        if not len(near):
            return best_d, best_in
        q, kk = xy[near], k[near]
        dn = np.full(len(near), np.inf)
        inn = np.zeros(len(near), dtype=bool)
        for a in (self.prev[kk], kk):  # the two polyline edges meeting at the nearest sample
            p0, p1 = self.points[a], self.points[self.next[a]]
            e = p1 - p0
            t = np.clip(np.einsum("ij,ij->i", q - p0, e) / np.einsum("ij,ij->i", e, e), 0, 1)
            foot = p0 + t[:, None] * e
            d = np.linalg.norm(q - foot, axis=1)
            inside = np.einsum("ij,ij->i", q - foot, self.normals[a]) > 0
            better = d < dn
            dn = np.where(better, d, dn)
            inn = np.where(better, inside, inn)
        best_d[near], best_in[near] = dn, inn
        return best_d, best_in

    def _inside_far(self, xy: np.ndarray) -> np.ndarray:
        if self._coarse is None:
            self._coarse = [self.placement.map_xy(lp.sample(0.1)) for lp in self.slab.region.loops]
        return region_contains(self._coarse, xy)


def _plane_relation(ra: _Region, rb: _Region):
    """(min boundary distance, max penetration depth, worst xy) of two regions (mm)."""
    tol = CONTACT_TOL_MM
    (la, ha), (lb, hb) = ra.bbox, rb.bbox
    if np.any(la > hb + tol) or np.any(lb > ha + tol):
        gap = float(np.max(np.maximum(la - hb, lb - ha)))
        return gap, 0.0, None
    dist, worst, where = np.inf, 0.0, None
    for src, dst in ((ra, rb), (rb, ra)):
        # only points near the other region's box can touch or enter it; the rest
        # are at least NEAR_MM away (distances beyond that are reported as lower bounds)
        lo, hi = dst.bbox[0] - NEAR_MM, dst.bbox[1] + NEAR_MM
        near = np.all((src.points >= lo) & (src.points <= hi), axis=1)
        if not near.any():
            dist = min(dist, NEAR_MM)
            continue
        pts = src.points[near]
        d, inside = dst.side_distance(pts)
        k = int(np.argmin(d))
        if d[k] < dist:
            dist = float(d[k])
            if worst == 0.0:
                where = pts[k]
        deep = inside & (d > tol)
        if deep.any():
            k = int(np.flatnonzero(deep)[np.argmax(d[deep])])
            if d[k] > worst:
                worst, where = float(d[k]), pts[k]
    if worst <= tol and dist <= tol:
        # boundaries meet: the regions are neighbours unless points just inside one
        # lie inside the other (coincident or nested regions with a shared edge)
        for src, dst in ((ra, rb), (rb, ra)):
            d, inside = dst.side_distance(src.probes)
            deep = inside & (d > tol)
            if deep.any():
                k = int(np.flatnonzero(deep)[np.argmax(d[deep])])
                worst, where = max(worst, float(d[k])), src.probes[k]
    return dist, worst, where


class InterferenceChecker:
    """Pairwise relation of every two placed parts of a :class:`StackAssembly`."""

    def __init__(self, assembly):
        self.assembly = assembly
        self._regions: dict = {}
        self._plane: dict = {}
        self._radii: dict = {}

    def _region(self, inst, k):
        key = (id(inst.part), k, inst.placement.x_mm, inst.placement.y_mm,
               inst.placement.flipped, inst.placement.angle_rad)
        if key not in self._regions:  # holding the part keeps its id unique
            self._regions[key] = (inst.part, _Region(inst.part.slabs[k], inst.placement))
        return key, self._regions[key][1]

    def _radial(self, inst):
        """(r_min, r_max) of an axis-centred part's material, or None when off-axis (mm)."""
        p = inst.placement
        if p.x_mm or p.y_mm:
            return None
        key = id(inst.part)
        if key not in self._radii:
            lo, hi = np.inf, 0.0
            for slab in inst.part.slabs:
                rs = [np.hypot(*lp.sample(STEP_MM).T) for lp in slab.region.loops]
                centre_in = bool(inside_region(slab.region, np.zeros((1, 2)), STEP_MM)[0])
                lo = min(lo, 0.0 if centre_in else min(r.min() for r in rs))
                hi = max(hi, rs[0].max())
            self._radii[key] = (inst.part, (lo, hi))
        return self._radii[key][1]

    def pair(self, a, b) -> PairResult:
        """Relation of two placed parts."""
        tol = CONTACT_TOL_MM
        za, zb = a.z_range_mm, b.z_range_mm
        if za[0] > zb[1] + tol or zb[0] > za[1] + tol:
            return PairResult(a.name, b.name, "clear", None, 0.0, None)
        ra_, rb_ = self._radial(a), self._radial(b)
        if ra_ and rb_ and (ra_[0] > rb_[1] + tol or rb_[0] > ra_[1] + tol):
            return PairResult(a.name, b.name, "clear",
                              max(ra_[0] - rb_[1], rb_[0] - ra_[1]), 0.0, None)
        relation, clearance, depth, where = "clear", None, 0.0, None
        for i, sa in enumerate(a.part.slabs):
            for j, sb in enumerate(b.part.slabs):
                z0a, z1a = a.placement.map_z(sa.z0_mm, sa.z1_mm)
                z0b, z1b = b.placement.map_z(sb.z0_mm, sb.z1_mm)
                shared = min(z1a, z1b) - max(z0a, z0b)
                if shared < -tol:
                    continue
                ka, ga = self._region(a, i)
                kb, gb = self._region(b, j)
                key = (ka, kb)
                if key not in self._plane:
                    self._plane[key] = _plane_relation(ga, gb)
                dist, pen, xy = self._plane[key]
                z_mid = 0.5 * (max(z0a, z0b) + min(z1a, z1b))
                if shared <= tol:  # faces meet along z: contact when the regions overlap
                    if pen > tol and relation == "clear":
                        relation, where = "axial_contact", (*xy, z_mid)
                    continue
                clearance = dist if clearance is None else min(clearance, dist)
                if pen > tol:
                    if pen > depth:
                        depth, where = pen, (*xy, z_mid)
                    relation = "overlap"
                elif dist <= tol and relation != "overlap":
                    relation, where = "radial_contact", (*xy, z_mid)
        loc = tuple(float(v) for v in where) if where is not None else None
        return PairResult(a.name, b.name, relation, clearance, depth, loc)

    def all_pairs(self) -> list[PairResult]:
        inst = self.assembly.instances
        return [self.pair(inst[i], inst[j]) for i in range(len(inst)) for j in range(i + 1, len(inst))]


# ----------------------------------------------------------------------- cam clearance
@dataclass(frozen=True)
class ClearanceResult:
    """Cam-to-tip clearance of one ring and the camshaft that drives it (mm).

    Attributes:
        ring, camshaft: instance names.
        design_gap_mm: the designed gap w_gap.
        sampled_min_mm: minimum over every flexure from the sampled exact profiles.
        sampled_flexure: flexure index where it occurs.
        kernel_min_mm: minimum of the B-rep distances on the checked sectors.
        kernel_by_flexure: {flexure index: B-rep distance}.
    """

    ring: str
    camshaft: str
    design_gap_mm: float
    sampled_min_mm: float
    sampled_flexure: int
    kernel_min_mm: float
    kernel_by_flexure: dict


def _tip_zone(points: np.ndarray, r_lo: float, r_hi: float) -> np.ndarray:
    r = np.hypot(points[:, 0], points[:, 1])
    return points[(r >= r_lo) & (r <= r_hi)]


def _faces_with_boxes(inst):
    """The placed solid's side faces with their bounding boxes (cached on the instance)."""
    from build123d import GeomType

    cached = inst._face_boxes
    if cached is None:
        cached = []
        for f in inst.shape.faces():
            if f.geom_type == GeomType.PLANE and abs(abs(f.normal_at().Z) - 1.0) < 1e-9:
                continue  # end faces span the whole part; the gap lies between side faces
            bb = f.bounding_box()
            cached.append((f, (bb.min.X, bb.min.Y, bb.min.Z, bb.max.X, bb.max.Y, bb.max.Z)))
        inst._face_boxes = cached
    return cached


def _select(faces, box):
    """Faces whose bounding box meets ``box`` = (xmin, ymin, zmin, xmax, ymax, zmax)."""
    return [f for f, b in faces
            if all(b[k] <= box[k + 3] and b[k + 3] >= box[k] for k in range(3))]


def _tip_samples(loop, samples: dict | None) -> np.ndarray:
    """``loop`` sampled every :data:`TIP_STEP_MM` in its part's frame (mm), kept in
    ``samples`` (by the loop's identity, the loop held) when given: two rings of one part,
    or two camshafts, are sampled once (the ring's flexures: ~10^6 points)."""
    if samples is None:
        return loop.sample(TIP_STEP_MM)
    if id(loop) not in samples:
        samples[id(loop)] = (loop, loop.sample(TIP_STEP_MM))
    return samples[id(loop)][1]


def cam_clearance(ring_inst, cam_inst, sectors: int = 2,
                  samples: dict | None = None) -> ClearanceResult:
    """Measure the gap between a placed flexure ring and its placed camshaft.

    The sampled profiles give the minimum over every flexure; the kernel distance
    is taken on ``sectors`` evenly spaced flexure tips, starting at the one where
    the sampled minimum lies. ``samples``: a dict the tip loops' samples are kept in
    between calls on the same parts (:func:`_tip_samples`), or None.
    """
    import build123d as bd
    from scipy.spatial import cKDTree

    ring, cam = ring_inst.part, cam_inst.part
    n = ring.n_flexures
    r_lo, r_hi = ring.contact_radius - 2 * ring.tip_radius - 0.2, cam.tip_radius + 0.3
    rp = _tip_zone(ring_inst.placement.map_xy(_tip_samples(ring.spring.ring.loop("flexures"),
                                                           samples)), r_lo, r_hi)
    cp = _tip_zone(cam_inst.placement.map_xy(_tip_samples(cam.info.cut_profile.loop("teeth"),
                                                          samples)), r_lo, r_hi)
    d, _ = cKDTree(cp).query(rp)
    k = int(np.argmin(d))
    pitch = 2 * math.pi / n
    flex = int(round((math.atan2(rp[k, 1], rp[k, 0]) - math.pi / 2) / pitch)) % n
    # exact B-rep distance between the placed solids' side faces near a few flexure tips
    z0 = max(ring_inst.z_range_mm[0], cam_inst.z_range_mm[0])
    z1 = min(ring_inst.z_range_mm[1], cam_inst.z_range_mm[1])
    ring_faces, cam_faces = _faces_with_boxes(ring_inst), _faces_with_boxes(cam_inst)
    by_flexure = {}
    for i in sorted({(flex + (j * n) // sectors) % n for j in range(sectors)}):
        a = math.pi / 2 + i * pitch
        centre = (ring.contact_radius * math.cos(a), ring.contact_radius * math.sin(a))
        half = 0.5 * pitch * ring.contact_radius + ring.tip_radius
        box = (centre[0] - half, centre[1] - half, z0, centre[0] + half, centre[1] + half, z1)
        near_r, near_c = _select(ring_faces, box), _select(cam_faces, box)
        by_flexure[i] = float(bd.Compound(near_r).distance_to(bd.Compound(near_c)))
    return ClearanceResult(ring_inst.name, cam_inst.name, ring.spring.manufacturing.w_gap_mm,
                           float(d[k]), flex, min(by_flexure.values()), by_flexure)
