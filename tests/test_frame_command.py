"""``hdvr frame``: one frame as a picture with a pixel grid and the tracked boxes, to read a correction off it."""

import cv2
import numpy as np
import pytest

from hdvr.cli import main
from hdvr.tracking.testclips import default_crossing_specs, render_clip
from hdvr.video import VideoReader


@pytest.fixture(scope="module")
def tracked(tmp_path_factory):
    root = tmp_path_factory.mktemp("frame")
    video = root / "clip.mp4"
    truth = render_clip(video, frames=30, specs=default_crossing_specs(num_figures=2, seed=4))
    boxes = ";".join(",".join(f"{v:g}" for v in b) for b in truth.boxes[0])
    assert main(["track", str(video), "--out", str(root / "out"), "--boxes", boxes, "--detector", "none",
                 "--no-overlay", "--no-timeline"]) == 0
    assert not (root / "out" / "timeline.png").exists()
    return video, root / "out"


def test_the_frame_is_written_with_a_grid_and_each_tracked_box_as_a_ready_correction(tracked, tmp_path, capsys):
    video, out = tracked
    capsys.readouterr()
    assert main(["frame", str(video), "12", "--out", str(tmp_path / "f.png"), "--tracks", str(out)]) == 0
    printed = capsys.readouterr().out
    picture = cv2.imread(str(tmp_path / "f.png"))
    original = list(VideoReader(video))[12]
    assert picture.shape == original.shape
    assert (picture[:, 100] == 255).all(axis=1).mean() > 0.8  # the grid (boxes and labels drawn over it)
    assert "frame 12, 640x480 px" in printed
    from hdvr.tracking.boxes import read_tracks_json

    for i, box in enumerate(read_tracks_json(out).boxes[12]):
        x, y, w, h = (int(round(v)) for v in box)
        assert f"dancer {i} (tracked): --correct {i}@12:{x},{y},{w},{h}" in printed
    assert main(["frame", str(video), "12", "--out", str(tmp_path / "plain.jpg"), "--grid", "0"]) == 0
    plain = cv2.imread(str(tmp_path / "plain.jpg"))
    assert np.abs(plain[60:].astype(float) - original[60:]).mean() < 3  # no grid, no boxes: the frame as decoded
    assert (plain[:20, :60] < 40).all(axis=2).any()  # (JPEG) but for the frame number, white on black, top left
    capsys.readouterr()
    assert main(["frame", str(video), "12", "--out", str(tmp_path / "g.png"), "--tracks",
                 str(out / "tracks.json")]) == 0
    assert "dancer 1 (tracked): --correct 1@12:" in capsys.readouterr().out  # the file instead of its folder


def test_several_frames_go_into_a_folder_from_one_pass(tracked, tmp_path, capsys):
    video, out = tracked
    capsys.readouterr()
    assert main(["frame", str(video), "20,3,12", "--out", str(tmp_path / "frames"), "--tracks", str(out)]) == 0
    printed = capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "frames").iterdir()) == [
        "frame_000003.png", "frame_000012.png", "frame_000020.png"]
    assert printed.index("frame_000003") < printed.index("frame_000012") < printed.index("frame_000020")
    assert "--correct 0@20:" in printed


def test_bad_requests_get_one_line_errors(tracked, tmp_path, capsys):
    video, out = tracked
    other = tmp_path / "small.mp4"
    render_clip(other, frames=3, size=(320, 240), specs=default_crossing_specs(num_figures=1, seed=1))
    cases = {("30", "f.png"): "frame 30 is past the end of clip.mp4 (30 frames, 0-29)",
             ("40", "f.png", "--tracks", str(out)): "frame 40 was not tracked",
             ("3", "f.gif"): "give a .png or .jpg",
             ("3,5", "f.png"): "for 2 frames give a folder",
             ("3;5", "f.png"): "cannot read frame",
             ("3,40", "dir", "--tracks", str(out)): "frame 40 was not tracked",
             ("3", "f.png", "--grid", "4"): "at least 10 px",
             ("3", "f.png", "--tracks", str(tmp_path / "none")): "tracks file not found"}
    for (frame, name, *extra), message in cases.items():
        capsys.readouterr()
        assert main(["frame", str(video), frame, "--out", str(tmp_path / name), *extra]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err
    assert main(["frame", str(other), "1", "--out", str(tmp_path / "g.png"), "--tracks", str(out)]) == 2
    assert "not the same video" in capsys.readouterr().err
    assert not list(tmp_path.glob("f.*"))
