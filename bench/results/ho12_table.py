"""Markdown table and json of ho12's held-out run (bench/spec_heldout_b.py, seed 2712, 30 specs),
read from the harness's outputs in DIR (default /tmp/ho12/b):

* DIR/results.json, DIR/design/<name>.log: ``springcad design`` of every spec (--design-only);
* DIR/builds.json, DIR/build/<name>.log: ``springcad build`` of the designed specs (--build)
  and of the first change each refusal names, applied to DIR/specs/<name>_fix.toml (--fixes).

usage: python bench/results/ho12_table.py OUT.md OUT.json [DIR]
"""
import json
import re
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from heldout_fixes import parse_fixes  # noqa: E402
from spec_heldout_b import refusal_text  # noqa: E402

#: spring keys a spec may fix beyond the target, the deflection and the envelope
CHOICE_KEYS = ("n_flexures", "contact_radius_mm", "tip_radius_mm", "min_tip_radius_mm",
               "flexure", "root_radius_mm", "max_thickness_mm")


def reason_kind(reason: str, declared_duty: bool) -> str:
    """"default duty" for a reason that is only springcad's default duty (flexure fatigue, tip-ball
    contact fatigue over the duty) on a spec without [duty], "declared duty" with one;
    manufacturing/geometry: "contact at full deflection" (clearances and the tip ball's Hertz
    stress at +-theta_max), "tolerance interference" (the design's warning that the profile
    tolerances exceed w_gap_mm), "design warning" (another note the design stage printed),
    else "other"."""
    if re.match(r"spring \S+: (duty|tip-ball contact fatigue)", reason):
        return "declared duty" if declared_duty else "default duty"
    if reason.startswith("contact at full deflection"):
        return "contact at full deflection"
    if "interference warning" in reason:
        return "tolerance interference"
    return "design warning" if reason.startswith("design warning") else "other"


def short(text: str, n: int = 170) -> str:
    text = " ".join(str(text).replace("|", "/").split())
    return text if len(text) <= n else text[:n] + " ..."


def _spec_summary(cfg: dict) -> dict:
    springs = cfg["springs"]
    fixed = sorted({k for s in springs.values() for k in s if k in CHOICE_KEYS})
    return {"description": cfg["job"].get("description", ""),
            "material": cfg["material"]["name"],
            "disks": len(cfg["stack"]["sequence"]), "input": cfg["stack"]["input"],
            "springs": {n: {k: s[k] for k in ("target_stiffness_Nm_per_rad",
                                              "max_deflection_deg", "outer_radius_mm",
                                              "thickness_mm") if k in s}
                        for n, s in springs.items()},
            "fixed_spring_keys": fixed, "hardware": cfg.get("hardware", {}),
            "duty": cfg.get("duty", {}).get("preset"),
            "manufacturing": cfg.get("manufacturing", {})}


def _build_summary(b: dict, declared_duty: bool) -> dict:
    out = {k: b.get(k) for k in ("build_outcome", "build_s", "build_rc", "stage", "change",
                                 "parser")}
    rel = b.get("release") or {}
    reasons = [r for r in rel.get("reasons", []) if "deprecated" not in r]
    out["reasons"] = reasons
    out["notes"] = rel.get("notes", [])
    kinds = sorted({reason_kind(r, declared_duty) for r in reasons})
    out["reason_kinds"] = kinds
    if b.get("build_outcome") not in ("RELEASED", "NOT FOR MANUFACTURE"):
        out["message"] = b.get("build_message", "")
    return out


