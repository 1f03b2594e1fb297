#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `bitmap` texture evaluated at fixed uvs: the fixture of tests/textures.rs's
check that pathlab's bitmap lookups (the image's decoding, sRGB or raw, bilinear and nearest
filtering, the repeat, mirror and clamp wrap modes, `to_uv`) are Mitsuba's. Run once with the
reference renderer's venv (../shared/reference-renderer):

    /tmp/mitsuba-venv/bin/python scripts/bitmap_evals.py

It writes the small test images into tests/fixtures/textures/ (deterministic: texel values from a
fixed formula) unless they exist, then tests/fixtures/textures/bitmap_evals.json: per
configuration (file, filter_type, wrap_mode, raw, the to_uv matrix's 2x3 part) the uvs, Mitsuba's
eval at each and its eval_1_grad (the gradient in uv that its bumpmap reads) (llvm_ad_rgb, the
variant of the reference renders)."""
import json
import os
import sys

import numpy as np
import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DIR = os.path.join(ROOT, "tests", "fixtures", "textures")


def make_images():
    os.makedirs(DIR, exist_ok=True)
    from PIL import Image

    # 5 x 3 RGB, 8-bit (sRGB-encoded, as PNGs are): every texel different, dark values too
    # (the sRGB curve's linear segment below 0.04045 * 255 = 10.3).
    w, h = 5, 3
    rgb = np.zeros((h, w, 3), np.uint8)
    for y in range(h):
        for x in range(w):
            rgb[y, x] = [(37 * x + 61 * y + 5) % 256, (83 * x + 29 * y + 200) % 256, (3 + 7 * x * y) % 256]
    path = os.path.join(DIR, "grid.png")
    if not os.path.exists(path):
        Image.fromarray(rgb, "RGB").save(path)
    # 3 x 2 grey with alpha (alpha is dropped; grey is read as r = g = b).
    grey = np.array([[[10, 255], [128, 100], [250, 0]], [[0, 50], [64, 255], [200, 7]]], np.uint8)
    path = os.path.join(DIR, "grey_alpha.png")
    if not os.path.exists(path):
        Image.fromarray(grey, "LA").save(path)
    # 4 x 3 float RGB EXR (linear): values above 1 as an HDR texture has.
    w, h = 4, 3
    f = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        for x in range(w):
            f[y, x] = [0.1 + 0.7 * x + 0.05 * y, 2.5 - 0.3 * y * x, 0.01 * (x + 1) * (y + 2)]
    write_exr(os.path.join(DIR, "ramp.exr"), f)
    # 6 x 4 float RGB EXR of reflectances in [0.05, 0.9] (the Cornell box's back wall,
    # tests/fixtures/cornell_bitmap/).
    w, h = 6, 4
    a = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        for x in range(w):
            a[y, x] = [0.05 + 0.85 * x / (w - 1), 0.9 - 0.8 * y / (h - 1), 0.3 + 0.1 * ((x + y) % 3)]
    write_exr(os.path.join(DIR, "albedo.exr"), a)


def write_exr(path, f):
    import OpenEXR
    if not os.path.exists(path):
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        channels = {"R": f[:, :, 0].copy(), "G": f[:, :, 1].copy(), "B": f[:, :, 2].copy()}
        with OpenEXR.File(header, channels) as out:
            out.write(path)


# (file, filter_type, wrap_mode, raw, to_uv as the 2 x 3 part of a 3 x 3 matrix)
IDENTITY = [[1, 0, 0], [0, 1, 0]]
CONFIGS = [
    ("grid.png", "bilinear", "repeat", False, IDENTITY),
    ("grid.png", "bilinear", "mirror", False, IDENTITY),
    ("grid.png", "bilinear", "clamp", False, IDENTITY),
    ("grid.png", "nearest", "repeat", False, IDENTITY),
    ("grid.png", "nearest", "mirror", False, IDENTITY),
    ("grid.png", "nearest", "clamp", False, IDENTITY),
    ("grid.png", "bilinear", "repeat", True, IDENTITY),
    ("grid.png", "bilinear", "mirror", False, [[2.0, 0.5, 0.25], [-0.3, 3.0, 0.1]]),
    ("grey_alpha.png", "bilinear", "repeat", False, IDENTITY),
    ("ramp.exr", "bilinear", "repeat", False, IDENTITY),
    ("ramp.exr", "nearest", "mirror", False, IDENTITY),
    ("ramp.exr", "bilinear", "clamp", False, [[1.5, 0, 0], [0, -2.0, 0.5]]),
    ("albedo.exr", "bilinear", "mirror", False, [[3.0, 0, 0], [0, 3.0, 0]]),
]


def uvs():
    rng = np.random.default_rng(7)
    pts = list(rng.uniform(-2.5, 2.5, size=(100, 2)))
    # Texel centres and edges, exactly: where filtering and wrapping change.
    for u in [0.0, 0.1, 0.2, 0.5, 0.9, 1.0, -0.1, -1.0, 1.3]:
        for v in [0.0, 1.0 / 6.0, 0.5, 1.0, -0.5, 2.0]:
            pts.append([u, v])
    return np.array(pts, dtype=np.float32)


def main():
    make_images()
    out = {"mitsuba": mi.__version__, "variant": mi.variant(), "configs": []}
    pts = uvs()
    for (name, filt, wrap, raw, m) in CONFIGS:
        to_uv = mi.ScalarAffineTransform3f(mi.ScalarMatrix3f(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], 0, 0, 1))
        tex = mi.load_dict({"type": "bitmap", "filename": os.path.join(DIR, name), "filter_type": filt,
                            "wrap_mode": wrap, "raw": raw, "to_uv": to_uv})
        si = dr.zeros(mi.SurfaceInteraction3f, len(pts))
        si.uv = mi.Point2f(pts[:, 0], pts[:, 1])
        c = tex.eval(si)
        vals = np.stack([np.array(c[0]), np.array(c[1]), np.array(c[2])], axis=1)
        g = tex.eval_1_grad(si)
        grads = np.stack([np.array(g[0]), np.array(g[1])], axis=1)
        out["configs"].append({"file": name, "filter_type": filt, "wrap_mode": wrap, "raw": raw, "to_uv": m,
                               "mean": float(np.array(tex.mean()).ravel()[0]),
                               "uv": pts.tolist(), "rgb": vals.tolist(), "grad": grads.tolist()})
    path = os.path.join(DIR, "bitmap_evals.json")
    with open(path, "w") as f:
        json.dump(out, f)
    print(f"wrote {path}: {len(CONFIGS)} configurations x {len(pts)} uvs", file=sys.stderr)


if __name__ == "__main__":
    main()
