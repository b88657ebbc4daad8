"""The FEA stress PNG: its title gives the one peak that fea.json and the console report."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import springcad as sc
from springcad.report.fea_png import peak_title
from tests.conftest import template


def test_peak_title_rounds_like_the_console():
    assert peak_title("S1 at 16.0° (2d)", 1050.6, "root fillet") == \
        "S1 at 16.0° (2d): peak von Mises 1051 MPa at the root fillet"


@pytest.mark.slow
def test_png_title_peak_equals_fea_json_and_console(tmp_path):
    """A 2D verification of S1 (three levels), written as the build writes it."""
    from PIL import Image

    from springcad.report.fea_outputs import write_outputs

    v = sc.verify(sc.design_job(template("paper_S1")), model="2d", levels=3, keep_fields=True)
    written = write_outputs(v.raw, tmp_path)
    peak = json.loads((tmp_path / "fea.json").read_text())["springs"]["S1"]["peak_von_mises_MPa"]
    console = v.summary()
    assert re.search(rf"\b{peak:.0f}\b", console)  # the console's sigma column
    mesh_peak = v.raw.springs["S1"].run.study.finest.peak_von_mises_MPa
    for name in ("S1_von_mises.png", "S1_von_mises_peak.png"):
        assert tmp_path / name in written
        title = Image.open(tmp_path / name).text["Title"]
        numbers = re.findall(r"(\d+) MPa", title)
        assert numbers == [f"{peak:.0f}"], title  # one peak value, the reported one
    # the finest mesh's own maximum is a different number (discretisation error), which
    # is why the old title (mesh peak) and the console disagreed
    assert mesh_peak != pytest.approx(peak, abs=1e-9)
    # the von Mises renders drawn by a second process beside the rest: the same files, bytes
    # and order (what springcad verify writes through sc.export_verification)
    beside = tmp_path / "beside"
    beside.mkdir()
    again = write_outputs(v.raw, beside, beside_renders=True)
    assert [p.name for p in again] == [p.name for p in written]
    for p in written:
        assert (beside / p.name).read_bytes() == p.read_bytes(), p.name


@pytest.mark.slow
def test_renders_from_the_cache_start_no_second_process(tmp_path, monkeypatch):
    """A verification whose renders the cache holds writes them here: no fork (and no
    matplotlib import) for files that are copied."""
    from springcad.cache import Cache
    from springcad.report import fea_outputs

    v = sc.verify(sc.design_job(template("paper_S1")), model="2d", levels=3, keep_fields=True,
                  contact=False, cache=False)
    for k, spring in enumerate(v.raw.springs.values()):
        spring.cache_key = f"test-key-{k}"  # as a verification read through the cache
    cache = Cache(tmp_path / "cache")
    (tmp_path / "first").mkdir()
    first = fea_outputs.write_outputs(v.raw, tmp_path / "first", cache=cache, beside_renders=True)

    def no_fork(*a, **k):
        raise AssertionError("a second process for renders the cache holds")

    monkeypatch.setattr(fea_outputs, "beside", no_fork)
    (tmp_path / "again").mkdir()
    again = fea_outputs.write_outputs(v.raw, tmp_path / "again", cache=cache, beside_renders=True)
    assert [p.name for p in again] == [p.name for p in first]
    for p in first:
        assert (tmp_path / "again" / p.name).read_bytes() == p.read_bytes(), p.name


def _square_field(n: int = 4):
    """A plane field on the square [0, 10]^2 mm of 2 n^2 quadratic triangles (VTK node
    order), von Mises = 10 x + 5 y MPa at every node (linear: a linear triangle's Gouraud
    shading holds it exactly)."""
    from fea.results import Field

    h = 10.0 / (2 * n)
    idx = {}
    pts = []

    def node(i, j):
        if (i, j) not in idx:
            idx[(i, j)] = len(pts)
            pts.append((i * h, j * h, 0.0))
        return idx[(i, j)]

    cells = []
    for a in range(0, 2 * n, 2):
        for b in range(0, 2 * n, 2):
            c00, c20, c02, c22 = node(a, b), node(a + 2, b), node(a, b + 2), node(a + 2, b + 2)
            cells.append([c00, c20, c22, node(a + 1, b), node(a + 2, b + 1), node(a + 1, b + 1)])
            cells.append([c00, c22, c02, node(a + 1, b + 1), node(a + 1, b + 2), node(a, b + 1)])
    pts = np.array(pts)
    vm = 10.0 * pts[:, 0] + 5.0 * pts[:, 1]
    return Field(points_mm=pts, cells=np.array(cells), displacement_mm=np.zeros_like(pts),
                 von_mises_MPa=vm, excluded=np.zeros(len(pts), bool), thickness_mm=1.0)


def test_plane_field_colours_are_the_nodal_values_through_the_colour_map():
    """The drawn colour at a point is the colour map of the field there (a linear field:
    exact on the linear sub-triangles), read back from the rendered pixels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from springcad.report.fea_png import draw_plane_field, view_extent_mm

    field = _square_field()
    clim = (0.0, 150.0)
    extent = view_extent_mm(field.points_mm, (900, 900), None, None)
    fig, ax = plt.subplots(figsize=(5, 5), dpi=100)
    draw_plane_field(ax, field, clim, extent)
    ax.set_xlim(extent[:2])
    ax.set_ylim(extent[2:])
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    cmap = matplotlib.colormaps["turbo"]
    for x, y in [(1.3, 1.7), (5.0, 5.0), (8.6, 2.2), (3.3, 9.1), (9.4, 9.4)]:
        px, py = ax.transData.transform((x, y))
        row, col = rgba.shape[0] - int(round(py)), int(round(px))
        got = rgba[row, col, :3] / 255.0
        want = np.array(cmap((10 * x + 5 * y) / clim[1])[:3])
        assert np.abs(got - want).max() < 0.04, (x, y, got, want)
    # outside the part: the axes' white background
    px, py = ax.transData.transform((-0.4, 5.0))
    assert (rgba[rgba.shape[0] - int(round(py)), int(round(px)), :3] == 255).all()
    plt.close(fig)


def test_a_zoomed_view_draws_only_the_triangles_it_shows():
    from springcad.report.fea_png import plane_triangles, view_extent_mm

    field = _square_field()
    whole = plane_triangles(field, view_extent_mm(field.points_mm, (900, 900), None, None))
    assert len(whole) == 4 * len(field.cells)  # each quadratic triangle as four
    corner = plane_triangles(field, view_extent_mm(field.points_mm, (900, 900), 0.5,
                                                   (0.2, 0.2)))
    assert 0 < len(corner) < len(whole) / 8
    xy = field.points_mm[corner][:, :, :2]
    assert (xy.min(axis=1) <= 0.7).all()  # every kept triangle reaches into the view
