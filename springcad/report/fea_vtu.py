"""VTU output of FEA results: quadratic cells with displacement and von Mises fields.

The fields are those at the spring's maximum deflection. A half-thickness 3D
model (mid-plane symmetry) is mirrored to the full disk for viewing.
Units: mm, MPa.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from springcad.report.outdir import require_free_space

#: VTK cell types of the quadratic cells (:class:`fea.results.Field`, VTK node order)
_VTK_QUADRATIC = {6: 22, 10: 24}  # nodes per cell -> VTK_QUADRATIC_TRIANGLE / _TETRA


def result_grid(result):
    """A pyvista ``UnstructuredGrid`` of a :class:`~fea.results.StaticResult` with fields
    (its :attr:`~fea.results.StaticResult.field`)."""
    import pyvista as pv

    f = result.field
    cells, pts, disp, vm = f.cells, f.points_mm.copy(), f.displacement_mm, f.von_mises_MPa
    excluded = f.excluded.astype(np.uint8)
    if f.thickness_fraction < 1.0:  # mirror the upper half about the mid-plane
        z_mid = 0.5 * f.thickness_mm
        mirror = pts.copy()
        mirror[:, 2] = 2 * z_mid - mirror[:, 2]
        dmir = disp.copy()
        dmir[:, 2] *= -1
        n = len(pts)
        c2 = cells.copy() + n
        c2[:, [1, 2]] = c2[:, [2, 1]]  # keep positive orientation
        c2[:, [4, 6, 8, 9]] = c2[:, [6, 4, 9, 8]]
        pts = np.vstack([pts, mirror])
        disp = np.vstack([disp, dmir])
        vm = np.concatenate([vm, vm])
        excluded = np.concatenate([excluded, excluded])
        cells = np.vstack([cells, c2])
    nloc = cells.shape[1]
    ctype = np.full(len(cells), _VTK_QUADRATIC[nloc], dtype=np.uint8)
    conn = np.hstack([np.full((len(cells), 1), nloc), cells]).ravel()
    grid = pv.UnstructuredGrid(conn, ctype, pts)
    grid.point_data["displacement_mm"] = disp
    grid.point_data["von_mises_MPa"] = vm
    grid.point_data["excluded_from_peak"] = excluded
    return grid


def vtu_bytes_estimate(grid) -> int:
    """An upper estimate of the ``.vtu`` size of ``grid`` (bytes): every point and cell
    array at 8 bytes a value, base64-encoded (4/3), plus the XML around them; the
    writer's compression only makes the file smaller."""
    values = grid.n_points * 3 + grid.n_cells * 3  # points; offsets, types, ...
    values += int(grid.cells.size)  # connectivity
    for name in grid.point_data.keys():
        values += int(np.asarray(grid.point_data[name]).size)
    for name in grid.cell_data.keys():
        values += int(np.asarray(grid.cell_data[name]).size)
    return int(8 * values * 4 / 3) + 64 * 1024


def write_vtu(result, path: Path | str) -> Path:
    """Write the result's mesh and fields as ``.vtu`` (binary XML).

    The free space is checked first: VTK's writer crashes the process (segmentation
    fault) on a full disk instead of reporting it.

    Raises:
        NoSpaceError: the disk cannot hold the file (the message names the space needed).
    """
    path = Path(path)
    grid = result_grid(result)
    require_free_space(path.parent, vtu_bytes_estimate(grid), f"the FEA field '{path.name}'")
    grid.save(str(path))
    return path
