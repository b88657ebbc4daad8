"""Off-screen PNG render of the stack assembly (pyvista / VTK).

The stack is shown in a three-quarter view with one quarter cut away, so the
flexures, the camshafts between their tips, the spacers and the shafts are all
visible. Each part is tessellated once and placed per instance. Rendering is
off-screen (VTK's EGL or OSMesa window); no display is needed.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from springcad.parallel import trim_heap

#: tessellation tolerance (mm) and angular tolerance (rad) for the render
RENDER_TOLERANCE_MM = 0.02
RENDER_ANGULAR_RAD = 0.3


def quiet_vtk() -> None:
    """Silence VTK's warnings and log on stderr, through the one VTK module that holds them
    (``import vtk`` loads every VTK module, ~180 libraries: 0.4 s CPU and up to 4 s on a busy
    machine, in each process that renders)."""
    from vtkmodules.vtkCommonCore import vtkLogger, vtkObject

    vtkObject.GlobalWarningDisplayOff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)


def part_triangles(assembly) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each distinct part tessellated in its own frame: part number -> (points (n, 3) mm,
    triangles (m, 3) point indices). The CAD kernel's share of a render: with these given,
    :func:`render_png` needs no solid (it can run in a forked process, where OCCT's
    meshing thread pool would wait forever on the parent's threads)."""
    return {pn: tessellate(part.solid, RENDER_TOLERANCE_MM, RENDER_ANGULAR_RAD)
            for pn, part in assembly.parts.items()}


