"""Retarget BODY_25 mocap (e.g. the CMU salsa couples) to the digital dancer, to mix real motion into the data.

Per frame, damped Gauss-Newton (Levenberg-Marquardt) on the dancer's 40 velocity DOF (free root + 34 hinges)
minimises the weighted distance between the dancer's BODY_25 sites and the mocap keypoints, warm-started from
the previous frame; hinges are clamped to their ranges after each step, so the result never violates a limit.
Face points weigh less (the mocap's eyes / ears are derived). Afterwards the root is lowered or raised so that the
lowest sole point of each frame touches the floor (z = 0); feet that slide in the mocap still slide.
"""

from __future__ import annotations

import mujoco
import numpy as np

from hdvr import dh
from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import ROOT_QPOS, Skeleton

#: Per-keypoint weights of the fit (face points are derived in CMU files: nose = mid-eyes, ears beside the eyes).
WEIGHTS = np.array([0.3 if n in ("nose", "left_eye", "right_eye", "left_ear", "right_ear") else
                    0.5 if n.endswith(("small_toe", "heel")) else 1.0 for n in BODY25_NAMES])


def _initial_root(kp: np.ndarray, sk: Skeleton) -> np.ndarray:
    q = sk.rest_qpos()
    q[:3] = kp[8]
    hip = kp[12] - kp[9]
    yaw = np.arctan2(hip[1], hip[0]) - np.pi / 2  # the dancer faces 90 deg clockwise of the right -> left hip line
    q[3:7] = [np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]
    return q


def fit_frame(sk: Skeleton, target: np.ndarray, q0: np.ndarray, iterations: int = 8, damping: float = 1e-2) -> np.ndarray:
    """qpos (41,) whose BODY_25 sites best match ``target`` (25, 3) metres, starting from ``q0``."""
    q = q0.copy()
    w = np.repeat(WEIGHTS, 3)
    for _ in range(iterations):
        jac = sk.keypoint_jacobians(q).reshape(75, -1)  # (75, 40); also leaves kinematics at q
        res = (sk.data.site_xpos[sk.keypoint_site_ids] - target).ravel()
        jw = jac * w[:, None]
        step = -np.linalg.solve(jw.T @ jac + damping * np.eye(jac.shape[1]), jw.T @ res)
        mujoco.mj_integratePos(sk.model, q, step, 1.0)
        q[ROOT_QPOS:] = np.clip(q[ROOT_QPOS:], np.maximum(sk.lower, dh.LOWER), np.minimum(sk.upper, dh.UPPER))
        if np.abs(step).max() < 1e-5:
            break
    return q


def bone_lengths_from_body25(kp: np.ndarray) -> np.ndarray:
    """The dancer's 9 bone lengths (metres, :data:`hdvr.dh.BONE_NAMES`) measured on BODY_25 mocap (medians)."""
    i = {n: k for k, n in enumerate(BODY25_NAMES)}

    def dist(a, b):
        return float(np.median(np.linalg.norm(kp[:, i[a]] - kp[:, i[b]], axis=-1)))

    def both(fmt_a, fmt_b):
        return 0.5 * (dist(fmt_a.format("left"), fmt_b.format("left")) + dist(fmt_a.format("right"), fmt_b.format("right")))

    ear_mid = 0.5 * (kp[:, i["left_ear"]] + kp[:, i["right_ear"]])
    head = float(np.median(np.linalg.norm(kp[:, i["nose"]] - ear_mid, axis=-1)))
    ankle_height = float(np.median(kp[:, [i["left_ankle"], i["right_ankle"]], 2] -
                                   kp[:, [i["left_heel"], i["right_heel"]], 2]))
    return np.array([dist("neck", "mid_hip"), head, 0.5 * dist("left_shoulder", "right_shoulder"),
                     both("{}_shoulder", "{}_elbow"), both("{}_elbow", "{}_wrist"), 0.5 * dist("left_hip", "right_hip"),
                     both("{}_hip", "{}_knee"), both("{}_knee", "{}_ankle"), max(ankle_height, 0.03)])


def stature_from_body25(kp: np.ndarray) -> float:
    """The height (m) whose table-average bone lengths best match the mocap's (least squares): a dancer of that
    height can be rendered with :func:`hdvr.dancer_model.build_mjcf`."""
    from hdvr import dh

    bones = bone_lengths_from_body25(kp)
    return float(bones @ dh.BONE_RATIO_MEAN / (dh.BONE_RATIO_MEAN @ dh.BONE_RATIO_MEAN))


def retarget(keypoints: np.ndarray, sk: Skeleton | None = None, iterations: int = 8) -> tuple[np.ndarray, dict]:
    """qpos (T, 41) of the dancer following BODY_25 keypoints (T, 25, 3) metres (world, z up); and fit figures:
    mean / max keypoint error (m), the root height shift applied for the floor, the dancer's height. Without
    ``sk`` the dancer gets the height that best fits the mocap's bone lengths (:func:`stature_from_body25`)."""
    kp = np.asarray(keypoints, dtype=np.float64)
    if kp.ndim != 3 or kp.shape[1:] != (25, 3) or kp.shape[0] == 0:
        raise HDVRError(f"keypoints must be BODY_25 (T, 25, 3) metres, got shape {kp.shape}")
    if not np.isfinite(kp).all():
        raise HDVRError("mocap keypoints contain NaN; fill or drop those frames before retargeting")
    if sk is None:
        sk = Skeleton(height_m=stature_from_body25(kp))
    T = kp.shape[0]
    qpos = np.empty((T, 41))
    q = fit_frame(sk, kp[0], _initial_root(kp[0], sk), iterations=60)
    for t in range(T):
        q = fit_frame(sk, kp[t], q, iterations=iterations if t else 10)
        qpos[t] = q
    fitted = sk.keypoints(qpos)
    err = np.linalg.norm(fitted - kp, axis=-1)
    lowest = fitted[:, [19, 20, 21, 22, 23, 24], 2].min(1)
    qpos[:, 2] -= lowest  # lowest sole point on the floor
    return qpos, {"mean_error_m": float(err.mean()), "max_error_m": float(err.max()),
                  "mean_floor_shift_m": float(np.abs(lowest).mean()), "height_m": sk.height_m}
