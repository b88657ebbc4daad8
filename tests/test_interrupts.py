"""SIGINT and SIGTERM during ``springcad build`` (a real subprocess) lose nothing.

The signal is sent when the build's progress on stderr reaches a given point: the
design step, the first solid, the exports. Afterwards no temporary folder is left
beside the output, the exit status is 130 (SIGINT) or 143 (SIGTERM), and an
output folder that existed before an ``--overwrite`` run is byte-for-byte unchanged.
"""

import os
import signal
import subprocess
import sys
import time

import pytest

from tests.conftest import ROOT, template

POINTS = {"design": "[1/5] design", "solids": "built ", "exports": "[5/5] exports"}


def snapshot(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def run_until(argv, marker, sig, cwd, timeout=300):
    """Start springcad, send ``sig`` once ``marker`` appears on stderr; (status, stderr)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-m", "springcad", *argv], cwd=cwd, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            # a background shell may ignore SIGINT; let Python install its handler
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lines = []
    t0 = time.monotonic()
    try:
        for line in proc.stderr:
            lines.append(line)
            if marker in line:
                proc.send_signal(sig)
                break
            assert time.monotonic() - t0 < timeout, "".join(lines)
        else:
            pytest.fail("the run ended before the marker:\n" + "".join(lines))
        _, rest = proc.communicate(timeout=timeout)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, "".join(lines) + (rest or "")


CASES = [("design", signal.SIGTERM), ("design", signal.SIGINT), ("solids", signal.SIGTERM),
         ("exports", signal.SIGINT)]


@pytest.mark.slow
@pytest.mark.parametrize("point,sig", CASES, ids=[f"{p}-{s.name}" for p, s in CASES])
def test_signal_during_build_leaves_no_temporary_folder(tmp_path, point, sig):
    out = tmp_path / "out"
    status, err = run_until(["build", str(template("paper_S1")), "--out", str(out),
                             "--no-verify", "--no-render"], POINTS[point], sig, tmp_path)
    assert status == 128 + sig, err
    assert "Traceback" not in err
    assert "temporary files removed" in err.splitlines()[-1]
    assert list(tmp_path.iterdir()) == [], [p.name for p in tmp_path.iterdir()]


@pytest.mark.slow
@pytest.mark.parametrize("point,sig", [("solids", signal.SIGINT), ("exports", signal.SIGTERM)],
                         ids=["solids-SIGINT", "exports-SIGTERM"])
def test_interrupted_overwrite_keeps_the_old_output(tmp_path, point, sig):
    out = tmp_path / "out"
    out.mkdir()
    (out / "design.json").write_text("{}\n")
    (out / "parts").mkdir()
    (out / "parts" / "old.step").write_bytes(b"ISO-10303-21;\n")
    before = snapshot(out)
    status, err = run_until(["build", str(template("paper_S1")), "--out", str(out), "--overwrite",
                             "--no-verify", "--no-render"], POINTS[point], sig, tmp_path)
    assert status == 128 + sig, err
    assert snapshot(out) == before
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
