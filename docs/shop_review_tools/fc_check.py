# run with freecadcmd: checks every DXF (FreeCAD legacy importer) and STEP
import sys, glob, os, json
import FreeCAD, Part
import importDXF
p = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Draft")
p.SetBool("dxfUseLegacy", True)
p.SetBool("dxfCreatePart", True)
p.SetBool("dxfUseDraftVisGroups", False)
out = {}
root = os.environ["ROOT"]
for f in sorted(glob.glob(root + "/*/parts/*.dxf")):
    doc = FreeCAD.newDocument("d")
    importDXF.insert(f, "d")
    edges = []
    for o in doc.Objects:
        if hasattr(o, "Shape") and not o.Shape.isNull() and o.Shape.Edges:
            edges += o.Shape.Edges
    wires = Part.sortEdges(edges)
    ws = [Part.Wire(w) for w in wires]
    closed = [w.isClosed() for w in ws]
    faces = sorted([Part.Face(w) for w in ws if w.isClosed()], key=lambda fc: -fc.Area)
    area = faces[0].Area - sum(fc.Area for fc in faces[1:]) if faces else None
    bb = faces[0].BoundBox if faces else None
    out[f] = dict(n_edges=len(edges), n_wires=len(ws), all_closed=all(closed), area_mm2=area,
                  outer_bb=(bb.XMin, bb.XMax, bb.YMin, bb.YMax) if bb else None,
                  types=sorted(set(type(e.Curve).__name__ for e in edges)))
    FreeCAD.closeDocument("d")
for f in sorted(glob.glob(root + "/*/parts/*.step")) + sorted(glob.glob(root + "/*/assembly.step")):
    s = Part.Shape(); s.read(f)
    sols = s.Solids
    out[f] = dict(n_solids=len(sols), valid=s.isValid(), closed=all(x.isClosed() for x in sols),
                  volume_mm3=s.Volume, vol_sum=sum(x.Volume for x in sols),
                  bb=(s.BoundBox.XLength, s.BoundBox.YLength, s.BoundBox.ZLength),
                  surftypes=sorted({type(fc.Surface).__name__ for fc in s.Faces}))
json.dump(out, open(os.environ["OUT"], "w"), indent=1)
