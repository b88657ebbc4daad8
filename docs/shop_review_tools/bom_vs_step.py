"""BOM mass against the FreeCAD volume of each part's STEP: mass / volume is the density the
BOM used, so a part whose STEP carries the BOM's mass gives its material's density (within the
BOM's 3-decimal rounding of grams).  Usage: python bom_vs_step.py ROOT  (after review.sh)."""
import csv
import json
import sys
from pathlib import Path

root = Path(sys.argv[1])
fc = json.loads((root / "review" / "freecad.json").read_text())
for bom in sorted(root.glob("*/bom.csv")):
    for r in csv.DictReader(bom.open()):
        step = str(bom.parent / "parts" / f"{r['part_number']}.step")
        v = fc.get(step)
        if not v:
            print(f"{bom.parent.name:12s} {r['part_number']:28s} no STEP read")
            continue
        g = float(r["mass_each_g"])
        rho = g / v["volume_mm3"] * 1e6  # g/mm^3 -> kg/m^3
        print(f"{bom.parent.name:12s} {r['part_number']:28s} {g:9.3f} g  {v['volume_mm3']:11.3f} "
              f"mm^3  {rho:7.1f} kg/m^3  valid {v['valid']} closed {v['closed']} "
              f"solids {v['n_solids']}  {r['material'][:40]}")
