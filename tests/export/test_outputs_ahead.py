"""The FEA outputs written ahead: ``sc.build`` of a verification starts a second process that
writes ``fea.json``, the .vtu fields and the PNG renders while the solids are made and checked;
``sc.export_build`` moves its files into the build folder. They are the files an export writes
itself (byte for byte); an export that does not want them (``render=False``) or comes second
writes its own, and none leaves its staging folder or its process behind."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

import springcad.api as sc
from springcad.api.pipeline import _OutputsAhead
from springcad.parallel import enabled

pytestmark = [pytest.mark.skipif(not enabled(), reason="fork not available or switched off"),
              pytest.mark.slow]
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def verification():
    # a 2D verification with its fields: seconds, and every FEA output but the 3D field
    return sc.verify(ROOT / "templates" / "paper_S1.toml", model="2d", levels=3, contact=False,
                     keep_fields=True, cache=False)


def _fea(out: Path) -> dict:
    return {str(p.relative_to(out / "fea")): p.read_bytes() for p in sorted((out / "fea").rglob("*"))}


def test_outputs_written_ahead_equal_those_written_in_the_export(verification, tmp_path):
    from springcad.report.fea_outputs import write_outputs

    said = []
    built = sc.build(verification, accept_violations=True, cache=False,
                     progress=lambda m, f=None: said.append(m))
    ahead = built._outputs_ahead
    assert ahead is not None and ahead.folder.is_dir()
    assert any("FEA outputs" in m and "second process" in m for m in said)
    first = sc.export_build(built, tmp_path / "ahead", cache=False)
    assert not ahead.folder.exists()  # taken: moved into the build folder
    # what an export writes itself (export_build without outputs ahead: these calls, here)
    (tmp_path / "own" / "fea").mkdir(parents=True)
    own_order = [Path(p).name for p in write_outputs(verification.raw, tmp_path / "own" / "fea",
                                                     render=True)]
    ahead_files, own_files = _fea(first.out_dir), _fea(tmp_path / "own")
    assert {"fea.json", "S1_von_mises.png", "S1_sector_2d.vtu"} <= set(ahead_files)
    assert ahead_files == own_files
    listed = [f["path"] for f in json.loads((first.out_dir / "build.json").read_text())["files"]]
    # in the order write_outputs returns them
    assert [p for p in listed if p.startswith("fea/")] == [f"fea/{n}" for n in own_order]
    # the same build again, without renders: the outputs were taken, it writes fea.json itself
    plain = sc.export_build(built, tmp_path / "plain", render=False, cache=False)
    assert _fea(plain.out_dir) == {"fea.json": ahead_files["fea.json"]}


def test_outputs_not_taken_are_stopped_and_removed(verification, monkeypatch):
    ahead = _OutputsAhead.start(verification, None, None)
    assert ahead is not None and ahead.folder.is_dir()
    proc = ahead.pending._proc
    ahead.close()
    assert not ahead.folder.exists() and not proc.is_alive()
    assert not ahead.usable(True, None)  # closed: an export writes its own
    # a build that is never exported: its outputs go with it (the solids and checks are
    # stood in for: only the outputs' lifetime is tested here)
    import springcad.geometry.checks as checks

    monkeypatch.setattr(checks, "build_and_check", lambda *a, **k: (None, None, {}))
    built = sc.build(verification, accept_violations=True, cache=False)
    folder, proc = built._outputs_ahead.folder, built._outputs_ahead.pending._proc
    del built
    import gc

    gc.collect()
    for _ in range(100):
        if not folder.exists() and not proc.is_alive():
            break
        time.sleep(0.05)
    assert not folder.exists() and not proc.is_alive()
