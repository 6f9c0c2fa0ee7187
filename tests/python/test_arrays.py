"""Planes in and out of memory: the same pixels as the file path, analytic results, no copies
handed back, the caller's arrays left alone, and the GIL free while the device works."""
import threading
import time

import numpy as np
import pytest

import decalcomp
from conftest import SAMPLE, read_channels, sample_planes

CAMERA = SAMPLE / "camera.json"


def test_arrays_equal_the_file_path_bit_for_bit(compositor, tmp_path):
    compositor.composite_files(str(SAMPLE / "gbuffer.exr"), str(tmp_path / "out.exr"), camera=str(CAMERA))
    written = read_channels(tmp_path / "out.exr")
    changed = compositor.composite(sample_planes(), decalcomp.Camera.load(str(CAMERA)))
    assert sorted(changed) == ["albedo", "metallic", "normal", "roughness"]
    for i, axis in enumerate("RGB"):
        np.testing.assert_array_equal(changed["albedo"][:, :, i], written[f"albedo.{axis}"])
    for i, axis in enumerate("XYZ"):
        np.testing.assert_array_equal(changed["normal"][:, :, i], written[f"N.{axis}"])
    np.testing.assert_array_equal(changed["roughness"], written["roughness"])
    np.testing.assert_array_equal(changed["metallic"], written["metallic"])


def test_results_own_their_memory_and_inputs_stay_untouched(compositor):
    planes = sample_planes()
    before = {name: plane.copy() for name, plane in planes.items()}
    changed = compositor.composite(planes, decalcomp.Camera.load(str(CAMERA)))
    for name, plane in planes.items():
        np.testing.assert_array_equal(plane, before[name])
    for plane in changed.values():
        assert plane.dtype == np.float32 and plane.flags.c_contiguous
        assert not plane.flags.owndata and plane.base is not None  # the library's buffer, no copy
    assert not np.array_equal(changed["albedo"], planes["albedo"])


# A pinhole camera at the origin looking down -Z at a plane facing it, 4 units away.
WIDTH, HEIGHT, FOCAL, DEPTH = 96, 64, 1.5, 4.0
PROJECTION = [[FOCAL * HEIGHT / WIDTH, 0, 0, 0], [0, FOCAL, 0, 0], [0, 0, -1.002, -0.2002], [0, 0, -1, 0]]


