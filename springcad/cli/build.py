"""``springcad build CONFIG --out DIR``: design, solids, checks, exports; writes build.json.

The run is a pipeline of named steps over one :class:`BuildContext`
(:data:`PIPELINE`); a step is a function ``(ctx) -> None``. A verification
step (FEA) goes between "checks" and "exports" by adding it to
:data:`STEPS` and :data:`PIPELINE`. Everything is written into a temporary
folder that becomes ``DIR`` only when every step succeeded. A failed FEA
verification or check is exit status 1; a CAD-kernel, mesher or solver failure
is one message naming the stage, the part and what to change (exit status 2).
"""

from __future__ import annotations

import datetime
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from springcad.cli.common import default_out, stage, warn
from springcad.errors import CheckFailed, ConfigError
from springcad.report.jsonio import write_json

SCHEMA = "springcad.build/1"


def register(sub):
    p = sub.add_parser("build", help="design, build solids, check them and export CAD files")
    p.add_argument("config", type=Path, help="job TOML (see templates/)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<config name>/)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.add_argument("--accept-violations", action="store_true",
                   help="build even when a wire-EDM manufacturability rule is broken "
                        "(the violations are recorded in build.json)")
    p.add_argument("--revision", default="A", type=_revision, help="drawing revision (default A)")
    p.add_argument("--title-block", type=Path, default=None,
                   help="title block template (default templates/drawing_title_block.toml)")
    p.add_argument("--no-render", action="store_true", help="skip the PNG renders")
    p.add_argument("--no-verify", action="store_true",
                   help="skip the FEA verification (and correction) before the CAD step")
    p.set_defaults(func=run)


def _revision(text: str) -> str:
    import argparse

    if not (1 <= len(text) <= 8 and text.isascii() and text.isalnum()):
        raise argparse.ArgumentTypeError(f"{text!r}: 1 to 8 ASCII letters or digits")
    return text


@dataclass
class BuildContext:
    """State passed from step to step."""

    args: object
    out_tmp: Path
    job: object = None
    design: object = None
    verification: object = None
    assembly: object = None
    report: object = None
    files: list = field(default_factory=list)
    roundtrip: list = field(default_factory=list)
    release: object = None
    timings: dict = field(default_factory=dict)
    started: str = ""
    template: dict | None = None
    last: str = ""
    """The last progress message: names the part a failing stage was working on."""

    spring: str = ""

    def say(self, msg: str, fraction: float | None = None) -> None:
        """The progress protocol (:mod:`springcad.progress`); the fraction is not shown."""
        self.last = msg
        if msg.startswith("verifying spring "):
            self.spring = msg.split()[2]
        print(f"  {msg}", file=sys.stderr, flush=True)


def step_design(ctx: BuildContext) -> None:
    from springcad.design.job import design_job

    ctx.design = design_job(ctx.job)
    warn("build", ctx.design.warnings)
    write_json(ctx.out_tmp / "design.json", ctx.design.to_dict())


def step_verify(ctx: BuildContext) -> None:
    """FEA-verify (and correct) every spring; the corrected springs are what gets built."""
    if ctx.args.no_verify:
        ctx.say("skipped (--no-verify): the parts are beam-theory designs, not FEA-verified")
        return
    from fea.verify import VerificationFailed, VerifyOptions, verify_job
    from springcad.report.fea_outputs import write_outputs

    def progress(message, fraction=None):
        ctx.say(message)

    result = verify_job(ctx.design, VerifyOptions(keep_fields=not ctx.args.no_render), progress)
    ctx.verification = result
    ctx.say(result.summary().replace("\n", "\n  "))
    try:
        result.raise_for_failures()
    except VerificationFailed as err:
        raise CheckFailed(str(err)) from err
    (ctx.out_tmp / "fea").mkdir()
    write_outputs(result, ctx.out_tmp / "fea", render=not ctx.args.no_render, progress=ctx.say)
    ctx.design = ctx.design.with_springs(result.corrected_designs())
    write_json(ctx.out_tmp / "design.json", ctx.design.to_dict())


def step_solids(ctx: BuildContext) -> None:
    from springcad.geometry.stack import build_stack

    ctx.assembly = build_stack(ctx.design, progress=ctx.say)


