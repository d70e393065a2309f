#!/usr/bin/env python3
"""Writes the specular Cornell boxes of `lgh bench gi` into tests/data/cornell-specular/.

The walls, their colours and the ceiling light are those of the original Cornell box in OBJ
(Guedis Cardenas and Morgan McGuire, Williams College, 2011, released into the public domain);
the two boxes are replaced by two spheres of radius 0.3, as in McGuire's CornellBox-Sphere:

- cornell-specular.obj: a mirror sphere (illum 3, Ks 0.95) on the left and a glass sphere
  (illum 7, Ni 1.5, Tf 1 1 1) on the right;
- cornell-phong-N.obj for N in 10, 100, 1000: both spheres glossy Phong (Kd 0.2, Ks 0.6, Ns N);
- cornell-phong-mirror.obj: both spheres the glossy mirror of Phong's model (Kd 0, Ks 0.95,
  Ns 1000, illum 2), the material the hierarchy erred on by 10-19% before its lobes were split.

Each sphere is 24 rings of 48 segments with the sphere's own vertex normals (vn), wound
counter-clockwise seen from outside (a closed mesh, as glass must be). Deterministic: running it
again writes the same bytes. Usage: python3 tools/scenes/cornell_specular.py [OUT_DIR]
"""
import math
import os
import sys

WALLS = {
    "floor": [(-1.01, 0.00, 0.99), (1.00, 0.00, 0.99), (1.00, 0.00, -1.04), (-0.99, 0.00, -1.04)],
    "ceiling": [(-1.02, 1.99, 0.99), (-1.02, 1.99, -1.04), (1.00, 1.99, -1.04), (1.00, 1.99, 0.99)],
    "backWall": [(-0.99, 0.00, -1.04), (1.00, 0.00, -1.04), (1.00, 1.99, -1.04), (-1.02, 1.99, -1.04)],
    "rightWall": [(1.00, 0.00, -1.04), (1.00, 0.00, 0.99), (1.00, 1.99, 0.99), (1.00, 1.99, -1.04)],
    "leftWall": [(-1.01, 0.00, 0.99), (-0.99, 0.00, -1.04), (-1.02, 1.99, -1.04), (-1.02, 1.99, 0.99)],
    "light": [(-0.24, 1.98, 0.16), (-0.24, 1.98, -0.22), (0.23, 1.98, -0.22), (0.23, 1.98, 0.16)],
}
WHITE = "0.725 0.71 0.68"
COLOURS = {
    "floor": WHITE,
    "ceiling": WHITE,
    "backWall": WHITE,
    "rightWall": "0.14 0.45 0.091",
    "leftWall": "0.63 0.065 0.05",
    "light": "0.78 0.78 0.78",
}
SPHERES = [("leftSphere", (-0.42, 0.3, -0.35)), ("rightSphere", (0.42, 0.3, 0.25))]
RADIUS, RINGS, SEGMENTS = 0.3, 24, 48


def sphere(lines, centre, first):
    """Appends a sphere's v, vn and f lines; `first` is the index of its first vertex."""
    cx, cy, cz = centre
    for i in range(RINGS + 1):
        theta = math.pi * i / RINGS
        for j in range(SEGMENTS):
            phi = 2 * math.pi * j / SEGMENTS
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            lines.append("v %.6f %.6f %.6f" % (cx + RADIUS * n[0], cy + RADIUS * n[1], cz + RADIUS * n[2]))
            lines.append("vn %.6f %.6f %.6f" % n)

    def at(i, j):
        return first + i * SEGMENTS + j % SEGMENTS

    for i in range(RINGS):
        for j in range(SEGMENTS):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            # Counter-clockwise seen from outside; the poles' degenerate halves are skipped.
            if i != 0:
                lines.append("f %d//%d %d//%d %d//%d" % (a, a, d, d, c, c))
            if i != RINGS - 1:
                lines.append("f %d//%d %d//%d %d//%d" % (a, a, c, c, b, b))
    return first + (RINGS + 1) * SEGMENTS


def obj(mtl):
    lines = ["# A Cornell box with two spheres: tools/scenes/cornell_specular.py", "mtllib " + mtl]
    vertex, normal = 1, 1
    for name, corners in WALLS.items():
        lines += ["v %.2f %.2f %.2f" % c for c in corners]
        lines += ["g " + name, "usemtl " + name, "f %d %d %d %d" % tuple(range(vertex, vertex + 4))]
        vertex += 4
    for name, centre in SPHERES:
        lines += ["g " + name, "usemtl " + name]
        # Vertex and normal indices advance together (one vn per v of a sphere).
        body = []
        end = sphere(body, centre, vertex)
        # vn indices start at `normal`, v indices at `vertex`: rewrite the faces' normals.
        shift = normal - vertex
        for line in body:
            if line.startswith("f "):
                corners = [c.split("//") for c in line[2:].split()]
                line = "f " + " ".join("%s//%d" % (v, int(n) + shift) for v, n in corners)
            lines.append(line)
        normal += end - vertex
        vertex = end
    return "\n".join(lines) + "\n"


def mtl(spheres):
    lines = ["# Materials of tools/scenes/cornell_specular.py (walls: the original Cornell box)"]
    for name, colour in COLOURS.items():
        lines += ["newmtl " + name, "Kd " + colour]
        if name == "light":
            lines.append("Ke 17 12 4")
    for (name, _), statements in zip(SPHERES, spheres):
        lines += ["newmtl " + name] + statements
    return "\n".join(lines) + "\n"


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(__file__), "..", "..", "tests", "data", "cornell-specular")
    os.makedirs(out, exist_ok=True)
    scenes = {
        "cornell-specular": [
            ["illum 3", "Kd 0 0 0", "Ks 0.95 0.95 0.95"],
            ["illum 7", "Ni 1.5", "Tf 1 1 1"],
        ]
    }
    for ns in (10, 100, 1000):
        phong = ["Kd 0.2 0.2 0.2", "Ks 0.6 0.6 0.6", "Ns %d" % ns]
        scenes["cornell-phong-%d" % ns] = [phong, phong]
    mirror = ["Kd 0 0 0", "Ks 0.95 0.95 0.95", "Ns 1000"]
    scenes["cornell-phong-mirror"] = [mirror, mirror]
    for name, spheres in scenes.items():
        with open(os.path.join(out, name + ".obj"), "w") as f:
            f.write(obj(name + ".mtl"))
        with open(os.path.join(out, name + ".mtl"), "w") as f:
            f.write(mtl(spheres))


if __name__ == "__main__":
    main()
