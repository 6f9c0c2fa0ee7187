"""decalcomp: decals composited into rendered G-buffer EXRs on OpenCL devices.

Load a scene once, composite many frames (docs/python.md)::

    import decalcomp
    compositor = decalcomp.Compositor(device="gpu", scene=decalcomp.Scene.load("decals.json"))
    report = compositor.composite_files("beauty.0001.exr", "out/beauty.0001.exr")

Every call releases the GIL while it works; failures raise decalcomp.Error subclasses whose
message is the CLI's (file and field).
"""
from __future__ import annotations

import os
from typing import Any, Mapping, Union

from ._decalcomp import (
    Camera,
    Compositor,
    Device,
    DeviceError,
    Error,
    InputError,
    OutputError,
    Scene,
    UsageError,
    __version__,
    bake,
    batch,
    devices,
)

__all__ = [
    "Camera", "Compositor", "Device", "DeviceError", "Error", "InputError", "OutputError", "Scene",
    "UsageError", "__version__", "bake", "batch", "composite_files", "devices", "load_scene",
]

SceneLike = Union[Scene, Mapping[str, Any], str, "os.PathLike[str]"]


def load_scene(scene: SceneLike, base_dir: str = ".", ocio: str = "") -> Scene:
    """A Scene from a Scene (returned as is), a scene-format dict (paths relative to base_dir) or a JSON path.
    `ocio`: the OpenColorIO config of the scene's colour spaces (default: $OCIO)."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(dict(scene), base_dir=base_dir, ocio=ocio)
    return Scene.load(os.fspath(scene), ocio=ocio)


def composite_files(inputs, output, scene: SceneLike, *, device: str = "", **options) -> dict:
    """One frame, as `decalcomp composite INPUTS --decals SCENE -o OUTPUT`: opens the device and
    loads the scene for this call only (keep a Compositor to composite many frames)."""
    return Compositor(device, load_scene(scene)).composite_files(inputs, os.fspath(output), **options)
