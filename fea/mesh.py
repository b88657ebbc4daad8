"""Meshing the ring face: from the exact profile to quadratic triangles and tetrahedra.

The exact design curves (lines, arcs, the interpolating B-splines of the
flexure edges) are rebuilt in gmsh's OpenCASCADE kernel, the face is meshed
with triangles whose size follows the local flexure width, the fillets, the
tip ball and the contact patch (:mod:`fea.mesh_size`), and the mesh is made
quadratic with its mid-edge nodes on the true curves. For 3D the quadratic
triangle mesh is extruded through the thickness into quadratic tetrahedra
(each prism split into three tets); every node of the extruded mesh lies on
the true surface. Refinement levels are nested (uniform splitting), which is
what makes the Richardson extrapolation of :mod:`fea.convergence` clean.
A flat disk is a prism, so the extrusion loses nothing; the stress in an
in-plane bent flexure is nearly uniform through the thickness, so two
quadratic layers suffice there (measured in the tests).

Any other solid is meshed by :func:`fea.mesh_solid.mesh_solid` (gmsh or
pytetwild). Every mesh comes with a :class:`~fea.mesh_quality.MeshQuality`
report (:mod:`fea.mesh_quality`).

Point arrays: scikit-fem uses (dim, n); gmsh, pyvista and pytetwild use
(n, dim). :func:`to_rows` and :func:`to_columns` are the only conversions.
Units: mm.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass

import numpy as np

from fea.geometry import check_profile
from fea.mesh_quality import MeshQuality, check_mesh
from fea.mesh_size import MeshSize, SizeField
from springcad.design.curves import Arc, Circle, Line, Spline
from springcad.errors import MeshingError

#: gmsh element type ids
_GMSH_LINE3, _GMSH_TRI6 = 8, 9


def to_rows(points_dim_n: np.ndarray) -> np.ndarray:
    """(dim, n) scikit-fem points to (n, dim) rows (pyvista, gmsh, pytetwild)."""
    return np.ascontiguousarray(np.asarray(points_dim_n).T)


def to_columns(points_n_dim: np.ndarray) -> np.ndarray:
    """(n, dim) rows to (dim, n) scikit-fem points."""
    return np.ascontiguousarray(np.asarray(points_n_dim, dtype=float).T)


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
        quality: the :class:`~fea.mesh_quality.MeshQuality` report.
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

