#!/usr/bin/env python3
"""Volume of each solid of a STEP file three ways, to tell which of OCCT's figures is right.

Usage: scripts/occt_grid_volume.py FILE.step [GRID]   (GRID points per side, default 200)

Prints per solid: BRepGProp's default fixed Gauss rule (what ../shared/corpus/reference.jsonl
holds), its adaptive rule (eps 1e-8), and an independent midpoint sum of P.N/3 over a
GRID x GRID (u, v) grid of every face, classified against the face's trims with OCCT's own
IntTools_FClass2d and taken about the solid's centroid (no cancellation far from the origin).
Slow (pure Python): about a minute per 20 faces at GRID 200. Used for the bm2_ec_exhaust-A.stp
correction in crates/cadre-mesh/tests/data/reference_corrections.jsonl.
Needs: pip install cadquery-ocp-novtk
"""
import sys

from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepGProp import BRepGProp
from OCP.BRepTools import BRepTools
from OCP.GProp import GProp_GProps
from OCP.IntTools import IntTools_FClass2d
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_FACE, TopAbs_IN, TopAbs_REVERSED, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Vec


def grid_volume(solid, centre, n):
    """Midpoint sum of (P - centre).N / 3 over every face of `solid`."""
    total = 0.0
    faces = TopExp_Explorer(solid, TopAbs_FACE)
    while faces.More():
        face = TopoDS.Face(faces.Current())
        surface = BRepAdaptor_Surface(face)
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        inside = IntTools_FClass2d(face, 1e-9)
        du, dv = (u1 - u0) / n, (v1 - v0) / n
        part = 0.0
        for i in range(n):
            for j in range(n):
                u, v = u0 + (i + 0.5) * du, v0 + (j + 0.5) * dv
                if inside.Perform(gp_Pnt2d(u, v)) != TopAbs_IN:
                    continue
                p, su, sv = gp_Pnt(), gp_Vec(), gp_Vec()
                surface.D1(u, v, p, su, sv)
                normal = su.Crossed(sv)
                part += ((p.X() - centre.X()) * normal.X() + (p.Y() - centre.Y()) * normal.Y()
                         + (p.Z() - centre.Z()) * normal.Z()) / 3.0 * du * dv
        total += -part if face.Orientation() == TopAbs_REVERSED else part
        faces.Next()
    return total


def main():
    path = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    reader = STEPControl_Reader()
    reader.ReadFile(path)
    reader.TransferRoots()
    solids = TopExp_Explorer(reader.OneShape(), TopAbs_SOLID)
    totals = [0.0, 0.0, 0.0]
    k = 0
    while solids.More():
        k += 1
        solid = solids.Current()
        default = GProp_GProps()
        BRepGProp.VolumeProperties_s(solid, default)
        adaptive = GProp_GProps()
        BRepGProp.VolumeProperties_s(solid, adaptive, 1e-8)
        grid = grid_volume(solid, default.CentreOfMass(), n)
        figures = (default.Mass(), adaptive.Mass(), grid)
        totals = [t + f for t, f in zip(totals, figures)]
        print("solid %d: default rule %.1f  adaptive rule %.1f  grid %.1f" % ((k,) + figures))
        solids.Next()
    print("total:   default rule %.1f  adaptive rule %.1f  grid %.1f" % tuple(totals))


if __name__ == "__main__":
    main()
