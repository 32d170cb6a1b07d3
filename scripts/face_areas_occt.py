#!/usr/bin/env python3
"""Per-face exact areas from OCCT against cadre's mesh areas, matched by centroid.

Usage: scripts/face_areas_occt.py FILE.step [DEFLECTION_REL]
Runs cadre's `face_areas` example (build it first: cargo build --release -p cadre-mesh
--example face_areas) and OCCT (pip install cadquery-ocp-novtk) on the same file, and prints
the faces whose areas differ by more than 0.2 %, worst first. Faces are matched by centroid
in the part's own coordinates (OCCT's instances are un-located first), so parts placed
several times appear once.
"""
import json, math, os, subprocess, sys

from OCP.STEPControl import STEPControl_Reader
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_FACE
from OCP.TopoDS import TopoDS
from OCP.TopLoc import TopLoc_Location
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp

path = sys.argv[1]
rel = sys.argv[2] if len(sys.argv) > 2 else "0.0002"
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
target = os.environ.get("CARGO_TARGET_DIR", os.path.join(root, "target"))
out = subprocess.run([os.path.join(target, "release/examples/face_areas"), path, rel],
                     capture_output=True, text=True, check=True).stdout
ours = [json.loads(l) for l in out.splitlines() if l.startswith("{")]

r = STEPControl_Reader()
r.ReadFile(path)
r.TransferRoots()
shape = r.OneShape()
occ = []
seen = set()
ex = TopExp_Explorer(shape, TopAbs_FACE)
while ex.More():
    f = TopoDS.Face(ex.Current()).Located(TopLoc_Location())
    g = GProp_GProps()
    BRepGProp.SurfaceProperties_s(f, g)
    c = g.CentreOfMass()
    key = (round(g.Mass(), 6), round(c.X(), 4), round(c.Y(), 4), round(c.Z(), 4))
    if key not in seen:
        seen.add(key)
        occ.append((g.Mass(), (c.X(), c.Y(), c.Z())))
    ex.Next()

rows = []
for o in ours:
    best = min(occ, key=lambda q: math.dist(q[1], o["centroid"]) + abs(q[0] - o["area"]) / max(q[0], 1e-12)) if occ else None
    if best is None:
        continue
    err = (o["area"] - best[0]) / max(best[0], 1e-12)
    if abs(err) > 0.002 or not o["meshed"]:
        rows.append((abs(err), o["id"], o["area"], best[0], math.dist(best[1], o["centroid"])))
rows.sort(reverse=True)
print(f"{len(ours)} cadre faces, {len(occ)} distinct OCCT faces; {len(rows)} differ by > 0.2 %")
for e, fid, a, b, d in rows[:30]:
    print(f"  #{fid:<8} cadre {a:14.6f}  OCCT {b:14.6f}  {100 * e:8.3f} %  (centroid {d:.3g} apart)")
