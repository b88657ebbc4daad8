"""The contact solver: rigid cam against the elastic flexure sector.

Node-to-surface contact of the sector's boundary nodes with a rigid cam
contour sampled every :data:`CAM_STEP_MM` (closest-point projection; the
normal is interpolated between vertex normals so that it is continuous as a
node slides over the polyline: a piecewise-constant normal makes the
conformal ball-in-pocket contact cycle between two states 10 nm apart).

Each cam angle is solved by Newton's method on the (linear or total
Lagrangian) elasticity combined with a primal-dual active set for the
contact conditions g >= 0, lambda >= 0, lambda g = 0: per iteration the
tangent is factorised once, the active constraints (typically 1-4 nodes) are
eliminated through their Schur complement, and the active set is updated
(nodes with negative force leave it, penetrating nodes join it) until it no
longer changes and the displacement increment is below 1e-9 mm.
Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fea.nonlinear import internal_force, nodal_von_mises_green
from fea.problem import LoadCase, assemble
from fea.results import nodal_von_mises
from springcad.design.contact_stress import line_contact
from springcad.errors import SolverError

#: cam contour sampling step for the closest-point projection (mm)
CAM_STEP_MM = 1e-3
#: penetration accepted at convergence (mm)
PENETRATION_TOL_MM = 1e-7
#: displacement increment at convergence (mm)
INCREMENT_TOL_MM = 1e-7
#: out-of-balance force at convergence, relative to the total contact force (min 1 N)
RESIDUAL_TOL = 1e-7
#: the nonlinear tangent is re-factorised when the state moved this far from it (mm)
REFACTOR_MM = 0.2
#: beyond this distance from the nominal cam the normal of a dilated cam is the direction
#: from the nearest point (mm); nearer, the interpolated vertex normal
OFFSET_NORMAL_MM = 1e-4
#: contact points per quadratic boundary edge (nodes included)
POINTS_PER_EDGE = 8
#: candidates nearer than this to the cam enter each iteration's complementarity problem (mm)
NEAR_MM = 0.01
#: round-off allowance of :meth:`_Segments.min_distance`'s bound on a projected distance
#: (mm): far above the ~1e-14 mm of a foot point's own rounding, far below any gap reported
BOX_SLACK_MM = 1e-9


def lcp(M: np.ndarray, q: np.ndarray) -> np.ndarray:
    """lambda >= 0 with w = q + M lambda >= 0 and lambda . w = 0, M symmetric positive definite.

    Equivalent to min 1/2 l.M.l + q.l over l >= 0, which with M = L L^T is the
    non-negative least-squares problem min |L^T l + L^-1 q| (Lawson-Hanson: exact,
    finite).
    """
    from scipy.linalg import cholesky, solve_triangular
    from scipy.optimize import nnls

    if not np.any(q < 0):
        return np.zeros_like(q)
    scale = float(np.mean(np.abs(np.diag(M))))
    # several points on one quadratic facet can make M singular: a 1e-10 relative contact
    # compliance keeps it definite without changing the solution measurably
    try:
        L = cholesky(M / scale + 1e-10 * np.eye(len(q)), lower=True)
    except np.linalg.LinAlgError as err:  # an indefinite tangent: a diverged iterate
        raise SolverError("contact compliance is not positive definite (the tangent "
                          "stiffness of this iterate is indefinite)") from err
    rhs = -solve_triangular(L, q / scale, lower=True)
    lam, _ = nnls(L.T, rhs, maxiter=50 * len(q))
    return lam


def rot(a: float) -> np.ndarray:
    """2D rotation matrix by ``a`` (rad)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


