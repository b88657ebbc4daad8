"""PNG renders of the von Mises field (pyvista, off-screen).

The sector result is shown in the plane with the peak marked, and zoomed at
the peak. Units: mm, MPa.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _quiet_vtk():
    try:
        import vtk

        vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_OFF)
        vtk.vtkObject.GlobalWarningDisplayOff()
    except Exception:  # pragma: no cover - cosmetic only
        pass


def render_von_mises(result, path: Path | str, title: str = "", zoom_mm: float | None = None,
                     window=(1000, 1000), clim=None, reported_peak_MPa: float | None = None
                     ) -> Path:
    """Top view of the von Mises field at max deflection (deformed x1), peak marked.

    Args:
        result: :class:`~fea.results.StaticResult` with fields.
        path: output PNG.
        title: text in the corner.
        zoom_mm: half-size of a square view centred on the peak (None: whole model).
        clim: colour range (MPa); default 0 .. peak.
        reported_peak_MPa: the peak the console and ``fea.json`` report (extrapolated
            over the mesh levels); printed beside this mesh's peak so the two agree.
    """
    import pyvista as pv

    from springcad.report.fea_vtu import result_grid

    pv.OFF_SCREEN = True
    _quiet_vtk()
    grid = result_grid(result)
    surf = grid.extract_surface(nonlinear_subdivision=2, algorithm="dataset_surface")
    peak = np.asarray(result.peak_location_mm)
    clim = clim or (0.0, float(result.peak_von_mises_MPa))
    p = pv.Plotter(off_screen=True, window_size=list(window))
    p.set_background("white")
    p.add_mesh(surf, scalars="von_mises_MPa", cmap="turbo", clim=clim, show_edges=False,
               scalar_bar_args={"title": "von Mises MPa", "color": "black", "vertical": True,
                                "fmt": "%.0f", "position_x": 0.82, "position_y": 0.1,
                                "width": 0.08, "height": 0.5, "label_font_size": 14,
                                "title_font_size": 14})
    p.add_mesh(pv.Sphere(radius=(zoom_mm or 2.0) * 0.03, center=peak), color="magenta")
    text = title or ""
    text += (f"\npeak on this mesh {result.peak_von_mises_MPa:.0f} MPa ({result.peak_region}) "
             f"at ({peak[0]:.2f}, {peak[1]:.2f}) mm")
    if reported_peak_MPa is not None:
        text += f"\nreported peak {reported_peak_MPa:.0f} MPa (extrapolated over the mesh levels)"
    p.add_text(text.strip(), font_size=10, color="black", position="upper_left")
    p.view_xy()
    if zoom_mm:
        p.camera.focal_point = (peak[0], peak[1], 0.0)
        p.camera.position = (peak[0], peak[1], 100.0)
        p.camera.parallel_projection = True
        p.camera.parallel_scale = zoom_mm
    else:
        p.camera.parallel_projection = True
        p.reset_camera()
        p.camera.parallel_scale *= 1.3  # a margin: the title sits above the part, not on it
    p.screenshot(str(path))
    p.close()
    return Path(path)
