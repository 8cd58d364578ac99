"""2D keypoint files: the contract between the video stage (tracking + 2D pose) and the 3D stage.

NPZ keys (fixed):

- ``keypoints``    float32 (T, J, 3): x_px, y_px (image pixels, origin top-left, x right, y down), confidence
                   in [0, 1]. A missing keypoint has confidence 0 and NaN coordinates.
- ``joint_names``  str (J,): the layout's joint names (BODY_25 canonical; COCO-17 and H36M-17 accepted).
- ``fps``          float scalar: frames per second of the source video.
- ``image_size``   int (2,): (width, height) in pixels.

Readers for an OpenPose JSON folder (``*_keypoints.json``; BODY_25 or COCO-17 ordered ``pose_keypoints_2d``)
and for COCO keypoint JSON (``annotations`` with ``keypoints`` [x, y, v] * 17) convert into it.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.atomic import save_npz_atomic
from hdvr.io.npz import open_npz
from hdvr.layouts import BODY25, BODY25_NAMES, COCO17_NAMES, Layout, convert, guess_layout

KEYPOINTS2D_KEYS = ("keypoints", "joint_names", "fps", "image_size")


@dataclass
class Keypoints2D:
    """A single dancer's 2D keypoints over time (see module docstring for units)."""

    keypoints: np.ndarray  # (T, J, 3) float32: x_px, y_px, confidence
    joint_names: tuple[str, ...]
    fps: float
    image_size: tuple[int, int]  # (width, height) px

    def __post_init__(self) -> None:
        kp = np.asarray(self.keypoints, dtype=np.float32)
        if kp.ndim != 3 or kp.shape[2] != 3:
            raise HDVRError(f"keypoints must be shaped (T, J, 3) = x_px, y_px, confidence; got {kp.shape}")
        if kp.shape[1] != len(self.joint_names):
            raise HDVRError(f"keypoints have {kp.shape[1]} joints but {len(self.joint_names)} joint names")
        guess_layout(self.joint_names)  # raises on unknown names
        if not np.isfinite(self.fps) or self.fps <= 0:
            raise HDVRError(f"fps must be a positive number, got {self.fps}")
        w, h = (int(v) for v in self.image_size)
        if w <= 0 or h <= 0:
            raise HDVRError(f"image_size must be positive (width, height), got {self.image_size}")
        conf = kp[..., 2]
        conf = np.where(np.isfinite(conf), np.clip(conf, 0.0, 1.0), 0.0)
        missing = (conf <= 0) | ~np.isfinite(kp[..., :2]).all(axis=-1)
        kp[..., 2] = np.where(missing, 0.0, conf)
        kp[missing, :2] = np.nan
        self.keypoints = kp
        self.joint_names = tuple(str(n) for n in self.joint_names)
        self.fps = float(self.fps)
        self.image_size = (w, h)

    @property
    def num_frames(self) -> int:
        return int(self.keypoints.shape[0])

    @property
    def layout(self) -> Layout:
        return guess_layout(self.joint_names)

    def to_body25(self) -> "Keypoints2D":
        """The same keypoints in BODY_25 order (derived joints as in :mod:`hdvr.layouts`)."""
        if self.layout is BODY25:
            return self
        kp = convert(self.keypoints, self.layout, BODY25, has_confidence=True).astype(np.float32)
        return Keypoints2D(kp, BODY25_NAMES, self.fps, self.image_size)

    def visible_fraction(self) -> float:
        return float((self.keypoints[..., 2] > 0).mean()) if self.keypoints.size else 0.0


def save_keypoints2d(path: str | os.PathLike, kp: Keypoints2D, compress: bool = True) -> None:
    """Write ``kp`` to ``path`` (NPZ, atomically; ``compress=False`` writes faster, larger files)."""
    save_npz_atomic(path, compress, keypoints=kp.keypoints.astype(np.float32), joint_names=np.array(kp.joint_names),
                    fps=np.float64(kp.fps), image_size=np.array(kp.image_size, dtype=np.int64))


