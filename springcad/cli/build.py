"""``springcad build CONFIG --out DIR``: design, verify, solids, checks, exports.

A thin layer on the public API (:mod:`springcad.api`): ``design_job``,
``verify``, ``build`` and ``export_build`` are the stages (:data:`PIPELINE`), each
announced as ``[i/n] name`` on stderr with its progress and time. The verification
includes the cam contact sweep over +-theta_max (its curve is in fea.json, a PNG and
report.html; its flags are release notes, not failures). The output
folder is checked before any work and appears only when every file was
written (``export_build`` writes into a temporary folder). A failed FEA
verification or check is exit status 1; a CAD-kernel, mesher or solver failure
is one message naming the stage, the part and what to change (exit status 2).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import springcad.api as sc
from springcad.cli.common import add_cache_flag, cache_of, default_out, warn
from springcad.cli.progress import console
from springcad.errors import ConfigError
from springcad.options import DXF_VERSION, DXF_VERSIONS, REVISION, check_revision
from springcad.parallel import import_while_waiting, return_freed_memory, trim_heap
from springcad.report.outdir import check_output_dir

#: the stages, in order: the FEA verification (and correction) comes before any solid is
#: made, so the parts checked and exported are the corrected ones
PIPELINE = ["design", "verify", "solids", "checks", "exports"]


def register(sub):
    p = sub.add_parser("build", help="design, build solids, check them and export CAD files")
    p.add_argument("config", type=Path, help="job TOML (see templates/)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<config name>/)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.add_argument("--accept-violations", action="store_true",
                   help="build even when a wire-EDM manufacturability rule is broken "
                        "(the violations are recorded in build.json)")
    p.add_argument("--revision", default=REVISION, type=_revision,
                   help="drawing revision (default %(default)s)")
    p.add_argument("--title-block", type=Path, default=None,
                   help="title block template (default templates/drawing_title_block.toml)")
    p.add_argument("--dxf-version", choices=DXF_VERSIONS, default=DXF_VERSION,
                   help="DXF file version of the cutting profiles (default %(default)s; R12 "
                        "writes AC1009 for CAM that reads nothing newer; both hold LINE, ARC "
                        "and CIRCLE entities only)")
    p.add_argument("--no-render", action="store_true", help="skip the PNG renders")
    p.add_argument("--no-verify", action="store_true",
                   help="skip the FEA verification (and correction) before the CAD step")
    add_cache_flag(p)
    p.set_defaults(func=run)


def _revision(text: str) -> str:
    """The drawing revision (argparse ``type``): :func:`springcad.options.check_revision`."""
    try:
        check_revision(text)
    except ConfigError:
        raise argparse.ArgumentTypeError(f"{text!r}: 1 to 8 ASCII letters or digits") from None
    return text


#: the modules of the solids, checks and exports (the CAD kernel: build123d, OCP, ezdxf),
#: imported while the verification waits (:func:`springcad.parallel.import_while_waiting`)
CAD_MODULES = ("springcad.geometry.families", "springcad.geometry.checks",
               "springcad.export.bundle")

#: progress on stderr, indented under the stage it belongs to
say = console(indent="  ")


def _announce(name: str) -> float:
    print(f"[{PIPELINE.index(name) + 1}/{len(PIPELINE)}] {name}", file=sys.stderr, flush=True)
    return time.perf_counter()


def _done(name: str, t0: float, timings: dict) -> None:
    timings[name] = round(time.perf_counter() - t0, 3)
    print(f"      {name} done in {timings[name]:.1f} s", file=sys.stderr, flush=True)


def run(args) -> int:
    out = args.out or default_out(args.config)
    job = sc.load(args.config)  # everything that can be checked, before any work
    template = sc.load_title_block(args.title_block)
    check_output_dir(out, args.overwrite, inputs=[args.config, args.title_block])
    timings = {}
    return_freed_memory()  # the FEA's large arrays go back to the OS when freed

    t0 = _announce("design")
    cache = cache_of(args)
    design = sc.design_job(job, cache=cache, progress=say)
    warn("build", design.warnings)
    _done("design", t0, timings)

    t0 = _announce("verify")
    # the solids' CAD kernel is imported while the verification waits for its 3D factor
    import_while_waiting(*CAD_MODULES)
    verification = None
    if args.no_verify:
        say("skipped (--no-verify): the parts are beam-theory designs, not FEA-verified")
    else:
        verification = sc.verify(design, keep_fields=not args.no_render, progress=say,
                                 cache=cache)
        say(verification.summary().replace("\n", "\n  "))
        if not verification.ok:
            verification.raise_for_failures()
        trim_heap()  # the FEA's freed factorisations: ~200 MB less for the CAD steps
    _done("verify", t0, timings)

    # solids and checks are one API call (sc.build); its own timings split them
    t0 = _announce("solids")
    built = sc.build(verification or design, accept_violations=args.accept_violations,
                     progress=say, cache=cache)
    print(f"[{PIPELINE.index('checks') + 1}/{len(PIPELINE)}] checks "
          f"({built.checks.summary()})", file=sys.stderr, flush=True)
    built.raise_for_failures()
    for name in ("solids", "checks"):
        timings[name] = built.timings_s[name]
        print(f"      {name} done in {timings[name]:.1f} s", file=sys.stderr, flush=True)

    t0 = _announce("exports")
    built = sc.export_build(built, out, overwrite=args.overwrite, render=not args.no_render,
                            revision=args.revision, title_block=template, progress=say,
                            timings_s=timings, cache=cache, dxf_version=args.dxf_version)
    _done("exports", t0, timings)
    _print_summary(built, out)
    print(f"report: {out / 'report.html'} (open it in a web browser)")
    return 0


def _print_summary(built, out: Path) -> None:
    asm = built.assembly
    rows = [("part", "qty", "title", "process")]
    rows += [(p["part_number"], str(p["quantity"]), p["title"], p["process"])
             for p in built.parts()]
    w = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.ljust(n) for c, n in zip(r, w)))
    print(f"\n{built.checks.summary()}; {sum(c.passed for c in built.roundtrip)}/"
          f"{len(built.roundtrip)} export read-backs passed")
    print("\n".join(built.release.summary_lines()))
    print(f"input: {', '.join(asm.input_names)}; output: {', '.join(asm.output_names)}")
    print(f"wrote {len(built.files) + 1} files to {out} in {built.timings_s['total']:.1f} s")
