"""Monte Carlo of the fit's confidence intervals against known truth.

Run: ``PYTHONPATH=. python bench/fit_coverage.py [--n 100] [--only NAME ...] [--seed0 20000]``,
or ``... --heldout [--only NAME ...]`` for records of the held-out cases of
``bench/fit_heldout.py`` (its own simulator and protocols: sine sweeps, cosine
ramps, linear ramps at two or three speeds), ``--n`` seeds each from ``--seed0``.

For each case (an effect combination on a short protocol), ``--n`` seeded
records are simulated with :func:`springcad.fit.bench.simulate` and fitted
with the residual loop; per reported parameter it prints

* ``cover``: the share of records whose 95 % interval holds the truth (over
  the records that report the parameter on its own, not in a confounded group);
* ``n``: how many records reported it;
* ``bias/se``: the mean of (estimate - truth)/se: bias from model mismatch;
* ``sd(z)``: the spread of (estimate - truth)/se, 1 when the standard errors
  are right (larger: the intervals are too tight);
* ``med width``: the median interval width;
* ``named ok``: records whose named effect set was exactly the truth.

Nothing is asserted: this script measures. Units: N·m, rad, s.
"""

from __future__ import annotations

import argparse
import sys
import time
import zlib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from springcad.fit.bench import BenchSpring, Protocol, SineSweep, simulate  # noqa: E402
from springcad.fit.loop import run_loop  # noqa: E402
from springcad.fit.segment import segment  # noqa: E402
from springcad.fit.signals import make_signals  # noqa: E402

K = 40.0
#: a short staircase (about 4500 samples at 500 Hz), as in tests/fit/test_fit_validity.py
SHORT = Protocol(amplitudes_rad=(0.1, 0.2, 0.3, 0.4), ramp_s=0.5)
#: linear ramps at two speeds: friction and a lag come apart
TWO_RATES = Protocol(amplitudes_rad=(0.1, 0.2, 0.3, 0.4), rates_rad_per_s=(0.6, 0.2),
                     profile="linear")
#: stepped sines at two amplitudes and three frequencies (about 8000 samples)
SWEEP = SineSweep(amplitudes_rad=(0.15, 0.3), frequencies_hz=(0.4, 1.0, 2.0), cycles=2)

#: name: (spring, protocol, true values of the reported keys, effects that must be named)
CASES = {
    "friction": (BenchSpring(K, friction_torque_Nm=0.15), SHORT,
                 {"friction_torque_Nm": 0.15}, {"hysteresis"}),
    "lag": (BenchSpring(K, lag_s=0.015), SHORT, {"lag_s": 0.015}, {"time_lag"}),
    "friction_lag_two_rates": (BenchSpring(K, friction_torque_Nm=0.15, lag_s=0.015), TWO_RATES,
                               {"friction_torque_Nm": 0.15, "lag_s": 0.015},
                               {"hysteresis", "time_lag"}),
    "friction_lag_stiffening_sweep": (
        BenchSpring(K, friction_torque_Nm=0.1, lag_s=0.01, cubic_stiffness_Nm_per_rad3=20.0),
        SWEEP, {"friction_torque_Nm": 0.1, "lag_s": 0.01, "cubic_stiffness_Nm_per_rad3": 20.0},
        {"hysteresis", "time_lag", "stiffening"}),
    "backlash_friction_drift": (
        BenchSpring(K, backlash_rad=0.04, friction_torque_Nm=0.15, drift_Nm_per_s=0.01), SHORT,
        {"backlash_rad": 0.04, "friction_torque_Nm": 0.15, "drift_Nm_per_s": 0.01},
        {"backlash", "hysteresis", "drift"}),
    "stiffening": (BenchSpring(K, cubic_stiffness_Nm_per_rad3=7.6), SHORT,
                   {"cubic_stiffness_Nm_per_rad3": 7.6}, {"stiffening"}),
    "hysteresis_presliding": (BenchSpring(K, friction_torque_Nm=0.2, presliding_rad=0.02), SHORT,
                              {"friction_torque_Nm": 0.2, "presliding_rad": 0.02},
                              {"hysteresis"}),
}


