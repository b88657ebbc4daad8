"""Held-out generator E for ``springcad fit`` (issue 24), written from FIT_PHYSICS.md alone.

Run::

    python bench/heldout_fit_e.py --seed 1 --out /tmp/e --code /work/main --jobs 2
    python bench/heldout_fit_e.py --seed 1 --only lugre_sines filter_staircase --keep

It simulates ~55 records (``heldout_fit_e_cases`` and ``_cases_out``; simulator in
``heldout_fit_e_sim``): library effects alone, pairs and triples on protocols that separate
them, confounded pairs, and physics outside the library (LuGre/Stribeck, Dahl, regularised
Coulomb, stick-slip friction, a first-order sensor filter, a viscous damper, a Hertzian
take-up, a hard stop, clipping, relaxation, ripple in angle, a stiffness step, a settling
zero, a temperature-dependent K, mains hum); coloured noise, encoder counts, degrees and
N·mm, other column names, 200 Hz to 5 kHz, 10 s to 5 min. Each record's truth is written
to ``truth.json`` BEFORE any fit runs; then each record is fitted with
``python -m springcad fit`` of the checkout ``--code`` (PYTHONPATH=CHECKOUT) and scored.

Scoring rule (fixed before the first fit was run)
-------------------------------------------------
A record is RIGHT when all of these hold:

1. Named set: the set of library effects the fit names (``final.effects`` plus every name in
   ``final.confounded``) equals one of the truth's acceptable sets A, extended by any subset
   of the truth's optional effects. A confounded pair {A, B} that the protocol cannot
   separate is accepted as {A}, {B} or {A, B} (or the pair named confounded).
2. ``unexplained``: equals the truth where the truth is True or False. For physics outside
   the library the truth is decided by the oracle (``heldout_fit_e_oracle``): my own library
   laws fitted to the clean channels, excess chi-square E of what is left: E >= 2000 ->
   True, E <= 200 -> False, in between -> either accepted (genuinely ambiguous, marked so
   before any fit). Records with only library physics (and white/AR(1) noise, encoder
   counts, spikes) must not be flagged.
3. K: where all the physics is in the library (``k_check``), the fitted
   ``stiffness_Nm_per_rad`` is within 2 % of the truth K (for an asymmetric spring: within
   2 % of either side's K, their mean or their harmonic mean).
4. The final NRMSE is not above the linear baseline's.
5. The fit exits 0 and writes fit.json.

Ambiguities declared before scoring: angle offset alone on a linear spring is a torque
offset (either or both accepted); Coulomb friction and a delay on one-rate triangles without
holds (either or both); a regularised Coulomb friction at one linear speed with holds is a
damper, i.e. a lag (either or both); an offset beside any drift is optional (where the
drift's zero is, is a convention); a cubic beside a hard stop or clipping is optional; friction
or a lag beside a relaxing element is optional; a lag beside LuGre friction (it has a
viscous part) is optional. ``series_compliance`` is never simulated: with one angle channel a
linear compliance in series is only a lower K.

Amendment (issue 24 session 7, ``--rule readme``, the default; see heldout_fit_e.md): the
oracle's library laws are those the README puts within a library name, so E is the least
over them: friction's presliding law elasto-plastic or Dahl, the lag a pure delay or a
viscous damper. ``--rule original`` scores as first written; ``--rescore`` scores the fits
already under ``--out``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import heldout_fit_e_cases as cases_in  # noqa: E402
import heldout_fit_e_cases_out as cases_out  # noqa: E402
from heldout_fit_e_oracle import expected_flag, structure  # noqa: E402
from heldout_fit_e_sim import simulate, write_record  # noqa: E402

LIBRARY = ("backlash", "hysteresis", "time_lag", "drift", "torque_offset", "angle_offset", "stiffening",
           "asymmetric_stiffness", "outliers", "series_compliance")

BUILDERS = [
    cases_in.linear_staircase, cases_in.backlash_staircase, cases_in.hysteresis_sines, cases_in.lag_sines,
    cases_in.drift_triangles, cases_in.torque_offset_levels, cases_in.angle_offset_linear,
    cases_in.angle_offset_backlash, cases_in.stiffening_sines, cases_in.asymmetric_staircase,
    cases_in.outliers_torque_sines, cases_in.outliers_angle_levels, cases_in.angle_drift_staircase,
    cases_in.backlash_hysteresis_staircase, cases_in.hysteresis_lag_sines, cases_in.hysteresis_lag_one_rate,
    cases_in.hysteresis_lag_two_rates, cases_in.stiffening_asymmetric_levels, cases_in.drift_backlash_staircase,
    cases_in.lag_stiffening_chirp, cases_in.offset_hysteresis_sines, cases_in.outliers_lag_sines,
    cases_in.backlash_lag_sines, cases_in.backlash_hysteresis_lag_sines,
    cases_in.stiffening_drift_outliers_staircase, cases_in.asymmetric_hysteresis_offset_levels,
    cases_in.backlash_stiffening_angle_offset, cases_in.stack2_backlash_hysteresis,
    cases_in.coloured_noise_hysteresis, cases_in.quantised_backlash_staircase, cases_in.deg_nmm_backlash_lag,
    cases_in.deg_stiffening_levels, cases_in.fast_short_lag_stiffening, cases_in.slow_long_drift_hysteresis,
    cases_in.nmm_asymmetric_hysteresis_triangles,
    cases_out.lugre_sines, cases_out.stribeck_three_rates, cases_out.dahl_two_rates, cases_out.tanh_sines,
    cases_out.tanh_staircase_cos, cases_out.tanh_one_rate_linear, cases_out.filter_staircase,
    cases_out.filter_sines, cases_out.filter_backlash_staircase, cases_out.viscous_sines,
    cases_out.hertz_backlash_staircase, cases_out.hardstop_sines, cases_out.clipping_triangles,
    cases_out.relaxation_staircase, cases_out.stickslip_two_rates, cases_out.ripple_levels,
    cases_out.kstep_triangles, cases_out.thermal_settle_sines, cases_out.temperature_K_staircase,
    cases_out.hum_hysteresis_staircase, cases_out.lugre_lag_deg,
]


def make_truth(seed, out_dir, only=None, rule="original"):
    """Simulate every record, write its CSV and decide its truth (no fit involved).

    ``rule``: the oracle's library laws, ``original`` (as first written) or ``readme`` (the
    README's laws within a library name: Dahl friction, a damper as the lag; see
    ``heldout_fit_e_oracle`` and the amendment in ``heldout_fit_e.md``).
    """
    truths = []
    for i, build in enumerate(BUILDERS):
        rng = np.random.default_rng([seed, i])
        case = build(rng)
        if only and case.name not in only:
            continue
        rec = simulate(case.physics, case.protocol, case.fs_hz, rng)
        dur = rec.t[-1]
        if not (10.0 <= dur <= 300.0):
            raise SystemExit(f"{case.name}: record of {dur:.1f} s outside 10 s - 5 min")
        path = out_dir / f"{case.name}.csv"
        write_record(path, rec, case.cols, case.angle_unit, case.torque_unit)
        ph = case.physics
        entry = {
            "name": case.name, "csv": str(path), "n_samples": int(rec.t.size), "duration_s": float(dur),
            "fs_hz": case.fs_hz, "K": ph.K, "k_truth": [float(k) for k in case.k_truth],
            "k_check": case.k_check, "alternatives": [sorted(a) for a in case.alternatives],
            "optional": sorted(case.optional), "note": case.note,
            "cols": list(case.cols), "angle_unit": case.angle_unit, "torque_unit": case.torque_unit,
            "target_stiffness": float(ph.K * rng.uniform(0.9, 1.1)),
            "physics": {k: v for k, v in vars(ph).items() if v not in (None, 0, 0.0, {})},
        }
        if case.unexplained == "oracle":
            sigma_eff = math.sqrt(ph.sigma_T**2 * (1 + ph.rho_T) / (1 - ph.rho_T) + (ph.K * ph.sigma_th) ** 2)
            effects = set().union(*case.alternatives) | case.optional
            E, rms, params = structure(rec.t, rec.angle_clean, rec.torque_clean, effects, case.hints, sigma_eff,
                                       rule)
            entry.update(unexplained=expected_flag(E), oracle_E=E, oracle_rms_over_noise=rms, oracle_params=params)
        else:
            entry["unexplained"] = bool(case.unexplained)
        truths.append(entry)
        print(f"  simulated {case.name}: {rec.t.size} samples, {dur:.0f} s, unexplained "
              f"{entry['unexplained']}" + (f" (E={entry['oracle_E']:.3g})" if "oracle_E" in entry else ""),
              flush=True)
    return truths


def run_fit(entry, code, fit_dir):
    """Run the checkout's ``springcad fit`` on one record; return (exit code, fit.json or None, s)."""
    out = fit_dir / entry["name"]
    cmd = [sys.executable, "-m", "springcad", "fit", entry["csv"], "--out", str(out), "--no-plots",
           "--overwrite", "--target-stiffness", f"{entry['target_stiffness']:.6g}",
           "--time-col", entry["cols"][0], "--torque-col", entry["cols"][1], "--deflection-col", entry["cols"][2],
           "--angle-unit", entry["angle_unit"], "--torque-unit", entry["torque_unit"]]
    env = dict(os.environ, PYTHONPATH=str(code), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=str(code), env=env, capture_output=True, text=True, timeout=900)
        rc, err = p.returncode, p.stderr[-400:]
    except subprocess.TimeoutExpired:
        rc, err = -9, "timeout 900 s"
    fj = out / "fit.json"
    fit = json.loads(fj.read_text()) if fj.exists() and rc == 0 else None
    return rc, fit, time.time() - t0, err