# ============================================================ polylines
class _Segments:
    """Straight segments A->B with optional outward normals: closest points (mm)."""

    def __init__(self, A: np.ndarray, B: np.ndarray, normals: np.ndarray | None = None,
                 k: int = 8):
        from scipy.spatial import cKDTree

        self.A, self.B = np.asarray(A, float), np.asarray(B, float)
        d = self.B - self.A
        self.len = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        self.T = d / self.len[:, None]
        self.normals = normals
        # uncompacted nodes: the same exact neighbours, found ~1.5x faster for points far from
        # a dense polyline (the cam's 1 um segments), the common query here
        self.tree = cKDTree(0.5 * (self.A + self.B), compact_nodes=False)
        self.k = min(k, len(self.A))  # nearest midpoints searched (3 for equal segments)

    def project(self, q: np.ndarray):
        """(distance, signed distance or None, foot (m, 2), segment index, t (mm along it))."""
        q = np.atleast_2d(q)
        _, idx = self.tree.query(q, k=self.k)
        idx = idx.reshape(len(q), -1)
        a = self.A[idx]
        t = np.clip(np.einsum("mkj,mkj->mk", q[:, None, :] - a, self.T[idx]), 0.0,
                    self.len[idx])
        foot = a + t[..., None] * self.T[idx]
        dist = np.linalg.norm(q[:, None, :] - foot, axis=2)
        best = np.argmin(dist, axis=1)
        rows = np.arange(len(q))
        seg, foot, t, dist = idx[rows, best], foot[rows, best], t[rows, best], dist[rows, best]
        signed = None
        if self.normals is not None:
            side = np.einsum("ij,ij->i", q - foot, self.normals[seg])
            signed = np.where(side < 0, -dist, dist)
        return dist, signed, foot, seg, t

    def min_distance(self, q: np.ndarray, below: float = math.inf) -> float:
        """``min(below, project(q)[0].min())`` (mm), projecting only the points that can
        come nearer than ``below``: the same number, bit for bit, at a fraction of the cost
        when most points are far (a cam surface against one flexure). A foot point lies on
        its segment, so a point whose nearest segment midpoint is farther than ``below`` +
        half the longest segment (+ :data:`BOX_SLACK_MM` for round-off) projects farther
        than ``below``."""
        q = np.atleast_2d(q)
        if below < 0.0:  # a distance is never negative
            return below
        if not math.isfinite(below):  # nothing to prune against
            return float(self.project(q)[0].min())
        half = 0.5 * float(self.len.max())
        reach = below + half + BOX_SLACK_MM
        d_mid, _ = self.tree.query(q, k=1, distance_upper_bound=reach)
        keep = d_mid <= reach
        if keep.any():
            below = min(below, float(self.project(q[keep])[0].min()))
        return below


