"""`pathlab.metrics` and `pathlab.compare` against scikit-image (PSNR, SSIM to 1e-6) on the
committed metric fixtures and on arrays made here, and `compare` against `pathlab compare
--json`. Deterministic: no tolerance for chance."""

import json

import numpy as np
import pytest
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

import pathlab
from conftest import FIXTURES, STUDY

TOL = 1e-6


def skimage_psnr(test, ref):
    # scikit-image computes in the inputs' precision: float32 arrays give float32 sums (up to
    # 5e-7 off in SSIM); pathlab computes in f64, so scikit-image gets the same values as f64.
    return peak_signal_noise_ratio(ref.astype(np.float64), test.astype(np.float64), data_range=1.0)


def skimage_ssim(test, ref):
    return structural_similarity(ref.astype(np.float64), test.astype(np.float64), channel_axis=2, data_range=1.0)


def fixture_pairs():
    expected = json.loads((FIXTURES / "metrics" / "expected.json").read_text())
    for p in expected["pairs"]:
        shape = (p["height"], p["width"], 3)
        load = lambda kind: np.fromfile(FIXTURES / "metrics" / f"{p['name']}_{kind}.f32", dtype="<f4").reshape(shape)  # noqa: E731
        yield p["name"], load("test"), load("ref")


def made_pairs():
    rng = np.random.default_rng(20261201)
    ref = rng.random((30, 41, 3), dtype=np.float32)
    yield "uniform_noise", np.clip(ref + rng.normal(0, 0.1, ref.shape), 0, 1).astype(np.float32), ref
    yy, xx = np.mgrid[0:24, 0:33]
    smooth = np.stack([xx / 32, yy / 23, (xx + yy) / 55], axis=2).astype(np.float32)
    yield "gradient_offset", np.clip(smooth * 0.9 + 0.05, 0, 1).astype(np.float32), smooth


PAIRS = list(fixture_pairs()) + list(made_pairs())


@pytest.mark.parametrize("name, test, ref", PAIRS, ids=[p[0] for p in PAIRS])
def test_metrics_equal_scikit_image(name, test, ref):
    ours_psnr = pathlab.metrics.psnr(test, ref)
    ours_ssim = pathlab.metrics.ssim(test, ref)
    theirs_psnr, theirs_ssim = skimage_psnr(test, ref), skimage_ssim(test, ref)
    print(f"{name}: PSNR differs by {abs(ours_psnr - theirs_psnr):.1e} dB, SSIM by {abs(ours_ssim - theirs_ssim):.1e}")
    assert abs(ours_psnr - theirs_psnr) <= TOL
    assert abs(ours_ssim - theirs_ssim) <= TOL


@pytest.mark.parametrize("name, test, ref", PAIRS, ids=[p[0] for p in PAIRS])
def test_compare_equals_scikit_image(name, test, ref):
    # gamma:1 at exposure 0 is the identity on [0, 1]: compare scores the arrays as given.
    c = pathlab.compare(test, ref, display="gamma:1")
    assert abs(c["psnr"] - skimage_psnr(test, ref)) <= TOL
    assert abs(c["ssim"] - skimage_ssim(test, ref)) <= TOL
    assert abs(c["mse"] - np.mean((test.astype(np.float64) - ref) ** 2)) <= 1e-9
    assert c["rel_mse"] == pytest.approx(np.mean((test.astype(np.float64) - ref) ** 2 / (ref.astype(np.float64) ** 2 + 0.01)), rel=1e-9)
    assert pathlab.metrics.rel_mse(test, ref) == c["rel_mse"]
    assert pathlab.metrics.flip(test, ref) == c["flip"]


def test_float64_input_is_scored_as_float32():
    _, test, ref = PAIRS[0]
    assert pathlab.metrics.psnr(test.astype(np.float64), ref) == pathlab.metrics.psnr(test, ref)


def test_display_transform_is_applied_on_request():
    _, test, ref = PAIRS[0]
    # Through sRGB the values change, and so does PSNR.
    assert pathlab.metrics.psnr(test, ref, display="srgb") != pathlab.metrics.psnr(test, ref)
    assert pathlab.metrics.psnr(test, ref, display="gamma:1") == pytest.approx(pathlab.metrics.psnr(test, ref), abs=1e-12)


def test_compare_equals_cli_json(cli, tmp_path):
    scene = pathlab.load_scene(STUDY, width=32, height=16)
    a = pathlab.render(scene, "mis", spp=8, seed=1, variance=True)
    b = pathlab.render(scene, "best", spp=256, seed=2, variance=True)
    pa, pb = tmp_path / "a.exr", tmp_path / "b.exr"
    pathlab.write_exr(pa, a)
    pathlab.write_exr(pb, b)
    theirs = json.loads(cli("compare", pa, pb, "--json").stdout)
    assert pathlab.compare(a, b) == theirs
    assert pathlab.compare(pathlab.read_exr(pa), pathlab.read_exr(pb)) == theirs
    assert theirs["display"] == "gamma:1.6", "the reference's recorded display transform"
    assert theirs["z_test"] is not None


def test_to_display_is_the_transform_compare_scores():
    scene = pathlab.load_scene(STUDY, width=32, height=16)
    a, b = pathlab.render(scene, "mis", spp=4), pathlab.render(scene, "best", spp=64)
    # compare() scores the reference's recorded transform (gamma:1.6): the same PSNR as the
    # metrics on the arrays to_display gives.
    da, db = a.to_display(), b.to_display()
    assert da.dtype == np.float32 and da.min() >= 0 and da.max() <= 1
    assert pathlab.metrics.psnr(da, db) == pathlab.compare(a, b)["psnr"]
    assert np.array_equal(pathlab.to_display(a.image, "gamma:1.6"), da)
    srgb = pathlab.to_display(a.image)
    x = np.clip(a.image.astype(np.float64), 0, 1)
    expected = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    assert np.abs(srgb - expected).max() < 1e-6
