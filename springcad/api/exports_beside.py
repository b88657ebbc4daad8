"""The exports' share for second processes (:mod:`springcad.parallel`), beside the build's own
STEP/STL and DXF exports and read-backs (:func:`springcad.api.pipeline.export_build`): the
parts' drawings, then the assembly render (and the FEA files when they were not written
ahead). One at a time: the render's VTK frame buffers and the drawings' matplotlib sheets in
two processes beside the build's were its memory peak (default job: 0.99 GB).

Units: lengths mm.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from springcad.parallel import Pending, beside, enabled, trim_heap
from springcad.report.fea_outputs import write_outputs


def render_inputs(assembly, tmp: Path, render: bool, store, track) -> tuple:
    """``(png, triangles)``: the assembly render's files from the cache ([] without a render)
    and None, or None and the parts' tessellation for :func:`fea_and_render` (made here:
    the CAD kernel stays in this process)."""
    from springcad.export.bundle import cached_render
    from springcad.export.render import part_triangles
    from springcad.export.skeleton import with_solids

    if not render:
        return [], None
    png = cached_render(assembly, tmp, store)
    if png is not None:
        track("assembly.png from the cache")
        return png, None
    return None, part_triangles(with_solids(assembly))


@contextlib.contextmanager
def fea_and_render(ver, assembly, tmp: Path, png, triangles, store, track):
    """The FEA files (``fea/``: fea.json, .vtu fields, PNG renders) of a verified build and the
    assembly render (unless ``png`` holds it: :func:`render_inputs`), written by a second
    process beside the part exports (:func:`springcad.parallel.beside`). Yields a pending
    result whose ``.result()`` is (FEA files, render files)."""
    render = png is None or bool(png)
    if ver is not None:
        (tmp / "fea").mkdir()
    if ver is None and png is not None:
        yield Pending(value=([], png))
        return
    if ver is not None and not render:
        yield Pending(value=(write_outputs(ver.raw, tmp / "fea", render=False, progress=track,
                                           cache=store), []))
        return
    if enabled():
        track("writing the " + " and ".join(
            (["FEA outputs (.vtu, renders)"] if ver is not None else [])
            + (["assembly render"] if png is None else [])) + " in a second process")
    with beside(_writefea_and_render, None if ver is None else ver.raw, assembly, tmp, png,
                triangles, cache=store, progress=track) as pending:
        yield pending


def _writefea_and_render(ver_raw, assembly, tmp: Path, png, triangles, cache=None,
                          progress=None) -> tuple[list, list]:
    """The second process's share of the exports (:func:`fea_and_render`): the FEA outputs
    (when verified), then the assembly render from ``triangles`` (unless ``png`` holds the
    cached one)."""
    from springcad.export.bundle import export_render

    fea = ([] if ver_raw is None else
           write_outputs(ver_raw, tmp / "fea", render=True, cache=cache, progress=progress))
    if png is None:
        trim_heap()  # the FEA renders' freed buffers, before the assembly render's
        png = export_render(assembly, tmp, progress=progress, cache=cache, triangles=triangles)
    return fea, png


@contextlib.contextmanager
def part_drawings(assembly, tmp: Path, info: dict, template, store, track):
    """The parts' drawings (:func:`springcad.export.bundle.export_part_drawings`: no CAD
    kernel), written by a second process beside the STEP/STL and DXF exports, the assembly
    and the read-backs when the solids are built (a cached, lazy assembly's are cached too,
    or would be built in the child); yields a pending result whose ``.result()`` is the
    list of files."""
    from springcad.export.bundle import export_part_drawings
    from springcad.export.skeleton import LazyAssembly

    if not enabled() or isinstance(assembly, LazyAssembly):
        yield Pending(value=export_part_drawings(assembly, tmp, info, template, progress=track,
                                                 cache=store))
        return
    track("writing the drawings in a second process")
    with beside(export_part_drawings, assembly, tmp, info, template, cache=store,
                progress=track) as pending:
        yield pending