def flat_plane_planes():
    return {
        "depth": np.full((HEIGHT, WIDTH), DEPTH, np.float32),
        "albedo": np.full((HEIGHT, WIDTH, 3), 0.5, np.float32),
        "normal": np.dstack([np.zeros((HEIGHT, WIDTH)), np.zeros((HEIGHT, WIDTH)),
                             np.ones((HEIGHT, WIDTH))]).astype(np.float32),
        "object_id": np.where(np.arange(WIDTH)[None, :] < WIDTH // 2, 1.0, 2.0).repeat(HEIGHT, 0).astype(np.float32),
    }


def pixel_world_x():
    ndc_x = 2.0 * (np.arange(WIDTH) + 0.5) / WIDTH - 1.0
    return ndc_x * DEPTH / PROJECTION[0][0]


def box_scene(**extra):
    decal = {"kind": "box", "translate": [0, 0, -DEPTH], "scale": [2.0, 2.0, 1.0],
             "affects": {"albedo": {"value": [0.2, 0.4, 0.8], "op": "replace"}}}
    decal.update(extra)
    return decalcomp.Scene.from_dict({"decals": [decal]})


def test_constant_box_decal_on_a_flat_plane_is_analytic():
    compositor = decalcomp.Compositor("cpu", box_scene())
    camera = decalcomp.Camera(np.eye(4), PROJECTION)
    albedo = compositor.composite(flat_plane_planes(), camera)["albedo"]
    x = pixel_world_x()
    inside, outside = np.abs(x) < 0.9, np.abs(x) > 1.1
    row = albedo[HEIGHT // 2]
    np.testing.assert_allclose(row[inside], np.tile([0.2, 0.4, 0.8], (inside.sum(), 1)), rtol=0, atol=1e-6)
    np.testing.assert_array_equal(row[outside], np.full((outside.sum(), 3), 0.5, np.float32))
    stats = compositor.last_stats
    assert stats["decals"] == 1
    steps = ("bin_coarse_ms", "bin_count_ms", "bin_scan_ms", "bin_fill_ms")
    assert sum(stats[k] for k in steps) == pytest.approx(stats["binning_ms"])


def test_id_mask_limits_the_decal_to_one_object():
    compositor = decalcomp.Compositor("cpu", box_scene(mask={"ids": [1]}))
    albedo = compositor.composite(flat_plane_planes(), decalcomp.Camera(np.eye(4), PROJECTION))["albedo"]
    x = pixel_world_x()
    row = albedo[HEIGHT // 2]
    left = (np.abs(x) < 0.9) & (np.arange(WIDTH) < WIDTH // 2)
    right = (np.abs(x) < 0.9) & (np.arange(WIDTH) >= WIDTH // 2)
    np.testing.assert_allclose(row[left], np.tile([0.2, 0.4, 0.8], (left.sum(), 1)), atol=1e-6)
    np.testing.assert_array_equal(row[right], np.full((right.sum(), 3), 0.5, np.float32))


def test_id_mask_without_an_object_id_plane_names_it():
    compositor = decalcomp.Compositor("cpu", box_scene(mask={"ids": [1]}))
    planes = flat_plane_planes()
    del planes["object_id"]
    with pytest.raises(decalcomp.InputError, match="object_id"):
        compositor.composite(planes, decalcomp.Camera(np.eye(4), PROJECTION))


def test_cryptomatte_masks_need_files():
    compositor = decalcomp.Compositor("cpu", box_scene(mask={"cryptomatte": {"layer": "CryptoObject", "names": ["Sphere"]}}))
    with pytest.raises(decalcomp.InputError, match="[Cc]ryptomatte"):
        compositor.composite(flat_plane_planes(), decalcomp.Camera(np.eye(4), PROJECTION))


@pytest.mark.parametrize("planes, message", [
    ({"depth": np.zeros((4, 4), np.float32), "albedo": np.zeros((4, 4), np.float32)}, r"planes\['albedo'\]: shape 4x4"),
    ({"depth": np.zeros((4, 4), np.float32), "albedo": np.zeros((4, 5, 3), np.float32)}, r"5x4 pixels, the other planes 4x4"),
    ({"depth": np.zeros((4, 4), np.float32), "glitter": np.zeros((4, 4), np.float32)}, r"planes\['glitter'\]: unknown"),
    ({}, "no pixels"),
])
def test_bad_planes_name_the_plane(compositor, planes, message):
    with pytest.raises(decalcomp.InputError, match=message):
        compositor.composite(planes, decalcomp.Camera(np.eye(4), PROJECTION))


def test_non_invertible_camera_is_an_input_error(compositor):
    with pytest.raises(decalcomp.Error, match="invert"):
        compositor.composite(flat_plane_planes(), decalcomp.Camera(np.zeros((4, 4)), PROJECTION))


def test_float64_inputs_are_converted():
    compositor = decalcomp.Compositor("cpu", box_scene())
    planes = {name: plane.astype(np.float64) for name, plane in flat_plane_planes().items()}
    albedo = compositor.composite(planes, decalcomp.Camera(np.eye(4), PROJECTION))["albedo"]
    assert albedo.dtype == np.float32
    np.testing.assert_allclose(albedo[HEIGHT // 2, WIDTH // 2], [0.2, 0.4, 0.8], atol=1e-6)


def test_the_gil_is_released_while_compositing(compositor):
    """The main thread keeps taking turns while another thread composites. Were the GIL held through
    each call, the main thread could wake only between calls (once a switch interval had passed),
    so a few turns at most; released, it wakes about every millisecond. Counting turns, not a
    counter's rate, keeps the test sound on a loaded machine, where PoCL's threads and other tests
    take the cores (a rate against the counter's rate alone failed there once)."""
    planes, camera = sample_planes(), decalcomp.Camera.load(str(CAMERA))
    calls = 3
    started, finished, spans = threading.Event(), threading.Event(), []

    def composite():
        started.set()
        t0 = time.perf_counter()
        try:
            for _ in range(calls):
                compositor.composite(planes, camera)
        finally:
            spans.append(time.perf_counter() - t0)
            finished.set()

    worker = threading.Thread(target=composite)
    worker.start()
    started.wait()
    turns = 0
    while not finished.is_set():
        turns += 1
        time.sleep(0.001)  # gives the GIL back; waking takes it again
    worker.join()
    assert spans[0] > 0.1, "composites too short to tell"
    # held through each call: at most about one turn per call boundary
    assert turns > 3 * (calls + 1), (turns, spans[0])