def _library_records(name: str, n: int, seed0: int):
    """``(record, truth, named_ok)`` of case ``name`` simulated with :mod:`springcad.fit.bench`."""
    spring, protocol, truth, effects = CASES[name]
    truth = {"stiffness_Nm_per_rad": spring.stiffness_Nm_per_rad, **truth}
    for i in range(n):
        record = simulate(spring, protocol=protocol, seed=seed0 + i).record
        yield record, truth, lambda res: set(res.identified) == effects and not res.confounded


def _heldout_records(name: str, n: int, seed0: int):
    """``(record, truth, named_ok)`` of the held-out case ``name`` (bench/fit_heldout.py)."""
    import fit_heldout

    from springcad.fit.data import make_record

    for i in range(n):
        seed = seed0 + i
        case = next((c for c in fit_heldout.cases(seed) if c.name == name), None)
        if case is None:
            raise SystemExit(f"no held-out case {name!r}; the cases are "
                             + ", ".join(c.name for c in fit_heldout.cases(seed)))
        rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
        t, theta = case.protocol
        torque, measured = fit_heldout.make(case.truth, t, theta, rng)

        def named_ok(res, accept=case.accept):
            named = set(res.identified) | {"|".join(sorted(g.effects)) for g in res.confounded}
            return frozenset(named) in accept

        yield make_record(t, torque, measured), case.truth.intervals(), named_ok


def run_case(name: str, n: int, seed0: int, heldout: bool = False) -> dict:
    records = (_heldout_records if heldout else _library_records)(name, n, seed0)
    rows: dict[str, list] = {}
    named = 0
    for record, truth, named_ok in records:
        res = run_loop(make_signals(record, segment(record)))
        named += bool(named_ok(res))
        for k, v in truth.items():
            ci = res.intervals.get(k)
            if ci is None or ci.get("confounded_with"):
                rows.setdefault(k, [])
                continue
            rows.setdefault(k, []).append((ci["value"], ci["se"], ci["ci_low"], ci["ci_high"], v))
    out = {"named": named, "n": n, "params": {}}
    for k, r in rows.items():
        if not r:
            out["params"][k] = None
            continue
        a = np.array(r)
        z = (a[:, 0] - a[:, 4]) / np.where(a[:, 1] > 0, a[:, 1], np.nan)
        out["params"][k] = {"cover": float(np.mean((a[:, 2] <= a[:, 4]) & (a[:, 4] <= a[:, 3]))),
                            "n": len(r), "bias_se": float(np.nanmean(z)),
                            "sd_z": float(np.nanstd(z)),
                            "width": float(np.median(a[:, 3] - a[:, 2]))}
    return out


#: held-out cases measured by ``--heldout`` without ``--only``: every protocol that
#: carries friction and a lag
HELDOUT_CASES = ("three_sweep", "three_rates", "sep_two_rates", "quiet_friction_lag_cos",
                 "lag_sweep", "friction_cos")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed0", type=int, default=20000)
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--heldout", action="store_true",
                    help="records of bench/fit_heldout.py's cases and simulator")
    args = ap.parse_args(argv)
    names = args.only or (list(HELDOUT_CASES) if args.heldout else list(CASES))
    print(f"{'case':<26}{'parameter':<30}{'cover':>7}{'n':>5}{'bias/se':>9}{'sd(z)':>7}"
          f"{'med width':>11}")
    for name in names:
        t0 = time.perf_counter()
        res = run_case(name, args.n, args.seed0, args.heldout)
        for k, p in res["params"].items():
            if p is None:
                print(f"{name:<26}{k:<30}{'-':>7}{0:>5}")
                continue
            print(f"{name:<26}{k:<30}{p['cover']:>7.3f}{p['n']:>5}{p['bias_se']:>9.2f}"
                  f"{p['sd_z']:>7.2f}{p['width']:>11.4g}")
        print(f"{name:<26}named ok {res['named']}/{res['n']}, "
              f"{time.perf_counter() - t0:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