def load_keypoints2d(path: str | os.PathLike, require_visible: bool = True) -> Keypoints2D:
    """Read a 2D keypoint NPZ; raise :class:`HDVRError` naming the problem if it is malformed.

    With ``require_visible`` a file where no keypoint is visible (all NaN / confidence 0) is an error.
    """
    data = open_npz(path, KEYPOINTS2D_KEYS, "2D keypoint")
    kp = Keypoints2D(data["keypoints"], tuple(data["joint_names"].tolist()), float(data["fps"]),
                     tuple(int(v) for v in data["image_size"]))
    if kp.num_frames == 0:
        raise HDVRError(f"2D keypoint file {path} has zero frames")
    if require_visible and kp.visible_fraction() == 0:
        raise HDVRError(f"2D keypoint file {path} has no visible keypoint (all NaN or confidence 0)")
    return kp


def read_openpose_folder(folder: str | os.PathLike, fps: float, image_size: tuple[int, int],
                         person: int = 0) -> Keypoints2D:
    """Read an OpenPose ``--write_json`` folder (one ``*_keypoints.json`` per frame, sorted by name).

    ``pose_keypoints_2d`` of 25 joints is read as BODY_25, of 17 as COCO-17 order (converted to BODY_25).
    ``person`` picks the index in ``people``; frames without that person are missing.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise HDVRError(f"OpenPose JSON folder not found: {folder}")
    files = sorted(folder.glob("*.json"))
    if not files:
        raise HDVRError(f"no OpenPose JSON files (*.json) in {folder}")
    frames = []
    n_joints = None
    for f in files:
        try:
            doc = json.loads(f.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError):
            raise HDVRError(f"corrupt OpenPose JSON file: {f}") from None
        people = doc.get("people", [])
        if person < len(people):
            flat = np.asarray(people[person].get("pose_keypoints_2d", []), dtype=np.float64)
            if flat.size % 3:
                raise HDVRError(f"pose_keypoints_2d length {flat.size} is not a multiple of 3 in {f}")
            arr = flat.reshape(-1, 3)
            if n_joints is None:
                n_joints = arr.shape[0]
            elif arr.shape[0] != n_joints:
                raise HDVRError(f"{f} has {arr.shape[0]} joints, earlier files had {n_joints}")
            frames.append(arr)
        else:
            frames.append(None)
    if n_joints is None:
        raise HDVRError(f"no person {person} in any OpenPose JSON file in {folder}")
    if n_joints not in (25, 17):
        raise HDVRError(f"OpenPose files have {n_joints} joints; expected 25 (BODY_25) or 17 (COCO-17)")
    names = BODY25_NAMES if n_joints == 25 else COCO17_NAMES
    kp = np.stack([f if f is not None else np.zeros((n_joints, 3)) for f in frames]).astype(np.float32)
    kp[kp[..., 2] <= 0, :2] = np.nan  # OpenPose writes (0, 0, 0) for missing joints
    return Keypoints2D(kp, names, fps, image_size).to_body25()


def read_coco_json(path: str | os.PathLike, fps: float, track_id: int | None = None) -> Keypoints2D:
    """Read COCO keypoint JSON (``images`` + ``annotations``), one annotation per image, frames in image order.

    Visibility v = 0 is missing; v = 1, 2 give confidence 1. ``track_id`` selects annotations with that
    ``track_id`` (PoseTrack style) when several people are annotated per image; otherwise the first is used.
    """
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"COCO keypoint JSON not found: {p}")
    try:
        doc = json.loads(p.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError):
        raise HDVRError(f"corrupt COCO keypoint JSON: {p}") from None
    images = sorted(doc.get("images", []), key=lambda im: (im.get("frame_id", im["id"]), im["id"]))
    if not images:
        raise HDVRError(f"COCO JSON {p} has no images")
    by_image: dict[int, list] = {}
    for ann in doc.get("annotations", []):
        if track_id is not None and ann.get("track_id") != track_id:
            continue
        by_image.setdefault(ann["image_id"], []).append(ann)
    kp = np.zeros((len(images), 17, 3), dtype=np.float32)
    for t, im in enumerate(images):
        anns = by_image.get(im["id"], [])
        if not anns:
            continue
        arr = np.asarray(anns[0]["keypoints"], dtype=np.float32).reshape(-1, 3)
        if arr.shape[0] != 17:
            raise HDVRError(f"COCO annotation in {p} has {arr.shape[0]} keypoints, expected 17")
        kp[t, :, :2] = arr[:, :2]
        kp[t, :, 2] = (arr[:, 2] > 0).astype(np.float32)
    size = (int(images[0].get("width", 1)), int(images[0].get("height", 1)))
    return Keypoints2D(kp, COCO17_NAMES, fps, size).to_body25()
