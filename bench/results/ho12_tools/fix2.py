"""Second step after a change that did not design (ho12): for each `<name>_fix` whose build was
REFUSED AT DESIGN, the first change its own refusal names is applied to the applied spec and
built (`<name>_fix2`), with spec_heldout_b's parser and build; rows in DIR/builds2.json.
Extra rows given as NAME=KEY:VALUE,... apply several changes at once to DIR/specs/NAME.toml
(e.g. both springs' first changes of a two-spring refusal).

usage: python bench/results/ho12_tools/fix2.py DIR CODE STOP_HH:MM [NAME=springs.B.outer_radius_mm:64 ...]
"""
import datetime
import json
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
import spec_heldout_b as hb  # noqa: E402

work, code = Path(sys.argv[1]), Path(sys.argv[2])
hh, mm = (int(x) for x in sys.argv[3].split(":"))
stop_at = datetime.datetime.now(datetime.timezone.utc).replace(
    hour=hh, minute=mm, second=0, microsecond=0).timestamp()
builds = json.loads((work / "builds.json").read_text())
out = work / "builds2.json"
done = json.loads(out.read_text()) if out.exists() else {}
todo = []
for name, b in sorted(builds.items()):
    if name.endswith("_fix") and b.get("build_outcome") == "REFUSED AT DESIGN":
        cfg = tomllib.loads((work / "specs" / f"{name}.toml").read_text())
        alts, note = hb.parse_fixes(hb.refusal_text((work / "build" / f"{name}.log").read_text()),
                                    cfg)
        todo.append((name + "2", cfg, alts[:1], note))
for arg in sys.argv[4:]:
    name, changes = arg.split("=", 1)
    cfg = tomllib.loads((work / "specs" / f"{name}.toml").read_text())
    ops = []
    for ch in changes.split(","):
        key, val = ch.split(":", 1)
        parts = key.split(".")
        value = val.strip('"') if val.startswith('"') else float(val)
        ops.append(("set", parts[0], parts[1] if len(parts) == 3 else None, parts[-1], value))
    todo.append((name + "_both", cfg, [ops], "by hand: " + arg))
for tag, cfg, alts, note in todo:
    if tag in done:
        continue
    row = {"parser": note}
    if not alts:
        row["build_outcome"] = "NO CHANGE PARSED"
    else:
        timeout = hb._capped(480.0, stop_at)
        if timeout is None:
            print("stop: too close to the stop time", flush=True)
            break
        new = hb.apply_ops(cfg, alts[0], "")
        new["job"]["name"] = tag
        (work / "specs" / f"{tag}.toml").write_text(hb.to_toml(new))
        row["change"] = hb.describe(alts[0])
        row.update(hb.build_case(tag, work, code, timeout))
    done[tag] = row
    out.write_text(json.dumps(done, indent=1))
    print(f"{tag}  {row.get('change', '-')}  {row['build_outcome']}  {row.get('build_s', '')} s",
          flush=True)
