#!/usr/bin/env python3
"""OCCT's XCAF counts of the PMI in STEP files, for `cadre info --json`'s "pmi" object.

Reads each file with STEPCAFControl_Reader in GD&T mode (OCCT's default) and prints one JSON
line per file: dimensions, tolerances, datums (datum features), datum targets, how many of
the dimensions and tolerances have a presentation (graphic PMI), and the saved views' names.
Needs `pip install cadquery-ocp-novtk`.

    python3 scripts/occt_pmi_counts.py FILE_OR_FOLDER...
"""
import json
import os
import sys

from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPCAFControl import STEPCAFControl_Reader
from OCP.TCollection import TCollection_ExtendedString
try:  # OCP 7.x names it TDF_LabelSequence, OCP 8 a generic collection
    from OCP.TDF import TDF_LabelSequence
except ImportError:
    from OCP.OCP.collections import Sequence_TDF_Label as TDF_LabelSequence
from OCP.TDataStd import TDataStd_Name
from OCP.TDocStd import TDocStd_Document
from OCP.XCAFDoc import (
    XCAFDoc_Datum,
    XCAFDoc_Dimension,
    XCAFDoc_DocumentTool,
    XCAFDoc_GeomTolerance,
    XCAFDoc_View,
)


def labels(getter):
    seq = TDF_LabelSequence()
    getter(seq)
    return [seq.Value(i + 1) for i in range(seq.Length())]


def counts(path):
    doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
    reader = STEPCAFControl_Reader()
    reader.SetGDTMode(True)
    reader.SetViewMode(True)
    reader.SetNameMode(True)
    if reader.ReadFile(path) != IFSelect_RetDone or not reader.Transfer(doc):
        return {"file": os.path.basename(path), "error": "not read"}
    tool = XCAFDoc_DocumentTool.DimTolTool_s(doc.Main())
    dims = labels(tool.GetDimensionLabels)
    tols = labels(tool.GetGeomToleranceLabels)
    datums = labels(tool.GetDatumLabels)
    presented = 0
    for lab in dims:
        # `Set` finds the label's attribute (the binding cannot fill a FindAttribute handle).
        attr = XCAFDoc_Dimension.Set_s(lab)
        if attr is not None:
            if not attr.GetObject().GetPresentation().IsNull():
                presented += 1
    for lab in tols:
        # `Set` finds the label's attribute (the binding cannot fill a FindAttribute handle).
        attr = XCAFDoc_GeomTolerance.Set_s(lab)
        if attr is not None:
            if not attr.GetObject().GetPresentation().IsNull():
                presented += 1
    targets = 0
    for lab in datums:
        # `Set` finds the label's attribute (the binding cannot fill a FindAttribute handle).
        attr = XCAFDoc_Datum.Set_s(lab)
        if attr is not None:
            if attr.GetObject().IsDatumTarget():
                targets += 1
    views = []
    view_tool = XCAFDoc_DocumentTool.ViewTool_s(doc.Main())
    for lab in labels(view_tool.GetViewLabels):
        # `Set` finds the label's attribute (the binding cannot fill a FindAttribute handle).
        attr = XCAFDoc_View.Set_s(lab)
        if attr is not None:
            name = attr.GetObject().Name()
            views.append(name.ToCString() if name is not None else "")
    return {
        "file": os.path.basename(path),
        "dimensions": len(dims),
        "tolerances": len(tols),
        "datums": len(datums) - targets,
        "datum_targets": targets,
        "presented": presented,
        "saved_views": views,
    }


def main():
    paths = []
    for arg in sys.argv[1:]:
        if os.path.isdir(arg):
            paths += sorted(
                os.path.join(arg, f)
                for f in os.listdir(arg)
                if f.lower().endswith((".stp", ".step"))
            )
        else:
            paths.append(arg)
    for p in paths:
        print(json.dumps(counts(p)), flush=True)


if __name__ == "__main__":
    main()
