"""Wall time of `springcad design` on every template, start-up included (target < 2 s each).

Run: python bench/bench_design.py
"""

import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for cfg in sorted((ROOT / "templates").glob("*.toml")):
            if "[springs." not in cfg.read_text():  # the drawing title block is not a job
                continue
            times = []
            for i in range(3):
                t = time.perf_counter()
                subprocess.run([sys.executable, "-m", "springcad", "design", str(cfg), "--out",
                                f"{tmp}/{cfg.stem}-{i}"], check=True, capture_output=True)
                times.append(time.perf_counter() - t)
            worst = max(worst, max(times))
            print(f"{cfg.name:28s} best {min(times):.2f} s  worst {max(times):.2f} s")
    print(f"slowest template: {worst:.2f} s (target < 2 s): {'PASS' if worst < 2 else 'FAIL'}")
    return 0 if worst < 2 else 1


if __name__ == "__main__":
    sys.exit(main())
