"""``springcad fit DATA.csv [--out DIR]``: fit bench data and close the loop on the residual.

Writes ``DIR/fit.json``, ``DIR/report.md`` (or ``.html``) and PNG plots, and
prints a short summary. The input file is only read.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springcad.errors import DataError


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be positive")
    return value


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
    p.add_argument("--target-stiffness", type=_positive, metavar="K",
                   help="target stiffness (N·m/rad) for the stiffness error")
    p.add_argument("--time-col", default="time_s", help="time column (s) [time_s]")
    p.add_argument("--torque-col", default="torque_Nm", help="torque column [torque_Nm]")
    p.add_argument("--deflection-col", default="deflection_rad",
                   help="optical deflection column [deflection_rad]")
    p.add_argument("--encoder-cols", nargs="+", metavar="COL",
                   help="encoder angle column(s): INPUT [OUTPUT]; default: encoder_in_rad and "
                        "encoder_out_rad when present")
    p.add_argument("--angle-unit", choices=("rad", "deg"), default="rad",
                   help="unit of every angle column [rad]")
    p.add_argument("--torque-unit", choices=("Nm", "Nmm"), default="Nm",
                   help="unit of the torque column [Nm]")
    p.add_argument("--format", choices=("md", "html"), default="md", help="report format [md]")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``springcad fit``; returns the exit status."""
    from springcad.cli.common import default_out
    from springcad.fit.analysis import fit_record
    from springcad.fit.compare import design_from_config
    from springcad.fit.data import ColumnMap, read_bench_csv
    from springcad.report.fit_report import write_fit_outputs
    from springcad.report.outdir import atomic_output_dir

    if args.encoder_cols is not None and len(args.encoder_cols) > 2:
        raise DataError(f"--encoder-cols takes one or two columns, got {len(args.encoder_cols)}")
    columns = ColumnMap(args.time_col, args.torque_col, args.deflection_col,
                        tuple(args.encoder_cols) if args.encoder_cols else None)
    record = read_bench_csv(args.data, columns, args.angle_unit, args.torque_unit)
    for w in record.warnings:
        print(f"springcad fit: warning: {w}", file=sys.stderr)
    design = design_from_config(args.config) if args.config else None
    result = fit_record(record, args.target_stiffness, design)
    out = args.out or default_out(args.data)
    with atomic_output_dir(out, overwrite=args.overwrite) as tmp:
        written = write_fit_outputs(result, tmp, fmt=args.format, plots=not args.no_plots)
    _print_summary(result, out, [p.name for p in written])
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
        print(f"  final: {final['model']}, K = {k['value']:.4g} N·m/rad "
              f"[{k['ci_low']:.4g}, {k['ci_high']:.4g}], NRMSE {final['nrmse_pct']:.3g} % "
              f"(noise floor {final['noise_floor_nrmse_pct']:.3g} %)")
        for name, ci in final["intervals"].items():
            if name != "stiffness_Nm_per_rad" and not ci.get("confounded_with"):
                print(f"    {name} = {ci['value']:.4g} [{ci['ci_low']:.4g}, {ci['ci_high']:.4g}]")
        for r in d["rejected"]:
            print(f"  rejected {r['effect']}: {r['short_reason']}")
        for g in final["confounded"]:
            print(f"  confounded: {g['statement']}")
            if g.get("advice"):
                print(f"    to separate them: {g['advice']['command']}")
    if final["unexplained"]:
        where = final["unexplained_where"]
        print("  unexplained: structure remains in the residual"
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
