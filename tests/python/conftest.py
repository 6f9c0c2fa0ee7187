"""Fixtures of the Python module's tests (ctest runs each file; docs/python.md).

The build puts the package in <build>/python (PYTHONPATH) and ctest names the CLI in
DECALCOMP_CLI, so results can be compared with the command line's, byte for byte.
"""
import os
import pathlib
import shutil
import subprocess

import numpy as np
import OpenImageIO as oiio
import pytest

import decalcomp

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "data" / "sample"


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("DECALCOMP_CLI") or shutil.which("decalcomp")
    assert path, "DECALCOMP_CLI is not set and no decalcomp on PATH"
    return path


def run_cli(cli, *args, expect=0):
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == expect, done.stderr
    return done


@pytest.fixture(scope="session")
def sample_scene():
    return decalcomp.Scene.load(str(SAMPLE / "scene.json"))


@pytest.fixture(scope="session")
def compositor(sample_scene):
    """One PoCL CPU device for the session: the program is built once."""
    return decalcomp.Compositor("cpu", sample_scene)


def read_channels(path):
    """Every channel of a single-part EXR as float32 H x W arrays, by name."""
    image = oiio.ImageInput.open(str(path))
    assert image, oiio.geterror()
    spec = image.spec()
    pixels = image.read_image(oiio.FLOAT)
    image.close()
    return {name: np.ascontiguousarray(pixels[:, :, i]) for i, name in enumerate(spec.channelnames)}


def stack(channels, *names):
    return np.ascontiguousarray(np.dstack([channels[n] for n in names]))


def sample_planes():
    """data/sample/gbuffer.exr as the module's planes (its generic channel names)."""
    c = read_channels(SAMPLE / "gbuffer.exr")
    return {
        "depth": c["Z"],
        "albedo": stack(c, "albedo.R", "albedo.G", "albedo.B"),
        "normal": stack(c, "N.X", "N.Y", "N.Z"),
        "roughness": c["roughness"],
        "metallic": c["metallic"],
        "object_id": c["id"],
    }
