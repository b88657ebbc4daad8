"""assembly.png layout, without CAD: the legend of part colours, tight framing, title margins."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from springcad.export.render import _content_box, _layout, legend_entries


def inst(title, colour, role=""):
    return SimpleNamespace(part=SimpleNamespace(info=SimpleNamespace(title=title)),
                           colour=colour, role=role)


def test_legend_has_one_row_per_colour_input_first():
    steel, green, orange = (0.6, 0.6, 0.6), (0.2, 0.6, 0.3), (0.8, 0.3, 0.2)
    asm = SimpleNamespace(instances=[
        inst("Flexure ring, 28 flexures", steel), inst("Flexure ring, 28 flexures", steel),
        inst("Rim flange", orange, "output"), inst("Torque shaft", green, "input"),
        inst("End camshaft, 28 teeth", green, "input")])
    rows = legend_entries(asm)
    assert [c for _, c in rows] == [green, orange, steel]
    assert rows[0][0] == "input: Torque shaft, End camshaft"  # sizes after the comma dropped
    assert rows[1][0] == "output: Rim flange" and rows[2][0] == "Flexure ring"


def test_content_box_is_the_model_plus_margin():
    img = np.ones((200, 300, 3))
    img[50:80, 100:250] = 0.3
    rows, cols = _content_box(img, margin=0.0)
    assert (rows.start, rows.stop, cols.start, cols.stop) == (50, 80, 100, 250)
    rows, cols = _content_box(img, margin=0.02)  # 2 % of 300 px = 6 px
    assert (rows.start, rows.stop, cols.start, cols.stop) == (44, 86, 94, 256)


@pytest.mark.parametrize("aspect", [0.8, 1.6, 2.5])
def test_layout_leaves_the_model_most_of_the_picture(aspect):
    size = (1600, 1200)
    box, legend = _layout(aspect, size, 7)
    ax_aspect = box[2] * size[0] / (box[3] * size[1])
    filled = min(aspect / ax_aspect, ax_aspect / aspect) * box[2] * box[3]
    assert filled > 0.45  # the model never leaves a mostly empty half
    assert box[1] + box[3] <= 0.93  # below the title
    # a wide model gets the legend below it, a tall one beside it
    assert legend["loc"] == ("lower center" if aspect > 1.5 else "center left")
