#!/usr/bin/env python3
"""Writes the meshes of assets/scenes/lamps.xml into assets/scenes/meshes/ (standard library only):

  tilted_quad.obj    the quad [-1, 1]^2 tilted by 26.6 degrees about z: normal (2, -4, 0)
  icosphere.obj      the icosahedron subdivided once onto the unit sphere (80 faces), no normals:
                     Mitsuba (and pathlab) recompute smooth vertex normals; coarse, so that
                     shading and geometric normals differ by up to 20 degrees
  icosphere_vn.obj   the icosahedron subdivided twice (320 faces), its exact normals as `vn`

Usage: scripts/lamp_meshes.py [OUT_DIR]
"""
import math
import os
import sys


def icosphere(k):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def unit(p):
        n = math.sqrt(sum(c * c for c in p))
        return tuple(c / n for c in p)

    v = [unit(p) for p in v]
    for _ in range(k):
        mids = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                v.append(unit(tuple((v[a][i] + v[b][i]) / 2 for i in range(3))))
                mids[key] = len(v) - 1
            return mids[key]

        g = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return v, f


def write(path, text):
    with open(path, "w") as out:
        out.write(text)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "assets", "scenes", "meshes")
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "tilted_quad.obj"),
          "# The quad [-1, 1]^2 tilted by 26.6 degrees about z: winding normal (2, -4, 0)\n"
          "v -1 -0.5 -1\nv 1 0.5 -1\nv 1 0.5 1\nv -1 -0.5 1\nf 1 2 3 4\n")
    def header(f):
        return "# Icosphere: the icosahedron subdivided onto the unit sphere, %d faces, outward\n" % len(f)

    def vertices(v):
        return "".join("v %.9f %.9f %.9f\n" % p for p in v)

    v, f = icosphere(1)
    write(os.path.join(out, "icosphere.obj"), header(f) + vertices(v) + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in f))
    v, f = icosphere(2)
    write(os.path.join(out, "icosphere_vn.obj"), header(f) + "# with its exact normals\n" + vertices(v)
          + "".join("vn %.9f %.9f %.9f\n" % p for p in v)
          + "".join("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in f))


if __name__ == "__main__":
    main()
