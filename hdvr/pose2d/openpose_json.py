"""Precomputed OpenPose output as a detector: one ``*_keypoints.json`` per frame (sorted by name = frame order),
every person of ``people`` with ``pose_keypoints_2d`` in BODY_25 (25 joints) or COCO-17 (17 joints) order."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES, COCO17_NAMES
from hdvr.pose2d.base import PersonPose, box_from_keypoints


class OpenPoseJsonDetector:
    """Looks up frame ``frame_index``'s people in an OpenPose ``--write_json`` folder."""

    def __init__(self, folder: str | os.PathLike):
        self.folder = Path(folder)
        if not self.folder.is_dir():
            raise HDVRError(f"OpenPose JSON folder not found: {self.folder}")
        self.files = sorted(self.folder.glob("*.json"))
        if not self.files:
            raise HDVRError(f"no OpenPose JSON files (*.json) in {self.folder}")
        self.name = f"openpose-json:{self.folder.name}"
        self.supports_crops = False  # results are looked up by frame index: a crop of the frame finds nothing new

    def detect(self, frame_bgr: np.ndarray, frame_index: int) -> list[PersonPose]:
        if frame_index >= len(self.files):
            return []
        path = self.files[frame_index]
        try:
            doc = json.loads(path.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError):
            raise HDVRError(f"corrupt OpenPose JSON file: {path}") from None
        people = []
        for person in doc.get("people", []):
            flat = np.asarray(person.get("pose_keypoints_2d", []), np.float32)
            if flat.size % 3:
                raise HDVRError(f"pose_keypoints_2d length {flat.size} is not a multiple of 3 in {path}")
            kp = flat.reshape(-1, 3)
            if kp.shape[0] == 25:
                names = BODY25_NAMES
            elif kp.shape[0] == 17:
                names = COCO17_NAMES
            else:
                raise HDVRError(f"{path} has {kp.shape[0]} joints; expected 25 (BODY_25) or 17 (COCO-17)")
            kp = kp.copy()
            kp[kp[:, 2] <= 0, :2] = np.nan  # OpenPose writes (0, 0, 0) for a missing joint
            box = box_from_keypoints(kp)
            if box is None:
                continue
            visible = kp[:, 2] > 0
            people.append(PersonPose(kp, box, float(kp[visible, 2].mean()), names))
        return people
