#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `principled` evaluated at fixed direction pairs: the fixture of
tests/principled.rs's check that pathlab's principled BSDF (every lobe, its Fresnel blend, its
lobe probabilities and pdf) is Mitsuba's. Run once with the reference renderer's venv
(../shared/reference-renderer), writes tests/fixtures/principled_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/principled_evals.py

The pairs and their values: bsdf_evals.py (`pdf` with visible-normal sampling, Mitsuba's
default)."""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import bsdf_evals  # noqa: E402 (after the variant)

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
def main():
    bsdf_evals.record("principled", CONFIGS, "principled_evals.json")


if __name__ == "__main__":
    main()
