#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `checkerboard` texture evaluated at fixed uvs, for `to_uv` transforms that
scale, translate, rotate and shear: the fixture of tests/textures.rs's check that pathlab reads a
checkerboard's `to_uv` as Mitsuba does (its 2D affine part) and looks it up alike. Run once with
the reference renderer's venv:

    /tmp/mitsuba-venv/bin/python scripts/checkerboard_evals.py

It writes tests/fixtures/textures/checkerboard_evals.json: per configuration the `to_uv`
transform as XML (what the test gives pathlab's reader), colour0 and colour1, the uvs, and
Mitsuba's eval at each (llvm_ad_rgb, the variant of the reference renders)."""
import json
import os

import numpy as np
import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "textures", "checkerboard_evals.json")

CONFIGS = [
    '<scale x="6" y="6"/><translate x="0.5" y="0.5"/>',
    '<translate x="0.3" y="-0.2"/><scale x="4" y="2"/>',
    '<rotate z="1" angle="30"/><scale x="5" y="3"/><translate x="0.1" y="0.7"/>',
    '<matrix value="3 1.5 0 -0.25  -2 4 0 0.6  0 0 1 0  0 0 0 1"/>',
]


def main():
    rng = np.random.default_rng(7)
    uvs = rng.random((64, 2)).tolist()
    out = []
    for xml in CONFIGS:
        c0, c1 = [0.8, 0.5, 0.1], [0.05, 0.2, 0.7]
        scene_xml = f"""<texture version="3.0.0" type="checkerboard">
            <rgb name="color0" value="{c0[0]}, {c0[1]}, {c0[2]}"/>
            <rgb name="color1" value="{c1[0]}, {c1[1]}, {c1[2]}"/>
            <transform name="to_uv">{xml}</transform></texture>"""
        t = mi.load_string(scene_xml)
        si = dr.zeros(mi.SurfaceInteraction3f, len(uvs))
        si.uv = mi.Point2f([u for u, _ in uvs], [v for _, v in uvs])
        values = np.array(t.eval(si)).T.tolist()
        out.append({"to_uv": xml, "color0": c0, "color1": c1, "uvs": uvs, "values": values})
    with open(OUT, "w") as f:
        json.dump({"mitsuba": mi.__version__, "variant": "llvm_ad_rgb", "configs": out}, f, indent=1)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
