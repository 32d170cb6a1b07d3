#!/usr/bin/env python3
"""Writes plate.step: the part that plate.ngc machines, written here for cadre's examples.

An 80 x 50 x 12 mm plate (corner at the origin, top at Z12) with four through holes of
diameter 8 at (10, 10), (70, 10), (70, 40), (10, 40) and a circular pocket of diameter 30 and
depth 5 at (40, 25). Exact B-Rep (planes, cylinders, circles, lines) in AP214.

    python3 examples/toolpath/make_plate_step.py   # rewrites examples/toolpath/plate.step
"""

import os

LINES = []
NEXT = [10]


def ent(text):
    """Adds entity `text`, returns its id."""
    n = NEXT[0]
    NEXT[0] += 1
    LINES.append(f"#{n}={text};")
    return n


def f(x):
    s = f"{x:.6f}".rstrip("0")
    return s if not s.endswith(".") else s + ""


def point(p):
    return ent(f"CARTESIAN_POINT('',({f(p[0])},{f(p[1])},{f(p[2])}))")


def direction(d):
    return ent(f"DIRECTION('',({f(d[0])},{f(d[1])},{f(d[2])}))")


def placement(origin, z=(0, 0, 1), x=(1, 0, 0)):
    return ent(f"AXIS2_PLACEMENT_3D('',#{point(origin)},#{direction(z)},#{direction(x)})")


VERTICES = {}


def vertex(p):
    key = tuple(round(c, 9) for c in p)
    if key not in VERTICES:
        VERTICES[key] = ent(f"VERTEX_POINT('',#{point(p)})")
    return VERTICES[key]


LINE_EDGES = {}


def line_edge(a, b):
    """The straight edge between points a and b, and whether it runs a -> b."""
    ka, kb = tuple(a), tuple(b)
    if (kb, ka) in LINE_EDGES:
        return LINE_EDGES[(kb, ka)], False
    if (ka, kb) not in LINE_EDGES:
        d = [b[i] - a[i] for i in range(3)]
        length = sum(c * c for c in d) ** 0.5
        unit = [c / length for c in d]
        vec = ent(f"VECTOR('',#{direction(unit)},{f(length)})")
        line = ent(f"LINE('',#{point(a)},#{vec})")
        LINE_EDGES[(ka, kb)] = ent(f"EDGE_CURVE('',#{vertex(a)},#{vertex(b)},#{line},.T.)")
    return LINE_EDGES[(ka, kb)], True


def circle_edge(centre, radius):
    """A full circle about +Z through its point at angle 0."""
    circle = ent(f"CIRCLE('',#{placement(centre)},{f(radius)})")
    v = vertex((centre[0] + radius, centre[1], centre[2]))
    return ent(f"EDGE_CURVE('',#{v},#{v},#{circle},.T.)")


def oriented(edge, forward):
    return ent(f"ORIENTED_EDGE('',*,*,#{edge},{'.T.' if forward else '.F.'})")


def loop(oriented_edges, outer=True):
    l = ent(f"EDGE_LOOP('',({','.join('#' + str(e) for e in oriented_edges)}))")
    kind = "FACE_OUTER_BOUND" if outer else "FACE_BOUND"
    return ent(f"{kind}('',#{l},.T.)")


def polygon_loop(corners):
    """Corners in order (counter-clockwise about the face's normal)."""
    edges = []
    for i, a in enumerate(corners):
        b = corners[(i + 1) % len(corners)]
        e, forward = line_edge(a, b)
        edges.append(oriented(e, forward))
    return loop(edges)


FACES = []


def face(name, bounds, surface, same_sense=True):
    FACES.append(
        ent(
            f"ADVANCED_FACE('{name}',({','.join('#' + str(b) for b in bounds)}),#{surface},"
            f"{'.T.' if same_sense else '.F.'})"
        )
    )


def plane(origin, normal=(0, 0, 1), x=(1, 0, 0)):
    return ent(f"PLANE('',#{placement(origin, normal, x)})")


L, W, H = 80.0, 50.0, 12.0
HOLES = [(10.0, 10.0), (70.0, 10.0), (70.0, 40.0), (10.0, 40.0)]
HOLE_R = 4.0
POCKET = (40.0, 25.0)
POCKET_R = 15.0
POCKET_FLOOR = 7.0

c = [
    (0, 0, 0), (L, 0, 0), (L, W, 0), (0, W, 0),
    (0, 0, H), (L, 0, H), (L, W, H), (0, W, H),
]

# Circles: the holes at the bottom and the top, the pocket at the top and its floor.
hole_bottom = [circle_edge((x, y, 0.0), HOLE_R) for x, y in HOLES]
hole_top = [circle_edge((x, y, H), HOLE_R) for x, y in HOLES]
pocket_top = circle_edge((POCKET[0], POCKET[1], H), POCKET_R)
pocket_floor = circle_edge((POCKET[0], POCKET[1], POCKET_FLOOR), POCKET_R)

