#!/usr/bin/env python3
"""Mitsuba 3's speed on a scene file: loads it (llvm_ad_rgb, the reference renderer's venv),
renders SPP samples per pixel once to compile its kernels, then REPEAT more times, and prints
one JSON line: width, height, spp and the best pixel samples per second of the timed renders.

    /tmp/mitsuba-venv/bin/python scripts/census/speed.py SCENE.xml [--spp 16] [--repeat 2] [-D name=value ...]
"""
import argparse
import json
import os
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.environ.get("REFERENCE_RENDERER", os.path.join(here, "..", "..", "..", "shared", "reference-renderer")))
import mitsuba_render as mr  # noqa: E402  (picks a libLLVM >= 16 for Dr.Jit)

mi, dr = mr.mi, mr.dr


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("-D", "--define", action="append", default=[])
    a = p.parse_args()
    mi.set_variant("llvm_ad_rgb")
    params = dict(d.split("=", 1) for d in a.define)
    scene = mi.load_file(os.path.abspath(a.scene), **params)
    film = scene.sensors()[0].film()
    w, h = film.size()
    img = mi.render(scene, spp=a.spp, seed=0)
    dr.eval(img)
    dr.sync_thread()
    best = 0.0
    for r in range(a.repeat):
        t0 = time.perf_counter()
        img = mi.render(scene, spp=a.spp, seed=r + 1)
        dr.eval(img)
        dr.sync_thread()
        best = max(best, w * h * a.spp / (time.perf_counter() - t0))
    print(json.dumps({"scene": a.scene, "width": int(w), "height": int(h), "spp": a.spp, "samples_per_s": best}))


if __name__ == "__main__":
    main()
