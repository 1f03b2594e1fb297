"""pathlab: a GPU path tracer for studying Monte Carlo rendering, from Python.

Scenes in (pathlab TOML or Mitsuba 3 XML), numpy arrays out::

    import pathlab
    scene = pathlab.load_scene("assets/scenes/study.toml", width=256, height=128)
    r = pathlab.render(scene, "mis", spp=64)        # r.image: float32 (H, W, 3), linear
    ref = pathlab.render(scene, "best", spp=4096)
    pathlab.compare(r, ref)["rel_mse"]

Every render runs on one GPU device, opened at the first render and reused for the rest of
the process (``PATHLAB_ADAPTER`` picks one by name; ``pathlab.adapters()`` lists them). Renders
release the GIL; Ctrl-C stops one within a dispatch and raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _pathlab
from ._pathlab import GpuError, RenderError, Scene, SceneError
from . import metrics
from .metrics import _image

__version__: str = _pathlab.VERSION

__all__ = [
    "Scene",
    "Technique",
    "Render",
    "Renderer",
    "SceneError",
    "GpuError",
    "RenderError",
    "load_scene",
    "render",
    "compare",
    "to_display",
    "metrics",
    "study",
    "advise",
    "write_exr",
    "read_exr",
    "adapters",
    "device",
    "names",
]

PathLike = Union[str, "os.PathLike[str]"]
#: Most samples per pixel a render may take (sample indices are 32-bit).
MAX_SPP: int = _pathlab.MAX_SPP


# ---------------------------------------------------------------------------------------------
# Argument checks: a wrong type is a TypeError, an impossible value a ValueError, each naming
# the argument.


def _whole(name: str, value: Any, minimum: int, maximum: Optional[int] = None) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, not {type(value).__name__}")
    v = int(value)
    if v < minimum:
        raise ValueError(f"{name} must be at least {minimum}, not {v}")
    if maximum is not None and v > maximum:
        raise ValueError(f"{name} must be at most {maximum}, not {v}")
    return v


def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number, not {type(value).__name__}")
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, not {value!r}")
    return v


def _name(argument: str, value: Any) -> Optional[str]:
    """A str or None (the native side says which names are known)."""
    if value is None:
        return None
    if not isinstance(value, str):
        raise TypeError(f"{argument} must be a str, not {type(value).__name__}")
    return value


def _path(argument: str, value: Any) -> str:
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{argument} must be a path (str or os.PathLike), not {type(value).__name__}")
    return os.fspath(value)


def _scene(scene: Any) -> Scene:
    """A Scene, or the scene a path names."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(scene)
    raise TypeError(f"scene must be a pathlab.Scene or a path, not {type(scene).__name__}")


# ---------------------------------------------------------------------------------------------
# Progress: a tqdm bar when asked for and tqdm is installed; nothing is printed otherwise.


