#!/usr/bin/env python3
"""Writes crates/cadre-render/tests/data/bspline-sphere-corner.step: the corner of a sphere of
radius 25 mm cut by the planes x = 5, y = 5 and z = 5 (a spherical triangle on three quarter
discs, the shape of a corner blend), every face converted to a B-spline by OCCT
(BRepBuilderAPI_NurbsConvert; the sphere a rational one), as exporters that write every
surface as a B-spline do. A fixture of `trim_quadrics` (B-spline faces drawn as the spheres
they are). Needs OCP: pip install cadquery-ocp-novtk. Run from the
repository root, or give the output path.
"""
from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere, BRepPrimAPI_MakeBox
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
from OCP.gp import gp_Pnt
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bspline_fixture import write_as_bspline  # noqa: E402

sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 25).Shape()
box = BRepPrimAPI_MakeBox(gp_Pnt(5, 5, 5), 30, 30, 30).Shape()
shape = BRepAlgoAPI_Common(sphere, box).Shape()
DEFAULT = "crates/cadre-render/tests/data/bspline-sphere-corner.step"
OUT = sys.argv[1] if len(sys.argv) > 1 else DEFAULT
write_as_bspline(shape, OUT)
