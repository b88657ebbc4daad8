"""Plain-text views of a synthesis run, what ``springcad synthesize`` prints: the best
screened stacks with their full designs, and the per-family feasibility report.

The run itself (:class:`springcad.synthesis.pipeline.SynthesisResult`, the family report
of :func:`springcad.synthesis.ranking.family_report`) holds data only. Units: g, mm, MPa.
"""

from __future__ import annotations

from springcad.synthesis.pipeline import SynthesisResult
from springcad.units import G_PER_KG

__all__ = ["format_family_report", "summary_table"]


def summary_table(result: SynthesisResult, n: int = 10) -> str:
    """The best screened stacks (every finalist, at least ``n``) as plain text, with the
    full design's mass and predicted peak, or why it failed."""
    req = result.requirements
    col = req.objective_column
    full = {f["cid"]: f for f in result.finalists}
    rows = [("rank", "cid", "family", "input", "z mm", "r_c", "R_o", "N", "mass g", "h mm",
             "peak MPa", col, "full design")]
    for k, r in enumerate(result.top[:max(n, len(result.finalists))], 1):
        f = full.get(int(r["cid"]))
        fd = ("-" if f is None else
              f"{G_PER_KG * f['mass_kg']:.1f} g, {f['peak_stress_MPa']:.0f} MPa" if f["ok"]
              else f"FAIL ({f['failure']})")
        z = f"{r['thickness_a_mm']:g}" + (f"/{r['thickness_b_mm']:g}" if r["n_b"] else "")
        n_fl = f"{r['n_flexures_a']}" + (f"/{r['n_flexures_b']}" if r["n_b"] else "")
        rows.append((str(k), str(r["cid"]), r["family"], r["input"], z,
                     f"{r['contact_radius_mm']:g}", f"{r['outer_radius_mm']:.2f}", n_fl,
                     f"{G_PER_KG * r['mass_kg']:.1f}", f"{r['axial_length_mm']:.1f}",
                     f"{r['peak_stress_MPa']:.0f}", f"{r[col]:.4g}", fd))
    w = [max(len(x[i]) for x in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.rjust(k) for c, k in zip(x, w)) for x in rows)


def format_family_report(report: list[dict], objective_column: str) -> str:
    """The family report as plain text lines."""
    lines = []
    for e in report:
        head = f"{e['family']:>14s}: {e['feasible']:6d} / {e['candidates']:6d} feasible"
        if e["feasible"]:
            b = e["best"]
            lines.append(f"{head}; best {objective_column} {b[objective_column]:.4g} "
                         f"(mass {G_PER_KG * b['mass_kg']:.1f} g, {b['axial_length_mm']:.1f} mm)")
            continue
        lines.append(f"{head}; fails on:")
        for c in e["binding"][:3]:
            cand = c["candidate"]
            where = (f"z {cand['thickness_a_mm']:g}"
                     + (f"/{cand['thickness_b_mm']:g}" if cand["thickness_b_mm"] else "")
                     + f" mm, r_c {cand['contact_radius_mm']:g} mm, R_o {cand['outer_radius_mm']:.2f} mm")
            lines.append(f"{'':16s}{c['constraint']} ({c['candidates']} candidates); nearest miss "
                         f"[{where}]: {c['nearest_miss']}")
    return "\n".join(lines)
