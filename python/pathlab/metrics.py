"""Image metrics on numpy arrays: the same code as ``pathlab compare`` and the study.

``psnr``, ``ssim`` and ``flip`` are display-referred. With ``display=None`` (the default) the
arrays are taken as display values already, as scikit-image takes them: ``psnr(test, ref)``
equals ``skimage.metrics.peak_signal_noise_ratio(ref, test, data_range=1.0)`` and ``ssim`` its
``structural_similarity(ref, test, channel_axis=2, data_range=1.0)``. With ``display="srgb"``
(or ``"gamma:2.2"``; ``exposure`` in stops) linear radiance goes through pathlab's display
transform first. ``mse`` and ``rel_mse`` are on linear radiance.

Arrays are float (H, W, 3): ``float32`` is used as is, other float types are converted.
"""

from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy as np

from . import _pathlab

__all__ = ["psnr", "ssim", "flip", "mse", "rel_mse"]


def _image(name: str, a: Any) -> np.ndarray:
    """``a`` (an array, or a ``Render``'s image) as a C-contiguous float32 (H, W, 3) array;
    a TypeError for a non-float dtype, a ValueError for a wrong shape or a non-finite value."""
    if hasattr(a, "image") and not isinstance(a, np.ndarray):
        a = a.image
    arr = np.asarray(a)
    if not np.issubdtype(arr.dtype, np.floating):
        raise TypeError(f"{name} must be a float array (float32 or float64), not dtype {arr.dtype}")
    if arr.ndim != 3 or arr.shape[2] != 3:
        raise ValueError(f"{name} must have shape (H, W, 3), not {arr.shape}")
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"{name} is empty: shape {arr.shape}")
    out = np.ascontiguousarray(arr, dtype=np.float32)
    if not np.isfinite(out).all():
        raise ValueError(f"{name} has non-finite values: the image cannot be scored")
    return out


def _pair(test: Any, reference: Any) -> Tuple[np.ndarray, np.ndarray]:
    t, r = _image("test", test), _image("reference", reference)
    if t.shape != r.shape:
        raise ValueError(f"test is {t.shape} and reference {r.shape}: the shapes differ")
    return t, r


def _metric(name: str, test: Any, reference: Any, display: Optional[str], exposure: float) -> float:
    if display is not None and not isinstance(display, str):
        raise TypeError(f"display must be a str such as 'srgb' or 'gamma:2.2', not {type(display).__name__}")
    if isinstance(exposure, bool) or not isinstance(exposure, (int, float)) or not np.isfinite(exposure):
        raise ValueError(f"exposure must be a finite number of stops, not {exposure!r}")
    t, r = _pair(test, reference)
    return _pathlab.metric(name, t, r, display, float(exposure))


def psnr(test: Any, reference: Any, *, display: Optional[str] = None, exposure: float = 0.0) -> float:
    """Peak signal-to-noise ratio in dB, peak 1 (infinite for identical images)."""
    return _metric("psnr", test, reference, display, exposure)


def ssim(test: Any, reference: Any, *, display: Optional[str] = None, exposure: float = 0.0) -> float:
    """SSIM (Wang et al. 2004) as scikit-image computes it: 7x7 uniform windows, sample
    covariances, the mean over channels of the pixels whose window lies inside the image."""
    return _metric("ssim", test, reference, display, exposure)


def flip(test: Any, reference: Any, *, display: Optional[str] = None, exposure: float = 0.0) -> float:
    """NVIDIA's FLIP (LDR, 67 pixels per degree): the mean error, 0 for identical images."""
    return _metric("flip", test, reference, display, exposure)


def mse(test: Any, reference: Any) -> float:
    """Mean squared error over pixels and channels, on linear radiance."""
    return _metric("mse", test, reference, None, 0.0)


def rel_mse(test: Any, reference: Any) -> float:
    """Relative MSE: the mean of (test - ref)^2 / (ref^2 + 0.01), on linear radiance."""
    return _metric("rel_mse", test, reference, None, 0.0)
