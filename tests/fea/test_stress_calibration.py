"""The design-side stress model against its FEA calibration, re-run in part.

The shipped coefficients (``springcad/data/stress_calibration.json``) are the fit of
the shipped rows; fresh FEA solves of calibration cases reproduce the rows and the
model predicts their peak within 5 %.
"""

from __future__ import annotations

import json
from importlib import resources

import pytest


@pytest.fixture(scope="module")
def shipped():
    return json.loads(resources.files("springcad.data").joinpath("stress_calibration.json")
                      .read_text())


def test_shipped_coefficients_are_the_fit_of_the_shipped_rows(shipped):
    from springcad.design.stress import calibration, fit_calibration

    from springcad.design.stress import flank_by_shape

    refit = fit_calibration(shipped["rows"]).to_dict()
    for key, value in shipped["coefficients"].items():
        assert refit[key] == pytest.approx(value, rel=1e-9, abs=1e-12), key
    by_shape = flank_by_shape(shipped["rows"])
    assert set(by_shape) == set(shipped["flank_by_shape"]) == {"straight", "serpentine"}
    for shape, coefficients in shipped["flank_by_shape"].items():
        for key, value in coefficients.items():
            assert by_shape[shape][key] == pytest.approx(value, rel=1e-9, abs=1e-12), key
            assert getattr(calibration(shape), key) == value
    assert calibration().cases == len(shipped["rows"]) >= 15
    assert calibration().max_error_pct < 6.0
    # the set spans the flares the design chooses from and more than one geometry
    assert {r["root_flare"] for r in shipped["rows"]} >= {0.0, 0.1, 0.2, 0.3}
    assert len({r["case"] for r in shipped["rows"]}) >= 4


@pytest.mark.parametrize("case, flare", [("paper_S2", 0.1), ("default", 0.2)])
def test_fresh_fea_reproduces_the_calibration(shipped, case, flare):
    """Re-run two calibration cases (the bench script's geometry) and compare with the rows."""
    import importlib.util
    from pathlib import Path

    from springcad.design.resize import with_root
    from springcad.design.stress import calibration, predict_row

    from fea.calibrate import calibration_row

    path = Path(__file__).resolve().parents[2] / "bench" / "calibrate_stress.py"
    spec = importlib.util.spec_from_file_location("calibrate_stress", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    design, = bench.calibration_designs(labels=(case,)).values()  # this case only
    row = calibration_row(with_root(design, flare), case)
    old = next(r for r in shipped["rows"] if r["case"] == case and r["root_flare"] == flare)
    assert row["fea_peak_MPa"] == pytest.approx(old["fea_peak_MPa"], rel=0.01)
    assert row["root_nominal_MPa"] == pytest.approx(old["root_nominal_MPa"], rel=0.01)
    assert predict_row(row, calibration()) == pytest.approx(row["fea_peak_MPa"], rel=0.05)


def test_winkler_factor_closed_form():
    """Winkler-Bach inner fibre factor: straight bar 1; R/c = 2 gives 1.52 (Roark table)."""
    import numpy as np

    from springcad.design.stress import winkler_factors

    inner, outer = winkler_factors(np.array([2.0, 2.0]), np.array([0.0, 1.0 / 2.0]))
    assert inner[0] == pytest.approx(1.0) and outer[0] == pytest.approx(1.0)
    # R = 2, c = 1 (R/c = 2): exact Winkler-Bach for a rectangle
    R, c = 2.0, 1.0
    rn = 2 * c / np.log((R + c) / (R - c))
    e = R - rn
    k_in = (rn - (R - c)) / (2 * c * e * (R - c)) / (6 / (2 * c) ** 2)
    assert inner[1] == pytest.approx(k_in, rel=1e-12)
    assert inner[1] == pytest.approx(1.52, abs=0.01)


def test_winkler_factor_nearly_straight_bar():
    """Where the curvature changes sign the bar is nearly straight: the factors follow their
    Taylor expansion 1 +- (w kappa)/3 + O((w kappa)^2) smoothly, without the cancellation
    spike of the direct formula (it gave 1.24 at w kappa ~ 1e-5 on a calibration spring)."""
    import numpy as np

    from springcad.design.stress import winkler_factors

    eps = np.logspace(-8, -2, 200)  # w * kappa
    inner, outer = winkler_factors(np.full_like(eps, 2.0), eps / 2.0)
    assert np.all(np.abs(inner - 1 - eps / 3) < eps ** 2 + 1e-14)
    assert np.all(np.abs(outer - 1 + eps / 3) < eps ** 2 + 1e-14)
    assert np.all(np.diff(inner) > 0) and np.all(np.diff(outer) < 0)
