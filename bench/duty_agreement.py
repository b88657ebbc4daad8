"""Do design.json and fea.json agree on the duty's damage? (issue 21)

For every template with a ``[duty]`` table and the default at several max deflections,
design and FEA-verify the job (``sc.verify``, the build's defaults) and print, per
spring, the design side's predicted peak at theta_max (of the FEA-corrected design, as
``design.json`` states it) beside the FEA's critical point, and the two Miner sums.
A few minutes per job on 2 cores (the result cache makes a second run instant).

Run: python bench/duty_agreement.py [--default-only] [--deg 8 10 12 14] [templates ...]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cases(names, degrees, default_only):
    """(label, config dict) of every job to measure."""
    out = []
    if not default_only:
        paths = [ROOT / "templates" / n for n in names] if names else sorted(
            p for p in (ROOT / "templates").glob("*.toml")
            if "[duty]" in p.read_text() and not p.name.startswith("requirements"))
        out += [(p.stem, tomllib.loads(p.read_text())) for p in paths]
    for deg in degrees:
        data = tomllib.loads((ROOT / "templates" / "default.toml").read_text())
        data["springs"]["S1"]["max_deflection_deg"] = deg
        out.append((f"default@{deg:g}deg", data))
    return out


def measure(label, data) -> list[dict]:
    """One row per spring of the job."""
    import springcad as sc

    ver = sc.verify(data)
    rows = []
    for name, v in ver.raw.springs.items():
        d = v.design  # the FEA-corrected design (what design.json states)
        dd, fd = d.duty_check, v.duty_check
        pred = d.stress
        run = v.run
        rows.append({
            "case": label, "spring": name,
            "design_peak_MPa": d.predicted_peak_stress_MPa,
            "design_region": pred.region if pred is not None else "beam",
            "fea_peak_MPa": fd.peak_MPa if fd else v.peak_von_mises_MPa,
            "fea_where": fd.where if fd else run.peak_result.peak_region,
            "fea_2d_peak_MPa": run.study.peak_stress.extrapolated,
            "factor_3d_sigma": run.factor_stress,
            "regions_MPa": v.duty_points_MPa(),
            "design_miner": dd.miner_sum if dd else math.nan,
            "fea_miner": fd.miner_sum if fd else math.nan,
            "design_sf": dd.safety_factor if dd else math.nan,
            "fea_sf": fd.safety_factor if fd else math.nan,
            "width_scale": d.width_scale,
            "prediction": pred.to_dict() if pred is not None else None,
        })
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("templates", nargs="*", help="template file names (default: all with a duty)")
    ap.add_argument("--deg", nargs="*", type=float, default=[8, 10, 12, 14],
                    help="max deflections of the default job (deg)")
    ap.add_argument("--default-only", action="store_true")
    args = ap.parse_args(argv)
    print(f"{'case':18s} {'spr':4s} {'design':>7s} {'FEA':>7s} {'s ratio':>7s} "
          f"{'3D':>6s} {'D design':>9s} {'D FEA':>9s} {'D ratio':>7s}  design region / FEA point")
    for label, data in cases(args.templates, args.deg, args.default_only):
        t0 = time.perf_counter()
        try:
            rows = measure(label, data)
        except Exception as exc:  # a job the design or FEA refuses: say so, go on
            print(f"{label:18s} refused: {str(exc)[:300]}", flush=True)
            continue
        for r in rows:
            ratio = (r["design_miner"] / r["fea_miner"]) if r["fea_miner"] else math.nan
            print(f"{r['case']:18s} {r['spring']:4s} {r['design_peak_MPa']:7.1f} "
                  f"{r['fea_peak_MPa']:7.1f} {r['design_peak_MPa'] / r['fea_peak_MPa']:7.4f} "
                  f"{r['factor_3d_sigma']:6.4f} {r['design_miner']:9.4g} {r['fea_miner']:9.4g} "
                  f"{ratio:7.3f}  {r['design_region']} / {r['fea_where']} "
                  f"[{time.perf_counter() - t0:.0f} s]", flush=True)
            regions = ", ".join(f"{k} {v:.0f}" for k, v in r["regions_MPa"].items())
            p = r["prediction"] or {}
            print(f"{'':23s} FEA 2D {r['fea_2d_peak_MPa']:.1f}; regions: {regions}; design: "
                  f"flank {p.get('flank_MPa', math.nan):.0f}, root {p.get('root_fillet_MPa', math.nan):.0f}, "
                  f"neck {p.get('neck_fillet_MPa', math.nan):.0f}; width scale {r['width_scale']:.5f}",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
