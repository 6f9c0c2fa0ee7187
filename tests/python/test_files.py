"""Files through the module are the CLI's files: same bytes, same errors, same refusals."""
import pathlib
import sys

import pytest

import decalcomp
from conftest import ROOT, SAMPLE, run_cli


def test_composite_files_is_the_cli_byte_for_byte(cli, compositor, tmp_path):
    report = compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "py.exr"),
                                        camera=str(SAMPLE / "camera.json"))
    run_cli(cli, "composite", SAMPLE / "gbuffer.exr", "--decals", SAMPLE / "scene.json",
            "--camera", SAMPLE / "camera.json", "--device", "cpu", "-o", tmp_path / "cli.exr", "-q")
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert report["outputs"] == [str(tmp_path / "py.exr")]
    assert report["changed_samples"] > 100_000
    assert report["stats"]["decals"] == 13
    assert report["camera_source"].endswith("camera.json")


def test_one_shot_function_takes_a_scene_path(tmp_path):
    report = decalcomp.composite_files(str(SAMPLE / "gbuffer.exr"), tmp_path / "out.exr", SAMPLE / "scene.json",
                                       device="cpu", camera=str(SAMPLE / "camera.json"))
    assert pathlib.Path(report["outputs"][0]).stat().st_size > 0


def test_camera_object_gives_the_sidecars_result(compositor, tmp_path):
    camera = decalcomp.Camera.load(str(SAMPLE / "camera.json"))
    arrays = decalcomp.Camera(camera.world_to_camera, camera.projection)
    compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "a.exr"), camera=str(SAMPLE / "camera.json"))
    compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "b.exr"), camera=arrays)
    assert (tmp_path / "a.exr").read_bytes() == (tmp_path / "b.exr").read_bytes()


def test_missing_input_raises_the_clis_message(cli, compositor, tmp_path):
    missing = tmp_path / "missing.exr"
    with pytest.raises(decalcomp.InputError) as raised:
        compositor.composite_files(str(missing), str(tmp_path / "out.exr"), camera=str(SAMPLE / "camera.json"))
    done = run_cli(cli, "composite", missing, "--decals", SAMPLE / "scene.json", "--camera", SAMPLE / "camera.json",
                   "--device", "cpu", "-o", tmp_path / "out.exr", expect=3)
    assert str(raised.value) in done.stderr
    assert str(missing) in str(raised.value)
    assert not (tmp_path / "out.exr").exists()


def test_refuses_to_overwrite_its_input(compositor, tmp_path):
    source = tmp_path / "frame.exr"
    source.write_bytes((SAMPLE / "gbuffer.exr").read_bytes())
    before = source.read_bytes()
    with pytest.raises(decalcomp.UsageError, match="overwrite"):
        compositor.composite_files(str(source), str(source), camera=str(SAMPLE / "camera.json"))
    assert source.read_bytes() == before
    compositor.composite_files(str(source), str(source), camera=str(SAMPLE / "camera.json"), overwrite_input=True)
    assert source.read_bytes() != before


def test_bad_keyword_is_a_type_error(compositor, tmp_path):
    with pytest.raises(TypeError, match="camra"):
        compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "o.exr"), camra="x")


def test_bad_mapping_option_names_the_argument(compositor, tmp_path):
    with pytest.raises(decalcomp.UsageError, match="channels\\['albedo'\\]: albedo needs 3"):
        compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "o.exr"),
                                   camera=str(SAMPLE / "camera.json"), channels={"albedo": "albedo.R"})
    with pytest.raises(decalcomp.UsageError, match="depth=sideways"):
        compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "o.exr"), depth="sideways")


def test_same_scene_over_its_output_needs_force(compositor, tmp_path):
    first, second = tmp_path / "first.exr", tmp_path / "second.exr"
    compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(first), camera=str(SAMPLE / "camera.json"))
    with pytest.raises(decalcomp.UsageError, match="already composited with this scene"):
        compositor.composite_files(str(first), str(second), camera=str(SAMPLE / "camera.json"))
    assert not second.exists()
    compositor.composite_files(str(first), str(second), camera=str(SAMPLE / "camera.json"), force=True)
    assert second.exists()


def test_pixel_filter_auto_fast_is_the_clis(cli, compositor, tmp_path):
    """pixel_filter takes the CLI's spellings, "auto:fast" among them (docs/pixel-filter.md)."""
    aa = ROOT / "data" / "blender-aa"
    scene = decalcomp.Scene.load(str(aa / "scene.json"))
    comp = decalcomp.Compositor("cpu", scene)
    report = comp.composite_files(str(aa / "gbuffer.exr"), str(tmp_path / "py.exr"), camera=str(aa / "camera.json"),
                                  pixel_filter="auto:fast")
    assert report["pixel_filter"] == "blackman-harris:3:fast (profile blender)"
    run_cli(cli, "composite", aa / "gbuffer.exr", "--decals", aa / "scene.json", "--camera", aa / "camera.json",
            "--device", "cpu", "--pixel-filter", "blackman-harris:3:fast", "-o", tmp_path / "cli.exr", "-q")
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()


def test_a_long_kernel_build_says_so_on_stderr(monkeypatch, capsys, tmp_path):
    # DECALCOMP_BUILD_NOTICE_AFTER=0: every build counts as long; a fresh device builds its programs
    monkeypatch.setenv("DECALCOMP_BUILD_NOTICE_AFTER", "0")
    fresh = decalcomp.Compositor("cpu", decalcomp.Scene.load(str(SAMPLE / "scene.json")))
    fresh.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "out.exr"), camera=str(SAMPLE / "camera.json"))
    err = capsys.readouterr().err
    assert err.count("decalcomp: note: ") == 1, err
    assert "still compiling the OpenCL kernels for binning and point-sampled shading after 0 s" in err
    monkeypatch.setattr(sys, "stderr", None)  # as under pythonw: the note is dropped, the work done
    decalcomp.Compositor("cpu", decalcomp.Scene.load(str(SAMPLE / "scene.json"))).composite_files(
        str(SAMPLE / "gbuffer.exr"), str(tmp_path / "quiet.exr"), camera=str(SAMPLE / "camera.json"))
    monkeypatch.undo()
    monkeypatch.setenv("DECALCOMP_BUILD_NOTICE_AFTER", "soon")
    with pytest.raises(decalcomp.UsageError, match="DECALCOMP_BUILD_NOTICE_AFTER=soon: not a number of seconds"):
        decalcomp.Compositor("cpu")
