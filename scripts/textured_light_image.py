#!/usr/bin/env python3
"""Writes tests/fixtures/textured_lights/radiance.exr, the radiance bitmap of the textured-light
fixture (tests/fixtures/textured_lights/textured_lights.xml): 4 x 3 pixels of linear RGB, 32-bit
float, every pixel different and no symmetry (so a mirrored or transposed uv lookup changes the
image), values from 0.25 to 9 (Mitsuba 3.9.1 refuses a checkerboard's colours above 1, so a bright
textured light needs a bitmap).

Usage (the reference renderer's venv has OpenEXR and numpy): /tmp/mitsuba-venv/bin/python scripts/textured_light_image.py
"""
import os

import numpy as np
import OpenEXR

W, H = 4, 3
x, y = np.meshgrid(np.arange(W), np.arange(H))
r = 1.0 + 2.0 * x + 0.5 * y            # rises to the right
g = 0.5 + 2.5 * y + 0.25 * x           # rises downwards
b = np.where((x + y) % 2 == 0, 9.0, 0.25)  # a checker of two levels
out = os.path.join(os.path.dirname(__file__), "..", "tests", "fixtures", "textured_lights", "radiance.exr")
header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
channels = {"R": r.astype(np.float32), "G": g.astype(np.float32), "B": b.astype(np.float32)}
with OpenEXR.File(header, channels) as f:
    f.write(out)
print("wrote", os.path.normpath(out))
