"""``springcad fit DATA.csv [--out DIR]``: fit bench data and close the loop on the residual.

Writes ``DIR/fit.json``, ``DIR/report.md`` (or ``.html``) and PNG plots, and
prints a short summary. The input file is only read.
"""

from __future__ import annotations

from pathlib import Path

from springcad.cli.common import bounded
from springcad.errors import DataError
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
    p.add_argument("--target-stiffness", type=bounded(0, 1e6, " N*m/rad", lo_open=True), metavar="K",
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
    p.add_argument("--trust-units", action="store_true",
                   help="fit even when the data contradicts --angle-unit/--torque-unit (a "
                        "stiffness 1000 or 57.3 times off the target, angles below a degree read "
                        "as degrees): a warning instead of the refusal")
    p.add_argument("--format", choices=("md", "html"), default="md", help="report format [md]")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.set_defaults(func=run)


#: a bench record is a few MB (20 000 samples at 500 Hz); refuse absurd files before reading
MAX_CSV_BYTES = 200_000_000
#: physical bounds of a torsion-spring bench record (N*m, rad): outside them the units or the
#: file are wrong, and the fit's numerics would be meaningless
TORQUE_RANGE_NM = (1e-6, 1e6)
DEFLECTION_RANGE_RAD = (1e-6, 1e4)
#: correlation of torque with deflection below minus this reads as a flipped channel
FLIPPED_CORRELATION = 0.3


def read_record(path: Path, columns, angle_unit: str, torque_unit: str,
                trust_units: bool = False):
    """Read a bench CSV: file, UTF-8 and size checks here, parsing by :mod:`springcad.fit.data`.

    Raises:
        DataError: unreadable, too large, not UTF-8, or malformed (see ``parse_bench_csv``).
    """
    from springcad.fit.data import parse_bench_csv
    from springcad.textio import decode_utf8

    try:
        if not path.is_file():
            raise DataError(f"bench data file '{path}' does not exist or is not a file")
        if path.stat().st_size > MAX_CSV_BYTES:
            raise DataError(f"bench data file '{path}' is larger than "
                            f"{MAX_CSV_BYTES // 1_000_000} MB; split the record")
        raw = path.read_bytes()
    except OSError as err:
        raise DataError(f"bench data file '{path}' cannot be read: {err.strerror or err}") from None
    text, problem = decode_utf8(raw)
    if text is None:
        raise DataError(f"bench data file '{path}' {problem}")
    return parse_bench_csv(text, columns, angle_unit, torque_unit, source=str(path),
                           trust_units=trust_units)


def check_record(record) -> None:
    """Refuse records no torsion spring produces: magnitudes out of range, torque falling
    as the deflection rises (a flipped sign).

    Raises:
        DataError: naming the channel, the value and what to check.
    """
    import math

    import numpy as np

    src = record.source
    for name, values, (lo, hi), unit in (
            ("torque", record.torque_Nm, TORQUE_RANGE_NM, "N*m"),
            ("deflection", record.deflection_rad, DEFLECTION_RANGE_RAD, "rad")):
        peak = float(np.max(np.abs(values)))
        if not lo <= peak <= hi:
            raise DataError(f"{src}: the {name} peaks at {peak:.3g} {unit}; a torsion-spring bench "
                            f"record lies between {lo:g} and {hi:g} {unit}: check the column's "
                            "unit (--torque-unit, --angle-unit) and scale")
    x = record.deflection_rad - record.deflection_rad.mean()
    y = record.torque_Nm - record.torque_Nm.mean()
    slope = float(x @ y) / float(x @ x)
    # a record with no spring (torque noise only) has a slope of either sign: it is refused
    # only when the torque clearly follows the deflection downwards, and otherwise the fit
    # reports whether any stiffness stands above the noise
    correlation = float(x @ y) / math.sqrt(float(x @ x) * float(y @ y))
    if correlation < -FLIPPED_CORRELATION:
        raise DataError(f"{src}: the torque falls as the deflection rises (least-squares slope "
                        f"{slope:.3g} N*m/rad): the sign of the torque or the deflection column "
                        "is flipped; negate one of them")


def run(args) -> int:
    """Run ``springcad fit``; returns the exit status."""
    from springcad.cli.common import default_out, stage, warn
    from springcad.fit.analysis import fit_record
    from springcad.fit.compare import design_from_config
    from springcad.fit.data import ColumnMap
    from springcad.report.fit_report import write_fit_outputs
    from springcad.report.outdir import atomic_output_dir, check_output_dir

    if args.encoder_cols is not None and len(args.encoder_cols) > 2:
        raise DataError(f"--encoder-cols takes one or two columns, got {len(args.encoder_cols)}")
    columns = ColumnMap(args.time_col, args.torque_col, args.deflection_col,
                        tuple(args.encoder_cols) if args.encoder_cols else None)
    out = args.out or default_out(args.data)
    inputs = [args.data, args.config]
    record = read_record(args.data, columns, args.angle_unit, args.torque_unit, args.trust_units)
    check_record(record)
    warn("fit", record.warnings)
    design = None
    if args.config:
        with stage("design", lambda: f"config {args.config}"):
            design = design_from_config(args.config)
        warn("fit", design.get("warnings", []))
    check_output_dir(out, args.overwrite, inputs=inputs)  # before the fit
    with stage("fit", lambda: f"record {args.data}"):
        result = fit_record(record, args.target_stiffness, design, trust_units=args.trust_units)
    warn("fit", result.record.warnings[len(record.warnings):])
    with atomic_output_dir(out, overwrite=args.overwrite, inputs=inputs) as tmp:
        written = write_fit_outputs(result, tmp, fmt=args.format, plots=not args.no_plots)
    _print_summary(result, out, [p.name for p in written])
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