def _stored_fit(out):
    """(exit code, fit.json, s, err) of a fit already run into ``out`` (for --rescore)."""
    fj = out / "fit.json"
    if not fj.exists():
        return 1, None, float("nan"), "no fit.json"
    return 0, json.loads(fj.read_text()), float("nan"), ""


def _names(obj):
    """Every library effect name inside a nested JSON value."""
    if isinstance(obj, str):
        return {obj} if obj in LIBRARY else set()
    if isinstance(obj, dict):
        return set().union(set(), *(_names(v) for v in obj.values()))
    if isinstance(obj, (list, tuple)):
        return set().union(set(), *(_names(v) for v in obj))
    return set()


def score(entry, rc, fit):
    """(right, found, why) by the rule in the module docstring."""
    if rc != 0 or fit is None:
        return False, [], f"exit {rc}"
    final = fit["final"]
    effects = list(final.get("effects", []))
    other = [e for e in effects if e not in LIBRARY]
    found = set(e for e in effects if e in LIBRARY) | _names(final.get("confounded", []))
    why = []
    optional = set(entry["optional"])
    if other:
        why.append(f"non-library names {other}")
    if not any(set(a) <= found and found - set(a) <= optional for a in entry["alternatives"]):
        why.append("set")
    flag = bool(final.get("unexplained"))
    if entry["unexplained"] is not None and flag != entry["unexplained"]:
        why.append(f"unexplained {flag}")
    K = final.get("params", {}).get("stiffness_Nm_per_rad")
    if entry["k_check"]:
        if K is None or min(abs(K / k - 1) for k in entry["k_truth"]) > 0.02:
            err = None if K is None else min((K / k - 1 for k in entry["k_truth"]), key=abs)
            why.append("K " + ("missing" if err is None else f"{100 * err:+.1f} %"))
    if final.get("nrmse_pct", 0) > fit["baseline"]["nrmse_pct"] * (1 + 1e-9):
        why.append("nrmse > baseline")
    return not why, sorted(found) + (["confounded"] if final.get("confounded") else []), ", ".join(why)


