import sys
from OCP.STEPControl import STEPControl_Reader
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
for f in sys.argv[1:]:
    r=STEPControl_Reader(); r.ReadFile(f); r.TransferRoots(); s=r.OneShape()
    vals=[]
    for eps in (1e-2,1e-3,1e-4,1e-6):
        p=GProp_GProps(); BRepGProp.VolumeProperties_s(s,p,eps); vals.append(round(p.Mass(),2))
    p=GProp_GProps(); BRepGProp.VolumeProperties_s(s,p); vals.append(round(p.Mass(),2))
    print(f, vals)
