#!/usr/bin/env python3
"""The normal maps of tests/fixtures/normal_map/ (deterministic), each normal n encoded as
(n + 1) / 2 in 8-bit RGB (Mitsuba's convention; the scene reads them with raw = true):
bumps.png, 64 x 64, the normals of a height field of round bumps and a ridge, n =
normalize(-dh/du, -dh/dv, 1); tiles.png, 4 x 4, a checkerboard of two normals tilted along
different azimuths (read with nearest filtering). Run with the reference renderer's venv:

    /tmp/mitsuba-venv/bin/python scripts/normal_map_image.py
"""
import os

import numpy as np
from PIL import Image

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "normal_map")


def main():
    n = 64
    u, v = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n)
    # Four round bumps and a diagonal ridge: slopes up to ~1.5 (normals tilted up to ~55 degrees).
    dhdu = np.zeros_like(u)
    dhdv = np.zeros_like(u)
    for cu, cv in [(0.25, 0.25), (0.75, 0.3), (0.3, 0.75), (0.7, 0.7)]:
        g = np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * 0.08 ** 2))
        dhdu += -0.12 * (u - cu) / 0.08 ** 2 * g
        dhdv += -0.12 * (v - cv) / 0.08 ** 2 * g
    ridge = np.sin(2 * np.pi * 3 * (u + v))
    dhdu += 0.1 * ridge
    dhdv += 0.1 * ridge
    normal = np.stack([-dhdu, -dhdv, np.ones_like(u)], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    rgb = np.clip(np.round((normal + 1) / 2 * 255), 0, 255).astype(np.uint8)
    os.makedirs(DIR, exist_ok=True)
    Image.fromarray(rgb).save(os.path.join(DIR, "bumps.png"))
    tilted = [np.array([0.5, 0.0, 0.86]), np.array([-0.3, -0.4, 0.866])]
    tiles = np.zeros((4, 4, 3), np.uint8)
    for y in range(4):
        for x in range(4):
            t = tilted[(x + y) % 2]
            t = t / np.linalg.norm(t)
            tiles[y, x] = np.clip(np.round((t + 1) / 2 * 255), 0, 255).astype(np.uint8)
    Image.fromarray(tiles).save(os.path.join(DIR, "tiles.png"))


if __name__ == "__main__":
    main()
