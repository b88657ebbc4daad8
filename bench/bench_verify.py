"""Speed and memory of FEA verification (issue 4).

Measures, on this machine:

1. ``springcad verify CONFIG`` from a cold start (a fresh Python process:
   imports, design, convergence study, correction loop, 3D factor, cam contact
   sweep, .vtu and PNG outputs): wall time and peak resident memory, and the
   contact sweep's own time and result.
2. The same quadratic-tet meshes solved by scikit-fem (assembly, PARDISO
   solve, stress recovery) and by CalculiX ``ccx`` (the whole process):
   wall times, their ratio, and the agreement of K and peak stress.

Usage::

    python bench/bench_verify.py [--config templates/default.toml] [--json out.json]
                                 [--cold-only]

Prints a table; ``--json`` also writes the numbers. Peak memory is the
maximum resident set size (``getrusage``) of the measured process.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def bench_cold_verify(config: Path) -> dict:
    """``springcad verify`` in a fresh process: wall time, peak RSS, key results."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "verify"
        cmd = [sys.executable, "-m", "springcad", "verify", str(config), "--out", str(out),
               "--quiet"]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=_env(), capture_output=True, text=True)
        wall = time.perf_counter() - t0
        peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        if proc.returncode not in (0, 1):
            raise SystemExit(f"springcad verify failed:\n{proc.stderr}")
        doc = json.loads((out / "fea.json").read_text())
    springs = {}
    for name, s in doc["springs"].items():
        springs[name] = {k: s[k] for k in (
            "stiffness_fea_Nm_per_rad", "stiffness_beam_original_Nm_per_rad",
            "target_stiffness_Nm_per_rad", "error_vs_target_pct", "discretisation_error_pct",
            "peak_von_mises_MPa", "peak_von_mises_error_pct", "peak_region", "yield_margin",
            "dofs", "dofs_3d", "timings_s")}
        springs[name]["iterations"] = len(s["correction_iterations"])
        c = s.get("contact_sweep")
        if c is not None:
            springs[name]["contact_sweep"] = {
                "time_s": c["timings_s"]["total"], "dofs": c["dofs"],
                "steps_per_direction": c["steps_per_direction"],
                "small_angle_vs_linear_pct": c["small_angle_vs_linear_pct"],
                "torque_at_max_Nm": {k: v[-1]["torque_Nm"] for k, v in c["torque_angle"].items()},
                "flags": [f["code"] for f in c["flags"]]}
        springs[name]["first_error_vs_target_pct"] = \
            s["correction_iterations"][0]["error_vs_target_pct"]
    return {"command": " ".join(["springcad"] + cmd[3:]), "exit_status": proc.returncode,
            "wall_s": wall, "peak_rss_MB": peak_kb / 1024.0, "springs": springs}


def compare_solvers(config: Path, levels=(0, 1, 2)) -> dict:
    """scikit-fem vs CalculiX on the same 3D meshes (run in this process)."""
    sys.path.insert(0, str(ROOT))
    from springcad.config import load_job
    from springcad.design.job import design_job

    from fea.calculix import cross_check
    from fea.geometry import sector_geometry
    from fea.mesh import fea_mesh_3d, mesh_face_levels
    from fea.problem import LoadCase, solver_material
    from fea.solve import _pardiso
    from fea.mesh_size import DEFAULT_SIZE

    design = design_job(load_job(config))
    spring = next(iter(design.springs.values()))
    g = sector_geometry(spring)
    mat = solver_material(spring.material)
    faces = mesh_face_levels(g, DEFAULT_SIZE, max(levels) + 1)
    _pardiso(2)  # library start-up is not solver time
    rows = []
    for k in levels:
        fm = fea_mesh_3d(faces[k], g, 2 ** k, k)
        cc = cross_check(fm, mat, LoadCase(), spring.max_deflection_rad)
        rows.append(cc.to_dict())
    return {"spring": spring.name, "rows": rows,
            "peak_rss_MB_skfem_process": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "peak_rss_MB_ccx": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", type=Path, default=ROOT / "templates" / "default.toml")
    ap.add_argument("--json", type=Path, default=None, help="also write the numbers here")
    ap.add_argument("--compare-only", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--cold-only", action="store_true",
                    help="only the cold verify (skip the scikit-fem vs CalculiX comparison)")
    args = ap.parse_args(argv)
    if args.compare_only:
        print(json.dumps(compare_solvers(args.config)))
        return 0
    cold = bench_cold_verify(args.config)
    comp = None
    if not args.cold_only:
        proc = subprocess.run([sys.executable, __file__, "--config", str(args.config),
                               "--compare-only"], env=_env(), capture_output=True, text=True)
        if proc.returncode != 0:
            raise SystemExit(f"solver comparison failed:\n{proc.stderr}")
        comp = json.loads(proc.stdout.strip().splitlines()[-1])
    result = {"machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                          "platform": platform.platform()},
              "cold_verify": cold, "skfem_vs_calculix": comp}
    print(f"cold start: {cold['command']}")
    print(f"  wall {cold['wall_s']:.1f} s, peak RSS {cold['peak_rss_MB']:.0f} MB, "
          f"exit {cold['exit_status']}")
    for name, s in cold["springs"].items():
        print(f"  {name}: K_fea {s['stiffness_fea_Nm_per_rad']:.2f} (beam "
              f"{s['stiffness_beam_original_Nm_per_rad']:.2f}, target "
              f"{s['target_stiffness_Nm_per_rad']:.2f}) N*m/rad, first error "
              f"{s['first_error_vs_target_pct']:+.2f} %, final {s['error_vs_target_pct']:+.3f} %, "
              f"disc. error {s['discretisation_error_pct']:.3f} %, {s['iterations']} iteration(s); "
              f"peak {s['peak_von_mises_MPa']:.0f} MPa +-{s['peak_von_mises_error_pct']:.2f} % "
              f"({s['peak_region']}), margin {s['yield_margin']:.3f}")
        c = s.get("contact_sweep")
        if c:
            print(f"    contact sweep: {c['time_s']:.1f} s ({c['dofs']} DOFs, "
                  f"{c['steps_per_direction']} steps per direction), small-angle K vs linear "
                  + ", ".join(f"{k} {v:+.2f} %" for k, v in c["small_angle_vs_linear_pct"].items())
                  + ", torque at max " + ", ".join(f"{k} {v:.2f} N*m"
                                                   for k, v in c["torque_at_max_Nm"].items())
                  + f", flags: {', '.join(c['flags']) or 'none'}")
    if comp is None:
        if args.json:
            args.json.write_text(json.dumps(result, indent=2) + "\n")
        return 0
    print(f"scikit-fem vs CalculiX, same quadratic-tet meshes ({comp['spring']} sector):")
    print(f"  {'DOFs':>8} {'skfem s':>8} {'ccx s':>8} {'ratio':>6} {'dK rel':>9} {'dpeak':>7}")
    for r in comp["rows"]:
        print(f"  {r['dofs']:8d} {r['time_skfem_s']:8.2f} {r['time_ccx_s']:8.2f} "
              f"{r['time_ratio_skfem_over_ccx']:6.2f} {r['stiffness_rel_diff']:9.1e} "
              f"{100 * r['peak_rel_diff']:6.2f}%")
    print(f"  peak RSS: scikit-fem process {comp['peak_rss_MB_skfem_process']:.0f} MB, "
          f"ccx {comp['peak_rss_MB_ccx']:.0f} MB")
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
