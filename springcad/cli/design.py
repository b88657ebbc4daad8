"""``springcad design CONFIG [--out DIR]``: design math only, writes design.json."""

from __future__ import annotations

import sys
from pathlib import Path

import springcad.api as sc
from springcad.cli.common import add_cache_flag, cache_of, default_out, warn
from springcad.cli.progress import console
from springcad.report.jsonio import write_json
from springcad.report.outdir import atomic_output_dir, check_output_dir


def register(sub):
    p = sub.add_parser("design", help="design springs and the stack; write design.json")
    p.add_argument("config", type=Path, help="job TOML (see templates/)")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default outputs/<config name>/)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    add_cache_flag(p)
    p.set_defaults(func=run)


def run(args) -> int:
    out = args.out or default_out(args.config)
    job = sc.load(args.config)
    check_output_dir(out, args.overwrite, inputs=[args.config])
    # progress on a terminal only: a refusal is one line on a redirected stderr
    progress = console() if sys.stderr.isatty() else None
    design = sc.design_job(job, cache=cache_of(args), progress=progress)
    warn("design", design.warnings)
    with atomic_output_dir(out, overwrite=args.overwrite, inputs=[args.config]) as tmp:
        write_json(tmp / "design.json", design.to_dict())
    print(design.summary())
    print(f"\nwrote {out / 'design.json'}")
    return 0
