"""Inputs the fuzz driver (``bench/fuzz_cli.py``, new seeds and families) found failing,
each kept as a fast in-process regression test: one clear :class:`SpringcadError`
naming the spring and what to change, never a library exception.
"""

import re
import tomllib

import pytest

from springcad.config import job_from_dict
from springcad.design.job import design_job
from springcad.errors import DesignError, SpringcadError
from tests.conftest import template


def paper(name="paper_S2"):
    return tomllib.loads(template(name).read_text())


def test_flexure_no_longer_than_its_tip_ball_is_a_design_error():
    """Every length at the top of its range (fuzz family every_length, seed 21): 10 mm tip
    balls on 17.5 mm flexures left nothing above the ball to check, and numpy's
    "zero-size array to reduction operation minimum" escaped the design.

    explain=False: the design's own search, where the error escaped (the neighbour
    clearance of the reference layout), raises the rule itself; the refusal's search for
    changes (explain=True) on this 250 mm disk took 80 s of a quiet core, nearly all of it
    in the reshaped-disk grid (feasibility.reshaped_envelope), and its message ends with the
    same rule after "Why"."""
    data = paper("paper_S2")
    data["springs"]["S2"].update(outer_radius_mm=250.0, thickness_mm=100.0,
                                 contact_radius_mm=200.0, tip_radius_mm=10.0)
    data["manufacturing"].update(t_spring_mm=0.5, t_shaft_mm=0.5, w_gap_mm=1.0)
    data["hardware"] = {"fastener_diameter_mm": 12.0}
    with pytest.raises(DesignError, match=r"spring 'S2'.* the flexures are [0-9.]+ mm long .* no "
                                          r"longer than their tip balls are wide \(20 mm\)"):
        design_job(job_from_dict(data), explain=False)
