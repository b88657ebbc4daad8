"""springcad.units: the conversions every module uses give the standard library's bits."""

import math

import numpy as np

from springcad import units


def test_degree_conversions_are_the_standard_ones_for_floats_and_arrays():
    x = np.random.default_rng(1).normal(0.0, 50.0, 2000)
    assert [units.deg_to_rad(float(v)) for v in x] == [math.radians(v) for v in x]
    assert [units.rad_to_deg(float(v)) for v in x] == [math.degrees(v) for v in x]
    assert np.array_equal(units.deg_to_rad(x), np.radians(x))
    assert np.array_equal(units.rad_to_deg(x), np.degrees(x))
    assert units.deg_to_rad(180.0) == math.pi and units.rad_to_deg(math.pi) == 180.0


def test_factors():
    assert units.nmm_to_nm(1500.0) == 1.5
    assert 2.5 * units.UM_PER_MM == 2500.0 and 0.5 * units.NMM_PER_NM * units.J_PER_NMM == 0.5
