#!/usr/bin/env python3
"""tests/fixtures/serialized/shapes.serialized: two shapes in Mitsuba's serialized format
(version 4, single precision, zlib; the layout of Mitsuba 3's src/shapes/serialized.cpp), written
by hand so that Mitsuba's own reader judges pathlab's: shape 0 a unit cube of 24 vertices with
normals and per-face texture coordinates, shape 1 a quad [-1, 1]^2 at z = 0 with texture
coordinates over [0, 2]. Deterministic; runs with any Python 3:

    python3 scripts/serialized_fixture.py
"""
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "serialized", "shapes.serialized")


def cube():
    positions, normals, uvs, faces = [], [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u_axis, v_axis = [(1, 2), (2, 0), (0, 1)][axis]
            base = len(positions)
            for (a, b) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                p = [0.0, 0.0, 0.0]
                p[axis] = sign
                p[u_axis] = a
                p[v_axis] = b
                positions.append(p)
                normals.append(n)
                uvs.append([(a + 1) / 2, (b + 1) / 2])
            tri = [(0, 1, 2), (0, 2, 3)] if sign > 0 else [(0, 2, 1), (0, 3, 2)]
            faces += [[base + i for i in t] for t in tri]
    return positions, normals, uvs, faces


def quad():
    positions = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]
    uvs = [[0, 0], [2, 0], [2, 2], [0, 2]]
    return positions, None, uvs, [[0, 1, 2], [0, 2, 3]]


def shape(name, positions, normals, uvs, faces):
    flags = 0x1000 | (0x0001 if normals else 0) | (0x0002 if uvs else 0)
    body = struct.pack("<I", flags) + name.encode() + b"\0" + struct.pack("<QQ", len(positions), len(faces))
    for arr in (positions, normals or [], uvs or []):
        for v in arr:
            body += struct.pack("<%df" % len(v), *v)
    for f in faces:
        body += struct.pack("<3I", *f)
    return struct.pack("<HH", 0x041C, 4) + zlib.compress(body)


if __name__ == "__main__":
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    data, offsets = b"", []
    for name, s in (("cube", cube()), ("quad", quad())):
        offsets.append(len(data))
        data += shape(name, *s)
    data += b"".join(struct.pack("<Q", o) for o in offsets) + struct.pack("<I", len(offsets))
    with open(OUT, "wb") as f:
        f.write(data)
