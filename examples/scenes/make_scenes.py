#!/usr/bin/env python3
"""Writes the thesis' test scenes (seed 001) as cadre scene files (docs/scene-format.md).

The thesis (Nyiri, Lille 1994) names four scenes: a teapot of 9 surface quadrics and 1
volume, a robot of 39 quadrics under a point light and a spot, a DNA fragment of 483 spheres
under 2 point lights, and "Mandala" of 4,000 spheres. Their data are not published; these are
our reconstructions with the same primitive counts and lights. The teapot is hand-written
(teapot.json); this script writes the other three, deterministically:

    python3 examples/scenes/make_scenes.py
"""

import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, scene):
    """One object or light per line."""
    lines = ["{"]
    keys = list(scene)
    for i, key in enumerate(keys):
        value = scene[key]
        end = "," if i + 1 < len(keys) else ""
        if isinstance(value, list):
            lines.append(f' "{key}": [')
            for j, item in enumerate(value):
                comma = "," if j + 1 < len(value) else ""
                lines.append("  " + json.dumps(item, separators=(", ", ": ")) + comma)
            lines.append(" ]" + end)
        else:
            lines.append(f' "{key}": ' + json.dumps(value, separators=(", ", ": ")) + end)
    lines.append("}")
    with open(os.path.join(HERE, name), "w") as f:
        f.write("\n".join(lines) + "\n")


def r(v, n=4):
    return [round(x, n) for x in v]


def slab(z0, z1):
    """Keeps z0 <= z <= z1 (in the object's frame)."""
    return [[0, 0, 1, -z1], [0, 0, -1, z0]]


def sphere(centre, radius, colour):
    return {"shape": {"sphere": radius}, "origin": r(centre), "colour": colour}


def dna():
    """A B-DNA fragment: 60 base pairs, 10 per turn, 3.4 apart along z; per pair two
    phosphates, two sugars and two bases per strand (8 spheres), and 3 end atoms: 483."""
    objects = []
    phosphate, sugar = [0.95, 0.55, 0.1], [0.85, 0.85, 0.8]
    bases = [[0.2, 0.45, 0.9], [0.9, 0.25, 0.25], [0.25, 0.75, 0.3], [0.95, 0.85, 0.2]]
    for i in range(60):
        a = math.radians(36.0 * i)
        z = 3.4 * i
        for strand, offset in ((0, 0.0), (1, math.radians(144.0))):
            b = a + offset
            objects.append(sphere([9.0 * math.cos(b), 9.0 * math.sin(b), z], 1.9, phosphate))
            objects.append(sphere([6.6 * math.cos(b + 0.25), 6.6 * math.sin(b + 0.25), z + 0.6], 1.5, sugar))
            for k, rad in enumerate((4.4, 2.2)):
                c = bases[(i + 2 * strand + k) % 4]
                objects.append(sphere([rad * math.cos(b + 0.45), rad * math.sin(b + 0.45), z + 0.9], 1.35, c))
    for k in range(3):
        objects.append(sphere([0.0, 0.0, -3.0 - 2.6 * k], 1.2, [0.6, 0.6, 0.65]))
    assert len(objects) == 483
    return {
        "shadows": True,
        "camera": {"eye": [95, -80, 130], "target": [0, 0, 100], "up": [0, 0, 1], "fov": 62},
        "lights": [
            {"point": {"position": [80, -60, 220], "intensity": [22000, 21000, 20000]}},
            {"point": {"position": [-90, 40, 20], "intensity": [9000, 9500, 11000]}},
        ],
        "objects": objects,
    }


def mandala():
    """4,000 spheres in 25 rings of 160 with a 16-fold pattern of sizes and heights."""
    objects = []
    for ring in range(25):
        radius = 6.0 + 4.0 * ring
        for k in range(160):
            a = 2.0 * math.pi * k / 160.0
            petal = 0.5 + 0.5 * math.cos(16.0 * a + ring * 0.7)
            size = 0.45 + 1.1 * petal * (1.0 - ring / 40.0)
            z = 2.5 * math.sin(8.0 * a) * math.sin(ring * 0.5)
            hue = (ring / 25.0 + 0.3 * petal) % 1.0
            colour = [
                round(0.5 + 0.5 * math.cos(2 * math.pi * hue), 3),
                round(0.5 + 0.5 * math.cos(2 * math.pi * (hue - 1 / 3)), 3),
                round(0.5 + 0.5 * math.cos(2 * math.pi * (hue - 2 / 3)), 3),
            ]
            objects.append(sphere([radius * math.cos(a), radius * math.sin(a), z], round(size, 3), colour))
    assert len(objects) == 4000
    return {
        "camera": {"eye": [0, -150, 190], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 40},
        "objects": objects,
    }


