"""Held-out evaluation of ``springcad fit``: records with known truth, scored.

Run: ``PYTHONPATH=. python bench/fit_heldout.py [--seed 7301] [--only NAME ...] [--keep DIR]``.

The records are generated here with a simulator written independently of
``springcad.fit.bench`` (its own protocols, its own friction, lag, backlash and
stiffening, its own noise), over the patterns of issue 10: library effects
alone, in pairs and in threes; structures outside the library (a hard stop,
a stiffness step mid-test, a thermal drift that settles, a ripple periodic in
angle, a torque-sensor dead band, a hum); friction and a lag on one ramp rate
(confounded) and on two rates (separable); records with no spring; unit
mistakes. Protocols: the staircase with fixed ramp times or at one or several
rates (linear or cosine ramps), sine sweeps, triangles with holds; 250 to
1000 Hz; several noise levels.

Each record is written as a CSV and fitted with the CLI (``python -m springcad
fit``, in a subprocess, with ``--no-plots``); ``fit.json`` is scored on

* ``named``: the named set (identified effects and confounded groups) is one
  the record supports (listed per case);
* ``flag``: the ``unexplained`` flag is right;
* ``conf``: a pair the record cannot separate is named as a confounded group,
  and a pair it can separate is not;
* ``ci``: the 95 % intervals cover the true values (counted over parameters;
  records with structure outside the library are not counted);
* ``valid``: no impossible quantity (negative energy loss, non-positive
  stiffness), no spring reported where there is none, unit mistakes refused
  with one message (exit status 1 or 2, no traceback).

Nothing here is used by the test suite; the seeds differ from those of the
tests. Units: N·m, rad, s.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]

# --- protocols (written here, not springcad.fit.protocols) ----------------------------------


def _ramp(a0, a1, n, shape):
    s = np.linspace(0.0, 1.0, n, endpoint=False)
    if shape == "cosine":
        s = 0.5 - 0.5 * np.cos(np.pi * s)
    return a0 + (a1 - a0) * s


def staircase(amps_deg, fs, ramp_s=None, rates_deg_s=None, shape="cosine", hold_s=0.0,
              rest_s=0.4):
    """Rest, 0 → +A → 0 → -A → 0 per amplitude (per rate), rest. Returns (t, θ)."""
    pieces = [np.zeros(int(rest_s * fs))]
    for rate in (rates_deg_s or [None]):
        for a_deg in amps_deg:
            a = math.radians(a_deg)
            d = ramp_s if rate is None else a_deg / rate
            n = max(2, int(round(d * fs)))
            for a0, a1 in ((0, a), (a, 0), (0, -a), (-a, 0)):
                pieces.append(_ramp(a0, a1, n, shape))
                if a1 != 0 and hold_s > 0:
                    pieces.append(np.full(int(hold_s * fs), a1))
    pieces.append(np.zeros(int(rest_s * fs)))
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


def sines(amps_deg, freqs, fs, cycles=3, rest_s=0.4):
    """Stepped sines faded in and out over a quarter cycle each."""
    pieces = [np.zeros(int(rest_s * fs))]
    for a_deg in amps_deg:
        for f in freqs:
            n = int(round(cycles / f * fs))
            u = np.arange(n) / fs
            d = cycles / f
            env = np.clip(np.minimum(u, d - u) / (0.25 / f), 0, 1)
            pieces.append(math.radians(a_deg) * env * np.sin(2 * np.pi * f * u))
    pieces.append(np.zeros(int(rest_s * fs)))
    th = np.concatenate(pieces)
    return np.arange(th.size) / fs, th


def triangles(amps_deg, fs, rate_deg_s, hold_s, rest_s=0.4):
    """Symmetric triangles ±A at one speed, holding at each peak."""
    return staircase(amps_deg, fs, rates_deg_s=[rate_deg_s], shape="linear", hold_s=hold_s,
                     rest_s=rest_s)


# --- the bench physics (written here, not springcad.fit.bench) -------------------------------


def deadband(th, half):
    return np.sign(th) * np.maximum(np.abs(th) - half, 0.0)


def elastoplastic_friction(th, level, presliding):
    """Friction torque: exponential approach to ±level over presliding after each turn."""
    out = np.zeros_like(th)
    f = 0.0
    d = np.diff(th, prepend=th[0])
    for i in range(th.size):
        if d[i] != 0.0:
            tgt = level if d[i] > 0 else -level
            f = tgt + (f - tgt) * math.exp(-abs(d[i]) / presliding)
        out[i] = f
    return out


@dataclass
class Truth:
    """What goes into one record; ``None``/0 fields are absent."""

    K: float = 40.0
    backlash: float = 0.0          # total width b (rad)
    friction: float = 0.0          # N·m
    presliding: float = 0.004      # rad
    lag: float = 0.0               # s
    drift: float = 0.0             # N·m/s
    offset: float = 0.0            # N·m
    angle_offset: float = 0.0      # rad
    k3: float = 0.0                # N·m/rad³
    asym: float = 0.0
    glitches: float = 0.0          # fraction
    torque_noise: float = 0.03
    defl_noise: float = 8e-4
    no_spring: bool = False
    extra: object = None           # f(t, θ_true, τ) -> τ' : structure outside the library

    def effects(self) -> set[str]:
        out = set()
        for name, v in (("backlash", self.backlash), ("hysteresis", self.friction),
                        ("time_lag", self.lag), ("drift", self.drift),
                        ("torque_offset", self.offset), ("angle_offset", self.angle_offset),
                        ("stiffening", self.k3), ("asymmetric_stiffness", self.asym),
                        ("outliers", self.glitches)):
            if v:
                out.add(name)
        return out

    def intervals(self) -> dict:
        """True values of the fit's reported quantities (keys of ``final.intervals``)."""
        if self.no_spring:
            return {}
        out = {"stiffness_Nm_per_rad": self.K}
        if self.backlash:
            out["backlash_rad"] = self.backlash
        if self.friction:
            out["friction_torque_Nm"] = self.friction
        if self.lag:
            out["lag_s"] = self.lag
        if self.drift:
            out["drift_Nm_per_s"] = self.drift
        if self.offset:
            out["torque_offset_Nm"] = self.offset
        if self.angle_offset:
            out["angle_offset_rad"] = self.angle_offset
        if self.k3:
            out["cubic_stiffness_Nm_per_rad3"] = self.k3
        if self.asym:
            out["stiffness_pos_Nm_per_rad"] = self.K * (1 + self.asym)
            out["stiffness_neg_Nm_per_rad"] = self.K * (1 - self.asym)
        return out


