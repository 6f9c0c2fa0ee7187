"""decalcomp.bake() is `decalcomp bake`: the same files byte for byte, the same errors."""
import json

import pytest

import decalcomp
from conftest import ROOT, run_cli

DEFORM = ROOT / "data" / "blender-deform"


@pytest.fixture()
def bake_scene(tmp_path):
    """data/blender-deform's decal in bake mode at 128² (small: the test is about the files)."""
    scene = json.loads((DEFORM / "decals.json").read_text())
    decal = scene["decals"][0]
    decal.update(mode="bake", bake_resolution=128, mesh=str(DEFORM / "mesh_rest.obj"),
                 texture=str(DEFORM / "decal_label.png"))
    path = tmp_path / "bake.json"
    path.write_text(json.dumps(scene))
    return path, decal["name"]


def test_bake_is_the_cli_byte_for_byte(cli, bake_scene, tmp_path):
    scene, name = bake_scene
    report = decalcomp.bake(scene, tmp_path / "py", device="cpu")
    run_cli(cli, "bake", "--decals", scene, "--device", "cpu", "-q", "-o", tmp_path / "cli")
    [baked] = report["files"]
    assert baked["decal"] == name and baked["width"] == 128 and baked["dilation"] == 8
    for ext in ("exr", "png"):
        py_file, cli_file = tmp_path / "py" / f"{name}.{ext}", tmp_path / "cli" / f"{name}.{ext}"
        assert baked[ext] == str(py_file)
        assert py_file.read_bytes() == cli_file.read_bytes(), ext
    assert report["warnings"] == []


def test_bake_takes_a_loaded_scene_and_png_false(bake_scene, tmp_path):
    scene, name = bake_scene
    report = decalcomp.bake(decalcomp.Scene.load(str(scene)), str(tmp_path / "out"), decal=name, png=False,
                            device="cpu")
    assert report["files"][0]["png"] is None
    assert (tmp_path / "out" / f"{name}.exr").exists()
    assert not (tmp_path / "out" / f"{name}.png").exists()


def test_bake_errors_are_the_clis(cli, bake_scene, tmp_path):
    scene, _ = bake_scene
    with pytest.raises(decalcomp.InputError) as raised:
        decalcomp.bake(scene, tmp_path / "out", decal="no such decal", device="cpu")
    done = run_cli(cli, "bake", "--decals", scene, "--decal", "no such decal", "--device", "cpu", "-o",
                   tmp_path / "out", expect=3)
    assert done.stderr.strip() == f"decalcomp: error: {raised.value}"
    (tmp_path / "file").write_text("")
    with pytest.raises(decalcomp.UsageError, match="not a folder"):
        decalcomp.bake(scene, tmp_path / "file", device="cpu")
