"""Read a DXF with dxf2gcode's own importer (a real CAM program, no GUI).

Run with the system Python that has dxf2gcode (Debian package ``dxf2gcode``):
``python3 dxf2gcode_read.py FILE.dxf OUT.json``. Writes the points of every geometry
dxf2gcode made from layer CUT (lines by their ends, arcs sampled every 4 um, mm) and
prints the entity kinds and the number of closed contours it found.

dxf2gcode chains contours recursively, one Python frame per entity; a contour of more
than ~990 entities (the ring's outer contour has ~3,600 lines and arcs) exceeds
Python's default recursion limit, so the limit is raised here as a user would.
"""

import json
import logging
import math
import os
import sys

sys.setrecursionlimit(100000)

from PyQt5 import QtCore  # noqa: E402

_app = QtCore.QCoreApplication([])

import dxf2gcode.globals.globals as g  # noqa: E402
from dxf2gcode.globals.config import MyConfig  # noqa: E402
from dxf2gcode.globals.logger import LoggerClass  # noqa: E402

g.logger = LoggerClass(logging.getLogger())
g.folder = os.path.join(os.path.expanduser("~"), ".config/dxf2gcode")
g.config = MyConfig()

from dxf2gcode.core.arcgeo import ArcGeo  # noqa: E402
from dxf2gcode.core.linegeo import LineGeo  # noqa: E402
from dxf2gcode.dxfimport.importer import ReadDXF  # noqa: E402

STEP_MM = 0.004

dxf = ReadDXF(sys.argv[1])
names = [layer.name for layer in dxf.layers]
paths, kinds = [], {}
for ent in dxf.entities.geo:
    if names[ent.Layer_Nr] != "CUT":
        continue
    kinds[type(ent).__name__] = kinds.get(type(ent).__name__, 0) + 1
    for geo in ent.geo:
        if isinstance(geo, LineGeo):
            paths.append([[geo.Ps.x, geo.Ps.y], [geo.Pe.x, geo.Pe.y]])
        elif isinstance(geo, ArcGeo):
            n = max(2, int(math.ceil(abs(geo.ext) * geo.r / STEP_MM)) + 1)
            angles = [geo.s_ang + geo.ext * k / (n - 1) for k in range(n)]
            paths.append([[geo.O.x + geo.r * math.cos(a), geo.O.y + geo.r * math.sin(a)]
                          for a in angles])
        else:
            raise SystemExit(f"unexpected dxf2gcode geometry {type(geo).__name__}")
with open(sys.argv[2], "w") as f:
    json.dump(paths, f)
print(json.dumps({"kinds": kinds, "contours": len(dxf.entities.cont),
                  "closed": sum(bool(c.closed) for c in dxf.entities.cont)}))
