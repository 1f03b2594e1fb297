"""Type stubs of the native module ``pathlab._pathlab`` (``python/src/lib.rs``). Users call the
package (``pathlab/__init__.py``), which checks arguments and builds ``Render``s; ``Scene`` and
the exceptions are the native ones, re-exported."""

from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

VERSION: str
MAX_SPP: int

class SceneError(ValueError):
    """A scene file that cannot be read or is invalid; the message is the CLI's
    ``file:line:column: error: ...`` (one line per finding)."""

class GpuError(RuntimeError):
    """No usable GPU adapter (the message says how to install a Vulkan driver), or the
    device failed."""

class RenderError(RuntimeError):
    """A render, study or file operation that failed."""

class Scene:
    """A validated scene (``pathlab.load_scene``). Immutable: ``with_`` returns a changed copy."""

    @property
    def path(self) -> str: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) in pixels."""
    @property
    def max_depth(self) -> int:
        """Path segments: 1 = emitters seen directly, 2 = direct lighting, ..."""
    @property
    def rr_depth(self) -> Optional[int]:
        """Russian roulette from this scattering vertex on, or None."""
    @property
    def spp(self) -> Optional[int]:
        """The scene's default samples per pixel (``render.spp``), or None."""
    @property
    def hash(self) -> str:
        """The canonical content hash, as ``pathlab check`` and every EXR header give it."""
    @property
    def num_triangles(self) -> int: ...
    @property
    def num_materials(self) -> int: ...
    @property
    def warnings(self) -> List[str]:
        """Findings that do not stop rendering, as the CLI prints them."""
    @property
    def display(self) -> Tuple[str, float]:
        """The display transform of the display-referred metrics: (transfer, exposure)."""
    @property
    def media(self) -> List[Dict[str, Any]]:
        """One dict per participating medium (name, sigma_t, albedo, phase, g, bounded_by: the
        materials whose surfaces bound it, camera: whether the camera is in it)."""
    @property
    def lights(self) -> List[Dict[str, Any]]:
        """One dict per emissive sphere (kind, index, center, radius, emission, power) and per
        emissive mesh (kind, index, triangles, emission, textured, two_sided, power; where
        `textured`, the emission is a texture over the mesh's uvs and `emission` its mean)."""
    @property
    def techniques(self) -> List[Tuple[str, str, str, str]]:
        """The researchers' techniques loaded: (kind, name, path, sha256) each."""
    def with_technique(self, kind: str, path: str, allow_unproven: bool = False) -> "Scene":
        """A copy with a technique loaded (validated by naga; ValueError at the file's line)."""
    def with_(
        self,
        *,
        width: int = ...,
        height: int = ...,
        max_depth: int = ...,
        rr_depth: Union[int, None, str] = ...,
        spp: int = ...,
    ) -> "Scene":
        """A copy with these render settings replaced (``rr_depth=None`` or ``"off"``: no
        Russian roulette)."""

_Callback = Optional[Callable[[str, float, float, str], None]]
_Parts = Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32], int, float, int, List[Tuple[str, str]], bool, Optional[str]]

class NativeRenderer:
    def __init__(self, scene: Scene, method: str, seed: int, sampler: Optional[str], bsdf: Optional[str], lights: Optional[str]) -> None: ...
    def add(self, spp: int, progress: _Callback) -> int: ...
    @property
    def spp(self) -> int: ...
    @property
    def seconds(self) -> float: ...
    def film(self) -> _Parts: ...

def load_scene(path: Union[str, "PathLike[str]"], defines: List[Tuple[str, str]], kwargs: Optional[Dict[str, Any]] = None) -> Scene: ...
def default_method(scene: Scene) -> str: ...
def render(
    scene: Scene,
    method: str,
    seed: int,
    spp: Optional[int],
    time: Optional[float],
    target_rel_error: Optional[float],
    sampler: Optional[str],
    bsdf: Optional[str],
    lights: Optional[str],
    progress: _Callback,
) -> _Parts: ...
def write_exr(
    path: str,
    image: npt.NDArray[np.float32],
    variance: Optional[npt.NDArray[np.float32]],
    spp: int,
    metadata: List[Tuple[str, str]],
) -> None: ...
def read_exr(path: str) -> Tuple[npt.NDArray[np.float32], Optional[npt.NDArray[np.float32]], int, List[Tuple[str, str]]]: ...
def metric(name: str, test: npt.NDArray[np.float32], reference: npt.NDArray[np.float32], display: Optional[str], exposure: float) -> float: ...
def compare_json(
    test: npt.NDArray[np.float32],
    test_variance: Optional[npt.NDArray[np.float32]],
    test_spp: int,
    reference: npt.NDArray[np.float32],
    reference_variance: Optional[npt.NDArray[np.float32]],
    reference_spp: int,
    display: str,
    exposure: float,
    block: int,
) -> str: ...
def to_display(image: npt.NDArray[np.float32], display: str, exposure: float) -> npt.NDArray[np.float32]: ...
def study_json(scene: Scene, out: str, options: Dict[str, Any], progress: _Callback) -> str: ...
def advise_json(
    scene: Scene,
    methods: Optional[List[str]],
    target_rel_error: Optional[float],
    target_psnr: Optional[float],
    pilot_seconds: float,
    display: Optional[str],
    progress: _Callback,
) -> str: ...
def adapters_json() -> str: ...
def device_info() -> str: ...
def names() -> List[Tuple[str, List[str]]]: ...
