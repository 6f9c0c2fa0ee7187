"""decalcomp.batch is `decalcomp batch`: same files, a progress callback per frame, failures as data
with keep_going and as the CLI's error without it."""
import shutil
import subprocess

import pytest

import decalcomp
from conftest import SAMPLE, run_cli


@pytest.fixture()
def sequence(tmp_path):
    frames = tmp_path / "in"
    frames.mkdir()
    for n in (1, 2, 3):
        shutil.copy(SAMPLE / "gbuffer.exr", frames / f"frame.{n:04d}.exr")
    return frames


def test_batch_writes_the_clis_files(cli, sequence, tmp_path):
    seen = []
    report = decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "py" / "out.####.exr"),
                             str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu",
                             progress=seen.append)
    run_cli(cli, "batch", sequence / "frame.####.exr", "-o", tmp_path / "cli" / "out.####.exr",
            "--decals", SAMPLE / "scene.json", "--camera", SAMPLE / "camera.json", "--device", "cpu", "-q")
    assert report["frames"] == [1, 2, 3] and report["written"] == 3 and report["failed"] == 0
    assert [r["frame"] for r in seen] == [1, 2, 3]
    assert all(r["status"] == "written" for r in seen)
    for n in (1, 2, 3):
        name = f"out.{n:04d}.exr"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_contact_sheet_is_the_clis(cli, sequence, tmp_path):
    (sequence / "frame.0002.exr").write_bytes(b"not an exr")  # a grey cell in both sheets
    report = decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "py" / "out.####.exr"),
                             str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu",
                             keep_going=True, contact_sheet=str(tmp_path / "py.png"))
    assert report["contact_sheet"] == str(tmp_path / "py.png") and report["failed"] == 1
    result = subprocess.run([str(cli), "batch", str(sequence / "frame.####.exr"), "-o", str(tmp_path / "cli" / "out.####.exr"),
                             "--decals", str(SAMPLE / "scene.json"), "--camera", str(SAMPLE / "camera.json"),
                             "--device", "cpu", "-q", "--keep-going", "--contact-sheet", str(tmp_path / "cli.png")],
                            capture_output=True, text=True)
    assert result.returncode != 0, "frame 2 failed"
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_keep_going_reports_failures(sequence, tmp_path):
    (sequence / "frame.0002.exr").write_bytes(b"not an exr")
    report = decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "out.####.exr"),
                             str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu",
                             keep_going=True)
    assert report["written"] == 2 and report["failed"] == 1
    assert [f["frame"] for f in report["failures"]] == [2]
    assert "frame.0002.exr" in report["failures"][0]["message"]
    assert not (tmp_path / "out.0002.exr").exists()


def test_first_failure_raises_and_later_frames_are_not_written(sequence, tmp_path):
    (sequence / "frame.0002.exr").write_bytes(b"not an exr")
    with pytest.raises(decalcomp.InputError, match="frame.0002.exr"):
        decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "out.####.exr"),
                        str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu")
    assert (tmp_path / "out.0001.exr").exists()
    assert not (tmp_path / "out.0003.exr").exists()


def test_an_exception_in_the_callback_stops_the_batch(sequence, tmp_path):
    def stop(result):
        raise KeyboardInterrupt("enough")

    with pytest.raises(KeyboardInterrupt):
        decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "out.####.exr"),
                        str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu",
                        progress=stop)
    assert not (tmp_path / "out.0003.exr").exists()


def test_unknown_keyword_is_a_type_error(sequence, tmp_path):
    with pytest.raises(TypeError, match="keepgoing"):
        decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "o.####.exr"), str(SAMPLE / "scene.json"),
                        keepgoing=True)


def test_a_long_kernel_build_says_so_on_stderr(monkeypatch, capsys, sequence, tmp_path):
    monkeypatch.setenv("DECALCOMP_BUILD_NOTICE_AFTER", "0")  # every build counts as long
    report = decalcomp.batch(str(sequence / "frame.####.exr"), str(tmp_path / "out.####.exr"),
                             str(SAMPLE / "scene.json"), camera=str(SAMPLE / "camera.json"), device="cpu")
    assert report["written"] == 3
    err = capsys.readouterr().err
    assert err.count("decalcomp: note: ") == 1, err
    assert "still compiling the OpenCL kernels for binning and point-sampled shading" in err
