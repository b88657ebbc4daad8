"""Quadratic tetrahedra of any CAD solid (a flexure-ring sector or the whole ring).

:func:`mesh_solid` meshes a build123d solid with one of two meshers:

``"pytetwild"``
    The solid is tessellated and tetrahedralised by fTetWild, and the linear
    tets are given mid-edge nodes (straight-sided quadratic tets). The envelope
    shrinks thin features a little (see the quality report's volume error).
``"gmsh"``
    The B-rep is imported into gmsh and meshed with curved quadratic tets.

Such meshes carry no curve labels from the design, so :func:`label_by_position`
labels their boundary facets by where they lie. The exact-curve route for the
ring face (and its extrusion) is :mod:`fea.mesh`; the two are cross-checked in
``tests/fea/test_mesh.py``. Units: mm.
"""

from __future__ import annotations

import contextlib
import math

import numpy as np

from fea.mesh import FeaMesh, _gmsh_session, _group, to_columns
from fea.mesh_quality import check_mesh
from springcad.errors import MeshingError

#: gmsh element type id of the quadratic tetrahedron
_GMSH_TET10 = 11
#: gmsh tetra10 -> scikit-fem / VTK node order (gmsh lists edge 2-3 before edge 1-3)
_GMSH_TET10_ORDER = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]


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