# ============================================================ the rigid cam
class CamCurve:
    """The cam contour around pocket 0 as a dense polyline with named features (cam frame, mm).

    Args:
        features: (kind, pocket k, segment) in contour order: kinds "flank_ccw",
            "pocket", "flank_cw", "tip" (see :func:`fea.contact._cam_features`).
        ccw: the contour runs counter-clockwise (material on its left).
        junction_mm: pocket arc next to the flank start that counts as the flank start (mm).
    """

    def __init__(self, features, ccw: bool, junction_mm: float, step_mm: float = CAM_STEP_MM):
        pts, fid, s = [], [], []
        self.features = list(features)
        self.lengths = []
        for j, (_kind, _k, seg) in enumerate(self.features):
            p = seg.sample(step_mm)
            cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
            self.lengths.append(float(cum[-1]))
            if pts:  # the start point is the previous segment's end point
                p, cum = p[1:], cum[1:]
            pts.append(p)
            fid.append(np.full(len(p), j))
            s.append(cum)
        self.P = np.vstack(pts)
        self.fid = np.concatenate(fid)
        self.s = np.concatenate(s)
        d = np.diff(self.P, axis=0)
        T = d / np.linalg.norm(d, axis=1)[:, None]
        self.N = np.column_stack([T[:, 1], -T[:, 0]]) * (1.0 if ccw else -1.0)
        self.all = _Segments(self.P[:-1], self.P[1:], self.N, k=3)
        self.outer_radius_mm = float(np.max(np.hypot(self.P[:, 0], self.P[:, 1])))
        # vertex normals: the normal interpolated along a segment between them is continuous,
        # so a node sliding over a vertex of the polyline sees no jump of the contact normal
        nv = np.vstack([self.N[:1], self.N[:-1] + self.N[1:], self.N[-1:]])
        self.Nv = nv / np.linalg.norm(nv, axis=1)[:, None]
        # signed curvature per vertex (positive convex), from points +-5 um apart
        k = max(1, round(5e-3 / step_mm))
        a, b, c = self.P[:-2 * k], self.P[k:-k], self.P[2 * k:]
        cross = ((b[:, 0] - a[:, 0]) * (c[:, 1] - b[:, 1])
                 - (b[:, 1] - a[:, 1]) * (c[:, 0] - b[:, 0]))
        den = (np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1)
               * np.linalg.norm(c - a, axis=1))
        curv = 2 * cross / np.maximum(den, 1e-300) * (1.0 if ccw else -1.0)
        self.curvature = np.concatenate([np.full(k, curv[0]), curv, np.full(k, curv[-1])])
        self.junction_mm = junction_mm
        self.offset_mm = 0.0

    def dilated(self, offset_mm: float) -> "CamCurve":
        """This cam grown by ``offset_mm`` normal to its surface (negative: shrunk): the
        contact sees the Minkowski offset (gap = distance - offset, the normal from the
        nearest point, so a sharp corner grows round), the polyline stays the nominal one.
        A ring and a cam whose profiles deviate by e_ring and e_cam touch as the nominal
        ring against the cam dilated by e_ring + e_cam."""
        import copy

        out = copy.copy(self)
        out.offset_mm = float(offset_mm)
        return out

    def index(self, kind: str, k: int = 0) -> int:
        return next(j for j, (kd, kk, _) in enumerate(self.features) if kd == kind and kk == k)

    def project(self, q: np.ndarray):
        """Signed distance (positive outside the cam), outward normal, foot point, segment, t."""
        dist, signed, foot, seg, t = self.all.project(q)
        # the contour is an open chain (pockets -2..2): beyond the tooth tips nothing is
        # inside the cam, whatever side of a chain end a far point projects to
        signed = np.where(np.hypot(q[:, 0], q[:, 1]) > self.outer_radius_mm, np.abs(signed),
                          signed)
        w = (t / self.all.len[seg])[:, None]
        n = (1 - w) * self.Nv[seg] + w * self.Nv[seg + 1]
        n = n / np.linalg.norm(n, axis=1)[:, None]
        if self.offset_mm:  # the offset surface's normal: from the nearest point (round corners)
            far = dist > OFFSET_NORMAL_MM
            radial = (q - foot) * (np.sign(signed) / np.maximum(dist, 1e-300))[:, None]
            n = np.where(far[:, None], radial, n)
            signed = signed - self.offset_mm
        return signed, n, foot, seg, t

    def groups(self, driving: str) -> dict:
        """Segments of every surface other than the driving flank, by name (for gaps)."""
        ccw = driving == "flank_ccw"
        back = "flank_cw" if ccw else "flank_ccw"
        j_drive, j_back = self.index(driving), self.index(back)
        j_pocket = self.index("pocket")
        tip_drive = self.index("tip", -1 if ccw else 0)
        tip_back = self.index("tip", 0 if ccw else -1)
        seg_f = self.fid[:-1]
        s_seg = self.s[:-1]
        pocket = seg_f == j_pocket
        dist_to_cusp = s_seg if ccw else self.lengths[j_pocket] - s_seg
        lo, hi = min(tip_drive, tip_back), max(tip_drive, tip_back)
        # the pocket's driving half continues the driving flank (one cut, tangent at the
        # cusp): a gap there is to the contact pair's own surface (fea.contact_tolerance)
        half = 0.5 * self.lengths[j_pocket]
        masks = {"driving_flank": seg_f == j_drive,
                 "driving_pocket": pocket & (dist_to_cusp > self.junction_mm)
                 & (dist_to_cusp <= half),
                 "pocket": pocket & (dist_to_cusp > max(self.junction_mm, half)),
                 "back_flank": seg_f == j_back,
                 "driving_tooth_tip": seg_f == tip_drive,
                 "back_tooth_tip": seg_f == tip_back,
                 "teeth_beyond_driving" if ccw else "teeth_beyond_back": seg_f < lo,
                 "teeth_beyond_back" if ccw else "teeth_beyond_driving": seg_f > hi}
        return {name: _Segments(self.P[:-1][m], self.P[1:][m], self.N[m], k=3)
                for name, m in masks.items() if m.any()}

    def describe(self, seg: int, t: float, driving: str) -> dict:
        """Feature of a foot point and its position along the driving flank (mm)."""
        j = int(self.fid[seg])
        kind, k, _ = self.features[j]
        s = float(self.s[seg] + t)
        length = self.lengths[j]
        drive = self.index(driving)
        kappa = float(self.curvature[seg])  # the offset surface: 1/(R + offset)
        out = {"feature": f"{kind}:{k}",
               "cam_curvature_per_mm": kappa / (1.0 + kappa * self.offset_mm)}
        if j == drive:  # distance from the driving flank's start (its cusp on the pocket arc)
            from_cusp = length - s if driving == "flank_ccw" else s
            out.update(flank_position_mm=from_cusp, flank_length_mm=length,
                       flank_fraction=from_cusp / length, flank_margin_mm=length - from_cusp)
        elif j == self.index("pocket"):
            to_cusp = s if driving == "flank_ccw" else length - s
            out.update(flank_position_mm=-to_cusp, flank_length_mm=self.lengths[drive],
                       flank_fraction=-to_cusp / self.lengths[drive])
        return out

    def intended(self, info: dict, driving: str) -> bool:
        """Ball on the driving flank of pocket 0, or on the pocket arc at the flank start."""
        if info["feature"] == f"{driving}:0":
            return True
        return info["feature"] == "pocket:0" and info["flank_position_mm"] >= -self.junction_mm


