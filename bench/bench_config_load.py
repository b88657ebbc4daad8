"""Wall time of loading and validating a job config (target < 10 ms a load).

Moved out of tests/test_config_schema.py (a timed assertion fails under load on a shared
machine); the test keeps what loading does and imports, this script keeps how fast.

Run: python bench/bench_config_load.py [TEMPLATE ...]   (default: paper_S2_3xS1)
"""

import sys
import time
from pathlib import Path

from springcad.config import load_job

ROOT = Path(__file__).resolve().parents[1]
TARGET_S = 0.01
REPEATS = 50


def main(names: list[str]) -> int:
    worst = 0.0
    for name in names or ["paper_S2_3xS1"]:
        path = ROOT / "templates" / f"{name}.toml"
        load_job(path)  # first load: imports and the material table, not timed
        t0 = time.perf_counter()
        for _ in range(REPEATS):
            load_job(path)
        each = (time.perf_counter() - t0) / REPEATS
        worst = max(worst, each)
        print(f"{name:28s} {each * 1e3:.2f} ms a load ({REPEATS} loads)")
    ok = worst < TARGET_S
    print(f"slowest: {worst * 1e3:.2f} ms (target < {TARGET_S * 1e3:.0f} ms): "
          f"{'PASS' if ok else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