def make(truth: Truth, t, th, rng):
    """Measured (torque, deflection) of the bench for true deflection ``th`` at ``t``."""
    def elastic(x):
        x = deadband(x, truth.backlash / 2) if truth.backlash else x
        k = truth.K * (1 + truth.asym * np.sign(x))
        return k * x + truth.k3 * x ** 3

    fs = 1.0 / (t[1] - t[0])
    if truth.lag:
        th_late = np.interp(t - truth.lag, t, th)
    else:
        th_late = th
    tau = np.zeros_like(t) if truth.no_spring else elastic(th_late)
    if truth.friction:
        tau = tau + elastoplastic_friction(th_late, truth.friction, truth.presliding)
    if truth.extra is not None:
        tau = truth.extra(t, th_late, tau)
    tau = tau + truth.offset + truth.drift * t
    tau = tau + rng.normal(0, truth.torque_noise, t.size)
    if truth.glitches:
        k = max(1, int(truth.glitches * t.size))
        where = rng.choice(t.size, k, replace=False)
        tau[where] += rng.choice([-1, 1], k) * rng.uniform(1.0, 2.5, k)
    meas = th + truth.angle_offset + rng.normal(0, truth.defl_noise, t.size)
    del fs
    return tau, meas


# --- cases -----------------------------------------------------------------------------------


@dataclass
class Case:
    name: str
    truth: Truth
    protocol: tuple                      # (t, θ)
    accept: list                         # acceptable named sets (frozensets; groups as "a|b")
    unexplained: bool = False
    confounded: tuple | None = None      # pair that must be named confounded
    separable: tuple | None = None       # pair that must not be
    refuse: bool = False                 # the CLI must refuse (unit mistake)
    warn_ok: str | None = None           # ...or warn with this text (the data barely contradicts)
    args: list = field(default_factory=list)
    angle_scale: float = 1.0             # file value = rad × this
    column: str = "deflection_rad"
    where: str | None = None             # expected first localisation kind


def G(*names):
    return "|".join(sorted(names))


def S(*items):
    return frozenset(items)


