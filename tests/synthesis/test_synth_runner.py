"""Dask execution: a sweep on a LocalCluster started here, and a killed run resumed."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from springcad.synthesis.candidates import CandidateSpace
from springcad.synthesis.evaluate import evaluate_batch
from springcad.synthesis.requirements import requirements_from_dict
from springcad.progress import Count
from springcad.synthesis.runner import run_sweep
from springcad.synthesis.store import ResultStore
from synth_fixtures import ROOT, small


def _same(a: dict, b: dict):
    assert set(a) == set(b)
    order = np.argsort(a["cid"])
    for k in a:
        x, y = a[k][order], b[k]
        if x.dtype == object:
            assert list(x) == list(y), k
        else:
            np.testing.assert_array_equal(x, y, err_msg=k)


def test_sweep_on_a_local_cluster_equals_in_process(tmp_path):
    from distributed import Client, LocalCluster

    req = requirements_from_dict(small())
    space = CandidateSpace.from_requirements(req)
    store = ResultStore(tmp_path / "run", req.fingerprint(), space.total, batch_size=97)
    seen = []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        stats = run_sweep(space, store, client,
                          lambda m, f=None: seen.append(Count.parse(m).done))
    assert stats.workers == 2
    assert stats.evaluated_batches == store.n_batches == -(-space.total // 97)
    assert stats.evaluated_candidates == space.total
    assert seen[-1] == space.total and seen == sorted(seen)
    _same(store.read(), evaluate_batch(space, 0, space.total))
    # a second run finds everything done and evaluates nothing
    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        again = run_sweep(space, store, client)
    assert again.evaluated_candidates == 0 and again.skipped_batches == store.n_batches


def test_store_refuses_another_space(tmp_path):
    from springcad.errors import OutputExistsError

    ResultStore(tmp_path, "aaaa", 10, 5)
    with pytest.raises(OutputExistsError, match="another candidate space"):
        ResultStore(tmp_path, "bbbb", 10, 5)
    ResultStore(tmp_path, "bbbb", 10, 5, overwrite=True)


def test_killed_run_resumes_without_redoing_batches(tmp_path):
    """SIGKILL the whole `springcad explore` process group midway, then resume."""
    from distributed import Client, LocalCluster

    from springcad.synthesis.explore import ExploreGrid

    out = tmp_path / "map"
    grid = ["--stiffness-Nm-per-rad", "10:300:12", "--deflection-rad", "0.1:2:12",
            "--max-disks", "4", "--thickness-mm", "3", "4.5", "--contact-radius-mm", "5.5", "7.5"]
    cmd = [sys.executable, "-m", "springcad", "explore", "--out", str(out), "--workers", "1",
           "--batch-size", "8", *grid]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(cmd, cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    parts = out / "parts"
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len(list(parts.glob("part-*.parquet"))) < 4:
            assert proc.poll() is None, "the run ended before it could be killed"
            time.sleep(0.01)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the CLI, its scheduler and its worker
        proc.wait(timeout=30)
    before = {p.name: p.stat().st_mtime_ns for p in parts.glob("part-*.parquet")}
    space = ExploreGrid(stiffness_Nm_per_rad=(10.0, 300.0, 12), deflection_rad=(0.1, 2.0, 12),
                        max_disks=4, thickness_mm=(3.0, 4.5),
                        contact_radius_mm=(5.5, 7.5)).space()
    manifest = json.loads((out / "manifest.json").read_text())
    store = ResultStore(out, manifest["fingerprint"], space.total, 8)
    n_batches = store.n_batches
    assert 4 <= len(before) < n_batches, "killed midway"
    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        stats = run_sweep(space, store, client)
    assert stats.skipped_batches == len(before)
    assert stats.evaluated_batches == n_batches - len(before)
    assert stats.evaluated_candidates == space.total - sum(
        min(8, space.total - 8 * int(n[5:11])) for n in before)
    after = {p.name: p.stat().st_mtime_ns for p in parts.glob("part-*.parquet")}
    assert {n: after[n] for n in before} == before  # finished parts untouched
    cols = store.read()
    assert np.array_equal(np.sort(cols["cid"]), np.arange(space.total))  # each candidate once
    _same(cols, evaluate_batch(space, 0, space.total))


def test_cli_runs_on_an_existing_scheduler(tmp_path, capsys):
    """`--scheduler ADDRESS`: the same command on a cluster it did not start."""
    from distributed import LocalCluster

    from springcad.cli import main

    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster:
        code = main(["explore", "--out", str(tmp_path / "map"), "--scheduler",
                     cluster.scheduler_address, "--stiffness-Nm-per-rad", "20:200:3",
                     "--deflection-rad", "0.2:1:3", "--max-disks", "2", "--thickness-mm", "4.5",
                     "--contact-radius-mm", "7"])
        assert code == 0
    summary = json.loads((tmp_path / "map" / "explore.json").read_text())
    assert summary["sweep"]["workers"] == 1 and summary["n_candidates"] == 3 * 3 * 2


def test_unreachable_scheduler_is_one_line(tmp_path, capsys):
    from springcad.cli import main

    code = main(["explore", "--out", str(tmp_path / "map"), "--scheduler", "tcp://127.0.0.1:9",
                 "--stiffness-Nm-per-rad", "20:200:2", "--deflection-rad", "0.2:1:2"])
    assert code == 2
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in capsys.readouterr().err


def test_progress_bar_line():
    from springcad.cli.progress import ProgressBar

    line = ProgressBar(width=10).line(done=600, total=1000, elapsed_s=2.0, done_before=200)
    # 400 candidates in 2 s this run: 200/s, 400 left: 2 s
    assert "600/1000 candidates (200 from an earlier run)" in line
    assert "200/s" in line and "left 00:02" in line and "[######....]" in line


def test_progress_bar_is_the_one_progress_protocol():
    """The sweep reports through ``progress(message, fraction)`` like every other step: a
    Count message draws the bar (read back to its numbers), any other message is a line."""
    import io

    from springcad.cli.progress import ProgressBar

    stream = io.StringIO()
    bar = ProgressBar(width=10, stream=stream, every_s=0.0)
    bar("12 candidate stacks in 2 batches (2 to evaluate)")
    for done in (200, 600, 1000):
        count = Count(done, 1000, "candidates", 200)
        bar(count.message(), count.fraction)
    lines = stream.getvalue().splitlines()
    assert lines[0] == "12 candidate stacks in 2 batches (2 to evaluate)"
    assert "[##........] 200/1000 candidates (200 from an earlier run)" in lines[1]
    assert "[######....] 600/1000 candidates" in lines[2]
    assert "[##########] 1000/1000 candidates" in lines[3] and len(lines) == 4
    assert Count.parse("600/1000 candidates") == Count(600, 1000, "candidates", 0)
    assert Count.parse("FEA of S1: rigid-cam load") is None
