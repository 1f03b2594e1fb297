#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `principled` evaluated at fixed direction pairs: the fixture of
tests/principled.rs's check that pathlab's principled BSDF (every lobe, its Fresnel blend, its
lobe probabilities and pdf) is Mitsuba's. Run once with the reference renderer's venv
(../shared/reference-renderer), writes tests/fixtures/principled_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/principled_evals.py

Directions are in the BSDF's local frame (+z the normal). `wo` is pathlab's (the viewer's
direction, Mitsuba's si.wi), `wi` the scattered one (Mitsuba's wo). `f` is Mitsuba's eval divided
by cos(wi), `pdf` its pdf (visible-normal sampling, its default)."""
import json
import math
import os
import sys

import mitsuba as mi

mi.set_variant("scalar_rgb")

# Each config: the plugin's properties (floats; base_color an RGB), covering every lobe alone
# and together, the specular/eta forms, flatness and the sampling rates.
CONFIGS = [
    {},
    {"base_color": [0.8, 0.2, 0.1], "roughness": 0.3, "metallic": 0.745455, "specular": 0.5},
    {"base_color": [0.2, 0.5, 0.9], "roughness": 0.8, "sheen": 0.9, "sheen_tint": 0.6, "spec_tint": 0.4},
    {"base_color": [0.6, 0.6, 0.3], "roughness": 0.1, "clearcoat": 0.8, "clearcoat_gloss": 0.7, "metallic": 0.2},
    {"base_color": [0.9, 0.4, 0.4], "roughness": 0.6, "flatness": 0.5, "eta": 1.8, "clearcoat": 0.3, "clearcoat_gloss": 0.1},
    {"base_color": [0.3, 0.8, 0.3], "roughness": 0.05, "metallic": 1.0, "spec_tint": 0.5},
    {"base_color": [0.5, 0.5, 0.5], "roughness": 0.4, "clearcoat": 1.0, "main_specular_sampling_rate": 0.5,
     "clearcoat_sampling_rate": 2.0, "diffuse_reflectance_sampling_rate": 3.0, "sheen": 0.3},
]
ANGLES = [0.0, 20.0, 45.0, 70.0, 85.0, 89.5]


def direction(theta, phi):
    t, p = math.radians(theta), math.radians(phi)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def main():
    out = {"mitsuba": mi.__version__, "variant": "scalar_rgb", "configs": []}
    for config in CONFIGS:
        d = {"type": "principled"}
        for k, v in config.items():
            d[k] = {"type": "rgb", "value": v} if isinstance(v, list) else v
        bsdf = mi.load_dict(d)
        ctx = mi.BSDFContext()
        pairs = []
        for a in ANGLES:
            for k, b in enumerate(ANGLES):
                wo = direction(a, 10.0)
                # Near the mirror direction for some pairs (the specular peaks), elsewhere others.
                wi = direction(b, 190.0 + 3.0 * k) if k % 2 == 0 else direction(b, 200.0 + 37.0 * k)
                si = mi.SurfaceInteraction3f()
                si.wi = mi.Vector3f(wo)
                si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
                value = bsdf.eval(ctx, si, mi.Vector3f(wi))
                pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
                cos = wi[2]
                f = [float(value[c]) / cos if cos > 0 else 0.0 for c in range(3)]
                pairs.append({"wo": wo, "wi": wi, "f": f, "pdf": float(pdf)})
        out["configs"].append({"properties": config, "pairs": pairs})
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "principled_evals.json")
    with open(path, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
        fh.write("\n")
    print(f"wrote {os.path.normpath(path)}", file=sys.stderr)


if __name__ == "__main__":
    main()
