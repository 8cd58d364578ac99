"""Limb depth over the whole clip: which side of the image plane each arm segment lies on, chosen by Viterbi.

A 2D keypoint pins a joint to its camera ray; with the parent joint and the bone length known, the child joint is
one of the ray's two intersections with the sphere around the parent (the near and the far branch: the monocular
depth ambiguity). An arm (shoulder -> elbow -> wrist) therefore has four *branches* per frame, each as well
supported by the image as the others. Frame-by-frame fitting (the windows of :mod:`hdvr.fitting.window`) picks
one greedily, from what came before; this module picks the branch sequence for the whole clip at once, with
evidence from both sides in time:

- **rigidity in the body frame** (pairwise, the deciding cue): a dancer holds arm shapes while the trunk turns;
  the true branch keeps the segments' directions in the trunk's frame steady, while a depth mirror of a held arm
  swings in the trunk's frame as soon as the trunk turns (the mirror is taken about the camera's view, not the
  body). Cost: ``|d_t - d_{t-1}| / sigma`` for the two segments' unit directions ``d`` in the trunk frame (stacked,
  6 numbers). Not squared: a slow swing over many frames adds up as much as one jump of the same total size.
- **the fit's own choice** (unary ``stay_cost`` per frame away from it): the fit weighs the pose prior and joint limits,
  which the branches' keypoints alone do not see;
- **the elbow** (unary ``elbow_cost``): a branch that flexes the elbow beyond ``max_flexion_deg`` is implausible;
  a branch whose ray misses the sphere (no real intersection) costs ``missing_cost``;
- **the dancer's own repertoire** (unary, second pass): dancers come back to the same arm shapes (a hold, a
  carriage), so where the trunk turns and the choice is clear, it shows where this dancer holds the arm. After a
  first Viterbi, each branch of each frame costs ``repertoire_weight x -log`` of a Gaussian kernel density
  (bandwidth ``repertoire_bandwidth`` in the 6 stacked direction numbers) of the directions chosen on the other
  frames (more than ``repertoire_exclude_frames`` away, so a frame does not vote for itself), relative to the
  frame's best branch; then the Viterbi runs again. This reaches frames whose trunk does not turn.

Measured on 14 salsa clips of 10 s (``scripts/fit_clips.py``; docs/fitting.md): the arm branches of the windowed
fit are wrong on 10-14 % of frames per segment; with this choice (made twice: after the windows and before the
last refinement sweep, :mod:`hdvr.fitting.sequence`) the fit's P-MPJPE goes from 53.9 to 42.9 mm clean and from
57.9 to 46.6 mm with 3 px noise (the repertoire's share: 45.2 -> 43.8 and 50.1 -> 47.3).

All positions are camera-frame metres (x right, y down, z forward; the camera centre at the origin).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.layouts import BODY25_NAMES

_IDX = {n: i for i, n in enumerate(BODY25_NAMES)}

#: (root, middle, end) keypoints of each arm.
ARMS = {side: (_IDX[f"{side}_shoulder"], _IDX[f"{side}_elbow"], _IDX[f"{side}_wrist"]) for side in ("right", "left")}


@dataclass(frozen=True)
class BranchCosts:
    """Weights of the branch choice (see module doc). ``sigma`` is a change of unit direction per frame
    (dimensionless, ~radians); the unary costs are in units of one ``sigma``-sized change."""

    sigma: float = 0.05
    stay_cost: float = 0.3
    elbow_cost: float = 3.0
    missing_cost: float = 3.0
    max_flexion_deg: float = 150.0
    repertoire_weight: float = 1.5  # 0: no second pass
    repertoire_bandwidth: float = 0.3
    repertoire_exclude_frames: int = 15


def ray_sphere_depths(centre: np.ndarray, ray: np.ndarray, radius: float | np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distances along unit rays ``ray`` (T, 3) from the camera centre to their near and far intersections with
    spheres ``centre`` (T, 3), ``radius`` (metres); and whether the ray meets the sphere (T,) bool. Where it
    does not, both distances are those of the ray's closest approach to the centre."""
    along = np.einsum("ti,ti->t", ray, centre)
    disc = along * along - np.einsum("ti,ti->t", centre, centre) + np.asarray(radius) ** 2
    half = np.sqrt(np.maximum(disc, 0.0))
    return along - half, along + half, disc > 0


