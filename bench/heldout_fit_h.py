"""Held-out generator H for `springcad fit` (issue 24): simulate, fit with the CLI, score.

Usage::

    nice -n 10 python bench/heldout_fit_h.py --seed 1 2 --code /work/main --out /tmp/h --jobs 1
    python bench/heldout_fit_h.py --seed 1 --truth-only --out /tmp/h   # records + truth + oracle E
    python bench/heldout_fit_h.py --seed 1 --rescore --out /tmp/h      # score fits already run

Each record is fitted as a user would: ``python -m springcad fit CSV --out DIR --no-plots``
plus the column/unit options its file needs, with ``PYTHONPATH=<--code>``.

Scoring rule (fixed before the first fit ran; bench/heldout_fit_h.md). N = final.effects plus
every effect of every group in final.confounded. A record is right iff all hold:
1. every required name is in N (a required group: any one member);
2. N holds nothing outside required, optional (and the members of required groups);
3. where the case declares a pair physics cannot separate (``not_both``), the two are not both
   in final.effects unless they are in one confounded group;
4. final.unexplained equals the label where the label is True or False (the label is decided
   before the fit, from the case or the oracle's E: >= 2000 True, <= 200 False, else either);
5. where K is scored, |final.params.stiffness_Nm_per_rad - K| <= 2 % of K for one accepted K;
6. final.nrmse_pct <= baseline.nrmse_pct * (1 + 1e-9);
7. the CLI exits 0 and writes fit.json.
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
import heldout_fit_h_oracle as oracle  # noqa: E402
import heldout_fit_h_sim as sim  # noqa: E402
from heldout_fit_h_cases import CASES  # noqa: E402

K_TOL = 0.02
FIT_TIMEOUT_S = 900


def case_rng(seed: int, name: str) -> np.random.Generator:
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def flatten(req) -> set:
    out = set()
    for r in req:
        out |= set(r) if isinstance(r, tuple) else {r}
    return out


def make_record(seed: int, name: str, folder: Path, oracle_all: bool) -> dict:
    """Simulate a case, write its CSV, decide its truth (oracle E where needed)."""
    rng = case_rng(seed, name)
    case = CASES[name](rng)
    rec = sim.simulate(case.bench, rng)
    folder.mkdir(parents=True, exist_ok=True)
    csv = folder / f"{name}.csv"
    sim.write_csv(csv, rec, case.fmt, rng)
    b = case.bench
    k0 = case.k_true[0]
    sigma = float(np.sqrt(b.sigma_T ** 2 + (k0 * b.sigma_th) ** 2))
    ora = None
    if case.unexplained == "oracle" or oracle_all or case.unexplained is True:
        ora = oracle.excess(rec["t"], rec["T_clean"], rec["theta_clean"], sigma, case.starts)
    label = oracle.label(ora["E"]) if case.unexplained == "oracle" else case.unexplained
    return {"name": name, "csv": str(csv), "args": case.fmt.cli_args(),
            "required": [list(r) if isinstance(r, tuple) else r for r in case.required],
            "optional": case.optional, "unexplained": label,
            "unexplained_rule": "oracle" if case.unexplained == "oracle" else "case",
            "oracle": ora, "k_true": case.k_true, "k_scored": case.k_scored,
            "not_both": list(case.not_both) if case.not_both else None, "note": case.note,
            "n_samples": int(rec["t"].size), "fs": b.fs, "sigma_Nm": sigma}


def run_fit(truth: dict, code: str, out: Path) -> dict:
    d = out / truth["name"]
    cmd = [sys.executable, "-m", "springcad", "fit", truth["csv"], "--out", str(d), "--no-plots",
           "--overwrite"] + truth["args"]
    env = dict(os.environ, PYTHONPATH=code, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    t0 = time.time()
    try:
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=FIT_TIMEOUT_S,
                           cwd=str(Path(truth["csv"]).parent))
        rc, err = p.returncode, p.stderr[-2000:]
    except subprocess.TimeoutExpired:
        rc, err = -9, "timeout"
    return {"rc": rc, "wall_s": time.time() - t0, "stderr": err, "dir": str(d)}


def groups(final: dict) -> list:
    out = []
    for g in final.get("confounded") or []:
        if isinstance(g, dict):
            names = g.get("effects") or g.get("names") or []
        else:
            names = list(g)
        out.append(set(names))
    return out


def score(truth: dict, run: dict) -> dict:
    fj = Path(run["dir"]) / "fit.json"
    res = {"name": truth["name"], "ok": False, "why": [], "wall_s": run.get("wall_s")}
    if run["rc"] != 0 or not fj.exists():
        res["why"].append(f"exit {run['rc']}: {run.get('stderr', '')[-200:]}")
        return res
    d = json.loads(fj.read_text())
    fin = d["final"]
    grp = groups(fin)
    named = set(fin.get("effects") or [])
    N = named.union(*grp) if grp else set(named)
    res.update(named=sorted(N), confounded=[sorted(g) for g in grp], unexplained=fin.get("unexplained"),
               K=fin["params"].get("stiffness_Nm_per_rad"), nrmse=fin.get("nrmse_pct"),
               base=d["baseline"]["nrmse_pct"])
    for r in truth["required"]:
        alts = set(r) if isinstance(r, list) else {r}
        if not alts & N:
            res["why"].append(f"missing {'/'.join(sorted(alts))}")
    allowed = flatten(tuple(r) if isinstance(r, list) else r for r in truth["required"]) | set(truth["optional"])
    extra = N - allowed
    if extra:
        res["why"].append(f"extra {','.join(sorted(extra))}")
    if truth["not_both"]:
        a, b = truth["not_both"]
        if a in named and b in named and not any({a, b} <= g for g in grp):
            res["why"].append(f"{a} and {b} both identified (physics cannot separate them)")
    lab = truth["unexplained"]
    if lab is not None and bool(fin.get("unexplained")) != lab:
        res["why"].append(f"unexplained {fin.get('unexplained')} (truth {lab})")
    K = res["K"]
    if truth["k_scored"]:
        err = min(abs(K - k) / k for k in truth["k_true"])
        res["k_err_pct"] = 100 * err
        if err > K_TOL:
            res["why"].append(f"K {K:.4g} vs {truth['k_true'][0]:.4g} ({100 * err:.1f} %)")
    else:
        res["k_err_pct"] = 100 * min(abs(K - k) / k for k in truth["k_true"])
    if res["nrmse"] > res["base"] * (1 + 1e-9):
        res["why"].append(f"final NRMSE {res['nrmse']:.3f} > baseline {res['base']:.3f}")
    res["ok"] = not res["why"]
    return res


def fmt_truth(t: dict) -> str:
    req = ["/".join(r) if isinstance(r, list) else r for r in t["required"]]
    s = "{" + ", ".join(req) + "}"
    if t["optional"]:
        s += " opt " + ",".join(t["optional"])
    return s


def table(seed: int, truths: list, scores: list, code: str) -> str:
    lines = [f"## seed {seed}, code {code}", "",
             "| record | truth (required; optional) | unexpl. truth (E) | named [confounded] | unexpl. | K err % (scored) | NRMSE base -> final | wall s | right | why |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for t, s in zip(truths, scores):
        E = t["oracle"]["E"] if t.get("oracle") else None
        lab = {True: "True", False: "False", None: "either"}[t["unexplained"]]
        if E is not None:
            lab += f" ({E:.3g})"
        named = ",".join(s.get("named", [])) or "-"
        if s.get("confounded"):
            named += " [" + ";".join(",".join(g) for g in s["confounded"]) + "]"
        kerr = f"{s['k_err_pct']:.2f}" + ("" if t["k_scored"] else " (n/s)") if "k_err_pct" in s else "-"
        nr = f"{s['base']:.3f} -> {s['nrmse']:.3f}" if "nrmse" in s else "-"
        lines.append(f"| {t['name']} | {fmt_truth(t)} | {lab} | {named} | {s.get('unexplained')} | {kerr} "
                     f"| {nr} | {s.get('wall_s') or 0:.0f} | {'yes' if s['ok'] else '**no**'} | {'; '.join(s['why'])} |")
    right = sum(s["ok"] for s in scores)
    lines += ["", f"seed {seed}: right {right}/{len(scores)}"]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, nargs="+", default=[1])
    ap.add_argument("--code", default=".")
    ap.add_argument("--out", default="/tmp/heldout_fit_h")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--truth-only", action="store_true")
    ap.add_argument("--rescore", action="store_true", help="score the fits already under --out")
    ap.add_argument("--reuse", action="store_true", help="fit the records and truth already under --out")
    ap.add_argument("--oracle-all", action="store_true", help="oracle E on every record (self-check)")
    ap.add_argument("--table", help="write the markdown table(s) here")
    a = ap.parse_args(argv)
    code = str(Path(a.code).resolve())
    names = a.only or list(CASES)
    out_md = []
    for seed in a.seed:
        root = Path(a.out) / f"seed{seed}"
        tj = root / "truth.json"
        if (a.rescore or a.reuse) and tj.exists():
            truths = {t["name"]: t for t in json.loads(tj.read_text())}
            truths = [truths[n] for n in names]
        else:
            t0 = time.time()
            truths = [make_record(seed, n, root / "records", a.oracle_all) for n in names]
            old = {}
            if tj.exists():
                old = {t["name"]: t for t in json.loads(tj.read_text())}
            old.update({t["name"]: t for t in truths})
            tj.write_text(json.dumps(list(old.values()), indent=1, default=float))
            print(f"seed {seed}: {len(truths)} records simulated, truth written ({time.time() - t0:.0f} s)",
                  flush=True)
        if a.truth_only:
            for t in truths:
                E = t["oracle"]["E"] if t.get("oracle") else None
                print(f"  {t['name']:34s} n={t['n_samples']:6d} {fmt_truth(t):50s} unexpl={t['unexplained']} "
                      f"E={E if E is None else round(E, 1)}")
            continue
        fits = root / "fits"
        if a.rescore:
            walls = {}
            for log in sorted(root.glob("runs*.json")):
                walls.update({Path(r["dir"]).name: r["wall_s"] for r in json.loads(log.read_text())})
            runs = [{"rc": 0, "dir": str(fits / t["name"]), "wall_s": walls.get(t["name"])} for t in truths]
        else:
            def go(t):
                r = run_fit(t, code, fits)
                print(f"  {t['name']}: exit {r['rc']} in {r['wall_s']:.0f} s", flush=True)
                return r
            with ThreadPoolExecutor(a.jobs) as ex:
                runs = list(ex.map(go, truths))
            tag = "" if not a.only else "_" + str(zlib.crc32(" ".join(names).encode()))
            (root / f"runs{tag}.json").write_text(json.dumps(runs, indent=1))
        scores = [score(t, r) for t, r in zip(truths, runs)]
        md = table(seed, truths, scores, code)
        print(md, flush=True)
        out_md.append(md)
    if a.table and out_md:
        Path(a.table).parent.mkdir(parents=True, exist_ok=True)
        Path(a.table).write_text("\n\n".join(out_md) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
