"""Synthesis speed: designs/s/core, a 10^5-candidate sweep, and the 1 -> 2 Dask worker speed-up.

Run: python bench/bench_synth.py [--repeats 3] [--batch-size 2000] [--skip-inner]

1. Inner loop: ``evaluate_batch`` (screening + stack assembly) in this process on
   batches of the sweep below: candidates per second on one core (wall and CPU
   time), with a cProfile of one batch; and the full ``design_spring`` of a few
   disks for comparison (what the screening replaces).
2. The sweep: ``springcad explore``'s space with a 30 x 30 target grid, stacks of
   1-6 disks, 4 thicknesses x 5 contact radii = 108 000 candidates, run with
   ``run_sweep`` on a LocalCluster of 1 and of 2 worker processes, alternately,
   ``--repeats`` times each (fresh result folders). Workers: processes, one thread each,
   BLAS/OpenMP pools pinned to one thread (:data:`THREAD_ENV`, checked inside each worker
   with threadpoolctl). A task (2000 candidates) is ~0.2-0.8 CPU-s, hundreds of times
   the scheduler's per-task cost. Reported per run: wall time and rate, CPU time of each
   worker and of the client (which writes the Parquet parts), how the workers spent the
   wall time: running, runnable but waiting for a core (``/proc/<pid>/task/*/schedstat``:
   other processes held the cores), or idle (waiting for work: the client or scheduler
   would be the limit), and the load average before and after. Then the speed-up per
   repeat, min and median: on wall time (what a user sees; on a loaded machine it
   measures the share of the cores the workers got as much as the code), and at
   dedicated cores (2 x CPU rate of 2 workers / CPU rate of 1: the parallel overhead only).
   With the kernel's autogroup scheduling (on here) the cores are shared between login
   sessions first, so while other sessions are busy this session gets about the same CPU
   with one worker as with two: the runs report how many other sessions had a running
   process, and only runs with none measure the code's wall-time speed-up.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import os
import pstats
import statistics
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


def busy_sessions() -> tuple[int, str]:
    """Scheduler autogroups (one per login session) of the other running processes, and ours.

    With ``kernel.sched_autogroup_enabled`` = 1 the kernel shares the cores between
    autogroups first: a session gets about cores / busy sessions, whether it runs one worker
    or two, so on a loaded machine the wall-time speed-up says little about the code.
    """
    try:
        enabled = Path("/proc/sys/kernel/sched_autogroup_enabled").read_text().strip() == "1"
        mine = Path("/proc/self/autogroup").read_text().split()[0]
    except OSError:
        return 0, "autogroup n/a"
    others = set()
    for d in Path("/proc").glob("[0-9]*"):
        try:
            if d.joinpath("stat").read_text().rsplit(")", 1)[1].split()[0] != "R":
                continue
            group = d.joinpath("autogroup").read_text().split()[0]
        except (OSError, IndexError):
            continue
        if group != mine:
            others.add(group)
    return len(others), f"autogroup {'on' if enabled else 'off'}, ours {mine}"


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
    from springcad.design.search import design_spring

    job = load_job(ROOT / "templates" / "paper_S1.toml")
    from springcad.errors import DesignError

    base = replace(job.springs["S1"], n_flexures=None, tip_radius_mm=None)
    t = time.perf_counter()
    k = refused = 0
    for K, th in ((150e3, math.radians(16)), (120e3, math.radians(12)), (200e3, math.radians(10))):
        try:
            design_spring(replace(base, target_stiffness_Nmm_per_rad=K, max_deflection_rad=th),
                          job.material, job.manufacturing, job.hardware)
        except DesignError:  # a refusal costs the same search; it is counted, not hidden
            refused += 1
        k += 1
    dt = time.perf_counter() - t
    print(f"full design_spring (exact profiles): {k} disks ({refused} refused) in {dt:.2f} s "
          f"= {k / dt:.2f} designs/s")


#: BLAS/OpenMP pools pinned to one thread in every worker (Dask's nanny sets the first three
#: before it spawns a worker; set here as well, and checked inside the workers)
THREAD_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "VECLIB_MAXIMUM_THREADS": "1", "NUMEXPR_NUM_THREADS": "1"}


def _worker_threads() -> dict:
    """Inside a worker: the BLAS/OpenMP pool sizes in effect and the thread env."""
    from threadpoolctl import threadpool_info

    return {"pools": sorted({(i["internal_api"], i["num_threads"]) for i in threadpool_info()}),
            "OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS")}


def _cpu_s(proc) -> float:
    t = proc.cpu_times()
    return t.user + t.system


def sweep(space, workers: int, batch_size: int) -> dict:
    """One sweep of ``space`` on a fresh LocalCluster of ``workers`` single-threaded worker
    processes; wall time, CPU time of each worker and of this (client) process, run-queue
    wait, load average before and after."""
    from distributed import Client, LocalCluster

    from springcad.synthesis.runner import run_sweep
    from springcad.synthesis.store import ResultStore

    import psutil

    with tempfile.TemporaryDirectory() as tmp, \
            LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                         dashboard_address=None, env=THREAD_ENV) as cluster, \
            Client(cluster) as client:
        store = ResultStore(Path(tmp) / "run", "bench", space.total, batch_size)
        threads = client.run(_worker_threads)
        pids = list(client.run(os.getpid).values())
        procs = [psutil.Process(pid) for pid in pids]
        me = psutil.Process()
        cpu0 = [_cpu_s(p) for p in procs]
        client0 = _cpu_s(me)
        wait0 = sum(runqueue_wait_s(pid) for pid in pids)
        load_before = os.getloadavg()
        busy_before = busy_sessions()[0]
        stats = run_sweep(space, store, client)
        busy_after = busy_sessions()[0]
        cpu = [_cpu_s(p) - c for p, c in zip(procs, cpu0)]
        client_cpu = _cpu_s(me) - client0
        wait = sum(runqueue_wait_s(pid) for pid in pids) - wait0
        load_after = os.getloadavg()
    wall = stats.wall_s
    share = sum(cpu) / (wall * workers)
    idle = max(0.0, 1.0 - (sum(cpu) + wait) / (wall * workers))
    pools = sorted({str(t["pools"]) for t in threads.values()})
    print(f"  {workers} worker(s): {stats.evaluated_candidates} candidates, "
          f"{stats.evaluated_batches} tasks of {batch_size}, wall {wall:.1f} s "
          f"= {stats.candidates_per_s:,.0f}/s; CPU per worker "
          f"{', '.join(f'{c:.1f}' for c in cpu)} s ({stats.evaluated_candidates / sum(cpu):,.0f} "
          f"candidates/CPU-s, {sum(cpu) / stats.evaluated_batches:.2f} CPU-s per task); "
          f"client CPU {client_cpu:.1f} s; per worker: running {100 * share:.0f} %, "
          f"waiting for a core {100 * wait / (wall * workers):.0f} %, idle {100 * idle:.0f} %; "
          f"load {load_before[0]:.2f} before, {load_after[0]:.2f} after; other sessions "
          f"running {busy_before} before, {busy_after} after; "
          f"worker BLAS/OpenMP pools {'; '.join(pools)}")
    return {"wall_s": wall, "cpu_s": sum(cpu), "share": share, "n": stats.evaluated_candidates,
            "busy": max(busy_before, busy_after),
            "load": 0.5 * (load_before[0] + load_after[0])}


def _median(x):
    return statistics.median(x)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--batch-size", type=int, default=2000)
    p.add_argument("--skip-inner", action="store_true", help="only the 1 -> 2 worker sweeps")
    args = p.parse_args()
    space = GRID.space()
    print(f"sweep space: {space.total} candidates (cores: {os.cpu_count()}; {load()}; "
          f"{busy_sessions()[1]})")
    if not args.skip_inner:
        inner_loop(space, args.batch_size)
        full_design_rate()
    runs = {1: [], 2: []}
    for r in range(args.repeats):
        print(f"repeat {r + 1}:")
        for w in (1, 2):
            runs[w].append(sweep(space, w, args.batch_size))
    for r, (a, b) in enumerate(zip(runs[1], runs[2]), 1):
        # wall: what a user sees; CPU: the same work per CPU-second with dedicated cores
        # (2 x the 2-worker CPU rate / the 1-worker CPU rate; < 2 only from parallel overhead)
        print(f"repeat {r}: speed-up 1 -> 2 workers {a['wall_s'] / b['wall_s']:.2f}x wall "
              f"({a['wall_s']:.1f} s -> {b['wall_s']:.1f} s, mean load {a['load']:.1f} / "
              f"{b['load']:.1f}, other sessions running <= {a['busy']} / {b['busy']}); "
              f"{2 * a['cpu_s'] / b['cpu_s']:.2f}x at dedicated cores "
              f"(worker CPU {a['cpu_s']:.1f} s -> {b['cpu_s']:.1f} s)")
    if not args.repeats:
        return 0
    w1 = [x["wall_s"] for x in runs[1]]
    w2 = [x["wall_s"] for x in runs[2]]
    ratios = [a / b for a, b in zip(w1, w2)]
    print(f"speed-up 1 -> 2 workers (wall): min {min(ratios):.2f}x, median "
          f"{_median(ratios):.2f}x, best-of-each {min(w1) / min(w2):.2f}x")
    print(f"sweep of {space.total} candidates on 2 workers: min {min(w2):.1f} s, median "
          f"{_median(w2):.1f} s (1 worker: min {min(w1):.1f} s, median {_median(w1):.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
