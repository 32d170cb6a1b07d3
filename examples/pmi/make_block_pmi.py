#!/usr/bin/env python3
"""Writes block-pmi.step: a 60 x 40 x 10 mm block with AP242 PMI, the bundled example of
`cadre render --pmi` and `--saved-view`.

- A flatness tolerance (0.05 mm, semantic) on the top face, presented by a draughting callout:
  a feature-control frame and its leader as a polyline, the frame's text as a text literal,
  in an annotation plane above the block.
- A saved view 'Top' (parallel projection looking down) showing the callout.
- A size dimension 60 +/- 0.1 mm between the end faces and datum feature A on the bottom face,
  semantic only (no presentation): cadre draws them as generated callouts.

Run: python3 examples/pmi/make_block_pmi.py (writes next to itself).
"""
import os

L, W, H = 60.0, 40.0, 10.0


def box():
    """The block's B-Rep: 8 vertices, 12 edges, 6 planar faces (ids 1-160)."""
    p = lambda i, x, y, z: f"#{i}=CARTESIAN_POINT('',({x:.1f},{y:.1f},{z:.1f}));"
    pts = [(0, 0, 0), (L, 0, 0), (L, W, 0), (0, W, 0), (0, 0, H), (L, 0, H), (L, W, H), (0, W, H)]
    out = [p(i + 1, *c) for i, c in enumerate(pts)]
    out += [f"#{11 + i}=VERTEX_POINT('',#{1 + i});" for i in range(8)]
    out += [
        "#20=DIRECTION('',(1.,0.,0.));#21=DIRECTION('',(0.,1.,0.));#22=DIRECTION('',(0.,0.,1.));",
        "#23=VECTOR('',#20,1.);#24=VECTOR('',#21,1.);#25=VECTOR('',#22,1.);",
    ]
    edges = [  # id, from, to, line origin point, vector
        (30, 11, 12, 1, 23), (32, 12, 13, 2, 24), (34, 14, 13, 4, 23), (36, 11, 14, 1, 24),
        (38, 15, 16, 5, 23), (40, 16, 17, 6, 24), (42, 18, 17, 8, 23), (44, 15, 18, 5, 24),
        (46, 11, 15, 1, 25), (48, 12, 16, 2, 25), (50, 13, 17, 3, 25), (52, 14, 18, 4, 25),
    ]
    for e, a, b, o, v in edges:
        out.append(f"#{e}=EDGE_CURVE('',#{a},#{b},#{e + 1},.T.);#{e + 1}=LINE('',#{o},#{v});")
    planes = [(60, 1, 22, 20), (62, 5, 22, 20), (64, 1, 21, 22), (66, 4, 21, 22), (68, 1, 20, 21), (70, 2, 20, 21)]
    for i, o, z, x in planes:
        out.append(f"#{i}=AXIS2_PLACEMENT_3D('',#{o},#{z},#{x});#{i + 1}=PLANE('',#{i});")
    faces = [  # face id, name, plane, same sense, oriented edges (edge, sense)
        (107, "bottom", 61, ".F.", [(36, "T"), (34, "T"), (32, "F"), (30, "F")]),
        (117, "top", 63, ".T.", [(38, "T"), (40, "T"), (42, "F"), (44, "F")]),
        (127, "front", 65, ".F.", [(30, "T"), (48, "T"), (38, "F"), (46, "F")]),
        (137, "back", 67, ".T.", [(34, "F"), (52, "T"), (42, "T"), (50, "F")]),
        (147, "left", 69, ".F.", [(46, "T"), (44, "T"), (52, "F"), (36, "F")]),
        (157, "right", 71, ".T.", [(32, "T"), (50, "T"), (40, "F"), (48, "F")]),
    ]
    for f, name, plane, sense, oes in faces:
        base = f - 6
        ids = []
        for k, (e, s) in enumerate(oes):
            out.append(f"#{base + k}=ORIENTED_EDGE('',*,*,#{e},.{s}.);")
            ids.append(f"#{base + k}")
        out.append(f"#{base + 4}=EDGE_LOOP('',({','.join(ids)}));")
        out.append(f"#{base + 5}=FACE_OUTER_BOUND('',#{base + 4},.T.);")
        out.append(f"#{f}=ADVANCED_FACE('{name}',(#{base + 5}),#{plane},{sense});")
    out.append("#160=CLOSED_SHELL('',(#107,#117,#127,#137,#147,#157));")
    out.append("#80=MANIFOLD_SOLID_BREP('block',#160);")
    return out


