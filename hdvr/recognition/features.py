"""Body-frame features for movement recognition.

The paper feeds each body part's LSTM the trajectories of the joints J_e connected to that part. Here a BODY_25
3D sequence (T, 25, 3), metres, in any frame with gravity along -z (world) or +y (camera), is first expressed in
a body frame so that the features do not depend on where the dancer stands, which way they face, or their size:

- origin at mid_hip; x forward (perpendicular to the hip line, horizontal), y to the dancer's left, z up;
- lengths divided by the clip's median torso length (mid_hip to neck).

Per joint and frame the features are position (3) and velocity (3, torso lengths per second): (T, J_e, 6).
Missing joints (NaN) become zeros.
"""

from __future__ import annotations

import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES

#: Joints connected to each of the 16 body parts (names as in hdvr/data/movements.json).
PART_JOINTS: dict[str, tuple[str, ...]] = {
    "head": ("neck", "nose", "left_eye", "right_eye", "left_ear", "right_ear"),
    "neck": ("mid_hip", "neck", "nose", "left_ear", "right_ear"),
    "left_shoulder": ("neck", "left_shoulder", "right_shoulder", "mid_hip"),
    "right_shoulder": ("neck", "right_shoulder", "left_shoulder", "mid_hip"),
    "left_upper_arm": ("neck", "left_shoulder", "left_elbow"),
    "right_upper_arm": ("neck", "right_shoulder", "right_elbow"),
    "left_lower_arm": ("left_shoulder", "left_elbow", "left_wrist"),
    "right_lower_arm": ("right_shoulder", "right_elbow", "right_wrist"),
    "torso": ("mid_hip", "neck", "left_shoulder", "right_shoulder", "left_hip", "right_hip"),
    "hips": ("mid_hip", "left_hip", "right_hip", "neck", "left_knee", "right_knee"),
    "left_upper_leg": ("mid_hip", "left_hip", "left_knee"),
    "right_upper_leg": ("mid_hip", "right_hip", "right_knee"),
    "left_lower_leg": ("left_hip", "left_knee", "left_ankle"),
    "right_lower_leg": ("right_hip", "right_knee", "right_ankle"),
    "left_foot": ("left_knee", "left_ankle", "left_heel", "left_big_toe", "left_small_toe"),
    "right_foot": ("right_knee", "right_ankle", "right_heel", "right_big_toe", "right_small_toe"),
}

FEATURES_PER_JOINT = 6


def _idx(name: str) -> int:
    return BODY25_NAMES.index(name)


def body_frame(keypoints3d: np.ndarray, up_axis: str = "z") -> np.ndarray:
    """(T, 25, 3) -> (T, 25, 3) in the body frame (see module docstring), in torso lengths.

    ``up_axis``: "z" for HDVR's world (z up), "-y" for camera-frame results (y down).
    """
    kp = np.asarray(keypoints3d, dtype=np.float64)
    if kp.ndim != 3 or kp.shape[1:] != (25, 3):
        raise HDVRError(f"3D keypoints must be (T, 25, 3), got {kp.shape}")
    up = {"z": np.array([0.0, 0.0, 1.0]), "-y": np.array([0.0, -1.0, 0.0])}.get(up_axis)
    if up is None:
        raise HDVRError(f"up_axis must be 'z' or '-y', got {up_axis!r}")
    origin = kp[:, _idx("mid_hip")]
    left = kp[:, _idx("left_hip")] - kp[:, _idx("right_hip")]
    left = left - (left @ up)[:, None] * up
    norm = np.linalg.norm(left, axis=-1, keepdims=True)
    left = np.where(norm > 1e-9, left / np.where(norm > 1e-9, norm, 1.0), np.array([0.0, 1.0, 0.0]))
    forward = np.cross(left, up)
    rot = np.stack([forward, left, np.broadcast_to(up, forward.shape)], axis=1)  # rows: body axes in input frame
    torso = np.linalg.norm(kp[:, _idx("neck")] - origin, axis=-1)
    scale = np.nanmedian(torso) if np.isfinite(torso).any() else 1.0
    if not np.isfinite(scale) or scale <= 0:
        scale = 1.0
    return np.einsum("tij,tkj->tki", rot, kp - origin[:, None]) / scale


def part_features(keypoints3d: np.ndarray, fps: float, up_axis: str = "z") -> dict[str, np.ndarray]:
    """Per part: (T, len(J_e) * 6) features (body-frame positions and velocities), float32, NaN -> 0."""
    body = body_frame(keypoints3d, up_axis)
    vel = np.gradient(body, axis=0) * fps if body.shape[0] > 1 else np.zeros_like(body)
    feats = np.concatenate([body, vel], axis=-1)
    feats = np.where(np.isfinite(feats), feats, 0.0).astype(np.float32)
    return {part: feats[:, [_idx(j) for j in joints]].reshape(feats.shape[0], -1)
            for part, joints in PART_JOINTS.items()}
