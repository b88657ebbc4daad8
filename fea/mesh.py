"""Meshing: from the exact ring profile (or any CAD solid) to quadratic elements.

Two routes, cross-checked in ``tests/fea/test_mesh.py``:

``"gmsh"`` (default)
    The exact design curves (lines, arcs, the interpolating B-splines of the
    flexure edges) are rebuilt in gmsh's OpenCASCADE kernel, the face is meshed
    with triangles whose size follows the local flexure width, the fillets, the
    tip ball and the contact patch, and the mesh is made quadratic with its
    mid-edge nodes on the true curves. For 3D the quadratic triangle mesh is
    extruded through the thickness into quadratic tetrahedra (each prism split
    into three tets); every node of the extruded mesh lies on the true surface.
    Refinement levels are nested (uniform splitting), which is what makes the
    Richardson extrapolation of :mod:`fea.convergence` clean.
    A flat disk is a prism, so the extrusion loses nothing; the stress in an
    in-plane bent flexure is nearly uniform through the thickness, so two
    quadratic layers suffice there (measured in the tests).

``"pytetwild"``
    For any solid (:func:`mesh_solid`): the build123d solid is tessellated and
    tetrahedralised by fTetWild, and the linear tets are given mid-edge nodes
    (straight-sided quadratic tets). The envelope shrinks thin features a
    little (see the quality report's volume error). gmsh can mesh any solid
    too (``mesher="gmsh"``: the B-rep is imported and meshed with quadratic tets).

Every mesh comes with a :class:`MeshQuality` report; a disconnected mesh, a
mesh whose volume misses the CAD volume, or one that lost a labelled feature
(tip ball, clamp, rim holes) raises :class:`~springcad.errors.MeshingError`.

Point arrays: scikit-fem uses (dim, n); gmsh, pyvista and pytetwild use
(n, dim). :func:`to_rows` and :func:`to_columns` are the only conversions.
Units: mm.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass, field

import numpy as np

from springcad.design.curves import Arc, Circle, Line, Spline
from springcad.errors import MeshingError

#: relative volume error above which a mesh is rejected (a lost or shrunk feature)
VOLUME_TOLERANCE = 5e-3
#: gmsh element type ids
_GMSH_LINE3, _GMSH_TRI6, _GMSH_TET10 = 8, 9, 11
#: gmsh tetra10 -> scikit-fem / VTK node order (gmsh lists edge 2-3 before edge 1-3)
_GMSH_TET10_ORDER = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]


def to_rows(points_dim_n: np.ndarray) -> np.ndarray:
    """(dim, n) scikit-fem points to (n, dim) rows (pyvista, gmsh, pytetwild)."""
    return np.ascontiguousarray(np.asarray(points_dim_n).T)


def to_columns(points_n_dim: np.ndarray) -> np.ndarray:
    """(n, dim) rows to (dim, n) scikit-fem points."""
    return np.ascontiguousarray(np.asarray(points_n_dim, dtype=float).T)


# =============================================================================== sizes
@dataclass(frozen=True)
class MeshSize:
    """Element size rules (level 0, before refinement).

    Attributes:
        across_width: quadratic elements across the local flexure width.
        per_fillet_radius: elements per fillet / ball radius (size = radius / this).
        patch_elements: elements across the contact-patch half-width.
        rim_size_fraction: element size in the rim as a fraction of the rim thickness.
        gradation: size growth per mm of distance from a feature (-).
        factor: global multiplier on every size.
        layers: quadratic element layers through the thickness (3D extrusion).
    """

    across_width: float = 1.5
    per_fillet_radius: float = 1.5
    patch_elements: float = 1.5
    rim_size_fraction: float = 0.5
    gradation: float = 0.4
    factor: float = 1.0
    layers: int = 2


#: the verification's level-0 mesh rules (2D study levels 1..n refine them)
DEFAULT_SIZE = MeshSize(across_width=1.0, per_fillet_radius=2.0, patch_elements=1.0,
                        gradation=0.3, rim_size_fraction=0.8, layers=1)


class SizeField:
    """Local target element size (mm) over the ring face, built from its geometry.

    Size is the smallest of: the rim size; in and near each flexure its width
    divided by ``across_width`` (so every station has the same number of
    elements across, the tip included); near each fillet and the tip ball
    their radius divided by ``per_fillet_radius``; near each contact point the
    patch half-width divided by ``patch_elements``; each grown linearly with
    distance by ``gradation``.
    """

    def __init__(self, geometry, rules: MeshSize, patch_half_width_mm: float):
        from scipy.spatial import cKDTree

        g = geometry
        self.rules = rules
        self.g = g
        self.h_max = rules.rim_size_fraction * g.rim_thickness_mm
        self.tree = cKDTree(g.centreline_mm)
        self.width = [float(w) for w in g.width_mm]
        h_tip = min(g.tip_radius_mm, g.neck_fillet_radius_mm) / rules.per_fillet_radius
        self.h_flex = [max(w / rules.across_width, h_tip) for w in self.width]
        self.n = g.n_flexures
        self.pitch = 2 * math.pi / g.n_flexures
        # modelled flexures by index around the ring (flexure 0 along +y)
        self.modelled = {int(round((a - math.pi / 2) / self.pitch)) % self.n
                         for a in g.flexure_angles_rad}
        # polar angle of the flexure-0 centreline as a function of radius: a point's
        # nearest flexures are found from its angle in O(1), however many flexures
        cl = np.asarray(g.centreline_mm)
        r = np.hypot(cl[:, 0], cl[:, 1])
        phi = np.arctan2(cl[:, 1], cl[:, 0])
        order = np.argsort(r)
        self.r_tab, self.phi_tab = r[order], phi[order]
        self.feat = [(x, y, r_, r_ / rules.per_fillet_radius) for x, y, r_, _k in g.fillets_mm]
        # contact point of flexure 0 (frame of flexure 0)
        self.patch = ((g.tip_radius_mm, g.contact_radius_mm),
                      patch_half_width_mm / rules.patch_elements)
        self.holes = [(c[0], c[1]) for c in g.hole_centres_mm]
        self.h_hole = (g.hole_radius_mm * 2 * math.pi / 16) if self.holes else 0.0

    def _candidates(self, x: float, y: float):
        r = math.hypot(x, y)
        phi_c = float(np.interp(r, self.r_tab, self.phi_tab))
        j = int(round((math.atan2(y, x) - phi_c) / self.pitch))
        return [(j + d) % self.n for d in (-1, 0, 1) if (j + d) % self.n in self.modelled]

    def __call__(self, x: float, y: float) -> float:
        grad = self.rules.gradation
        h = self.h_max
        for j in self._candidates(x, y):
            a = -j * self.pitch
            c, s = math.cos(a), math.sin(a)
            xl, yl = c * x - s * y, s * x + c * y  # point in flexure 0's frame
            d, i = self.tree.query((xl, yl))
            h = min(h, self.h_flex[i] + grad * max(d - 0.5 * self.width[i], 0.0))
            for fx_, fy_, fr, fh in self.feat:
                h = min(h, fh + grad * max(math.hypot(xl - fx_, yl - fy_) - fr, 0.0))
            (px, py), hp = self.patch
            h = min(h, hp + grad * math.hypot(xl - px, yl - py))
        for hx, hy in self.holes:
            dist = math.hypot(x - hx, y - hy) - self.g.hole_radius_mm
            h = min(h, self.h_hole + grad * max(dist, 0.0))
        return float(h * self.rules.factor)


# =============================================================================== meshes
@dataclass(eq=False)
class Mesh2D:
    """Quadratic triangle mesh of a face (scikit-fem node order).

    Attributes:
        points: node coordinates (2, n) (mm): vertices first, then mid-edge nodes.
        tris: (6, e) vertex, vertex, vertex, edge 01, edge 12, edge 02 node indices.
        edges: labelled boundary edges (3, b): vertex, vertex, middle node.
        edge_labels: label of each boundary edge (see ``RingGeometry.labels``).
        n_vertices: number of corner nodes (they come first in ``points``).
    """

    points: np.ndarray
    tris: np.ndarray
    edges: np.ndarray
    edge_labels: np.ndarray
    n_vertices: int


@dataclass(eq=False)
class FeaMesh:
    """A quadratic mesh ready for scikit-fem, with labelled boundaries and its quality.

    Attributes:
        mesh: ``skfem.MeshTri2`` (2D) or ``skfem.MeshTet2`` / ``skfem.MeshTet1`` (3D).
        dim: 2 or 3.
        boundaries: label -> boundary facet indices of ``mesh``.
        quality: the :class:`MeshQuality` report.
        mesher: "gmsh" or "pytetwild".
        thickness_mm: disk thickness (the 2D model's out-of-plane depth) (mm).
        level: refinement level (0 = coarsest).
    """

    mesh: object
    dim: int
    boundaries: dict
    quality: "MeshQuality"
    mesher: str
    thickness_mm: float
    level: int = 0
    geometry: object = None
    thickness_fraction: float = 1.0
    """Fraction of the disk thickness modelled (0.5: half model on the mid-plane)."""

    @property
    def n_elements(self) -> int:
        return int(self.mesh.t.shape[1])


@dataclass(frozen=True)
class MeshQuality:
    """Mesh-quality report.

    Attributes:
        n_elements: element count.
        n_nodes: node count (quadratic nodes included).
        min_angle_deg: smallest triangle angle (2D) or smallest dihedral angle (3D)
            of the straight-sided elements (deg).
        max_aspect_ratio: largest longest-edge / shortest-altitude ratio (-).
        volume_mm3: mesh volume (area x thickness in 2D) by quadrature on the
            curved elements (mm^3).
        cad_volume_mm3: exact CAD volume (mm^3).
        volume_error: (mesh - CAD) / CAD (-).
        components: connected components (must be 1).
        features: labelled boundary features found, label kind -> facet count.
    """

    n_elements: int
    n_nodes: int
    min_angle_deg: float
    max_aspect_ratio: float
    volume_mm3: float
    cad_volume_mm3: float
    volume_error: float
    components: int
    features: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"n_elements": self.n_elements, "n_nodes": self.n_nodes,
                "min_angle_deg": self.min_angle_deg, "max_aspect_ratio": self.max_aspect_ratio,
                "volume_mm3": self.volume_mm3, "cad_volume_mm3": self.cad_volume_mm3,
                "volume_error_pct": 100.0 * self.volume_error, "components": self.components,
                "features": dict(self.features)}


# =============================================================================== gmsh
def _restore_signal_handlers() -> None:
    """Put Python's SIGINT and SIGTERM handlers back after ``gmsh.initialize``.

    The gmsh library installs its own C handlers for them, which end the process at
    once: an interrupted ``verify`` or ``build`` would then leave its temporary
    output folder behind. Python still records its handlers, so setting them again
    reinstalls them (only possible from the main thread).
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler is not None:
            signal.signal(sig, handler)


@contextlib.contextmanager
def _gmsh_session(name: str):
    import gmsh

    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(interruptible=False)
        _restore_signal_handlers()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 1)
    gmsh.option.setNumber("General.NumThreads", 1)  # deterministic meshes
    gmsh.model.add(name)
    try:
        yield gmsh
    finally:
        gmsh.model.remove()
        if own:
            gmsh.finalize()


