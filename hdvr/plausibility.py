"""Physical plausibility of a 3D dance motion, from the MuJoCo dancer.

Inputs are sequences in the dancer world (x forward, y left, z up, floor z = 0, metres): BODY_25 keypoints
(T, 25, 3) and qpos (T, 41). Formulas (also in docs/fitting.md):

- foot penetration (m), per frame: ``max(0, -min_j z_j)`` over the six sole keypoints (toes, heels);
- foot skating (m/s): for each sole keypoint below ``contact_m`` (default 3 cm) in two consecutive frames, the
  horizontal speed ``|| (P_t - P_{t-1})_xy || * fps``; reported as the mean over such contacts;
- self-penetration (m), per frame: the deepest MuJoCo contact (``-dist``) between two body geoms (the floor
  excluded; MuJoCo already skips parent-child pairs), from ``mj_kinematics`` + ``mj_collision``;
- joint-limit violations: hinge values outside ``[lower, upper]`` of the skeleton (count of frame-hinge pairs over
  1e-6 rad, and the largest excess in radians);
- bone-length variation: per bone (keypoint pairs of :data:`MEASURED_BONES`) the coefficient of variation
  ``std_t(L) / mean_t(L)`` of its length over frames; reported as the largest over bones (percent);
- jitter (m/s^3): mean norm of the third difference ``P_{t+1} - 3 P_t + 3 P_{t-1} - P_{t-2}`` times fps^3.
"""

from __future__ import annotations

import mujoco
import numpy as np

from hdvr.layouts import BODY25_NAMES

SOLE_NAMES = ("left_big_toe", "left_small_toe", "left_heel", "right_big_toe", "right_small_toe", "right_heel")
SOLE_IDX = np.array([BODY25_NAMES.index(n) for n in SOLE_NAMES])
MEASURED_BONES: tuple[tuple[str, str], ...] = (
    ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"), ("left_shoulder", "left_elbow"),
    ("left_elbow", "left_wrist"), ("right_hip", "right_knee"), ("right_knee", "right_ankle"),
    ("left_hip", "left_knee"), ("left_knee", "left_ankle"), ("right_shoulder", "left_shoulder"),
    ("right_hip", "left_hip"), ("neck", "mid_hip"),
)
DEFAULT_CONTACT_M = 0.03


def foot_penetration(keypoints_world: np.ndarray) -> np.ndarray:
    """(T,) metres by which the lowest sole keypoint lies below the floor (0 when above)."""
    z = np.asarray(keypoints_world)[:, SOLE_IDX, 2]
    return np.maximum(0.0, -np.nanmin(z, axis=1))


def foot_skating(keypoints_world: np.ndarray, fps: float, contact_m: float = DEFAULT_CONTACT_M) -> np.ndarray:
    """Horizontal speeds (m/s) of sole keypoints that are in contact (z < contact_m) in two consecutive frames."""
    soles = np.asarray(keypoints_world)[:, SOLE_IDX]
    if len(soles) < 2:
        return np.zeros(0)
    contact = soles[:, :, 2] < contact_m
    both = contact[1:] & contact[:-1]
    speed = np.linalg.norm(np.diff(soles[:, :, :2], axis=0), axis=-1) * fps
    return speed[both]


def self_penetration(skeleton, qpos_world: np.ndarray, stride: int = 1) -> np.ndarray:
    """(ceil(T / stride),) deepest body-body penetration (m, 0 if none) per evaluated frame, via MuJoCo contacts."""
    model = skeleton.model
    data = mujoco.MjData(model)
    floor_ids = {i for i in range(model.ngeom) if model.geom_bodyid[i] == 0}
    out = []
    for q in np.asarray(qpos_world)[::stride]:
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        depth = 0.0
        for c in data.contact[:data.ncon]:
            if c.geom1 in floor_ids or c.geom2 in floor_ids:
                continue
            depth = max(depth, -float(c.dist))
        out.append(depth)
    return np.array(out)


def limit_violations(skeleton, qpos: np.ndarray, tolerance_rad: float = 1e-6) -> tuple[int, float]:
    """(number of frame-hinge pairs outside the skeleton's ranges, largest excess in radians)."""
    excess = skeleton.limit_violation(np.asarray(qpos))
    return int(np.sum(excess > tolerance_rad)), float(excess.max(initial=0.0))


def bone_length_cv(keypoints: np.ndarray) -> dict[str, float]:
    """Coefficient of variation (std / mean, fraction) of each measured bone's length over frames."""
    kp = np.asarray(keypoints)
    out = {}
    for a, b in MEASURED_BONES:
        length = np.linalg.norm(kp[:, BODY25_NAMES.index(a)] - kp[:, BODY25_NAMES.index(b)], axis=-1)
        out[f"{a}-{b}"] = float(np.nanstd(length) / max(np.nanmean(length), 1e-12))
    return out


def jitter(keypoints: np.ndarray, fps: float) -> float:
    """Mean norm of the third difference of keypoint positions times fps^3 (m/s^3)."""
    kp = np.asarray(keypoints)
    if len(kp) < 4:
        return float("nan")
    return float(np.nanmean(np.linalg.norm(np.diff(kp, 3, axis=0), axis=-1)) * fps ** 3)


def summarize(skeleton, keypoints_world: np.ndarray, qpos_world: np.ndarray, fps: float,
              self_penetration_stride: int = 5) -> dict[str, float]:
    """Plausibility figures of a clip (see module doc for formulas and units)."""
    pen = foot_penetration(keypoints_world)
    skate = foot_skating(keypoints_world, fps)
    selfpen = self_penetration(skeleton, qpos_world, self_penetration_stride)
    n_viol, max_viol = limit_violations(skeleton, qpos_world)
    cv = bone_length_cv(keypoints_world)
    return {
        "foot_penetration_mean_cm": float(pen.mean() * 100) if len(pen) else 0.0,
        "foot_penetration_p95_cm": float(np.percentile(pen, 95) * 100) if len(pen) else 0.0,
        "foot_skating_mean_cm_s": float(skate.mean() * 100) if len(skate) else 0.0,
        "self_penetration_frames_pct": float(np.mean(selfpen > 0.005) * 100) if len(selfpen) else 0.0,
        "self_penetration_max_cm": float(selfpen.max(initial=0.0) * 100),
        "limit_violations": n_viol,
        "limit_violation_max_deg": float(np.rad2deg(max_viol)),
        "bone_cv_max_pct": float(max(cv.values()) * 100),
        "jitter_m_s3": jitter(keypoints_world, fps),
    }


def world_keypoints(result) -> np.ndarray:
    """The fitted BODY_25 keypoints of a :class:`hdvr.io.result3d.Result3D` in its dancer world (metres):
    ``P_world = R^T P_cam + C``. (Recomputing them from qpos would use one bone set for every frame.)"""
    return np.asarray(result.keypoints3d, dtype=np.float64) @ result.camera_rotation + result.camera_centre


def summarize_result(skeleton, result) -> dict[str, float]:
    """:func:`summarize` for a fitted :class:`hdvr.io.result3d.Result3D`."""
    return summarize(skeleton, world_keypoints(result), result.qpos, result.fps)
