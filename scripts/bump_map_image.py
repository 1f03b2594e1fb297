#!/usr/bin/env python3
"""The height map of tests/fixtures/bump_map/ (deterministic): heights.png, 64 x 64, 8-bit grey
stored as RGB (the scene reads it with raw = true, so its luminance is the code / 255): round
bumps and a diagonal ridge, h in [0, 1], whose bilinear gradient tilts the bumped normals by up
to ~50 degrees at the fixture's scales. Run with the reference renderer's venv:

    /tmp/mitsuba-venv/bin/python scripts/bump_map_image.py
"""
import os

import numpy as np
from PIL import Image

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "bump_map")


def main():
    n = 64
    u, v = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n)
    h = np.zeros_like(u)
    for cu, cv in [(0.25, 0.25), (0.75, 0.3), (0.3, 0.75), (0.7, 0.7)]:
        h += np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * 0.09 ** 2))
    h += 0.35 * (0.5 + 0.5 * np.sin(2 * np.pi * 3 * (u + v)))
    h = (h - h.min()) / (h.max() - h.min())
    grey = np.round(h * 255).astype(np.uint8)
    os.makedirs(DIR, exist_ok=True)
    Image.fromarray(np.stack([grey] * 3, -1)).save(os.path.join(DIR, "heights.png"))


if __name__ == "__main__":
    main()