def cases(seed: int) -> list[Case]:
    rng = np.random.default_rng(seed)
    K = float(rng.uniform(25, 60))
    stair = staircase([3, 6, 9, 12, 15, 18], 500, ramp_s=1.0)
    stair1k = staircase([5, 10, 15, 20], 1000, ramp_s=0.7)
    stair250 = staircase([4, 8, 12, 16, 20, 24], 250, ramp_s=1.2)
    one_rate = staircase([5, 10, 15, 20], 500, rates_deg_s=[10.0], shape="linear")
    two_rate = staircase([5, 10, 15, 20], 500, rates_deg_s=[18.0, 5.0], shape="linear")
    three_rate = staircase([6, 12, 18], 400, rates_deg_s=[20.0, 9.0, 4.0], shape="linear")
    sweep = sines([8, 18], [0.15, 0.4, 1.0], 500)
    holds = triangles([6, 12, 18], 500, 12.0, 1.5)

    def T(**kw):
        return Truth(K=kw.pop("K", K), **kw)

    hard = lambda t, th, tau: tau + 300.0 * np.sign(th) * np.maximum(np.abs(th) - 0.26, 0.0)  # noqa: E731
    t_end = stair[0][-1]
    change = lambda t, th, tau: tau * np.where(t > 0.62 * t[-1], 0.93, 1.0)  # noqa: E731
    settle = lambda t, th, tau: tau + 0.35 * (1 - np.exp(-t / (0.2 * t[-1])))  # noqa: E731
    ripple = lambda t, th, tau: tau + 0.12 * np.sin(2 * np.pi * th / (2 * np.pi / 36))  # noqa: E731
    sensor_db = lambda t, th, tau: np.where(np.abs(tau) < 0.6, 0.0, tau)  # noqa: E731
    hum = lambda t, th, tau: tau + 0.08 * np.sin(2 * np.pi * 11.7 * t + 0.3)  # noqa: E731
    zero_jump = lambda t, th, tau: tau - 0.25 * (t > 0.3 * t[-1])  # noqa: E731
    del t_end

    out = [
        # library effects, alone
        Case("clean_stair", T(), stair, [S()]),
        Case("backlash_1k", T(backlash=0.05), stair1k, [S("backlash")]),
        Case("friction_cos", T(friction=0.12), stair, [S("hysteresis")]),
        Case("lag_sweep", T(lag=0.012), sweep, [S("time_lag")]),
        Case("drift_250", T(drift=0.008), stair250, [S("drift")]),
        Case("stiffening_stair", T(k3=0.5 * K), stair, [S("stiffening")]),
        Case("asym_sweep", T(asym=0.05), sweep, [S("asymmetric_stiffness")]),
        Case("offset_holds", T(offset=-0.25), holds, [S("torque_offset")]),
        Case("glitches_stair", T(glitches=0.003), stair, [S("outliers")]),
        # pairs
        Case("backlash_friction", T(backlash=0.06, friction=0.1), stair, [S("backlash", "hysteresis")]),
        Case("backlash_angleoff", T(backlash=0.05, angle_offset=0.01), stair1k,
             [S("backlash", "angle_offset")]),
        Case("stiff_drift_sweep", T(k3=0.6 * K, drift=-0.006), sweep, [S("stiffening", "drift")]),
        Case("asym_friction_holds", T(asym=-0.04, friction=0.1), holds,
             [S("asymmetric_stiffness", "hysteresis")]),
        # threes
        Case("three_stair", T(backlash=0.05, friction=0.1, drift=0.007), stair,
             [S("backlash", "hysteresis", "drift")]),
        Case("three_sweep", T(friction=0.1, lag=0.01, k3=0.5 * K), sweep,
             [S("hysteresis", "time_lag", "stiffening")], separable=("hysteresis", "time_lag")),
        Case("three_rates", T(friction=0.12, lag=0.012, offset=0.2), three_rate,
             [S("hysteresis", "time_lag", "torque_offset")], separable=("hysteresis", "time_lag")),
        Case("three_glitch", T(backlash=0.04, asym=0.04, glitches=0.002), stair1k,
             [S("backlash", "asymmetric_stiffness", "outliers")]),
        # confounded / separable friction and lag
        Case("conf_one_rate", T(friction=0.15, lag=0.02), one_rate,
             [S(G("hysteresis", "time_lag"))], confounded=("hysteresis", "time_lag")),
        Case("conf_one_rate_fric_only", T(friction=0.15), one_rate,
             [S(G("hysteresis", "time_lag")), S("hysteresis")]),
        Case("conf_one_rate_lag_only", T(lag=0.02), one_rate,
             [S(G("hysteresis", "time_lag")), S("time_lag")]),
        Case("sep_two_rates", T(friction=0.15, lag=0.02), two_rate,
             [S("hysteresis", "time_lag")], separable=("hysteresis", "time_lag")),
        Case("sep_two_rates_fric_only", T(friction=0.12), two_rate, [S("hysteresis")]),
        # structure outside the library
        Case("hard_stop", T(extra=hard), stair, [S()], unexplained=True, where="large_deflection"),
        Case("hard_stop_friction", T(friction=0.1, extra=hard), stair1k, [S("hysteresis")],
             unexplained=True, where="large_deflection"),
        Case("stiffness_step", T(extra=change), stair, [S()], unexplained=True, where="time_step"),
        Case("stiffness_step_backlash", T(backlash=0.05, extra=change), stair250, [S("backlash")],
             unexplained=True, where="time_step"),
        Case("settling_drift", T(extra=settle), stair, [S(), S("drift")], unexplained=True,
             where="time_trend"),
        Case("ripple_angle", T(extra=ripple), stair, [S()], unexplained=True,
             where="periodic_angle"),
        Case("ripple_friction_sweep", T(friction=0.1, extra=ripple), sweep, [S("hysteresis")],
             unexplained=True, where="periodic_angle"),
        Case("sensor_deadband", T(extra=sensor_db), stair, [S()], unexplained=True),
        Case("hum_drift", T(drift=0.008, extra=hum), stair1k, [S("drift")], unexplained=True,
             where="periodic_time"),
        Case("zero_jump_three", T(backlash=0.05, friction=0.1, extra=zero_jump), stair,
             [S("backlash", "hysteresis")], unexplained=True, where="time_step"),
        # no spring
        Case("noise_only", T(no_spring=True), stair, [S()]),
        Case("noise_only_sweep", T(no_spring=True, torque_noise=0.1), sweep, [S()]),
        # noise levels
        Case("noisy_backlash", T(backlash=0.05, torque_noise=0.12, defl_noise=2e-3), stair,
             [S("backlash")]),
        Case("quiet_friction_lag_cos", T(friction=0.06, lag=0.008, torque_noise=0.01,
                                         defl_noise=3e-4), stair1k,
             [S("hysteresis", "time_lag")], separable=("hysteresis", "time_lag")),
        # unit mistakes
        Case("rad_read_as_deg", T(), stair, [S()], refuse=True, column="angle",
             args=["--deflection-col", "angle", "--angle-unit", "deg"]),
        Case("rad_read_as_deg_target", T(), stair, [S()], refuse=True, column="angle",
             args=["--deflection-col", "angle", "--angle-unit", "deg",
                   "--target-stiffness", f"{K:.3g}"]),
        Case("nm_read_as_nmm", T(), stair, [S()], refuse=True, column="angle",
             warn_ok="is the column in N·m",
             args=["--deflection-col", "angle", "--torque-col", "torque", "--torque-unit", "Nmm"]),
    ]
    return out


