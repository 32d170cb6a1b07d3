#!/usr/bin/env python3
"""Writes crates/cadre-render/tests/data/bspline-sphere-corner.step: the corner of a sphere of
radius 25 mm cut by the planes x = 5, y = 5 and z = 5 (a spherical triangle on three quarter
discs, the shape of a corner blend), every face converted to a B-spline by OCCT
(BRepBuilderAPI_NurbsConvert; the sphere a rational one), as exporters that write every
surface as a B-spline do. A fixture of `trim_quadrics` (B-spline faces drawn as the spheres
they are). Needs OCP: pip install cadquery-ocp-novtk. Run from the repository root.
"""
from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere, BRepPrimAPI_MakeBox
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
from OCP.gp import gp_Pnt
from OCP.STEPControl import STEPControl_Writer, STEPControl_AsIs
from OCP.Interface import Interface_Static

sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 25).Shape()
box = BRepPrimAPI_MakeBox(gp_Pnt(5, 5, 5), 30, 30, 30).Shape()
shape = BRepAlgoAPI_Common(sphere, box).Shape()
nurbs = BRepBuilderAPI_NurbsConvert(shape, True).Shape()
Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
w = STEPControl_Writer()
w.Transfer(nurbs, STEPControl_AsIs)
w.Write("crates/cadre-render/tests/data/bspline-sphere-corner.step")
