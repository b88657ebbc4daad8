"""Bill of materials of a stack (CSV): one row per distinct part.

Quantities count the placed instances; masses come from the solids (exact
volume x density). Units: mm, g.
"""

from __future__ import annotations

import csv
from pathlib import Path

from springcad.design.processes import process_chain_text
from springcad.export.sheet import fmt
from springcad.export.skeleton import part_volume_mm3
from springcad.units import G_PER_KG, KG_PER_MM3_PER_KG_PER_M3

COLUMNS = ("item", "part_number", "name", "title", "kind", "quantity", "make_or_buy", "process",
           "material", "heat_treatment", "standard", "stock", "thickness_or_length_mm",
           "mass_each_g", "mass_total_g", "instances", "files")


def bom_rows(assembly, files_by_part: dict | None = None) -> list[dict]:
    """BOM rows, input side first (order of first appearance in the stack)."""
    files_by_part = files_by_part or {}
    qty = assembly.quantities()
    names: dict[str, list[str]] = {}
    for inst in assembly.instances:
        names.setdefault(inst.part.part_number, []).append(inst.name)
    rows = []
    for item, pn in enumerate(names, 1):
        part = assembly.parts[pn]
        info = part.info
        mass = (part_volume_mm3(part) * info.density_kg_per_m3
                * KG_PER_MM3_PER_KG_PER_M3 * G_PER_KG)  # g
        rows.append({
            "item": item, "part_number": pn, "name": info.name, "title": info.title, "kind": info.kind,
            "quantity": qty[pn], "make_or_buy": "buy" if info.process == "purchased" else "make",
            "process": process_chain_text(info.process, info.secondary_processes),
            "material": info.material,
            "heat_treatment": info.heat_treatment, "standard": info.standard, "stock": info.stock,
            "thickness_or_length_mm": fmt(info.thickness_mm),
            "mass_each_g": f"{mass:.3f}", "mass_total_g": f"{mass * qty[pn]:.3f}",
            "instances": " ".join(names[pn]), "files": " ".join(files_by_part.get(pn, [])),
        })
    return rows


def write_bom(assembly, path: Path, files_by_part: dict | None = None) -> Path:
    """Write the BOM CSV; returns the path."""
    rows = bom_rows(assembly, files_by_part)
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    return Path(path)
