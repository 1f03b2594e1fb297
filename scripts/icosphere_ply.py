#!/usr/bin/env python3
"""Writes a subdivided icosphere as a binary little-endian PLY: 20 * 4^k triangles.

Usage: scripts/icosphere_ply.py SUBDIVISIONS OUT.ply [RADIUS] [--normals]
Used by scripts/triangle_scaling.sh (how BVH traversal cost grows with triangle count); with
--normals each vertex also has its unit normal (nx, ny, nz), the sphere's: a smooth-shaded mesh
whose shading normals differ from its faces' (tests/fixtures/dielectric_normals).
Standard library only (k = 8, 1.3 M triangles, takes about half a minute).
"""
import math
import struct
import sys


def icosphere(k):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def unit(p):
        n = math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
        return (p[0] / n, p[1] / n, p[2] / n)

    v = [unit(p) for p in v]
    for _ in range(k):
        # The midpoint of every edge, shared by the edge's two faces.
        mids = {}

        def mid(a, b):
            key = (a, b) if a < b else (b, a)
            if key not in mids:
                pa, pb = v[a], v[b]
                v.append(unit((pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2])))
                mids[key] = len(v) - 1
            return mids[key]

        out = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = out
    return v, f


def main():
    args = [a for a in sys.argv[1:] if a != "--normals"]
    normals = "--normals" in sys.argv[1:]
    k, path = int(args[0]), args[1]
    radius = float(args[2]) if len(args) > 2 else 1.0
    v, f = icosphere(k)
    normal_props = "property float nx\nproperty float ny\nproperty float nz\n" if normals else ""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\n"
              f"property float z\n{normal_props}element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, 'wb') as out:
        out.write(header.encode())
        if normals:
            out.write(b''.join(struct.pack('<6f', *(radius * c for c in p), *p) for p in v))
        else:
            out.write(b''.join(struct.pack('<3f', *(radius * c for c in p)) for p in v))
        out.write(b''.join(struct.pack('<B3i', 3, *t) for t in f))


if __name__ == "__main__":
    main()
