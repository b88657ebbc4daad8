"""Held-out generator G for `springcad fit` (issue 24): simulate, fit with the CLI, score.

Usage::

    python bench/heldout_fit_g.py --seed 1 2 --code /work/main --out /tmp/g --jobs 2
    python bench/heldout_fit_g.py --seed 1 --truth-only --out /tmp/g   # records + truth
    python bench/heldout_fit_g.py --seed 1 --rescore --out /tmp/g      # score fits already run

Every record is fitted as a user would: ``python -m springcad fit CSV --out DIR --no-plots``
(with the column and unit options its CSV needs), with ``PYTHONPATH=<--code>`` and the
current folder set to the record's folder, so the checkout under ``--code`` is the one
fitted. The scoring rule (bench/heldout_fit_g.md, fixed before the first fit ran):
a record is right iff (1) every required name is named (or its declared confusable
partner), (2) nothing is named beyond required, optional and their partners, (3)
``final.unexplained`` equals the oracle's label where that is True or False, (4) K is
within 2 % of one accepted value where K is scored, (5) the final NRMSE is not above the
baseline's, and the CLI exits 0 with a fit.json.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
import zlib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import heldout_fit_g_oracle as oracle  # noqa: E402
import heldout_fit_g_sim as sim  # noqa: E402
from heldout_fit_g_cases import LIB_CASES  # noqa: E402
from heldout_fit_g_cases_out import OUT_CASES  # noqa: E402

CASES = {**LIB_CASES, **OUT_CASES}
FIT_TIMEOUT_S = 600


def case_rng(seed: int, name: str) -> np.random.Generator:
    """The generator of one record: the seed and the case's name, nothing else."""
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def make_record(seed: int, name: str, folder: Path) -> dict:
    """Simulate one case, write its CSV and return its truth (with the oracle's E)."""
    rng = case_rng(seed, name)
    case = CASES[name](rng)
    rec = sim.simulate(case.bench, rng)
    csv = folder / f"{name}.csv"
    sim.write_csv(csv, rec, case.angle_unit, case.torque_unit, case.names)
    t = case.truth
    k = t.k_true[0]
    ora = oracle.excess(rec, t.oracle, oracle.noise_variance(rec, case.bench.sensors, k))
    unexplained = oracle.label(ora["E"]) if t.needs_oracle else False
    args = ["--time-col", case.names[0], "--torque-col", case.names[1],
            "--deflection-col", case.names[2], "--angle-unit", case.angle_unit,
            "--torque-unit", case.torque_unit]
    return {"name": name, "csv": str(csv), "cli_args": args, "n_samples": int(rec.time_s.size),
            "rate_hz": case.bench.rate_hz, "required": t.required, "optional": sorted(t.optional),
            "confusable": [sorted(p) for p in t.confusable], "mechanisms": t.mechanisms,
            "k_true": t.k_true, "k_scored": t.in_library or unexplained is False, "unexplained": unexplained,
            "oracle_E": ora["E"], "oracle_leftover_rms_over_noise": ora["leftover_rms_over_noise"],
            "oracle_friction": ora["friction"]}


def run_fit(truth: dict, folder: Path, code: Path) -> dict:
    """Run the CLI on one record; returns exit status, wall time and fit.json (or None)."""
    out = folder / f"{truth['name']}_fit"
    cmd = [sys.executable, "-m", "springcad", "fit", truth["csv"], "--out", str(out), "--no-plots",
           "--overwrite", *truth["cli_args"]]
    env = dict(os.environ, PYTHONPATH=str(code), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=folder, env=env, capture_output=True, text=True, timeout=FIT_TIMEOUT_S)
        status, tail = p.returncode, (p.stdout + p.stderr)[-800:]
    except subprocess.TimeoutExpired:
        status, tail = -1, "timeout"
    wall = time.time() - t0
    fit_json = out / "fit.json"
    return {"status": status, "wall_s": wall, "tail": tail,
            "fit": json.loads(fit_json.read_text()) if status == 0 and fit_json.exists() else None}


def named_set(final: dict) -> set:
    """Names in final.effects and in every confounded group."""
    names = set(final.get("effects") or [])
    for group in final.get("confounded") or []:
        names.update(group.get("effects", []) if isinstance(group, dict) else group)
    return names