def trunk_frames(keypoints: np.ndarray) -> np.ndarray:
    """(T, 3, 3) rows = the trunk's left, up and forward axes in the camera frame, from keypoints (T, 25, 3):
    up = mid-hip -> neck, left = right -> left shoulder made perpendicular to up, forward = left x up."""
    up = keypoints[:, _IDX["neck"]] - keypoints[:, _IDX["mid_hip"]]
    up = up / np.maximum(np.linalg.norm(up, axis=1, keepdims=True), 1e-9)
    left = keypoints[:, _IDX["left_shoulder"]] - keypoints[:, _IDX["right_shoulder"]]
    left = left - np.einsum("ti,ti->t", left, up)[:, None] * up
    left = left / np.maximum(np.linalg.norm(left, axis=1, keepdims=True), 1e-9)
    return np.stack([left, up, np.cross(left, up)], axis=1)


def limb_branches(keypoints: np.ndarray, root: int, middle: int, end: int
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The four branches of a two-segment limb on the rays of its fitted middle and end joints.

    Returns candidate (middle, end) positions (4, T, 2, 3) ordered (near, near), (near, far), (far, near),
    (far, far) (which intersection each joint takes, nearer to the camera first), whether each exists (4, T)
    bool, and the index of the branch closest to the given keypoints (T,). Segment lengths are the clip's
    medians (the fit keeps them fixed)."""
    r, m, e = keypoints[:, root], keypoints[:, middle], keypoints[:, end]
    upper = float(np.median(np.linalg.norm(m - r, axis=1)))
    lower = float(np.median(np.linalg.norm(e - m, axis=1)))
    ray_m = m / np.linalg.norm(m, axis=1, keepdims=True)
    ray_e = e / np.linalg.norm(e, axis=1, keepdims=True)
    near_m, far_m, ok_m = ray_sphere_depths(r, ray_m, upper)
    cands, exists = [], []
    for depth_m in (near_m, far_m):
        mid = depth_m[:, None] * ray_m
        near_e, far_e, ok_e = ray_sphere_depths(mid, ray_e, lower)
        for depth_e in (near_e, far_e):
            cands.append(np.stack([mid, depth_e[:, None] * ray_e], axis=1))
            exists.append(ok_m & ok_e)
    cands = np.array(cands)
    gap = np.linalg.norm(cands - np.stack([m, e], axis=1)[None], axis=-1).sum(-1)  # (4, T)
    return cands, np.array(exists), np.argmin(gap, axis=0)


def viterbi(unary: np.ndarray, features: np.ndarray, sigma: float, missing_cost: float) -> np.ndarray:
    """The state sequence (T,) minimising ``sum_t unary[s_t, t] + |features[s_t, t] - features[s_{t-1}, t-1]| /
    sigma`` for unary (S, T) and features (S, T, D); a non-finite step costs ``missing_cost``."""
    n_state, n = unary.shape
    total = unary[:, 0].copy()
    back = np.zeros((n_state, n), dtype=np.int64)
    for t in range(1, n):
        pair = np.linalg.norm(features[:, None, t] - features[None, :, t - 1], axis=-1) / sigma  # (now, before)
        pair[~np.isfinite(pair)] = missing_cost
        step = total[None, :] + pair
        back[:, t] = np.argmin(step, axis=1)
        total = step[np.arange(n_state), back[:, t]] + unary[:, t]
    path = np.empty(n, dtype=np.int64)
    path[-1] = int(np.argmin(total))
    for t in range(n - 1, 0, -1):
        path[t - 1] = back[path[t], t]
    return path


def repertoire_cost(features: np.ndarray, chosen: np.ndarray, bandwidth: float, exclude_frames: int,
                    floor: float = 1e-3) -> np.ndarray:
    """(S, T) ``-log`` of the Gaussian kernel density (``bandwidth``) of each state's features (S, T, D) among
    the ``chosen`` features (T, D) of the frames more than ``exclude_frames`` away, minus the frame's least
    (so the best state of a frame costs 0); ``floor`` bounds the cost of a shape never seen elsewhere.
    Memory O(T^2) per state (float32: 7 MB at 1350 frames, the longest chunk)."""
    n = chosen.shape[0]
    ref = np.nan_to_num(chosen).astype(np.float32)
    frames = np.arange(n)
    far = np.abs(frames[:, None] - frames[None, :]) > exclude_frames  # (T, T) which references count
    count = np.maximum(far.sum(axis=1), 1)
    cost = np.empty(features.shape[:2])
    for state in range(features.shape[0]):
        x = np.nan_to_num(features[state]).astype(np.float32)
        d2 = np.maximum((x * x).sum(1)[:, None] + (ref * ref).sum(1)[None] - 2.0 * x @ ref.T, 0.0)
        density = (np.exp(-0.5 * d2 / bandwidth ** 2) * far).sum(axis=1) / count
        cost[state] = -np.log(density + floor)
    return cost - cost.min(axis=0, keepdims=True)


def choose_branches(keypoints: np.ndarray, root: int, middle: int, end: int, costs: BranchCosts = BranchCosts(),
                    frames: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Viterbi over the four branches of one limb for the whole clip (see module doc). ``frames``: the
    :func:`trunk_frames` of ``keypoints``, if already computed.

    Returns the chosen branch per frame (T,), the candidate positions (4, T, 2, 3) of :func:`limb_branches` and
    the branch the given keypoints are on (T,)."""
    cands, exists, fitted = limb_branches(keypoints, root, middle, end)
    frames = trunk_frames(keypoints) if frames is None else frames
    seg_a = cands[:, :, 0] - keypoints[None, :, root]
    seg_b = cands[:, :, 1] - cands[:, :, 0]
    seg_a = seg_a / np.maximum(np.linalg.norm(seg_a, axis=-1, keepdims=True), 1e-9)
    seg_b = seg_b / np.maximum(np.linalg.norm(seg_b, axis=-1, keepdims=True), 1e-9)
    flexion = np.degrees(np.arccos(np.clip(np.einsum("bti,bti->bt", seg_a, seg_b), -1.0, 1.0)))
    body = np.concatenate([np.einsum("tij,btj->bti", frames, seg_a), np.einsum("tij,btj->bti", frames, seg_b)],
                          axis=-1)  # (4, T, 6) both segments' directions in the trunk frame
    n_branch, n = exists.shape
    unary = (costs.stay_cost * (np.arange(n_branch)[:, None] != fitted[None])
             + costs.elbow_cost * (flexion > costs.max_flexion_deg) + costs.missing_cost * ~exists)
    path = viterbi(unary, body, costs.sigma, costs.missing_cost)
    if costs.repertoire_weight > 0:
        unary = unary + costs.repertoire_weight * repertoire_cost(body, body[path, np.arange(n)],
                                                                  costs.repertoire_bandwidth,
                                                                  costs.repertoire_exclude_frames)
        path = viterbi(unary, body, costs.sigma, costs.missing_cost)
    return path, cands, fitted


def arm_targets(keypoints: np.ndarray, costs: BranchCosts = BranchCosts()
                ) -> tuple[np.ndarray, np.ndarray]:
    """Keypoints (T, 25, 3) with each arm's elbow and wrist moved to its chosen branch where that differs from
    the fitted one, and a mask (T, 25) bool of the keypoints a re-solve must hold at these targets: the moved
    elbow and wrist *and their shoulder*, which stays where it is. (Without the shoulder a solver reaches the
    moved elbow by turning the trunk in depth and keeps the arm's old direction: measured on 14 salsa clips,
    that left 97 % of the chosen frames on the old branch.) Frames with any mask are the ones to re-solve."""
    out = keypoints.copy()
    pinned = np.zeros(keypoints.shape[:2], dtype=bool)
    frames = trunk_frames(keypoints)
    for root, middle, end in ARMS.values():
        path, cands, fitted = choose_branches(keypoints, root, middle, end, costs, frames)
        change = np.flatnonzero(path != fitted)
        chosen = cands[path[change], change]  # (C, 2, 3)
        out[change, middle], out[change, end] = chosen[:, 0], chosen[:, 1]
        pinned[change, root] = pinned[change, middle] = pinned[change, end] = True
    return out, pinned
