#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `roughplastic` evaluated at fixed direction pairs: the fixture of
tests/plastics.rs's check that pathlab's roughplastic (its precomputed coating tables, their
interpolation, both lobes and the pdf) is Mitsuba's. Run once with the reference renderer's
venv (../shared/reference-renderer), writes tests/fixtures/roughplastic_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/roughplastic_evals.py

Directions are in the BSDF's local frame (+z the normal). `wo` is pathlab's (the viewer's
direction, Mitsuba's si.wi), `wi` the scattered one (Mitsuba's wo). `f` is Mitsuba's eval divided
by cos(wi), `pdf` its pdf (visible-normal sampling, its default)."""
import json
import math
import os
import sys

import mitsuba as mi

mi.set_variant("scalar_rgb")

# (distribution, alpha, diffuse, specular, int_ior, ext_ior, nonlinear)
CONFIGS = [
    ("beckmann", 0.1, [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], 1.49, 1.000277, False),
    ("ggx", 0.3, [0.9, 0.3, 0.05], [0.8, 0.8, 0.8], 1.5046, 1.0, True),
    ("beckmann", 0.6, [0.2, 0.7, 0.4], [1.0, 1.0, 1.0], 2.419, 1.33, False),
    ("ggx", 0.02, [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], 1.5, 1.0, False),
]
ANGLES = [0.0, 20.0, 45.0, 70.0, 85.0, 89.5]


def direction(theta, phi):
    t, p = math.radians(theta), math.radians(phi)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def main():
    out = {"mitsuba": mi.__version__, "variant": "scalar_rgb", "configs": []}
    for (dist, alpha, diffuse, specular, int_ior, ext_ior, nonlinear) in CONFIGS:
        bsdf = mi.load_dict({
            "type": "roughplastic",
            "distribution": dist,
            "alpha": alpha,
            "diffuse_reflectance": {"type": "rgb", "value": diffuse},
            "specular_reflectance": {"type": "rgb", "value": specular},
            "int_ior": int_ior,
            "ext_ior": ext_ior,
            "nonlinear": nonlinear,
        })
        ctx = mi.BSDFContext()
        pairs = []
        for a in ANGLES:
            for k, b in enumerate(ANGLES):
                wo = direction(a, 10.0)
                wi = direction(b, 200.0 + 17.0 * k)
                si = mi.SurfaceInteraction3f()
                si.wi = mi.Vector3f(wo)
                si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
                value = bsdf.eval(ctx, si, mi.Vector3f(wi))
                pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
                cos = wi[2]
                f = [float(value[c]) / cos if cos > 0 else 0.0 for c in range(3)]
                pairs.append({"wo": wo, "wi": wi, "f": f, "pdf": float(pdf)})
        out["configs"].append({
            "distribution": dist, "alpha": alpha, "diffuse": diffuse, "specular": specular,
            "int_ior": int_ior, "ext_ior": ext_ior, "nonlinear": nonlinear, "pairs": pairs,
        })
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "roughplastic_evals.json")
    with open(path, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
        fh.write("\n")
    print(f"wrote {os.path.normpath(path)}", file=sys.stderr)


if __name__ == "__main__":
    main()