# --- running and scoring ---------------------------------------------------------------------


def write_csv(path: Path, t, tau, th, column: str, torque_col: str = "torque_Nm") -> None:
    data = np.column_stack([t, tau, th])
    np.savetxt(path, data, delimiter=",", header=f"time_s,{torque_col},{column}", comments="",
               fmt="%.9g")


def named(d: dict) -> frozenset:
    final = d["final"]
    groups = [G(*g["effects"]) for g in final["confounded"]]
    return frozenset(list(final["effects"]) + groups)


def score(case: Case, rc: int, stderr: str, d: dict | None) -> dict:
    row = {"case": case.name}
    traceback = "Traceback" in stderr
    if case.refuse:
        ok = rc in (1, 2) and not traceback and d is None
        if case.warn_ok and rc == 0 and case.warn_ok in stderr:
            ok = True
        row.update(named=ok, flag=ok, conf=True, valid=ok, cov=(0, 0),
                   got="refused" if rc else "fitted", note=stderr.strip().splitlines()[-1][:90]
                   if stderr.strip() else "")
        return row
    if d is None:
        msg = stderr.strip().splitlines()[-1][:90] if stderr.strip() else ""
        row.update(named=False, flag=False, conf=False, valid=False, cov=(0, 0),
                   got=f"exit {rc}", note=msg)
        return row
    final = d["final"]
    got = named(d)
    row["got"] = ("NO SPRING" if final["no_spring"] else
                  " + ".join(sorted(got)) or "linear") + (" ?" if final["unexplained"] else "")
    row["named"] = got in case.accept and (final["no_spring"] == case.truth.no_spring)
    row["flag"] = final["unexplained"] == case.unexplained
    groups = {G(*g["effects"]) for g in final["confounded"]}
    conf = True
    if case.confounded and G(*case.confounded) not in groups:
        conf = False
    if case.separable and any(set(case.separable) <= set(g.split("|")) for g in groups):
        conf = False
    row["conf"] = conf
    # impossible quantities
    valid = True
    notes = []
    en = d["energy_loss"]
    if en["pct"] is not None and (en["pct"] < 0 or (en["ci_low_pct"] or 0) < 0):
        valid = False
        notes.append(f"energy loss {en['pct']:.3g} %")
    for k, ci in final["intervals"].items():
        if k.endswith("stiffness_Nm_per_rad") and not final["no_spring"] and ci["value"] <= 0:
            valid = False
            notes.append(f"{k} = {ci['value']:.3g}")
    if case.truth.no_spring != final["no_spring"]:
        valid = False
        notes.append("no_spring wrong")
    row["valid"] = valid
    # coverage
    n = c = 0
    if not case.unexplained:
        for key, true in case.truth.intervals().items():
            ci = final["intervals"].get(key)
            if ci is None or ci.get("confounded_with"):
                continue
            n += 1
            if ci["ci_low"] <= true <= ci["ci_high"]:
                c += 1
            else:
                notes.append(f"{key} {true:.4g} outside [{ci['ci_low']:.4g}, {ci['ci_high']:.4g}]")
    row["cov"] = (c, n)
    if case.where and final["unexplained"] and final.get("unexplained_where"):
        kinds = [f["kind"] for f in final["unexplained_where"]["findings"]]
        row["where"] = kinds[0] if kinds else "-"
        if kinds and kinds[0] != case.where:
            notes.append(f"placed as {kinds[0]}, expected {case.where}")
    row["note"] = "; ".join(notes)
    return row


