"""``springcad explore``: the design-space map (paper Fig. 8) and its Pareto fronts.

Sweeps a grid of stack targets (stiffness x deflection) for stacks of 1 ... N
identical disks over thickness and contact radius, on Dask like ``synthesize``
(resumable), then writes ``DIR/parts/*.parquet`` (every candidate),
``region.parquet`` (reachable peak torque per number of disks and deflection,
with the best energy density and specific energy), ``pareto_mass.parquet``,
``pareto_energy.parquet``, ``region.png``, ``pareto_mass.png``,
``pareto_energy.png`` and ``explore.json``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from springcad.cli.synthesize import add_dask_options, check_dask_options


def _range(text: str):
    from springcad.errors import SpringcadError

    try:
        lo, hi, n = text.split(":")
        lo, hi, n = float(lo), float(hi), int(n)
    except ValueError as err:
        raise SpringcadError(f"range '{text}': expected MIN:MAX:COUNT, e.g. 5:500:24") from err
    if not (0 < lo < hi and n >= 2):
        raise SpringcadError(f"range '{text}': needs 0 < MIN < MAX and COUNT >= 2")
    return lo, hi, n


def register(sub):
    from springcad.synthesis.explore import ExploreGrid

    g = ExploreGrid()
    p = sub.add_parser("explore", help="map reachable peak torque vs deflection for one disk "
                                       "and stacks (Fig. 8); Pareto fronts; Parquet + PNG")
    p.add_argument("--out", type=Path, default=Path("outputs") / "explore",
                   help="run folder (default outputs/explore/); an interrupted run is resumed")
    p.add_argument("--stiffness-Nm-per-rad", default="{}:{}:{}".format(*g.stiffness_Nm_per_rad),
                   help="stack stiffness grid MIN:MAX:COUNT, log-spaced (default %(default)s)")
    p.add_argument("--deflection-rad", default="{}:{}:{}".format(*g.deflection_rad),
                   help="stack deflection grid MIN:MAX:COUNT, log-spaced (default %(default)s)")
    p.add_argument("--max-disks", type=int, default=g.max_disks, help="stacks of 1..N disks")
    p.add_argument("--envelope-radius-mm", type=float, default=g.envelope_radius_mm,
                   help="envelope radius, bushing included (default %(default)s mm: 4xS1)")
    p.add_argument("--thickness-mm", type=float, nargs="+", default=list(g.thickness_mm))
    p.add_argument("--contact-radius-mm", type=float, nargs="+", default=list(g.contact_radius_mm))
    p.add_argument("--material", default=g.material, help="built-in material (default 420_ht)")
    p.add_argument("--stress-concentration", type=float, default=g.stress_concentration,
                   help="first beam stress = yield / this (default 1344/912: the paper's 912 "
                        "MPa); lowered where the predicted peak would exceed the yield")
    add_dask_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import hashlib
    import json

    from springcad.cli.progress import ProgressBar
    from springcad.errors import SpringcadError
    from springcad.report.jsonio import write_json
    from springcad.report.synthesis_plots import (plot_energy_front, plot_mass_fronts,
                                                  plot_region, write_parquet)
    from springcad.synthesis.explore import (ExploreGrid, energy_front, mass_fronts,
                                             reachable_region)
    from springcad.synthesis.runner import dask_client
    from springcad.synthesis.store import ResultStore

    check_dask_options(args)
    if args.max_disks < 1 or args.max_disks > 20:
        raise SpringcadError(f"--max-disks {args.max_disks}: must be 1-20")
    if args.stress_concentration < 1.0:
        raise SpringcadError(f"--stress-concentration {args.stress_concentration}: must be >= 1")
    if min(args.thickness_mm + args.contact_radius_mm + [args.envelope_radius_mm]) <= 0:
        raise SpringcadError("--thickness-mm, --contact-radius-mm and --envelope-radius-mm "
                             "must be positive")
    grid = ExploreGrid(stiffness_Nm_per_rad=_range(args.stiffness_Nm_per_rad),
                       deflection_rad=_range(args.deflection_rad), max_disks=args.max_disks,
                       envelope_radius_mm=args.envelope_radius_mm,
                       thickness_mm=tuple(args.thickness_mm),
                       contact_radius_mm=tuple(args.contact_radius_mm), material=args.material,
                       stress_concentration=args.stress_concentration)
    space = grid.space()
    fingerprint = hashlib.sha256(json.dumps(grid.__dict__, sort_keys=True,
                                            default=str).encode()).hexdigest()[:16]
    out = args.out
    store = ResultStore(out, fingerprint, space.total, args.batch_size,
                        overwrite=args.restart, resume=not args.restart)
    print(f"{space.total} candidate stacks in {store.n_batches} batches "
          f"({len(store.pending_batches())} to evaluate)", file=sys.stderr, flush=True)
    with dask_client(args.scheduler, args.workers) as client:
        from springcad.synthesis.runner import run_sweep

        stats = run_sweep(space, store, client, ProgressBar())
    cols = store.read()
    region = reachable_region(cols)
    fronts = mass_fronts(cols)
    efront = energy_front(cols)
    write_parquet(out / "region.parquet", region)
    write_parquet(out / "pareto_mass.parquet", fronts)
    write_parquet(out / "pareto_energy.parquet", efront)
    plot_region(region, out / "region.png",
                f"Reachable region, {grid.material}, R {grid.envelope_radius_mm:g} mm envelope")
    plot_mass_fronts(fronts, out / "pareto_mass.png")
    plot_energy_front(cols, efront, out / "pareto_energy.png")
    n_feasible = int(cols["feasible"].sum())
    summary = {"schema": "springcad.explore/1", "grid": grid.__dict__, "sweep": stats.to_dict(),
               "n_candidates": len(cols["cid"]), "n_feasible": n_feasible,
               "per_n_disks": [
                   {"n_disks": int(n),
                    "feasible": int((cols["feasible"] & (cols["n_disks"] == n)).sum()),
                    "max_deflection_rad": float(region["deflection_rad"][region["n_disks"] == n].max())
                    if (region["n_disks"] == n).any() else None,
                    "max_peak_torque_Nm": float(region["max_peak_torque_Nm"][region["n_disks"] == n].max())
                    if (region["n_disks"] == n).any() else None}
                   for n in range(1, grid.max_disks + 1)]}
    write_json(out / "explore.json", summary)
    rows = [("disks", "feasible", "max deflection rad", "max peak torque N*m")]
    for e in summary["per_n_disks"]:
        rows.append((str(e["n_disks"]), str(e["feasible"]),
                     "-" if e["max_deflection_rad"] is None else f"{e['max_deflection_rad']:.3f}",
                     "-" if e["max_peak_torque_Nm"] is None else f"{e['max_peak_torque_Nm']:.1f}"))
    w = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.rjust(k) for c, k in zip(r, w)))
    print(f"{n_feasible} of {len(cols['cid'])} stacks feasible; "
          f"{stats.evaluated_candidates} evaluated in {stats.wall_s:.1f} s on {stats.workers} "
          f"worker(s) ({stats.candidates_per_s:,.0f}/s)")
    print(f"wrote {out}/region.parquet, pareto_*.parquet, region.png, pareto_mass.png, "
          "pareto_energy.png, explore.json")
    return 0
