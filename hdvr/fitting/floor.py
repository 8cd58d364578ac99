"""The floor in the camera frame, and the camera's pose in the dancer world (floor z = 0, z up).

The dancer world of :mod:`hdvr.skeleton` has its floor at z = 0; a monocular fit lives in the camera frame
(x right, y down, z forward). The floor plane ``n . P = d`` (unit normal n pointing up) is found from the soles:

1. ``up`` = mean direction from mid-hip to neck over the clip (dancers are upright on average);
2. each frame's lowest foot keypoint along ``up`` is a floor candidate;
3. three rounds of: keep candidates within 5 cm of the current plane (start: 20th percentile of their heights),
   fit the plane to them by PCA when they spread over at least 0.3 m in two directions (the dancer travels),
   else keep ``up`` and set d to their median height.

The world frame: z = n, x = the optical axis projected on the floor (the camera looks along +x), origin on the
floor below the mid-hip of the first frame. ``P_cam = R (P_world - C)`` as in :mod:`hdvr.camera`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.fitting.kinematics import quat_from_matrix, quat_multiply
from hdvr.layouts import BODY25_NAMES

FOOT_NAMES = ("left_big_toe", "left_small_toe", "left_heel", "right_big_toe", "right_small_toe", "right_heel")
FOOT_IDX = np.array([BODY25_NAMES.index(n) for n in FOOT_NAMES])
_NECK = BODY25_NAMES.index("neck")
_MID_HIP = BODY25_NAMES.index("mid_hip")


@dataclass
class Floor:
    normal: np.ndarray  # (3,) unit, camera frame, pointing up
    offset: float  # metres: floor points satisfy normal . P = offset
    contact_fraction: float  # fraction of frames with a sole within 5 cm of the plane

    def height(self, points_cam: np.ndarray) -> np.ndarray:
        """Signed height (metres) of camera-frame points above the floor."""
        return np.asarray(points_cam) @ self.normal - self.offset


def estimate_floor(keypoints_cam: np.ndarray, inlier_m: float = 0.05, min_spread_m: float = 0.3) -> Floor:
    """Floor plane from camera-frame BODY_25 keypoints (T, 25, 3) metres (see module doc)."""
    kp = np.asarray(keypoints_cam, dtype=np.float64)
    up = np.nanmean(kp[:, _NECK] - kp[:, _MID_HIP], axis=0)
    up = up / np.linalg.norm(up)
    feet = kp[:, FOOT_IDX]
    lowest = feet[np.arange(len(kp)), np.nanargmin(feet @ up, axis=1)]  # (T, 3)
    normal = up
    offset = float(np.nanpercentile(lowest @ normal, 20))
    inliers = np.ones(len(lowest), dtype=bool)
    for _ in range(3):
        inliers = np.abs(lowest @ normal - offset) < inlier_m
        if inliers.sum() < 3:
            break
        pts = lowest[inliers]
        centre = pts.mean(axis=0)
        evals, evecs = np.linalg.eigh(np.cov((pts - centre).T))
        if np.sqrt(max(evals[1], 0.0)) * 2 >= min_spread_m:
            n = evecs[:, 0]
            n = n if n @ up > 0 else -n
            if n @ up > np.cos(np.deg2rad(30)):  # a plausible floor, not a wall
                normal = n
        offset = float(np.median(pts @ normal)) if normal is up else float(centre @ normal)
    frac = float(np.mean(np.abs(lowest @ normal - offset) < inlier_m))
    return Floor(normal / np.linalg.norm(normal), offset, frac)


def camera_pose_in_world(floor: Floor, origin_cam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R (3, 3), C (3,)) with ``P_cam = R (P_world - C)``: world z up along the floor normal, x along the optical
    axis projected on the floor, origin on the floor below ``origin_cam`` (a camera-frame point)."""
    z = floor.normal
    x = np.array([0.0, 0.0, 1.0]) - z[2] * z
    if np.linalg.norm(x) < 1e-6:  # camera looks straight down: use image up
        x = np.array([0.0, -1.0, 0.0]) - z[1] * z
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    world_from_cam = np.stack([x, y, z])  # rows: world axes in camera coordinates
    origin = np.asarray(origin_cam, dtype=np.float64)
    origin_on_floor = origin - floor.height(origin) * z
    centre = -world_from_cam @ origin_on_floor  # camera centre in the world
    return world_from_cam.T, centre


def qpos_to_world(qpos_cam: np.ndarray, rotation: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Re-express camera-frame qpos (T, 41) in the world of ``P_cam = R (P_world - C)`` (hinges unchanged)."""
    q = np.array(qpos_cam, dtype=np.float64, copy=True)
    world_from_cam = rotation.T
    q[:, :3] = q[:, :3] @ world_from_cam.T + centre
    q[:, 3:7] = quat_multiply(quat_from_matrix(world_from_cam), q[:, 3:7])
    return q
