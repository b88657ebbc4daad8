"""``springcad verify CONFIG [--out DIR]``: FEA-verify (and correct) every spring of a job.

Writes ``DIR/fea.json`` (the :meth:`fea.verdict.JobVerification.to_dict`
document), per spring a 3D and a 2D ``.vtu`` of the sector at maximum
deflection (displacement, von Mises), PNG renders of the von Mises field and
``<spring>_contact.png`` (the cam contact sweep: torque-angle curve, stiffness,
deformed contact at +-max deflection; its flags are printed, they do not change
the exit status).
Exit status: 0 verified, 1 a spring or the stack fails its stiffness target or
stress limit (the report is still written), 2 bad input or a mesher/solver
failure (one message naming the spring; nothing written).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from springcad.cli.common import bounded, default_out, stage, warn
from springcad.report.fea_outputs import write_outputs


def register(sub):
    p = sub.add_parser("verify", help="FEA-verify and correct every spring; write fea.json, "
                                      ".vtu and PNG renders")
    p.add_argument("config", type=Path, help="job TOML (see templates/)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<config name>/verify)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.add_argument("--model", choices=("2d3d", "2d", "3d"), default="2d3d",
                   help="2d3d: plane-stress convergence study x 3D tet factor (default); "
                        "3d: convergence study on quadratic tets (slow); 2d: plane stress only")
    p.add_argument("--levels", type=bounded(3, 5, integer=True), default=3, help="mesh levels in the study (3 to 5)")
    p.add_argument("--mesher", choices=("gmsh", "pytetwild"), default="gmsh",
                   help="gmsh: exact face, nested levels, extruded quadratic tets (default); "
                        "pytetwild: fTetWild on the CAD solid (implies --model 3d, ~1 min)")
    p.add_argument("--tolerance-pct", type=bounded(0.01, 50, " %"), default=1.0,
                   help="accepted stiffness error vs target in %% (default 1)")
    p.add_argument("--no-correct", action="store_true",
                   help="verify the design as it is, without the width correction")
    p.add_argument("--load", choices=("traction", "rigid_cam"), default="traction",
                   help="cam load model (default: smooth tangential traction patch)")
    p.add_argument("--support-study", action="store_true",
                   help="also compare the rim held at the outer face vs at the rim holes "
                        "(full ring, ~10 s per spring)")
    p.add_argument("--no-contact", action="store_true",
                   help="skip the cam contact sweep (rigid cam turned to +-max deflection)")
    p.add_argument("--no-render", action="store_true", help="skip .vtu and PNG outputs")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=run)


def _progress(quiet: bool, state: dict):
    t0 = time.perf_counter()

    def report(message: str, fraction: float | None = None) -> None:
        if message.startswith("verifying spring "):
            state["spring"] = message.split()[2]
        if not quiet:
            pct = "" if fraction is None else f" {100 * fraction:3.0f}%"
            print(f"[{time.perf_counter() - t0:6.1f} s{pct}] {message}", file=sys.stderr,
                  flush=True)

    return report


def run(args) -> int:
    from springcad.config import load_job
    from springcad.report.outdir import atomic_output_dir, check_output_dir

    out = args.out or default_out(args.config) / "verify"
    job = load_job(args.config)
    check_output_dir(out, args.overwrite, inputs=[args.config])  # fail before the work

    from fea.problem import LoadCase
    from fea.verify import VerifyOptions, verify_job
    from springcad.design.job import design_job

    state = {"spring": ""}
    progress = _progress(args.quiet, state)
    model = "3d" if args.mesher == "pytetwild" else args.model
    options = VerifyOptions(model=model, levels=args.levels, mesher=args.mesher,
                            tolerance=args.tolerance_pct / 100.0, correct=not args.no_correct,
                            case=LoadCase(load=args.load), keep_fields=not args.no_render,
                            support_study=args.support_study, contact=not args.no_contact)
    progress("designing")
    with stage("design", lambda: f"job {job.name}"):
        design = design_job(job)
    warn("verify", design.warnings)
    with stage("verify", lambda: f"spring {state['spring']}" if state["spring"] else ""):
        result = verify_job(design, options, progress)
    with atomic_output_dir(out, overwrite=args.overwrite, inputs=[args.config]) as tmp:
        write_outputs(result, tmp, render=not args.no_render, progress=progress)
    print(result.summary())
    for finding in result.release_failures():  # not a verification failure: build's gate
        print(f"  contact: {finding}")
    print(f"\nwrote {out / 'fea.json'}")
    return 0 if result.ok else 1
