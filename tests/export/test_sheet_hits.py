"""The drawing sheet's free-space tests, against a brute-force reference: the pruned
line test (segments near the box only) and the boxes-at-once path test give the answers
clipping every segment against every box one at a time gives."""

import numpy as np

from springcad.export.sheet import Sheet
from springcad.export.sheet_hits import segments_hit_box, segments_hit_boxes


def _reference_hit(segs, box) -> np.ndarray:
    """Point-in-box / edge-crossing test of each segment, by a dense parameter sweep plus
    the exact end and crossing points (independent of the Liang-Barsky clipping)."""
    out = []
    x0, y0, x1, y1 = box
    for a, b, c, d in segs:
        p, q = np.array([a, b]), np.array([c, d])
        ts = [0.0, 1.0] + list(np.linspace(0, 1, 2001))
        for axis, lo, hi in ((0, x0, x1), (1, y0, y1)):
            dd = q[axis] - p[axis]
            if abs(dd) > 1e-12:
                ts += [(lo - p[axis]) / dd, (hi - p[axis]) / dd]
        pts = [p + t * (q - p) for t in ts if 0.0 <= t <= 1.0]
        out.append(any(x0 - 1e-9 <= x <= x1 + 1e-9 and y0 - 1e-9 <= y <= y1 + 1e-9
                       for x, y in pts))
    return np.array(out)


def test_boxes_at_once_equal_one_at_a_time():
    rng = np.random.default_rng(7)
    segs = rng.uniform(0, 100, (60, 4))
    segs[:5, 2] = segs[:5, 0]  # vertical
    segs[5:10, 3] = segs[5:10, 1]  # horizontal
    lo = rng.uniform(0, 90, (40, 2))
    boxes = np.hstack([lo, lo + rng.uniform(0.5, 20, (40, 2))])
    many = segments_hit_boxes(segs, boxes)
    assert many.shape == (40, 60)
    for k, box in enumerate(boxes):
        assert np.array_equal(many[k], segments_hit_box(segs, tuple(box)))
    assert many.any() and not many.all()
    # and the clipping answers what the sweep does where the sweep is sure (not grazing)
    for k in range(10):
        assert np.array_equal(many[k], _reference_hit(segs, boxes[k]))
    assert segments_hit_boxes(segs, np.zeros((0, 4))).shape == (0, 60)


def test_pruned_line_test_equals_clipping_every_segment():
    rng = np.random.default_rng(11)
    sheet = Sheet()
    for _ in range(30):  # polylines, some touching or ending on box edges below
        sheet._add_segments(rng.uniform(20, 200, (rng.integers(2, 40), 2)))
    sheet._add_segments(np.array([[250.0, 250.0], [260.0, 250.0]]))  # on the edge of a box
    segs = sheet.segments
    boxes = [(250.0, 240.0, 270.0, 250.0), (260.0, 250.0, 280.0, 260.0),
             (240.0, 250.0 + 1e-7, 270.0, 255.0)]
    lo = rng.uniform(10, 200, (300, 2))
    boxes += [tuple(b) for b in np.hstack([lo, lo + rng.uniform(0.1, 15, (300, 2))])]
    answers = [sheet._lines_hit(box) for box in boxes]
    assert answers == [bool(segments_hit_box(segs, box).any()) for box in boxes]
    assert answers[0] and answers[1] and not answers[2]
    assert any(answers) and not all(answers)
