"""Build the first change each design refusal of the design loop (/tmp/ho11/design/<name>.log)
names, with the harness's own functions (bench/spec_heldout.py run_spec, bench/heldout_fixes.py).
usage: run_fixes.py OUT_KEEP name1,name2,...   (writes OUT_KEEP/fixes/*.toml, OUT_KEEP/fixes.jsonl)"""
import json, sys, tomllib
from pathlib import Path
sys.path.insert(0, "/work/wt/ho11/bench")
import spec_heldout as sh
from heldout_fixes import apply_ops, describe, parse_fixes

keep = Path(sys.argv[1]); names = sys.argv[2].split(",")
timeout = float(sys.argv[3]) if len(sys.argv) > 3 else 420
(keep / "fixes").mkdir(parents=True, exist_ok=True); (keep / "out").mkdir(exist_ok=True)
for name in names:
    cfg = tomllib.loads(Path(f"/tmp/ho30/configs/{name}.toml").read_text())
    text = Path(f"/tmp/ho11/design/{name}.log").read_text()
    alts, note = parse_fixes("\n".join(sh.reason_lines(text)), cfg)
    row = {"name": name, "note": note, "n_alternatives": len(alts)}
    if alts:
        p = keep / "fixes" / f"{name}_fix1.toml"
        p.write_text(sh.to_toml(apply_ops(cfg, alts[0], "_fix1")))
        r = sh.run_spec(p, keep / "out", Path("/work/wt/ho11"), False, timeout, try_fix=False)
        row.update(change=describe(alts[0]), toml=str(p), outcome=r.outcome,
                   seconds=round(r.seconds, 1), stage=r.stage, reasons=r.reasons,
                   fix_note=r.fix_note, load=r.load)
    print(json.dumps({k: row.get(k) for k in ("name", "change", "outcome", "seconds")}), flush=True)
    with open(keep / "fixes.jsonl", "a") as f:
        f.write(json.dumps(row) + "\n")
