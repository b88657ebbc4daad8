"""Held-out check D for `springcad fit`: records from an independent simulator, scored.

    python bench/heldout_fit_d.py --seed S --out DIR [--only NAME ...] [--code DIR] [--jobs N]

Written from /work/wt/FIT_PHYSICS.md, the README and `springcad fit --help` only (no code,
tests or other held-out benches of the project were read). Laws and cases:
``bench/heldout_fit_d_sim.py`` and ``bench/heldout_fit_d_cases.py`` (27 records whose effects
all have the library's law, 24 with physics outside it). Each case's record is written as a
CSV (SI with the default columns, or degrees / N·mm with other column names, passed with the
CLI's column and unit options), fitted with ``python -m springcad fit`` in a subprocess, and
``fit.json`` is read.

SCORING RULE (fixed before the tool was run on any case; not changed after seeing results)
------------------------------------------------------------------------------------------
Named set N = final.effects ∪ final.terms ∪ every effect of every group in final.confounded
(a confounded pair names both of its members).

A case is RIGHT when all of these hold, else WRONG with the first failing reasons listed:

1. the CLI exits 0 and writes fit.json;
2. every required group of the truth meets N (a group lists names any one of which will do:
   e.g. Coulomb/Dahl friction or a pure delay alone on ramps at ONE speed look alike, so
   {hysteresis, time_lag} is one group there and both are allowed);
3. nothing in N lies outside (required ∪ allowed): an invented library effect is wrong;
4. final.unexplained equals the expected value (when that is not "either");
5. when every effect of the record has the library's law (in_library), the final K
   (final.params.stiffness_Nm_per_rad) is within 2 % of K_true (for asymmetric stiffness
   within 2 % of K+, K- or their mean, since the physics does not say which one K is);
6. the final NRMSE is not above the linear baseline's (final.nrmse_pct <=
   baseline.nrmse_pct * (1 + 1e-6)).

Expected `unexplained`: False for in-library cases (outlier bursts: either). For a case with
physics outside the library, the library's laws as FIT_PHYSICS.md states them (constant +
K*u; dead band on the angle delayed by d and shifted by c; linear drift in t; K- for u<0;
u**3; Dahl friction; viscous c*dtheta/dt with time_lag; each only if the truth requires or allows that name) are fitted by least
squares to the NOISELESS record; r = rms(what they leave) / sigma, sigma the per-sample
noise of the torque residual (torque noise, K x angle noise, quantisation steps / sqrt 12):
  r >= 0.5 -> True (structure clearly above noise); r < 0.03 -> False (the library's laws
  describe the record); otherwise either.
Family rule for out-of-library physics: its `family` (library names of the same family:
stiffening for a hard stop, hysteresis/time_lag for a friction or damper law, drift for a
settling zero, ...) is allowed; the family as a group is REQUIRED when without it the laws
leave r >= 0.5 and with it they leave at most a quarter of that; a single member f is
required alone when without f (the others kept) r >= 0.5 and that is at least 4 times the
residual with f, and this holds for EVERY member of the family (each law is needed, e.g.
Coulomb + viscous friction on several speeds); when one member alone will do (e.g. a friction
that lets go at rest on ramps at one speed, which a lag describes), the group is enough.
The library's laws include a viscous damper c*dtheta/dt in the time_lag family (springcad's
README: a viscous damper is within the time lag's meaning).
K is not scored on out-of-library cases (K of a spring beside a hard stop, a crack or a
relaxation is not one number); it is printed.

Reported: table (case, verdict, named, unexplained got/expected, K error, baseline and
final NRMSE, fit seconds), the misses with reasons, totals, K error on in-library cases.
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from heldout_fit_d_cases import CASES  # noqa: E402
from heldout_fit_d_sim import LIB, projection_residual, simulate  # noqa: E402

R_TRUE, R_FALSE = 0.5, 0.03


def build_truth(c, rec):
    tr = dict(c["truth"])
    tr["required"] = [list(g) for g in tr["required"]]
    sig = rec["sigma_eff"]
    R = {e for g in tr["required"] for e in g}
    A = set(tr["allowed"])
    P = R | A
    t, T, th = rec["t"], rec["T_clean"], rec["th_clean"]
    r_all = projection_residual(t, T, th, P) / sig
    tr["projection_r"] = r_all
    if not tr["in_library"]:
        fam = set(tr["family"])
        if fam:
            r_wo = projection_residual(t, T, th, P - fam) / sig
            tr["projection_r_without_family"] = r_wo
            if r_wo >= R_TRUE and r_all <= 0.25 * r_wo:
                if sorted(fam) not in [sorted(g) for g in tr["required"]]:
                    tr["required"].append(sorted(fam))
            if len(fam) > 1:
                need = []
                for f in sorted(fam):
                    r_f = projection_residual(t, T, th, P - {f}) / sig
                    tr[f"projection_r_without_{f}"] = r_f
                    need.append(r_f >= R_TRUE and r_f >= 4 * r_all)
                if all(need):
                    for f in sorted(fam):
                        if [f] not in tr["required"]:
                            tr["required"].append([f])
        tr["unexplained"] = True if r_all >= R_TRUE else (False if r_all < R_FALSE else None)
    tr["sigma_eff"] = sig
    return tr


def write_csv(path, rec, fmt):
    t, T, th = rec["t"], rec["T"], rec["th"]
    cols, opts = ["time_s", "torque_Nm", "deflection_rad"], []
    if fmt in ("deg_Nmm", "deg"):
        th = np.degrees(th)
    if fmt in ("deg_Nmm", "Nmm"):
        T = T * 1000.0
    if fmt == "deg_Nmm":
        cols = ["t_s", "T_Nmm", "angle_deg"]
        opts = ["--angle-unit", "deg", "--torque-unit", "Nmm"]
    elif fmt == "deg":
        cols = ["time_s", "torque_Nm", "defl_deg"]
        opts = ["--angle-unit", "deg"]
    elif fmt == "Nmm":
        cols = ["time", "torque_Nmm", "deflection_rad"]
        opts = ["--torque-unit", "Nmm"]
    if fmt:
        opts += ["--time-col", cols[0], "--torque-col", cols[1], "--deflection-col", cols[2]]
    np.savetxt(path, np.column_stack([t, T, th]), delimiter=",", header=",".join(cols),
               comments="", fmt=["%.6f", "%.7g", "%.8g"])
    return opts


def named_set(final):
    n = set(final.get("effects") or []) | set(final.get("terms") or [])
    for g in final.get("confounded") or []:
        n |= set(g.get("effects") or [])
    return n


def score(tr, fj, rc):
    if rc != 0 or fj is None:
        return False, [f"exit {rc}" + ("" if fj is not None else ", no fit.json")], {}
    f = fj["final"]
    N = named_set(f)
    why = []
    for g in tr["required"]:
        if not N & set(g):
            why.append("missed " + "|".join(g))
    R = {e for g in tr["required"] for e in g}
    extra = N - R - set(tr["allowed"])
    if extra:
        why.append("invented " + ",".join(sorted(extra)))
    got_u = bool(f.get("unexplained"))
    if tr["unexplained"] is not None and got_u != tr["unexplained"]:
        why.append("unexplained %s, expected %s" % (got_u, tr["unexplained"]))
    K = (f.get("params") or {}).get("stiffness_Nm_per_rad")
    kerr = None
    if K is not None and tr["K_true"]:
        cands = [tr["K_true"]] + list(tr.get("K_alt") or [])
        kerr = min((abs(K - k) / k * 100 for k in cands), key=abs)
        if tr["in_library"] and kerr > 2.0:
            why.append(f"K off {kerr:.2f} %")
    elif tr["in_library"]:
        why.append("no K")
    base = fj["baseline"]["nrmse_pct"]
    fin = f["nrmse_pct"]
    if fin > base * (1 + 1e-6):
        why.append(f"final NRMSE {fin:.3g} > baseline {base:.3g}")
    info = dict(named=sorted(N), unexplained=got_u, K=K, K_err_pct=kerr, base=base, final=fin,
                confounded=[g.get("effects") for g in f.get("confounded") or []],
                laws={k: v.get("law") for k, v in (f.get("laws") or {}).items()})
    return not why, why, info


def run_case(idx, fn, seed, out, code):
    name = fn.__name__
    rng = np.random.default_rng([seed, idx])
    c = fn(rng)
    rec = simulate(c["t"], c["phi"], c["p"], rng)
    tr = build_truth(c, rec)
    d = out / name
    d.mkdir(parents=True, exist_ok=True)
    csv = d / f"{name}.csv"
    opts = write_csv(csv, rec, c.get("fmt"))
    truth = dict(name=name, desc=c["desc"], fmt=c.get("fmt"), n=int(rec["t"].size),
                 fs=float(1 / (rec["t"][1] - rec["t"][0])), **tr,
                 params={k: (v if not isinstance(v, np.ndarray) else None) for k, v in c["p"].items()})
    (d / "truth.json").write_text(json.dumps(truth, indent=1, default=float))
    if code is None:
        return name, truth, None, None, 0.0, opts
    fo = d / "fit"
    env = dict(os.environ, PYTHONPATH=str(code))
    cmd = [sys.executable, "-m", "springcad", "fit", str(csv), "--out", str(fo), "--overwrite",
           "--no-plots"] + opts
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(code), timeout=900)
    dt = time.time() - t0
    (d / "stdout.txt").write_text(p.stdout + "\n--- stderr\n" + p.stderr)
    fj = None
    if (fo / "fit.json").exists():
        fj = json.loads((fo / "fit.json").read_text())
    return name, truth, fj, p.returncode, dt, opts


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", type=Path, default=Path("outputs/heldout_fit_d"))
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--code", type=Path, default=HERE.parent,
                    help="checkout whose springcad is run (PYTHONPATH) [this one]")
    ap.add_argument("--no-fit", action="store_true", help="write records and truth only")
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args(argv)
    out = a.out / f"seed{a.seed}"
    out.mkdir(parents=True, exist_ok=True)
    todo = [(i, fn) for i, fn in enumerate(CASES)
            if not a.only or any(o in fn.__name__ for o in a.only)]
    code = None if a.no_fit else a.code.resolve()
    results = {}
    with cf.ProcessPoolExecutor(max_workers=a.jobs) as ex:
        futs = {ex.submit(run_case, i, fn, a.seed, out, code): fn.__name__ for i, fn in todo}
        for fu in cf.as_completed(futs):
            try:
                name, truth, fj, rc, dt, _ = fu.result()
            except Exception as e:  # noqa: BLE001 - a crashed case is reported
                name = futs[fu]
                print(f"{name}: generator/run error {e!r}", flush=True)
                results[name] = (None, None, None, 0.0, False, [f"error {e!r}"], {})
                continue
            if code is None:
                ok, why, info = None, [], {}
            else:
                ok, why, info = score(truth, fj, rc)
            results[name] = (truth, fj, rc, dt, ok, why, info)
            print(f"  done {name} {'RIGHT' if ok else 'WRONG' if ok is False else ''} {dt:.1f}s",
                  flush=True)
    rows = []
    print()
    hdr = (f"{'case':32s} {'verdict':7s} {'named':42s} {'unexpl':11s} {'proj r':>7s} "
           f"{'K err%':>7s} {'base%':>7s} {'final%':>7s} {'s':>6s}")
    print(hdr)
    for i, fn in todo:
        name = fn.__name__
        truth, fj, rc, dt, ok, why, info = results[name]
        if truth is None:
            print(f"{name:32s} ERROR {why}")
            rows.append(dict(name=name, ok=False, why=why))
            continue
        exp_u = {True: "T", False: "F", None: "?"}[truth["unexplained"]]
        got_u = "-" if not info else ("T" if info["unexplained"] else "F")
        ke = info.get("K_err_pct")
        print(f"{name:32s} {('RIGHT' if ok else 'WRONG') if ok is not None else '-':7s} "
              f"{','.join(info.get('named', [])) or '-':42s} {got_u + ' (exp ' + exp_u + ')':11s} "
              f"{truth['projection_r']:7.2f} "
              f"{(f'{ke:7.2f}' if ke is not None else '      -')} "
              f"{(info.get('base') or float('nan')):7.3f} {(info.get('final') or float('nan')):7.3f} "
              f"{dt:6.1f}")
        rows.append(dict(name=name, ok=ok, why=why, truth_required=truth["required"],
                         allowed=truth["allowed"], expected_unexplained=truth["unexplained"],
                         in_library=truth["in_library"], **info, seconds=dt, rc=rc))
    if code is not None:
        print("\nmisses:")
        for r in rows:
            if not r["ok"]:
                req = " ".join("|".join(g) for g in r.get("truth_required", [])) or "none"
                print(f"  {r['name']}: {'; '.join(r['why'])}  [truth: required {req}; "
                      f"allowed {','.join(r.get('allowed', [])) or '-'}; unexplained "
                      f"{r.get('expected_unexplained')}]")
        nok = sum(1 for r in rows if r["ok"])
        lib = [r for r in rows if r.get("in_library")]
        xl = [r for r in rows if r.get("in_library") is False]
        print(f"\nseed {a.seed}: {nok}/{len(rows)} right "
              f"(in-library {sum(r['ok'] for r in lib)}/{len(lib)}, "
              f"outside the library {sum(r['ok'] for r in xl)}/{len(xl)})")
        ke = [abs(r["K_err_pct"]) for r in lib if r.get("K_err_pct") is not None]
        if ke:
            print(f"K error on in-library cases: median {np.median(ke):.3f} %, max {max(ke):.3f} %, "
                  f"over 2 %: {sum(k > 2 for k in ke)}")
        fr = [(r["final"], r["base"]) for r in rows if r.get("final") is not None]
        if fr:
            print(f"final/baseline NRMSE: median ratio {np.median([f / b for f, b in fr]):.3f}, "
                  f"final above baseline: {sum(f > b * (1 + 1e-6) for f, b in fr)}")
        ts = [r["seconds"] for r in rows if r.get("seconds")]
        if ts:
            print(f"fit time: median {np.median(ts):.1f} s, max {max(ts):.1f} s, total {sum(ts):.0f} s")
    (out / "summary.json").write_text(json.dumps(rows, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
