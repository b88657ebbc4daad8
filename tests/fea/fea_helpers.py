"""Helpers shared by the FEA tests (a uniquely named module: several test folders have a conftest)."""

from __future__ import annotations

from pathlib import Path

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"


def sector_2d(design, material, levels=(0, 1, 2)):
    """2D plane-stress convergence study of a design's sector on the given levels."""
    from fea.convergence import study
    from fea.geometry import sector_geometry
    from fea.mesh import fea_mesh_2d, mesh_face_levels
    from fea.problem import LoadCase
    from fea.mesh_size import DEFAULT_SIZE
    from fea.study import solve_mesh

    g = sector_geometry(design)
    faces = mesh_face_levels(g, DEFAULT_SIZE, max(levels) + 1)
    res = [solve_mesh(fea_mesh_2d(faces[k], g, k), material, LoadCase(),
                      design.max_deflection_rad) for k in levels]
    return study(res, "2d")