CONTEXT = """#900=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904))
 GLOBAL_UNIT_ASSIGNED_CONTEXT((#901,#902,#903)) REPRESENTATION_CONTEXT('',''));
#901=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#902=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#903=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#901,'distance_accuracy_value','');"""

PRODUCT = """#300=PRODUCT_DEFINITION_CONTEXT('part definition',#301,'design');
#301=APPLICATION_CONTEXT('managed model based 3d engineering');
#302=PRODUCT_CONTEXT('',#301,'mechanical');
#320=PRODUCT('block','block','',(#302));#321=PRODUCT_DEFINITION_FORMATION('','',#320);
#322=PRODUCT_DEFINITION('design','',#321,#300);#323=PRODUCT_DEFINITION_SHAPE('','',#322);
#200=ADVANCED_BREP_SHAPE_REPRESENTATION('block',(#80,#60),#900);
#324=SHAPE_DEFINITION_REPRESENTATION(#323,#200);"""

# The flatness callout: frame (two cells) 10 mm above the top face's middle, its leader down to
# the top face, and the frame's text; all in the plane z = 20 facing up.
FX, FY, FZ = 38.0, 30.0, H + 10.0
FRAME = [(FX, FY), (FX + 22, FY), (FX + 22, FY + 6), (FX, FY + 6), (FX, FY)]
DIVIDER = [(FX + 7, FY), (FX + 7, FY + 6)]


def polyline(pid, first_point, points, z):
    out, ids = [], []
    for k, (x, y) in enumerate(points):
        out.append(f"#{first_point + k}=CARTESIAN_POINT('',({x:.2f},{y:.2f},{z:.2f}));")
        ids.append(f"#{first_point + k}")
    out.append(f"#{pid}=POLYLINE('',({','.join(ids)}));")
    return out


