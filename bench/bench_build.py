"""Benchmark: cold and warm builds of the default job and the paper's 4xS1, ``verify`` and ``design``.

Usage: ``python bench/bench_build.py [--only default,4xS1,verify,design] [--keep DIR]``

Each case runs ``python -m springcad ...`` in a fresh process (interpreter start and imports
included, as a user sees it) with every export and verification: cold with an empty result
cache (``SPRINGCAD_CACHE_DIR`` a new temporary folder), then warm (the same command again on
that cache). It prints the wall time, the CPU time of the process tree (user + sys: on a
machine shared with other work the wall time says more about the load than about the
build), each stage's time (``build.json``; for ``verify`` the FEA steps of ``fea.json``), the peak memory of the process tree (psutil: the unique pages of every process alive together plus the largest
process's shared pages, so what a forked child shares with the build counts once; else the
largest process's ``ru_maxrss``), the load average, whether the warm files equal the cold ones byte
for byte (``build.json`` and ``report.html`` carry the run's own timings and start time and
are left out, as is the ``timings_s`` table of ``fea.json``),
and PASS/FAIL against the targets of issue 22 (2-core machine):

    default build   <= 10 s cold, <= 3 s warm     4xS1 build   <= 20 s cold
    verify paper_S1 <= 4 s                        design       <= 0.5 s
    peak memory     <= 1 GB

``SOURCE_DATE_EPOCH`` is fixed so that two builds give the same bytes.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GB = 2 ** 30
#: (case, state) -> target wall time (s)
TARGETS_S = {("default", "cold"): 10.0, ("default", "warm"): 3.0, ("4xS1", "cold"): 20.0,
             ("verify", "cold"): 4.0, ("design", "cold"): 0.5}
PEAK_TARGET_BYTES = 1 * GB
#: files that hold the run's own timings (and start time), not results
RUN_FILES = {"build.json", "report.html"}


def job_4xs1(folder: Path) -> Path:
    text = (ROOT / "templates" / "paper_S1.toml").read_text()
    text = text.replace('sequence = ["S1"]', 'sequence = ["S1", "S1", "S1", "S1"]')
    text = text.replace('name = "paper_S1"', 'name = "bench_4xS1"')
    path = folder / "bench_4xS1.toml"
    path.write_text(text)
    return path


def command(case: str, folder: Path, out: Path) -> list[str]:
    if case == "default":
        return ["build", str(ROOT / "templates" / "default.toml"), "--out", str(out)]
    if case == "4xS1":
        return ["build", str(job_4xs1(folder)), "--out", str(out), "--accept-violations"]
    if case == "verify":
        return ["verify", str(ROOT / "templates" / "paper_S1.toml"), "--out", str(out)]
    if case == "design":
        return ["design", str(ROOT / "templates" / "default.toml"), "--out", str(out)]
    raise SystemExit(f"unknown case {case!r}")


def run(args: list[str], env: dict) -> dict:
    """Run ``python -m springcad ARGS``: wall time, exit code, peak memory of the tree."""
    try:
        import psutil
    except ImportError:
        psutil = None
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "springcad", *args], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak = 0
    if psutil is not None:
        import threading

        def watch():
            nonlocal peak
            try:
                top = psutil.Process(proc.pid)
                while proc.poll() is None:
                    unique, shared = 0, 0
                    for p in [top, *top.children(recursive=True)]:
                        try:  # pages a forked child shares with its parent count once
                            m = p.memory_full_info()
                            unique += m.uss
                            shared = max(shared, m.rss - m.uss)
                        except (psutil.Error, AttributeError):
                            try:
                                unique += p.memory_info().rss
                            except psutil.Error:
                                pass
                    peak = max(peak, unique + shared)
                    time.sleep(0.05)
            except psutil.Error:
                pass

        watcher = threading.Thread(target=watch, daemon=True)
        watcher.start()
    out, err = proc.communicate()
    wall = time.perf_counter() - t0
    if psutil is not None:
        watcher.join(1.0)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    maxrss = after.ru_maxrss * 1024  # KB on Linux
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return {"wall_s": wall, "cpu_s": cpu, "code": proc.returncode,
            "peak_bytes": max(peak, 0) or maxrss, "stdout": out, "stderr": err}


def _content(path: Path):
    """A file's bytes; a JSON document without its ``timings_s`` (the run's own clock)."""
    if path.suffix == ".json":
        def strip(x):
            if isinstance(x, dict):
                return {k: strip(v) for k, v in x.items() if k != "timings_s"}
            return [strip(v) for v in x] if isinstance(x, list) else x
        return strip(json.loads(path.read_text()))
    return path.read_bytes()


def same_files(a: Path, b: Path) -> tuple[bool, list[str]]:
    """Whether two output folders hold the same files with the same bytes (the run files
    aside, and the ``timings_s`` of JSON files, which time the run, not its results)."""
    def files(root):
        return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}
    fa, fb = files(a), files(b)
    diff = sorted((fa ^ fb) | {f for f in fa & fb if Path(f).name not in RUN_FILES
                               and _content(a / f) != _content(b / f)})
    return not diff, diff


def stage_times(out: Path) -> dict:
    """A build's stage times (``build.json``), else a verification's FEA steps per spring
    (``fea.json``: mesh, assemble, solve, post, and the total with the correction loop), s."""
    doc = out / "build.json"
    if doc.is_file():
        return json.loads(doc.read_text()).get("timings_s", {})
    doc = out / "fea.json"
    if not doc.is_file():
        return {}
    steps = {}
    for name, spring in json.loads(doc.read_text()).get("springs", {}).items():
        for step, seconds in (spring.get("timings_s") or {}).items():
            if isinstance(seconds, (int, float)):
                steps[f"{name}.{step}"] = seconds
    return steps


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="default,4xS1,verify,design",
                    help="comma-separated cases (default: all)")
    ap.add_argument("--keep", type=Path, default=None, help="keep the outputs in this folder")
    args = ap.parse_args()
    cases = [c.strip() for c in args.only.split(",") if c.strip()]
    print(f"cpus: {os.cpu_count()}  python: {sys.version.split()[0]}")
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for case in cases:
            cache = tmp / f"cache-{case}"
            env = {**os.environ, "SPRINGCAD_CACHE_DIR": str(cache), "SOURCE_DATE_EPOCH": "1700000000",
                   "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
            env.pop("SPRINGCAD_CACHE", None)
            outs = {}
            for state in ("cold", "warm"):
                out = tmp / f"out-{case}-{state}"
                load = os.getloadavg()[0]
                res = run(command(case, tmp, out), env)
                outs[state] = out
                if res["code"] != 0:
                    print(f"{case} {state}: exit {res['code']}\n{res['stderr'][-3000:]}")
                    results.append((case, state, None, res))
                    break
                steps = stage_times(out)
                line = "  ".join(f"{k} {v:.2f}" for k, v in steps.items())
                target = TARGETS_S.get((case, state))
                verdict = ("" if target is None else
                           ("PASS" if res["wall_s"] <= target else "FAIL") + f" (<= {target:g} s)")
                print(f"{case:8s} {state}: {res['wall_s']:6.2f} s wall  {res['cpu_s']:6.2f} s CPU  peak "
                      f"{res['peak_bytes'] / GB:.2f} GB  load {load:.1f}  {verdict}"
                      + (f"\n          stages s: {line}" if line else ""))
                results.append((case, state, target, res))
            if len(outs) == 2 and all(o.exists() for o in outs.values()):
                ok, diff = same_files(outs["cold"], outs["warm"])
                print(f"{case:8s} warm files equal the cold ones: {ok}"
                      + ("" if ok else f" (differ: {diff[:8]})"))
                results.append((case, "identical", None, {"ok": ok}))
            if args.keep:
                for state, out in outs.items():
                    if out.exists():
                        shutil.copytree(out, args.keep / f"{case}-{state}", dirs_exist_ok=True)
    failed = []
    for case, state, target, res in results:
        if state == "identical":
            if not res["ok"]:
                failed.append(f"{case}: warm files differ")
            continue
        if res["code"] != 0:
            failed.append(f"{case} {state}: exit {res['code']}")
            continue
        if target is not None and res["wall_s"] > target:
            failed.append(f"{case} {state}: {res['wall_s']:.2f} s > {target:g} s")
        if res["peak_bytes"] > PEAK_TARGET_BYTES:
            failed.append(f"{case} {state}: peak {res['peak_bytes'] / GB:.2f} GB > 1 GB")
    print("PASS: every target met" if not failed else "FAIL: " + "; ".join(failed))
    return 0 if not failed else 1


if __name__ == "__main__":
    sys.exit(main())
