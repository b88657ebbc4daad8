"""What each convergence level and the 3D factor's recomputation buy (issue 22, item 4).

Usage: ``python bench/convergence_levels.py [TEMPLATE.toml ...]`` (default: the default job
and the paper's S1 and S2).

For each spring of each job, as designed (no correction loop), it solves the 2D levels
0..3 and the 3D factor (:func:`fea.study.run_model`) and prints:

* the Richardson extrapolation of K and of the peak von Mises stress over levels 1..3 (what a
  verification reports) and over levels 0..2 (the finest level dropped), the change between
  the two and each one's stated error: dropping the level is acceptable only when the change
  is < 0.1 % and within the coarser study's stated error;
* the 3D/2D factors of K and stress at the design and at the width scale one correction step
  changes it by (x1.009, the default job's and S1's step): what recomputing the factor at the
  corrected geometry buys against carrying it;
* the CPU time of the finest 2D level and of the 3D factor.

Units: N*m/rad, MPa, %, s.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

#: one correction step's width change (default job and paper S1: x1.0091, x0.9910)
STEP_SCALE = 1.009


def _pct(a: float, b: float) -> str:
    return f"{100 * (b / a - 1):+.4f} %"


def main(paths) -> None:
    from fea.convergence import FORMAL_ORDER, richardson
    from fea.problem import solver_material
    from fea.study import VerifyOptions, run_model
    from springcad.config import load_job
    from springcad.design.job import design_job
    from springcad.design.resize import with_width_scale

    options = VerifyOptions(keep_fields=False)
    for path in paths:
        job = design_job(load_job(path))
        for name, design in job.springs.items():
            material = solver_material(design.material)
            t = time.process_time()
            run = run_model(design, material, options, True)
            cpu_run = time.process_time() - t
            base = run.base2d
            K = [r.stiffness_Nmm_per_rad / 1e3 for r in base]
            S = [r.peak_von_mises_MPa for r in base]
            cpu_fine = sum(base[-1].timings_s.values())
            print(f"{Path(path).name} {name}: 2D levels "
                  + ", ".join(f"{r.level}: {r.dofs} DOFs K {k:.5f} S {s:.2f}"
                              for r, k, s in zip(base, K, S)))
            for what, vals, order in (("K", K, FORMAL_ORDER["stiffness"]),
                                      ("peak stress", S, FORMAL_ORDER["stress"])):
                fine, coarse = richardson(vals[1:4], order), richardson(vals[0:3], order)
                print(f"  {what:11s} levels 1..3: {fine.extrapolated:.5f} (error "
                      f"{100 * fine.error:.4f} %, {fine.behaviour}); levels 0..2: "
                      f"{coarse.extrapolated:.5f} (error {100 * coarse.error:.4f} %, "
                      f"{coarse.behaviour}); dropping level 3 moves it "
                      f"{_pct(fine.extrapolated, coarse.extrapolated)}")
            t = time.process_time()
            moved = run_model(with_width_scale(design, design.width_scale * STEP_SCALE),
                              material, options, True)
            cpu_moved = time.process_time() - t
            print(f"  3D factor K {run.factor_K:.6f} (error {100 * run.factor_K_error:.4f} %), "
                  f"at width x{STEP_SCALE}: {moved.factor_K:.6f} "
                  f"({_pct(run.factor_K, moved.factor_K)})")
            print(f"  3D factor stress {run.factor_stress:.6f} (error "
                  f"{100 * run.factor_stress_error:.4f} %), at width x{STEP_SCALE}: "
                  f"{moved.factor_stress:.6f} ({_pct(run.factor_stress, moved.factor_stress)})")
            cpu_3d = sum(sum(r.timings_s.values()) for r in run.check3d)
            print(f"  wall s (load-dependent): finest 2D level {cpu_fine:.2f}, 3D factor "
                  f"{cpu_3d:.2f}; CPU s of the study {cpu_run:.2f} / {cpu_moved:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:] or [ROOT / "templates" / t for t in
                          ("default.toml", "paper_S1.toml", "paper_S2.toml")])
