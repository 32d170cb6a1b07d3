#!/usr/bin/env python3
"""OCCT's tight bounding box of every STEP file in a folder, one JSON line per file.

`../shared/corpus/reference.jsonl` holds `BRepBndLib::Add(shape, box, False)`, which bounds
B-spline faces and curves by their control poles and analytic faces over their pcurves'
(u, v) boxes, so it can be tens of percent larger than the geometry. This script records
`BRepBndLib::AddOptimal(shape, box, useTriangulation=False, useShapeTolerance=False)`, the
exact extent OCCT computes from the same geometry; cadre's corpus test compares with it.

Usage: python3 scripts/occt_bbox_optimal.py FOLDER > OUT.jsonl
Needs: pip install cadquery-ocp-novtk
"""
import glob
import json
import os
import sys

from OCP.Bnd import Bnd_Box
from OCP.BRepBndLib import BRepBndLib
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader


def main():
    folder = sys.argv[1]
    for path in sorted(glob.glob(os.path.join(folder, "*"))):
        rec = {"file": os.path.basename(path)}
        try:
            reader = STEPControl_Reader()
            if reader.ReadFile(path) != IFSelect_RetDone:
                raise RuntimeError("read failed")
            reader.TransferRoots()
            shape = reader.OneShape()
            box = Bnd_Box()
            BRepBndLib.AddOptimal_s(shape, box, False, False)
            if not box.IsVoid():
                a, b = box.CornerMin(), box.CornerMax()
                rec["bbox_optimal"] = [a.X(), a.Y(), a.Z(), b.X(), b.Y(), b.Z()]
        except Exception as ex:  # keep going: one bad file must not stop the survey
            rec["error"] = repr(ex)[:200]
        print(json.dumps(rec), flush=True)


if __name__ == "__main__":
    main()
