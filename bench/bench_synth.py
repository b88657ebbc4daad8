"""Synthesis speed: designs/s/core, a 10^5-candidate sweep, and the 1 -> 2 Dask worker speed-up.

Run: python bench/bench_synth.py [--repeats 2] [--batch-size 2000]

1. Inner loop: ``evaluate_batch`` (screening + stack assembly) in this process on
   batches of the sweep below: candidates per second on one core (wall and CPU
   time), with a cProfile of one batch; and the full ``design_spring`` of a few
   disks for comparison (what the screening replaces).
2. The sweep: ``springcad explore``'s space with a 30 x 30 target grid, stacks of
   1-6 disks, 4 thicknesses x 5 contact radii = 108 000 candidates, run with
   ``run_sweep`` on a LocalCluster of 1 and of 2 worker processes, alternately,
   ``--repeats`` times each (fresh result folders); wall times, rates and the
   speed-up, with the load average (``os.getloadavg``) before each run, because
   the machine may be shared, and how the workers spent the wall time: running,
   runnable but waiting for a core (``/proc/<pid>/task/*/schedstat``: other
   processes held the cores), or idle (waiting for work: the client or scheduler
   would be the limit). On a loaded machine the wall-time speed-up measures the
   share of the cores the workers were given as much as the code.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import os
import pstats
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from springcad.synthesis.evaluate import evaluate_batch  # noqa: E402
from springcad.synthesis.explore import ExploreGrid  # noqa: E402

GRID = ExploreGrid(stiffness_Nm_per_rad=(5.0, 500.0, 30), deflection_rad=(0.05, 3.0, 30),
                   max_disks=6, thickness_mm=(3.0, 4.0, 5.0, 6.0),
                   contact_radius_mm=(4.5, 5.5, 6.5, 7.5, 9.0))


def load() -> str:
    a, b, c = os.getloadavg()
    return f"load {a:.2f} {b:.2f} {c:.2f}"


def runqueue_wait_s(pid: int) -> float:
    """Time the threads of ``pid`` spent runnable but waiting for a core (Linux schedstat, s)."""
    total = 0
    for stat in Path(f"/proc/{pid}/task").glob("*/schedstat"):
        try:
            total += int(stat.read_text().split()[1])
        except (OSError, IndexError, ValueError):
            pass
    return total * 1e-9


def inner_loop(space, batch_size: int) -> None:
    starts = [int(s) for s in range(0, space.total, space.total // 12)][:12]
    wall = cpu = 0.0
    n = 0
    for s in starts:
        t, c = time.perf_counter(), time.process_time()
        evaluate_batch(space, s, s + batch_size)
        wall += time.perf_counter() - t
        cpu += time.process_time() - c
        n += min(batch_size, space.total - s)
    print(f"inner loop: {n} candidates in {wall:.2f} s wall, {cpu:.2f} s CPU on one core: "
          f"{n / wall:,.0f} designs/s/core (wall), {n / cpu:,.0f} designs/s/core (CPU)  [{load()}]")
    pr = cProfile.Profile()
    pr.enable()
    evaluate_batch(space, starts[len(starts) // 2], starts[len(starts) // 2] + batch_size)
    pr.disable()
    s = io.StringIO()
    pstats.Stats(pr, stream=s).sort_stats("tottime").print_stats(6)
    print("profile of one batch (tottime):")
    print("\n".join(line for line in s.getvalue().splitlines() if line.strip())[-900:])


def full_design_rate() -> None:
    from springcad.config import load_job
    from springcad.design.spring import design_spring

    job = load_job(ROOT / "templates" / "paper_S1.toml")
    base = replace(job.springs["S1"], n_flexures=None, tip_radius_mm=None, contact_radius_mm=6.5)
    t = time.perf_counter()
    k = 0
    for K, th in ((150e3, math.radians(16)), (120e3, math.radians(12)), (200e3, math.radians(10))):
        design_spring(replace(base, stiffness_Nmm_per_rad=K, max_deflection_rad=th), job.material,
                      job.manufacturing, job.hardware)
        k += 1
    dt = time.perf_counter() - t
    print(f"full design_spring (exact profiles): {k} disks in {dt:.2f} s = {k / dt:.2f} designs/s")


def sweep(space, workers: int, batch_size: int) -> float:
    from distributed import Client, LocalCluster

    from springcad.synthesis.runner import run_sweep
    from springcad.synthesis.store import ResultStore

    import psutil

    with tempfile.TemporaryDirectory() as tmp, \
            LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                         dashboard_address=None) as cluster, Client(cluster) as client:
        store = ResultStore(Path(tmp) / "run", "bench", space.total, batch_size)
        pids = list(client.run(os.getpid).values())
        procs = [psutil.Process(pid) for pid in pids]
        cpu0 = sum(sum(p.cpu_times()[:2]) for p in procs)
        wait0 = sum(runqueue_wait_s(pid) for pid in pids)
        before = load()
        stats = run_sweep(space, store, client)
        cpu = sum(sum(p.cpu_times()[:2]) for p in procs) - cpu0
        wait = sum(runqueue_wait_s(pid) for pid in pids) - wait0
    share = cpu / (stats.wall_s * workers)
    idle = max(0.0, 1.0 - (cpu + wait) / (stats.wall_s * workers))
    print(f"  {workers} worker(s): {stats.evaluated_candidates} candidates in {stats.wall_s:.1f} s "
          f"= {stats.candidates_per_s:,.0f}/s; worker CPU {cpu:.1f} s "
          f"({stats.evaluated_candidates / cpu:,.0f}/CPU-s); per worker: running "
          f"{100 * share:.0f} %, runnable but waiting for a core (summed over its threads) "
          f"{100 * wait / (stats.wall_s * workers):.0f} %, "
          f"idle {100 * idle:.0f} %  [before: {before}; after: {load()}]")
    return stats.wall_s


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--batch-size", type=int, default=2000)
    args = p.parse_args()
    space = GRID.space()
    print(f"sweep space: {space.total} candidates (cores: {os.cpu_count()})")
    inner_loop(space, args.batch_size)
    full_design_rate()
    times = {1: [], 2: []}
    for r in range(args.repeats):
        print(f"repeat {r + 1}:")
        for w in (1, 2):
            times[w].append(sweep(space, w, args.batch_size))
    for r, (t1, t2) in enumerate(zip(times[1], times[2]), 1):
        print(f"speed-up 1 -> 2 workers, repeat {r}: {t1 / t2:.2f}x ({t1:.1f} s -> {t2:.1f} s)")
    print(f"best: {min(times[1]) / min(times[2]):.2f}x; 2-worker sweep of {space.total} "
          f"candidates: best {min(times[2]):.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