class _Progress:
    """The callback the native side calls with ``(kind, position, total, text)``."""

    def __init__(self, enabled: bool, description: str) -> None:
        if not isinstance(enabled, bool):
            raise TypeError(f"progress must be a bool, not {type(enabled).__name__}")
        self.tqdm: Any = None
        self.bar: Any = None
        self.description = description
        if enabled:
            try:
                from tqdm.auto import tqdm  # type: ignore[import-untyped]
            except ImportError:
                warnings.warn("progress=True shows a tqdm bar: install tqdm (pip install tqdm)", stacklevel=3)
            else:
                self.tqdm = tqdm

    def callback(self) -> Optional[Callable[[str, float, float, str], None]]:
        return self if self.tqdm is not None else None

    def _open(self, total: float, unit: str) -> None:
        if self.bar is None:
            whole = unit != "s"
            self.bar = self.tqdm(total=int(total) if whole else total, unit=unit, desc=self.description, leave=False)

    def __call__(self, kind: str, position: float, total: float, text: str) -> None:
        if kind == "samples":
            self._open(total, "spp")
            self.bar.n = int(position)
            self.bar.refresh()
        elif kind == "seconds":
            # A time budget: the bar runs over seconds, the samples so far beside it.
            self._open(total, "s")
            self.bar.n = round(position, 1)
            self.bar.set_postfix_str(text, refresh=False)
            self.bar.refresh()
        elif kind.startswith("begin-"):
            self.close()
            self._open(total, {"begin-samples": "spp", "begin-seconds": "s", "begin-runs": "runs"}[kind])
        elif kind == "update" and self.bar is not None:
            self.bar.n = position
            if text:
                self.bar.set_postfix_str(text, refresh=False)
            self.bar.refresh()
        elif kind == "end":
            self.close()
        elif kind in ("stage", "note"):
            self.tqdm.write(text)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _warnings_too(progress: _Progress) -> Callable[[str, float, float, str], None]:
    """A callback that turns the library's warnings into Python warnings, and passes the rest
    to the progress bar (if any)."""
    bar = progress.callback()

    def callback(kind: str, position: float, total: float, text: str) -> None:
        if kind == "warn":
            warnings.warn(text, stacklevel=2)
        elif bar is not None:
            bar(kind, position, total, text)

    return callback


# ---------------------------------------------------------------------------------------------
# Scenes.


@dataclass(frozen=True)
class Technique:
    """A sampling technique of your own: one WGSL file implementing the contract of
    ``shaders/technique.wgsl`` (README, "Your own technique"). ``Technique("light:cone.wgsl")``
    or ``Technique("cone.wgsl", kind="light")``; ``kind`` is ``"bsdf"`` (directions at Phong
    materials) or ``"light"`` (points on spherical lights). Load it with
    ``load_scene(..., techniques=[t])`` (or ``scene.with_technique``); methods then use it as
    ``"mis+light=NAME"``, NAME the file's stem (``t.name``). ``render``, ``Renderer`` and
    ``study`` check it (chi-square and coverage, as ``pathlab check-technique``) before its first
    use and raise ``RenderError`` with the report if it is refused, unless ``allow_unproven``.
    """

    path: str
    kind: str
    #: Used even where it fails its check, every result marked unproven (``technique_verdict``
    #: in the header ``UNPROVEN: ...``; a study's rows marked as the biased demonstrations).
    allow_unproven: bool

    def __init__(self, path: PathLike, kind: Optional[str] = None, *, allow_unproven: bool = False) -> None:
        p = _path("path", path)
        if kind is None:
            k, sep, rest = p.partition(":")
            if not sep or k not in ("bsdf", "light"):
                raise ValueError(f"Technique({p!r}): give KIND:FILE.wgsl (KIND bsdf, light or env), or kind=")
            kind, p = k, rest
        if kind not in ("bsdf", "light"):
            raise ValueError(f"Technique kind must be 'bsdf' or 'light', not {kind!r}")
        object.__setattr__(self, "path", p)
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "allow_unproven", bool(allow_unproven))

    @property
    def name(self) -> str:
        """The name methods use: the file's stem."""
        return os.path.splitext(os.path.basename(self.path))[0]

    def method(self, base: str = "mis") -> str:
        """``base`` using this technique, e.g. ``"mis+light=cone"``."""
        return f"{base}+{self.kind}={self.name}"