def robot():
    """A robot of 39 quadrics: cylinders and cones between planes, spheres, ellipsoids,
    a paraboloid lamp and hyperboloid joints; a point light and a spot."""
    steel, dark, red, glass = [0.7, 0.72, 0.75], [0.25, 0.27, 0.3], [0.8, 0.15, 0.1], [0.3, 0.7, 0.95]
    objects = []

    def cyl(base, axis, radius, length, colour, volume=True):
        objects.append({"shape": {"cylinder": radius}, "planes": slab(0, length), "volume": volume,
                        "origin": r(base), "axis": r(axis), "colour": colour})

    def cone(apex, axis, slope, z0, z1, colour):
        objects.append({"shape": {"cone": [slope, slope, 1]}, "planes": slab(z0, z1), "volume": True,
                        "origin": r(apex), "axis": r(axis), "colour": colour})

    def ball(c, radius, colour):
        objects.append(sphere(c, radius, colour))

    def ellipsoid(c, radii, colour, axis=(0, 0, 1), cut=None):
        o = {"shape": {"ellipsoid": radii}, "origin": r(c), "axis": list(axis), "colour": colour}
        if cut is not None:
            o["planes"] = cut
            o["volume"] = True
        objects.append(o)

    # Base and body.
    cyl([0, 0, 0], [0, 0, 1], 3.0, 0.4, dark)                                   # 1
    cyl([0, 0, 0.4], [0, 0, 1], 0.5, 1.2, steel)                                 # 2
    objects.append({"shape": {"hyperboloid_one_sheet": [0.45, 0.45, 0.5]}, "planes": slab(-0.6, 0.6),
                    "origin": [0, 0, 2.2], "colour": steel})                     # 3 waist
    cyl([0, 0, 2.8], [0, 0, 1], 1.2, 2.0, red)                                   # 4 torso
    ellipsoid([0, 0, 4.8], [1.2, 1.2, 0.5], red, cut=[[0, 0, -1, 0]])           # 5 shoulders dome
    objects.append({"shape": {"elliptic_paraboloid": [0.5, 0.5]}, "planes": [[0, 0, 1, -0.35]],
                    "origin": [0, -1.15, 3.9], "axis": [0, 1, 0], "colour": glass})  # 6 chest lamp
    cyl([0, 0, 5.2], [0, 0, 1], 0.25, 0.5, steel)                                # 7 neck
    ball([0, 0, 6.2], 0.75, steel)                                               # 8 head
    ball([0.3, -0.65, 6.35], 0.14, glass)                                        # 9 eye
    ball([-0.3, -0.65, 6.35], 0.14, glass)                                       # 10 eye
    cyl([0, 0, 6.9], [0, 0, 1], 0.05, 0.7, dark)                                 # 11 antenna
    ball([0, 0, 7.65], 0.12, red)                                                # 12 antenna tip
    cone([0.95, 0, 6.2], [1, 0, 0], 0.6, -0.3, 0.0, dark)                        # 13 ear (apex out)
    cone([-0.95, 0, 6.2], [-1, 0, 0], 0.6, -0.3, 0.0, dark)                      # 14 ear
    objects.append({"shape": {"hyperbolic_paraboloid": [0.5, 0.5]},
                    "planes": [[1, 0, 0, -0.3], [-1, 0, 0, -0.3], [0, 1, 0, -0.1], [0, -1, 0, -0.1]],
                    "origin": [0, -0.7, 5.85], "axis": [0, -1, 0], "x": [1, 0, 0], "colour": dark})  # 15 mouth
    # Arms: shoulder, upper arm, elbow, forearm, hand, two fingers (7 each).
    for side in (1, -1):
        sx = 1.55 * side
        ball([sx, 0, 4.5], 0.45, steel)                                          # 16, 23
        cyl([sx, 0, 4.4], [0.25 * side, -0.2, -1], 0.28, 1.4, red)               # 17, 24
        elbow = [sx + 0.35 * side, -0.28, 3.05]
        ball(elbow, 0.32, steel)                                                 # 18, 25
        cone([elbow[0] + 0.1 * side, elbow[1] - 2.6, elbow[2] + 0.9], [-0.04 * side, 1, -0.35], 0.12, 0.6, 2.5, red)  # 19, 26
        hand = [elbow[0] + 0.1 * side, elbow[1] - 1.5, elbow[2] + 0.5]
        ellipsoid(hand, [0.3, 0.22, 0.18], steel)                                # 20, 27
        cyl([hand[0] + 0.1, hand[1] - 0.15, hand[2]], [0, -1, 0.1], 0.06, 0.4, dark)  # 21, 28
        cyl([hand[0] - 0.1, hand[1] - 0.15, hand[2]], [0, -1, 0.1], 0.06, 0.4, dark)  # 22, 29
    # Legs on the base: hip, thigh, knee, shin, foot (5 each).
    for side in (1, -1):
        lx = 0.7 * side
        ball([lx, 0, 2.75], 0.35, steel)                                         # 30, 35
        cyl([lx, 0, 2.6], [0.05 * side, 0, -1], 0.25, 0.9, dark)                 # 31, 36
        ball([lx + 0.05 * side, 0, 1.55], 0.28, steel)                           # 32, 37
        cone([lx + 0.1 * side, 0, -0.6], [0, 0, 1], 0.12, 1.1, 2.1, dark)        # 33, 38
        ellipsoid([lx + 0.1 * side, -0.2, 0.55], [0.35, 0.6, 0.25], red, cut=[[0, 0, -1, -0.1]])  # 34, 39
    assert len(objects) == 39, len(objects)
    return {
        "shadows": True,
        "camera": {"eye": [9, -14, 8], "target": [0, 0, 3.6], "up": [0, 0, 1], "fov": 35},
        "lights": [
            {"point": {"position": [6, -8, 12], "intensity": [320, 310, 300]}},
            {"spot": {"position": [-5, -6, 10], "axis": [0.45, 0.55, -0.7], "intensity": [420, 400, 380],
                      "inner": 12, "outer": 22}},
        ],
        "objects": objects,
    }


if __name__ == "__main__":
    write("dna.json", dna())
    write("mandala.json", mandala())
    write("robot.json", robot())