# ============================================================ Hertz line contact
def hertz_line_contact(line_load_N_per_mm: float, curvature_sum_per_mm: float,
                       youngs_modulus_MPa: float, poisson_ratio: float) -> dict:
    """Hertz contact of two parallel elastic cylinders of the same material (plane strain):
    :func:`springcad.design.contact_stress.line_contact` as a dict (p0_MPa, half_width_mm,
    von_mises_max_MPa, depth_mm, radius_mm, max_shear_MPa); zero stresses without load or
    for a conformal (non-Hertzian) pair, curvature sum <= 0."""
    if line_load_N_per_mm <= 0 or curvature_sum_per_mm <= 0:
        return {"p0_MPa": 0.0, "half_width_mm": 0.0, "von_mises_max_MPa": 0.0,
                "depth_mm": 0.0, "radius_mm": math.inf if curvature_sum_per_mm <= 0 else
                1 / curvature_sum_per_mm, "max_shear_MPa": 0.0}
    c = line_contact(line_load_N_per_mm, curvature_sum_per_mm, youngs_modulus_MPa,
                     poisson_ratio)
    return {"p0_MPa": c.p0_MPa, "half_width_mm": c.half_width_mm,
            "von_mises_max_MPa": c.von_mises_max_MPa, "depth_mm": c.depth_mm,
            "radius_mm": c.radius_mm, "max_shear_MPa": c.max_shear_MPa}


# ============================================================ the sector
@dataclass
class State:
    """Converged contact state at one cam angle.

    Attributes:
        theta: cam angle (rad).
        u: displacement DOF vector of the sector (mm).
        active: indices (into the candidate nodes) of the active contacts.
        lam: contact force magnitude per candidate node (N), zero when inactive.
        normals: (m, 2) contact normals (ring frame, from the cam into the ring).
        gaps: (m,) signed gaps (mm).
        foot_seg, foot_t: closest cam polyline segment and distance along it.
        iterations: Newton / active-set iterations.
    """

    theta: float
    u: np.ndarray
    active: np.ndarray
    lam: np.ndarray
    normals: np.ndarray
    gaps: np.ndarray
    foot_seg: np.ndarray
    foot_t: np.ndarray
    iterations: int = 0