# Top (normal +Z): the rectangle counter-clockwise; the holes and the pocket clockwise.
top_bounds = [polygon_loop([c[4], c[5], c[6], c[7]])]
top_bounds += [loop([oriented(e, False)], outer=False) for e in hole_top + [pocket_top]]
face("top", top_bounds, plane((0, 0, H)))
# Bottom (normal -Z): the same plane's sense reversed.
bottom_bounds = [polygon_loop([c[0], c[3], c[2], c[1]])]
bottom_bounds += [loop([oriented(e, True)], outer=False) for e in hole_bottom]
face("bottom", bottom_bounds, plane((0, 0, 0)), same_sense=False)
# Sides, each counter-clockwise about its outward normal.
face("front", [polygon_loop([c[0], c[1], c[5], c[4]])], plane((0, 0, 0), (0, -1, 0)))
face("right", [polygon_loop([c[1], c[2], c[6], c[5]])], plane((L, 0, 0), (1, 0, 0), (0, 1, 0)))
face("back", [polygon_loop([c[2], c[3], c[7], c[6]])], plane((0, W, 0), (0, 1, 0)))
face("left", [polygon_loop([c[3], c[0], c[4], c[7]])], plane((0, 0, 0), (-1, 0, 0), (0, 1, 0)))


def bore(name, centre, radius, z0, z1, bottom_circle, top_circle):
    """A cylindrical wall facing its axis (material outside), from z0 to z1, with its seam."""
    surface = ent(f"CYLINDRICAL_SURFACE('',#{placement((centre[0], centre[1], z0))},{f(radius)})")
    seam, _ = line_edge((centre[0] + radius, centre[1], z0), (centre[0] + radius, centre[1], z1))
    edges = [
        oriented(bottom_circle, False),
        oriented(seam, True),
        oriented(top_circle, True),
        oriented(seam, False),
    ]
    face(name, [loop(edges)], surface, same_sense=False)


for k, (x, y) in enumerate(HOLES):
    bore(f"hole {k + 1}", (x, y), HOLE_R, 0.0, H, hole_bottom[k], hole_top[k])
bore("pocket wall", POCKET, POCKET_R, POCKET_FLOOR, H, pocket_floor, pocket_top)
face(
    "pocket floor",
    [loop([oriented(pocket_floor, True)])],
    plane((POCKET[0], POCKET[1], POCKET_FLOOR)),
)

shell = ent(f"CLOSED_SHELL('',({','.join('#' + str(x) for x in FACES)}))")
brep = ent(f"MANIFOLD_SOLID_BREP('plate',#{shell})")
origin = placement((0, 0, 0))
units = NEXT[0]
LINES.append(
    f"#{units}=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{units + 4}))"
    f" GLOBAL_UNIT_ASSIGNED_CONTEXT((#{units + 1},#{units + 2},#{units + 3}))"
    " REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY'));"
)
LINES.append(f"#{units + 1}=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));")
LINES.append(f"#{units + 2}=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));")
LINES.append(f"#{units + 3}=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());")
LINES.append(
    f"#{units + 4}=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#{units + 1},"
    "'distance_accuracy_value','confusion accuracy');"
)
NEXT[0] = units + 5
rep = ent(f"ADVANCED_BREP_SHAPE_REPRESENTATION('plate',(#{brep},#{origin}),#{units})")
app = ent("APPLICATION_CONTEXT('automotive design')")
pctx = ent(f"PRODUCT_CONTEXT('',#{app},'mechanical')")
prod = ent(f"PRODUCT('plate','plate','a plate with four holes and a pocket',(#{pctx}))")
form = ent(f"PRODUCT_DEFINITION_FORMATION('','',#{prod})")
dctx = ent(f"PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')")
pdef = ent(f"PRODUCT_DEFINITION('design','',#{form},#{dctx})")
pds = ent(f"PRODUCT_DEFINITION_SHAPE('','',#{pdef})")
ent(f"SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})")

header = """ISO-10303-21;
HEADER;
/* Written by examples/toolpath/make_plate_step.py for cadre's examples: an 80 x 50 x 12 mm
   plate with four through holes of diameter 8 and a pocket of diameter 30, 5 deep; the part
   examples/toolpath/plate.ngc machines. */
FILE_DESCRIPTION(('cadre example: plate'),'2;1');
FILE_NAME('plate.step','2026-12-07T00:00:00',('cadre'),('cadre'),'make_plate_step.py','cadre','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));
ENDSEC;
DATA;
"""
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "plate.step")
with open(out, "w") as fh:
    fh.write(header + "\n".join(LINES) + "\nENDSEC;\nEND-ISO-10303-21;\n")
print(f"wrote {out} ({len(LINES)} entities)")