def load_scene(
    path: PathLike,
    *,
    defines: Optional[Mapping[str, Any]] = None,
    techniques: Sequence[Technique] = (),
    **overrides: Any,
) -> Scene:
    """Reads and validates a scene: pathlab TOML, or Mitsuba 3 XML (``.xml``).

    Keyword overrides replace render settings: ``width``, ``height``, ``max_depth``,
    ``rr_depth`` (an int, or None / ``"off"``) and ``spp`` (the default of ``render``).
    ``defines`` gives a Mitsuba scene's ``$name`` values (Mitsuba's ``-D name=value``).
    ``techniques`` loads researchers' techniques (``Technique``) with the scene.

    Raises ``SceneError`` (a ``ValueError``) with the CLI's ``file:line:column: error: ...``
    message for a file that cannot be read or is invalid.
    """
    p = _path("path", path)
    pairs: List[Tuple[str, str]] = []
    if defines is not None:
        if not isinstance(defines, Mapping):
            raise TypeError(f"defines must be a dict of $name values, not {type(defines).__name__}")
        for k, v in defines.items():
            if not isinstance(k, str):
                raise TypeError(f"defines: a name is a str, not {type(k).__name__}")
            pairs.append((k, str(v).lower() if isinstance(v, bool) else str(v)))
    scene = _pathlab.load_scene(p, pairs, overrides)
    for t in techniques:
        if not isinstance(t, Technique):
            raise TypeError(f"techniques: a Technique, not {type(t).__name__}")
        scene = scene.with_technique(t.kind, t.path, t.allow_unproven)
    return scene


# ---------------------------------------------------------------------------------------------
# Renders.


