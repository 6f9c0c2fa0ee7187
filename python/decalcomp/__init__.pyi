# Type stubs of the decalcomp module (the package and its compiled _decalcomp part).
import os
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class Error(RuntimeError): ...
class UsageError(Error): ...
class InputError(Error): ...
class DeviceError(Error): ...
class OutputError(Error): ...

class Device:
    index: int
    name: str
    vendor: str
    platform: str
    version: str
    type: str  # "gpu", "cpu", "accelerator" or "other"

def devices() -> list[Device]: ...

class Scene:
    source: str
    warnings: list[str]
    decal_names: list[str]
    animated: bool
    working_space: str  # the OpenColorIO space colour textures were converted to ("" = built-in decode)
    colour_config: str  # the OpenColorIO config read ("" = none)
    @staticmethod
    def load(path: str, ocio: str = "") -> Scene: ...
    @staticmethod
    def from_json(text: str, label: str = "<json>", base_dir: str = ".", ocio: str = "") -> Scene: ...
    @staticmethod
    def from_dict(scene: dict[str, Any], label: str = "<dict>", base_dir: str = ".", ocio: str = "") -> Scene: ...
    def __len__(self) -> int: ...

Matrix4 = npt.ArrayLike  # 4x4, row-major mathematical order: m[row][col]

class Camera:
    source: str
    def __init__(self, world_to_camera: Matrix4, projection: Matrix4) -> None: ...
    @staticmethod
    def load(path: str) -> Camera: ...
    @property
    def world_to_camera(self) -> npt.NDArray[np.float64]: ...
    @property
    def projection(self) -> npt.NDArray[np.float64]: ...

CameraLike = Union[Camera, Tuple[Matrix4, Matrix4], str]
SceneLike = Union[Scene, Mapping[str, Any], str, os.PathLike[str]]

class Compositor:
    def __init__(self, device: str = "", scene: Optional[Scene] = None) -> None: ...
    def set_scene(self, scene: Scene) -> None: ...
    def composite(
        self,
        planes: Mapping[str, npt.ArrayLike],
        camera: CameraLike,
        *,
        depth: str = "planar",
        reversed_z: bool = False,
        normals: str = "world",
        pixel_filter: str = "none",
        uv_origin: str = "bottom",
        frame: Optional[float] = None,
        binned: bool = True,
    ) -> dict[str, npt.NDArray[np.float32]]: ...
    def composite_files(
        self,
        inputs: Union[str, Sequence[str]],
        output: str,
        *,
        camera: Optional[CameraLike] = None,
        passes: Optional[Mapping[str, str]] = None,
        preview: Optional[str] = None,
        overwrite_input: bool = False,
        force: bool = False,
        profile: str = "auto",
        profile_files: Sequence[str] = (),
        layer: str = "",
        channels: Optional[Mapping[str, Union[str, Sequence[str]]]] = None,
        depth: Optional[str] = None,
        reversed_z: bool = False,
        normals: Optional[str] = None,
        add_channels: Optional[Mapping[str, Optional[float]]] = None,
        pixel_filter: Optional[str] = None,
        uv_origin: Optional[str] = None,
        frame: Optional[float] = None,
        binned: bool = True,
    ) -> dict[str, Any]: ...
    @property
    def device(self) -> Device: ...
    @property
    def last_stats(self) -> dict[str, Any]: ...

def load_scene(scene: SceneLike, base_dir: str = ".", ocio: str = "") -> Scene: ...
def composite_files(inputs: Union[str, Sequence[str]], output: Union[str, os.PathLike[str]], scene: SceneLike, *,
                    device: str = "", **options: Any) -> dict[str, Any]: ...
def bake(
    scene: Union[Scene, str, os.PathLike[str]],
    output_dir: Union[str, os.PathLike[str]],
    *,
    decal: Optional[str] = None,
    png: bool = True,
    device: Optional[str] = None,
    ocio: Optional[str] = None,
) -> dict[str, Any]: ...
def batch(
    input: str,
    output: str,
    scene: str,
    *,
    extra_inputs: Sequence[str] = (),
    passes: Optional[Mapping[str, str]] = None,
    preview: Optional[str] = None,
    contact_sheet: Optional[str] = None,
    frames: Optional[str] = None,
    camera: Optional[str] = None,
    cameras: Optional[str] = None,
    device: Optional[str] = None,
    overwrite_input: bool = False,
    force: bool = False,
    resume: bool = False,
    keep_going: bool = False,
    shard: Optional[str] = None,
    threads: int = 0,
    queue: int = 2,
    workers: int = 0,
    progress: Optional[Callable[[dict[str, Any]], None]] = None,
    profile: str = "auto",
    profile_files: Sequence[str] = (),
    layer: str = "",
    channels: Optional[Mapping[str, Union[str, Sequence[str]]]] = None,
    depth: Optional[str] = None,
    reversed_z: bool = False,
    normals: Optional[str] = None,
    add_channels: Optional[Mapping[str, Optional[float]]] = None,
    pixel_filter: Optional[str] = None,
    ocio: Optional[str] = None,
    binned: bool = True,
) -> dict[str, Any]: ...