def rows_of(work: Path) -> list[dict]:
    results = json.loads((work / "results.json").read_text())
    builds = json.loads((work / "builds.json").read_text()) if (work / "builds.json").exists() \
        else {}
    rows = []
    for r in results:
        name = r["name"]
        cfg = tomllib.loads((work / "specs" / f"{name}.toml").read_text())
        declared = "duty" in cfg
        row = {"name": name, "label": r["label"], "label_reasons": r["label_reasons"],
               "spec": _spec_summary(cfg), "design": r["outcome"], "design_s": r["design_s"]}
        log = (work / "design" / f"{name}.log").read_text()
        if r["outcome"] == "DESIGNED":
            row["design_notes"] = [ln for ln in log.splitlines()
                                   if ln.startswith("note:") or "NOT met" in ln
                                   or "warning" in ln.lower()]
        else:
            msg = refusal_text(log)
            alts, note = parse_fixes(msg, cfg)
            row["message"] = msg
            row["parse"] = note
            row["n_alternatives"] = len(alts)
            row["design"] = "REFUSED+NUMBERS" if alts else "REFUSED"
        if name in builds:
            row["build"] = _build_summary(builds[name], declared)
        if name + "_fix" in builds:
            row["fix"] = _build_summary(builds[name + "_fix"], declared)
        rows.append(row)
    return rows


def _cell(b: dict | None) -> str:
    if not b:
        return "-"
    s = f"{b['build_outcome']}" + (f" ({b['stage']})" if b["build_outcome"] in (
        "LATE FAILURE", "CRASH", "TIMEOUT") else "")
    return s + (f" ({b['build_s']:.0f})" if b.get("build_s") is not None else "")


def _why(b: dict | None) -> str:
    if not b:
        return ""
    if b["reasons"]:
        return "; ".join(short(x, 90) for x in b["reasons"][:3]) + \
            (f"; (+{len(b['reasons']) - 3})" if len(b["reasons"]) > 3 else "")
    msg = [ln for ln in (b.get("message") or "").splitlines()
           if re.match(r"springcad \w+: ", ln)]
    return short(msg[0] if msg else b.get("message", ""), 200)


def _asks(spec: dict) -> str:
    """One line: joint, disks, material, envelope, the keys fixed beyond them, duty, tolerances."""
    sp = next(iter(spec["springs"].values()))
    joint = spec["description"].replace("held-out B: ", "").split(",")[0]
    fixed = ", ".join(k.replace("_mm", "") for k in spec["fixed_spring_keys"])
    hw = spec["hardware"]
    bits = [joint, f"{spec['disks']} disk(s){' A/B' if len(spec['springs']) > 1 else ''}",
            spec["material"], f"R_o {sp['outer_radius_mm']:g}",
            f"z {sp['thickness_mm']:g}" if "thickness_mm" in sp else "z free",
            f"{hw.get('fastener', 'dowel')} {hw.get('fastener_diameter_mm', '')}".strip()]
    if fixed:
        bits.append("fixed: " + fixed)
    if spec["duty"]:
        bits.append("duty " + spec["duty"])
    if spec["manufacturing"]:
        bits.append("Mfr2 tolerances")
    return "; ".join(bits)


def _refusal(msg: str) -> str:
    """The refusal's cause: what follows "Why" if written, else the message's start."""
    at = msg.find("Why")
    return short(msg[at:] if at >= 0 else msg.replace("springcad design: error: ", ""), 200)


def table(rows: list[dict]) -> str:
    out = ["| spec | what it asks | label | design (s) | build (s) | reasons / message (shortened) |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        design = f"{r['design']} ({r['design_s']:.0f})"
        why = _why(r.get("build")) if "build" in r else \
            _refusal(r.get("message", "")) if r["design"] != "DESIGNED" else ""
        out.append(f"| {r['name']} | {_asks(r['spec'])} | {r['label']} | {design} | "
                   f"{_cell(r.get('build'))} | {why} |")
        if "fix" in r:
            fx = r["fix"]
            change = short(fx.get("change") or fx.get("parser") or "", 110)
            out.append(f"| &nbsp;&nbsp;first change: `{change}` | | | | {_cell(fx)} | "
                       f"{_why(fx)} |")
    return "\n".join(out)


def main() -> int:
    md, js = Path(sys.argv[1]), Path(sys.argv[2])
    work = Path(sys.argv[3]) if len(sys.argv) > 3 else Path("/tmp/ho12/b")
    rows = rows_of(work)
    md.write_text(table(rows) + "\n")
    js.write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
