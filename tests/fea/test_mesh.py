"""Meshing: exact geometry, nested levels, quality report, rejection of bad meshes."""

from __future__ import annotations

import numpy as np
import pytest

from springcad.errors import MeshingError


def test_sector_is_one_repeating_unit(s1):
    from fea.geometry import ring_geometry, sector_geometry

    g = sector_geometry(s1)
    ring = ring_geometry(s1, holes=False)
    assert g.area_mm2 == pytest.approx(ring.area_mm2 / s1.n_flexures, rel=1e-6)
    assert g.labels[0][0] == "clamp" and g.labels[0].count("side") == 2
    assert np.allclose(g.contact_points_mm()[0], (s1.tip_radius_mm, s1.contact_radius_mm))


def test_face_levels_nested_exact_and_good(s1_faces):
    from fea.mesh import fea_mesh_2d

    g, faces = s1_faces
    n = [f.tris.shape[1] for f in faces]
    assert n[1] == 4 * n[0] and n[2] == 4 * n[1]  # uniform splitting, ratio 2
    for k, m in enumerate(faces):
        fm = fea_mesh_2d(m, g, k)
        q = fm.quality
        assert q.components == 1
        assert q.min_angle_deg > 20.0
        # curved quadratic elements reproduce the exact area (fillets, ball, splines)
        assert abs(q.volume_error) < (1e-4 if k == 0 else 1e-5)
        assert {"clamp", "ball", "root", "neck", "edge", "side", "rim"} <= set(q.features)
    # every mid-edge node of the tip ball lies on the true circle
    m = faces[1]
    ball = m.edges[:, m.edge_labels == "ball:0"]
    pts = m.points[:, ball.ravel()]
    r = np.hypot(pts[0], pts[1] - s1_faces[0].contact_radius_mm)
    assert np.allclose(r, g.tip_radius_mm, atol=1e-9)


def test_extruded_tets_on_the_true_surface(s1_faces):
    from fea.mesh import fea_mesh_3d

    g, faces = s1_faces
    fm = fea_mesh_3d(faces[0], g, layers=2, level=0, half=True)
    q = fm.quality
    assert q.components == 1
    assert abs(q.volume_error) < 1e-4
    assert fm.thickness_fraction == 0.5 and "symmetry" in fm.boundaries
    z = fm.mesh.doflocs[2]
    assert z.min() == pytest.approx(0.5 * g.thickness_mm)
    assert z.max() == pytest.approx(g.thickness_mm)
    full = fea_mesh_3d(faces[0], g, layers=2, level=0, half=False)
    assert full.quality.volume_mm3 == pytest.approx(2 * q.volume_mm3, rel=1e-10)
    # quality report keys for fea.json
    d = q.to_dict()
    assert {"n_elements", "min_angle_deg", "volume_error_pct", "components"} <= set(d)
    assert d["min_angle_deg"] > 0.1


def test_pattern_sector_gives_the_ring(s1, s1_faces):
    from fea.geometry import ring_geometry
    from fea.mesh import fea_mesh_2d, pattern_sector

    g, faces = s1_faces
    ring = pattern_sector(faces[0], s1.n_flexures)
    fm = fea_mesh_2d(ring, ring_geometry(s1, holes=False))
    assert fm.quality.components == 1
    assert abs(fm.quality.volume_error) < 1e-4
    assert sum(1 for k in fm.boundaries if k.startswith("ball:")) == s1.n_flexures


def test_disconnected_mesh_is_rejected(s1_faces):
    from fea.mesh import Mesh2D, fea_mesh_2d

    g, faces = s1_faces
    m = faces[0]
    # drop the elements crossing the middle of the flexure: the tip is cut off
    cy = m.points[1, m.tris[:3]].mean(axis=0)
    keep = np.abs(cy - 0.5 * (g.contact_radius_mm + g.root_radius_mm)) > 0.6
    cut = Mesh2D(m.points, m.tris[:, keep], m.edges, m.edge_labels, m.n_vertices)
    with pytest.raises(MeshingError):
        fea_mesh_2d(cut, g)


def test_lost_feature_is_rejected(s1_faces):
    from fea.mesh import Mesh2D, fea_mesh_2d

    g, faces = s1_faces
    m = faces[0]
    labels = np.where(m.edge_labels == "ball:0", "neck:0", m.edge_labels)
    with pytest.raises(MeshingError, match="tip ball|lost feature"):
        fea_mesh_2d(Mesh2D(m.points, m.tris, m.edges, labels, m.n_vertices), g)


