"""``springcad simulate CONFIG --out RECORD.csv``: a bench record of the designed stack.

Plans a test before the hardware exists: the paper's protocol (ramps to +-4, 8 ... 24 deg
and back, 500 Hz) on the designed stack, with noise and any effects asked for.
"""

from __future__ import annotations

from pathlib import Path

from springcad.cli.common import bounded, stage, warn


def register(sub):
    p = sub.add_parser("simulate", help="simulate a bench record of the designed stack (CSV)")
    p.add_argument("config", type=Path, help="job TOML")
    p.add_argument("--out", type=Path, required=True, help="CSV file to write")
    p.add_argument("--stiffness", type=bounded(0, 1e6, " N*m/rad", lo_open=True), default=None,
                   help="stiffness N*m/rad (default: the design's beam-theory stack stiffness)")
    p.add_argument("--backlash-rad", type=bounded(0, 0.5, " rad"), default=None,
                   help="backlash rad (default: the design's nominal stack backlash)")
    p.add_argument("--friction-Nm", type=bounded(0, 1e4, " N*m"), default=0.0,
                   help="Coulomb friction torque N*m")
    p.add_argument("--lag-s", type=bounded(0, 1, " s"), default=0.0, help="torque channel lag s")
    p.add_argument("--drift-Nm-per-s", type=bounded(-100, 100, " N*m/s"), default=0.0,
                   help="torque zero drift N*m/s")
    p.add_argument("--seed", type=bounded(0, 2 ** 32 - 1, integer=True), default=0,
                   help="random seed")
    p.add_argument("--overwrite", action="store_true", help="replace an existing file")
    p.set_defaults(func=run)


def run(args) -> int:
    from springcad.config import load_job
    from springcad.design.job import design_job
    from springcad.fit.bench import BenchSpring, simulate
    from springcad.fit.data import to_csv_text
    from springcad.report.outdir import atomic_output_file, check_output_file

    job = load_job(args.config)
    check_output_file(args.out, args.overwrite, inputs=[args.config])
    with stage("design", lambda: f"job {job.name}"):
        design = design_job(job)
    warn("simulate", design.warnings)
    stack = design.stack
    k = args.stiffness or stack.stiffness_Nmm_per_rad / 1000
    b = stack.backlash.nominal if args.backlash_rad is None else args.backlash_rad
    with stage("simulate"):
        sim = simulate(BenchSpring(k, backlash_rad=b, friction_torque_Nm=args.friction_Nm,
                                   lag_s=args.lag_s, drift_Nm_per_s=args.drift_Nm_per_s),
                       seed=args.seed)
        text = to_csv_text(sim.record)
    with atomic_output_file(args.out, args.overwrite, inputs=[args.config]) as tmp:
        tmp.write_text(text)
    print(f"wrote {args.out}: {sim.record.n_samples} samples, K = {k:.2f} N*m/rad, "
          f"backlash {b:.4f} rad, seed {args.seed}")
    return 0
