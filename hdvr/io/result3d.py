"""3D result files: the output of ``hdvr fit3d`` (and later the lifter), the input of movement recognition.

NPZ keys (fixed):

- ``keypoints3d``          float32 (T, 25, 3): BODY_25 keypoints, metres, camera frame (x right, y down, z forward).
- ``qpos``                 float64 (T, 41): dancer configuration in the dancer world (x forward at identity root,
                           z up, floor at z = 0; see :mod:`hdvr.skeleton`, hinges in DH-row order).
- ``joint_names``          str (25,): BODY_25 names.
- ``focal``                float64 (T,): focal length per frame, pixels.
- ``principal_point``      float64 (T, 2): pixels.
- ``bone_lengths``         float64 (9,): metres, order :data:`hdvr.dh.BONE_NAMES`.
- ``reprojection_error_px`` float64 (T,): mean distance between projected and observed visible keypoints, pixels.

Further keys (written always, optional on reading): ``fps`` (float), ``camera_rotation`` (3, 3) and
``camera_centre`` (3,) mapping the dancer world to the camera (``P_cam = R (P_world - C)``, so
``keypoints3d = R (world keypoints of qpos - C)``), ``meta`` (JSON string: settings, plausibility figures).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.atomic import save_npz_atomic
from hdvr.io.npz import open_npz
from hdvr.layouts import BODY25_NAMES

RESULT3D_KEYS = ("keypoints3d", "qpos", "joint_names", "focal", "principal_point", "bone_lengths",
                 "reprojection_error_px")


@dataclass
class Result3D:
    """A dancer's 3D motion (see module docstring for units and frames)."""

    keypoints3d: np.ndarray
    qpos: np.ndarray
    focal: np.ndarray
    principal_point: np.ndarray
    bone_lengths: np.ndarray
    reprojection_error_px: np.ndarray
    joint_names: tuple[str, ...] = BODY25_NAMES
    fps: float = 30.0
    camera_rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    camera_centre: np.ndarray = field(default_factory=lambda: np.zeros(3))
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.keypoints3d = np.asarray(self.keypoints3d, dtype=np.float32)
        t = self.keypoints3d.shape[0] if self.keypoints3d.ndim == 3 else -1
        if self.keypoints3d.ndim != 3 or self.keypoints3d.shape[1:] != (25, 3):
            raise HDVRError(f"keypoints3d must be (T, 25, 3) metres, got {self.keypoints3d.shape}")
        self.qpos = np.asarray(self.qpos, dtype=np.float64)
        if self.qpos.shape != (t, 41):
            raise HDVRError(f"qpos must be (T={t}, 41), got {self.qpos.shape}")
        self.focal = np.broadcast_to(np.asarray(self.focal, dtype=np.float64), (t,)).copy()
        self.principal_point = np.broadcast_to(np.asarray(self.principal_point, dtype=np.float64), (t, 2)).copy()
        self.bone_lengths = np.asarray(self.bone_lengths, dtype=np.float64)
        if self.bone_lengths.shape != (9,):
            raise HDVRError(f"bone_lengths must be (9,) metres, got {self.bone_lengths.shape}")
        self.reprojection_error_px = np.broadcast_to(np.asarray(self.reprojection_error_px, dtype=np.float64),
                                                     (t,)).copy()
        if tuple(self.joint_names) != BODY25_NAMES:
            raise HDVRError("3D results must use BODY_25 joint names in OpenPose order")
        self.joint_names = BODY25_NAMES
        self.camera_rotation = np.asarray(self.camera_rotation, dtype=np.float64).reshape(3, 3)
        self.camera_centre = np.asarray(self.camera_centre, dtype=np.float64).reshape(3)

    @property
    def num_frames(self) -> int:
        return int(self.keypoints3d.shape[0])


def save_result3d(path: str | os.PathLike, r: Result3D) -> None:
    """Write ``r`` to ``path`` (NPZ, atomically)."""
    save_npz_atomic(path, keypoints3d=r.keypoints3d, qpos=r.qpos, joint_names=np.array(r.joint_names),
                    focal=r.focal, principal_point=r.principal_point, bone_lengths=r.bone_lengths,
                    reprojection_error_px=r.reprojection_error_px, fps=np.float64(r.fps),
                    camera_rotation=r.camera_rotation, camera_centre=r.camera_centre,
                    meta=np.array(json.dumps(r.meta, default=float)))


def load_result3d(path: str | os.PathLike) -> Result3D:
    """Read a 3D result NPZ; raise :class:`HDVRError` naming the problem if it is malformed."""
    data = open_npz(path, RESULT3D_KEYS, "3D result")
    extra = {}
    if "fps" in data.files:
        extra["fps"] = float(data["fps"])
    if "camera_rotation" in data.files:
        extra["camera_rotation"] = data["camera_rotation"]
    if "camera_centre" in data.files:
        extra["camera_centre"] = data["camera_centre"]
    if "meta" in data.files:
        try:
            extra["meta"] = json.loads(str(data["meta"]))
        except json.JSONDecodeError:
            raise HDVRError(f"3D result file {path} has a corrupt 'meta' entry") from None
    return Result3D(keypoints3d=data["keypoints3d"], qpos=data["qpos"], focal=data["focal"],
                    principal_point=data["principal_point"], bone_lengths=data["bone_lengths"],
                    reprojection_error_px=data["reprojection_error_px"],
                    joint_names=tuple(data["joint_names"].tolist()), **extra)
