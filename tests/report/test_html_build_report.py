"""``report.html`` of a build: content from the build's files, rendered by headless Chromium."""

from __future__ import annotations

import json
import re

import pytest

from springcad.report.html_build import SECTIONS, render_build_report, verdict
from tests.browser import assert_rendered, assert_self_contained, needs_chromium, screenshot


@pytest.fixture(scope="module")
def built(s1_cli_build):
    """An S1 build without FEA (the session's, tests/conftest.py): the report must say it is
    not for manufacture."""
    code, out = s1_cli_build
    assert code == 0
    return out


def test_verdict_uses_build_json_and_explains_refusals():
    assert verdict({"verdict": "released", "reasons": []}, None) == (True, [])
    ok, why = verdict({"verdict": {"status": "not for manufacture", "reasons": ["rev A draft"]}},
                      None)
    assert not ok and why == ["rev A draft"]
    verified = {"verification": {"ok": True}, "checks": {"passed": True}}
    assert verdict(verified, {"failures": []}) == (True, [])
    ok, why = verdict({"verification": "skipped (--no-verify)", "checks": {"passed": True}}, None)
    assert not ok and "not FEA-verified" in why[0]
    ok, why = verdict({"release": {"released": False, "reasons": ["design warning: w"]},
                       "verification": {"ok": True}}, None)
    assert not ok and why == ["design warning: w"]
    ok, why = verdict({"verification": {"ok": False}, "checks": {"passed": True}},
                      {"failures": ["S1: K 3 % low"]})
    assert not ok and "S1: K 3 % low" in why


def test_report_is_written_listed_and_self_contained(built):
    text = (built / "report.html").read_text(encoding="utf-8")
    doc = json.loads((built / "build.json").read_text())
    entry = [f for f in doc["files"] if f["path"] == "report.html"]
    assert entry and entry[0]["bytes"] == (built / "report.html").stat().st_size
    positions = [text.index(f"<h2>{s}</h2>") for s in SECTIONS]
    assert positions == sorted(positions)  # verdict first, BOM last
    assert "Not for manufacture" in text and "--no-verify" in text
    # the page gives the release gate's reasons, the ones stamped on the drawings
    import html

    for reason in doc["release"]["reasons"]:
        assert html.escape(reason) in text
    # no network: every image is inline data, the only links are the drawing PDFs
    assert_self_contained(text)
    links = re.findall(r"href='([^']+)'", text)
    pdfs = [p for p in links if p.endswith(".pdf")]
    assert pdfs and all((built / p).is_file() for p in links)  # every link is a built file
    assert "name='viewport'" in text
    # phone width: the figures are marked as desktop figures (shown on narrow screens only)
    from springcad.report.html_build import NARROW_NOTE

    assert text.count(f"<p class='narrow'>{NARROW_NOTE}</p><div class='figs'>") >= 1
    style = text[text.index("<style>"):text.index("</style>")]
    wide, _, narrow = style.partition("@media (max-width:700px){")
    assert ".narrow{display:none" in wide and ".narrow{display:block}" in narrow
    design = json.loads((built / "design.json").read_text())
    k = design["springs"]["S1"]["stiffness_Nm_per_rad"]
    assert f"{k:.4g}" in text
    z = design["springs"]["S1"]["thickness_mm"]  # the plate (chosen or given) is shown
    assert f"<td>disk thickness (mm)</td><td class='n'>{z:.4g}</td>" in text
    import csv

    rows = list(csv.DictReader((built / "bom.csv").open()))
    for r in rows:  # the readable BOM: part number, title, quantity and the files as links
        assert f"<td>{r['part_number']}</td>" in text and f"<td>{r['title']}</td>" in text
        assert all(f"href='{f}'" in text for f in r["files"].split())
    assert render_build_report(built) == text  # rendered from the files alone


@needs_chromium
def test_report_renders_in_headless_chromium(built, tmp_path):
    img = screenshot(built / "report.html", tmp_path)
    assert_rendered(img)
    red = (img[..., 0] > 200) & (img[..., 1] < 240) & (img[..., 2] < 235) & \
          (img[..., 0] - img[..., 1] > 15)
    assert red[:500].sum() > 1000  # the verdict box is near the top


def test_every_negative_stack_quantity_says_what_below_zero_means():
    """Backlash bounds below 0 (a preloaded, interfering cam: the paper 4xS1's worst case
    -0.0655 and RSS -0.0041 rad) are explained in their row's label, not left bare."""
    from springcad.report.html_build import _spec_rows

    design = {"springs": {}, "stack": {"backlash_rad": {
        "nominal": 0.036, "worst_min": -0.0655, "worst_max": 0.138,
        "rss_min": -0.0041, "rss_max": 0.0769}}}
    rows = re.findall(r"<tr><td>([^<]*)</td><td class='n'>([^<]*)</td></tr>",
                      _spec_rows(design, None))
    negative = [label for label, value in rows if re.search(r"(^|\s)-\d", value)]
    assert len(negative) == 2, rows  # worst case and RSS
    assert all("below 0" in label for label in negative), negative


def test_verdict_keeps_reasons_ratings_and_notes_apart():
    """A NOT FOR MANUFACTURE verdict lists the release gate's reasons under "Why not"; what a
    spring is rated for ("duty met ...") is not a reason and not a caveat: it has a list of
    its own, as on the drawings' release box, and the gate's notes a third one."""
    from springcad.report.html_build import _verdict_html

    build = {"release": {"released": False, "reasons": ["contact at full deflection: r"],
                         "notes": ["contact fatigue, spring S1: n"]}}
    fea = {"springs": {"S1": {"duty": {"rating": "duty met: Miner sum 0.0883",
                                       "where": "FEA flexure flank"}}}}
    text = _verdict_html(build, fea, {"springs": {"S1": {}}})
    why, rated, notes = (text.index(h) for h in ("<p>Why not:</p>", "<p>Rated for (not a reason)",
                                                 "<p>Notes (do not stop the release)"))
    assert why < text.index("contact at full deflection: r") < rated
    assert rated < text.index("duty met: Miner sum 0.0883") < notes
    assert notes < text.index("contact fatigue, spring S1: n")
    assert "Caveats" not in text
