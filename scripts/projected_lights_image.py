#!/usr/bin/env python3
"""The image tests/fixtures/projected_lights/ projects (deterministic): slide.png, 24 x 16,
8-bit sRGB RGB: a colour ramp across u, bars along v and a dark corner square, so that a
mirrored, swapped or shifted uv, or a wrong aspect ratio, moves something visible. Run with the
reference renderer's venv:

    /tmp/mitsuba-venv/bin/python scripts/projected_lights_image.py
"""
import os

import numpy as np
from PIL import Image

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "projected_lights")


def main():
    w, h = 24, 16
    u, v = np.meshgrid((np.arange(w) + 0.5) / w, (np.arange(h) + 0.5) / h)
    r = 0.15 + 0.85 * u
    g = 0.25 + 0.75 * (np.floor(v * 4) % 2)
    b = 0.9 - 0.7 * u * v
    img = np.stack([r, g, b], -1)
    img[: h // 4, : w // 4] = 0.05  # the top-left corner (u, v near 0)
    os.makedirs(DIR, exist_ok=True)
    Image.fromarray(np.round(np.clip(img, 0, 1) * 255).astype(np.uint8)).save(os.path.join(DIR, "slide.png"))


if __name__ == "__main__":
    main()