def tessellate(solid, tolerance_mm: float, angular_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """build123d's ``Shape.tessellate`` as arrays: the same mesh (``solid.mesh``), faces,
    nodes and triangles in the same order, the same numbers, without a ``Vector`` per node
    (two thirds of its time on the default stack's 24k nodes).

    Returns:
        points (n, 3) mm and triangles (m, 3) point indices (reversed faces' turned)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_Orientation
    from OCP.TopLoc import TopLoc_Location

    solid.mesh(tolerance_mm, angular_rad)
    points: list[tuple[float, float, float]] = []
    tris: list[tuple[int, int, int]] = []
    for face in solid.faces():
        loc = TopLoc_Location()
        poly = BRep_Tool.Triangulation_s(face.wrapped, loc)
        trsf = loc.Transformation()
        offset = len(points) - 1  # OCCT numbers nodes from 1
        for i in range(1, poly.NbNodes() + 1):
            v = poly.Node(i).Transformed(trsf)
            points.append((v.X(), v.Y(), v.Z()))
        if face.wrapped.Orientation() == TopAbs_Orientation.TopAbs_REVERSED:
            tris += [(t.Value(1) + offset, t.Value(3) + offset, t.Value(2) + offset)
                     for t in poly.Triangles()]
        else:
            tris += [(t.Value(1) + offset, t.Value(2) + offset, t.Value(3) + offset)
                     for t in poly.Triangles()]
    return np.array(points, dtype=float).reshape(-1, 3), np.asarray(tris)


def _part_mesh(points, tris):
    """pyvista PolyData of a part in its own frame."""
    import pyvista as pv

    faces = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
    return pv.PolyData(points, faces)


def _placed(mesh, placement):
    """A copy of a part mesh moved to its place in the stack."""
    p = np.asarray(mesh.points, dtype=float)
    out = mesh.copy()
    z = placement.z_mm - p[:, 2] if placement.flipped else placement.z_mm + p[:, 2]
    out.points = np.column_stack([placement.map_xy(p[:, :2]), z])
    return out


def _cut_quarter(mesh):
    """The part without the quarter x > 0, y < 0, as closed pieces (cut faces capped).

    The half x < 0 and the half y > 0 are each clipped with a cap
    (``clip_closed_surface``) and drawn together: an open cut would show the
    parts' inner faces, which touch their neighbours' and flicker in streaks.
    A part whose surface is not closed falls back to an uncapped box clip.
    """
    surf = mesh.clean()
    try:
        pieces = [surf.clip_closed_surface(normal=(-1.0, 0.0, 0.0), origin=(0.0, 0.0, 0.0)),
                  surf.clip_closed_surface(normal=(0.0, 1.0, 0.0), origin=(0.0, 0.0, 0.0))]
    except (RuntimeError, ValueError):
        b = mesh.bounds
        cut = mesh.clip_box((0, max(b[1], 1.0) + 1, min(b[2], -1.0) - 1, 0, b[4] - 1, b[5] + 1),
                            invert=True)
        return [cut.extract_surface()] if cut.n_points else []
    return [q for q in pieces if q.n_points]


def legend_entries(assembly) -> list[tuple[str, tuple]]:
    """One legend row per part colour: (label, RGB 0-1), input side first.

    The label names the parts of that colour by their titles (without the
    sizes after a comma) and says which side carries the input or the output.
    """
    groups: dict[tuple, dict] = {}
    for inst in assembly.instances:
        g = groups.setdefault(tuple(inst.colour), {"titles": [], "roles": set()})
        title = inst.part.info.title.split(",")[0].strip()
        if title not in g["titles"]:
            g["titles"].append(title)
        if inst.role:
            g["roles"].add(inst.role)
    rows = []
    for colour, g in groups.items():
        label = ", ".join(g["titles"][:3]) + (" …" if len(g["titles"]) > 3 else "")
        if g["roles"]:
            label = f"{' and '.join(sorted(g['roles']))}: {label}"
        rows.append((label, colour))
    order = {"input": 0, "output": 1}
    return sorted(rows, key=lambda r: order.get(r[0].split(":")[0], 2))


def _content_box(img, background: float = 0.985, margin: float = 0.015):
    """Pixel rows and columns holding the model (non-white), with a margin (slices)."""
    solid = ~np.all(img > background, axis=-1)
    rows, cols = np.flatnonzero(solid.any(axis=1)), np.flatnonzero(solid.any(axis=0))
    if rows.size == 0:
        return slice(None), slice(None)
    pad = int(margin * max(img.shape[:2]))
    return (slice(max(0, rows[0] - pad), min(img.shape[0], rows[-1] + 1 + pad)),
            slice(max(0, cols[0] - pad), min(img.shape[1], cols[-1] + 1 + pad)))


def _render_model(assembly, size, cutaway: bool, triangles=None):
    """The stack rendered off-screen, no text; an RGB float image."""
    import pyvista as pv

    quiet_vtk()
    pv.OFF_SCREEN = True
    triangles = part_triangles(assembly) if triangles is None else triangles
    meshes = {pn: _part_mesh(*triangles[pn]) for pn in assembly.parts}
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background("white")
    plotter.enable_depth_peeling(8)  # the see-through bushing without sorting streaks
    r = max(float(np.abs(m.points[:, :2]).max()) for m in meshes.values())
    z_lo = min(i.z_range_mm[0] for i in assembly.instances)
    z_hi = max(i.z_range_mm[1] for i in assembly.instances)
    for inst in assembly.instances:
        mesh = _placed(meshes[inst.part.part_number], inst.placement)
        opacity = 0.35 if inst.component.kind == "bushing" else 1.0
        for piece in (_cut_quarter(mesh) if cutaway else [mesh]):
            # normals split at sharp edges: smooth curved walls, crisp edges (flat shading of
            # the long thin tessellation triangles drew streaks on the flexure walls)
            piece = piece.triangulate().compute_normals(split_vertices=True, feature_angle=35.0,
                                                        auto_orient_normals=False)
            plotter.add_mesh(piece, color=inst.colour, smooth_shading=True, opacity=opacity,
                             specular=0.2)
    plotter.enable_parallel_projection()
    plotter.camera_position = [(2.2 * r, -3.0 * r, 0.5 * (z_lo + z_hi) + 2.6 * r),
                               (0.0, 0.0, 0.5 * (z_lo + z_hi)), (0, 0, 1)]
    plotter.reset_camera()
    _fill_view(plotter, size)
    img = plotter.screenshot(None, return_img=True)
    plotter.close()
    trim_heap()  # VTK's frame buffers, before the picture's arrays and matplotlib's
    return _unit_rgb(img)


def _unit_rgb(img) -> np.ndarray:
    """An RGB(A) uint8 screenshot as RGB floats in 0..1, divided in place (the same numbers as
    ``img / 255.0`` without a second 46 MB array at 1600 x 1200)."""
    rgb = np.asarray(img[..., :3], dtype=float)
    rgb /= 255.0
    return rgb


def _fill_view(plotter, size, fill: float = 0.96) -> None:
    """Centre the model in the view and zoom until it fills ``fill`` of it (parallel view).

    ``reset_camera`` frames the bounding sphere, which leaves the tilted stack in
    the middle third of the picture; one trial render measures where it is.
    """
    shot = plotter.screenshot(None, return_img=True)[..., :3]
    # on the bytes: v / 255 > 0.985 exactly when v > 0.985 * 255 (v >= 252), without a
    # 46 MB float copy beside VTK's frame buffers (the render's memory peak)
    rows, cols = _content_box(shot, background=0.985 * 255.0, margin=0.0)
    if rows.start is None:
        return
    h, w = shot.shape[:2]
    cam = plotter.camera
    px_mm = 2.0 * cam.parallel_scale / h  # world size of one pixel
    dx = 0.5 * (cols.start + cols.stop) - 0.5 * w  # content centre offset (px, right, down)
    dy = 0.5 * (rows.start + rows.stop) - 0.5 * h
    view = np.subtract(cam.focal_point, cam.position)
    view /= np.linalg.norm(view)
    up = np.asarray(cam.up, dtype=float)
    up = up - (up @ view) * view
    up /= np.linalg.norm(up)
    right = np.cross(view, up)
    shift = px_mm * (dx * right - dy * up)
    cam.focal_point = tuple(np.add(cam.focal_point, shift))
    cam.position = tuple(np.add(cam.position, shift))
    zoom = fill * min(w / (cols.stop - cols.start), h / (rows.stop - rows.start))
    cam.parallel_scale = cam.parallel_scale / zoom


#: title position (figure fraction, top-left anchored): clear of the edges
TITLE_XY = (0.02, 0.975)
#: the model's area below the title (figure fraction of the height)
_TOP = 0.92


def _layout(image_aspect: float, size, n_entries: int):
    """Axes box and legend placement: the legend beside or below the model, whichever
    leaves the model the larger picture (an image fills its axes only at one aspect)."""
    w, h = size
    side = (0.01, 0.01, 0.72, _TOP - 0.01)
    rows = -(-n_entries // 3)
    strip = min(0.3, 0.045 * (rows + 1) * 1200 / h)
    below = (0.01, strip + 0.01, 0.98, _TOP - strip - 0.02)

    def fill(box):  # fraction of the axes the image covers
        ax_aspect = box[2] * w / (box[3] * h)
        return min(image_aspect / ax_aspect, ax_aspect / image_aspect) * box[2] * box[3]

    if fill(side) >= fill(below):
        return side, {"loc": "center left", "bbox_to_anchor": (0.74, 0.5)}
    return below, {"loc": "lower center", "bbox_to_anchor": (0.5, 0.005), "ncol": 3}


def render_png(assembly, path: Path, size=(1600, 1200), cutaway: bool = True,
               triangles=None) -> Path:
    """Render the assembly to a PNG: the model framed tight, a title, a legend of part colours.

    Args:
        assembly: a :class:`~springcad.geometry.stack.StackAssembly`.
        path: output file.
        size: image size in pixels.
        cutaway: remove the quarter x > 0, y < 0 to show the inside.
        triangles: the parts' tessellation (:func:`part_triangles`), made from the solids
            if None.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    img = _render_model(assembly, size, cutaway, triangles)
    rows, cols = _content_box(img)
    img = img[rows, cols]
    dpi = size[0] / 16.0  # a 16-inch-wide figure: text keeps its share of any image size
    fig = plt.figure(figsize=(16.0, size[1] / dpi), dpi=dpi)
    entries = legend_entries(assembly)
    box, legend_kw = _layout(img.shape[1] / img.shape[0], size, len(entries))
    ax = fig.add_axes(box)
    ax.imshow(img, interpolation="antialiased")
    ax.set_axis_off()
    st = assembly.design.stack
    fig.text(TITLE_XY[0], TITLE_XY[1], f"{assembly.design.job.name}: {' + '.join(st.sequence)}  "
             f"(input {st.input}, output {st.output})", fontsize=15, va="top")
    handles = [Patch(facecolor=c, edgecolor="0.3", label=textwrap.fill(label, 34))
               for label, c in entries]
    fig.canvas.draw()
    for fontsize in (11, 10, 9, 8, 7):  # the legend stays inside the picture
        legend = fig.legend(handles=handles, fontsize=fontsize, frameon=False,
                            title="part colours", title_fontsize=fontsize + 1, alignment="left",
                            **legend_kw)
        box = legend.get_window_extent(fig.canvas.get_renderer())
        if box.x1 <= fig.bbox.x1 - 4 and box.y0 >= 2:
            break
        legend.remove()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return Path(path)
