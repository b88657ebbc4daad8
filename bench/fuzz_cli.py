"""Fuzz the command line with mutated job configs, bench CSVs and output paths.

Every case runs ``python -m springcad ...`` in a subprocess (60 s limit) and is
classified: ``ok`` (exit 0/1 without a traceback), ``refused`` (exit 2 with a
one-line error), ``traceback`` (a Python traceback on the console, or an exit
status outside {0, 1, 2}), ``hang`` (over the time limit), ``multiline`` (an
error message longer than one line), ``leftover`` (a temporary or partial
folder left beside the output), ``input_changed`` (an input file modified) and
``nonsense`` (exit 0 with an implausible number in design.json: negative or
missing mass, a mass over 100 kg).

Usage::

    PYTHONPATH=. python bench/fuzz_cli.py --configs 300 --csvs 60 --paths 30 --seed 1
    PYTHONPATH=. python bench/fuzz_cli.py --configs 40 --command "build --no-verify --no-render"

The families follow issue 11: sections of the wrong type, values of the wrong
type, huge/tiny/negative/non-finite numbers, 400-digit integers, deep nesting,
non-UTF-8 bytes, names unusable in exports, unknown keys; CSVs with flipped,
scaled, broken or non-UTF-8 data; output paths that are files, lie under files
or are not writable.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TEMPLATES = sorted(p for p in (ROOT / "templates").glob("*.toml") if "title_block" not in p.name)
LIMIT_S = 60.0

#: every numeric key a config can hold, by section (springs use the "S" placeholder)
NUMERIC_KEYS = {
    "material": ["youngs_modulus_GPa", "poisson_ratio", "yield_strength_MPa", "density_kg_per_m3",
                 "design_stress_MPa", "safety_factor"],
    "springs": ["stiffness_Nm_per_rad", "max_deflection_deg", "max_deflection_rad",
                "outer_radius_mm", "thickness_mm", "contact_radius_mm", "min_tip_radius_mm",
                "tip_radius_mm", "n_flexures", "root_radius_mm"],
    "manufacturing": ["t_spring_mm", "t_shaft_mm", "w_gap_mm", "wire_diameter_mm", "spark_gap_mm",
                      "min_slot_width_mm", "min_web_mm", "min_hole_edge_mm"],
    "hardware": ["fastener_diameter_mm", "fastener_count", "shaft_diameter_mm",
                 "rim_spacer_thickness_mm", "bushing_wall_mm", "camshaft_hub_length_mm",
                 "rim_spacer_density_kg_per_m3", "plastic_density_kg_per_m3"],
    "analysis": ["monte_carlo_samples", "seed"],
}
STRING_KEYS = {"job": ["name", "description"], "material": ["name", "heat_treatment"],
               "stack": ["input", "output"], "manufacturing": ["process", "tolerance_distribution"],
               "hardware": ["fastener"], "springs": ["flexure"]}
HUGE_INT = int("9" * 400)


class Raw:
    """A TOML value written verbatim (inf, nan, nested inline tables)."""

    def __init__(self, text):
        self.text = text


def _value(v) -> str:
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def _key(k: str) -> str:
    return k if k and all(c.isalnum() and c.isascii() or c in "_-" for c in k) else json.dumps(k)


def toml_dumps(data: dict) -> str:
    """Tables of tables (two levels, as job configs are) and inline values below."""
    top, lines = [], []
    for k, v in data.items():
        if isinstance(v, dict) and v and all(isinstance(x, dict) for x in v.values()) and k == "springs":
            for name, t in v.items():
                lines.append(f"\n[{_key(k)}.{_key(name)}]")
                lines += [f"{_key(a)} = {_value(b)}" for a, b in t.items()]
        elif isinstance(v, dict):
            lines.append(f"\n[{_key(k)}]")
            lines += [f"{_key(a)} = {_value(b)}" for a, b in v.items()]
        else:
            top.append(f"{_key(k)} = {_value(v)}")
    return "\n".join(top + lines) + "\n"


def bad_values(rng: random.Random, current):
    """Mutations of one value: every class the issue lists."""
    x = current if isinstance(current, (int, float)) and not isinstance(current, bool) else 1.0
    if not (isinstance(x, float) or abs(x) < 1e15) or not math.isfinite(x) or abs(x) > 1e15:
        x = 1.0
    return rng.choice([
        0, -1, -x, 1e300, -1e300, 1e-300, 1e6, 1e-6, x * 10, x * 100, x / 100, x * 1.5, x * 0.7,
        float("inf"), float("nan"), "12", "abc", True, [1, 2], {"a": 1}, HUGE_INT, 2 ** 63 - 1,
        int(1e9), 0.001, 50, 1000, 2, 3, 0.5, 5.0, 20.0, x + 0.3])


def mutate_config(rng: random.Random) -> tuple[str, bytes]:
    """One mutated config: (family, bytes)."""
    base = rng.choice(TEMPLATES)
    text = base.read_text()
    data = tomllib.loads(text)
    springs = list(data.get("springs", {}))
    fam = rng.choices(["value", "value_new_key", "section", "names", "encoding", "structure",
                       "stack", "unknown", "multi"], [30, 20, 6, 8, 5, 5, 6, 4, 16])[0]
    if fam in ("value", "value_new_key", "multi"):
        for _ in range(1 if fam != "multi" else rng.randint(2, 4)):
            sec = rng.choice(list(NUMERIC_KEYS))
            key = rng.choice(NUMERIC_KEYS[sec])
            table = (data.setdefault("springs", {}).setdefault(rng.choice(springs), {})
                     if sec == "springs" else data.setdefault(sec, {}))
            if sec == "springs" and key.startswith("max_deflection"):
                table.pop("max_deflection_deg", None), table.pop("max_deflection_rad", None)
            if fam == "value" and key not in table:
                present = [k for k in table if k in NUMERIC_KEYS[sec]]
                key = rng.choice(present) if present else key
            table[key] = bad_values(rng, table.get(key))
        return fam, toml_dumps(data).encode()
    if fam == "section":
        sec = rng.choice(["job", "material", "springs", "stack", "manufacturing", "hardware",
                          "analysis"])
        data[sec] = rng.choice(["x", 5, [1, 2], True, 1.5, {}])
        if sec == "springs" and rng.random() < 0.5:
            data[sec] = {springs[0]: rng.choice(["x", 5, [1, 2]])}
        return fam, toml_dumps(data).encode()
    if fam == "names":
        choice = rng.randrange(8)
        if choice == 0:
            data.setdefault("job", {})["name"] = rng.choice(
                [[1, 2], 5, True, {"a": 1}, "", "é-ünï", "a/b", "x" * 400, "CON", "a\nb", " ", "../up"])
        elif choice == 1:
            data.setdefault("job", {})["description"] = rng.choice(
                [[1, 2], 5, 1.5, "ü" * 10, "x" * 5000, "line\nbreak", "\x00"])
        elif choice in (2, 3):  # rename a spring
            new = rng.choice(["Sé", "S 1", "S/1", "", "ß", "S.1", "x" * 200, "1", "S-1", "s_1",
                              "Ω", "S\t1", "CON"])
            old = springs[0]
            data["springs"][new] = data["springs"].pop(old)
            if "stack" in data:
                data["stack"]["sequence"] = [new if s == old else s for s in data["stack"]["sequence"]]
        elif choice == 4:
            data.setdefault("material", {})["name"] = rng.choice([[1, 2], 5, "", "420_HT", "stéel"])
        elif choice == 5:
            data.setdefault("material", {})["heat_treatment"] = rng.choice([[1], 5, "ü", "x" * 3000])
        elif choice == 6:
            data.setdefault("springs", {})[springs[0]]["flexure"] = rng.choice([1, ["auto"], "curvy"])
        else:
            data.setdefault("manufacturing", {})["process"] = rng.choice([1, "laser", ["wire_edm"]])
        return fam, toml_dumps(data).encode()
    if fam == "encoding":
        raw = text.encode()
        choice = rng.randrange(5)
        if choice == 0:
            return fam, b"# caf\xe9 latin-1 comment\n" + raw
        if choice == 1:
            return fam, text.encode("utf-16")
        if choice == 2:
            i = rng.randrange(len(raw))
            return fam, raw[:i] + bytes([rng.choice([0xff, 0xfe, 0xc3, 0x80, 0x00])]) + raw[i:]
        if choice == 3:
            return fam, b"\xef\xbb\xbf" + raw
        return fam, raw.replace(b'name = "', b'name = "\xe9', 1)
    if fam == "structure":
        choice = rng.randrange(6)
        if choice == 0:
            return fam, (text + "\n[" + ".".join(["a"] * 1000) + "]\nx = 1\n").encode()
        if choice == 1:
            return fam, (text + "\nx = " + "[" * 1000 + "]" * 1000 + "\n").encode()
        if choice == 2:
            return fam, (text + "\nx = " + "{a = " * 1000 + "1" + "}" * 1000 + "\n").encode()
        if choice == 3:
            return fam, text[: rng.randrange(len(text))].encode()
        if choice == 4:
            return fam, b""
        return fam, bytes(rng.randrange(256) for _ in range(200))
    if fam == "stack":
        st = data.setdefault("stack", {"sequence": [springs[0]]})
        choice = rng.randrange(6)
        if choice == 0:
            st["sequence"] = [springs[0]] * rng.choice([9, 50, 1000])
        elif choice == 1:
            st["sequence"] = rng.choice([springs[0], [1, 2], [[springs[0]]], [], 5])
        elif choice == 2:
            st["input"] = rng.choice(["belt", 1, ["shaft"]])
        elif choice == 3:
            st["output"] = rng.choice(["rim", "shaft", 2])
        elif choice == 4:
            del data["stack"]
            data["springs"]["extra"] = dict(next(iter(data["springs"].values())))
        else:
            st["sequence"] = [springs[0], "nope"]
        return fam, toml_dumps(data).encode()
    # unknown keys
    sec = rng.choice(["job", "material", "stack", "manufacturing", "hardware", "analysis", "top"])
    key = rng.choice(["outer_radius_in", "foo", "centre_spacer_thickness_mm",
                      "centre_spacer_clearance_mm", "seed_", "Name"])
    if sec == "top":
        data[key] = 1
    else:
        data.setdefault(sec, {})[key] = 1.0
    return fam, toml_dumps(data).encode()


def mutate_csv(rng: random.Random, clean: str) -> tuple[str, bytes]:
    lines = clean.splitlines()
    header_i = next(i for i, l in enumerate(lines) if l and not l.startswith("#"))
    header = lines[header_i].split(",")
    body = lines[header_i + 1:]
    ti = header.index("torque_Nm")

    def scale(f):
        out = []
        for l in body:
            cells = l.split(",")
            cells[ti] = repr(f(float(cells[ti])))
            out.append(",".join(cells))
        return "\n".join(lines[:header_i + 1] + out) + "\n"

    fam = rng.choice(["negate", "scale_big", "scale_small", "latin1", "nan", "truncate",
                      "missing_col", "junk_cell", "few_rows", "constant", "utf16", "decreasing_time",
                      "inf", "empty", "dup_header", "semicolon"])
    if fam == "negate":
        return fam, scale(lambda t: -t).encode()
    if fam == "scale_big":
        return fam, scale(lambda t: t * rng.choice([1e300, 1e30, 1e10])).encode()
    if fam == "scale_small":
        return fam, scale(lambda t: t * rng.choice([1e-300, 1e-30, 1e-12])).encode()
    if fam == "latin1":
        return fam, b"# caf\xe9\n" + clean.encode()
    if fam == "nan":
        i = rng.randrange(len(body))
        cells = body[i].split(",")
        cells[ti] = "nan"
        body[i] = ",".join(cells)
        return fam, "\n".join(lines[:header_i + 1] + body).encode()
    if fam == "truncate":
        return fam, clean[: rng.randrange(len(clean))].encode()
    if fam == "missing_col":
        return fam, clean.replace("torque_Nm", "torque_x", 1).encode()
    if fam == "junk_cell":
        i = rng.randrange(len(body))
        body[i] = body[i] + ",extra"
        return fam, "\n".join(lines[:header_i + 1] + body).encode()
    if fam == "few_rows":
        return fam, "\n".join(lines[:header_i + 1] + body[:rng.choice([0, 1, 3, 150])]).encode()
    if fam == "constant":
        return fam, scale(lambda t: 1.0).encode()
    if fam == "utf16":
        return fam, clean.encode("utf-16")
    if fam == "decreasing_time":
        return fam, "\n".join(lines[:header_i + 1] + body[::-1]).encode()
    if fam == "inf":
        return fam, scale(lambda t: float("inf") if rng.random() < 0.01 else t).encode()
    if fam == "empty":
        return fam, b""
    if fam == "dup_header":
        return fam, "\n".join(lines[:header_i + 1] + [lines[header_i]] + body).encode()
    return fam, clean.replace(",", ";").encode()


def _leftovers(folder: Path, keep: set[str]) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


def run_case(case: dict) -> dict:
    work = Path(tempfile.mkdtemp(prefix="fuzz-"))
    try:
        inp = work / case["input_name"]
        inp.write_bytes(case["data"])
        for name, content in case.get("extra_files", {}).items():
            p = work / name
            p.parent.mkdir(parents=True, exist_ok=True)
            if content is None:
                p.mkdir(exist_ok=True)
            else:
                p.write_bytes(content)
        out = case.get("out", "out")
        argv = [sys.executable, "-m", "springcad", *case["command"].split(), str(inp)]
        if case["command"].split()[0] == "paper":
            argv = argv[:-1]
        argv += ["--out", out if out.startswith("/") else str(work / out), *case.get("flags", [])]
        before = set(p.name for p in work.iterdir())
        env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(argv, capture_output=True, text=True, timeout=LIMIT_S, env=env,
                                  cwd=work, errors="replace")
            rc, err = proc.returncode, proc.stderr
        except subprocess.TimeoutExpired:
            rc, err = None, "TIMEOUT"
        dt = time.perf_counter() - t0
        verdict = []
        if rc is None:
            verdict.append("hang")
        elif "Traceback" in err or rc not in (0, 1, 2):
            verdict.append("traceback")
        if rc == 2:
            errors = [l for l in err.splitlines() if "error:" in l]
            if len(errors) != 1 or not err.rstrip().splitlines()[-1].startswith(errors[-1][:20]):
                verdict.append("multiline")
        if inp.read_bytes() != case["data"]:
            verdict.append("input_changed")
        stray = [n for n in _leftovers(work, before | {Path(out).name})
                 if n.startswith(".") or "tmp" in n]
        if stray:
            verdict.append("leftover")
        design = work / out / "design.json"
        if rc == 0 and design.exists():
            d = json.loads(design.read_text())
            masses = [s.get("mass_kg") for s in d["springs"].values()] + [d["stack"].get("mass_kg")]
            if any(m is None or m <= 0 or m > 100 for m in masses):
                verdict.append("nonsense")
        if not verdict:
            verdict.append("refused" if rc == 2 else "ok")
        return {"id": case["id"], "family": case["family"], "command": case["command"],
                "rc": rc, "seconds": round(dt, 2), "verdict": verdict,
                "stderr_tail": err.strip().splitlines()[-3:] if err.strip() else []}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def clean_csv() -> str:
    work = Path(tempfile.mkdtemp(prefix="fuzz-csv-"))
    try:
        out = work / "rec.csv"
        subprocess.run([sys.executable, "-m", "springcad", "simulate",
                        str(ROOT / "templates" / "paper_2xS1.toml"), "--out", str(out), "--seed", "4"],
                       check=True, capture_output=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
        return out.read_text()
    finally:
        shutil.rmtree(work, ignore_errors=True)


def path_cases(rng: random.Random, n: int, config: bytes) -> list[dict]:
    """--out that is a file, lies under a file, is not writable, or exists."""
    cases = []
    for i in range(n):
        kind = rng.choice(["is_file", "under_file", "proc", "exists", "exists_overwrite",
                           "sim_dir_overwrite", "sim_under_file", "paper_exists"])
        c = {"input_name": "job.toml", "data": config, "family": f"path:{kind}",
             "command": rng.choice(["design", "build --no-verify --no-render"])}
        if kind == "is_file":
            c["extra_files"], c["out"] = {"afile": b"x"}, "afile"
        elif kind == "under_file":
            c["extra_files"], c["out"] = {"afile": b"x"}, "afile/sub"
        elif kind == "proc":
            c["out"] = "/proc/springcad-fuzz-out"
        elif kind == "exists":
            c["extra_files"], c["out"] = {"out/keep.txt": b"mine"}, "out"
        elif kind == "exists_overwrite":
            c["extra_files"], c["out"], c["flags"] = {"out/keep.txt": b"mine"}, "out", ["--overwrite"]
            c["command"] = "design"
        elif kind == "sim_dir_overwrite":
            c["extra_files"], c["out"], c["flags"] = {"outdir": None}, "outdir", ["--overwrite"]
            c["command"] = "simulate"
        elif kind == "sim_under_file":
            c["extra_files"], c["out"], c["command"] = {"afile": b"x"}, "afile/rec.csv", "simulate"
        else:
            c["extra_files"], c["out"], c["command"] = {"out/keep.txt": b"mine"}, "out", "paper"
        cases.append(c)
    return cases


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--configs", type=int, default=300)
    ap.add_argument("--csvs", type=int, default=60)
    ap.add_argument("--paths", type=int, default=30)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--command", default="design", help="subcommand (and flags) for the configs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path, help="write every case result here")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    cases = []
    for i in range(args.configs):
        fam, data = mutate_config(rng)
        cases.append({"input_name": "job.toml", "data": data, "family": fam,
                      "command": args.command})
    if args.csvs:
        clean = clean_csv()
        for i in range(args.csvs):
            fam, data = mutate_csv(rng, clean)
            cases.append({"input_name": "rec.csv", "data": data, "family": f"csv:{fam}",
                          "command": "fit", "flags": ["--no-plots"]})
    cases += path_cases(rng, args.paths, (ROOT / "templates" / "paper_S1.toml").read_bytes())
    for i, c in enumerate(cases):
        c["id"] = i
    results = []
    t0 = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for r in pool.map(run_case, cases):
            results.append(r)
            if not set(r["verdict"]) <= {"ok", "refused"}:
                print(f"#{r['id']} {r['family']} {r['command']}: {r['verdict']} rc={r['rc']} "
                      f"{r['seconds']} s: {' | '.join(r['stderr_tail'])[-300:]}", flush=True)
    counts = collections.Counter(v for r in results for v in r["verdict"])
    slowest = max(results, key=lambda r: r["seconds"])
    print(f"\n{len(results)} cases in {time.perf_counter() - t0:.0f} s: "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + f"; slowest #{slowest['id']} {slowest['seconds']} s")
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    bad = {"traceback", "hang", "multiline", "leftover", "input_changed", "nonsense"}
    return 1 if any(set(r["verdict"]) & bad for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