@dataclass
class Render:
    """A finished render: the image estimate and what made it.

    ``image`` is the per-pixel mean radiance, float32 (H, W, 3), linear, top row first;
    ``variance`` the per-pixel variance of that mean (when asked for, else None); ``metadata``
    the fields of the EXR header ``pathlab render`` writes (text, as in the file).
    """

    image: np.ndarray
    variance: Optional[np.ndarray]
    spp: int
    seconds: float
    rays: int
    metadata: Dict[str, str] = field(default_factory=dict)
    #: A render to a target error: the estimate, whether it was reached, and its history.
    error_estimate: Optional[Dict[str, Any]] = None

    @property
    def method(self) -> Optional[str]:
        """The method's name, as the header records it."""
        return self.metadata.get("method")

    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) in pixels."""
        return (self.image.shape[1], self.image.shape[0])

    def to_display(self, display: Optional[str] = None, *, exposure: Optional[float] = None) -> np.ndarray:
        """The display image (float32 (H, W, 3) in [0, 1], for ``plt.imshow``): through
        ``display`` (default: the header's transform, else sRGB) at ``exposure`` stops."""
        return to_display(self.image, display or self.metadata.get("display", "srgb"), exposure=float(self.metadata.get("exposure", 0.0)) if exposure is None else exposure)

    def __repr__(self) -> str:
        w, h = self.size
        return f"pathlab.Render({w}x{h}, method={self.method!r}, spp={self.spp}, seconds={self.seconds:.3f}, rays={self.rays})"


def _render_of(parts: Tuple[Any, ...], variance: bool) -> Render:
    # (An interrupted render raises KeyboardInterrupt instead of returning.)
    image, var, spp, seconds, rays, metadata, _interrupted, error = parts
    return Render(
        image=image,
        variance=var if variance else None,
        spp=spp,
        seconds=seconds,
        rays=rays,
        metadata=dict(metadata),
        error_estimate=json.loads(error) if error is not None else None,
    )


def render(
    scene: Union[Scene, PathLike],
    method: Optional[str] = None,
    spp: Optional[int] = None,
    seed: int = 0,
    *,
    sampler: Optional[str] = None,
    bsdf: Optional[str] = None,
    lights: Optional[str] = None,
    time: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    variance: bool = False,
    progress: bool = False,
) -> Render:
    """Renders ``scene`` with ``method`` (a preset such as ``"plain"``, ``"mis"``, ``"best"``),
    exactly as ``pathlab render`` does: the same scene, method, seed and spp give the same
    image, bit for bit. Without a method, ``"best"``, and ``"best+env"`` under an environment
    map (as ``pathlab render``).

    ``spp`` defaults to the scene's ``render.spp``, else 64; ``time`` renders for that many
    seconds instead. ``target_rel_error`` renders until the estimated relative MSE (no
    reference needed) is at most this, ``spp`` and ``time`` then being upper bounds.
    ``sampler``, ``bsdf`` and ``lights`` override the preset's strategies. ``variance=True``
    also returns the per-pixel variance of the mean. ``progress=True`` shows a tqdm bar.
    """
    s = _scene(scene)
    named = _name("method", method)
    method_name: str = named if named is not None else _pathlab.default_method(s)
    if spp is not None:
        spp = _whole("spp", spp, 1, MAX_SPP)
    seed = _whole("seed", seed, 0, 2**32 - 1)
    if time is not None:
        time = _positive("time", time)
        if spp is not None and target_rel_error is None:
            raise ValueError("give spp or time, not both (with target_rel_error both are upper bounds)")
    if target_rel_error is not None:
        target_rel_error = _positive("target_rel_error", target_rel_error)
    if not isinstance(variance, bool):
        raise TypeError(f"variance must be a bool, not {type(variance).__name__}")
    bar = _Progress(progress, f"render {method_name}")
    try:
        parts = _pathlab.render(
            s,
            method_name,
            seed,
            spp,
            time,
            target_rel_error,
            _name("sampler", sampler),
            _name("bsdf", bsdf),
            _name("lights", lights),
            bar.callback(),
        )
    finally:
        bar.close()
    return _render_of(parts, variance)


class Renderer:
    """A progressive render for convergence plots: ``add`` samples, look at ``image``, add
    more. After adds of n1, n2, ... samples the image equals one ``render`` of n1 + n2 + ...
    samples with the same scene, method and seed, bit for bit.

    Ctrl-C during ``add`` raises ``KeyboardInterrupt`` and keeps the samples finished until
    then (``spp`` says how many); adding more continues the same sequence.
    """

    def __init__(
        self,
        scene: Union[Scene, PathLike],
        method: str = "best",
        seed: int = 0,
        *,
        sampler: Optional[str] = None,
        bsdf: Optional[str] = None,
        lights: Optional[str] = None,
    ) -> None:
        self.scene: Scene = _scene(scene)
        self.method: str = _name("method", method)  # type: ignore[assignment]
        seed = _whole("seed", seed, 0, 2**32 - 1)
        self._native = _pathlab.NativeRenderer(
            self.scene,
            self.method,
            seed,
            _name("sampler", sampler),
            _name("bsdf", bsdf),
            _name("lights", lights),
        )
        self._snapshot: Optional[Render] = None

    def add(self, spp: int, *, progress: bool = False) -> "Renderer":
        """Adds ``spp`` samples per pixel (returns the renderer, so calls chain)."""
        spp = _whole("spp", spp, 1, MAX_SPP)
        bar = _Progress(progress, f"add {self.method}")
        self._snapshot = None
        try:
            self._native.add(spp, bar.callback())
        finally:
            bar.close()
        return self

    @property
    def spp(self) -> int:
        """Samples per pixel accumulated so far."""
        return self._native.spp

    def render(self, variance: bool = True) -> Render:
        """The render so far, read back from the GPU (cached until the next ``add``)."""
        if self._snapshot is None or self._snapshot.spp != self.spp:
            self._snapshot = _render_of(self._native.film(), True)
        r = self._snapshot
        return r if variance else Render(r.image, None, r.spp, r.seconds, r.rays, r.metadata)

    @property
    def image(self) -> np.ndarray:
        """The mean so far: float32 (H, W, 3)."""
        return self.render().image

    @property
    def variance(self) -> np.ndarray:
        """The per-pixel variance of the mean so far: float32 (H, W, 3)."""
        return self.render().variance  # type: ignore[return-value]

    @property
    def seconds(self) -> float:
        """Seconds of rendering over all adds."""
        return self._native.seconds

    def __repr__(self) -> str:
        return f"pathlab.Renderer({self.scene!r}, method={self.method!r}, spp={self.spp})"


# ---------------------------------------------------------------------------------------------
# Comparing.


def to_display(image: Union["Render", np.ndarray], display: str = "srgb", *, exposure: float = 0.0) -> np.ndarray:
    """Linear radiance through a display transform (``"srgb"``, ``"gamma:2.2"``) at
    ``exposure`` stops: float32 (H, W, 3) in [0, 1], what PNGs, figures and PSNR/SSIM/FLIP see."""
    if isinstance(image, Render):
        return image.to_display(display, exposure=exposure)
    if not isinstance(display, str):
        raise TypeError(f"display must be a str such as 'srgb' or 'gamma:2.2', not {type(display).__name__}")
    if isinstance(exposure, bool) or not isinstance(exposure, (int, float)) or not np.isfinite(exposure):
        raise ValueError(f"exposure must be a finite number of stops, not {exposure!r}")
    return _pathlab.to_display(_image("image", image), display, float(exposure))



def _spp(x: Any) -> int:
    return x.spp if isinstance(x, Render) else 0


def _variance_of(x: Any) -> Optional[np.ndarray]:
    if isinstance(x, Render) and x.variance is not None:
        return _image("variance", x.variance)
    return None


def compare(
    test: Union[Render, np.ndarray],
    reference: Union[Render, np.ndarray],
    display: Optional[str] = None,
    *,
    exposure: Optional[float] = None,
    block: int = 1,
) -> Dict[str, Any]:
    """Every metric of ``test`` against ``reference``: the numbers of ``pathlab compare --json``
    (MSE, relMSE and bias on linear radiance; PSNR, SSIM and FLIP on the display image; the
    per-pixel z-test when both carry variances).

    ``test`` and ``reference`` are ``Render``s or float (H, W, 3) arrays of linear radiance.
    ``display`` is the display transform (``"srgb"``, ``"gamma:2.2"``); by default the one the
    reference's header records, else sRGB. ``block`` runs the z-test on block x block pixels.
    """
    t, r = _image("test", test), _image("reference", reference)
    if t.shape != r.shape:
        raise ValueError(f"test is {t.shape} and reference {r.shape}: the shapes differ")
    recorded = reference.metadata if isinstance(reference, Render) else {}
    display = _name("display", display) or recorded.get("display", "srgb")
    if exposure is None:
        exposure = float(recorded.get("exposure", 0.0))
    elif isinstance(exposure, bool) or not isinstance(exposure, (int, float)) or not np.isfinite(exposure):
        raise ValueError(f"exposure must be a finite number of stops, not {exposure!r}")
    block = _whole("block", block, 1)
    out = _pathlab.compare_json(
        t, _variance_of(test), _spp(test), r, _variance_of(reference), _spp(reference), display, float(exposure), block
    )
    result: Dict[str, Any] = json.loads(out)
    return result


# ---------------------------------------------------------------------------------------------
# The study and the advice.


def study(scene: Union[Scene, PathLike], out_dir: PathLike, *, progress: bool = False, **options: Any) -> Dict[str, Any]:
    """Runs the variance-reduction study (``pathlab study``) into ``out_dir`` and returns its
    ``results.json``. A rerun into the same directory continues where it stopped.

    Options, each as the CLI's flag: ``methods`` (list of names), ``spp`` (list of ints),
    ``time`` (list of seconds), ``seeds``, ``reference`` (an EXR path), ``reference_spp``,
    ``reference_method``, ``size`` ((width, height)), ``max_depth``, ``rr_depth``, ``display``,
    ``target``, ``regions`` (a regions TOML), ``checkpoint_every`` (seconds) and ``quick``
    (a small study: the scene's aspect ratio at 128 pixels on the longer side, a 4096-spp
    reference, two seeds).
    """
    s = _scene(scene)
    out = _path("out_dir", out_dir)
    for key in ("reference", "regions"):
        if options.get(key) is not None:
            options[key] = _path(key, options[key])
    for key in ("spp", "time", "methods"):
        v = options.get(key)
        if v is not None and (isinstance(v, (str, bytes)) or not isinstance(v, Sequence)):
            raise TypeError(f"{key} must be a list, not {type(v).__name__}")
        if v is not None:
            options[key] = list(v)
    bar = _Progress(progress, "study")
    try:
        text = _pathlab.study_json(s, out, options, _warnings_too(bar))
    finally:
        bar.close()
    results: Dict[str, Any] = json.loads(text)
    return results


def advise(
    scene: Union[Scene, PathLike],
    *,
    target_rel_error: Optional[float] = None,
    target_psnr: Optional[float] = None,
    methods: Optional[Sequence[str]] = None,
    pilot_seconds: float = 2.0,
    display: Optional[str] = None,
    progress: bool = False,
) -> List[Dict[str, Any]]:
    """Which method reaches a target error first (``pathlab advise``): a short pilot of each
    method, then the predicted seconds to the target, best first, one dict per method."""
    s = _scene(scene)
    if (target_rel_error is None) == (target_psnr is None):
        raise ValueError("give target_rel_error or target_psnr (one of them)")
    if target_rel_error is not None:
        target_rel_error = _positive("target_rel_error", target_rel_error)
    if target_psnr is not None and not (isinstance(target_psnr, (int, float)) and np.isfinite(target_psnr)):
        raise ValueError(f"target_psnr must be a finite number of dB, not {target_psnr!r}")
    names: Optional[List[str]] = None  # None: every preset
    if methods is not None:
        if isinstance(methods, str) or not isinstance(methods, Sequence):
            raise TypeError(f"methods must be a list of method names, not {type(methods).__name__}")
        names = []
        for n in methods:
            if not isinstance(n, str):
                raise TypeError(f"methods: a method name is a str, not {type(n).__name__}")
            names.append(n)
    pilot = _positive("pilot_seconds", pilot_seconds)
    bar = _Progress(progress, "advise")
    try:
        text = _pathlab.advise_json(s, names, target_rel_error, None if target_psnr is None else float(target_psnr), pilot, _name("display", display), _warnings_too(bar))
    finally:
        bar.close()
    table: List[Dict[str, Any]] = json.loads(text)
    return table


# ---------------------------------------------------------------------------------------------
# Files and devices.


def write_exr(path: PathLike, render: Render, *, variance: Optional[bool] = None) -> None:
    """Writes ``render`` as an EXR (atomically, with its header as ``pathlab render`` writes
    it); ``variance`` (default: when the render has it) adds variance.R/G/B channels."""
    p = _path("path", path)
    if not isinstance(render, Render):
        raise TypeError(f"render must be a pathlab.Render, not {type(render).__name__}")
    with_variance = render.variance is not None if variance is None else variance
    if with_variance and render.variance is None:
        raise ValueError("variance=True, but the render has no variance (render(..., variance=True))")
    image = _image("render.image", render.image)
    var = _image("render.variance", render.variance) if with_variance else None
    _pathlab.write_exr(p, image, var, render.spp, list(render.metadata.items()))


def read_exr(path: PathLike) -> Render:
    """Reads an EXR (any RGB EXR; pathlab's header fields, when present, fill ``metadata``,
    ``spp``, ``seconds`` and ``rays``)."""
    image, var, spp, metadata = _pathlab.read_exr(_path("path", path))
    meta = dict(metadata)
    return Render(
        image=image,
        variance=var,
        spp=spp,
        seconds=float(meta.get("render_seconds", "nan")),
        rays=int(meta.get("rays", 0)),
        metadata=meta,
    )


def adapters() -> List[Dict[str, str]]:
    """Every graphics adapter wgpu can see, best first (name, device_type, backend, driver)."""
    listed: List[Dict[str, str]] = json.loads(_pathlab.adapters_json())
    return listed


def device() -> Dict[str, str]:
    """The adapter this process renders on (opening it if no render has yet). Raises
    ``GpuError`` saying how to install a Vulkan driver when there is none."""
    info: Dict[str, str] = json.loads(_pathlab.device_info())
    return info


def names() -> Dict[str, List[str]]:
    """The values ``method``, ``sampler``, ``bsdf`` and ``lights`` may take."""
    return dict(_pathlab.names())
