"""``springcad simulate [CONFIG] --out RECORD.csv``: a bench record of a spring under a test protocol.

Plans a test before the hardware exists, or checks that a planned protocol
separates the effects a measured record confounded (``springcad fit``
prints the command line of the protocol it recommends). The spring is the
designed stack of CONFIG (beam-theory stiffness, nominal backlash) or the one
given by ``--stiffness``; the protocol is the paper's staircase of ramps (at
a fixed ramp time or at one or more rates, with optional holds) or a stepped
sine sweep; noise and effects are added on request.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import springcad.api as sc
from springcad.cli.common import bounded, warn
from springcad.errors import DataError
from springcad.report.outdir import atomic_output_file, check_output_file


def _floats(text: str) -> tuple[float, ...]:
    """A comma-separated list of finite numbers (argparse ``type``)."""
    try:
        values = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of numbers") from None
    if not values:
        raise argparse.ArgumentTypeError("give at least one number")
    if not all(math.isfinite(v) for v in values) or len(values) > 1000:
        raise argparse.ArgumentTypeError(f"{text!r}: give at most 1000 finite numbers")
    return values


def register(sub):
    p = sub.add_parser("simulate", help="simulate a bench record under a test protocol (CSV)",
                       description=__doc__.split("\n\n")[1])
    p.add_argument("config", type=Path, nargs="?", help="job TOML (or give --stiffness)")
    p.add_argument("--out", type=Path, required=True, help="CSV file to write")
    p.add_argument("--stiffness", type=bounded(0, 1e6, " N*m/rad", lo_open=True), default=None,
                   help="stiffness N*m/rad (default: the design's beam-theory stack stiffness)")
    p.add_argument("--backlash-rad", type=bounded(0, 0.5, " rad"), default=None,
                   help="backlash rad (default: the design's nominal stack backlash, or 0)")
    g = p.add_argument_group("protocol")
    g.add_argument("--protocol", choices=("staircase", "sine"), default="staircase",
                   help="staircase of ramps 0 -> +A -> 0 -> -A -> 0 (the paper's), or a "
                        "stepped sine sweep [staircase]")
    g.add_argument("--amplitudes-deg", type=_floats, default=None,
                   help="ramp targets or sine amplitudes, deg (default 4,8,...,24 for the "
                        "staircase, 20 for sines)")
    g.add_argument("--ramp-s", type=bounded(1e-3, 1e4, " s"), default=None,
                   help="duration of every ramp, s, when no --rates-deg-per-s [1.6]")
    g.add_argument("--rates-deg-per-s", type=_floats, default=None,
                   help="ramp speeds, deg/s: the staircase is run once per rate")
    g.add_argument("--profile", choices=("cosine", "linear"), default=None,
                   help="ramp shape [cosine]")
    g.add_argument("--hold-s", type=bounded(0, 1e4, " s"), default=None,
                   help="hold at each peak, s [0]")
    g.add_argument("--frequencies-hz", type=_floats, default=None,
                   help="sine frequencies, Hz [0.1,0.3,1]")
    g.add_argument("--cycles", type=bounded(1, 1000, integer=True), default=None,
                   help="sine cycles per frequency [3]")
    g.add_argument("--sample-rate-hz", type=bounded(1, 1e5, " Hz"), default=None,
                   help="sample rate, Hz [500]")
    g.add_argument("--rest-s", type=bounded(0, 1e3, " s"), default=None,
                   help="rest before and after, s [0.5]")
    e = p.add_argument_group("effects and noise")
    e.add_argument("--friction-Nm", type=bounded(0, 1e4, " N*m"), default=None,
                   help="Coulomb friction torque N*m")
    e.add_argument("--presliding-rad", type=bounded(0, 0.5, " rad"), default=None,
                   help="angle over which friction reverses, rad [0.005]")
    e.add_argument("--lag-s", type=bounded(0, 1, " s"), default=None, help="torque channel lag s")
    e.add_argument("--drift-Nm-per-s", type=bounded(-100, 100, " N*m/s"), default=None,
                   help="torque zero drift N*m/s")
    e.add_argument("--torque-noise-Nm", type=bounded(0, 1e4, " N*m"), default=None,
                   help="torque noise SD [0.03]")
    e.add_argument("--deflection-noise-rad", type=bounded(0, 1, " rad"), default=None,
                   help="deflection noise SD [0.001]")
    e.add_argument("--camera-fps", type=bounded(0, 1e5, " Hz", lo_open=True), default=None,
                   help="deflection noise drawn per camera frame at this rate (correlated)")
    p.add_argument("--seed", type=bounded(0, 2 ** 32 - 1, integer=True), default=0,
                   help="random seed")
    p.add_argument("--overwrite", action="store_true", help="replace an existing file")
    p.set_defaults(func=run)


def protocol_from_args(args):
    """The protocol the options describe (rad, s); options not given take its defaults."""
    amps = (None if args.amplitudes_deg is None
            else tuple(math.radians(a) for a in args.amplitudes_deg))
    if args.protocol == "sine":
        return sc.bench_protocol("sine", amplitudes_rad=amps, frequencies_hz=args.frequencies_hz,
                                 cycles=args.cycles, sample_rate_hz=args.sample_rate_hz,
                                 rest_s=args.rest_s)
    rates = (None if args.rates_deg_per_s is None
             else tuple(math.radians(r) for r in args.rates_deg_per_s))
    return sc.bench_protocol("staircase", amplitudes_rad=amps, ramp_s=args.ramp_s,
                             profile=args.profile, sample_rate_hz=args.sample_rate_hz,
                             rest_s=args.rest_s, rates_rad_per_s=rates, hold_s=args.hold_s)


def run(args) -> int:
    inputs = [args.config] if args.config is not None else []
    if args.config is None and args.stiffness is None:
        raise DataError("give a job CONFIG or --stiffness (N*m/rad)")
    check_output_file(args.out, args.overwrite, inputs=inputs)
    spring = args.stiffness if args.config is None else sc.design_job(args.config)
    if args.config is not None:
        warn("simulate", spring.warnings)
    protocol = protocol_from_args(args)
    noise = {"torque_Nm": args.torque_noise_Nm, "deflection_rad": args.deflection_noise_rad,
             "camera_fps": args.camera_fps}
    effects = {"friction_torque_Nm": args.friction_Nm, "presliding_rad": args.presliding_rad,
               "lag_s": args.lag_s, "drift_Nm_per_s": args.drift_Nm_per_s}
    sim = sc.simulate(spring, protocol=protocol, seed=args.seed, backlash_rad=args.backlash_rad,
                      stiffness_Nm_per_rad=args.stiffness,
                      noise={k: v for k, v in noise.items() if v is not None},
                      **{k: v for k, v in effects.items() if v is not None})
    with atomic_output_file(args.out, args.overwrite, inputs=inputs) as tmp:
        tmp.write_text(sim.record.to_csv())
    print(f"wrote {args.out}: {sim.record.n_samples} samples ({protocol.duration_s:.4g} s, "
          f"{protocol.describe()['kind']}), K = {sim.spring.stiffness_Nm_per_rad:.4g} N*m/rad, "
          f"backlash {sim.spring.backlash_rad:.4g} rad, seed {args.seed}")
    return 0
