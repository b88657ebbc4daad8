"""A downstream CAD measures the exported STEP right (issue 26 item 5).

The ring's flanks used to be one ~40-span B-spline face each, on which OCC's volume
integral (what FreeCAD's ``Shape.Volume`` and OCC-based CAD report) was 0.2 % off at its
default and 10,764-11,404 mm^3 against 10,882 at explicit tolerances. Here the read-back
STEP is measured by OCC at its default and at two tolerances, by FreeCAD (another
application on its own OCC build) and by a surface mesh from gmsh (a different mesher and
our own divergence-theorem sum), all against the exact 2D area x thickness.
"""

import json
import shutil
import subprocess

import numpy as np
import pytest
from cad_fixtures import assembly

from springcad.design.curves import Spline
from springcad.export.step import write_part_step
from springcad.geometry.bezier import FIT_TOL_MM, bernstein, spline_beziers

#: the issue's acceptance: every reader within 0.2 % of area x thickness
READER_RTOL = 2e-3
JOBS = ("default", "4xS1")


def _ring(job):
    return next(p for p in assembly(job).parts.values() if p.info.kind == "flexure_ring")


def _occ_volumes_mm3(shape) -> dict:
    """OCC's volume integral at its default (no tolerance) and at two tolerances."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    out = {}
    for tol in (None, 1e-2, 1e-5):
        props = GProp_GProps()
        if tol is None:
            BRepGProp.VolumeProperties_s(shape, props)
        else:
            BRepGProp.VolumeProperties_s(shape, props, tol, False)
        out[tol] = props.Mass()
    return out


@pytest.fixture(scope="module")
def ring_steps(tmp_path_factory):
    """(job, ring part, STEP path) of the default and the 4xS1 ring."""
    folder = tmp_path_factory.mktemp("ring_steps")
    return [(job, _ring(job), write_part_step(_ring(job), folder / f"{job}.step"))
            for job in JOBS]


@pytest.mark.parametrize("job", JOBS)
def test_flank_pieces_follow_the_design_spline(job):
    """Every flank's Bezier pieces meet the spline's ends exactly, join C1 and stay within
    the fit tolerance of the spline (checked here at 2000 points a piece, by distance to
    a dense sampling of the spline, independent of the fit's own check)."""
    from scipy.spatial import cKDTree

    ring = _ring(job)
    splines = {s for sl in ring.slabs for lp in sl.region.loops for s in lp.segments
               if isinstance(s, Spline)}
    assert splines
    for seg in list(splines)[:6]:
        pieces, worst = spline_beziers(seg)
        assert worst <= FIT_TOL_MM
        assert np.allclose(pieces[0][0], seg.start, atol=1e-9)
        assert np.allclose(pieces[-1][-1], seg.end, atol=1e-9)
        for a, b in zip(pieces, pieces[1:]):
            assert np.allclose(a[-1], b[0], atol=1e-9)
            ta, tb = a[-1] - a[-2], b[1] - b[0]  # end tangents of the control polygon
            assert abs(ta[0] * tb[1] - ta[1] * tb[0]) <= 1e-9 * np.linalg.norm(ta) * \
                np.linalg.norm(tb) and ta @ tb > 0
        tree = cKDTree(seg.sample(5e-5))  # a point 0.05 um apart: overstates a 0.5 um
        # distance by < 1e-6 um
        t = np.linspace(0.0, 1.0, 2000)
        for c in pieces:
            d, _ = tree.query(bernstein(len(c) - 1, t) @ c)
            assert d.max() <= 1.001 * FIT_TOL_MM, (job, d.max())


def test_occ_volume_is_right_at_any_tolerance(ring_steps):
    import build123d as bd

    for job, ring, path in ring_steps:
        shape = bd.import_step(str(path))
        assert len(shape.solids()) == 1 and shape.is_valid, job
        truth = ring.slab_volume_mm3()  # exact 2D area x thickness
        vols = _occ_volumes_mm3(shape.wrapped)
        for tol, v in vols.items():
            assert abs(v / truth - 1) < READER_RTOL, (job, tol, v, truth)
        # measured: within 1.3e-5 of each other and of the truth (the pieces are 0.5 um
        # from the design; the old spline faces spread 8 %)
        assert (max(vols.values()) - min(vols.values())) / truth < 1e-4, (job, vols)
        assert "SURFACE_OF_LINEAR_EXTRUSION" not in path.read_text()  # B-spline surfaces


FREECAD_SCRIPT = """
import json, Part
out = {}
for p in %r:
    s = Part.Shape(); s.read(p)
    out[p] = dict(valid=s.isValid(), solids=len(s.Solids), volume=s.Volume)
print("RESULT " + json.dumps(out))
"""


@pytest.mark.skipif(shutil.which("freecadcmd") is None, reason="FreeCAD (freecadcmd) not installed")
def test_freecad_reads_the_volume(ring_steps, tmp_path):
    """FreeCAD, a second CAD, reads each ring STEP as one valid solid of the right volume
    (its ``Shape.Volume`` gave 10,823.87 for the old 4xS1 ring of 10,806.07 mm^3)."""
    script = tmp_path / "measure.py"
    script.write_text(FREECAD_SCRIPT % [str(p) for _, _, p in ring_steps])
    run = subprocess.run(["freecadcmd", str(script)], capture_output=True, text=True,
                         timeout=600)
    line = next(x for x in run.stdout.splitlines() if x.startswith("RESULT "))
    got = json.loads(line[len("RESULT "):])
    for job, ring, path in ring_steps:
        r = got[str(path)]
        assert r["valid"] and r["solids"] == 1, (job, r)
        assert r["volume"] == pytest.approx(ring.slab_volume_mm3(), rel=1e-4), job


@pytest.mark.skipif(shutil.which("freecadcmd") is None, reason="FreeCAD (freecadcmd) not installed")
def test_freecad_reads_every_part_as_one_valid_solid(tmp_path):
    """Issue 26's acceptance: every STEP of the default and the 4xS1 package (made and
    bought parts) imports in FreeCAD as one valid solid whose volume x density is the
    BOM's mass (the BOM's from springcad's own divergence-theorem volume)."""
    from springcad.export.bom import bom_rows

    rows = {}
    for job in JOBS:
        a = assembly(job)
        for r in bom_rows(a):
            part = a.parts[r["part_number"]]
            rows[str(write_part_step(part, tmp_path / f"{job}-{r['part_number']}.step"))] = (
                job, r, part.info.density_kg_per_m3)
    script = tmp_path / "measure.py"
    script.write_text(FREECAD_SCRIPT % list(rows))
    run = subprocess.run(["freecadcmd", str(script)], capture_output=True, text=True,
                         timeout=900)
    line = next(x for x in run.stdout.splitlines() if x.startswith("RESULT "))
    got = json.loads(line[len("RESULT "):])
    kinds = set()
    for path, (job, r, density) in rows.items():
        f = got[path]
        assert f["valid"] and f["solids"] == 1, (job, r["part_number"], f)
        mass_g = f["volume"] * density * 1e-6
        # the BOM writes grams to 3 decimals
        assert mass_g == pytest.approx(float(r["mass_each_g"]), rel=1e-4, abs=6e-4), (
            job, r["part_number"], mass_g, r["mass_each_g"])
        kinds.add(r["kind"])
    assert {"flexure_ring", "camshaft", "torque_shaft", "fastener", "bushing"} <= kinds


def _gmsh_mesh_volume_mm3(path, size_mm: float) -> float:
    """Volume enclosed by gmsh's surface mesh of a STEP (sum of signed tetrahedra from
    the origin over every triangle; gmsh orients the boundary outwards)."""
    import gmsh

    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(path))
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size_mm)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 5)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = np.zeros((int(tags.max()) + 1, 3))
        xyz[tags.astype(int)] = coords.reshape(-1, 3)
        vol = 0.0
        for dim, tag in gmsh.model.getEntities(2):
            for nodes in gmsh.model.mesh.getElements(dim, tag)[2]:
                tri = xyz[nodes.astype(int).reshape(-1, 3)]
                vol += np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum()
        return vol / 6.0
    finally:
        gmsh.finalize()


@pytest.mark.slow
def test_mesh_volume_of_the_step(ring_steps):
    """A mesh of the STEP's surfaces (gmsh, 0.3 mm triangles: chords stray < 0.004 mm
    from the flanks) encloses area x thickness (measured 3.6e-5 off on the 4xS1 ring,
    ~30 s)."""
    pytest.importorskip("gmsh")
    job, ring, path = ring_steps[1]
    v = _gmsh_mesh_volume_mm3(path, 0.3)
    assert v == pytest.approx(ring.slab_volume_mm3(), rel=READER_RTOL / 4), job
