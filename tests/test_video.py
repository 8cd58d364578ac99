import os
import subprocess
import sys

import cv2
import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.video import VideoReader, VideoWriter, probe_video, read_frame


def _frames(n=12, size=(97, 64)):
    rng = np.random.default_rng(0)
    base = rng.integers(0, 255, (size[1], size[0], 3), dtype=np.uint8)
    base = cv2.GaussianBlur(base, (9, 9), 3)
    return [np.roll(base, 2 * i, axis=1) for i in range(n)]


def _write(path, frames):
    with VideoWriter(path, fps=25.0, size=(97, 64), crf=12) as writer:
        for f in frames:
            writer.write(f)


def test_h264_round_trip_odd_size(tmp_path):
    frames = _frames()
    path = tmp_path / "out.mp4"
    _write(path, frames)
    assert not list(tmp_path.glob(".out.mp4*")), "temporary file removed"
    import av

    with av.open(str(path)) as c:
        assert c.streams.video[0].codec_context.name == "h264"
    reader = VideoReader(path)
    assert reader.info.fps == pytest.approx(25.0)
    back = list(reader)
    assert len(back) == len(frames)
    assert back[0].shape[:2] in [(64, 98), (64, 97)]
    err = np.abs(back[5][:, :97].astype(float) - frames[5].astype(float)).mean()
    assert err < 6.0, f"decoded frame differs by {err:.1f} grey levels on average"


def test_writer_abort_leaves_nothing(tmp_path):
    path = tmp_path / "x.mp4"
    with pytest.raises(RuntimeError):
        with VideoWriter(path, fps=30, size=(32, 32)) as w:
            w.write(np.zeros((32, 32, 3), np.uint8))
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_writer_rejects_wrong_frame_size(tmp_path):
    with VideoWriter(tmp_path / "x.mp4", fps=30, size=(32, 32)) as w:
        with pytest.raises(HDVRError, match="differs"):
            w.write(np.zeros((16, 32, 3), np.uint8))
        w.write(np.zeros((32, 32, 3), np.uint8))


@pytest.mark.parametrize("fourcc,suffix", [("MJPG", ".avi"), ("VP90", ".webm")])
def test_reads_other_containers(tmp_path, fourcc, suffix):
    path = tmp_path / f"clip{suffix}"
    vw = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), 20.0, (64, 48))
    if not vw.isOpened():
        pytest.skip(f"this OpenCV build cannot write {fourcc}")
    for f in _frames(8, (64, 48)):
        vw.write(f)
    vw.release()
    reader = VideoReader(path)
    assert (reader.info.width, reader.info.height) == (64, 48)
    assert len(list(reader)) == 8


def test_reads_h264_in_a_quicktime_mov(tmp_path):
    """Phones record H.264 in a QuickTime .mov: written here with PyAV's libx264, read back frame by frame."""
    import av

    path = tmp_path / "phone.mov"
    with av.open(str(path), "w") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = 64, 48, "yuv420p"
        written = _frames(10, (64, 48))
        for frame in written:
            container.mux(stream.encode(av.VideoFrame.from_ndarray(frame, format="bgr24")))
        container.mux(stream.encode())
    reader = VideoReader(path)
    assert (reader.info.width, reader.info.height, reader.info.fps) == (64, 48, 25.0)
    frames = list(reader)
    assert len(frames) == 10 and frames[0].shape == (48, 64, 3)
    for got, sent in zip(frames, written):  # lossy, but the same picture, in BGR order
        assert np.abs(got.astype(int) - sent.astype(int)).mean() < 12


def test_bad_inputs(tmp_path):
    with pytest.raises(HDVRError, match="not found"):
        VideoReader(tmp_path / "missing.mp4")
    empty = tmp_path / "empty.mp4"
    empty.write_bytes(b"")
    with pytest.raises(HDVRError, match="empty"):
        VideoReader(empty)
    junk = tmp_path / "junk.mp4"
    junk.write_bytes(b"this is not a video" * 100)
    with pytest.raises(HDVRError, match="cannot read video|no decodable frame"):
        probe_video(junk)