def pmi():
    out = [
        "#1000=PRESENTATION_STYLE_ASSIGNMENT((#1001));",
        "#1001=CURVE_STYLE('',#1002,POSITIVE_LENGTH_MEASURE(0.25),#1003);",
        "#1002=DRAUGHTING_PRE_DEFINED_CURVE_FONT('continuous');",
        "#1003=COLOUR_RGB('',0.0,0.35,0.15);",
        "#1004=PRESENTATION_STYLE_ASSIGNMENT((#1005));",
        "#1005=TEXT_STYLE_WITH_BOX_CHARACTERISTICS('',#1006,(BOX_HEIGHT(3.5)));",
        "#1006=CHARACTER_GLYPH_STYLE_OUTLINE(#1001);",
    ]
    out += polyline(1010, 1011, FRAME, FZ)
    out += polyline(1020, 1021, DIVIDER, FZ)
    # Leader: from the frame's left side down to the top face.
    out += [
        "#1030=POLYLINE('',(#1031,#1032,#1033));",
        f"#1031=CARTESIAN_POINT('',({FX:.2f},{FY + 3:.2f},{FZ:.2f}));",
        f"#1032=CARTESIAN_POINT('',({FX - 8:.2f},{FY + 3:.2f},{FZ:.2f}));",
        f"#1033=CARTESIAN_POINT('',({FX - 8:.2f},{FY - 10:.2f},{H:.2f}));",
        "#1040=GEOMETRIC_CURVE_SET('frame',(#1010,#1020,#1030));",
        "#1041=ANNOTATION_CURVE_OCCURRENCE('',(#1000),#1040);",
        # The symbol (U+23E5, flatness) and the value, left of each cell.
        f"#1050=CARTESIAN_POINT('',({FX + 1.5:.2f},{FY + 1.25:.2f},{FZ:.2f}));",
        f"#1051=CARTESIAN_POINT('',({FX + 8.5:.2f},{FY + 1.25:.2f},{FZ:.2f}));",
        "#1052=DIRECTION('',(0.,0.,1.));#1053=DIRECTION('',(1.,0.,0.));",
        "#1054=AXIS2_PLACEMENT_3D('',#1050,#1052,#1053);",
        "#1055=AXIS2_PLACEMENT_3D('',#1051,#1052,#1053);",
        "#1056=DRAUGHTING_PRE_DEFINED_TEXT_FONT('ISO 3098');",
        "#1057=TEXT_LITERAL('','\\X2\\23E5\\X0\\',#1054,'baseline left',.RIGHT.,#1056);",
        "#1058=TEXT_LITERAL('','0.05',#1055,'baseline left',.RIGHT.,#1056);",
        "#1059=COMPOSITE_TEXT('',(#1057,#1058));",
        "#1060=ANNOTATION_TEXT_OCCURRENCE('',(#1004),#1059);",
        "#1061=DRAUGHTING_CALLOUT('Flatness.1',(#1041,#1060));",
        # Its annotation plane and draughting model.
        f"#1070=CARTESIAN_POINT('',(0.,0.,{FZ:.2f}));",
        "#1071=AXIS2_PLACEMENT_3D('',#1070,#1052,#1053);#1072=PLANE('',#1071);",
        "#1073=ANNOTATION_PLANE('Top notes',(#1000),#1072,(#1061));",
        "#1080=DRAUGHTING_MODEL('',(#1061,#1073,#1090),#900);",
        # The saved view: parallel, looking down. The camera placement's axis is the
        # direction of view, its y axis (axis x ref_direction) up on screen: ref_direction
        # -x puts +y up and +x right.
        f"#1085=CARTESIAN_POINT('',({L / 2:.1f},{W / 2:.1f},100.));",
        "#1086=DIRECTION('',(0.,0.,-1.));#1087=DIRECTION('',(-1.,0.,0.));",
        "#1088=AXIS2_PLACEMENT_3D('',#1085,#1086,#1087);",
        "#1089=CARTESIAN_POINT('',(0.,0.,0.));",
        "#1090=CAMERA_MODEL_D3('Top',#1088,#1091);",
        "#1091=VIEW_VOLUME(.PARALLEL.,#1089,100.,0.,.F.,0.,.F.,.F.,#1092);",
        "#1092=PLANAR_BOX('',120.,90.,#1093);",
        "#1093=AXIS2_PLACEMENT_2D('',#1094,#1095);",
        "#1094=CARTESIAN_POINT('',(-60.,-45.));#1095=DIRECTION('',(1.,0.));",
        # Semantic: flatness on the top face, presented by the callout.
        "#1100=SHAPE_ASPECT('top face','',#323,.T.);",
        "#1101=GEOMETRIC_ITEM_SPECIFIC_USAGE('','',#1100,#200,#117);",
        "#1102=(FLATNESS_TOLERANCE()GEOMETRIC_TOLERANCE('flatness','',#1103,#1100));",
        "#1103=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(0.05),#901);",
        "#1104=DRAUGHTING_MODEL_ITEM_ASSOCIATION('Flatness.1','',#1102,#1080,#1061);",
        # Semantic only: the length between the end faces, and datum A on the bottom.
        "#1110=SHAPE_ASPECT('ends','',#323,.F.);",
        "#1111=GEOMETRIC_ITEM_SPECIFIC_USAGE('','',#1110,#200,#147);",
        "#1112=GEOMETRIC_ITEM_SPECIFIC_USAGE('','',#1110,#200,#157);",
        "#1113=DIMENSIONAL_SIZE(#1110,'length');",
        "#1114=DIMENSIONAL_CHARACTERISTIC_REPRESENTATION(#1113,#1115);",
        "#1115=SHAPE_DIMENSION_REPRESENTATION('',(#1116),#900);",
        "#1116=(LENGTH_MEASURE_WITH_UNIT()MEASURE_REPRESENTATION_ITEM()"
        "MEASURE_WITH_UNIT(LENGTH_MEASURE(60.),#901)REPRESENTATION_ITEM('nominal value'));",
        "#1117=PLUS_MINUS_TOLERANCE(#1118,#1113);",
        "#1118=TOLERANCE_VALUE(#1119,#1120);",
        "#1119=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(-0.1),#901);",
        "#1120=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(0.1),#901);",
        "#1130=DATUM_FEATURE('A','',#323,.T.);",
        "#1131=GEOMETRIC_ITEM_SPECIFIC_USAGE('','',#1130,#200,#107);",
        "#1132=DATUM('A','',#323,.F.,'A');",
    ]
    return out


def main():
    lines = box() + [CONTEXT, PRODUCT] + pmi()
    text = (
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('cadre PMI example'),'2;1');\n"
        "FILE_NAME('block-pmi.step','2026-12-07T00:00:00',('cadre'),(''),'','','');\n"
        "FILE_SCHEMA(('AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF { 1 0 10303 442 1 1 4 }'));\n"
        "ENDSEC;\nDATA;\n" + "\n".join(lines) + "\nENDSEC;\nEND-ISO-10303-21;\n"
    )
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "block-pmi.step")
    with open(path, "w") as f:
        f.write(text)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
