"""Re-fit the design-side stress model to FEA and write ``springcad/data/stress_calibration.json``.

The calibration set: the springs of the bundled templates (paper S1 and S2, the
default) and three more geometries (the default's first 5 mm layout, a thin, soft
spring and a thick one with fewer flexures), each at root flares 0, 0.1, 0.2, 0.3,
solved as the verification solves them (2D levels extrapolated x the 3D factor,
:func:`fea.calibrate.calibration_row`). About 5-8 minutes on 2 cores.

Run: python bench/calibrate_stress.py [--check] [--refit]   (--check: fit and report, write
nothing; --refit: fit the shipped rows again, no FEA)
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import tomllib
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "springcad" / "data" / "stress_calibration.json"

#: extra geometries: (label, template, overrides of its first spring)
EXTRA = (
    ("thin_soft", "default.toml", {"thickness_mm": 3.0, "target_stiffness_Nm_per_rad": 60.0,
                                   "max_deflection_deg": 18.0}),
    ("thick_few", "default.toml", {"thickness_mm": 6.0, "target_stiffness_Nm_per_rad": 250.0,
                                   "max_deflection_deg": 12.0}),
)


def calibration_designs(flare_free: bool = True, labels=None) -> dict:
    """label -> SpringDesign of every calibration geometry (root flare 0).

    ``labels``: only these geometries (e.g. ``("paper_S2",)``; None: all). Each design
    takes seconds to tens of seconds (the default duty's sizing), so a caller that solves
    one case designs only that one.
    """
    from springcad.config import job_from_dict
    from springcad.design.job import design_job
    from springcad.design.resize import with_root

    out = {}
    # the default's 5 mm layout as first calibrated (2026-11-23), pinned: a serpentine
    # geometry; the default template itself (12 mm, straight flexures) is a case too
    default_5mm = {"n_flexures": 29, "contact_radius_mm": 5.581245263275046,
                   "tip_radius_mm": 0.30170661466728743, "thickness_mm": 5.0}
    cases = [(name, name, {}) for name in ("paper_S1.toml", "paper_S2.toml", "default.toml")]
    cases.append(("default_5mm", "default.toml", default_5mm))
    for label, template, over in [*cases, *EXTRA]:
        if labels is not None and label.removesuffix(".toml") not in labels:
            continue
        data = tomllib.loads((ROOT / "templates" / template).read_text())
        data = copy.deepcopy(data)
        data.pop("duty", None)  # geometries sized for yield alone, as calibrated
        first = next(iter(data["springs"]))
        data["springs"][first].update(over)
        data["stack"]["sequence"] = [first]
        job = job_from_dict(data, label)
        # explain=False: the same spring, without the default duty's advice text (a search
        # of up to a minute the geometry does not need)
        spring = next(iter(design_job(job, explain=False).springs.values()))
        out[label.removesuffix(".toml")] = with_root(spring, 0.0)
    return out


def main(argv=None) -> int:
    from fea.calibrate import calibrate, calibration_rows
    from springcad.design.stress import flank_by_shape, predict_row

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="fit and report, write nothing")
    ap.add_argument("--refit", action="store_true",
                    help="fit the shipped rows again (no FEA), e.g. after a change of the fit")
    args = ap.parse_args(argv)

    def progress(msg, frac):
        print(f"[{100 * frac:3.0f} %] {msg}", file=sys.stderr, flush=True)

    if args.refit:
        rows = json.loads(OUT.read_text())["rows"]
    else:
        rows = calibration_rows(calibration_designs(), progress=progress)
    cal = calibrate(rows)
    by_shape = flank_by_shape(rows)
    print(json.dumps({**cal.to_dict(), "flank_by_shape": by_shape}, indent=2))
    print(f"{'case':12s} {'flare':>5s} {'FEA peak':>9s} {'model':>7s} {'err %':>6s}  FEA region")
    for r in rows:
        m = predict_row(r, replace(cal, **by_shape.get(r.get("flexure"), {})))
        print(f"{r['case']:12s} {r['root_flare']:5.2f} {r['fea_peak_MPa']:9.0f} {m:7.0f} "
              f"{100 * (m / r['fea_peak_MPa'] - 1):+6.1f}  {r['fea_peak_region']}")
    if not args.check:
        coefficients = {k: v for k, v in cal.to_dict().items()}
        OUT.write_text(json.dumps({"coefficients": coefficients,
                                   "flank_by_shape": flank_by_shape(rows),
                                   "rows": rows}, indent=1) + "\n")
        print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