def _truth_text(e):
    alts = " | ".join("{" + ",".join(a) + "}" for a in e["alternatives"])
    if e["optional"]:
        alts += " +opt{" + ",".join(e["optional"]) + "}"
    flag = {True: "U", False: "-", None: "U?"}[e["unexplained"]]
    return f"{alts} {flag}"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, nargs="+", default=[1])
    ap.add_argument("--out", type=Path, default=Path("/tmp/heldout_fit_e"))
    ap.add_argument("--code", type=Path, default=Path(__file__).resolve().parents[1])
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--truth-only", action="store_true", help="simulate and write truth.json, no fit")
    ap.add_argument("--rule", choices=("original", "readme"), default="readme",
                    help="the oracle's library laws: as first written, or the README's (amendment)")
    ap.add_argument("--rescore", action="store_true",
                    help="score the fit.json files already under --out for --code's name (no fit)")
    args = ap.parse_args(argv)
    summary = {}
    for seed in args.seed:
        sdir = args.out / f"seed{seed}"
        (sdir / "records").mkdir(parents=True, exist_ok=True)
        print(f"seed {seed}: simulating into {sdir}", flush=True)
        truths = make_truth(seed, sdir / "records", args.only, args.rule)
        (sdir / f"truth_{args.rule}.json").write_text(json.dumps(truths, indent=1, default=float))
        if args.truth_only:
            continue
        tag = args.code.resolve().name
        fit_dir = sdir / f"fits_{tag}"
        if args.rescore:
            runs = [_stored_fit(fit_dir / e["name"]) for e in truths]
        else:
            with ThreadPoolExecutor(args.jobs) as pool:
                runs = list(pool.map(lambda e: run_fit(e, args.code, fit_dir), truths))
        tag = f"{tag}_{args.rule}"
        rows, n_right = [], 0
        for e, (rc, fit, secs, err) in zip(truths, runs):
            ok, found, why = score(e, rc, fit)
            n_right += ok
            K = fit["final"]["params"].get("stiffness_Nm_per_rad") if fit else None
            kerr = min((K / k - 1 for k in e["k_truth"]), key=abs) * 100 if K else float("nan")
            rows.append({"name": e["name"], "truth": _truth_text(e), "found": found,
                         "unexplained": fit["final"].get("unexplained") if fit else None,
                         "K_err_pct": kerr, "right": ok, "why": why, "secs": secs,
                         "oracle_E": e.get("oracle_E"), "stderr": err if rc else ""})
        (sdir / f"results_{tag}.json").write_text(json.dumps(rows, indent=1, default=str))
        lines = [f"| record | truth | found | K err % | right | why |", "|---|---|---|---|---|---|"]
        for r in rows:
            found = "{" + ",".join(r["found"]) + "}" + (" U" if r["unexplained"] else " -")
            lines.append(f"| {r['name']} | {r['truth']} | {found} | {r['K_err_pct']:+.2f} | "
                         f"{'right' if r['right'] else 'WRONG'} | {r['why']} |")
        lines.append(f"\nseed {seed}, code {args.code}: {n_right}/{len(rows)} right")
        text = "\n".join(lines)
        (sdir / f"table_{tag}.md").write_text(text + "\n")
        print(text, flush=True)
        summary[seed] = (n_right, len(rows))
    for seed, (a, b) in summary.items():
        print(f"seed {seed}: {a}/{b}")


if __name__ == "__main__":
    main()
