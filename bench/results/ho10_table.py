"""Markdown table + json of the ho10 held-out runs, read from the harness logs under
/tmp/ho10/{b,c}/out/logs (builds in b, design-only in c). usage: ho10_table.py OUT.md OUT.json"""
import json, re, sys, tomllib
from pathlib import Path
sys.path.insert(0, "/work/wt/ho10/bench")
import spec_heldout as sh

CFG = Path("/tmp/ho30/configs")
KEEPS = [Path(p) for p in ["/tmp/ho10/b", "/tmp/ho10/c", "/tmp/ho10/d", "/tmp/ho10/h"]]

def head(p):
    if not p.exists():
        return None
    t = p.read_text()
    m = re.search(r"# exit (\S+), ([\d.]+) s(, TIMEOUT)?", t)
    return {"rc": m.group(1), "s": float(m.group(2)), "timeout": bool(m.group(3)), "text": t}

def body(t):
    return [l for l in t.splitlines()[2:] if "deprecated" not in l and l.strip()]

def err(t):
    ls = body(t)
    e = [l for l in ls if l.startswith("springcad") and "error" in l]
    return (e[-1] if e else " / ".join(ls[-2:]))

def find(name, kind):
    """latest log of name.kind across keeps"""
    best = None
    for k in KEEPS:
        p = k / "out" / "logs" / f"{name}.{kind}.log"
        if p.exists() and (best is None or p.stat().st_mtime > best[1].stat().st_mtime):
            best = (k, p)
    return best

def classify(name):
    f = find(name, "design")
    if f is None:
        return None
    k, p = f
    d = head(p)
    row = {"name": name, "design_s": d["s"]}
    if d["timeout"]:
        row["design"] = "TIMEOUT"; return row
    if d["rc"] != "0":
        row["design"] = "REFUSED"; row["message"] = err(d["text"])
        row["fixes"] = []
        for k2 in KEEPS:
            for fl in sorted((k2 / "out" / "logs").glob(f"{name}_*fix*.design.log")):
                fn = fl.name.split(".")[0]
                toml = next((q for q in [k2 / "fixes" / f"{fn}.toml", Path("/tmp/ho10/hand") / f"{fn}.toml"] if q.exists()), None)
                change = ""
                if toml:
                    a = tomllib.loads((CFG / f"{name}.toml").read_text()); b = tomllib.loads(toml.read_text())
                    change = diffcfg(a, b)
                if not any(x["fix"] == fn for x in row["fixes"]):
                    row["fixes"].append({"fix": fn, "change": change, **(classify(fn) or {})})
        return row
    row["design"] = "DESIGNED"
    row["design_warnings"] = [l for l in body(d["text"]) if "warning" in l.lower()]
    fb = find(name, "build")
    if fb is None:
        row["build"] = "not run"; return row
    k, p = fb
    b = head(p)
    row["build_s"] = b["s"]
    st = re.findall(r"\[(\d)/5\] (\w+)", b["text"])
    if b["timeout"]:
        row["build"] = f"TIMEOUT (in {st[-1][1] if st else '?'})"; return row
    if sh._is_crash(sh.Run(int(b["rc"]) if b["rc"].lstrip('-').isdigit() else None, 0, b["text"])):
        row["build"] = "CRASH"; row["message"] = err(b["text"]); return row
    if b["rc"] != "0":
        row["build"] = f"LATE FAILURE ({st[-1][1] if st else '?'}, exit {b['rc']})"
        row["message"] = err(b["text"]); return row
    rel = json.loads((k / "out" / name / "build.json").read_text())["release"]
    row["build"] = rel["status"]; row["reasons"] = rel.get("reasons", [])
    return row

def diffcfg(a, b, pre=""):
    out = []
    for key in sorted(set(a) | set(b)):
        if key in ("job",):
            continue
        va, vb = a.get(key, "<absent>"), b.get(key, "<absent>")
        if isinstance(va, dict) and isinstance(vb, dict):
            s = diffcfg(va, vb, pre + key + ".")
            if s: out.append(s)
        elif va != vb:
            out.append(f"{pre}{key}: {va} -> {vb}")
    return "; ".join(out)

def short_reasons(rs):
    out = []
    for r in rs:
        m = re.match(r"spring (\w+): (duty|tip-ball contact fatigue)", r)
        if m and m.group(2) == "duty":
            sf = re.search(r"fatigue safety factor ([\d.]+) < ([\d.]+)", r)
            out.append(f"{m.group(1)}: duty SF {sf.group(1) if sf else '?'}")
        elif m:
            p = re.search(r"Hertz pressure (\d+) MPa", r)
            out.append(f"{m.group(1)}: contact fatigue p0 {p.group(1) if p else '?'} MPa")
        else:
            out.append(r[:160])
    return "; ".join(out)

rows = [r for p in sorted(CFG.glob("*.toml")) if (r := classify(p.stem))]
for r in rows:
    r["label"] = sh.assess(tomllib.loads((CFG / f"{r['name']}.toml").read_text()))["label"]
json.dump(rows, open(sys.argv[2], "w"), indent=1)
L = ["| spec | label | design | build | reasons / message (shortened) |", "|---|---|---|---|---|"]
for r in rows:
    why = short_reasons(r.get("reasons", [])) if r.get("reasons") else (r.get("message", "")[:300].replace("|", "/"))
    L.append(f"| {r['name']} | {r['label']} | {r['design']} ({r['design_s']:.0f} s) | {r.get('build', '-')}"
             f"{' (%.0f s)' % r['build_s'] if 'build_s' in r else ''} | {why} |")
    for f in r.get("fixes", []):
        why = short_reasons(f.get("reasons", [])) if f.get("reasons") else f.get("message", "")[:200].replace("|", "/")
        L.append(f"| &nbsp;&nbsp;fix `{f['change']}` | | {f.get('design', '?')} | {f.get('build', '-')} | {why} |")
open(sys.argv[1], "w").write("\n".join(L) + "\n")
print("\n".join(L))