def test_truncated_video_keeps_decoded_frames(tmp_path):
    path = tmp_path / "full.mp4"
    with VideoWriter(path, fps=30, size=(160, 120)) as w:
        for f in _frames(60, (160, 120)):
            w.write(f)
    data = path.read_bytes()
    cut = tmp_path / "cut.mp4"
    cut.write_bytes(data[: len(data) // 2])
    try:
        reader = VideoReader(cut)
    except HDVRError:
        return  # a cut that removes the index is a clear error too
    n = sum(1 for _ in reader)
    assert 0 < n <= 60


def test_real_video_streams(shared_data):
    path = shared_data / "video" / "two-people-tree" / "video.mp4"
    reader = VideoReader(path)
    assert reader.info.size == (1768, 994)
    assert reader.info.fps == pytest.approx(30.0, abs=0.1)
    n = 0
    for frame in reader:
        assert frame.shape == (994, 1768, 3)
        n += 1
        if n == 20:
            break
    assert n == 20


def test_background_rgb_writer_matches_foreground_bgr(tmp_path):
    """Encoding in a worker thread from RGB frames gives the same video as the plain BGR writer."""
    yy, xx = np.mgrid[0:48, 0:64]
    frames = [np.stack([(xx * 4 + 9 * t) % 256, (yy * 5) % 256, (xx + yy + 30 * t) % 256], -1).astype(np.uint8)
              for t in range(5)]
    with VideoWriter(tmp_path / "bgr.mp4", 10, (64, 48), crf=0) as w:
        for f in frames:
            w.write(f)
    with VideoWriter(tmp_path / "rgb.mp4", 10, (64, 48), crf=0, pixel_format="rgb24", background=True) as w:
        for f in frames:
            w.write(f[..., ::-1])
    with VideoReader(tmp_path / "bgr.mp4") as a, VideoReader(tmp_path / "rgb.mp4") as b:
        got_a, got_b = list(a), list(b)
    assert len(got_a) == len(got_b) == 5
    for x, y, src in zip(got_a, got_b, frames):
        assert np.abs(x.astype(int) - y.astype(int)).mean() < 1.0  # same up to colour-conversion rounding
        assert np.abs(y.astype(int) - src.astype(int)).mean() < 8.0  # and close to what was written


def test_a_file_that_is_no_video_gives_one_error_line_with_libav_s_reason(tmp_path):
    """Neither OpenCV's FFmpeg nor PyAV prints its own log line beside hdvr's error (fresh process: OpenCV reads
    its log level once)."""
    junk = tmp_path / "junk.mp4"
    junk.write_text("hello\n")
    env = {k: v for k, v in os.environ.items() if k != "OPENCV_FFMPEG_LOGLEVEL"}
    proc = subprocess.run([sys.executable, "-m", "hdvr", "track", str(junk), "--dancers", "1", "--out",
                           str(tmp_path / "out")], capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode != 0
    assert proc.stderr.strip().splitlines() == [
        f"hdvr: error: cannot read video {junk}: not a video file or corrupt (moov atom not found)"]


def test_read_frame_gives_exactly_the_numbered_frame_and_names_one_past_the_end(tmp_path):
    frames = _frames()
    path = tmp_path / "v.mp4"
    _write(path, frames)
    decoded = list(VideoReader(path))
    for index in (0, 5, len(frames) - 1):
        np.testing.assert_array_equal(read_frame(path, index), decoded[index])
    with pytest.raises(HDVRError, match=r"frame 12 is past the end of v.mp4 \(12 frames, 0-11\)"):
        read_frame(path, 12)
    with pytest.raises(HDVRError, match="counted from 0"):
        read_frame(path, -1)
