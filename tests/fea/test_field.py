"""``Verification.field``: the FE field as plain arrays, held to the design it came from."""

from __future__ import annotations

import numpy as np
import pytest

import springcad as sc
from springcad.errors import ConfigError
from tests.conftest import template


@pytest.fixture(scope="module")
def verified():
    return sc.verify(template("paper_S2"), model="2d", contact=False, keep_fields=True)


def test_field_arrays_describe_the_solved_sector(verified):
    f = verified.field("S2")
    spring = verified.raw.springs["S2"]
    design, finest = spring.design, spring.run.study.finest
    n = len(f.points_mm)
    assert f.points_mm.shape == f.displacement_mm.shape == (n, 3)
    assert f.von_mises_MPa.shape == f.excluded.shape == (n,)
    assert f.cells.shape[1] == 6 and f.cells.min() == 0 and f.cells.max() == n - 1
    assert not np.any(f.points_mm[:, 2]) and not np.any(f.displacement_mm[:, 2])  # 2D
    # the reported peak is the largest nodal stress outside the excluded zones
    assert f.von_mises_MPa[~f.excluded].max() == finest.peak_von_mises_MPa
    # the cells cover one flexure's share of the ring profile (straight-sided corners: 1 %)
    p, c = f.points_mm[:, :2], f.cells[:, :3]
    e1, e2 = p[c[:, 1]] - p[c[:, 0]], p[c[:, 2]] - p[c[:, 0]]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    assert area == pytest.approx(design.profile_area_mm2 / design.n_flexures, rel=0.02)
    # the cam turns the ball by theta_max: the tip moves r_c theta_max
    r = np.hypot(p[:, 0], p[:, 1])
    tip = np.abs(r - design.contact_radius_mm) < 0.05
    assert np.linalg.norm(f.displacement_mm[tip], axis=1).max() == pytest.approx(
        design.contact_radius_mm * design.max_deflection_rad, rel=0.02)


def test_field_refuses_what_it_does_not_have(verified):
    with pytest.raises(ConfigError, match="option spring = 'X': is one of 'S2'"):
        verified.field("X")
    with pytest.raises(ConfigError, match="needs the 3D check"):
        verified.field("S2", model="3d")
