#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `roughplastic` evaluated at fixed direction pairs: the fixture of
tests/plastics.rs's check that pathlab's roughplastic (its precomputed coating tables, their
interpolation, both lobes and the pdf) is Mitsuba's. Run once with the reference renderer's
venv (../shared/reference-renderer), writes tests/fixtures/roughplastic_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/roughplastic_evals.py

The pairs and their values: bsdf_evals.py (`pdf` with visible-normal sampling, Mitsuba's
default)."""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import bsdf_evals  # noqa: E402 (after the variant)

# (distribution, alpha, diffuse, specular, int_ior, ext_ior, nonlinear)
CONFIGS = [
    ("beckmann", 0.1, [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], 1.49, 1.000277, False),
    ("ggx", 0.3, [0.9, 0.3, 0.05], [0.8, 0.8, 0.8], 1.5046, 1.0, True),
    ("beckmann", 0.6, [0.2, 0.7, 0.4], [1.0, 1.0, 1.0], 2.419, 1.33, False),
    ("ggx", 0.02, [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], 1.5, 1.0, False),
]
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
        out["configs"].append({
            "distribution": dist, "alpha": alpha, "diffuse": diffuse, "specular": specular,
            "int_ior": int_ior, "ext_ior": ext_ior, "nonlinear": nonlinear,
            "pairs": bsdf_evals.pairs(bsdf, lambda k: 200.0 + 17.0 * k),
        })
    bsdf_evals.write(out, "roughplastic_evals.json")


if __name__ == "__main__":
    main()
