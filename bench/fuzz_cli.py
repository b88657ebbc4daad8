"""Fuzz the command line with mutated job configs, bench CSVs and output paths.

Every case runs ``python -m springcad ...`` in a subprocess (60 s limit) and is
classified: ``ok`` (exit 0/1 without a traceback), ``refused`` (exit 2 with a
one-line error), ``interrupted`` (``--interrupt``: exit 130/143 after the signal),
``traceback`` (a Python traceback on the console, or an exit status outside
{0, 1, 2}), ``killed`` (ended by a signal it did not handle, so no cleanup ran),
``hang`` (over the time limit), ``multiline`` (an
error message longer than one line), ``leftover`` (a temporary or partial
folder left beside the output), ``input_changed`` (an input file modified) and
``nonsense`` (exit 0 with an implausible number in design.json: negative or
missing mass, a mass over 100 kg).

Usage::

    PYTHONPATH=. python bench/fuzz_cli.py --configs 300 --csvs 60 --paths 30 --seed 1
    PYTHONPATH=. python bench/fuzz_cli.py --configs 40 --command "build --no-verify --no-render"
    PYTHONPATH=. python bench/fuzz_cli.py --designable --configs 10 --csvs 0 --paths 0 \
        --command "build --no-render" --interrupt 60      # SIGINT/SIGTERM at random times

The families follow issue 11 (``tests/fuzz_cases.py``): sections of the wrong
type, values of the wrong type, huge/tiny/negative/non-finite numbers, 400-digit
integers, deep nesting, non-UTF-8 bytes, names unusable in exports, unknown keys,
every length at once (1e300, tiny), every key at a bound of its schema range, the
issue's own values, rad vs deg; CSVs with flipped, scaled, broken or non-UTF-8
data (also one Latin-1 byte in a cell, degrees under the rad header, huge cells,
swapped columns); output paths that are files, lie under files or are not
writable, and ``simulate``/``paper`` outputs that exist.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from tests.fuzz_cases import mutate_config, mutate_csv  # noqa: E402

LIMIT_S = 60.0
#: folder to keep the inputs of failing cases in (``--save``)
SAVE_DIR: Path | None = None

def _leftovers(folder: Path, keep: set[str]) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


def run_case(case: dict) -> dict:
    work = Path(tempfile.mkdtemp(prefix="fuzz-"))
    try:
        inp = work / case["input_name"]
        inp.write_bytes(case["data"])
        for name, content in case.get("extra_files", {}).items():
            p = work / name
            p.parent.mkdir(parents=True, exist_ok=True)
            if content is None:
                p.mkdir(exist_ok=True)
            else:
                p.write_bytes(content)
        out = case.get("out", "out")
        argv = [sys.executable, "-m", "springcad", *case["command"].split(), str(inp)]
        if case["command"].split()[0] == "paper":
            argv = argv[:-1]
        argv += ["--out", out if out.startswith("/") else str(work / out), *case.get("flags", [])]
        before = set(p.name for p in work.iterdir())
        env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
        t0 = time.perf_counter()
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                text=True, env=env, cwd=work, errors="replace",
                                # let Python install its SIGINT handler in a background job
                                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        try:
            if case.get("interrupt"):  # (signal, seconds): as a user pressing Ctrl-C or a kill
                sig, delay = case["interrupt"]
                try:
                    proc.communicate(timeout=delay)  # finished before the signal: that's fine
                except subprocess.TimeoutExpired:
                    proc.send_signal(sig)
            _, err = proc.communicate(timeout=LIMIT_S)
            rc = proc.returncode
        except subprocess.TimeoutExpired:  # stop it as a user would: SIGTERM, then wait
            proc.terminate()
            try:
                proc.communicate(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.communicate()
            rc, err = None, "TIMEOUT"
        dt = time.perf_counter() - t0
        verdict = []
        if rc is None:
            verdict.append("hang")
        elif rc < 0:  # ended by a signal it did not handle: no cleanup ran
            verdict.append("killed")
        elif "Traceback" in err or rc not in (0, 1, 2) and not (
                case.get("interrupt") and rc == 128 + case["interrupt"][0]):
            verdict.append("traceback")
        if rc == 2:
            errors = [l for l in err.splitlines() if "error:" in l]
            if len(errors) != 1 or not err.rstrip().splitlines()[-1].startswith(errors[-1][:20]):
                verdict.append("multiline")
        if inp.read_bytes() != case["data"]:
            verdict.append("input_changed")
        stray = [n for n in _leftovers(work, before | {Path(out).name})
                 if n.startswith(".") or "tmp" in n]
        if stray:
            verdict.append("leftover")
        design = work / out / "design.json"
        if rc == 0 and design.exists():
            d = json.loads(design.read_text())
            masses = [s.get("mass_kg") for s in d["springs"].values()] + [d["stack"].get("mass_kg")]
            if any(m is None or m <= 0 or m > 100 for m in masses):
                verdict.append("nonsense")
        if not verdict:
            verdict.append("refused" if rc == 2 else "interrupted" if rc and rc > 128 else "ok")
        elif SAVE_DIR is not None:  # keep the input of every failing case to reproduce it
            SAVE_DIR.mkdir(parents=True, exist_ok=True)
            (SAVE_DIR / f"case{case['id']}-{case['family'].replace(':', '_')}"
                        f"{Path(case['input_name']).suffix}").write_bytes(case["data"])
        return {"id": case["id"], "family": case["family"], "command": case["command"],
                "rc": rc, "seconds": round(dt, 2), "verdict": verdict,
                "stderr_tail": err.strip().splitlines()[-3:] if err.strip() else []}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def designable(data: bytes) -> bool:
    """Does ``springcad design`` accept this config (in-process, quick)?"""
    from springcad.config import job_from_dict
    from springcad.design.job import design_job
    from springcad.errors import SpringcadError

    try:
        design_job(job_from_dict(tomllib.loads(data.decode())))
        return True
    except (SpringcadError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError):
        return False
    except Exception:  # noqa: BLE001 - a crash is worth fuzzing further
        return True


def clean_csv() -> str:
    work = Path(tempfile.mkdtemp(prefix="fuzz-csv-"))
    try:
        out = work / "rec.csv"
        subprocess.run([sys.executable, "-m", "springcad", "simulate",
                        str(ROOT / "templates" / "paper_2xS1.toml"), "--out", str(out), "--seed", "4"],
                       check=True, capture_output=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
        return out.read_text()
    finally:
        shutil.rmtree(work, ignore_errors=True)


def path_cases(rng: random.Random, n: int, config: bytes) -> list[dict]:
    """--out that is a file, lies under a file, is not writable, or exists."""
    cases = []
    for i in range(n):
        kind = rng.choice(["is_file", "under_file", "proc", "exists", "exists_overwrite",
                           "sim_dir_overwrite", "sim_under_file", "paper_exists"])
        c = {"input_name": "job.toml", "data": config, "family": f"path:{kind}",
             "command": rng.choice(["design", "build --no-verify --no-render"])}
        if kind == "is_file":
            c["extra_files"], c["out"] = {"afile": b"x"}, "afile"
        elif kind == "under_file":
            c["extra_files"], c["out"] = {"afile": b"x"}, "afile/sub"
        elif kind == "proc":
            c["out"] = "/proc/springcad-fuzz-out"
        elif kind == "exists":
            c["extra_files"], c["out"] = {"out/keep.txt": b"mine"}, "out"
        elif kind == "exists_overwrite":
            c["extra_files"], c["out"], c["flags"] = {"out/keep.txt": b"mine"}, "out", ["--overwrite"]
            c["command"] = "design"
        elif kind == "sim_dir_overwrite":
            c["extra_files"], c["out"], c["flags"] = {"outdir": None}, "outdir", ["--overwrite"]
            c["command"] = "simulate"
        elif kind == "sim_under_file":
            c["extra_files"], c["out"], c["command"] = {"afile": b"x"}, "afile/rec.csv", "simulate"
        else:
            c["extra_files"], c["out"], c["command"] = {"out/keep.txt": b"mine"}, "out", "paper"
        cases.append(c)
    return cases


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--configs", type=int, default=300)
    ap.add_argument("--csvs", type=int, default=60)
    ap.add_argument("--paths", type=int, default=30)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--command", default="design", help="subcommand (and flags) for the configs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path, help="write every case result here")
    ap.add_argument("--limit-s", type=float, default=LIMIT_S, help="time limit per case (s)")
    ap.add_argument("--designable", action="store_true",
                    help="keep only configs that `design` accepts (to exercise build/verify)")
    ap.add_argument("--save", type=Path, help="keep the input of every failing case here")
    ap.add_argument("--interrupt", type=float, default=0.0, metavar="S",
                    help="send SIGINT or SIGTERM to every config case after a random 0.5..S s "
                         "(exit 130/143 expected, no temporary folder left)")
    args = ap.parse_args(argv)
    globals()["LIMIT_S"] = args.limit_s
    globals()["SAVE_DIR"] = args.save
    rng = random.Random(args.seed)
    cases = []
    tries = 0
    while len(cases) < args.configs and tries < 100 * max(args.configs, 1):
        tries += 1
        fam, data = mutate_config(rng)
        if args.designable and not designable(data):
            continue
        cases.append({"input_name": "job.toml", "data": data, "family": fam,
                      "command": args.command})
        if args.interrupt:
            cases[-1]["interrupt"] = (rng.choice([signal.SIGINT, signal.SIGTERM]),
                                      rng.uniform(0.5, args.interrupt))
    if args.csvs:
        clean = clean_csv()
        for i in range(args.csvs):
            fam, data = mutate_csv(rng, clean)
            cases.append({"input_name": "rec.csv", "data": data, "family": f"csv:{fam}",
                          "command": "fit", "flags": ["--no-plots"]})
    cases += path_cases(rng, args.paths, (ROOT / "templates" / "paper_S1.toml").read_bytes())
    for i, c in enumerate(cases):
        c["id"] = i
    results = []
    t0 = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for r in pool.map(run_case, cases):
            results.append(r)
            if not set(r["verdict"]) <= {"ok", "refused", "interrupted"}:
                print(f"#{r['id']} {r['family']} {r['command']}: {r['verdict']} rc={r['rc']} "
                      f"{r['seconds']} s: {' | '.join(r['stderr_tail'])[-300:]}", flush=True)
    counts = collections.Counter(v for r in results for v in r["verdict"])
    slowest = max(results, key=lambda r: r["seconds"])
    print(f"\n{len(results)} cases in {time.perf_counter() - t0:.0f} s: "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + f"; slowest #{slowest['id']} {slowest['seconds']} s")
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    bad = {"traceback", "hang", "killed", "multiline", "leftover", "input_changed", "nonsense"}
    return 1 if any(set(r["verdict"]) & bad for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
