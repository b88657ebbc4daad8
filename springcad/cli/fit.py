"""``springcad fit DATA.csv [--out DIR]``: fit bench data and close the loop on the residual.

Writes ``DIR/fit.json``, ``DIR/report.md`` (or ``.html``) and PNG plots, and
prints a short summary. The input file is only read.
"""

from __future__ import annotations

from pathlib import Path

import springcad.api as sc
from springcad.cli.common import bounded, default_out, warn
from springcad.options import ANGLE_UNITS, BENCH, TORQUE_UNITS
from springcad.report.outdir import atomic_output_dir, check_output_dir
from springcad.units import fmt_interval


def register(subparsers) -> None:
    """Add the ``fit`` subcommand."""
    p = subparsers.add_parser(
        "fit", help="fit bench torque-deflection data and explain the residual",
        description="Fit the paper's linear, deadband and logit models to a bench record, then "
                    "add physical effects the residual asks for, one at a time, and report the "
                    "error before and after each step.")
    p.add_argument("data", type=Path, help="bench CSV (header: time_s, torque_Nm, deflection_rad)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<data file name>/; must not exist or be empty)")
    p.add_argument("--config", type=Path, help="job config: compare with the designed stack")
    p.add_argument("--target-stiffness", dest="target_stiffness_Nm_per_rad",
                   type=bounded(0, 1e6, " N*m/rad", lo_open=True), metavar="K",
                   help="target stiffness (N·m/rad) for the stiffness error")
    p.add_argument("--time-col", default=BENCH.time_col, help="time column (s) [%(default)s]")
    p.add_argument("--torque-col", default=BENCH.torque_col, help="torque column [%(default)s]")
    p.add_argument("--deflection-col", default=BENCH.deflection_col,
                   help="optical deflection column [%(default)s]")
    p.add_argument("--encoder-cols", nargs="+", metavar="COL",
                   help="encoder angle column(s): INPUT [OUTPUT]; default: encoder_in_rad and "
                        "encoder_out_rad when present")
    p.add_argument("--angle-unit", choices=ANGLE_UNITS, default=BENCH.angle_unit,
                   help="unit of every angle column [%(default)s]")
    p.add_argument("--torque-unit", choices=TORQUE_UNITS, default=BENCH.torque_unit,
                   help="unit of the torque column [%(default)s]")
    p.add_argument("--trust-units", action="store_true",
                   help="fit even when the data contradicts --angle-unit/--torque-unit (a "
                        "stiffness 1000 or 57.3 times off the target, angles below a degree read "
                        "as degrees): a warning instead of the refusal")
    p.add_argument("--format", choices=("md", "html"), default="md", help="report format [md]")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``springcad fit``; returns the exit status."""
    from springcad.report.fit_report import write_fit_outputs  # numpy, scipy: only when fitting

    out = args.out or default_out(args.data)
    inputs = [args.data, args.config]
    check_output_dir(out, args.overwrite, inputs=inputs)  # before the fit
    fit = sc.fit_record(args.data, args.target_stiffness_Nm_per_rad, args.config,
                        time_col=args.time_col, torque_col=args.torque_col,
                        deflection_col=args.deflection_col, encoder_cols=args.encoder_cols,
                        angle_unit=args.angle_unit, torque_unit=args.torque_unit,
                        trust_units=args.trust_units)
    warn("fit", fit.warnings)
    with atomic_output_dir(out, overwrite=args.overwrite, inputs=inputs) as tmp:
        written = write_fit_outputs(fit.raw, tmp, fmt=args.format, plots=not args.no_plots)
    _print_summary(fit.raw, out, [p.name for p in written])
    print(f"  report: {out / 'report.html'} (open it in a web browser)")
    return 0


def _print_summary(result, out: Path, files: list[str]) -> None:
    d = result.to_dict()
    final = d["final"]
    print(f"springcad fit: {result.record.source} ({result.record.n_samples} samples, "
          f"{d['segmentation']['n_cycles']} loading-unloading cycles)")
    print(f"  {'model':<10}{'K (N·m/rad)':>14}{'b (rad)':>11}{'NRMSE (%)':>11}")
    for name, m in d["paper_models"].items():
        print(f"  {name:<10}{m['stiffness_Nm_per_rad']:>14.4g}{m['backlash_rad']:>11.4g}"
              f"{m['nrmse_pct']:>11.3g}")
    if final["no_spring"]:
        sc = d["spring_check"]
        print(f"  no stiffness above noise: K = {sc['stiffness_Nm_per_rad']:.3g} N·m/rad, "
              f"95 % CI {sc['ci_low']:.3g} … {sc['ci_high']:.3g} ({sc['z']:.2g} standard errors)")
    else:
        chain = [f"linear ({d['baseline']['nrmse_pct']:.3g} %)"]
        sign = {"add": "+", "remove": "-", "reject": "x"}
        for s in d["steps"]:
            chain.append(f"{sign[s['action']]}{s['effect']} ({s['nrmse_after_pct']:.3g} %)")
        print("  loop: " + " -> ".join(chain))
        k = final["intervals"]["stiffness_Nm_per_rad"]
        lo, hi = fmt_interval(k["ci_low"], k["ci_high"])
        print(f"  final: {final['model']}, K = {k['value']:.4g} N·m/rad "
              f"[{lo}, {hi}], NRMSE {final['nrmse_pct']:.3g} % "
              f"(noise floor {final['noise_floor_nrmse_pct']:.3g} %)")
        for name, ci in final["intervals"].items():
            if name != "stiffness_Nm_per_rad" and not ci.get("confounded_with"):
                lo, hi = fmt_interval(ci["ci_low"], ci["ci_high"])
                print(f"    {name} = {ci['value']:.4g} [{lo}, {hi}]")
        for r in d["rejected"]:
            print(f"  rejected {r['effect']}: {r['short_reason']}")
        for g in final["confounded"]:
            print(f"  confounded: {g['statement']}")
            if g.get("advice"):
                print(f"    to separate them: {g['advice']['command']}")
    if final["unexplained"]:
        where = final["unexplained_where"]
        only_laws = bool(where and where["findings"]) and all(
            f["kind"] == "law_outside_library" for f in where["findings"])
        print("  unexplained: " + ("physics outside the library"
                                   if only_laws else "structure remains in the residual")
              + (f": {where['summary']}" if where else "") + "; see the report")
    en = d["energy_loss"]
    if en["pct"] is not None:
        print(f"  energy loss (hysteresis model): {en['pct']:.3g} % "
              f"[{en['ci_low_pct']:.3g}, {en['ci_high_pct']:.3g}]")
    else:
        print(f"  energy loss: {en['note']}")
    if d.get("stiffness_error_pct"):
        print(f"  stiffness error vs target {d['target_stiffness_Nm_per_rad']:.4g} N·m/rad: "
              f"{d['stiffness_error_pct']['deadband']:+.3g} % (deadband)")
    comp = d.get("design_comparison")
    if comp:
        print(f"  design: {comp['backlash']['statement']}")
    print(f"  wrote {out}/: {', '.join(files)}")
