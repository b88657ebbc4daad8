"""The root fillet is springcad's choice, not the user's: where the fillets of neighbouring
flexures meet on the rim (a swept or flared root reaches further round than its width),
the design lowers it towards the wire's inside radius instead of refusing the layout with
"a smaller root fillet", for which the config has no key (issue 25; held-out A 4242 g18,
N = 24 fixed: every layout was refused for overlapping fillets)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pytest

from springcad.config import job_from_dict, load_job
from springcad.design.job import design_job
from springcad.design import resize
from springcad.design.ring import RootFilletsOverlap, ring_profile
from springcad.errors import DesignError

DEFAULT = Path(__file__).resolve().parents[1] / "templates" / "default.toml"
G18 = {"job": {"name": "g18"}, "material": {"name": "ti6al4v", "design_stress_MPa": 530.0},
       "springs": {"A": {"target_stiffness_Nm_per_rad": 38, "max_deflection_deg": 29,
                         "outer_radius_mm": 43.0, "thickness_mm": 5.0, "n_flexures": 24}},
       "stack": {"input": "shaft"}, "manufacturing": {"process": "wire_edm"},
       "duty": {"preset": "static"}}


def test_a_fixed_flexure_count_is_not_refused_for_the_fillets_springcad_chose():
    with pytest.raises(DesignError) as refused:
        design_job(job_from_dict(G18), explain=False)
    assert "root fillet" not in str(refused.value), str(refused.value)


def test_the_fillet_is_lowered_only_as_far_as_the_neighbours_need():
    """The default spring with its root fillet set to the whole pitch arc (the fillets
    overlap; with_width's own cap on the fillet is passed by): the profiles are rebuilt
    with a smaller fillet that fits (the ring builds), not below the wire's inside
    radius, and no smaller than one step past the largest that overlaps."""
    d = design_job(load_job(DEFAULT), explain=False).springs["S1"]
    floor = d.manufacturing.min_inside_radius_mm
    pitch_arc_mm = 2 * math.pi * d.root_radius_mm / d.n_flexures
    big = replace(d, root_fillet_radius_mm=pitch_arc_mm)
    with pytest.raises(RootFilletsOverlap):
        ring_profile(big)
    fitted = resize._with_fitting_root_fillet(big)
    assert floor <= fitted.root_fillet_radius_mm < big.root_fillet_radius_mm
    ring_profile(fitted)  # builds
    with pytest.raises(RootFilletsOverlap):
        ring_profile(replace(fitted, root_fillet_radius_mm=fitted.root_fillet_radius_mm
                             / resize.ROOT_FILLET_STEP))
