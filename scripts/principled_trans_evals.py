#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `principled` with `spec_trans` evaluated at fixed direction pairs on both
sides of the surface: the fixture of tests/principled.rs's check that pathlab's principled BSDF
with transmission (the rough dielectric lobe, the back side's dielectric alone, the lobe
probabilities that depend on the Fresnel term) is Mitsuba's. Run once with the reference
renderer's venv (../shared/reference-renderer), writes
tests/fixtures/principled_trans_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/principled_trans_evals.py

The pairs and their values: bsdf_evals.py's `pairs_both_sides` (wo and wi above and below;
`pdf` with visible-normal sampling, Mitsuba's default)."""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import bsdf_evals  # noqa: E402 (after the variant)

# Each config: the plugin's properties (floats; base_color an RGB): transmission alone and beside
# every other lobe, metallic, the index as `eta` and as `specular`, and the sampling rates.
CONFIGS = [
    {"spec_trans": 1.0},
    {"base_color": [0.3, 0.6, 0.8], "roughness": 0.15, "spec_trans": 0.7, "specular": 0.4, "clearcoat": 0.6, "sheen": 0.9},
    {"base_color": [0.8, 0.5, 0.2], "roughness": 0.5, "spec_trans": 0.3, "metallic": 0.4, "spec_tint": 0.5, "eta": 1.33},
    {"base_color": [0.9, 0.9, 0.9], "roughness": 0.3, "spec_trans": 0.9, "eta": 1.8, "flatness": 0.4, "sheen": 0.3, "sheen_tint": 0.7},
    {"base_color": [0.5, 0.7, 0.4], "roughness": 0.7, "spec_trans": 0.5, "clearcoat": 1.0, "clearcoat_gloss": 0.3,
     "main_specular_sampling_rate": 2.0, "clearcoat_sampling_rate": 0.5, "diffuse_reflectance_sampling_rate": 3.0},
]


def main():
    bsdf_evals.record("principled", CONFIGS, "principled_trans_evals.json", both_sides=True)


if __name__ == "__main__":
    main()
