#!/usr/bin/env python3
"""Writes the metric fixtures of tests/metrics_fixtures.rs: pairs of display images and the
PSNR, SSIM and FLIP that the libraries people trust compute for them.

    pip install scikit-image flip-evaluator numpy
    python3 scripts/metrics_fixtures.py tests/fixtures/metrics

Each image is H x W x 3 float32 in [0, 1] holding multiples of 1/255 (so FLIP's 8-bit input,
which pathlab feeds through nv-flip, sees exactly these values), stored raw little-endian in
row-major RGB order as NAME_ref.f32 / NAME_test.f32. expected.json holds, per pair, the size and
    psnr = skimage.metrics.peak_signal_noise_ratio(ref, test, data_range=1.0)
    ssim = skimage.metrics.structural_similarity(ref, test, channel_axis=2, data_range=1.0)
    flip = flip_evaluator.evaluate(ref, test, "LDR")[1]  (mean FLIP error, 67 ppd)
computed in float64 from those values. CI does not need Python: the outputs are committed.
"""
import json
import os
import sys

import flip_evaluator
import numpy as np
import skimage
from skimage.metrics import peak_signal_noise_ratio, structural_similarity


def q(img):
    """Quantise to multiples of 1/255 in [0, 1]."""
    return (np.round(np.clip(img, 0.0, 1.0) * 255.0) / 255.0).astype(np.float32)


def pairs(rng):
    h, w = 48, 64
    y, x = np.mgrid[0:h, 0:w]
    gradient = np.stack([x / (w - 1), y / (h - 1), 0.5 + 0.5 * np.sin(x / 5.0) * np.cos(y / 7.0)], axis=2)
    yield "gradient_noise", q(gradient), q(gradient + rng.normal(0, 0.08, gradient.shape))

    # Shapes on a dark background against a blurred, darker copy (structure and mean change).
    scene = np.zeros((h, w, 3))
    scene[(x - 20) ** 2 + (y - 24) ** 2 < 120] = [0.9, 0.6, 0.2]
    scene[10:30, 38:58] = [0.2, 0.5, 0.9]
    k = np.ones(5) / 5.0
    blurred = np.apply_along_axis(lambda r: np.convolve(r, k, mode="same"), 1, scene)
    blurred = np.apply_along_axis(lambda c: np.convolve(c, k, mode="same"), 0, blurred)
    yield "shapes_blur", q(scene), q(0.8 * blurred)

    # Odd size; sparse fireflies on a dim image, as a 10-spp path-traced image shows them.
    h2, w2 = 23, 37
    base = 0.15 + 0.1 * rng.random((h2, w2, 3))
    noisy = base + rng.normal(0, 0.05, base.shape)
    fireflies = rng.random((h2, w2)) < 0.03
    noisy[fireflies] = 1.0
    yield "fireflies_odd", q(base), q(noisy)

    # Near black against near black plus tiny noise (the dark end of every metric).
    dark = 0.02 * rng.random((32, 32, 3))
    yield "dark", q(dark), q(dark + rng.normal(0, 0.01, dark.shape))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "tests/fixtures/metrics"
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(20261130)
    expected = {
        "generator": "scripts/metrics_fixtures.py",
        "versions": {"scikit-image": skimage.__version__, "flip-evaluator": "1.7", "numpy": np.__version__},
        "pairs": [],
    }
    for name, ref, test in pairs(rng):
        ref.astype("<f4").tofile(os.path.join(out, f"{name}_ref.f32"))
        test.astype("<f4").tofile(os.path.join(out, f"{name}_test.f32"))
        r64, t64 = ref.astype(np.float64), test.astype(np.float64)
        psnr = peak_signal_noise_ratio(r64, t64, data_range=1.0)
        ssim = structural_similarity(r64, t64, channel_axis=2, data_range=1.0)
        _, flip, _ = flip_evaluator.evaluate(ref, test, "LDR")
        expected["pairs"].append(
            {"name": name, "width": ref.shape[1], "height": ref.shape[0], "psnr": float(psnr), "ssim": float(ssim), "flip": float(flip)}
        )
    with open(os.path.join(out, "expected.json"), "w") as f:
        json.dump(expected, f, indent=2)
        f.write("\n")
    for p in expected["pairs"]:
        print(p)


if __name__ == "__main__":
    main()
