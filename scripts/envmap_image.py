#!/usr/bin/env python3
"""The latitude-longitude sky of tests/fixtures/envmap/ (deterministic): sky.exr, 64 x 32 linear
RGB, a blue-to-white sky over a dim brown ground, with a sun of 2 x 2 texels at 50 times the
sky's brightness near (u, t) = (0.3, 0.3); and sun.exr, the same with a sun of 10^4 times
(the chi-square tests' hard case); and envmap_evals.json, Mitsuba's own envmap evaluated towards
300 directions. Run with the reference renderer's venv:

    /tmp/mitsuba-venv/bin/python scripts/envmap_image.py
"""
import os

import numpy as np
import OpenEXR

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "envmap")


def sky(w, h, sun):
    img = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        t = (y + 0.5) / h
        for x in range(w):
            u = (x + 0.5) / w
            if t < 0.5:
                k = t / 0.5
                img[y, x] = [0.25 + 0.55 * k, 0.45 + 0.4 * k, 1.0 - 0.1 * k]
                img[y, x] *= 1.0 + 0.3 * np.cos(2 * np.pi * u)
            else:
                img[y, x] = [0.12, 0.09, 0.06]
    sx, sy = int(0.3 * w), int(0.3 * h)
    img[sy:sy + 2, sx:sx + 2] = np.array([1.0, 0.9, 0.7], np.float32) * sun
    return img


def write(name, img):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    channels = {"R": img[:, :, 0].copy(), "G": img[:, :, 1].copy(), "B": img[:, :, 2].copy()}
    with OpenEXR.File(header, channels) as out:
        out.write(os.path.join(DIR, name))


def mitsuba_evals():
    """Mitsuba's own envmap (sky.exr, rotated about y by 30 degrees, scale 1.5, as envmap.xml)
    evaluated towards 300 directions: envmap_evals.json, the fixture of tests/environment_map.rs's
    check of pathlab's direction-to-texel mapping and filtering."""
    import json
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    emitter = mi.load_dict({"type": "envmap", "filename": os.path.join(DIR, "sky.exr"), "scale": 1.5,
                            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 30)})
    rng = np.random.default_rng(11)
    z = rng.uniform(-1, 1, 300)
    phi = rng.uniform(0, 2 * np.pi, 300)
    d = np.stack([np.sqrt(1 - z * z) * np.cos(phi), z, np.sqrt(1 - z * z) * np.sin(phi)], axis=1).astype(np.float32)
    # The poles and the seam (u = 0: -z in the map's frame, rotated).
    extra = np.array([[0, 1, 0], [0, -1, 0], [-0.5, 0, -0.866025], [-0.5, 0.2, -0.866025]], np.float32)
    d = np.concatenate([d, extra / np.linalg.norm(extra, axis=1, keepdims=True)])
    si = dr.zeros(mi.SurfaceInteraction3f, len(d))
    si.wi = mi.Vector3f(-d[:, 0], -d[:, 1], -d[:, 2])
    c = emitter.eval(si)
    rgb = np.stack([np.array(c[0]), np.array(c[1]), np.array(c[2])], axis=1)
    out = {"mitsuba": mi.__version__, "variant": mi.variant(), "file": "sky.exr", "scale": 1.5, "rotate_y_degrees": 30.0,
           "directions": d.tolist(), "rgb": rgb.tolist()}
    with open(os.path.join(DIR, "envmap_evals.json"), "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    os.makedirs(DIR, exist_ok=True)
    write("sky.exr", sky(64, 32, 50.0))
    write("sun.exr", sky(64, 32, 1e4))
    mitsuba_evals()
