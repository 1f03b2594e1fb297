#!/usr/bin/env python3
"""Mitsuba 3.9.1's own `principledthin` evaluated at fixed direction pairs on both sides of the
sheet: the fixture of tests/principled.rs's check that pathlab's thin principled BSDF (every
lobe, its Fresnel blend, its lobe probabilities and pdf) is Mitsuba's. Run once with the
reference renderer's venv (../shared/reference-renderer), writes
tests/fixtures/principled_thin_evals.json:

    /tmp/mitsuba-venv/bin/python scripts/principled_thin_evals.py

The pairs and their values: bsdf_evals.py's `pairs_both_sides` (wo and wi above and below;
`pdf` with visible-normal sampling, Mitsuba's default)."""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import bsdf_evals  # noqa: E402 (after the variant)

# Each config: the plugin's properties (floats; base_color an RGB), covering every lobe alone
# and together, the tinted Fresnel, flatness, eta and the sampling rates.
CONFIGS = [
    {},
    {"base_color": [0.7, 0.1, 0.1], "roughness": 0.3, "spec_trans": 0.8, "eta": 1.33},
    {"base_color": [0.2, 0.5, 0.9], "roughness": 0.6, "spec_trans": 0.4, "diff_trans": 1.4, "sheen": 0.8, "sheen_tint": 0.5},
    {"base_color": [0.6, 0.6, 0.3], "roughness": 0.1, "spec_trans": 1.0, "spec_tint": 0.7, "eta": 1.8},
    {"base_color": [0.9, 0.4, 0.4], "roughness": 0.7, "flatness": 0.6, "diff_trans": 0.5},
    {"base_color": [0.3, 0.8, 0.3], "roughness": 0.2, "spec_trans": 0.5, "diff_trans": 2.0, "spec_tint": 0.3,
     "specular_reflectance_sampling_rate": 2.0, "specular_transmittance_sampling_rate": 0.5,
     "diffuse_reflectance_sampling_rate": 3.0, "diffuse_transmittance_sampling_rate": 1.5},
]


def main():
    bsdf_evals.record("principledthin", CONFIGS, "principled_thin_evals.json", both_sides=True)


if __name__ == "__main__":
    main()
