"""Benchmark: build the paper's 4xS1 stack with every export (``springcad build``).

Usage: ``python bench/bench_build.py [--repeat N] [--keep DIR]``

Writes a 4xS1 job (the S1 template with ``sequence = ["S1"] * 4``) into a
temporary folder, runs the build in-process with ``--accept-violations`` and
prints the wall time of each step and in total. Target: under 60 s on 2 cores.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import shutil
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def job_4xs1(folder: Path) -> Path:
    text = (ROOT / "templates" / "paper_S1.toml").read_text()
    text = text.replace('sequence = ["S1"]', 'sequence = ["S1", "S1", "S1", "S1"]')
    text = text.replace('name = "paper_S1"', 'name = "bench_4xS1"')
    path = folder / "bench_4xS1.toml"
    path.write_text(text)
    return path


def run_once(folder: Path) -> dict:
    from springcad.cli import main

    out = folder / "out"
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = main(["build", str(job_4xs1(folder)), "--out", str(out), "--accept-violations",
                     "--no-verify"])
    wall = time.perf_counter() - t0
    if code != 0:
        raise SystemExit(f"build failed with exit code {code}")
    doc = json.loads((out / "build.json").read_text())
    return {"wall_s": wall, "steps_s": doc["timings_s"], "files": len(doc["files"]),
            "checks": doc["checks"]["n_checks"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--keep", type=Path, default=None, help="keep the output in this folder")
    args = ap.parse_args()
    t_import = time.perf_counter()
    import springcad.cli  # noqa: F401
    print(f"cpus: {os.cpu_count()}  import: {time.perf_counter() - t_import:.2f} s")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for i in range(args.repeat):
            res = run_once(folder)
            steps = "  ".join(f"{k} {v:.1f}" for k, v in res["steps_s"].items())
            print(f"run {i + 1}: 4xS1 build with all exports {res['wall_s']:.1f} s wall "
                  f"({res['files']} files, {res['checks']} checks); steps s: {steps}")
        if args.keep:
            shutil.copytree(folder / "out", args.keep, dirs_exist_ok=True)


if __name__ == "__main__":
    main()
