#!/usr/bin/env python3
"""The mesh of tests/fixtures/mesh_attributes/: a wavy 7 x 7 grid over [-1, 1]^2 (72 triangles:
more than the 64 that small scenes unroll, so the kernel's BVH path finds it), written as ASCII
PLY with Mitsuba's attribute naming (src/shapes/ply.h, find_other_fields):

- per vertex `r g b` as float: `vertex_color` (floats: Mitsuba 3.9.1 reads integer colour
  fields as the integers themselves, 0-255, with a warning);
- per face `color_0 color_1 color_2` as float: `face_color`;
- per face `weight_0` as float: `face_weight`, one channel (a blend weight in the fixture).

Fixed seed, so the file is reproducible: python3 scripts/mesh_attribute_ply.py
tests/fixtures/mesh_attributes/grid.ply
"""
import math
import random
import sys

N = 7
rng = random.Random(20261205)
vertices = []
for j in range(N):
    for i in range(N):
        x = -1 + 2 * i / (N - 1)
        y = -1 + 2 * j / (N - 1)
        z = 0.15 * math.sin(2.5 * x) * math.cos(2.0 * y)
        vertices.append((x, y, z, *(round(rng.uniform(0.05, 0.95), 4) for _ in range(3))))
faces = []
for j in range(N - 1):
    for i in range(N - 1):
        a, b, c, d = j * N + i, j * N + i + 1, (j + 1) * N + i + 1, (j + 1) * N + i
        for tri in ((a, b, c), (a, c, d)):
            faces.append((tri, [round(rng.uniform(0.05, 0.95), 4) for _ in range(3)], round(rng.uniform(0, 1), 4)))

lines = [
    "ply",
    "format ascii 1.0",
    "comment scripts/mesh_attribute_ply.py: vertex_color, face_color and face_weight",
    f"element vertex {len(vertices)}",
    "property float x", "property float y", "property float z",
    "property float r", "property float g", "property float b",
    f"element face {len(faces)}",
    "property list uchar int vertex_indices",
    "property float color_0", "property float color_1", "property float color_2",
    "property float weight_0",
    "end_header",
]
lines += [f"{x:.6f} {y:.6f} {z:.6f} {r} {g} {b}" for x, y, z, r, g, b in vertices]
lines += [f"3 {t[0]} {t[1]} {t[2]} {c[0]} {c[1]} {c[2]} {w}" for t, c, w in faces]
with open(sys.argv[1], "w") as f:
    f.write("\n".join(lines) + "\n")
