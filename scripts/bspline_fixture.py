"""Shared by the make_bspline_*.py fixture scripts: writes a shape to STEP with every face
converted to a B-spline by OCCT (BRepBuilderAPI_NurbsConvert; quadrics become rational
B-splines), as exporters that write every surface as a B-spline do. Needs OCP:
pip install cadquery-ocp-novtk.
"""
from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
from OCP.STEPControl import STEPControl_Writer, STEPControl_AsIs
from OCP.Interface import Interface_Static


def write_as_bspline(shape, path):
    """Writes `shape`, every face a B-spline, to the AP214 STEP file `path`."""
    nurbs = BRepBuilderAPI_NurbsConvert(shape, True).Shape()
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    w = STEPControl_Writer()
    w.Transfer(nurbs, STEPControl_AsIs)
    w.Write(path)