def step_checks(ctx: BuildContext) -> None:
    from springcad.geometry.checks import ChecksFailed, run_checks

    ctx.report = run_checks(ctx.assembly, progress=ctx.say)
    try:
        ctx.report.raise_if_failed(ctx.args.accept_violations)
    except ChecksFailed as err:
        raise CheckFailed(str(err)) from err


def step_exports(ctx: BuildContext) -> None:
    from springcad.export.bundle import export_parts, export_stack, roundtrip_checks
    from springcad.export.release import release_status
    from springcad.geometry.checks import CheckReport, ChecksFailed

    template = ctx.template
    ctx.release = release_status(ctx.design, ctx.verification, ctx.args.no_verify,
                                 ctx.report.checks)
    info = {"job": ctx.job.name, "revision": ctx.args.revision,
            "date": build_date(), "drawn_by": _drawn_by(),
            "release": ctx.release}
    parts = export_parts(ctx.assembly, ctx.out_tmp, info, template, progress=ctx.say)
    ctx.files = parts + export_stack(ctx.assembly, ctx.out_tmp, parts,
                                     render=not ctx.args.no_render, progress=ctx.say,
                                     release=ctx.release, date=info["date"])
    ctx.roundtrip = roundtrip_checks(ctx.assembly, ctx.out_tmp, ctx.files, progress=ctx.say)
    try:
        CheckReport(ctx.roundtrip).raise_if_failed()
    except ChecksFailed as err:
        raise CheckFailed(str(err)) from err


STEPS = {"design": step_design, "verify": step_verify, "solids": step_solids,
         "checks": step_checks, "exports": step_exports}
#: step order: the FEA verification (and correction) comes before any solid is made, so
#: the parts checked and exported are the corrected ones
PIPELINE = ["design", "verify", "solids", "checks", "exports"]


def build_date() -> str:
    """The build's date (YYYY-MM-DD) for title blocks and STEP headers: today, or the UTC
    day of ``SOURCE_DATE_EPOCH`` (seconds since 1970, the reproducible-builds convention)
    when it is set, so two builds of one job give byte-identical files.

    Raises:
        ConfigError: ``SOURCE_DATE_EPOCH`` is not a whole number of seconds.
    """
    import os

    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if not epoch:
        return datetime.date.today().isoformat()
    try:
        stamp = datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc)
    except (ValueError, OverflowError, OSError) as err:
        raise ConfigError("SOURCE_DATE_EPOCH (environment)", epoch,
                          "must be whole seconds since 1970-01-01 UTC",
                          "unset it to date the build today") from err
    return stamp.date().isoformat()


def _drawn_by() -> str:
    from springcad.version import __version__

    return f"springcad {__version__}"


def build_json(ctx: BuildContext) -> dict:
    """The ``build.json`` document: inputs, every file written, every check."""
    from springcad.version import __version__

    asm, st = ctx.assembly, ctx.design.stack
    qty = asm.quantities()
    report = ctx.report
    checks = report.checks + ctx.roundtrip
    return {
        "schema": SCHEMA,
        "springcad_version": __version__,
        "job": {"name": ctx.job.name, "config": str(ctx.args.config)},
        "started": ctx.started,
        "verification": ({"ok": ctx.verification.ok, "fea_json": "fea/fea.json",
                          "springs": {n: {"stiffness_fea_Nm_per_rad": v.stiffness_fea_Nmm_per_rad / 1e3,
                                          "yield_margin": v.yield_margin}
                                      for n, v in ctx.verification.springs.items()}}
                         if ctx.verification is not None else "skipped (--no-verify)"),
        "options": {"accept_violations": ctx.args.accept_violations, "verify": not ctx.args.no_verify,
                    "revision": ctx.args.revision, "render": not ctx.args.no_render},
        "timings_s": ctx.timings,
        "release": ctx.release.to_dict(),
        "stack": {"sequence": list(st.sequence), "input": st.input, "output": st.output,
                  "joints": list(st.joints), "input_parts": asm.input_names,
                  "output_parts": asm.output_names, "instances": len(asm.instances)},
        "parts": [{"part_number": pn, "name": p.info.name, "title": p.info.title, "kind": p.info.kind,
                   "quantity": qty[pn], "process": p.info.process,
                   "dimensions_mm": p.info.dimensions} for pn, p in asm.parts.items()],
        "files": [f.to_dict() for f in ctx.files] + [
            {"path": "design.json", "kind": "design", "part": "", "bytes":
             (ctx.out_tmp / "design.json").stat().st_size}],
        "checks": {
            "passed": all(c.passed for c in checks if c.kind == "error"),
            "violations_accepted": bool(report.violations) and ctx.args.accept_violations,
            "summary": report.summary(),
            "n_checks": len(checks),
            "n_failed": sum(not c.passed for c in checks),
            "items": [c.to_dict() for c in checks]},
    }