class SectorContact:
    """The verification's 2D sector (outer rim held) against a rigid cam.

    Args:
        fm: 2D :class:`~fea.mesh.FeaMesh` of the sector.
        material: :class:`~fea.problem.Material`.
        cam: :class:`CamCurve`.
        reach_mm: boundary nodes (ball, neck, edges) closer than this to the axis are
            contact candidates.
        nonlinear: total Lagrangian (large rotations) instead of linear kinematics.
    """

    def __init__(self, fm, material, cam: CamCurve, reach_mm: float, nonlinear: bool = True):
        from scipy.spatial import cKDTree

        self.fm, self.cam, self.nonlinear = fm, cam, nonlinear
        self.system = system = assemble(fm, material, LoadCase())
        self.basis = basis = system.basis
        n = system.A.shape[0]
        self.free = np.setdiff1d(np.arange(n), system.fixed)
        self.pos = np.full(n, -1)
        self.pos[self.free] = np.arange(len(self.free))
        self._lu_linear = self._factor(system.A.tocsr()[self.free][:, self.free])
        # the linear FEA of this very mesh (traction patch): the reference stiffness
        f = system.f[self.free]
        u_t = self._lu_linear.solve(f)
        self.stiffness_linear = system.torque_Nmm ** 2 / float(f @ u_t) * \
            fm.geometry.n_flexures
        self.u_traction = np.zeros(n)  # unit torque per flexure (mm)
        self.u_traction[self.free] = u_t
        self.X = basis.doflocs[:2]
        self.facets = {lab: fc for lab, fc in fm.boundaries.items()
                       if lab.split(":")[0] in ("ball", "neck", "edge")}
        self._contact_points(reach_mm)
        held = np.unique(system.held // 2)
        d_held, _ = cKDTree(self.X[:, held].T).query(self.X.T)
        self.near_held = d_held < 0.5 * fm.geometry.rim_thickness_mm
        self._lu, self._u_lu = None, None
        self._cache_lu, self._cache = None, {}
        self.factorisations = 0
        self.log: list[tuple] = []  # (theta, iterations, active set sizes) per solve

    def reset(self, cam: CamCurve | None = None) -> None:
        """Forget the factorisations kept between solves (the tangent matrix reused by
        Newton's method and the contact points' cached columns), and set the cam (default:
        the one it has): the solves that follow give the numbers a new model gives, bit for
        bit, whatever was solved before."""
        self._lu, self._u_lu = None, None
        self._cache_lu, self._cache = None, {}
        if cam is not None:
            self.cam = cam

    # ------------------------------------------------------------ mesh helpers

    def facet_nodes(self, facets) -> np.ndarray:
        """(3, m) vertex, vertex, mid-edge node of quadratic boundary facets."""
        mesh = self.basis.mesh
        v = self.basis.nodal_dofs[0][mesh.facets[:, facets]]
        return np.vstack([v, self.basis.facet_dofs[0][facets]])

    def _contact_points(self, reach_mm: float) -> None:
        """Contact points on the quadratic boundary facets within reach of the cam: the
        nodes and :data:`POINTS_PER_EDGE` - 1 points between them on each edge, so a
        contact travels along the ball in small steps (a node-only contact jumps by half an
        element edge, which shows as +-1 % noise in the tangent stiffness). A
        point's position and its force use the facet's shape functions N_a(s)."""
        p = POINTS_PER_EDGE
        s = np.linspace(0.0, 1.0, p + 1)
        N = np.stack([(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)], axis=1)
        pn, pw, lab, seen = [], [], [], set()
        for name, fc in self.facets.items():
            nodes = self.facet_nodes(fc).T  # (m, 3)
            keep = np.hypot(*self.X[:, nodes].reshape(2, -1)).reshape(-1, 3).min(1) < reach_mm
            for tri in nodes[keep]:
                for k in range(p + 1):
                    key = (int(tri[0]),) if k == 0 else (int(tri[1]),) if k == p else \
                        (int(tri[2]),) if 2 * k == p else (int(tri[0]), int(tri[1]), k)
                    if key in seen:
                        continue
                    seen.add(key)
                    pn.append(tri)
                    pw.append(N[k])
                    lab.append(name)
        if not pn:
            raise SolverError("no flexure boundary within reach of the cam")
        self.pnodes = np.asarray(pn, dtype=int)
        self.pweights = np.asarray(pw)
        self.plabels = np.asarray(lab, dtype=object)
        self.pX = np.einsum("pa,dpa->pd", self.pweights, self.X[:, self.pnodes])
        self.nodes = np.unique(self.pnodes)
        if np.any(self.pos[2 * self.nodes] < 0):
            raise SolverError("a contact candidate node is held: the cam would touch the support")

    def boundary(self, u: np.ndarray | None, per_facet: int = 6,
                 part: str | None = None) -> _Segments:
        """The (deformed) flexure boundary (ball, neck, edges, or only ``part``, e.g.
        "ball") as short straight segments."""
        s = np.linspace(0.0, 1.0, per_facet + 1)
        N = np.array([(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)])
        x = self.X if u is None else self.X + u.reshape(-1, 2).T
        facets = [fc for lab, fc in self.facets.items()
                  if part is None or lab.split(":")[0] == part]
        nodes = self.facet_nodes(np.concatenate(facets))
        P = np.einsum("ak,dam->mkd", N, x[:, nodes])
        return _Segments(P[:, :-1].reshape(-1, 2), P[:, 1:].reshape(-1, 2))

    def positions(self, u: np.ndarray) -> np.ndarray:
        """Current positions of the contact points, (m, 2) (mm)."""
        x = self.X + u.reshape(-1, 2).T
        return np.einsum("pa,dpa->pd", self.pweights, x[:, self.pnodes])

    # ------------------------------------------------------------ elasticity
    @staticmethod
    def _factor(K):
        from scipy.sparse.linalg import splu

        return splu(K.tocsc(), permc_spec="MMD_AT_PLUS_A")

    def _internal(self, u: np.ndarray, refactor: bool):
        """Internal force (free DOFs) and a factorised Jacobian: the linear stiffness, or the
        tangent at a nearby state (re-factorised when ``refactor`` or when ``u`` moved more
        than :data:`REFACTOR_MM` from it; Newton then converges linearly at a rate of the
        tangent's change, ~1e-3 per iteration here, at a fraction of the cost)."""
        A = self.system.A
        if not self.nonlinear:
            return (A @ u)[self.free], self._lu_linear
        s = self.system
        stale = self._lu is None or float(np.max(np.abs(u - self._u_lu))) > REFACTOR_MM
        f, K = internal_force(self.basis, u, s.lam, s.mu, s.thickness_mm,
                              tangent=refactor or stale)
        if K is not None:
            self._lu = self._factor(K[self.free][:, self.free])
            self._u_lu = u.copy()
            self.factorisations += 1
        return f[self.free], self._lu

    def internal_full(self, u: np.ndarray) -> np.ndarray:
        """Internal force on every DOF (N): the reactions at the held DOFs."""
        if not self.nonlinear:
            return self.system.A @ u
        s = self.system
        return internal_force(self.basis, u, s.lam, s.mu, s.thickness_mm, tangent=False)[0]

    def von_mises(self, u: np.ndarray) -> np.ndarray:
        """Nodal von Mises stress (MPa): of the Green-Lagrange strain when nonlinear."""
        if self.nonlinear:
            return nodal_von_mises_green(self.system, u)
        return nodal_von_mises(self.system, u)[0]

    # ------------------------------------------------------------ contact
    def _gaps(self, u: np.ndarray, theta: float):
        R = rot(theta)
        g, n_cam, _, seg, t = self.cam.project(self.positions(u) @ R)  # x @ R == R^-1 x rows
        return g, n_cam @ R.T, seg, t

    def rest(self) -> State:
        u = np.zeros(2 * self.basis.N)
        g, n, seg, t = self._gaps(u, 0.0)
        return State(0.0, u, np.zeros(0, int), np.zeros(len(self.pX)), n, g, seg, t)

    def solve(self, theta: float, start: State, predictor: np.ndarray | None = None,
              max_iter: int = 40) -> State:
        """Contact equilibrium at cam angle ``theta`` (rad), Newton from ``start`` (see
        :meth:`_solve`). A failed solve drops the tangent it factorised on the way: it
        belongs to a diverged iterate and must not seed the next solve."""
        try:
            return self._solve(theta, start, predictor, max_iter)
        except SolverError:
            self._lu, self._u_lu = None, None
            raise

    def _solve(self, theta: float, start: State, predictor: np.ndarray | None = None,
               max_iter: int = 40) -> State:
        """Contact equilibrium at cam angle ``theta`` (rad), Newton from ``start``.

        Each iteration linearises the elasticity and the gaps of the candidates nearer
        than :data:`NEAR_MM` to the cam (and of those in contact) and solves that
        complementarity problem exactly (:func:`lcp`). Converged when the contact set
        repeats, nothing penetrates by more than :data:`PENETRATION_TOL_MM`, the last
        increment is below :data:`INCREMENT_TOL_MM` and the out-of-balance force is below
        :data:`RESIDUAL_TOL` of the contact force (a small increment alone would allow a
        large residual in the stiff in-plane modes).

        Raises:
            SolverError: no convergence within ``max_iter`` iterations.
        """
        u = start.u.copy() if predictor is None else start.u + predictor
        m = len(self.pX)
        g, n, seg, t = self._gaps(u, theta)
        active = np.asarray(start.active, dtype=int)
        lam = np.zeros(m)
        du_max, history, sizes, stable = np.inf, [], [], False
        for it in range(1, max_iter + 1):
            near = np.union1d(np.flatnonzero(g < NEAR_MM), active)
            slow = len(history) >= 3 and history[-1] > 0.3 * history[-2] > 0
            f_int, lu = self._internal(u, refactor=slow)
            if slow:
                history.clear()
            if stable and du_max < INCREMENT_TOL_MM and float(g.min()) >= -PENETRATION_TOL_MM:
                r = f_int - self._contact_force(lam, n)
                if float(np.max(np.abs(r))) <= RESIDUAL_TOL * max(1.0, float(lam.sum())):
                    self.log.append((theta, it - 1, sizes))
                    return State(theta, u, active, lam, n, g, seg, t, it - 1)
            x0 = lu.solve(-f_int)
            lam_near = np.zeros(len(near))
            W = np.zeros((len(self.free), 0))
            if len(near):
                # B: normal displacement of each near point from the DOFs of its nodes
                U, inv = np.unique(self.pnodes[near], return_inverse=True)
                inv = inv.reshape(-1, 3)
                B = np.zeros((len(near), 2 * len(U)))
                rr = np.repeat(np.arange(len(near)), 3)
                wts = self.pweights[near].ravel()
                np.add.at(B, (rr, inv.ravel()), wts * np.repeat(n[near, 0], 3))
                np.add.at(B, (rr, len(U) + inv.ravel()), wts * np.repeat(n[near, 1], 3))
                Wx, Wy = self._unit_responses(lu, U)
                WU = np.hstack([Wx, Wy])
                W = WU @ B.T
                rows = self.pos[2 * U]
                sel = np.concatenate([rows, rows + 1])
                M = B @ WU[sel] @ B.T
                lam_near = lcp(0.5 * (M + M.T), g[near] + B @ x0[sel])
            du = x0 + W @ lam_near
            u[self.free] += du
            du_max = float(np.max(np.abs(du)))
            history.append(du_max)
            g, n, seg, t = self._gaps(u, theta)
            new_active = near[lam_near > 0]
            lam = np.zeros(m)
            lam[near] = lam_near
            sizes.append((len(near), len(new_active), du_max))
            stable = np.array_equal(new_active, active)
            active = new_active
        raise SolverError(f"contact at cam angle {math.degrees(theta):+.4f} deg did not converge "
                          f"in {max_iter} iterations (last increment {du_max:.2e} mm)")

    def _contact_force(self, lam: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """Nodal forces (free DOFs, N) of contact forces lam * normals at the contact points."""
        f = np.zeros(len(self.free))
        act = np.flatnonzero(lam)
        if len(act):
            rows = self.pos[2 * self.pnodes[act]]  # (k, 3)
            w = self.pweights[act] * lam[act][:, None]
            np.add.at(f, rows.ravel(), (w * normals[act, 0][:, None]).ravel())
            np.add.at(f, rows.ravel() + 1, (w * normals[act, 1][:, None]).ravel())
        return f

    def _unit_responses(self, lu, nodes: np.ndarray):
        """Responses (free DOFs) to unit x and y forces at ``nodes``, cached per
        factorisation: the nodes near the cam change little between iterations."""
        if self._cache_lu is not lu:
            self._cache_lu, self._cache = lu, {}
        near = nodes
        missing = [int(i) for i in near if int(i) not in self._cache]
        if missing:
            rows = self.pos[2 * np.asarray(missing)]
            E = np.zeros((len(self.free), 2 * len(missing)), order="F")
            E[rows, 2 * np.arange(len(missing))] = 1.0
            E[rows + 1, 2 * np.arange(len(missing)) + 1] = 1.0
            Z = lu.solve(E)
            for k, i in enumerate(missing):
                self._cache[i] = (Z[:, 2 * k], Z[:, 2 * k + 1])
        if not len(near):
            return np.zeros((len(self.free), 0)), np.zeros((len(self.free), 0))
        return (np.column_stack([self._cache[int(i)][0] for i in near]),
                np.column_stack([self._cache[int(i)][1] for i in near]))

    def torque(self, st: State) -> float:
        """Torque of the contact forces about the axis at their current points, whole ring
        (N flexures) (N*mm); positive counter-clockwise."""
        x = self.positions(st.u)
        F = st.lam[:, None] * st.normals
        return float(np.sum(x[:, 0] * F[:, 1] - x[:, 1] * F[:, 0])) * \
            self.fm.geometry.n_flexures

    def reaction_torque(self, st: State) -> float:
        """Torque of the reactions at the held rim about the axis, whole ring (N*mm)."""
        f = self.internal_full(st.u)
        fixed = self.system.fixed
        return -float(f[fixed] @ self.system.rotation[fixed]) * self.fm.geometry.n_flexures
