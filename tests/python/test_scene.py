"""Scenes from files, JSON text and dicts, and their errors (the CLI's file and field wording)."""
import json

import pytest

import decalcomp
from conftest import SAMPLE


def test_dict_and_file_load_the_same_scene():
    text = (SAMPLE / "scene.json").read_text()
    from_file = decalcomp.Scene.load(str(SAMPLE / "scene.json"))
    from_dict = decalcomp.Scene.from_dict(json.loads(text), base_dir=str(SAMPLE))
    from_text = decalcomp.Scene.from_json(text, base_dir=str(SAMPLE))
    assert len(from_file) == len(from_dict) == len(from_text) == 13
    assert from_file.decal_names == from_dict.decal_names == from_text.decal_names
    assert decalcomp.load_scene(json.loads(text), base_dir=str(SAMPLE)).decal_names == from_file.decal_names


def test_bad_field_names_label_and_path():
    with pytest.raises(decalcomp.InputError) as raised:
        decalcomp.Scene.from_dict({"decals": [{"translate": [0, 0, 0], "affects": {"roughness": {"value": 0.5}}, "opacity": "half"}]}, label="shot.json")
    assert str(raised.value).startswith("shot.json: decals[0].opacity: ")


def test_missing_texture_names_the_file(tmp_path):
    scene = {"decals": [{"translate": [0, 0, 0], "texture": "nowhere.png"}]}
    with pytest.raises(decalcomp.InputError, match="nowhere.png"):
        decalcomp.Scene.from_dict(scene, base_dir=str(tmp_path))


def test_scene_file_errors_match_the_cli(cli, tmp_path):
    from conftest import run_cli
    bad = tmp_path / "bad.json"
    bad.write_text('{"decals": [ {"translate": [0, 0, 0], }')
    with pytest.raises(decalcomp.InputError) as raised:
        decalcomp.Scene.load(str(bad))
    done = run_cli(cli, "composite", SAMPLE / "gbuffer.exr", "--decals", bad, "--device", "cpu",
                   "-o", tmp_path / "o.exr", expect=3)
    assert str(raised.value) in done.stderr


def test_devices_lists_pocl_cpu():
    devices = decalcomp.devices()
    assert any(d.type == "cpu" for d in devices)
    assert [d.index for d in devices] == list(range(len(devices)))


OCIO_CONFIG = SAMPLE.parent / "ocio" / "config.ocio"


def test_colour_managed_scene_names_its_working_space_and_config():
    scene = {"working_space": "ACEScg", "decals": [{"translate": [0, 0, 0], "texture": "textures/scorch.png"}]}
    loaded = decalcomp.Scene.from_dict(scene, base_dir=str(SAMPLE), ocio=str(OCIO_CONFIG))
    assert loaded.working_space == "ACEScg"
    assert loaded.colour_config == str(OCIO_CONFIG)
    assert decalcomp.load_scene(scene, base_dir=str(SAMPLE), ocio=str(OCIO_CONFIG)).working_space == "ACEScg"
    assert decalcomp.Scene.load(str(SAMPLE / "scene.json")).working_space == ""


def test_colour_space_without_a_config_is_the_clis_error(monkeypatch):
    monkeypatch.delenv("OCIO", raising=False)
    with pytest.raises(decalcomp.InputError) as raised:
        decalcomp.Scene.from_dict({"working_space": "ACEScg", "decals": []}, label="shot.json")
    assert str(raised.value) == ("shot.json: working_space: colour spaces need an OpenColorIO config: "
                                 "give --ocio FILE or set $OCIO")