def _spline_bspline(seg: Spline):
    """Exact B-spline form (knots, control points) of the design's clamped cubic spline."""
    from scipy.interpolate import make_interp_spline

    p = np.asarray(seg.points, dtype=float)
    u = seg.parameters()
    if seg.start_tangent is not None and seg.end_tangent is not None:
        bc = ([(1, np.asarray(seg.start_tangent))], [(1, np.asarray(seg.end_tangent))])
    else:
        bc = "not-a-knot"
    b = make_interp_spline(u, p, k=3, bc_type=bc, axis=0)
    knots, counts = np.unique(b.t, return_counts=True)
    return b.c, knots, counts


def _build_face(gmsh, geometry):
    """Rebuild the profile in gmsh's OCC kernel; return (surface tag, curve tag -> label)."""
    occ = gmsh.model.occ
    curve_label: dict[int, str] = {}
    loops = []
    for loop, labels in zip(geometry.profile.loops, geometry.labels):
        segs = loop.segments
        if len(segs) == 1 and isinstance(segs[0], Circle):
            c = segs[0]
            tag = occ.addCircle(c.center[0], c.center[1], 0.0, c.radius)
            curve_label[tag] = labels[0]
            loops.append(occ.addCurveLoop([tag]))
            continue
        first = occ.addPoint(*segs[0].start, 0.0)
        prev = first
        tags = []
        for k, (seg, lab) in enumerate(zip(segs, labels)):
            end = first if k == len(segs) - 1 else occ.addPoint(*seg.end, 0.0)
            if isinstance(seg, Line):
                new = [occ.addLine(prev, end)]
            elif isinstance(seg, Arc):
                npieces = max(1, int(math.ceil(abs(seg.sweep) / (0.5 * math.pi))))
                cen = occ.addPoint(*seg.center, 0.0)
                new, a_prev = [], prev
                for j in range(1, npieces + 1):
                    if j == npieces:
                        b = end
                    else:
                        b = occ.addPoint(*seg.point_at(seg.start_angle + seg.sweep * j / npieces),
                                         0.0)
                    new.append(occ.addCircleArc(a_prev, cen, b))
                    a_prev = b
            elif isinstance(seg, Spline):
                ctrl, knots, mult = _spline_bspline(seg)
                inner = [occ.addPoint(x, y, 0.0) for x, y in ctrl[1:-1]]
                new = [occ.addBSpline([prev, *inner, end], degree=3, knots=list(knots),
                                      multiplicities=[int(m) for m in mult])]
            else:  # pragma: no cover - profiles only hold these types
                raise MeshingError(f"cannot mesh a {type(seg).__name__} segment")
            for t in new:
                curve_label[t] = lab
            tags += new
            prev = end
        loops.append(occ.addCurveLoop(tags))
    surf = occ.addPlaneSurface(loops)
    occ.synchronize()
    return surf, curve_label


