"""Markdown table and json of ho11's held-out runs (seed-2511 configs in /tmp/ho30/configs),
read from the run outputs:

* /tmp/ho11/design/<name>.log and times.txt: ``springcad design`` of every config
  (/tmp/ho11/design_all.sh);
* /tmp/ho11/b/results_partial.jsonl: ``springcad build`` of the designed ones (harness
  bench/spec_heldout.py --only ...);
* /tmp/ho11/f/fixes.jsonl: ``springcad build`` of the first change each refusal names
  (/tmp/ho11/tools/run_fixes.py, the harness's parse and apply).

usage: python bench/results/ho11_table.py OUT.md OUT.json
"""
import json
import re
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import spec_heldout as sh  # noqa: E402
from heldout_fixes import parse_fixes  # noqa: E402

CFG = Path("/tmp/ho30/configs")
DESIGN = Path("/tmp/ho11/design")


def jsonl(p: Path) -> dict:
    """name -> row of a results file, the deprecation warning of the configs' key dropped."""
    rows = {}
    if p.exists():
        for line in p.read_text().splitlines():
            r = json.loads(line)
            r["reasons"] = [x for x in r.get("reasons") or [] if "deprecated" not in x]
            rows[r["name"]] = r
    return rows


def design_rows() -> dict:
    rows = {}
    for line in (DESIGN / "times.txt").read_text().splitlines():
        m = re.match(r"(\S+) rc=(\d+) s=([\d.]+) load=([\d.]+)", line)
        if not m:
            continue
        name, rc, s, load = m[1], int(m[2]), float(m[3]), float(m[4])
        text = (DESIGN / f"{name}.log").read_text()
        body = [ln for ln in text.splitlines() if "deprecated" not in ln]
        row = {"design_rc": rc, "design_s": round(s, 1), "design_load": load}
        if rc == 0:
            row["design"] = "DESIGNED"
            row["design_warnings"] = [ln for ln in body if "warning" in ln.lower()]
            row["design_notes"] = [ln for ln in body if ln.startswith("note:")
                                   or "NOT met" in ln]
        elif rc in (124, 137) and not sh.reason_lines(text)[0].startswith("springcad design:"):
            row["design"] = "TIMEOUT"
        elif rc == 3 or "Traceback" in text:
            row["design"] = "CRASH"
            row["message"] = "\n".join(body[-5:])
        else:
            cfg = tomllib.loads((CFG / f"{name}.toml").read_text())
            reasons = sh.reason_lines(text)
            alts, note = parse_fixes("\n".join(reasons), cfg)
            row["design"] = "REFUSED+NUMBERS" if alts else "REFUSED"
            row["message"] = "\n".join(reasons)
            row["parse"] = note
            row["n_alternatives"] = len(alts)
            if rc in (124, 137):      # the message was out when the timeout killed the run
                row["design_note"] = f"refusal printed, then killed by the {s:.0f} s timeout"
        rows[name] = row
    return rows


def reason_kind(reason: str) -> str:
    """"duty" for a reason that is only springcad's default duty (flexure fatigue, tip-ball
    contact fatigue over the duty; no held-out config sets a duty), else "manufacturing/
    geometry" (tolerances, clearances, interference, static margins, EDM rules)."""
    return "duty" if re.search(r"\bduty\b|contact fatigue", reason) else "manufacturing/geometry"


def short(text: str, n: int = 170) -> str:
    text = text.replace("|", "/").replace("\n", " ")
    return text if len(text) <= n else text[:n] + " ..."


def main(out_md: str, out_json: str) -> None:
    des = design_rows()
    builds = jsonl(Path("/tmp/ho11/b/results_partial.jsonl"))
    fixes = jsonl(Path("/tmp/ho11/f/fixes.jsonl"))
    rows, md = [], ["| spec | label | design (s) | build (s) | reasons / message (shortened) |",
                    "|---|---|---|---|---|"]
    for p in sorted(CFG.glob("g*.toml")):
        name = p.stem
        info = sh.assess(tomllib.loads(p.read_text()))
        row = {"name": name, "label": info["label"], "rho": round(info["rho"], 3),
               **des.get(name, {"design": "not run"})}
        b = builds.get(name)
        if b:
            row.update(build=b["outcome"], build_s=round(b["seconds"], 1), build_stage=b["stage"],
                       build_reasons=b["reasons"], build_load=b["load"],
                       build_reason_kinds=sorted({reason_kind(x) for x in b["reasons"]}))
        f = fixes.get(name)
        if f:
            f["reason_kinds"] = sorted({reason_kind(x) for x in f.get("reasons") or []})
            row["fix"] = f
        rows.append(row)
        bcell = f"{row['build']} ({row['build_s']:.0f})" if b else \
            ("-" if row["design"].startswith("REFUSED") else "not run")
        why = "; ".join(short(r, 90) for r in (b or {}).get("reasons", [])[:3]) if b else \
            short(row.get("message", ""))
        md.append(f"| {name} | {info['label']} | {row['design']} ({row.get('design_s', 0):.0f}) "
                  f"| {bcell} | {why} |")
        if f and f.get("change"):
            fr = "; ".join(short(r, 90) for r in f.get("reasons", [])[:3])
            md.append(f"| &nbsp;&nbsp;first change: `{short(f['change'], 120)}` | | | "
                      f"{f['outcome']} ({f['seconds']:.0f}) | {fr} |")
    Path(out_md).write_text("\n".join(md) + "\n")
    Path(out_json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main(*sys.argv[1:3])
