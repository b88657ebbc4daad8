"""Free space on a drawing sheet: which line segments cross which text boxes.

Pure geometry on sheet millimetres (no figure): a box is (x0, y0, x1, y1), a segment
(x0, y0, x1, y1). :class:`springcad.export.sheet.Sheet` places every label with these.
"""

from __future__ import annotations

import numpy as np


def segments_hit_box(segs: np.ndarray, box) -> np.ndarray:
    """Which segments (n, 4: x0, y0, x1, y1) cross or touch the box (x0, y0, x1, y1)."""
    return segments_hit_boxes(segs, np.asarray([box], dtype=float))[0]


def segments_hit_boxes(segs: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Which segments (n, 4: x0, y0, x1, y1) cross or touch which boxes (m, 4: x0, y0, x1,
    y1): an (m, n) array, each entry :func:`segments_hit_box`'s (the same arithmetic,
    broadcast over the boxes)."""
    segs = np.asarray(segs, dtype=float)
    boxes = np.asarray(boxes, dtype=float)
    if len(segs) == 0 or len(boxes) == 0:
        return np.zeros((len(boxes), len(segs)), dtype=bool)
    p = segs[:, :2]
    d = segs[:, 2:] - p
    shape = (len(boxes), len(segs))
    t0 = np.zeros(shape)
    t1 = np.ones(shape)
    ok = np.ones(shape, dtype=bool)
    for axis in (0, 1):  # Liang-Barsky clipping
        lo, hi = boxes[:, axis, None], boxes[:, axis + 2, None]
        dd, pp = d[:, axis], p[:, axis]
        flat = np.abs(dd) < 1e-12
        ok &= ~flat | ((pp >= lo) & (pp <= hi))
        with np.errstate(divide="ignore", invalid="ignore"):
            ta, tb = (lo - pp) / dd, (hi - pp) / dd
        t_in = np.where(flat, -np.inf, np.minimum(ta, tb))
        t_out = np.where(flat, np.inf, np.maximum(ta, tb))
        t0, t1 = np.maximum(t0, t_in), np.minimum(t1, t_out)
    return ok & (t0 <= t1)


#: the margin (mm) by which a segment's bounding box may miss a box and the segment still be
#: clipped against it: far above the rounding of the clipping's ratios (~1e-12 mm here)
NEAR_MM = 1e-6


def boxes_overlap(a, b) -> bool:
    """Whether two boxes overlap (touching edges do not)."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def grow(box, pad: float):
    """The box grown by ``pad`` (mm) on every side."""
    return (box[0] - pad, box[1] - pad, box[2] + pad, box[3] + pad)
