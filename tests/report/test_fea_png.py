"""The FEA stress PNG: its title gives the one peak that fea.json and the console report."""

from __future__ import annotations

import json
import re

import pytest

import springcad as sc
from springcad.report.fea_png import peak_title
from tests.conftest import template


def test_peak_title_rounds_like_the_console():
    assert peak_title("S1 at 16.0° (2d)", 1050.6, "root fillet") == \
        "S1 at 16.0° (2d): peak von Mises 1051 MPa at the root fillet"


@pytest.mark.slow
def test_png_title_peak_equals_fea_json_and_console(tmp_path):
    """A 2D verification of S1 (three levels), written as the build writes it."""
    from PIL import Image

    from springcad.report.fea_outputs import write_outputs

    v = sc.verify(sc.design_job(template("paper_S1")), model="2d", levels=3, keep_fields=True)
    written = write_outputs(v.raw, tmp_path)
    peak = json.loads((tmp_path / "fea.json").read_text())["springs"]["S1"]["peak_von_mises_MPa"]
    console = v.summary()
    assert re.search(rf"\b{peak:.0f}\b", console)  # the console's sigma column
    mesh_peak = v.raw.springs["S1"].run.study.finest.peak_von_mises_MPa
    for name in ("S1_von_mises.png", "S1_von_mises_peak.png"):
        assert tmp_path / name in written
        title = Image.open(tmp_path / name).text["Title"]
        numbers = re.findall(r"(\d+) MPa", title)
        assert numbers == [f"{peak:.0f}"], title  # one peak value, the reported one
    # the finest mesh's own maximum is a different number (discretisation error), which
    # is why the old title (mesh peak) and the console disagreed
    assert mesh_peak != pytest.approx(peak, abs=1e-9)
    # the von Mises renders drawn by a second process beside the rest: the same files, bytes
    # and order (what springcad verify writes through sc.export_verification)
    beside = tmp_path / "beside"
    beside.mkdir()
    again = write_outputs(v.raw, beside, beside_renders=True)
    assert [p.name for p in again] == [p.name for p in written]
    for p in written:
        assert (beside / p.name).read_bytes() == p.read_bytes(), p.name


@pytest.mark.slow
def test_renders_from_the_cache_start_no_second_process(tmp_path, monkeypatch):
    """A verification whose renders the cache holds writes them here: no fork (and no
    matplotlib import) for files that are copied."""
    from springcad.cache import Cache
    from springcad.report import fea_outputs

    v = sc.verify(sc.design_job(template("paper_S1")), model="2d", levels=3, keep_fields=True,
                  contact=False, cache=False)
    for k, spring in enumerate(v.raw.springs.values()):
        spring.cache_key = f"test-key-{k}"  # as a verification read through the cache
    cache = Cache(tmp_path / "cache")
    (tmp_path / "first").mkdir()
    first = fea_outputs.write_outputs(v.raw, tmp_path / "first", cache=cache, beside_renders=True)

    def no_fork(*a, **k):
        raise AssertionError("a second process for renders the cache holds")

    monkeypatch.setattr(fea_outputs, "beside", no_fork)
    (tmp_path / "again").mkdir()
    again = fea_outputs.write_outputs(v.raw, tmp_path / "again", cache=cache, beside_renders=True)
    assert [p.name for p in again] == [p.name for p in first]
    for p in first:
        assert (tmp_path / "again" / p.name).read_bytes() == p.read_bytes(), p.name
