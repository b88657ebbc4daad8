"""PNG renders of the von Mises field: pyvista draws the field, matplotlib frames it.

The sector result is rendered off-screen in a top view with parallel
projection, so the picture maps linearly onto the plane: it is placed on
matplotlib axes in mm, with the title above the axes (never over the part), a
colour bar beside them and the peak circled. The title carries one peak
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
    if zoom_mm:
        cx, cy = peak[0], peak[1]
        scale = zoom_mm
    else:
        b = surf.bounds  # frame the part itself: no empty half, a small margin
        cx, cy = 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])
        aspect = window[0] / window[1]
        scale = (1 + _MARGIN) * max(0.5 * (b[3] - b[2]), 0.5 * (b[1] - b[0]) / aspect)
    z = float(surf.bounds[5]) + 100.0
    p.camera.focal_point = (cx, cy, 0.0)
    p.camera.position = (cx, cy, z)
    p.camera.up = (0.0, 1.0, 0.0)
    p.camera.parallel_scale = scale  # half the view height (mm)
    img = p.screenshot(None, return_img=True)
    p.close()
    half_w = scale * window[0] / window[1]
    return img[..., :3], (cx - half_w, cx + half_w, cy - scale, cy + scale)


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
    img, extent = _field_image(result, clim, window, zoom_mm, peak)
    shown = mesh_peak if reported_peak_MPa is None else float(reported_peak_MPa)
    head = peak_title(title, shown, result.peak_region)
    fig, ax = plt.subplots(figsize=(7.2, 7.0), dpi=110)
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
