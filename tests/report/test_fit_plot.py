"""torque_deflection.png and crossover.png: the measured data is drawn above every model."""

from __future__ import annotations

import pytest

import springcad as sc
from springcad.report.fit_plots import models_figure
from springcad.report.mpl import pyplot as _pyplot
from tests.browser import assert_rendered, assert_self_contained, headings, needs_chromium, screenshot


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


@needs_chromium
def test_fit_report_html_is_self_contained_and_renders(fitted, tmp_path):
    from springcad.report.fit_report import write_fit_outputs

    out = tmp_path / "fit"
    out.mkdir()
    written = {p.name for p in write_fit_outputs(fitted.raw, out)}
    assert {"report.md", "report.html", "torque_deflection.png"} <= written
    text = (out / "report.html").read_text(encoding="utf-8")
    assert_self_contained(text)
    h2 = headings(text)
    assert h2[0] == "Verdict" and {"Paper models (Section II-B)", "Residual loop"} <= set(h2)
    # the plots are inside the page (base64 of the very PNG written beside it)
    import base64

    png = base64.b64encode((out / "torque_deflection.png").read_bytes()).decode()
    assert png in text
    k = fitted.to_dict()["paper_models"]["deadband"]["stiffness_Nm_per_rad"]
    assert f"{k:.4g}" in text
    assert_rendered(screenshot(out / "report.html", tmp_path))
