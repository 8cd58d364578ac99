"""Video input and output in constant memory.

Reading: :class:`VideoReader` decodes frame by frame (BGR uint8, shape (height, width, 3)) with OpenCV's FFmpeg
backend (fast, H.264 included), falling back to PyAV for containers OpenCV cannot open. Only one frame is held
at a time, so memory does not grow with the length of the video.

Writing: :class:`VideoWriter` encodes H.264 (``libx264``, yuv420p) through PyAV, because OpenCV's headless build
cannot encode H.264. The file is written to a temporary name beside the target and renamed on :meth:`close`,
so an interrupted run never leaves a half-written video under the target name.

FFmpeg's own log lines (e.g. ``moov atom not found`` for a file that is no video) are kept off stderr: a video that
cannot be read gets one ``HDVRError`` line that carries libav's reason. OpenCV's FFmpeg backend is quietened
through ``OPENCV_FFMPEG_LOGLEVEL`` (set here unless the user set it, read when the backend first opens a file).
"""

from __future__ import annotations

import contextlib
import os
import queue
import threading
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Iterator

import cv2
import numpy as np

from hdvr.errors import HDVRError
from hdvr.memory import keep_large_blocks_out_of_heap

os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")  # AV_LOG_QUIET: failures reach the user as HDVRError lines

VIDEO_SUFFIXES = (".mp4", ".avi", ".mov", ".webm", ".mkv", ".m4v")


@dataclass(frozen=True)
class VideoInfo:
    """What a video container says about its stream."""

    width: int  # pixels
    height: int  # pixels
    fps: float  # frames per second
    num_frames: int  # as reported by the container; 0 if unknown (counting needs a full decode)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return (self.width, self.height)


@contextlib.contextmanager
def _libav_messages_captured():
    """Within the block, libav's log messages (errors and worse) are kept on the exceptions PyAV raises
    (``FFmpegError.log``) instead of being printed to stderr; the previous log level is restored after."""
    import av.logging

    level = av.logging.get_level()
    av.logging.set_level(av.logging.ERROR)
    try:
        with av.logging.Capture():
            yield
    finally:
        av.logging.set_level(level)


def _failure_reason(exc: Exception) -> str:
    """Short reason for a failed open: libav's own message where it gave one (e.g. "moov atom not found"), else
    the exception's type."""
    log = getattr(exc, "log", None)
    if log and len(log) == 3 and str(log[2]).strip():
        return str(log[2]).strip()
    return type(exc).__name__


