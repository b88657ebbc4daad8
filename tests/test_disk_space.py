"""A full disk and the leftovers of a killed run (springcad.report.outdir).

A full disk is simulated in-process: ``shutil.disk_usage`` reporting little free space
(the .vtu writer must refuse before VTK writes, VTK itself crashes the process on a full
disk), and writes raising ENOSPC. The real SIGKILL case is in ``test_interrupts.py``.
"""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
from collections import namedtuple

import numpy as np
import pytest

from springcad.cli import main
from springcad.errors import EXIT_BAD_INPUT, NoSpaceError
from springcad.report import outdir
from tests.conftest import template

Usage = namedtuple("Usage", "total used free")


def _dead_pid() -> int:
    """The id of a process that has exited (and been reaped)."""
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    return int(proc.stdout)


def _grid(n=40):
    """A small quadratic-triangle grid with the fields of an FEA result."""
    import pyvista as pv

    rng = np.random.default_rng(3)
    pts = rng.uniform(0, 10, size=(6 * n, 3))
    cells = np.arange(6 * n).reshape(n, 6)
    conn = np.hstack([np.full((n, 1), 6), cells]).ravel()
    grid = pv.UnstructuredGrid(conn, np.full(n, 22, dtype=np.uint8), pts)
    grid.point_data["displacement_mm"] = rng.normal(size=(6 * n, 3))
    grid.point_data["von_mises_MPa"] = rng.uniform(0, 900, 6 * n)
    grid.point_data["excluded_from_peak"] = np.zeros(6 * n, np.uint8)
    return grid


@pytest.mark.parametrize("n", [40, 4000])
def test_vtu_size_estimate_is_an_upper_bound(tmp_path, n):
    from springcad.report.fea_vtu import vtu_bytes_estimate

    grid = _grid(n)
    path = tmp_path / "g.vtu"
    grid.save(str(path))
    size = path.stat().st_size
    assert size <= vtu_bytes_estimate(grid) < 3 * size + 128 * 1024


def test_vtu_write_refuses_a_nearly_full_disk(tmp_path, monkeypatch):
    from springcad.report import fea_vtu

    grid = _grid(4000)
    monkeypatch.setattr(fea_vtu, "result_grid", lambda result: grid)
    need = fea_vtu.vtu_bytes_estimate(grid) + outdir.SPACE_RESERVE_BYTES
    monkeypatch.setattr(outdir.shutil, "disk_usage",
                        lambda p: Usage(10 ** 9, 10 ** 9 - need // 2, need // 2))
    with pytest.raises(NoSpaceError) as info:
        fea_vtu.write_vtu(None, tmp_path / "S1_sector_2d.vtu")
    msg = str(info.value)
    assert "S1_sector_2d.vtu" in msg and f"{need / 2 ** 20:.1f} MB" in msg
    assert f"{need // 2 / 2 ** 20:.1f} MB free" in msg
    assert list(tmp_path.iterdir()) == []
    # with the space there it writes
    monkeypatch.setattr(outdir.shutil, "disk_usage", lambda p: Usage(10 ** 9, 0, 2 * need))
    assert fea_vtu.write_vtu(None, tmp_path / "ok.vtu").stat().st_size > 0


def test_enospc_while_writing_is_exit_2_naming_the_space(tmp_path, capsys, monkeypatch):
    """The disk fills while `springcad design` writes: one message, exit 2, nothing left."""
    import springcad.cli.design as design_cli

    def full(path, data):
        path.write_text("x" * 1000)  # part of it was written before the disk filled
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(design_cli, "write_json", full)
    out = tmp_path / "deep" / "out"
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error: the disk holding" in err[0]
    assert "is full" in err[0] and "MB is free" in err[0] and "free more than 8.0 MB" in err[0]
    assert "Traceback" not in err[0]
    assert list(tmp_path.iterdir()) == []  # the partial output and the parents it made


def test_other_write_errors_are_not_called_a_full_disk(tmp_path, monkeypatch, capsys):
    import springcad.cli.design as design_cli

    def denied(path, data):
        raise OSError(errno.EIO, os.strerror(errno.EIO), str(path))

    monkeypatch.setattr(design_cli, "write_json", denied)
    status = main(["design", str(template("paper_S1")), "--out", str(tmp_path / "out")])
    assert status != 0 and "is full" not in capsys.readouterr().err


def test_stale_entries_of_dead_runs_are_removed_live_and_unknown_ones_kept(tmp_path, capsys):
    out = tmp_path / "out"
    dead = _dead_pid()
    stale_dir = tmp_path / f".out.{outdir.TMP_TAG}{dead}-abc123"
    (stale_dir / "parts").mkdir(parents=True)
    (stale_dir / "parts" / "x.step").write_bytes(b"x" * 100)
    stale_file = tmp_path / f".out.{outdir.TMP_TAG}{dead}-k9"
    stale_file.write_text("partial")
    live = tmp_path / f".out.{outdir.TMP_TAG}{os.getppid()}-live1"  # a running process
    live.mkdir()
    legacy = tmp_path / f".out.{outdir.TMP_TAG}q8w7e6r5"  # no pid: older springcad
    legacy.mkdir()
    other = tmp_path / f".other.{outdir.TMP_TAG}{dead}-zz"  # another output's
    other.mkdir()
    held_old = tmp_path / f".out.{outdir.OLD_TAG}{dead}-h1"  # the old output, not in place
    (held_old / "out").mkdir(parents=True)
    removed, kept = outdir.clean_stale(out)
    assert sorted(removed) == sorted([stale_dir, stale_file])
    assert live.exists() and legacy.exists() and other.exists() and held_old.exists()
    assert len(kept) == 2 and any(str(legacy) in k for k in kept)
    assert any(str(held_old) in k and "move it back" in k for k in kept)
    err = capsys.readouterr().err
    assert f"removed '{stale_dir}'" in err and "no longer running" in err


def test_a_run_names_its_temporary_folder_with_its_pid(tmp_path):
    seen = []
    with outdir.atomic_output_dir(tmp_path / "out") as tmp:
        seen.append(tmp.name)
    assert seen[0].startswith(f".out.{outdir.TMP_TAG}{os.getpid()}-")
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_the_next_run_into_the_same_place_removes_a_dead_runs_folder(tmp_path, capsys):
    out = tmp_path / "out"
    stale = tmp_path / f".out.{outdir.TMP_TAG}{_dead_pid()}-x1y2"
    stale.mkdir()
    (stale / "design.json").write_text("{")
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert f"removed '{stale}'" in capsys.readouterr().err


def test_require_free_space_passes_with_room(tmp_path):
    outdir.require_free_space(tmp_path, 1024, "a file")
    free = shutil.disk_usage(tmp_path).free
    with pytest.raises(NoSpaceError, match="free at least"):
        outdir.require_free_space(tmp_path, free, "a file")
