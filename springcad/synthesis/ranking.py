"""Ranking of feasible stacks and the reasons infeasible families fail.

Works on the column dict of a sweep (:meth:`ResultStore.read`). Pure functions.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from springcad.synthesis.evaluate import detail

#: columns shown for a candidate (what a person needs to recognise the stack)
KEY_COLUMNS = ("cid", "family", "input", "material", "thickness_a_mm", "thickness_b_mm",
               "contact_radius_mm", "outer_radius_mm", "split", "n_flexures_a", "n_flexures_b")


def rank(cols: dict, objective_column: str, minimise: bool = True) -> np.ndarray:
    """Indices of the feasible rows, best first (ties: lighter, then lower id)."""
    idx = np.flatnonzero(cols["feasible"])
    obj = cols[objective_column][idx]
    primary = obj if minimise else -obj
    order = np.lexsort((cols["cid"][idx], cols["mass_kg"][idx], primary))
    return idx[order]


def stack_signature(r: dict) -> tuple:
    """What makes two candidate rows the same stack (a mixed row whose A and B disks are
    equal is an identical stack): input, material, R_o, r_c and the disks in order."""
    n_a, n_b, split = int(r["n_a"]), int(r["n_b"]), float(r["split"])
    K = r["target_stiffness_Nm_per_rad"]
    disks = [(r["thickness_a_mm"], round(n_a * K / split, 6), int(r["n_flexures_a"]))] * n_a
    if n_b:
        disks += [(r["thickness_b_mm"], round(n_b * K / (1 - split), 6),
                   int(r["n_flexures_b"]))] * n_b
    return (r["input"], r["material"], round(float(r["outer_radius_mm"]), 6),
            float(r["contact_radius_mm"]), tuple(disks))


def distinct(cols: dict, order, count: int) -> list[dict]:
    """The first ``count`` rows of ``order`` that are distinct stacks, as dicts."""
    out, seen = [], set()
    for i in order:
        r = row(cols, int(i))
        sig = stack_signature(r)
        if sig in seen:
            continue
        seen.add(sig)
        out.append(r)
        if len(out) == count:
            break
    return out


def row(cols: dict, i: int) -> dict:
    """Row ``i`` as a plain dict of Python values."""
    out = {}
    for k, v in cols.items():
        x = v[i]
        out[k] = x.item() if hasattr(x, "item") else x
    return out


def family_report(cols: dict, objective_column: str, minimise: bool = True) -> list[dict]:
    """Per family: how many candidates, how many feasible, the best, or why none is.

    For a family with no feasible stack: every binding constraint with its count
    and the nearest miss (smallest violation) with its numbers.
    """
    out = []
    families = cols["family"]
    order = sorted(set(families), key=lambda f: (int(cols["n_disks"][np.flatnonzero(families == f)[0]]), f))
    for fam in order:
        sel = np.flatnonzero(families == fam)
        feas = sel[cols["feasible"][sel]]
        entry = {"family": fam, "n_disks": int(cols["n_disks"][sel[0]]), "candidates": len(sel),
                 "feasible": len(feas)}
        if len(feas):
            obj = cols[objective_column][feas]
            best = feas[np.argmin(obj) if minimise else np.argmax(obj)]
            entry["best"] = {k: row(cols, best)[k] for k in
                             (*KEY_COLUMNS, objective_column, "mass_kg", "axial_length_mm")}
        else:
            counts = Counter(cols["binding"][sel])
            binding = []
            for name, count in counts.most_common():
                rows = sel[cols["binding"][sel] == name]
                v = cols["violation"][rows]
                near = rows[np.nanargmin(v)] if np.any(np.isfinite(v)) else rows[0]
                binding.append({"constraint": name, "candidates": count,
                                "nearest_miss": detail(cols, near),
                                "violation_pct": (100 * float(cols["violation"][near])
                                                  if np.isfinite(cols["violation"][near]) else None),
                                "candidate": {k: row(cols, near)[k] for k in KEY_COLUMNS}})
            entry["binding"] = binding
        out.append(entry)
    return out
