#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `pplastic` (scalar_rgb: its unpolarised branch) evaluated at fixed direction
pairs: the fixture of tests/polarized_plastics.rs's check that pathlab's pplastic (both lobes,
the fixed lobe probability and the visible-normal pdf) is Mitsuba's. Run once with the reference
renderer's venv (../shared/reference-renderer), writes tests/fixtures/pplastic_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/pplastic_evals.py

The pairs and their values: bsdf_evals.py (`pdf` with visible-normal sampling, Mitsuba's
default)."""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import bsdf_evals  # noqa: E402 (after the variant)

# (distribution, alpha, diffuse, specular, eta): the documentation's purple, a GGX one given by
# `eta` with a specular_reflectance below 1, a rough Beckmann one of index below the default.
CONFIGS = [
    ("beckmann", 0.06, [0.05, 0.03, 0.1], [1.0, 1.0, 1.0], 1.49 / 1.000277),
    ("ggx", 0.3, [0.6, 0.45, 0.2], [0.8, 0.8, 0.8], 1.6),
    ("beckmann", 0.5, [0.2, 0.7, 0.4], [1.0, 0.9, 0.7], 1.33),
]


def main():
    out = {"mitsuba": mi.__version__, "variant": "scalar_rgb", "configs": []}
    for (dist, alpha, diffuse, specular, eta) in CONFIGS:
        bsdf = mi.load_dict({
            "type": "pplastic",
            "distribution": dist,
            "alpha": alpha,
            "diffuse_reflectance": {"type": "rgb", "value": diffuse},
            "specular_reflectance": {"type": "rgb", "value": specular},
            "eta": eta,
        })
        out["configs"].append({
            "distribution": dist, "alpha": alpha, "diffuse": diffuse, "specular": specular, "eta": eta,
            "pairs": bsdf_evals.pairs(bsdf, lambda k: 200.0 + 17.0 * k),
        })
    bsdf_evals.write(out, "pplastic_evals.json")


if __name__ == "__main__":
    main()
