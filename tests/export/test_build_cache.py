"""A build read from the result cache writes the same files, byte for byte, as one computed
without it (the run's own timings and start time aside).

Each build runs in a process of its own, as a user runs them: OCCT numbers the assembly
STEP's entities from a counter of the process, so two exports in one process differ. Across
processes OCCT writes the assembly STEP's colour styles in an order of its own (measured: the
same entities, the styles in another order), so that file is held to its points between two
fresh builds, and to its bytes between a cached build and the one that stored it. OCCT
also writes a zero coordinate with either sign from one process to the next (in the part
STEP and STL files, before this change too): fresh files are compared with zeros unsigned."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: files that time the run (and say when it started), not its results
RUN_FILES = {"build.json", "report.html"}


def _content(path: Path):
    if path.suffix == ".json":
        def strip(x):
            if isinstance(x, dict):
                return {k: strip(v) for k, v in x.items() if k not in ("timings_s", "started")}
            return [strip(v) for v in x] if isinstance(x, list) else x
        return strip(json.loads(path.read_text()))
    return path.read_bytes()


def _signless_zero(step: bytes) -> bytes:
    """A STEP file with -0. written as 0.: OCCT writes a zero coordinate of some points
    with either sign from one process to the next (measured on cc51105 too)."""
    return re.sub(rb"-0\.(?=[,)])", b"0.", step)


def _points(step: bytes) -> list:
    """Every CARTESIAN_POINT of a STEP file, sorted (zeros without their sign)."""
    return sorted(re.findall(rb"CARTESIAN_POINT\('[^']*',\(([^)]*)\)", _signless_zero(step)))


def _stl_equal(a: bytes, b: bytes) -> bool:
    """Two binary STL files hold the same triangles (-0.0 == 0.0)."""
    import numpy as np

    rec = np.dtype([("f", "<f4", 12), ("attr", "<u2")])
    if a[:80] != b[:80] or len(a) != len(b):
        return False
    return bool(np.array_equal(np.frombuffer(a, rec, offset=84)["f"],
                               np.frombuffer(b, rec, offset=84)["f"]))


def _files(root: Path) -> dict:
    return {str(p.relative_to(root)): _content(p) for p in sorted(root.rglob("*"))
            if p.is_file() and p.name not in RUN_FILES}


def test_cached_build_files_equal_fresh_ones(tmp_path):
    # one hash seed: ezdxf orders the DXF's OBJECTS section by a set's order
    env = {**os.environ, "SPRINGCAD_CACHE_DIR": str(tmp_path / "cache"),
           "SOURCE_DATE_EPOCH": "1700000000", "PYTHONHASHSEED": "0"}
    env.pop("SPRINGCAD_CACHE", None)  # the default: on
    outs, logs = {}, {}
    for run, flags in (("stored", []), ("cached", []), ("fresh", ["--no-cache"])):
        # the cached run lists its imports: it never loads the CAD kernel (export/skeleton.py)
        imports = ["-X", "importtime"] if run == "cached" else []
        res = subprocess.run([sys.executable, *imports, "-m", "springcad", "build",
                              str(ROOT / "templates" / "paper_S1.toml"), "--out",
                              str(tmp_path / run), "--no-verify", "--accept-violations", *flags],
                             env=env, capture_output=True, text=True, cwd=tmp_path)
        assert res.returncode == 0, res.stderr[-3000:]
        outs[run], logs[run] = _files(tmp_path / run), res.stderr
    assert "from the cache" not in logs["stored"] + logs["fresh"]
    loaded = {line.rsplit("|", 1)[1].strip() for line in logs["cached"].splitlines()
              if line.startswith("import time:")}
    assert "springcad.geometry.stack" in loaded  # the skeleton was read
    assert not {"build123d", "OCP", "springcad.geometry.base"} & loaded
    hits = [line for line in logs["cached"].splitlines() if "from the cache" in line]
    assert any("checks" in m for m in hits) and any("assembly STEP" in m for m in hits), hits
    assert sum("files from the cache" in m for m in hits) >= 4, hits
    assert "design" in logs["cached"] and "findfont" not in logs["cached"] + logs["fresh"]
    assert set(outs["cached"]) == set(outs["fresh"]) == set(outs["stored"])
    assert len(outs["fresh"]) > 15
    for name in outs["fresh"]:
        assert outs["cached"][name] == outs["stored"][name], name  # the stored bytes
        fresh, stored = outs["fresh"][name], outs["stored"][name]
        if name == "assembly.step":
            assert _points(fresh) == _points(stored)
        elif name.endswith(".step"):
            assert _signless_zero(fresh) == _signless_zero(stored), name
        elif name.endswith(".stl"):
            assert _stl_equal(fresh, stored), name
        elif name != "vendor.zip":  # it holds the STEP files
            assert fresh == stored, name
    # the read-back checks are in build.json: the cached ones equal the fresh ones
    docs = {run: json.loads((tmp_path / run / "build.json").read_text()) for run in outs}
    assert docs["cached"]["checks"] == docs["fresh"]["checks"]
