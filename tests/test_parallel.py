"""A step run beside the caller in a second process: its result and progress come back in
order, its exceptions are raised in the caller, and it never outlives the caller's block."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from springcad.errors import GeometryError
from springcad.parallel import beside, enabled, single_threaded

pytestmark = pytest.mark.skipif(not enabled(), reason="fork not available or switched off")
ROOT = Path(__file__).resolve().parents[1]


def _work(path, n, progress):
    for k in range(n):
        progress(f"step {k}", k / n)
    Path(path).write_text(f"pid {os.getpid()}")
    return [os.getpid(), n * n]


def _fail(progress):
    progress("about to fail")
    raise GeometryError("the child's own error")


def _sleep(path, progress):
    Path(path).write_text(str(os.getpid()))
    time.sleep(600)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:
        with open(f"/proc/{pid}/stat") as fh:  # a zombie is not running
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:  # reaped meanwhile
        return False


def test_result_and_progress_come_back_in_order(tmp_path):
    said = []
    with beside(_work, tmp_path / "f", 3, progress=lambda m, f=None: said.append((m, f))) as p:
        said.append(("parent", None))
        pid, sq = p.result()
    assert sq == 9 and pid != os.getpid()
    assert (tmp_path / "f").read_text() == f"pid {pid}"
    assert said == [("parent", None), ("step 0", 0.0), ("step 1", 1 / 3), ("step 2", 2 / 3)]


def test_the_childs_exception_is_raised_in_the_caller():
    said = []
    with pytest.raises(GeometryError, match="the child's own error"):
        with beside(_fail, progress=lambda m, f=None: said.append(m)) as p:
            p.result()
    assert said == ["about to fail"]


def test_leaving_the_block_early_stops_the_child(tmp_path):
    flag = tmp_path / "pid"
    with pytest.raises(KeyboardInterrupt):
        with beside(_sleep, flag):
            for _ in range(600):
                if flag.exists() and flag.read_text():
                    break
                time.sleep(0.05)
            raise KeyboardInterrupt
    pid = int(flag.read_text())
    assert not _alive(pid)


def test_a_killed_caller_leaves_no_orphan(tmp_path):
    flag = tmp_path / "pid"
    code = (f"import sys, time; sys.path.insert(0, {str(ROOT / 'tests')!r})\n"
            "from test_parallel import _sleep\nfrom springcad.parallel import beside\n"
            f"with beside(_sleep, {str(flag)!r}):\n    time.sleep(600)\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    parent = subprocess.Popen([sys.executable, "-c", code], env=env)
    try:
        for _ in range(1200):
            if flag.exists() and flag.read_text():
                break
            time.sleep(0.05)
        child = int(flag.read_text())
        assert _alive(child)
        parent.send_signal(signal.SIGKILL)
        parent.wait(60)
        for _ in range(200):
            if not _alive(child):
                break
            time.sleep(0.05)
        assert not _alive(child)
    finally:
        if parent.poll() is None:
            parent.kill()


def test_work_started_ahead_is_used_or_dropped(tmp_path, monkeypatch):
    """``ahead``: a child whose result is asked for gives it (progress replayed then); one
    not asked for is terminated when stopped or when its stack closes, its progress dropped.
    Switched off, the work runs in the caller at ``.result()`` only, never when not asked."""
    import contextlib

    from springcad import parallel

    said = []
    say = lambda m, f=None: said.append(m)  # noqa: E731
    with contextlib.ExitStack() as stack:
        used = parallel.ahead(stack, _work, tmp_path / "used", 2, progress=say)
        flag = tmp_path / "dropped"
        dropped = parallel.ahead(stack, _sleep, flag, progress=say)
        said.append("parent")
        pid, sq = used.result()
        assert sq == 4 and pid != os.getpid()
        for _ in range(600):
            if flag.exists() and flag.read_text():
                break
            time.sleep(0.05)
    assert not _alive(int(flag.read_text())) and dropped._done is False
    assert said == ["parent", "step 0", "step 1"]
    # switched off: deferred to .result(), in this process
    monkeypatch.setenv("SPRINGCAD_PARALLEL", "0")
    said.clear()
    with contextlib.ExitStack() as stack:
        used = parallel.ahead(stack, _work, tmp_path / "serial", 2, progress=say)
        never = parallel.ahead(stack, _work, tmp_path / "never", 2, progress=say)
        said.append("parent")
        assert not (tmp_path / "serial").exists()
        assert used.result()[0] == os.getpid()
        never.stop()
    assert said == ["parent", "step 0", "step 1"] and not (tmp_path / "never").exists()


def test_a_child_stopped_as_it_starts_prints_nothing(tmp_path):
    """The CLI's SIGTERM handler raises; a child stopped right after the fork (Ctrl-C as the
    exports begin) used to run it before setting its own and print a traceback. 30 children
    started and stopped at once: the child keeps the signals blocked until it is ready."""
    code = (f"import signal, sys; sys.path.insert(0, {str(ROOT / 'tests')!r})\n"
            "from test_parallel import _sleep\nfrom springcad.parallel import beside\n"
            "def handler(*a):\n    raise SystemExit('the inherited handler ran')\n"
            "signal.signal(signal.SIGTERM, handler)\n"
            f"for k in range(30):\n    with beside(_sleep, {str(tmp_path / 'f')!r}):\n"
            "        pass\nprint('done')\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0 and res.stdout.strip() == "done", res.stderr
    assert "Traceback" not in res.stderr and "inherited" not in res.stderr, res.stderr


def _pools(progress):
    """(library, threads) of every native thread pool of this process (threadpoolctl)."""
    from threadpoolctl import threadpool_info

    return sorted((p["internal_api"], p["num_threads"]) for p in threadpool_info())


def test_work_run_here_single_threaded_sees_the_pools_a_second_process_sees():
    """The 3D factor may be solved in the caller or in a second process; it gives the same
    numbers only if both run with the same thread pools (a serial and a parallel verify of
    the default differed in 1040 fields of fea.json while the caller limited BLAS alone,
    and in none with every pool limited). :func:`single_threaded` in the caller gives
    every pool the one thread the child has."""
    pytest.importorskip("threadpoolctl")
    if not enabled():
        pytest.skip("no second process on this platform")
    import numpy  # noqa: F401 - loads the BLAS pool

    with single_threaded():
        here = _pools(None)
    with beside(_pools) as child:
        there = child.result()
    assert here == there and here and all(n == 1 for _, n in here)


def test_objects_stay_frozen_while_a_child_shares_them(tmp_path):
    """The caller's objects are left out of its garbage collections (``gc.freeze``) until
    the last child forked beside it has ended: a full collection writes into every object it
    scans, which copied the caller's pages out of what it shared with the child (the
    default build: ~150 MB counted twice). Then they are collected again."""
    import gc

    assert gc.get_freeze_count() == 0
    with beside(_work, tmp_path / "a", 1) as first:
        frozen = gc.get_freeze_count()
        assert frozen > 0
        with beside(_work, tmp_path / "b", 1) as second:
            second.result()
        assert gc.get_freeze_count() >= frozen  # the first child may still share them
        first.result()
        assert first.ready() and gc.get_freeze_count() == 0
    with pytest.raises(GeometryError):  # a child that fails is reaped too
        with beside(_fail) as failing:
            failing.result()
    assert gc.get_freeze_count() == 0
    with beside(_sleep, tmp_path / "c") as slow:  # stopped on leaving the block
        assert not slow.ready() and gc.get_freeze_count() > 0  # a question, not a wait
    assert gc.get_freeze_count() == 0


def _nap(seconds, progress):
    time.sleep(seconds)
    return seconds


def test_modules_named_for_later_are_imported_while_the_caller_waits(monkeypatch):
    """import_while_waiting: the caller imports the named modules while a child it waits
    for still runs (not before, not when nothing waits), and each only once."""
    from springcad import parallel

    name = "tabnanny"  # a standard module nothing in springcad or its libraries imports
    monkeypatch.delitem(sys.modules, name, raising=False)
    monkeypatch.setattr(parallel, "_WAITING_IMPORTS", [])
    parallel.import_while_waiting(name, name)
    assert parallel._WAITING_IMPORTS == [name] and name not in sys.modules
    with beside(_nap, 0.5) as pending:
        assert name not in sys.modules  # nothing is imported until the caller waits
        assert pending.result() == 0.5
    assert name in sys.modules and parallel._WAITING_IMPORTS == []
