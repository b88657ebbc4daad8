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

from pathlib import Path

import springcad.api as sc
from springcad.cli.progress import ProgressBar
from springcad.cli.synthesize import add_dask_options, dask_options
from springcad.options import EXPLORE


def register(sub):
    g = EXPLORE
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
    summary = sc.explore(args.out, stiffness_Nm_per_rad=args.stiffness_Nm_per_rad,
                         deflection_rad=args.deflection_rad, max_disks=args.max_disks,
                         envelope_radius_mm=args.envelope_radius_mm,
                         thickness_mm=args.thickness_mm, contact_radius_mm=args.contact_radius_mm,
                         material=args.material, stress_concentration=args.stress_concentration,
                         **dask_options(args), progress=ProgressBar())
    rows = [("disks", "feasible", "max deflection rad", "max peak torque N*m")]
    for e in summary["per_n_disks"]:
        rows.append((str(e["n_disks"]), str(e["feasible"]),
                     "-" if e["max_deflection_rad"] is None else f"{e['max_deflection_rad']:.3f}",
                     "-" if e["max_peak_torque_Nm"] is None else f"{e['max_peak_torque_Nm']:.1f}"))
    w = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.rjust(k) for c, k in zip(r, w)))
    stats = summary["sweep"]
    print(f"{summary['n_feasible']} of {summary['n_candidates']} stacks feasible; "
          f"{stats['evaluated_candidates']} evaluated in {stats['wall_s']:.1f} s on "
          f"{stats['workers']} worker(s) ({stats['candidates_per_s']:,.0f}/s)")
    print(f"wrote {args.out}/region.parquet, pareto_*.parquet, region.png, pareto_mass.png, "
          "pareto_energy.png, explore.json")
    return 0
