"""The DXF writer measures its extents on the entities that can reach them
(:func:`springcad.export.dxf._hull_entities`, issue 22): the same $EXTMIN/$EXTMAX and view as
ezdxf's own measurement of every entity, bit for bit. Reference: ezdxf's ``bbox.extents``
of the whole modelspace (exact and control-point boxes) and ``zoom.extents``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from springcad.design.curves import Arc, Circle, Line, Loop, Profile
from springcad.export.dxf import _arc_bound, _hull_entities, write_dxf


def _drawing(rng, n: int):
    """Random LINE/ARC/CIRCLE entities (small arcs inside, large-radius and full-sweep arcs,
    some near the border) and a TEXT below them."""
    import ezdxf

    doc = ezdxf.new("R2010", setup=False)
    msp = doc.modelspace()
    for _ in range(n):
        kind = rng.integers(0, 3)
        c = rng.uniform(-30, 30, 2)
        if kind == 0:
            msp.add_line(tuple(c), tuple(c + rng.uniform(-5, 5, 2)))
        elif kind == 1:
            r = float(rng.choice([rng.uniform(0.05, 3), rng.uniform(20, 400)]))
            a0 = float(rng.uniform(0, 360))
            sweep = float(rng.choice([rng.uniform(0.01, 3), rng.uniform(3, 359)]))
            msp.add_arc(tuple(c), r, a0, (a0 + sweep) % 360)
        else:
            msp.add_circle(tuple(c), float(rng.uniform(0.1, 10)))
    msp.add_text("PART-1 t=5 mm", height=2.5).set_placement((-30, -45))
    return doc, msp


def _boxes(entities):
    from ezdxf import bbox

    exact, fast = bbox.extents(entities), bbox.extents(entities, fast=True)
    return (tuple(exact.extmin), tuple(exact.extmax), tuple(fast.extmin), tuple(fast.extmax))


@pytest.mark.parametrize("seed", range(12))
def test_hull_measures_what_every_entity_measures(seed):
    rng = np.random.default_rng(seed)
    doc, msp = _drawing(rng, int(rng.integers(5, 400)))
    hull = _hull_entities(msp)
    assert _boxes(hull) == _boxes(msp)
    assert len(hull) <= len(msp)


def test_arc_bound_holds_ezdxf_control_points():
    """Every Bezier control point ezdxf makes of an arc lies in :func:`_arc_bound`."""
    import ezdxf
    from ezdxf import path

    msp = ezdxf.new("R2010", setup=False).modelspace()
    rng = np.random.default_rng(5)
    for _ in range(300):
        c, r = rng.uniform(-50, 50, 2), float(rng.uniform(0.01, 500))
        a0, a1 = (float(v) for v in rng.uniform(0, 360, 2))
        arc = msp.add_arc(tuple(c), r, a0, a1)
        pts = np.array([(v.x, v.y) for v in path.make_path(arc).control_vertices()])
        x0, y0, x1, y1 = _arc_bound(c[0], c[1], r, a0, a1)
        assert (pts[:, 0] >= x0).all() and (pts[:, 0] <= x1).all()
        assert (pts[:, 1] >= y0).all() and (pts[:, 1] <= y1).all()
        # and the bound is tight: within the control hull's growth of the arc's own box
        assert x1 - x0 <= 2 * r * (1 + 4 / 3 * math.tan(math.pi / 8)) * (1 + 1e-6) + 1e-6


def test_written_dxf_view_and_extents_are_ezdxfs(tmp_path):
    """A written DXF's $EXTMIN/$EXTMAX and active VPORT are those ezdxf's bbox.extents and
    zoom.extents give on the file's own modelspace."""
    import ezdxf
    from ezdxf import bbox, zoom

    outer = Loop((Line((0.0, 0.0), (40.0, 0.0)), Line((40.0, 0.0), (40.0, 20.0)),
                  Arc((20.0, 20.0), 20.0, 0.0, math.pi), Line((0.0, 20.0), (0.0, 0.0))))
    profile = Profile(outer, (Loop((Circle((20.0, 10.0), 3.0),)),))
    path = write_dxf(profile, tmp_path / "p.dxf", "P-1", 3.0).path
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    box = bbox.extents(msp)
    assert (tuple(doc.header["$EXTMIN"]), tuple(doc.header["$EXTMAX"])) == (
        tuple(box.extmin), tuple(box.extmax))
    vport = doc.viewports.get("*Active")[0]
    seen = (tuple(vport.dxf.center), vport.dxf.height)
    zoom.extents(msp)
    vport = doc.viewports.get("*Active")[0]
    assert seen == (tuple(vport.dxf.center), vport.dxf.height)
