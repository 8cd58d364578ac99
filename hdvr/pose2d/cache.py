"""The detector's people per frame, kept in a file so that tracking the same video again (after a correction, with
other tracker options) does not run the pose model again on the frames it has seen.

``detections.npz`` (written by ``hdvr track`` into its output folder, atomically) holds, for every whole frame the
detector looked at, the people it found there (:class:`hdvr.pose2d.base.PersonPose`):

- ``frames`` (F,) int: the 0-based frames the detector ran on (a frame with nobody found is listed too);
- ``person_frame`` (P,) int, ``box`` (P, 4) x, y, w, h px, ``score`` (P,), ``weak`` (P,) bool, ``keypoints``
  (P, J, 3) x_px, y_px, confidence in the detector's layout, ``joint_names`` (J,);
- ``signature``: JSON text naming the video (file name, size in bytes, modification time, frame size) and the
  detector with every setting that changes what it finds (:func:`detector_signature`). A file whose signature
  differs from the run's is not used (and is replaced at the end of the run).

Only whole frames are kept: crops the tracker looks at zoomed in (``zoom_detections``) depend on where the tracker
is and are run each time. Detectors without a ``cache_key()`` method (precomputed OpenPose output, which is already
a file) are not cached.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from hdvr.io.atomic import save_npz_atomic
from hdvr.pose2d.base import PersonPose

CACHE_FORMAT = "hdvr-detections-1"


def detector_signature(detector) -> dict | None:
    """What identifies ``detector``'s results: its ``cache_key()`` (a dict of the model and the settings that change
    what it finds), or None when it has none (its results are not cached)."""
    key = getattr(detector, "cache_key", None)
    return None if key is None else {"name": detector.name, **key()}


def video_signature(video: str | os.PathLike, frame_size: tuple[int, int]) -> dict:
    """The video file as far as a cache needs to know it is the same one: name, bytes, modification time (ns) and
    frame size (width, height px)."""
    stat = Path(video).stat()
    return {"name": Path(video).name, "bytes": stat.st_size, "mtime_ns": stat.st_mtime_ns,
            "frame_size": [int(frame_size[0]), int(frame_size[1])]}


def load_detections(path: str | os.PathLike, signature: dict) -> dict[int, list[PersonPose]]:
    """The people per frame stored in ``path`` if it exists and was written for ``signature``; else ``{}`` (a
    missing, unreadable or foreign file only means the detector runs again)."""
    p = Path(path)
    if not p.is_file():
        return {}
    try:
        with np.load(p, allow_pickle=False) as data:
            expected = json.loads(json.dumps({"format": CACHE_FORMAT, **signature}))  # tuples as JSON lists
            if json.loads(str(data["signature"])) != expected:
                return {}
            names = tuple(str(n) for n in data["joint_names"])
            found: dict[int, list[PersonPose]] = {int(t): [] for t in data["frames"]}
            for t, box, score, weak, kp in zip(data["person_frame"], data["box"], data["score"], data["weak"],
                                               data["keypoints"]):
                found[int(t)].append(PersonPose(kp.copy(), tuple(float(v) for v in box), float(score), names,
                                                weak=bool(weak)))
            return found
    except (OSError, ValueError, KeyError, EOFError):
        return {}


def save_detections(path: str | os.PathLike, signature: dict, found: dict[int, list[PersonPose]]) -> Path:
    """Write ``found`` (frame -> people) to ``path`` (atomically) under ``signature``; returns the path."""
    frames = sorted(found)
    people = [(t, p) for t in frames for p in found[t]]
    names = people[0][1].joint_names if people else ()
    if any(tuple(p.joint_names) != tuple(names) for _, p in people):
        raise ValueError("detections in one cache must share one keypoint layout")
    joints = len(names)
    save_npz_atomic(
        path, signature=np.array(json.dumps({"format": CACHE_FORMAT, **signature}, sort_keys=True)),
        frames=np.array(frames, np.int64), person_frame=np.array([t for t, _ in people], np.int64),
        box=np.array([p.box for _, p in people], np.float64).reshape(-1, 4),
        score=np.array([p.score for _, p in people], np.float64),
        weak=np.array([p.weak for _, p in people], bool),
        keypoints=(np.array([p.keypoints for _, p in people], np.float32) if people
                   else np.zeros((0, joints, 3), np.float32)),
        joint_names=np.array(names, dtype=str))
    return Path(path)


class CachingDetector:
    """``detector`` with its whole-frame results taken from ``stored`` (frame -> people, from
    :func:`load_detections`) where they are there, and everything it finds on whole frames kept in :attr:`found`
    for :func:`save_detections`. Crops (any other image size than ``frame_size``) always go to the detector."""

    def __init__(self, detector, frame_size: tuple[int, int], stored: dict[int, list[PersonPose]] | None = None):
        self.detector = detector
        self.name = detector.name
        self.supports_crops = getattr(detector, "supports_crops", True)
        self.frame_size = (int(frame_size[0]), int(frame_size[1]))
        self.stored = dict(stored or {})
        self.found: dict[int, list[PersonPose]] = {}
        self.reused = 0  # whole frames answered from the file

    def detect(self, frame_bgr: np.ndarray, frame_index: int) -> list[PersonPose]:
        whole = (frame_bgr.shape[1], frame_bgr.shape[0]) == self.frame_size
        if whole and frame_index in self.stored:
            self.reused += 1
            people = self.stored[frame_index]
        else:
            people = self.detector.detect(frame_bgr, frame_index)
        if whole:
            self.found[frame_index] = people
        return people

    def at_input_size(self, input_size: int):
        """The wrapped detector at another input size, for crops (which never come from the file), where it has
        one (:meth:`hdvr.pose2d.onnx_pose.OnnxPoseDetector.at_input_size`); else this one."""
        resize = getattr(self.detector, "at_input_size", None)
        return resize(input_size) if resize is not None else self

    def all_found(self) -> dict[int, list[PersonPose]]:
        """What the file held and what this run found (this run's answer where both have a frame)."""
        return {**self.stored, **self.found}
