"""A refused serpentine says which rule binds, with the number that binds it.

The two layouts are the best-ranked ones of held-out specs (``bench/spec_heldout.py
--seed 7311``) that were refused with "the shapes reach ... at most", which read as a
tilt budget short by a hair:

* g13 (``contact_radius_mm`` removed): r_c 9.578 mm, R_r 18.2 mm, N 30, area ratio
  1.874. Shapes reach up to 2.23 at full tilt; the ones reaching 1.874 turn tighter at
  their lobe reversal than the wire cuts (concave edge radius 0.094 mm at best, rule
  0.125 mm). The old message quoted only the shapes short of their budget (1.855).
* g26: r_c 11.44 mm, R_r 19 mm, N 35, area ratio 1.858: every shape is short of its
  budget; the closest reaches 1.835.

Each test holds the quoted number to the search itself: a rule just past it changes the
outcome, a rule just short of it does not.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from springcad.design import flexure as fx
from springcad.design.search import _alike
from springcad.errors import DesignError

#: held-out 7311 g13's best-ranked layout (width law w^2 = C (y - r_c), C in mm)
G13 = dict(target_area_ratio=1.8737, contact_radius_mm=9.5784, root_radius_mm=18.2,
           n_flexures=30, tip_radius_mm=0.5, min_clearance_mm=0.3, min_inside_radius_mm=0.125,
           root_zone_mm=5.6)
G13_C = 0.045787
#: held-out 7311 g26's best-ranked layout
G26 = dict(target_area_ratio=1.8582, contact_radius_mm=11.4415, root_radius_mm=19.0,
           n_flexures=35, tip_radius_mm=0.5, min_clearance_mm=0.35, min_inside_radius_mm=0.15,
           root_zone_mm=5.0)
G26_C = 0.083387

EDGE = re.compile(r"(\d+) reach the area ratio with a concave edge radius below ([\d.]+) mm "
                  r"\(closest (k=\d, a=\d, \w+): keeps (-?[\d.]+) mm\)")
BUDGET = re.compile(r"(\d+) fall short of the tilt budget between neighbours at full tilt "
                    r"\(closest (k=\d, a=\d, \w+): reaches ([\d.]+)\)")


def _serpentine(c_mm: float, **kw):
    rc = kw["contact_radius_mm"]
    return fx.design_serpentine(
        width_fn=lambda y: np.sqrt(c_mm * np.maximum(np.asarray(y) - rc, 0.0)), **kw)


def _refusal(c_mm: float, **kw) -> str:
    with pytest.raises(DesignError) as err:
        _serpentine(c_mm, **kw)
    return str(err.value)


def test_refusal_names_the_edge_radius_when_shapes_reach_the_ratio():
    msg = _refusal(G13_C, **G13)
    edge, budget = EDGE.search(msg), BUDGET.search(msg)
    assert edge and budget, msg
    assert re.search(r"of 33 trial shapes", msg)
    assert int(edge.group(1)) + int(budget.group(1)) == 33
    assert float(budget.group(3)) < G13["target_area_ratio"]
    quoted = float(edge.group(4))
    assert quoted < G13["min_inside_radius_mm"]
    # the quoted edge radius is the one that binds: a wire cutting 1 um less designs it,
    # a wire needing 1 um more does not
    done = _serpentine(G13_C, **{**G13, "min_inside_radius_mm": quoted - 0.001})
    assert done.min_edge_radius_mm >= quoted - 0.001
    assert done.area_ratio == pytest.approx(G13["target_area_ratio"], abs=2e-3)
    assert EDGE.search(_refusal(G13_C, **{**G13, "min_inside_radius_mm": quoted + 0.001}))


def test_refusal_quotes_the_closest_budget_when_every_shape_falls_short():
    msg = _refusal(G26_C, **G26)
    budget = BUDGET.search(msg)
    assert budget and budget.group(1) == "33" and not EDGE.search(msg), msg
    reach = float(budget.group(3))
    assert reach < G26["target_area_ratio"]
    # at an area ratio just above the quoted reach every shape still falls short; just
    # below it one shape reaches (and designs, or fails on another rule)
    above = BUDGET.search(_refusal(G26_C, **{**G26, "target_area_ratio": reach + 0.001}))
    assert above and above.group(1) == "33"
    try:
        _serpentine(G26_C, **{**G26, "target_area_ratio": reach - 0.001})
    except DesignError as err:
        below = BUDGET.search(str(err))
        assert below is None or int(below.group(1)) < 33, str(err)


def test_layouts_refused_by_the_curved_flexure_rule_count_alike():
    """The design search counts the layouts refused by the best-ranked one's rule
    (:func:`springcad.design.search._alike`): the trial shapes' detail differs from layout to
    layout (g13's shapes break the edge radius, g26's fall short of the budget), the rule
    does not."""
    g13, g26 = _refusal(G13_C, **G13), _refusal(G26_C, **G26)
    assert EDGE.search(g13) and not EDGE.search(g26)
    assert fx.without_shape_detail(g13) != g13
    rejected = [(None, DesignError(g13), []), (None, DesignError(g26), []),
                (None, DesignError("flexure roots leave 0.1 mm between them"), [])]
    assert _alike(rejected) == 2
