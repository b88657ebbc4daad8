"""The biarc fit of the DXF writer (issue 22 speed-ups keep its numbers): the row norms are
numpy's, bit for bit; distances to a line or bulge arc match a dense sampling of it; a fitted
spline's biarcs stay within the tolerance of the spline, sampled densely."""

from __future__ import annotations

import math

import numpy as np

from springcad.design.curves import Spline
from springcad.export.biarc import (_row_norms, arc_centre, distance_to_segment,
                                    spline_biarcs)


def test_row_norms_are_numpys_bit_for_bit():
    rng = np.random.default_rng(3)
    for n in (1, 2, 7, 400):
        v = rng.normal(size=(n, 2)) * 10.0 ** rng.integers(-6, 4, size=(n, 1))
        assert np.array_equal(_row_norms(v), np.linalg.norm(v, axis=1))


def _dense(a, b, bulge, n=20001):
    if not bulge:
        t = np.linspace(0, 1, n)[:, None]
        return a + t * (b - a)
    c, r, sweep = arc_centre(a, b, bulge)
    a0 = math.atan2(a[1] - c[1], a[0] - c[0])
    phi = a0 + np.linspace(0, sweep, n)
    return c + r * np.column_stack([np.cos(phi), np.sin(phi)])


def test_distance_to_segment_against_dense_sampling():
    rng = np.random.default_rng(4)
    for _ in range(60):
        a, b = rng.uniform(-5, 5, 2), rng.uniform(-5, 5, 2)
        bulge = float(rng.choice([0.0, rng.uniform(-1.5, 1.5)]))
        p = rng.uniform(-8, 8, (50, 2))
        pts = _dense(a, b, bulge)
        want = np.min(np.linalg.norm(p[:, None, :] - pts[None], axis=2), axis=1)
        got = distance_to_segment(p, a, b, bulge)
        assert np.allclose(got, want, atol=2e-3)  # the sampling's own step


def test_spline_biarcs_within_tolerance():
    t = np.linspace(0, 1, 9)
    pts = tuple((float(10 * x), float(2 * math.sin(3 * x) + x * x)) for x in t)
    spline = Spline(pts, (1.0, 0.0), (0.0, 1.0))
    verts, worst, count = spline_biarcs(spline, 1e-3)
    assert count >= 1 and worst <= 1e-3
    ends = [np.array(v[:2]) for v in verts] + [np.array(pts[-1])]
    dense = spline.sample(0.002)
    dist = np.min(np.stack([distance_to_segment(dense, ends[k], ends[k + 1], verts[k][2])
                            for k in range(len(verts))]), axis=0)
    assert dist.max() <= 1.5e-3  # the fit's tolerance, checked between its samples too
