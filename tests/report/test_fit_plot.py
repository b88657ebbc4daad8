"""torque_deflection.png and crossover.png: the measured data is drawn above every model."""

from __future__ import annotations

import pytest

import springcad as sc
from springcad.report.fit_report import _pyplot, models_figure


@pytest.fixture(scope="module")
def fitted():
    return sc.fit_record(sc.simulate(150.0, backlash_rad=0.011, seed=2))


@pytest.mark.parametrize("zoom", [False, True])
def test_measured_data_is_on_top(fitted, zoom):
    plt = _pyplot()
    fig = models_figure(plt, fitted.raw, zoom)
    lines = fig.axes[0].get_lines()
    data = [ln for ln in lines if ln.get_label() == "measured"]
    models = [ln for ln in lines if ln.get_label() != "measured"]
    assert len(data) == 1 and len(models) >= 3  # linear, deadband, logit (+ final)
    assert all(data[0].get_zorder() > m.get_zorder() for m in models)
    plt.close(fig)
