"""Off-screen PNG render of the stack assembly (pyvista / VTK).

The stack is shown in a three-quarter view with one quarter cut away, so the
flexures, the camshafts between their tips, the spacers and the shafts are all
visible. Each part is tessellated once and placed per instance. Rendering is
off-screen (VTK's EGL or OSMesa window); no display is needed.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: tessellation tolerance (mm) and angular tolerance (rad) for the render
RENDER_TOLERANCE_MM = 0.02
RENDER_ANGULAR_RAD = 0.3


def _part_mesh(part):
    """pyvista PolyData of a part in its own frame."""
    import pyvista as pv

    verts, tris = part.solid.tessellate(RENDER_TOLERANCE_MM, RENDER_ANGULAR_RAD)
    pts = np.array([(v.X, v.Y, v.Z) for v in verts])
    faces = np.hstack([np.full((len(tris), 1), 3), np.asarray(tris)]).ravel()
    return pv.PolyData(pts, faces)


def _placed(mesh, placement):
    """A copy of a part mesh moved to its place in the stack."""
    p = np.asarray(mesh.points, dtype=float)
    out = mesh.copy()
    z = placement.z_mm - p[:, 2] if placement.flipped else placement.z_mm + p[:, 2]
    out.points = np.column_stack([placement.map_xy(p[:, :2]), z])
    return out


def render_png(assembly, path: Path, size=(1600, 1200), cutaway: bool = True) -> Path:
    """Render the assembly to a PNG.

    Args:
        assembly: a :class:`~springcad.geometry.stack.StackAssembly`.
        path: output file.
        size: image size in pixels.
        cutaway: remove the quarter x > 0, y < 0 to show the inside.
    """
    import pyvista as pv
    import vtk

    vtk.vtkObject.GlobalWarningDisplayOff()
    vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_OFF)
    pv.OFF_SCREEN = True
    meshes = {pn: _part_mesh(part) for pn, part in assembly.parts.items()}
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background("white")
    r = max(float(np.abs(m.points[:, :2]).max()) for m in meshes.values())
    z_lo = min(i.z_range_mm[0] for i in assembly.instances)
    z_hi = max(i.z_range_mm[1] for i in assembly.instances)
    for inst in assembly.instances:
        mesh = _placed(meshes[inst.part.part_number], inst.placement)
        if cutaway:
            mesh = mesh.clip_box((0, 2 * r, -2 * r, 0, z_lo - 1, z_hi + 1), invert=True)
            if mesh.n_points == 0:
                continue
        opacity = 0.35 if inst.component.kind == "bushing" else 1.0
        plotter.add_mesh(mesh, color=inst.colour, smooth_shading=False, opacity=opacity,
                         specular=0.3)
    plotter.enable_parallel_projection()
    plotter.camera_position = [(2.2 * r, -3.0 * r, 0.5 * (z_lo + z_hi) + 2.6 * r),
                               (0.0, 0.0, 0.5 * (z_lo + z_hi)), (0, 0, 1)]
    plotter.reset_camera()
    plotter.camera.zoom(1.5)
    plotter.add_text(f"{assembly.design.job.name}: {' + '.join(assembly.design.stack.sequence)}  "
                     f"(input {assembly.design.stack.input}, output {assembly.design.stack.output})",
                     font_size=12, color="black")
    plotter.screenshot(str(path))
    plotter.close()
    return Path(path)
