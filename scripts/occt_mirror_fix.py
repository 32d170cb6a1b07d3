#!/usr/bin/env python3
"""An OCCT figure for a solid whose face OCCT misreads, when the solid is mirror symmetric:
the solid's faces with the misread one replaced by the mirror image of its twin, sewn, and
measured (area, volume) with OCCT's own BRepGProp.

Usage: scripts/occt_mirror_fix.py FILE.step SOLID_INDEX BAD_AREA TWIN_AREA [NX,NY,NZ] [CX,CY,CZ]
  SOLID_INDEX: the solid's place in OCCT's explorer order; BAD_AREA, TWIN_AREA: the areas of
  the misread face and of its twin (matched within 0.5 mm2); the mirror plane through
  (CX, CY, CZ) with normal (NX, NY, NZ), default the plane y = 0.
Used for the corrections of trj3_s1-ct-214.stp and trj5_s1-in-214.stp
(crates/cadre-mesh/tests/data/reference_corrections.jsonl). Needs: pip install cadquery-ocp-novtk
"""
import sys
from OCP.STEPControl import STEPControl_Reader
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_SOLID, TopAbs_FACE
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
from OCP.TopoDS import TopoDS
from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing, BRepBuilderAPI_Transform, BRepBuilderAPI_MakeSolid
from OCP.gp import gp_Trsf, gp_Ax2, gp_Pnt, gp_Dir
from OCP.BRepCheck import BRepCheck_Analyzer
path, idx, bad_area, twin_area = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]); nrm=[float(x) for x in (sys.argv[5] if len(sys.argv)>5 else "0,1,0").split(",")]; ctr=[float(x) for x in (sys.argv[6] if len(sys.argv)>6 else "0,0,0").split(",")]
r=STEPControl_Reader(); r.ReadFile(path); r.TransferRoots(); s=r.OneShape()
e=TopExp_Explorer(s, TopAbs_SOLID); i=0
def area(f):
    g=GProp_GProps(); BRepGProp.SurfaceProperties_s(f,g); return g.Mass()
while e.More():
    if i==idx:
        faces=[]; f=TopExp_Explorer(e.Current(),TopAbs_FACE)
        while f.More(): faces.append(TopoDS.Face(f.Current())); f.Next()
        twin=[x for x in faces if abs(area(x)-twin_area)<0.5][0]
        keep=[x for x in faces if abs(area(x)-bad_area)>0.5]
        t=gp_Trsf(); t.SetMirror(gp_Ax2(gp_Pnt(*ctr), gp_Dir(*nrm)))
        m=BRepBuilderAPI_Transform(twin,t,True).Shape()
        sew=BRepBuilderAPI_Sewing(1e-4)
        for x in keep: sew.Add(x)
        sew.Add(m); sew.Perform(); sh=sew.SewedShape()
        print('sewn shape type', sh.ShapeType(), 'free edges', sew.NbFreeEdges())
        from OCP.TopAbs import TopAbs_SHELL
        ex=TopExp_Explorer(sh,TopAbs_SHELL); shell=TopoDS.Shell(ex.Current())
        so=BRepBuilderAPI_MakeSolid(shell).Solid()
        g=GProp_GProps(); BRepGProp.VolumeProperties_s(so,g)
        print('area', area(so), 'volume', g.Mass(), 'valid', BRepCheck_Analyzer(so).IsValid())
    i+=1; e.Next()
