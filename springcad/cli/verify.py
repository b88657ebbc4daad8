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

from pathlib import Path

import springcad.api as sc
from springcad.cli.common import add_cache_flag, bounded, cache_of, default_out, warn
from springcad.cli.progress import console
from springcad.options import LEVELS_RANGE, LOADS, MESHERS, MODELS, TOLERANCE_PCT_RANGE, VERIFY
from springcad.report.outdir import check_output_dir


def register(sub):
    p = sub.add_parser("verify", help="FEA-verify and correct every spring; write fea.json, "
                                      ".vtu and PNG renders")
    p.add_argument("config", type=Path, help="job TOML (see templates/)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<config name>/verify)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.add_argument("--model", choices=MODELS, default=VERIFY.model,
                   help="2d3d: plane-stress convergence study x 3D tet factor (default); "
                        "3d: convergence study on quadratic tets (slow); 2d: plane stress only")
    p.add_argument("--levels", type=bounded(*LEVELS_RANGE, integer=True), default=VERIFY.levels,
                   help="mesh levels in the study ({} to {})".format(*LEVELS_RANGE))
    p.add_argument("--mesher", choices=MESHERS, default=VERIFY.mesher,
                   help="gmsh: exact face, nested levels, extruded quadratic tets (default); "
                        "pytetwild: fTetWild on the CAD solid (implies --model 3d, ~1 min)")
    p.add_argument("--tolerance-pct", type=bounded(*TOLERANCE_PCT_RANGE, " %", lo_open=True,
                                                   hi_open=True),
                   default=VERIFY.tolerance_pct,
                   help="accepted stiffness error vs target in %% (default %(default)g)")
    p.add_argument("--no-correct", dest="correct", action="store_false",
                   help="verify the design as it is, without the width correction")
    p.add_argument("--load", choices=LOADS, default=VERIFY.load,
                   help="cam load model (default: smooth tangential traction patch)")
    p.add_argument("--support-study", action="store_true",
                   help="also compare the rim held at the outer face vs at the rim holes "
                        "(full ring, ~10 s per spring)")
    p.add_argument("--no-contact", dest="contact", action="store_false",
                   help="skip the cam contact sweep (rigid cam turned to +-max deflection)")
    p.add_argument("--no-render", action="store_true", help="skip .vtu and PNG outputs")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    add_cache_flag(p)
    p.set_defaults(func=run, correct=VERIFY.correct, contact=VERIFY.contact)


def run(args) -> int:
    out = args.out or default_out(args.config) / "verify"
    job = sc.load(args.config)
    check_output_dir(out, args.overwrite, inputs=[args.config])  # fail before the work
    progress = console(args.quiet)
    design = sc.design_job(job, cache=cache_of(args), progress=progress)
    warn("verify", design.warnings)
    result = sc.verify(design, model=args.model, levels=args.levels, mesher=args.mesher,
                       tolerance_pct=args.tolerance_pct, correct=args.correct, load=args.load,
                       support_study=args.support_study, contact=args.contact,
                       keep_fields=not args.no_render, progress=progress, cache=cache_of(args))
    sc.export_verification(result, out, overwrite=args.overwrite, render=not args.no_render,
                           progress=progress, cache=cache_of(args))
    print(result.summary())
    for finding in result.raw.release_failures():  # not a verification failure: build's gate
        print(f"  contact: {finding}")
    print(f"\nwrote {out / 'fea.json'}")
    return 0 if result.ok else 1
