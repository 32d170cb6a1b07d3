#!/usr/bin/env python3
"""Writes crates/cadre-render/tests/data/bspline-bore.step: a 40 x 30 x 10 mm plate with an
oblique bore of radius 6 mm, every face converted to a B-spline by OCCT
(BRepBuilderAPI_NurbsConvert; the bore a rational one), as exporters that write every surface
as a B-spline do. The fixture of `trim_quadrics` (B-spline faces drawn as the planes and
cylinders they are). Needs OCP: pip install cadquery-ocp-novtk. Run from the
repository root, or give the output path.
"""
from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakeBox
from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
from OCP.gp import gp_Ax2, gp_Pnt, gp_Dir
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bspline_fixture import write_as_bspline  # noqa: E402

# A plate 40 x 30 x 10 with a bore of radius 6 through it, along an oblique axis.
box = BRepPrimAPI_MakeBox(gp_Pnt(-20, -15, 0), 40, 30, 10).Shape()
cyl = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(2, 1, -5), gp_Dir(0.2, 0.1, 1)), 6, 20).Shape()
shape = BRepAlgoAPI_Cut(box, cyl).Shape()
DEFAULT = "crates/cadre-render/tests/data/bspline-bore.step"
OUT = sys.argv[1] if len(sys.argv) > 1 else DEFAULT
write_as_bspline(shape, OUT)
