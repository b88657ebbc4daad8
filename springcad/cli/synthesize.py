"""``springcad synthesize REQUIREMENTS.toml``: the best stack for a requirement.

Enumerates every stack of the requirement's design space, screens them with
the closed-form design on a Dask cluster (a local one by default), ranks the
feasible ones by the objective and says why each infeasible family fails, gives
the best ones the full design and the top ones ``springcad build``'s FEA and
geometry checks, and writes the winner (the best that passed) as a job config that
``springcad build`` accepts.

Writes ``DIR/parts/*.parquet`` (every candidate; a rerun resumes), ``DIR/synthesis.json``
and ``DIR/winner.toml`` (``DIR/closest.toml`` when every verified finalist failed). Exit status: 0 a winner that passed (or skipped) FEA,
1 no feasible stack or the FEA or build checks failed every verified finalist (the report is
still written), 2 bad input.
"""

from __future__ import annotations

from pathlib import Path

import springcad.api as sc
from springcad.cli.common import default_out
from springcad.cli.progress import ProgressBar
from springcad.options import SYNTHESIS
from springcad.units import G_PER_KG


def add_dask_options(p) -> None:
    """--scheduler / --workers / --batch-size / --restart (shared with ``explore``)."""
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on an existing Dask cluster (e.g. tcp://host:8786); default: a "
                        "local cluster with one worker process per core")
    p.add_argument("--workers", type=int, default=None,
                   help="local cluster workers (default: every core)")
    p.add_argument("--batch-size", type=int, default=SYNTHESIS.batch_size,
                   help="candidates per Dask task and per Parquet part (default %(default)s)")
    p.add_argument("--restart", action="store_true",
                   help="discard the parts of an earlier run in DIR instead of resuming it")


def dask_options(args) -> dict:
    """The Dask options as keyword arguments of ``sc.synthesize`` and ``sc.explore``."""
    return {"scheduler": args.scheduler, "workers": args.workers,
            "batch_size": args.batch_size, "restart": args.restart}


def register(sub):
    p = sub.add_parser("synthesize", help="search every stack for the best one meeting a "
                                          "requirement; write the winner's job config")
    p.add_argument("requirements", type=Path, help="requirements TOML (see templates/requirements_*.toml)")
    p.add_argument("--out", type=Path, default=None,
                   help="run folder (default outputs/<requirements name>/); an interrupted "
                        "run in it is resumed")
    add_dask_options(p)
    p.add_argument("--finalists", type=int, default=SYNTHESIS.finalists,
                   help="screened stacks given the full design per round, best first; while "
                        "none passes, the next round goes further down (default %(default)s)")
    p.add_argument("--max-finalists", type=int, default=SYNTHESIS.max_finalists,
                   help="most screened stacks given the full design in all (default %(default)s)")
    p.add_argument("--verify-top", type=int, default=SYNTHESIS.verify_top,
                   help="full-design-feasible finalists given the FEA and checks of "
                        "`springcad build`, best first; the winner is the first that passes "
                        "(default %(default)s)")
    p.add_argument("--no-verify", action="store_true",
                   help="skip the FEA and build checks of the finalists")
    p.add_argument("--fea-model", choices=("2d", "2d3d"), default=SYNTHESIS.fea_model,
                   help="FEA model of the finalists (default 2d3d: build's; 2d: plane stress "
                        "only, faster)")
    p.set_defaults(func=run)


def run(args) -> int:
    from springcad.report.synthesis_text import format_family_report, summary_table

    out = args.out or default_out(args.requirements)
    result = sc.synthesize(args.requirements, out, **dask_options(args),
                           finalists=args.finalists, max_finalists=args.max_finalists,
                           verify_top=args.verify_top, verify=not args.no_verify,
                           fea_model=args.fea_model, progress=ProgressBar())
    print(summary_table(result))
    failed = [f for f in result.finalists if not f["ok"]]
    if failed:
        print(f"\n{len(failed)} of {len(result.finalists)} finalists failed the full design:")
        for f in failed:
            print(f"  candidate {f['cid']} ({f['failure']}): {f['error'][:300]}")
    print()
    print(format_family_report(result.families, result.requirements.objective_column))
    print()
    if result.winner is not None:
        w = result.winner
        full = next(f for f in result.finalists if f["cid"] == int(w["cid"]))
        fea = result.verifications.get(int(w["cid"]), {})
        built = (f" ({G_PER_KG * fea['mass_kg']:.1f} g with the FEA-corrected widths build makes)"
                 if "mass_kg" in fea else "")
        print(f"winner: candidate {w['cid']} ({w['family']}, input {w['input']}), "
              f"{G_PER_KG * full['mass_kg']:.1f} g{built}, {full['axial_length_mm']:.1f} mm long, "
              f"R {full['envelope_radius_mm']:.2f} mm: {result.winner_status}")
        name = result.winner_file
        print(f"wrote {out / name} (springcad build {out / name})" if result.ok else
              f"no verified finalist passed: the closest is written to {out / name}; it "
              "fails as said above")
    else:
        print(f"no winner: {result.winner_status}")
    print(f"wrote {out / 'synthesis.json'}")
    return 0 if result.ok else 1