class VideoReader:
    """Iterate over the frames of a video file (BGR uint8), one at a time.

    Raises :class:`HDVRError` if the file is missing, cannot be opened, or has no decodable frame.
    A stream that breaks off mid-way (truncated or corrupt file) ends the iteration; :attr:`frames_read`
    tells how many frames came out, and :attr:`error` says why decoding stopped early, if it did.
    """

    def __init__(self, path: str | os.PathLike):
        self.path = Path(path)
        if not self.path.is_file():
            raise HDVRError(f"video file not found: {self.path}")
        if self.path.stat().st_size == 0:
            raise HDVRError(f"video file is empty (0 bytes): {self.path}")
        self.frames_read = 0
        self.error: str | None = None
        self._backend = "cv2"
        cap = cv2.VideoCapture(str(self.path))
        ok = cap.isOpened()
        first = None
        if ok:
            ok, first = cap.read()
        if ok and first is not None:
            fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
            n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
            h, w = first.shape[:2]
            self._cap = cap
            self._first = first
        else:
            cap.release()
            self._backend = "av"
            w, h, fps, n, first = self._open_with_pyav()
            self._first = first
        if not np.isfinite(fps) or fps <= 0 or fps > 1000:
            fps = 30.0  # containers without a frame rate (image sequences, some webm): assume 30
        self.info = VideoInfo(int(w), int(h), float(fps), max(int(n), 0))

    def _open_with_pyav(self):
        import av

        try:
            with _libav_messages_captured():  # libav would print its reason as a second line; it goes into ours
                self._container = av.open(str(self.path))
            stream = self._container.streams.video[0]
        except (av.FFmpegError, IndexError, OSError, UnicodeDecodeError) as exc:
            raise HDVRError(f"cannot read video {self.path}: not a video file or corrupt "
                            f"({_failure_reason(exc)})") from None
        stream.thread_type = "AUTO"
        self._av_frames = self._container.decode(stream)
        try:
            first = next(self._av_frames).to_ndarray(format="bgr24")
        except (StopIteration, av.FFmpegError):
            self._container.close()
            raise HDVRError(f"video {self.path} has no decodable frame (zero frames or corrupt)") from None
        rate = stream.average_rate or stream.base_rate or 0
        return first.shape[1], first.shape[0], float(rate), int(stream.frames or 0), first

    def __iter__(self) -> Iterator[np.ndarray]:
        if self._first is None:
            raise HDVRError(f"video {self.path} can be iterated only once; open a new VideoReader")
        first, self._first = self._first, None
        self.frames_read = 1
        yield first
        if self._backend == "cv2":
            while True:
                ok, frame = self._cap.read()
                if not ok:
                    if self.info.num_frames and self.frames_read < self.info.num_frames - 1:
                        self.error = (f"decoding stopped after {self.frames_read} of "
                                      f"{self.info.num_frames} frames (truncated or corrupt video)")
                    break
                self.frames_read += 1
                yield frame
        else:
            import av

            try:
                for frame in self._av_frames:
                    self.frames_read += 1
                    yield frame.to_ndarray(format="bgr24")
            except av.FFmpegError as exc:
                self.error = f"decoding stopped after {self.frames_read} frames ({type(exc).__name__})"
        self.close()

    def close(self) -> None:
        if self._backend == "cv2":
            self._cap.release()
        else:
            self._container.close()

    def __enter__(self) -> "VideoReader":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def read_frames(path: str | os.PathLike, indices, show_progress: bool = False) -> Iterator[tuple[int, np.ndarray]]:
    """(index, frame) for each 0-based frame in ``indices`` of the video at ``path``, in ascending order, from one
    pass over the video: BGR uint8 (height, width, 3).

    The frames between are decoded and dropped (seeking in H.264 lands on key frames, not on a given frame, so a
    decode from the start is the one way to get exactly the frames the outputs of ``hdvr track`` number so);
    ``show_progress``: with a progress bar while doing so. Raises :class:`HDVRError` for a negative index or one
    past the last decodable frame (after yielding the frames before it)."""
    from hdvr.progress import progress

    wanted = sorted(set(int(i) for i in indices))
    if wanted and wanted[0] < 0:
        raise HDVRError(f"frame {wanted[0]}: frames are counted from 0")
    if not wanted:
        return
    with VideoReader(path) as reader:
        bar = progress(total=wanted[-1] + 1, desc="decode", unit="frame", disable=not show_progress)
        try:
            for t, frame in enumerate(reader):
                bar.update(1)
                if t == wanted[0]:
                    yield t, frame
                    wanted.pop(0)
                    if not wanted:
                        return
        finally:
            bar.close()
        count = reader.frames_read
    raise HDVRError(f"frame {wanted[0]} is past the end of {Path(path).name} ({count} frames, 0-{count - 1})")


def read_frame(path: str | os.PathLike, index: int, show_progress: bool = False) -> np.ndarray:
    """Frame ``index`` (0-based) of the video at ``path``, BGR uint8 (height, width, 3) (:func:`read_frames`)."""
    _, frame = next(read_frames(path, [index], show_progress))  # raises for a frame it cannot give
    return frame


def probe_video(path: str | os.PathLike) -> VideoInfo:
    """Open ``path``, decode its first frame, and return its :class:`VideoInfo` (raises :class:`HDVRError`)."""
    with VideoReader(path) as reader:
        return reader.info


