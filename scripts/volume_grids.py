#!/usr/bin/env python3
"""Writes the grid volumes of tests/fixtures/volume/ in Mitsuba's .vol format (version 3,
float32; little-endian; data[((z * ny + y) * nx + x) * channels + c]):

  rgb.vol   4 x 3 x 2 cells, 3 channels: a colour ramp along x, bands along y, a step along z,
            so that trilinear lookups vary along every axis; its bounding box (-0.2, 0.1, -0.3)
            to (1.3, 0.9, 0.6), which only `use_grid_bbox` reads;
  grey.vol  3 x 2 x 2 cells, 1 channel: values 0.1 to 0.9 in an irregular order.

Usage: scripts/volume_grids.py OUT_DIR
"""
import struct
import sys


def write(path, res, channels, cells, bbox=(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)):
    nx, ny, nz = res
    assert len(cells) == nx * ny * nz * channels
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, nx, ny, nz, channels))
        f.write(struct.pack("<6f", *bbox))
        f.write(struct.pack("<%df" % len(cells), *cells))


def main():
    out = sys.argv[1]
    rgb = []
    for z in range(2):
        for y in range(3):
            for x in range(4):
                rgb += [0.1 + 0.25 * x, 0.2 + 0.3 * (y % 2) + 0.1 * z, 0.8 - 0.5 * z - 0.1 * y]
    write(f"{out}/rgb.vol", (4, 3, 2), 3, rgb, bbox=(-0.2, 0.1, -0.3, 1.3, 0.9, 0.6))
    grey = [0.1, 0.9, 0.3, 0.7, 0.5, 0.2, 0.8, 0.4, 0.6, 0.15, 0.85, 0.35]
    write(f"{out}/grey.vol", (3, 2, 2), 1, grey)


if __name__ == "__main__":
    main()
