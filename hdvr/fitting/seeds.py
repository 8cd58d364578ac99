"""Starting points of the per-frame solves: a root pose from the 2D keypoints, yaw sweeps, the paper's random
seeds, and mirrored-limb seeds for the monocular depth ambiguity. Poses are in the camera frame (x right, y down,
z forward, metres)."""

from __future__ import annotations

import numpy as np

from hdvr import dh
from hdvr.fitting.kinematics import DancerKinematics, quat_from_matrix
from hdvr.fitting.residuals import FrameProblem, LinearTerm, UprightTerm
from hdvr.fitting.solver import parameter_bounds, solve_frame
from hdvr.fitting.kinematics import tangent_from_qpos, qpos_from_tangent
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import NQ, ROOT_QPOS

_IDX = {n: i for i, n in enumerate(BODY25_NAMES)}

#: Limb segments for mirrored seeds: (root keypoint, child keypoint, keypoints that move with the child).
_ARM = ("elbow", "wrist")
SEGMENTS: dict[str, tuple[int, int, tuple[int, ...]]] = {}
for _side in ("right", "left"):
    _foot = tuple(_IDX[f"{_side}_{n}"] for n in ("big_toe", "small_toe", "heel"))
    SEGMENTS[f"{_side}_upper_arm"] = (_IDX[f"{_side}_shoulder"], _IDX[f"{_side}_elbow"],
                                      (_IDX[f"{_side}_elbow"], _IDX[f"{_side}_wrist"]))
    SEGMENTS[f"{_side}_forearm"] = (_IDX[f"{_side}_elbow"], _IDX[f"{_side}_wrist"], (_IDX[f"{_side}_wrist"],))
    SEGMENTS[f"{_side}_thigh"] = (_IDX[f"{_side}_hip"], _IDX[f"{_side}_knee"],
                                  (_IDX[f"{_side}_knee"], _IDX[f"{_side}_ankle"]) + _foot)
    SEGMENTS[f"{_side}_shank"] = (_IDX[f"{_side}_knee"], _IDX[f"{_side}_ankle"], (_IDX[f"{_side}_ankle"],) + _foot)
LIMB_NAMES = tuple(SEGMENTS)

#: Weight (per metre) of 3D targets that pull a pose towards a chosen limb shape while it keeps fitting the image
#: (mirrored-limb seeds here; the clip-level arm depth of :func:`hdvr.fitting.sequence.repair_limb_depth`).
TARGET_WEIGHT = 300.0


def root_rotation_facing(yaw_rad: float, vertical: np.ndarray | None = None) -> np.ndarray:
    """Pelvis rotation (3, 3) in the camera frame: upright (body z -> ``vertical``, the clip's up direction in the
    camera frame; default image up), turned ``yaw`` from facing the camera (yaw 0: body x -> towards the
    camera)."""
    up = np.array([0.0, -1.0, 0.0]) if vertical is None else np.asarray(vertical, dtype=np.float64)
    up = up / np.linalg.norm(up)
    towards = np.array([0.0, 0.0, -1.0])  # towards the camera ...
    towards = towards - (towards @ up) * up  # ... made perpendicular to up
    if np.linalg.norm(towards) < 1e-6:  # camera looking along the vertical: "towards" is image down instead
        towards = np.array([0.0, 1.0, 0.0]) - up[1] * up
    towards /= np.linalg.norm(towards)
    side = np.cross(up, towards)
    forward = np.cos(yaw_rad) * towards + np.sin(yaw_rad) * side
    left = np.cross(up, forward)
    return np.stack([forward, left, up], axis=1)


def _visible_mean(obs: np.ndarray, weights: np.ndarray, names) -> np.ndarray | None:
    idx = [_IDX[n] for n in names if weights[_IDX[n]] > 0 and np.isfinite(obs[_IDX[n]]).all()]
    return obs[idx].mean(axis=0) if idx else None


def root_from_2d(obs: np.ndarray, weights: np.ndarray, focal: float, principal_point, bones: np.ndarray
                 ) -> np.ndarray:
    """Pelvis position (3,) in the camera frame back-projected from the 2D hips at the depth implied by the
    2D torso length (``focal * torso_m / torso_px``), or by the visible extent when the torso is not seen."""
    pp = np.asarray(principal_point, dtype=np.float64)
    hips = _visible_mean(obs, weights, ("mid_hip", "right_hip", "left_hip"))
    shoulders = _visible_mean(obs, weights, ("neck", "right_shoulder", "left_shoulder"))
    vis = obs[(weights > 0) & np.isfinite(obs).all(axis=1)]
    centre = hips if hips is not None else (vis.mean(axis=0) if len(vis) else pp)
    if hips is not None and shoulders is not None and np.linalg.norm(shoulders - hips) > 1.0:
        depth = focal * bones[0] / np.linalg.norm(shoulders - hips)
    elif len(vis) >= 2:
        extent = float(np.ptp(vis[:, 1])) + 1.0
        depth = focal * 0.9 * (bones[0] + bones[6] + bones[7]) / extent
    else:
        depth = 5.0
    depth = float(np.clip(depth, 0.5, 100.0))
    xy = (centre - pp) * depth / focal
    return np.array([xy[0], xy[1], depth])


def upright_qpos(kin: DancerKinematics, root_pos: np.ndarray, yaw_rad: float,
                 vertical: np.ndarray | None = None) -> np.ndarray:
    q = kin.skeleton.rest_qpos()
    q[:3] = root_pos
    q[3:7] = quat_from_matrix(root_rotation_facing(yaw_rad, vertical))
    return q


