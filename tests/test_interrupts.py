"""SIGINT and SIGTERM during ``springcad build`` (a real subprocess) lose nothing.

The signal is sent when the build's progress on stderr reaches a given point: the
design step, the FEA verification, the first solid, the exports. Afterwards no
temporary folder is left beside the output, the exit status is 130 (SIGINT) or
143 (SIGTERM), and an output folder that existed before an ``--overwrite`` run is
byte-for-byte unchanged.

Robust under load: the signal follows a progress line (no fixed sleeps), stderr is
read by a thread so a silent child cannot block the test, and every wait has a
generous limit (the child is killed and the test fails with its stderr if reached).
"""

import os
import queue
import signal
import subprocess
import sys
import threading
import time

import pytest

from tests.conftest import ROOT, template

#: progress lines on stderr: build step headers and the stages' own progress messages
POINTS = {"design": "[1/5] design", "fea": "2D level", "solids": "built ",
          "exports": "exporting "}
#: limits for a machine shared with other work (the build itself takes ~30 s unloaded)
MARKER_TIMEOUT_S = 900
EXIT_TIMEOUT_S = 600


def snapshot(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def run_until(argv, marker, sig, cwd):
    """Start springcad, send ``sig`` once ``marker`` appears on stderr; (status, stderr)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-m", "springcad", *argv], cwd=cwd, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            # a background shell may ignore SIGINT; let Python install its handler
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lines: queue.Queue = queue.Queue()
    seen = []

    def read():
        for line in proc.stderr:
            lines.put(line)
        lines.put(None)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    deadline = time.monotonic() + MARKER_TIMEOUT_S
    try:
        while True:
            try:
                line = lines.get(timeout=max(deadline - time.monotonic(), 0.1))
            except queue.Empty:
                pytest.fail(f"no '{marker}' within {MARKER_TIMEOUT_S} s:\n" + "".join(seen))
            if line is None:
                pytest.fail(f"the run ended before '{marker}':\n" + "".join(seen))
            seen.append(line)
            if marker in line:
                proc.send_signal(sig)
                break
        proc.wait(timeout=EXIT_TIMEOUT_S)
        reader.join(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    while not lines.empty():
        line = lines.get()
        if line is not None:
            seen.append(line)
    return proc.returncode, "".join(seen)


def build_argv(out, point, *extra):
    flags = ["--no-render"] + ([] if point == "fea" else ["--no-verify"])
    return ["build", str(template("paper_S1")), "--out", str(out), *flags, *extra]


CASES = [("design", signal.SIGTERM), ("design", signal.SIGINT), ("fea", signal.SIGTERM),
         ("fea", signal.SIGINT), ("solids", signal.SIGTERM), ("exports", signal.SIGINT)]


@pytest.mark.slow
@pytest.mark.parametrize("point,sig", CASES, ids=[f"{p}-{s.name}" for p, s in CASES])
def test_signal_during_build_leaves_no_temporary_folder(tmp_path, point, sig):
    out = tmp_path / "out"
    status, err = run_until(build_argv(out, point), POINTS[point], sig, tmp_path)
    assert status == 128 + sig, err
    assert "Traceback" not in err
    assert "temporary files removed" in err.splitlines()[-1]
    assert list(tmp_path.iterdir()) == [], [p.name for p in tmp_path.iterdir()]


@pytest.mark.slow
@pytest.mark.parametrize("point,sig", [("fea", signal.SIGTERM), ("solids", signal.SIGINT),
                                       ("exports", signal.SIGTERM)],
                         ids=["fea-SIGTERM", "solids-SIGINT", "exports-SIGTERM"])
def test_interrupted_overwrite_keeps_the_old_output(tmp_path, point, sig):
    out = tmp_path / "out"
    out.mkdir()
    (out / "design.json").write_text("{}\n")
    (out / "parts").mkdir()
    (out / "parts" / "old.step").write_bytes(b"ISO-10303-21;\n")
    before = snapshot(out)
    status, err = run_until(build_argv(out, point, "--overwrite"), POINTS[point], sig, tmp_path)
    assert status == 128 + sig, err
    assert snapshot(out) == before
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


@pytest.mark.slow
def test_a_killed_builds_folder_is_removed_by_the_next_run(tmp_path, capsys):
    """SIGKILL cannot be caught: the hidden folder stays, named with the dead run's pid,
    and the next run into the same place removes it and says so."""
    import re

    from springcad.cli import main

    out = tmp_path / "out"
    status, err = run_until(build_argv(out, "exports"), POINTS["exports"], signal.SIGKILL,
                            tmp_path)
    assert status == -signal.SIGKILL, err
    (stale,) = tmp_path.iterdir()
    m = re.match(r"^\.out\.springcad-tmp-(\d+)-", stale.name)
    assert m and stale.is_dir(), stale.name
    with pytest.raises(ProcessLookupError):
        os.kill(int(m.group(1)), 0)
    assert main(["design", str(template("paper_S1")), "--out", str(out)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert f"removed '{stale}'" in capsys.readouterr().err


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_gmsh_leaves_python_signal_handlers_in_place(sig):
    """gmsh.initialize installs C handlers that ended the process on SIGTERM at once (an
    interrupted FEA left its temporary folder); inside and after a gmsh session the
    Python handler still runs."""
    from fea.mesh import _gmsh_session

    got = []
    previous = signal.signal(sig, lambda signum, frame: got.append(signum))
    try:
        with _gmsh_session("signals"):
            os.kill(os.getpid(), sig)
            time.sleep(0.05)  # the handler runs at the next bytecode boundary
        os.kill(os.getpid(), sig)
        time.sleep(0.05)
    finally:
        signal.signal(sig, previous)
    assert got == [sig, sig]
