#!/usr/bin/env python3
"""Writes the signed distance grids of tests/fixtures/sdf_grids/ in Mitsuba's .vol format
(version 3, float32, one channel; little-endian; data[(z * ny + y) * nx + x]), the distances at
the nodes of a grid on the unit cube (node i at i / (n - 1)), in cells (as mitsuba-data's
torus_sdfgrid.vol stores them):

  torus.vol   24 x 24 x 24 nodes: a torus about the y axis through the cube's centre, radii 0.3
              and 0.12;
  sphere.vol  8 x 8 x 8 nodes: a sphere of radius 0.36 about the centre, so coarse that the
              cells' analytic normals show their facets and the smooth ones hide them.

Usage: scripts/sdf_grids.py OUT_DIR
"""
import math
import struct
import sys


def write(path, n, f):
    values = []
    for z in range(n):
        for y in range(n):
            for x in range(n):
                p = (x / (n - 1), y / (n - 1), z / (n - 1))
                values.append(f(p) * (n - 1))
    with open(path, "wb") as out:
        out.write(b"VOL" + bytes([3]))
        out.write(struct.pack("<iiiii", 1, n, n, n, 1))
        out.write(struct.pack("<6f", 0.0, 0.0, 0.0, 1.0, 1.0, 1.0))
        out.write(struct.pack("<%df" % len(values), *values))


def torus(p):
    x, y, z = (c - 0.5 for c in p)
    return math.hypot(math.hypot(x, z) - 0.3, y) - 0.12


def sphere(p):
    return math.dist(p, (0.5, 0.5, 0.5)) - 0.36


def main():
    out = sys.argv[1]
    write(f"{out}/torus.vol", 24, torus)
    write(f"{out}/sphere.vol", 8, sphere)


if __name__ == "__main__":
    main()
