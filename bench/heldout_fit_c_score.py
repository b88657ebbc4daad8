"""Held-out generator C: score one `springcad fit` result against the record's truth.

Written from /work/wt/FIT_PHYSICS.md, the README's `springcad fit` section and the
fit.json the CLI writes (its keys were read off a fit's output after the truths were
committed, never from springcad/fit/).

What the fit said is read from fit.json: ``final.effects`` (identified effects),
``final.confounded[*].effects`` (groups the fit names as one confounded term: each member
counts as named, as a group), ``final.unexplained``, ``final.params.stiffness_Nm_per_rad``,
``final.nrmse_pct`` against ``baseline.nrmse_pct``.

Rules (fixed with the truths, before any fit was run):
- effects: each required group is met by a named member; nothing named outside the
  required groups and the optional names.
- unexplained: equal to the truth (a truth of None accepts either).
- K: within 2 % of the truth where the truth says K is scored.
- NRMSE: the final model's not above the linear baseline's.
- no crash: exit status 0 or 1 and a fit.json.
"""
from __future__ import annotations

import json
from pathlib import Path

K_TOL = 0.02


def read_fit(path: Path) -> dict | None:
    """The parts of fit.json the score needs (None if the file is missing or unreadable)."""
    try:
        d = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return None
    fin = d.get("final", {})
    groups = [sorted(g.get("effects", [])) for g in fin.get("confounded", []) or []]
    laws = {k: v.get("law") for k, v in (fin.get("laws") or {}).items()}
    where = fin.get("unexplained_where") or {}
    return {"effects": sorted(fin.get("effects", [])), "confounded": groups,
            "unexplained": fin.get("unexplained"), "laws": laws,
            "unexplained_kinds": sorted({f.get("kind", "?") for f in where.get("findings", []) or []}),
            "K": (fin.get("params") or {}).get("stiffness_Nm_per_rad"),
            "nrmse_pct": fin.get("nrmse_pct"),
            "baseline_nrmse_pct": (d.get("baseline") or {}).get("nrmse_pct"),
            "no_spring": fin.get("no_spring")}


def said(fit: dict) -> str:
    """What the fit named, in one line: effects, (confounded groups), unexplained, laws."""
    parts = list(fit["effects"]) + ["(" + "|".join(g) + ")" for g in fit["confounded"]]
    laws = ",".join(f"{k}:{v}" for k, v in sorted(fit["laws"].items()))
    return (f"{{{', '.join(parts)}}} unexplained={fit['unexplained']}"
            + (f" laws[{laws}]" if laws else ""))


def truth_text(truth: dict) -> str:
    """The truth in one line."""
    req = ", ".join("|".join(g) for g in truth["required"])
    opt = f" opt[{','.join(truth['optional'])}]" if truth["optional"] else ""
    return f"{{{req}}}{opt} unexplained={truth['unexplained']}"


def score_record(truth: dict, run: dict) -> dict:
    """Score one record: the five checks, what was wrong, the wall time."""
    fit = run["fit"]
    row = {"name": truth["name"], "wall_s": run["wall_s"], "truth": truth_text(truth),
           "said": said(fit) if fit else f"exit {run['rc']}: {run['stderr'][-200:]}",
           "misses": []}
    checks = {"no_crash": fit is not None, "effects": False, "unexplained": False,
              "K": None, "nrmse": False}
    if fit is None:
        row["misses"].append(f"crash/timeout (exit {run['rc']})")
        row.update(checks=checks, ok=False)
        return row
    named = set(fit["effects"]).union(*map(set, fit["confounded"])) if fit["confounded"] else set(fit["effects"])
    allowed = set(truth["optional"]).union(*map(set, truth["required"])) if truth["required"] else set(truth["optional"])
    missing = [g for g in truth["required"] if not named & set(g)]
    extra = sorted(named - allowed)
    checks["effects"] = not missing and not extra
    if missing:
        row["misses"].append("missed " + ", ".join("|".join(g) for g in missing))
    if extra:
        row["misses"].append("extra " + ", ".join(extra))
    checks["unexplained"] = truth["unexplained"] is None or fit["unexplained"] == truth["unexplained"]
    if not checks["unexplained"]:
        row["misses"].append(f"unexplained {fit['unexplained']} (truth {truth['unexplained']})")
    K_true = truth["K_Nm_per_rad"]
    row["K_err_pct"] = None if fit["K"] is None else round(100 * (fit["K"] / K_true - 1), 3)
    if truth["k_check"]:
        checks["K"] = fit["K"] is not None and abs(fit["K"] / K_true - 1) <= K_TOL
        if not checks["K"]:
            row["misses"].append(f"K {row['K_err_pct']:+.2f} %")
    b, f = fit["baseline_nrmse_pct"], fit["nrmse_pct"]
    checks["nrmse"] = b is not None and f is not None and f <= b * (1 + 1e-9)
    if not checks["nrmse"]:
        row["misses"].append(f"final NRMSE {f} > baseline {b}")
    row.update(checks=checks, ok=all(v is not False for v in checks.values()),
               nrmse=[b, f], unexplained_kinds=fit["unexplained_kinds"])
    return row
