#!/bin/sh
# The shop review's third-party reads of every package under ROOT (ROOT/<package>/parts/):
#   DXF entity counts, extents, text heights (our own group-code reader, rawdxf.py);
#   LibreCAD dxf2pdf of every DXF (LibreCAD's reader) and a PNG of each;
#   FreeCAD (freecadcmd): every DXF closed wires + area, every STEP valid/closed/volume;
#   dxf2gcode (a CAM) reading every DXF, compared with the STEP section (OCC) both ways;
#   every drawing PDF page rendered to PNG at 80 dpi (to be looked at).
# Usage: ROOT=/tmp/s8/v1 sh docs/shop_review_tools/review.sh   (outputs in ROOT/review/)
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(cd "$HERE/../.." && pwd)
OUT="$ROOT/review"
mkdir -p "$OUT/lc" "$OUT/d2g" "$OUT/png"
python3 "$HERE/rawdxf.py" "$ROOT"/*/parts/*.dxf > "$OUT/rawdxf.txt"
for f in "$ROOT"/*/parts/*.dxf; do
  pkg=$(basename "$(dirname "$(dirname "$f")")"); b=$(basename "$f" .dxf)
  cp "$f" "$OUT/lc/${pkg}_$b.dxf"
  (cd "$OUT/lc" && QT_QPA_PLATFORM=offscreen timeout 300 librecad dxf2pdf -a -m "${pkg}_$b.dxf" \
      > /dev/null 2>&1; echo "librecad ${pkg}_$b rc=$?")
  pdftoppm -r 50 -png "$OUT/lc/${pkg}_$b.pdf" "$OUT/lc/${pkg}_$b" 2>/dev/null
  echo "dxf2gcode ${pkg}_$b $(/usr/bin/python3 "$REPO/tests/export/dxf2gcode_read.py" "$f" \
      "$OUT/d2g/${pkg}_$b.json" 2>/dev/null | tail -1)"
done > "$OUT/readers.txt"
ROOT="$ROOT" OUT="$OUT/freecad.json" freecadcmd "$HERE/fc_check.py" > "$OUT/freecad.log" 2>&1
ROOT="$ROOT" D2G="$OUT/d2g" python "$HERE/d2g_vs_step.py" > "$OUT/d2g_vs_step.txt" 2>&1
for f in "$ROOT"/*/parts/*.pdf; do
  pkg=$(basename "$(dirname "$(dirname "$f")")")
  pdftoppm -r 80 -png "$f" "$OUT/png/${pkg}_$(basename "$f" .pdf)"
done
echo "done: $OUT"