def _extract_tri6(gmsh, curve_label):
    """Nodes, quadratic triangles and labelled quadratic boundary edges from gmsh."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    pts = coords.reshape(-1, 3)[:, :2]
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    types, _, nodes = gmsh.model.mesh.getElements(2)
    if list(types) != [_GMSH_TRI6]:
        raise MeshingError(f"gmsh produced element types {list(types)}, "
                           "expected quadratic triangles")
    tri = index[nodes[0].astype(np.int64)].reshape(-1, 6)
    edges, labels = [], []
    for ctag, lab in curve_label.items():
        et, _, en = gmsh.model.mesh.getElements(1, ctag)
        for t, n in zip(et, en):
            if t != _GMSH_LINE3:
                raise MeshingError("gmsh boundary elements are not quadratic lines")
            e = index[n.astype(np.int64)].reshape(-1, 3)
            edges.append(e)
            labels += [lab] * len(e)
    edges = np.vstack(edges)
    # vertices first (scikit-fem expects corner nodes numbered before mid-edge nodes)
    corner = np.unique(tri[:, :3])
    order = np.concatenate([corner, np.setdiff1d(np.arange(len(pts)), corner)])
    used = np.zeros(len(pts), bool)
    used[tri.ravel()] = True
    order = order[used[order]]
    new = np.full(len(pts), -1, dtype=np.int64)
    new[order] = np.arange(len(order))
    tri = new[tri]
    # orient counter-clockwise (positive Jacobian)
    p = pts[order]
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    cw = ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) < 0
    tri[cw] = tri[cw][:, [0, 2, 1, 5, 4, 3]]
    return Mesh2D(points=to_columns(p), tris=np.ascontiguousarray(tri.T),
                  edges=np.ascontiguousarray(new[edges].T), edge_labels=np.asarray(labels),
                  n_vertices=len(corner))


def _make_periodic(gmsh, sides, geometry):
    """Mesh the two sector cuts identically (the right one rotated by the pitch onto
    the left one), so that rotated copies of the sector mesh join node to node."""
    pitch = 2 * math.pi / geometry.n_flexures

    def angle(tag):
        lo, hi = gmsh.model.getParametrizationBounds(1, tag)
        x, y, _ = gmsh.model.getValue(1, tag, [0.5 * (lo[0] + hi[0])])
        return math.atan2(y, x)

    right, left = sorted(sides, key=angle)
    c, s = math.cos(pitch), math.sin(pitch)
    affine = [c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    gmsh.model.mesh.setPeriodic(1, [left], [right], affine)


def pattern_sector(m2: Mesh2D, n_flexures: int, tol_mm: float = 1e-6) -> Mesh2D:
    """The full ring mesh made of ``n_flexures`` rotated copies of a periodic sector mesh.

    Copy i is rotated by 2 pi i / N; its labels "ball:0", "edge:0", ... become
    "ball:i", ...; the sector cuts ("side") become interior and disappear.
    The result has exactly the sector's elements, so sector and ring solutions
    differ only by the sector's free-side idealisation.

    Raises:
        MeshingError: the sector's cut lines do not match after rotation.
    """
    from scipy.spatial import cKDTree

    pitch = 2 * math.pi / n_flexures
    npt = m2.points.shape[1]
    pts, tris, edges, labels = [], [], [], []
    for i in range(n_flexures):
        c, s = math.cos(i * pitch), math.sin(i * pitch)
        p = m2.points
        pts.append(np.vstack([c * p[0] - s * p[1], s * p[0] + c * p[1]]))
        tris.append(m2.tris + i * npt)
        keep = m2.edge_labels != "side"
        edges.append(m2.edges[:, keep] + i * npt)
        labels += [lab.replace(":0", f":{i}") for lab in m2.edge_labels[keep]]
    P = np.hstack(pts)
    tree = cKDTree(to_rows(P))
    pairs = tree.query_pairs(tol_mm, output_type="ndarray")
    rep = np.arange(P.shape[1])
    # union duplicates onto the smaller index
    for a, b in sorted(map(tuple, np.sort(pairs, axis=1)), key=lambda ab: ab[1]):
        rep[b] = rep[a]
    while True:
        nxt = rep[rep]
        if np.array_equal(nxt, rep):
            break
        rep = nxt
    per_cut = int(np.sum(m2.edge_labels == "side")) // 2  # quadratic edges on one cut
    expected = n_flexures * (2 * per_cut + 1)  # shared nodes: 2 per quadratic edge + 1
    if len(pairs) != expected:
        raise MeshingError(f"sector cuts do not match after rotation ({len(pairs)} shared nodes, "
                           f"expected {expected}); was the sector meshed periodically?")
    T = rep[np.hstack(tris)]
    E = rep[np.hstack(edges)]
    corner = np.unique(T[:3])
    used = np.unique(T)
    order = np.concatenate([corner, np.setdiff1d(used, corner)])
    new = np.full(P.shape[1], -1, dtype=np.int64)
    new[order] = np.arange(len(order))
    return Mesh2D(points=np.ascontiguousarray(P[:, order]), tris=new[T], edges=new[E],
                  edge_labels=np.asarray(labels), n_vertices=len(corner))


def mesh_face_levels(geometry, size: MeshSize = MeshSize(), levels: int = 3,
                     patch_half_width_mm: float | None = None) -> list[Mesh2D]:
    """Quadratic triangle meshes of the ring face, nested by uniform refinement.

    Args:
        geometry: a :class:`~fea.geometry.RingGeometry`.
        size: level-0 size rules.
        levels: number of meshes; level k has 4**k times the triangles of level 0.
        patch_half_width_mm: half-width of the contact patch (for local sizing);
            defaults to half the tip-ball radius.

    Raises:
        MeshingError: gmsh failed or returned an unusable mesh.
    """
    from fea.geometry import check_profile

    if patch_half_width_mm is None:
        patch_half_width_mm = 0.5 * geometry.tip_radius_mm
    check_profile(geometry.profile, step_mm=min(0.05, 0.2 * geometry.tip_radius_mm),
                  name="ring face" if not geometry.sector else "sector face")
    field_fn = SizeField(geometry, size, patch_half_width_mm)
    out = []
    with _gmsh_session("ring") as gmsh:
        try:
            _, curve_label = _build_face(gmsh, geometry)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
            gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: good angles
            # the size callback is in Python: integrate it along curves coarsely
            gmsh.option.setNumber("Mesh.LcIntegrationPrecision", 1e-3)
            gmsh.option.setNumber("Mesh.MeshSizeMax", field_fn.h_max * size.factor)
            gmsh.model.mesh.setSizeCallback(lambda dim, tag, x, y, z, lc: field_fn(x, y))
            sides = [t for t, lab in curve_label.items() if lab == "side"]
            if geometry.sector and len(sides) == 2:
                _make_periodic(gmsh, sides, geometry)
            gmsh.model.mesh.generate(2)
            for level in range(levels):
                if level:
                    gmsh.model.mesh.setOrder(1)
                    gmsh.model.mesh.refine()
                gmsh.model.mesh.setOrder(2)
                out.append(_extract_tri6(gmsh, curve_label))
        except MeshingError:
            raise
        except Exception as err:
            raise MeshingError(f"gmsh could not mesh the ring face ({err}); check the profile "
                               "for self-intersections or features smaller than the mesh") from err
    return out


# =============================================================================== extrusion
def extrude_to_tets(m2: Mesh2D, thickness_mm: float, layers: int, z0_mm: float = 0.0):
    """Extrude a quadratic triangle mesh into quadratic tetrahedra.

    Each triangle x layer prism is split into three tets by the
    smallest-global-index rule, which makes neighbouring prisms conforming.
    Mid-edge nodes are the 2D mid-edge nodes (on the true curves) at the
    mean height of the edge's ends, so every node lies on the extruded surface.

    Returns:
        (points (3, n), tets (10, e) in scikit-fem order, boundary triangles
        (3, b) corner nodes, their labels).
    """
    n2 = m2.points.shape[1]
    nz = 2 * layers + 1  # vertex and mid levels
    z = z0_mm + np.linspace(0.0, thickness_mm, nz)
    tri = m2.tris.T  # (e, 6)
    # 2D mid-node of each vertex pair, looked up by a sorted integer key
    ka = np.concatenate([tri[:, 0], tri[:, 1], tri[:, 0]])
    kb = np.concatenate([tri[:, 1], tri[:, 2], tri[:, 2]])
    km = np.concatenate([tri[:, 3], tri[:, 4], tri[:, 5]])
    keys = np.minimum(ka, kb).astype(np.int64) * n2 + np.maximum(ka, kb)
    keys, first = np.unique(keys, return_index=True)
    key_mid = km[first]

    def mid2d(u, v):
        k = np.minimum(u, v).astype(np.int64) * n2 + np.maximum(u, v)
        pos = np.clip(np.searchsorted(keys, k), 0, len(keys) - 1)
        return np.where(keys[pos] == k, key_mid[pos], -1)

    def nid(node2d, k):
        return k * n2 + node2d

    # prism split: vertices sorted by global index; standard 3-tet decomposition
    tris = np.sort(tri[:, :3], axis=1)
    tets = []
    for lay in range(layers):
        k0, k1 = 2 * lay, 2 * lay + 2
        a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
        # quad side (u, v), u < v, split by the diagonal u0-v1; the three tets are
        # (a0 b0 c0 c1), (a0 b0 b1 c1), (a0 a1 b1 c1)
        one = np.ones_like(a)
        tets += [np.column_stack([a, b, c, c, k0 * one, k0 * one, k0 * one, k1 * one]),
                 np.column_stack([a, b, b, c, k0 * one, k0 * one, k1 * one, k1 * one]),
                 np.column_stack([a, a, b, c, k0 * one, k1 * one, k1 * one, k1 * one])]
    tv = np.vstack(tets)  # columns: 4 nodes2d + their levels
    nodes2d, levels = tv[:, :4], tv[:, 4:]
    verts = nid(nodes2d, levels)
    e_pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    mids = []
    for i, j in e_pairs:
        ni, nj, ki, kj = nodes2d[:, i], nodes2d[:, j], levels[:, i], levels[:, j]
        same = ni == nj
        m2d = np.where(same, ni, mid2d(ni, nj))
        if np.any(m2d < 0):
            raise MeshingError("extrusion: a tet edge is not a triangle edge")
        mids.append(nid(m2d, (ki + kj) // 2))
    t10 = np.column_stack([verts, np.column_stack(mids)])
    pts = np.vstack([np.tile(m2.points, (1, nz)), np.repeat(z, n2)[None, :]])
    # drop unused nodes, corner nodes first
    corner = np.unique(t10[:, :4])
    used = np.unique(t10)
    order = np.concatenate([corner, np.setdiff1d(used, corner)])
    new = np.full(pts.shape[1], -1, dtype=np.int64)
    new[order] = np.arange(len(order))
    t10 = new[t10]
    pts = pts[:, order]
    # orient positively
    p = to_rows(pts)
    a, b, c, d = (p[t10[:, i]] for i in range(4))
    neg = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    # swap vertices 1 and 2: edges (0,1)<->(0,2), (1,2) stays, (1,3)<->(2,3)
    t10[neg] = t10[neg][:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
    # labelled side faces: each 2D boundary edge x layer gives two triangles
    faces, labels = [], []
    e = m2.edges.T
    for lay in range(layers):
        k0, k1 = 2 * lay, 2 * lay + 2
        for (va, vb, _), lab in zip(e, m2.edge_labels):
            lo, hi = (va, vb) if va < vb else (vb, va)
            # the prism's quad face is split by the diagonal from the smaller vertex
            faces.append((new[nid(lo, k0)], new[nid(hi, k0)], new[nid(hi, k1)]))
            faces.append((new[nid(lo, k0)], new[nid(hi, k1)], new[nid(lo, k1)]))
            labels += [lab, lab]
    # bottom face (level 0) is labelled "bottom": the mid-plane of a half-thickness model
    tri0 = tri[:, :3]
    for a, b, c in tri0:
        faces.append((new[nid(a, 0)], new[nid(b, 0)], new[nid(c, 0)]))
    labels += ["bottom"] * len(tri0)
    return pts, np.ascontiguousarray(t10.T), np.asarray(faces).T, np.asarray(labels)


# =============================================================================== skfem meshes
def _facet_index(mesh, facets_vertices: np.ndarray) -> np.ndarray:
    """Indices of ``mesh.facets`` matching given corner-node tuples (k, b)."""
    key_mesh = np.sort(mesh.facets, axis=0)
    key = np.sort(facets_vertices, axis=0)
    n = mesh.p.shape[1] + 1
    code_mesh = np.zeros(key_mesh.shape[1], dtype=np.int64)
    code = np.zeros(key.shape[1], dtype=np.int64)
    for row in range(key.shape[0]):
        code_mesh = code_mesh * n + key_mesh[row]
        code = code * n + key[row]
    lookup = dict(zip(code_mesh.tolist(), range(len(code_mesh))))
    try:
        return np.array([lookup[c] for c in code.tolist()], dtype=np.int64)
    except KeyError as err:
        raise MeshingError("a labelled boundary edge is not a facet of the mesh") from err


def _group(labels: np.ndarray, facets: np.ndarray) -> dict:
    out: dict[str, np.ndarray] = {}
    for lab in np.unique(labels):
        out[str(lab)] = facets[labels == lab]
    return out


def fea_mesh_2d(m2: Mesh2D, geometry, level: int = 0) -> FeaMesh:
    """scikit-fem ``MeshTri2`` with labelled boundaries and a checked quality report."""
    from skfem import MeshTri2

    mesh = MeshTri2(m2.points, m2.tris)
    idx = _facet_index(mesh, m2.edges[:2])
    bnd = _group(m2.edge_labels, idx)
    fm = FeaMesh(mesh=mesh, dim=2, boundaries=bnd, quality=None, mesher="gmsh",
                 thickness_mm=geometry.thickness_mm, level=level, geometry=geometry)
    fm.quality = check_mesh(fm, geometry)
    return fm


def fea_mesh_3d(m2: Mesh2D, geometry, layers: int = 2, level: int = 0,
                half: bool = True) -> FeaMesh:
    """Extruded scikit-fem ``MeshTet2`` with labelled faces and a checked quality report.

    Args:
        layers: quadratic element layers through the modelled thickness.
        half: model the upper half of the disk (z from t/2 to t) with the mid-plane
            as a symmetry plane ("symmetry" facets, u_z = 0): disk, supports and
            cam load are symmetric about it, so this halves the DOFs exactly.
    """
    from skfem import MeshTet2

    z = geometry.thickness_mm
    pts, t10, faces, labels = extrude_to_tets(m2, 0.5 * z if half else z, layers,
                                              0.5 * z if half else 0.0)
    mesh = MeshTet2(pts, t10)
    idx = _facet_index(mesh, faces)
    labels = np.where(labels == "bottom", "symmetry" if half else "", labels)
    keep = labels != ""
    bnd = _group(labels[keep], idx[keep])
    fm = FeaMesh(mesh=mesh, dim=3, boundaries=bnd, quality=None, mesher="gmsh",
                 thickness_mm=z, level=level, geometry=geometry,
                 thickness_fraction=0.5 if half else 1.0)
    fm.quality = check_mesh(fm, geometry)
    return fm


# =============================================================================== any solid
def mesh_solid(solid, geometry, mesher: str = "gmsh", size_mm: float = 1.0,
               edge_length_fac: float | None = None) -> FeaMesh:
    """Quadratic tetrahedra of any build123d solid (a flexure-ring sector or ring).

    Args:
        solid: build123d ``Solid`` (mm).
        geometry: the :class:`~fea.geometry.RingGeometry` it was made from (labels the
            boundaries by position and gives the CAD volume).
        mesher: "gmsh" (B-rep import, curved quadratic tets) or "pytetwild"
            (fTetWild on the tessellated surface, straight-sided quadratic tets).
        size_mm: target element size for gmsh (mm).
        edge_length_fac: pytetwild ideal edge length as a fraction of the bounding-box
            diagonal (default: pytetwild's own).

    Raises:
        MeshingError: the mesher failed, or the mesh lost a feature.
    """
    if mesher == "pytetwild":
        p, t = _tetwild(solid, edge_length_fac)
        from skfem import MeshTet1, MeshTet2

        mesh = MeshTet2.from_mesh(MeshTet1(p, t))
    elif mesher == "gmsh":
        p, t = _gmsh_solid(solid, size_mm)
        from skfem import MeshTet2

        mesh = MeshTet2(p, t)
    else:
        raise MeshingError(f"unknown mesher '{mesher}'; use 'gmsh' or 'pytetwild'")
    bnd = label_by_position(mesh, geometry)
    fm = FeaMesh(mesh=mesh, dim=3, boundaries=bnd, quality=None, mesher=mesher,
                 thickness_mm=geometry.thickness_mm, geometry=geometry)
    fm.quality = check_mesh(fm, geometry)
    return fm


def _tetwild(solid, edge_length_fac):
    import pytetwild
    import pyvista as pv

    verts, tris = solid.tessellate(0.002, 2.0)
    v = np.array([(q.X, q.Y, q.Z) for q in verts])
    f = np.asarray(tris, dtype=np.int64)
    surf = pv.PolyData(v, np.hstack([np.full((len(f), 1), 3), f]).ravel())
    kw = {} if edge_length_fac is None else {"edge_length_fac": edge_length_fac}
    import tempfile

    try:
        # fTetWild writes a "__tracked_surface.stl" into the working folder: keep it out
        with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(tmp):
            grid = pytetwild.tetrahedralize_pv(surf, **kw)
    except Exception as err:
        raise MeshingError(f"pytetwild could not tetrahedralise the solid ({err})") from err
    if grid.n_cells == 0:
        raise MeshingError("pytetwild returned an empty mesh")
    cells = grid.cells_dict[pv.CellType.TETRA] if hasattr(grid, "cells_dict") else \
        grid.cells.reshape(-1, 5)[:, 1:]
    p = np.asarray(grid.points, dtype=float)
    t = np.asarray(cells, dtype=np.int64)
    # positive orientation
    a, b, c, d = (p[t[:, i]] for i in range(4))
    neg = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    t[neg] = t[neg][:, [0, 2, 1, 3]]
    return to_columns(p), np.ascontiguousarray(t.T)


def _gmsh_solid(solid, size_mm):
    import tempfile
    from pathlib import Path

    import build123d as bd

    with tempfile.TemporaryDirectory() as tmp, _gmsh_session("solid") as gmsh:
        path = str(Path(tmp) / "solid.brep")
        bd.export_brep(solid, path)
        try:
            gmsh.model.occ.importShapes(path)
            gmsh.model.occ.synchronize()
            gmsh.option.setNumber("Mesh.MeshSizeMax", size_mm)
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.05 * size_mm)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
            gmsh.model.mesh.generate(3)
            gmsh.model.mesh.setOrder(2)
        except Exception as err:
            raise MeshingError(f"gmsh could not mesh the solid ({err})") from err
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(len(tags))
        types, _, nodes = gmsh.model.mesh.getElements(3)
        if _GMSH_TET10 not in list(types):
            raise MeshingError("gmsh produced no quadratic tetrahedra")
        t = index[nodes[list(types).index(_GMSH_TET10)].astype(np.int64)].reshape(-1, 10)
    t = t[:, _GMSH_TET10_ORDER]
    p = coords.reshape(-1, 3)
    corner = np.unique(t[:, :4])
    order = np.concatenate([corner, np.setdiff1d(np.unique(t), corner)])
    new = np.full(len(p), -1, dtype=np.int64)
    new[order] = np.arange(len(order))
    return to_columns(p[order]), np.ascontiguousarray(new[t].T)


def label_by_position(mesh, geometry, tol_mm: float = 1e-3) -> dict:
    """Label boundary facets of a 3D mesh by where they lie.

    Used for meshes that do not carry the design's curve labels (pytetwild,
    gmsh on an imported solid): "clamp" (outer face), "ball:i", "root:i",
    "neck:i" (on the tip-ball and fillet circles), "hole:j", "side" (sector
    cuts), "rim" (root circle); other side faces are "edge:i" (flexure flanks,
    i the nearest modelled flexure); top and bottom faces are left unlabelled.
    Tolerances scale with the tip-ball radius (a tessellating mesher moves
    nodes off the true surface).
    """
    g = geometry
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    r = np.hypot(mid[0], mid[1])
    labels = np.full(bf.shape, "", dtype=object)
    tol = max(tol_mm, 0.05 * g.tip_radius_mm)
    zfaces = (np.abs(mid[2]) < tol) | (np.abs(mid[2] - g.thickness_mm) < tol)
    # flanks: every side face not claimed below belongs to the nearest flexure
    angles = np.array(g.flexure_angles_rad)
    nearest = np.zeros(bf.shape, dtype=int)
    if len(angles) > 1:
        best = np.full(bf.shape, np.inf)
        for k, a in enumerate(angles):
            c, s_ = math.cos(a - math.pi / 2), math.sin(a - math.pi / 2)
            xl, yl = c * mid[0] + s_ * mid[1], -s_ * mid[0] + c * mid[1]
            d = np.min(np.hypot(xl[:, None] - g.centreline_mm[None, :, 0],
                                yl[:, None] - g.centreline_mm[None, :, 1]), axis=1)
            better = d < best
            best[better], nearest[better] = d[better], k
    labels[~zfaces] = np.array([f"edge:{k}" for k in nearest])[~zfaces]
    labels[np.abs(r - g.root_radius_mm) < tol] = "rim"
    for i, a in enumerate(angles):
        c, s_ = math.cos(a - math.pi / 2), math.sin(a - math.pi / 2)
        for x, y, rad, kind in g.fillets_mm:
            cx, cy = c * x - s_ * y, s_ * x + c * y
            d = np.hypot(mid[0] - cx, mid[1] - cy)
            on = (np.abs(d - rad) < tol) & ~zfaces
            labels[on] = f"{kind}:{i}"
    labels[(np.abs(r - g.outer_radius_mm) < max(tol, 0.01 * g.outer_radius_mm)) & ~zfaces] = "clamp"
    for j, c in enumerate(g.hole_centres_mm):
        d = np.hypot(mid[0] - c[0], mid[1] - c[1])
        labels[(np.abs(d - g.hole_radius_mm) < max(tol, 0.05 * g.hole_radius_mm)) & ~zfaces] = \
            f"hole:{j}"
    if g.sector:
        ang = np.arctan2(mid[1], mid[0])
        on_side = np.zeros(len(r), dtype=bool)
        for a in g.side_angles_rad:
            on_side |= np.abs((ang - a + math.pi) % (2 * math.pi) - math.pi) * r < tol
        labels[on_side & (r > g.root_radius_mm - tol) & ~zfaces] = "side"
    keep = labels != ""
    return _group(labels[keep].astype(str), bf[keep])


# =============================================================================== quality
def _min_angles(mesh) -> tuple[float, float]:
    """Smallest triangle angle / tet dihedral angle (deg) and largest aspect ratio."""
    p = mesh.p
    t = mesh.t
    if t.shape[0] == 3:
        a, b, c = (p[:, t[i]].T for i in range(3))
        angs = []
        for u, v, w in ((a, b, c), (b, c, a), (c, a, b)):
            e1, e2 = v - u, w - u
            cosang = np.einsum("ij,ij->i", e1, e2) / (np.linalg.norm(e1, axis=1)
                                                      * np.linalg.norm(e2, axis=1))
            angs.append(np.degrees(np.arccos(np.clip(cosang, -1, 1))))
        lmax = np.max([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                       np.linalg.norm(a - c, axis=1)], axis=0)
        area = 0.5 * np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
        aspect = lmax ** 2 / (2 * area)  # longest edge / altitude on it
        return float(np.min(angs)), float(np.max(aspect))
    v = [p[:, t[i]].T for i in range(4)]
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]
    normals = []
    for f in faces:
        n = np.cross(v[f[1]] - v[f[0]], v[f[2]] - v[f[0]])
        opp = [i for i in range(4) if i not in f][0]
        # outward normal
        s = np.sign(np.einsum("ij,ij->i", n, v[f[0]] - v[opp]))
        normals.append(n * s[:, None] / np.linalg.norm(n, axis=1)[:, None])
    dih = []
    for i in range(4):
        for j in range(i + 1, 4):
            cosang = -np.einsum("ij,ij->i", normals[i], normals[j])
            dih.append(np.degrees(np.arccos(np.clip(cosang, -1, 1))))
    vol = np.abs(np.einsum("ij,ij->i", np.cross(v[1] - v[0], v[2] - v[0]), v[3] - v[0])) / 6
    edges = [np.linalg.norm(v[j] - v[i], axis=1) for i in range(4) for j in range(i + 1, 4)]
    lmax = np.max(edges, axis=0)
    areas = [0.5 * np.linalg.norm(np.cross(v[f[1]] - v[f[0]], v[f[2]] - v[f[0]]), axis=1)
             for f in faces]
    amax = np.max(areas, axis=0)
    aspect = lmax * amax / (3 * vol)  # longest edge / smallest height
    return float(np.min(dih)), float(np.max(aspect))


def _components(mesh) -> int:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    t = mesh.t
    ne = t.shape[1]
    rows = np.repeat(np.arange(ne), t.shape[0])
    a = coo_matrix((np.ones(rows.size), (rows, t.T.ravel())), shape=(ne, mesh.p.shape[1])).tocsr()
    n, _ = connected_components(a @ a.T, directed=False)
    return int(n)


def mesh_volume(fm: FeaMesh) -> float:
    """Volume (mm^3) by quadrature on the (curved) elements; 2D: area x thickness."""
    from skfem import Functional, CellBasis

    basis = CellBasis(fm.mesh, fm.mesh.elem())
    vol = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis)
    return float(vol * (fm.thickness_mm if fm.dim == 2 else 1.0))


def check_mesh(fm: FeaMesh, geometry, volume_tolerance: float = VOLUME_TOLERANCE) -> MeshQuality:
    """Quality report; reject disconnected meshes and meshes that lost a feature.

    Raises:
        MeshingError: more than one connected component, a volume error beyond
            ``volume_tolerance``, a non-positive element, or a missing feature
            (clamp, a tip ball, a rim hole).
    """
    mesh = fm.mesh
    min_ang, aspect = _min_angles(mesh)
    vol = mesh_volume(fm)
    cad = geometry.volume_mm3 * fm.thickness_fraction
    err = (vol - cad) / cad
    comps = _components(mesh)
    feats: dict[str, int] = {}
    for lab, f in fm.boundaries.items():
        kind = lab.split(":")[0]
        feats[kind] = feats.get(kind, 0) + int(len(f))
    q = MeshQuality(n_elements=int(mesh.t.shape[1]), n_nodes=int(mesh.doflocs.shape[1]),
                    min_angle_deg=min_ang, max_aspect_ratio=aspect, volume_mm3=vol,
                    cad_volume_mm3=cad, volume_error=err, components=comps, features=feats)
    if comps != 1:
        raise MeshingError(f"the mesh has {comps} disconnected parts; a flexure or the rim was "
                           "cut through (check the profile and the mesh size)")
    if min_ang <= 0.0:
        raise MeshingError("the mesh has degenerate elements (zero angle)")
    if abs(err) > volume_tolerance:
        raise MeshingError(f"mesh volume {vol:.4g} mm^3 differs from the CAD volume {cad:.4g} "
                           f"mm^3 by {100 * err:+.2f} % (limit {100 * volume_tolerance:.2g} %): "
                           "the mesher lost or shrank a feature; refine the mesh")
    missing = [k for k in ("clamp", "ball") if feats.get(k, 0) == 0]
    n_balls = sum(1 for lab in fm.boundaries if lab.startswith("ball:"))
    if n_balls < len(geometry.flexure_angles_rad) and "ball" not in missing:
        missing.append(f"{len(geometry.flexure_angles_rad) - n_balls} tip ball(s)")
    n_holes = sum(1 for lab in fm.boundaries if lab.startswith("hole:"))
    if n_holes < len(geometry.hole_centres_mm):
        missing.append(f"{len(geometry.hole_centres_mm) - n_holes} rim hole(s)")
    if missing:
        raise MeshingError(f"the mesh lost feature(s): {', '.join(missing)}; refine the mesh or "
                           "use the gmsh mesher")
    return q
