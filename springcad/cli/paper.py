"""``springcad paper --out DIR``: validation against the paper's seven configurations."""

from __future__ import annotations

from pathlib import Path

import springcad.api as sc
from springcad.cli.progress import console
from springcad.report.outdir import atomic_output_dir, check_output_dir
from springcad.report.paper_report import write_paper_report


def register(sub):
    p = sub.add_parser("paper", help="predict the paper's Table I configurations and explain the residual")
    p.add_argument("--out", type=Path, default=Path("outputs/paper"), help="output folder")
    p.add_argument("--data", type=Path, default=None, help="folder with the paper's CSV tables")
    p.add_argument("--templates", type=Path, default=None, help="folder with paper_*.toml")
    p.add_argument("--no-fea", action="store_true", help="beam theory only (fast)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output folder")
    p.set_defaults(func=run)


def run(args) -> int:
    inputs = [args.data, args.templates]
    check_output_dir(args.out, args.overwrite, inputs=inputs)  # before ~30 s of FEA
    v = sc.validate_paper(args.data, args.templates, use_fea=not args.no_fea,
                       progress=console(indent="  "))
    with atomic_output_dir(args.out, overwrite=args.overwrite, inputs=inputs) as tmp:
        write_paper_report(v, tmp)
    s = v.to_dict()["summary"]
    print(f"mean |error| before {s['mean_abs_error_before_pct']:.2f} %, after "
          f"{s['mean_abs_error_after_pct']:.2f} % (leave-one-out); worst "
          f"{s['worst_abs_error_before_pct']:.2f} % -> {s['worst_abs_error_after_pct']:.2f} %")
    print(f"wrote {args.out / 'validation.md'}")
    print(f"report: {args.out / 'report.html'} (open it in a web browser)")
    return 0