def test_mesher_failure_is_a_meshing_error(s1):
    """A profile gmsh cannot mesh (a hole crossing the outer contour) gives a clear error."""
    from dataclasses import replace

    from springcad.design.curves import Circle, Loop, Profile

    from fea.geometry import sector_geometry
    from fea.mesh import mesh_face_levels

    g = sector_geometry(s1)
    bad_hole = Loop((Circle((0.0, s1.outer_radius_mm), 1.0),))
    bad = replace(g, profile=Profile(g.profile.outer, (bad_hole,)),
                  labels=(*g.labels, ("hole:0",)))
    with pytest.raises(MeshingError):
        mesh_face_levels(bad, levels=1)


@pytest.mark.parametrize("hole, message", [
    ((9.5, 5.013), r"the outer contour crosses hole loop 1 near"),
    ((20.0, 20.0), r"hole loop 1 near \(21\.000, 20\.000\) mm lies outside the outer contour"),
])
def test_face_check_names_loop_and_place(hole, message):
    """The mesher's face check (the planar toolkit's) words its defects as MeshingErrors."""
    from springcad.design.curves import Circle, Line, Loop, Profile

    from fea.geometry import check_profile

    p = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
    outer = Loop(tuple(Line(p[k], p[(k + 1) % 4]) for k in range(4)))
    with pytest.raises(MeshingError, match=message):
        check_profile(Profile(outer, (Loop((Circle(hole, 1.0),)),)), name="test face")


@pytest.mark.slow
def test_pytetwild_and_gmsh_solid_agree_with_the_extruded_mesh(s1, material):
    """Both any-solid meshers against the default (gmsh face + extrusion), same solid."""
    from springcad.geometry.profile import extrude_profile

    from fea.geometry import sector_geometry
    from fea.mesh import mesh_face_levels, fea_mesh_3d
    from fea.mesh_solid import mesh_solid
    from fea.problem import LoadCase
    from fea.mesh_size import DEFAULT_SIZE
    from fea.study import solve_mesh

    g = sector_geometry(s1)
    case = LoadCase()
    theta = s1.max_deflection_rad
    ref = solve_mesh(fea_mesh_3d(mesh_face_levels(g, DEFAULT_SIZE, 2)[1], g, 2, 1), material,
                     case, theta).stiffness_Nmm_per_rad
    solid = extrude_profile(g.profile, g.thickness_mm, "sector")
    for mesher, kw, tol in (("gmsh", {"size_mm": 0.8}, 0.005),
                            ("pytetwild", {}, 0.01)):
        fm = mesh_solid(solid, g, mesher, **kw)
        assert fm.quality.components == 1
        # pytetwild's envelope shrinks the thin flexures: volume -0.2 %, reported
        assert abs(fm.quality.volume_error) < (1e-4 if mesher == "gmsh" else 5e-3)
        k = solve_mesh(fm, material, case, theta).stiffness_Nmm_per_rad
        assert k / ref - 1 == pytest.approx(0.0, abs=tol), mesher


def test_size_field_nearest_is_the_k_d_tree_answer(s1):
    """SizeField._nearest (a vector sweep over the centreline, for gmsh's per-point size
    callback) gives the k-d tree's distance and index bit for bit: at random points of the
    face, on the centreline itself and a micrometre off it."""
    from fea.geometry import sector_geometry
    from fea.mesh_size import DEFAULT_SIZE, SizeField

    g = sector_geometry(s1)
    field = SizeField(g, DEFAULT_SIZE, 0.5 * g.tip_radius_mm)
    rng = np.random.default_rng(3)
    cl = np.asarray(g.centreline_mm)
    r_out = float(np.max(np.hypot(cl[:, 0], cl[:, 1]))) + 2.0
    pts = np.vstack([rng.uniform(-r_out, r_out, (3000, 2)), cl,
                     cl + rng.normal(0.0, 1e-3, cl.shape)])
    for x, y in pts:
        d_tree, i_tree = field.tree.query((float(x), float(y)))
        assert field._nearest(float(x), float(y)) == (d_tree, i_tree)


def test_mesh_volume_is_scikit_fems_functional_of_one(s1_faces):
    """mesh_volume sums the default cell basis' quadrature weights itself: the very number
    (==) scikit-fem's Functional of 1 gives on that basis, for 2D and extruded 3D meshes."""
    from skfem import CellBasis, Functional

    from fea.mesh import fea_mesh_2d, fea_mesh_3d
    from fea.mesh_quality import mesh_volume

    g, faces = s1_faces
    for fm in (fea_mesh_2d(faces[1], g, 1), fea_mesh_3d(faces[0], g, 2, 0)):
        basis = CellBasis(fm.mesh, fm.mesh.elem())
        vol = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis)
        assert mesh_volume(fm) == float(vol * (fm.thickness_mm if fm.dim == 2 else 1.0))
