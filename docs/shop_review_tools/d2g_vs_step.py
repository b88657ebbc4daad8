"""dxf2gcode's reading of each DXF against the STEP solid's cross-section (OCC), both ways.

Environment: ROOT (folder of the built packages, ROOT/<package>/parts/<PN>.step) and D2G
(folder of dxf2gcode_read.py outputs named <package>_<PN>.json)."""
import json, glob, os
import numpy as np
from scipy.spatial import cKDTree
from OCP.STEPControl import STEPControl_Reader
from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
from OCP.gp import gp_Pln, gp_Pnt, gp_Dir
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_EDGE
from OCP.TopoDS import TopoDS
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.GCPnts import GCPnts_UniformAbscissa
from OCP.Bnd import Bnd_Box
from OCP.BRepBndLib import BRepBndLib
ROOT, D2G = os.environ['ROOT'], os.environ['D2G']
for j in sorted(glob.glob(f'{D2G}/*.json')):
    d, b = os.path.basename(j)[:-5].rsplit('_', 1)
    r = STEPControl_Reader(); r.ReadFile(f'{ROOT}/{d}/parts/{b}.step'); r.TransferRoots(); s = r.OneShape()
    box = Bnd_Box(); BRepBndLib.Add_s(s, box); cmin, cmax = box.CornerMin(), box.CornerMax(); z0, z1 = cmin.Z(), cmax.Z()
    z = z1 - 0.3 if 'CAM' in b else 0.5 * (z0 + z1)
    sec = BRepAlgoAPI_Section(s, gp_Pln(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1))); sec.Build()
    ref = []
    ex = TopExp_Explorer(sec.Shape(), TopAbs_EDGE)
    while ex.More():
        c = BRepAdaptor_Curve(TopoDS.Edge(ex.Current()))
        u = GCPnts_UniformAbscissa(c, 0.002)
        for k in range(1, u.NbPoints() + 1):
            p = c.Value(u.Parameter(k)); ref.append((p.X(), p.Y()))
        ex.Next()
    ref = np.array(ref)
    data = json.load(open(j)); paths = data['paths'] if isinstance(data, dict) else data
    # dxf2gcode_read.py writes a line by its two ends: sample it every 2 um like the arcs, or
    # a STEP point in the middle of a long line (the cam's D flat) looks half a line away
    pts = np.array([q for path in paths for a, b in zip(path[:-1], path[1:])
                    for q in np.linspace(a, b, max(2, int(np.hypot(b[0] - a[0], b[1] - a[1])
                                                            / 0.002) + 1))])
    d1, _ = cKDTree(ref).query(pts); d2, _ = cKDTree(pts).query(ref)
    print(f'{d:8s} {b:26s} z {z:6.2f} dxf2gcode pts {len(pts):7d} -> STEP max {d1.max()*1000:6.2f} um; STEP pts {len(ref):7d} -> dxf2gcode max {d2.max()*1000:6.2f} um', flush=True)
