"""Work shared between the exports' steps gives the numbers each step computed alone:
the sheets' one text-measuring renderer, and the render's tessellation as arrays."""

from __future__ import annotations

import numpy as np
import pytest

from springcad.export.sheet import Sheet

TEXTS = ["RING-13EC425C", "Ø 65.000 ±0.010", "SCALE 1:1", "DRAWN", "A", "3 × M3 THRU"]


@pytest.mark.parametrize("size, weight", [(3.5, "normal"), (2.5, "bold"), (7.0, "normal")])
def test_text_boxes_equal_those_measured_by_the_sheets_own_renderer(size, weight):
    # reference: the box matplotlib measures with the figure's own Agg canvas renderer,
    # as every sheet did before the renderer was shared
    first, second = Sheet(), Sheet(bottom_mm=-297.0)
    assert first._renderer is second._renderer  # one per process (and dpi)
    for s in TEXTS:
        for sheet in (first, second):
            t, box = sheet._make_text(40.0, sheet.bottom + 60.0, s, size, "left", "bottom",
                                      weight=weight)
            own = t.get_window_extent(sheet._canvas.get_renderer())
            (a, b), (c, d) = sheet.ax.transData.inverted().transform(
                [[own.x0, own.y0], [own.x1, own.y1]])
            assert box == (float(a), float(b), float(c), float(d))


def test_tessellation_arrays_equal_build123ds_tessellate():
    bd = pytest.importorskip("build123d")
    from springcad.export.render import RENDER_ANGULAR_RAD, RENDER_TOLERANCE_MM, tessellate

    def solid():  # a plate with a hole (reversed faces) and a cylinder boss, moved
        plate = bd.Box(30, 20, 4) - bd.Cylinder(5, 4)
        return (plate + bd.Pos(10, 0, 4) * bd.Cylinder(3, 6)).solid().moved(
            bd.Location((1.5, -2.0, 0.5)))

    verts, tris = solid().tessellate(RENDER_TOLERANCE_MM, RENDER_ANGULAR_RAD)
    points, triangles = tessellate(solid(), RENDER_TOLERANCE_MM, RENDER_ANGULAR_RAD)
    assert np.array_equal(points, np.array([(v.X, v.Y, v.Z) for v in verts]))
    assert np.array_equal(triangles, np.asarray(tris))
    assert points.shape[1] == 3 and triangles.shape[1] == 3 and len(triangles) > 50