class VideoWriter:
    """Write uint8 frames (BGR by default, ``pixel_format="rgb24"`` for RGB) to an H.264 MP4, atomically.

    ``size`` is (width, height) in pixels; odd sizes are padded with one black row/column (yuv420p needs
    even sizes). ``crf`` is x264's constant quality (lower = better, 23 = default). ``background=True`` encodes in
    a worker thread (frames are queued), so that rendering and encoding overlap. Use as a context manager: the
    file appears under ``path`` only when the writer closes without an exception.
    """

    def __init__(self, path: str | os.PathLike, fps: float, size: tuple[int, int], crf: int = 23,
                 preset: str = "superfast", pixel_format: str = "bgr24", background: bool = False):
        import av

        keep_large_blocks_out_of_heap()  # frame-sized blocks would otherwise fragment the heap (hdvr.memory)
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.size = (int(size[0]), int(size[1]))
        if self.size[0] <= 0 or self.size[1] <= 0:
            raise HDVRError(f"video size must be positive (width, height), got {size}")
        self._tmp = self.path.with_name(f".{self.path.name}.partial{self.path.suffix or '.mp4'}")
        self._container = av.open(str(self._tmp), mode="w")
        rate = Fraction(float(fps)).limit_denominator(1001)
        self._stream = self._container.add_stream("libx264", rate=rate)
        self._padded = (self.size[0] + self.size[0] % 2, self.size[1] + self.size[1] % 2)
        self._stream.width, self._stream.height = self._padded
        self._stream.pix_fmt = "yuv420p"
        self._stream.options = {"crf": str(crf), "preset": preset}
        self._stream.thread_type = "AUTO"
        self.pixel_format = pixel_format
        self.frames_written = 0
        self._closed = False
        self._queue: queue.Queue | None = None
        self._error: BaseException | None = None
        if background:
            self._queue = queue.Queue(maxsize=16)
            self._thread = threading.Thread(target=self._encode_queued, daemon=True)
            self._thread.start()

    def _encode(self, frame: np.ndarray | None) -> None:
        import av

        packets = self._stream.encode(None if frame is None else
                                      av.VideoFrame.from_ndarray(frame, format=self.pixel_format))
        for packet in packets:
            self._container.mux(packet)

    def _encode_queued(self) -> None:
        try:
            while (frame := self._queue.get()) is not None:
                self._encode(frame)
        except BaseException as exc:  # reported by write() / close()
            self._error = exc
            while self._queue.get() is not None:  # drain so that the producer never blocks
                pass

    def _stop_worker(self) -> None:
        if self._queue is not None:
            self._queue.put(None)
            self._thread.join()
            self._queue = None

    def write(self, frame_bgr: np.ndarray) -> None:
        """Append one (H, W, 3) uint8 frame in the writer's ``pixel_format`` (BGR by default)."""
        h, w = frame_bgr.shape[:2]
        if (w, h) != self.size:
            raise HDVRError(f"frame size {w}x{h} differs from the video size {self.size[0]}x{self.size[1]}")
        if self._padded != self.size:
            frame_bgr = cv2.copyMakeBorder(frame_bgr, 0, self._padded[1] - h, 0, self._padded[0] - w,
                                           cv2.BORDER_CONSTANT)
        if self._error is not None:
            raise HDVRError(f"video encoding failed: {self._error}")
        frame = np.ascontiguousarray(frame_bgr)
        if self._queue is not None:
            self._queue.put(frame.copy())
        else:
            self._encode(frame)
        self.frames_written += 1

    def close(self) -> None:
        """Flush the encoder and move the finished file to ``path``."""
        if self._closed:
            return
        self._closed = True
        self._stop_worker()
        if self._error is not None:
            self._container.close()
            self._tmp.unlink(missing_ok=True)
            raise HDVRError(f"video encoding failed: {self._error}")
        self._encode(None)
        self._container.close()
        os.replace(self._tmp, self.path)

    def abort(self) -> None:
        """Drop the partial file (nothing appears under ``path``)."""
        if self._closed:
            return
        self._closed = True
        try:
            self._stop_worker()
            self._container.close()
        finally:
            self._tmp.unlink(missing_ok=True)

    def __enter__(self) -> "VideoWriter":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()
