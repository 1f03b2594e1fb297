#!/usr/bin/env python3
"""Writes the meshes of assets/scenes/lamps.xml into assets/scenes/meshes/ (standard library only):

  tilted_quad.obj    the quad [-1, 1]^2 tilted by 26.6 degrees about z: normal (2, -4, 0)
  icosphere.obj      the icosahedron subdivided once onto the unit sphere (80 faces), no normals:
                     Mitsuba (and pathlab) recompute smooth vertex normals; coarse, so that
                     shading and geometric normals differ by up to 20 degrees
  icosphere_vn.obj   the icosahedron subdivided twice (320 faces), its exact normals as `vn`

Usage: scripts/lamp_meshes.py [OUT_DIR]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from icosphere_ply import icosphere  # noqa: E402


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
