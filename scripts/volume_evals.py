#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `volume` texture (around a `gridvolume`) evaluated at fixed world points:
the fixture of tests/volume_textures.rs's check that pathlab's grid lookups (the .vol layout, the
cell centres, trilinear and nearest filtering, the repeat, mirror and clamp wrap modes, the
volume's to_world, use_grid_bbox, one and three channels, eval_1 as luminance) are Mitsuba's. Run
once with the reference renderer's venv (../shared/reference-renderer), after
scripts/volume_grids.py:

    /tmp/mitsuba-venv/bin/python scripts/volume_evals.py

It writes tests/fixtures/volume/volume_evals.json: per configuration (file, filter_type,
wrap_mode, use_grid_bbox, to_world as three rows of four) the points, Mitsuba's eval (RGB) and
eval_1 at each (llvm_ad_rgb, the variant of the reference renders)."""
import json
import os
import sys

import numpy as np
import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "volume")

IDENTITY = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]
PLACED = [[1.2, 0, 0, 0.15], [0, 1.2, 0, 0], [0, 0, 1.2, -0.5]]
# A rotation about y by 30 degrees, a scale of 0.7 and a translation.
c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
TURNED = [[0.7 * c, 0, 0.7 * s, 0.2], [0, 0.7, 0, -0.1], [-0.7 * s, 0, 0.7 * c, 0.3]]
CONFIGS = [
    ("rgb.vol", "trilinear", "clamp", False, IDENTITY),
    ("rgb.vol", "trilinear", "repeat", False, IDENTITY),
    ("rgb.vol", "trilinear", "mirror", False, TURNED),
    ("rgb.vol", "nearest", "clamp", False, PLACED),
    ("grey.vol", "nearest", "repeat", False, [[0.3, 0, 0, 0], [0, 0.3, 0, 0], [0, 0, 0.3, 0]]),
    ("grey.vol", "trilinear", "mirror", False, IDENTITY),
    ("rgb.vol", "trilinear", "clamp", True, PLACED),
]


def points():
    rng = np.random.default_rng(11)
    pts = list(rng.uniform(-1.5, 2.5, size=(150, 3)))
    # Cell centres and faces of the unit cube, exactly.
    for x in [0.0, 0.125, 0.5, 0.875, 1.0, -0.2, 1.3]:
        for y in [0.0, 1.0 / 6.0, 0.5, 1.0]:
            for z in [0.25, 0.75, 0.5]:
                pts.append([x, y, z])
    return np.array(pts, dtype=np.float32)


def main():
    out = {"mitsuba": mi.__version__, "variant": mi.variant(), "configs": []}
    pts = points()
    for (name, filt, wrap, bbox, m) in CONFIGS:
        to_world = mi.ScalarTransform4f(mi.ScalarMatrix4f(*[x for row in m for x in row], 0, 0, 0, 1))
        tex = mi.load_dict({"type": "volume", "volume": {"type": "gridvolume", "filename": os.path.join(DIR, name),
                                                         "filter_type": filt, "wrap_mode": wrap,
                                                         "use_grid_bbox": bbox, "to_world": to_world}})
        si = dr.zeros(mi.SurfaceInteraction3f, len(pts))
        si.p = mi.Point3f(pts[:, 0], pts[:, 1], pts[:, 2])
        col = tex.eval(si)
        rgb = np.stack([np.array(col[0]), np.array(col[1]), np.array(col[2])], axis=1)
        one = np.array(tex.eval_1(si))
        # Nine significant digits: every f32 read back exactly.
        g = lambda a: [float(f"{x:.9g}") for x in np.asarray(a, np.float32).ravel()]
        out["configs"].append({"file": name, "filter_type": filt, "wrap_mode": wrap, "use_grid_bbox": bbox,
                               "to_world": [[float(x) for x in row] for row in m], "points": g(pts),
                               "rgb": g(rgb), "eval_1": g(one)})
    path = os.path.join(DIR, "volume_evals.json")
    with open(path, "w") as f:
        json.dump(out, f)
    print(f"wrote {path}: {len(CONFIGS)} configurations x {len(pts)} points", file=sys.stderr)


if __name__ == "__main__":
    main()