def run_case(case: Case, seed: int, workdir: Path, env: dict) -> dict:
    rng = np.random.default_rng([seed, zlib.crc32(case.name.encode())])
    t, th = case.protocol
    tau, meas = make(case.truth, t, th, rng)
    csv = workdir / f"{case.name}.csv"
    torque_col = "torque" if "--torque-col" in case.args else "torque_Nm"
    write_csv(csv, t, tau, meas * case.angle_scale, case.column, torque_col)
    out = workdir / case.name
    cmd = [sys.executable, "-m", "springcad", "fit", str(csv), "--out", str(out), "--no-plots",
           *case.args]
    t0 = time.perf_counter()
    # run from the work folder: ``python -m`` puts the current folder first on the path,
    # which must not shadow the package chosen by PYTHONPATH (--code)
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=workdir)
    dt = time.perf_counter() - t0
    d = None
    if proc.returncode == 0 and (out / "fit.json").is_file():
        d = json.loads((out / "fit.json").read_text())
    row = score(case, proc.returncode, proc.stderr, d)
    row["s"] = dt
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=7301)
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--keep", type=Path, default=None, help="keep CSVs and outputs here")
    ap.add_argument("--code", type=Path, default=REPO,
                    help="folder holding the springcad package to run (default: this checkout)")
    args = ap.parse_args(argv)
    env = {**os.environ, "PYTHONPATH": str(args.code.resolve())}
    all_cases = cases(args.seed)
    if args.only:
        all_cases = [c for c in all_cases if c.name in args.only]
    tmp = args.keep or Path(tempfile.mkdtemp(prefix="fit_heldout_"))
    tmp.mkdir(parents=True, exist_ok=True)
    rows = []
    print(f"seed {args.seed}, {len(all_cases)} records, code {args.code}, work in {tmp}")
    print(f"{'case':<26}{'named':>6}{'flag':>5}{'conf':>5}{'ci':>6}{'valid':>6}{'s':>6}  got / notes")
    for case in all_cases:
        row = run_case(case, args.seed, tmp, env)
        rows.append(row)
        c, n = row["cov"]
        yn = lambda b: "ok" if b else "NO"  # noqa: E731
        print(f"{case.name:<26}{yn(row['named']):>6}{yn(row['flag']):>5}{yn(row['conf']):>5}"
              f"{f'{c}/{n}':>6}{yn(row['valid']):>6}{row['s']:>6.1f}  {row['got']}"
              + (f"  | {row['note']}" if row.get("note") else ""), flush=True)
    tot = len(rows)
    cov_c = sum(r["cov"][0] for r in rows)
    cov_n = sum(r["cov"][1] for r in rows)
    all_ok = sum(all(r[k] for k in ("named", "flag", "conf", "valid")) for r in rows)
    print(f"\nnamed {sum(r['named'] for r in rows)}/{tot}, flag {sum(r['flag'] for r in rows)}/{tot}, "
          f"conf {sum(r['conf'] for r in rows)}/{tot}, valid {sum(r['valid'] for r in rows)}/{tot}, "
          f"CI coverage {cov_c}/{cov_n}; all four right on {all_ok}/{tot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