def random_qpos(kin: DancerKinematics, rng: np.random.Generator, root_qpos: np.ndarray) -> np.ndarray:
    """The paper's seed: hinges uniform within their bounds, root pose taken from ``root_qpos``."""
    q = np.array(root_qpos, dtype=np.float64)
    q[ROOT_QPOS:] = rng.uniform(kin.skeleton.lower, kin.skeleton.upper)
    return q


def random_bones(rng: np.random.Generator, height_m: float) -> np.ndarray:
    """The paper's bone-length seed: ratios uniform in mean +- std (clipped positive), times the stature."""
    ratios = rng.uniform(dh.BONE_RATIO_MEAN - dh.BONE_RATIO_STD, dh.BONE_RATIO_MEAN + dh.BONE_RATIO_STD)
    return np.maximum(ratios, 0.25 * dh.BONE_RATIO_MEAN) * height_m


def mirrored_targets(keypoints_cam: np.ndarray, segment: str) -> tuple[np.ndarray, np.ndarray]:
    """3D targets (25, 3) and mask (25,) for a limb segment reflected through the plane parallel to the image
    through its root joint: the child joint's depth Z -> 2 Z_root - Z (nearly the same image, opposite depth
    order); the keypoints below the child move with it, so the segments further down keep their direction."""
    root, child, moved = SEGMENTS[segment]
    target = keypoints_cam.copy()
    shift = 2 * (keypoints_cam[root, 2] - keypoints_cam[child, 2])
    target[list(moved), 2] += shift
    mask = np.zeros(len(BODY25_NAMES))
    mask[list(moved)] = 1.0
    mask[root] = 1.0
    return target, mask


def mirror_limb(problem: FrameProblem, qpos: np.ndarray, limb: str, bounds, max_iter: int = 6) -> np.ndarray:
    """A qpos whose ``limb`` approximates its depth mirror image: solve ``problem`` plus 3D targets on the limb."""
    kp = problem.kin.keypoints(qpos)
    target, mask = mirrored_targets(kp, limb)
    x0, quat = tangent_from_qpos(qpos)
    saved_quat, saved_terms = problem.quat_ref, problem.terms3d
    problem.quat_ref = quat
    problem.terms3d = [LinearTerm(1.0, -target, TARGET_WEIGHT, mask)]
    params0 = np.concatenate([x0, np.zeros(problem.num_params - len(x0))])
    if problem.estimate_focal:
        params0[-1] = np.log(problem.focal)
    sol = solve_frame(problem, params0, bounds, max_iter=max_iter)
    out = qpos_from_tangent(sol.params, quat)
    problem.quat_ref, problem.terms3d = saved_quat, saved_terms
    return out


def initial_pose(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, focal: float, principal_point,
                 joint_limits: bool = True, yaws: int = 8, max_iter: int = 15, robust_px: float | None = None,
                 flips: bool = True, vertical: np.ndarray | None = None, upright: UprightTerm | None = None
                 ) -> tuple[np.ndarray, float]:
    """Best (qpos (41,), cost) over ``yaws`` upright starting orientations (about ``vertical``, the clip's up
    direction in the camera frame, when known), each solved on the 2D keypoints (plus the trunk tilt prior
    ``upright``, if given), then (``flips``) over the depth mirrors of the limb segments (:func:`resolve_flips`)."""
    root = root_from_2d(obs, weights, focal, principal_point, kin.bone_lengths)
    best_q, best_cost = None, np.inf
    for yaw in np.arange(yaws) * 2 * np.pi / yaws:
        q0 = upright_qpos(kin, root, yaw, vertical)
        x0, quat = tangent_from_qpos(q0)
        problem = FrameProblem(kin, quat, obs, weights, focal, np.asarray(principal_point), robust_px=robust_px,
                               upright=upright)
        bounds = parameter_bounds(problem, kin.skeleton.lower, kin.skeleton.upper, joint_limits)
        sol = solve_frame(problem, x0, bounds, max_iter=max_iter)
        if sol.cost < best_cost:
            best_q, best_cost = qpos_from_tangent(sol.params, quat), sol.cost
    assert best_q is not None and best_q.shape == (NQ,)
    if flips:
        problem = FrameProblem(kin, None, obs, weights, focal, np.asarray(principal_point), robust_px=robust_px,
                               upright=upright)
        bounds = parameter_bounds(problem, kin.skeleton.lower, kin.skeleton.upper, joint_limits)
        best_q, best_cost = resolve_flips(problem, best_q, bounds, max_iter)
    return best_q, best_cost


def resolve_flips(problem: FrameProblem, qpos: np.ndarray, bounds, max_iter: int = 15) -> tuple[np.ndarray, float]:
    """Greedy single-frame search over the depth mirror of each limb segment: keep a mirror when the solved cost
    (reprojection + the problem's other terms) drops. Returns (qpos, cost)."""
    x0, quat = tangent_from_qpos(qpos)
    problem.quat_ref = quat
    cost = float(np.sum(problem.residual(x0) ** 2))
    for segment in LIMB_NAMES:
        start = mirror_limb(problem, qpos, segment, bounds)
        x0, quat = tangent_from_qpos(start)
        problem.quat_ref = quat
        sol = solve_frame(problem, x0, bounds, max_iter=max_iter)
        if sol.cost < cost:
            qpos, cost = qpos_from_tangent(sol.params, quat), sol.cost
    return qpos, cost