def score(truth: dict, fit: dict | None) -> dict:
    """The scoring rule of bench/heldout_fit_g.md on one record."""
    if fit is None:
        return {"right": False, "effects_ok": False, "flag_ok": False, "k_ok": False,
                "nrmse_ok": False, "named": None, "k_err_pct": None, "unexplained": None}
    final = fit["final"]
    named = named_set(final)
    partners = {}
    for a, b in truth["confusable"]:
        partners.setdefault(a, set()).add(b)
        partners.setdefault(b, set()).add(a)
    required, optional = set(truth["required"]), set(truth["optional"])
    have = all(e in named or partners.get(e, set()) & named for e in required)
    allowed = required | optional
    for e in list(allowed):
        allowed |= partners.get(e, set())
    effects_ok = bool(have and named <= allowed)
    flag_ok = truth["unexplained"] is None or bool(final.get("unexplained")) == truth["unexplained"]
    k_fit = final["params"].get("stiffness_Nm_per_rad")
    errs = [100 * (k_fit - k) / k for k in truth["k_true"]] if k_fit is not None else [1e9]
    k_err = min(errs, key=abs)
    k_ok = (not truth["k_scored"]) or abs(k_err) <= 2.0
    nrmse_ok = final["nrmse_pct"] <= fit["baseline"]["nrmse_pct"] * (1 + 1e-9)
    return {"right": bool(effects_ok and flag_ok and k_ok and nrmse_ok), "effects_ok": effects_ok,
            "flag_ok": bool(flag_ok), "k_ok": bool(k_ok), "nrmse_ok": bool(nrmse_ok),
            "named": sorted(named), "k_err_pct": k_err, "unexplained": bool(final.get("unexplained"))}


def table(rows: list) -> str:
    """A markdown table of the scored records, one row per record."""
    lines = ["| record | truth (req; opt) | label | E | named | flag | K err % | right | wall s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for truth, res, sc in rows:
        req = ", ".join(f"{k}" for k in sorted(truth["required"])) or "-"
        opt = ", ".join(truth["optional"])
        kerr = "-" if sc["k_err_pct"] is None else f"{sc['k_err_pct']:+.2f}" + ("" if truth["k_scored"] else " (ns)")
        miss = [k for k in ("effects_ok", "flag_ok", "k_ok", "nrmse_ok") if not sc[k]]
        lines.append(f"| {truth['name']} | {req}{'; ' + opt if opt else ''} | {truth['unexplained']} | "
                     f"{truth['oracle_E']:.3g} | {', '.join(sc['named'] or []) if sc['named'] is not None else 'CRASH ' + str(res['status'])} | "
                     f"{sc['unexplained']} | {kerr} | {'yes' if sc['right'] else 'NO: ' + ' '.join(m[:-3] for m in miss)} | "
                     f"{'-' if res.get('wall_s') is None else format(res['wall_s'], '.0f')} |")
    return "\n".join(lines)


def run_seed(seed: int, args) -> tuple:
    """Simulate, fit (unless --truth-only / --rescore) and score every case of one seed."""
    folder = Path(args.out).resolve() / f"seed{seed}"
    folder.mkdir(parents=True, exist_ok=True)
    names = args.only or sorted(CASES)
    truths = [make_record(seed, n, folder) for n in names]
    (folder / "truth.json").write_text(json.dumps(truths, indent=1, default=str))
    if args.truth_only:
        for t in truths:
            print(f"{t['name']:40s} n={t['n_samples']:6d} label={t['unexplained']!s:5s} E={t['oracle_E']:.3g}")
        return 0, len(truths)
    if args.rescore:
        results = []
        for t in truths:
            fj = folder / f"{t['name']}_fit" / "fit.json"
            results.append({"status": 0 if fj.exists() else 1, "wall_s": None,
                            "fit": json.loads(fj.read_text()) if fj.exists() else None})
    else:
        code = Path(args.code).resolve()
        with ThreadPoolExecutor(args.jobs) as pool:
            results = list(pool.map(lambda t: run_fit(t, folder, code), truths))
    rows = [(t, r, score(t, r["fit"])) for t, r in zip(truths, results)]
    text = table(rows)
    n_right = sum(sc["right"] for _, _, sc in rows)
    summary = (f"seed {seed}: right {n_right}/{len(rows)}; effects {sum(s['effects_ok'] for *_, s in rows)}, "
               f"flag {sum(s['flag_ok'] for *_, s in rows)}, K {sum(s['k_ok'] for *_, s in rows)}, "
               f"NRMSE<=baseline {sum(s['nrmse_ok'] for *_, s in rows)}, "
               f"crashes {sum(r['fit'] is None for _, r, _ in rows)}")
    (folder / "table.md").write_text(text + "\n\n" + summary + "\n")
    (folder / "scores.json").write_text(json.dumps(
        [{"name": t["name"], **sc, "status": r["status"], "wall_s": r["wall_s"],
          "tail": r.get("tail", "")[-300:] if r["fit"] is None else ""} for t, r, sc in rows], indent=1))
    print(text)
    print(summary)
    return n_right, len(rows)


def main(argv=None) -> int:
    """Command line: see the module docstring."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, nargs="+", default=[1])
    ap.add_argument("--code", default=str(Path(__file__).resolve().parents[1]),
                    help="checkout whose springcad package is fitted (PYTHONPATH)")
    ap.add_argument("--out", default="/tmp/heldout_fit_g")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", nargs="+", choices=sorted(CASES))
    ap.add_argument("--truth-only", action="store_true")
    ap.add_argument("--rescore", action="store_true")
    args = ap.parse_args(argv)
    t0 = time.time()
    totals = [run_seed(s, args) for s in args.seed]
    if not args.truth_only:
        print(f"total: {sum(a for a, _ in totals)}/{sum(b for _, b in totals)} right "
              f"({time.time() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
