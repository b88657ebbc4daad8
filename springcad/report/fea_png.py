"""PNG renders of the von Mises field in a top view on matplotlib axes in mm.

A plane (2D) result is drawn by matplotlib itself: each quadratic triangle split at its
mid-side nodes into four linear ones, coloured by Gouraud shading of the nodal values (so
the colour at every node is its own value), at the resolution the figure is shown at; no
VTK. A solid (3D) result is rendered off-screen by pyvista in a top view with parallel
projection, so the picture maps linearly onto the plane, and placed on the same axes. The
title is above the axes (never over the part), a colour bar beside them and the peak
circled. The title carries one peak
value: the one ``fea.json`` and the console report (Richardson-extrapolated
over the mesh levels, times the 3D factor of a "2d3d" run). The colours are
the finest mesh's nodal field, whose own maximum differs from that value by
the discretisation error; the caption says so. The title is also stored in
the PNG's ``Title`` text chunk so a test can read it. Units: mm, MPa.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from springcad.export.render import quiet_vtk
from springcad.report.fea_vtu import result_grid

#: the part fills this fraction of the framed view; the rest is margin
_MARGIN = 0.06


def peak_title(title: str, peak_MPa: float, region: str = "") -> str:
    """The figure title: the caller's text and the one reported peak (MPa, no decimals)."""
    where = f" at the {region}" if region else ""
    return f"{title}: peak von Mises {peak_MPa:.0f} MPa{where}".lstrip(": ")


#: the four linear triangles of a quadratic one, in VTK's node order (corners 0, 1, 2; 3 on
#: edge 0-1, 4 on edge 1-2, 5 on edge 2-0)
_SUBTRIANGLES = ((0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5))


def view_extent_mm(points_mm, window, zoom_mm: float | None, peak) -> tuple:
    """The shown rectangle ``(x0, x1, y0, y1)`` (mm) of a top view of ``window`` (px) aspect:
    a square of half-size ``zoom_mm`` centred on ``peak``, else the part's own bounds framed
    with :data:`_MARGIN` (no empty half)."""
    aspect = window[0] / window[1]
    if zoom_mm:
        cx, cy, scale = float(peak[0]), float(peak[1]), float(zoom_mm)
    else:
        lo, hi = np.min(points_mm[:, :2], axis=0), np.max(points_mm[:, :2], axis=0)
        cx, cy = 0.5 * (lo + hi)
        scale = (1 + _MARGIN) * max(0.5 * (hi[1] - lo[1]), 0.5 * (hi[0] - lo[0]) / aspect)
    half_w = scale * aspect
    return (cx - half_w, cx + half_w, cy - scale, cy + scale)


def plane_triangles(field, extent) -> np.ndarray:
    """The linear triangles (node indices, shape (m, 3)) of a plane field's quadratic cells
    split at their mid-side nodes, those whose bounding box meets ``extent`` (mm) only."""
    sub = np.concatenate([field.cells[:, list(t)] for t in _SUBTRIANGLES])
    xy = field.points_mm[:, :2][sub]  # (m, 3, 2)
    lo, hi = xy.min(axis=1), xy.max(axis=1)
    x0, x1, y0, y1 = extent
    seen = (hi[:, 0] >= x0) & (lo[:, 0] <= x1) & (hi[:, 1] >= y0) & (lo[:, 1] <= y1)
    return sub[seen]


def draw_plane_field(ax, field, clim, extent) -> None:
    """A plane field's nodal von Mises (MPa) on ``ax``: Gouraud-shaded linear triangles
    (:func:`plane_triangles`), colour map "turbo" over ``clim``, rasterised at the figure's
    resolution."""
    tris = plane_triangles(field, extent)
    x, y = field.points_mm[:, 0], field.points_mm[:, 1]
    ax.tripcolor(x, y, tris, field.von_mises_MPa, shading="gouraud", cmap="turbo",
                 vmin=clim[0], vmax=clim[1], rasterized=True)


def _field_image(result, clim, window, zoom_mm, peak):
    """The field rendered top-down; (RGB image, (x0, x1, y0, y1) world extent in mm)."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    quiet_vtk()
    grid = result_grid(result)
    surf = grid.extract_surface(nonlinear_subdivision=2, algorithm="dataset_surface")
    p = pv.Plotter(off_screen=True, window_size=list(window))
    p.set_background("white")
    p.add_mesh(surf, scalars="von_mises_MPa", cmap="turbo", clim=clim, show_edges=False,
               show_scalar_bar=False, lighting=False)
    p.view_xy()
    p.camera.parallel_projection = True
    extent = view_extent_mm(np.asarray(surf.points), window, zoom_mm, peak)
    cx, cy = 0.5 * (extent[0] + extent[1]), 0.5 * (extent[2] + extent[3])
    z = float(surf.bounds[5]) + 100.0
    p.camera.focal_point = (cx, cy, 0.0)
    p.camera.position = (cx, cy, z)
    p.camera.up = (0.0, 1.0, 0.0)
    p.camera.parallel_scale = 0.5 * (extent[3] - extent[2])  # half the view height (mm)
    img = p.screenshot(None, return_img=True)
    p.close()
    return img[..., :3], extent


def render_von_mises(result, path: Path | str, title: str = "", zoom_mm: float | None = None,
                     window=(900, 900), clim=None, reported_peak_MPa: float | None = None
                     ) -> Path:
    """Top view of the von Mises field at max deflection (deformed x1), peak circled.

    Args:
        result: :class:`~fea.results.StaticResult` with fields.
        path: output PNG.
        title: what is shown (spring, deflection, model); the peak is appended.
        zoom_mm: half-size of a square view centred on the peak (None: the whole part).
        window: render size (px).
        clim: colour range (MPa); default 0 .. this mesh's peak.
        reported_peak_MPa: the peak the console and ``fea.json`` report; the title
            shows it (default: this mesh's peak).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    peak = np.asarray(result.peak_location_mm, dtype=float)
    mesh_peak = float(result.peak_von_mises_MPa)
    clim = clim or (0.0, mesh_peak)
    shown = mesh_peak if reported_peak_MPa is None else float(reported_peak_MPa)
    head = peak_title(title, shown, result.peak_region)
    fig, ax = plt.subplots(figsize=(7.2, 7.0), dpi=110)
    if result.field.cells.shape[1] == 6:  # quadratic triangles: a plane result
        extent = view_extent_mm(result.field.points_mm, window, zoom_mm, peak)
        draw_plane_field(ax, result.field, clim, extent)
    else:
        img, extent = _field_image(result, clim, window, zoom_mm, peak)
        ax.imshow(img, extent=extent, origin="upper", interpolation="antialiased")
    r = (extent[3] - extent[2]) * 0.025
    ax.add_patch(plt.Circle(peak[:2], r, fill=False, ec="magenta", lw=2.0, zorder=5))
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(head, fontsize=10, pad=10, wrap=True)
    sm = plt.cm.ScalarMappable(norm=Normalize(*clim), cmap="turbo")
    fig.colorbar(sm, ax=ax, shrink=0.8, pad=0.02, label="von Mises (MPa)")
    note = "colours: the finest mesh's nodal field; circle: the peak location"
    if reported_peak_MPa is not None:
        note += ("\ntitle: the reported peak (fea.json, console): extrapolated over the mesh "
                 "levels, so it differs\nfrom the finest mesh's own maximum by the "
                 "discretisation error")
    fig.text(0.01, 0.01, note, fontsize=7, color="0.3", va="bottom")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, metadata={"Title": head})
    plt.close(fig)
    return Path(path)