def _title_block(path: Path | None) -> dict:
    """The drawing title block, read and checked before any work."""
    from springcad.config import read_toml
    from springcad.export.drawing import load_title_block

    template = read_toml(path) if path else load_title_block(None)
    for key in ("block", "rows"):
        if key not in template:
            raise ConfigError(f"{path}: {key}", None, "is required in a title block template "
                                                      "(see templates/drawing_title_block.toml)")
    return template


def _subject(ctx: BuildContext, name: str):
    """What a failing step was working on, from its progress messages."""
    def subject() -> str:
        last = ctx.last
        if name == "design":
            return f"job {ctx.job.name}"
        if name == "verify" and ctx.spring:
            return f"spring {ctx.spring}"
        if name == "solids":
            return (f"the part after {last.split()[-1]}" if last.startswith("built ")
                    else "the first part")
        return f"the step after '{last}'" if last else ""
    return subject


def run(args) -> int:
    from springcad.config import load_job
    from springcad.report.outdir import atomic_output_dir

    out = args.out or default_out(args.config)
    job = load_job(args.config)  # everything that can be checked, before any work
    template = _title_block(args.title_block)
    ctx = None
    t_all = time.perf_counter()
    with atomic_output_dir(out, overwrite=args.overwrite,
                           inputs=[args.config, args.title_block]) as tmp:
        ctx = BuildContext(args, Path(tmp), job=job, template=template,
                           started=datetime.datetime.now().isoformat(timespec="seconds"))
        for i, name in enumerate(PIPELINE, 1):
            print(f"[{i}/{len(PIPELINE)}] {name}", file=sys.stderr, flush=True)
            t0 = time.perf_counter()
            ctx.last = ""
            with stage(name, _subject(ctx, name)):
                STEPS[name](ctx)
            ctx.timings[name] = round(time.perf_counter() - t0, 3)
            print(f"      {name} done in {ctx.timings[name]:.1f} s", file=sys.stderr, flush=True)
        ctx.timings["total"] = round(time.perf_counter() - t_all, 3)
        from springcad.report.html_build import write_build_report

        doc = build_json(ctx)
        write_json(Path(tmp) / "build.json", doc)
        report = write_build_report(tmp)  # last: it reads the files written above
        doc["files"].append({"path": "report.html", "kind": "report", "part": "",
                             "bytes": report.stat().st_size})
        write_json(Path(tmp) / "build.json", doc)  # now listing the report too
    _print_summary(ctx, out)
    print(f"report: {out / 'report.html'} (open it in a web browser)")
    return 0


def _print_summary(ctx: BuildContext, out: Path) -> None:
    asm, rep = ctx.assembly, ctx.report
    qty = asm.quantities()
    rows = [("part", "qty", "title", "process")]
    rows += [(pn, str(qty[pn]), p.info.title, p.info.process) for pn, p in asm.parts.items()]
    w = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.ljust(n) for c, n in zip(r, w)))
    print(f"\n{rep.summary()}; {sum(c.passed for c in ctx.roundtrip)}/{len(ctx.roundtrip)} "
          "export read-backs passed")
    print("\n".join(ctx.release.summary_lines()))
    print(f"input: {', '.join(asm.input_names)}; output: {', '.join(asm.output_names)}")
    print(f"wrote {len(ctx.files) + 2} files to {out} in {ctx.timings['total']:.1f} s")
