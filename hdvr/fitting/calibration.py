"""Per-dancer calibration: one set of 9 bone lengths (and the focal length when not given) for the whole clip.

Monocular images fix a body's size only relative to its depth, so the stature is an input (default 1.70 m, the
height the benchmark's mocap is normalised to): the rest-pose eye height of the model must equal
``EYE_HEIGHT_FRACTION x stature`` (Drillis & Contini, as in :mod:`hdvr.io.bvh`). Within that, the bone lengths
follow the 2D evidence of a subsample of frames, with the table's prior ``(b - mean h) / (std h)``.

Alternation (block coordinate descent), ``rounds`` times:
(a) each subsampled frame's pose (40 parameters) with the bones fixed;
(b) the bones, log focal and every subsampled frame's root translation with the joint angles fixed. The bone
    Jacobian is exact (offsets are linear in the bones; :meth:`DancerKinematics.bone_jacobian`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.camera import projection_jacobian
from mujoco import minimize

from hdvr import dh
from hdvr.fitting.kinematics import DancerKinematics, qpos_from_tangent, tangent_from_qpos
from hdvr.fitting.residuals import FrameProblem
from hdvr.fitting.seeds import initial_pose
from hdvr.fitting.solver import parameter_bounds, solve_frame
from hdvr.io.bvh import EYE_HEIGHT_FRACTION
from hdvr.layouts import BODY25_NAMES

_EYES = [BODY25_NAMES.index("right_eye"), BODY25_NAMES.index("left_eye")]
_SOLES = [BODY25_NAMES.index(n) for n in ("left_big_toe", "left_heel", "right_big_toe", "right_heel")]
STATURE_SIGMA_M = 0.002


@dataclass
class Calibration:
    bone_lengths: np.ndarray  # (9,) metres
    focal: float  # pixels
    frames: np.ndarray  # indices of the subsampled frames
    qpos: np.ndarray  # (M, 41) their poses (camera frame)
    reprojection_error_px: float  # mean over their visible keypoints


def model_eye_height(kin: DancerKinematics) -> tuple[float, np.ndarray]:
    """Rest-pose eye height above the soles (metres) for the current bones, and its gradient (9,) (exact:
    linear in the bones)."""
    q = kin.skeleton.rest_qpos()
    q[:3] = 0.0
    kin.keypoints_and_jacobian(q)
    kp = kin.data.site_xpos[kin.site_ids]
    dkp = kin.bone_jacobian()
    height = kp[_EYES, 2].mean() - kp[_SOLES, 2].mean()
    grad = dkp[_EYES, 2, :].mean(axis=0) - dkp[_SOLES, 2, :].mean(axis=0)
    return float(height), grad


def stature_scaled_bones(kin: DancerKinematics, height_m: float) -> np.ndarray:
    """The table's mean bone ratios scaled so that the model's eye height matches the stature."""
    kin.set_bone_lengths(dh.bone_lengths_m(height_m))
    h, _ = model_eye_height(kin)
    return dh.bone_lengths_m(height_m) * (EYE_HEIGHT_FRACTION * height_m / h)


def pick_frames(weights: np.ndarray, count: int) -> np.ndarray:
    """Up to ``count`` frames spread evenly over the clip among those with the most keypoint weight."""
    total = weights.sum(axis=1)
    good = np.flatnonzero(total >= 0.7 * total.max()) if total.max() > 0 else np.arange(len(total))
    if len(good) <= count:
        return good
    return good[np.linspace(0, len(good) - 1, count).round().astype(int)]


class _BoneProblem:
    """Step (b): parameters [bones (9), log f, root translations (3M)] with joint angles fixed."""

    def __init__(self, kin, qpos, obs, weights, principal_point, height_m, prior_weight, estimate_focal,
                 log_focal0, focal_sigma, robust_px):
        self.kin, self.qpos, self.obs, self.weights = kin, qpos, obs, weights
        self.pp = np.asarray(principal_point, dtype=np.float64)
        self.height_m, self.prior_weight = height_m, prior_weight
        self.estimate_focal, self.log_focal0, self.focal_sigma = estimate_focal, log_focal0, focal_sigma
        self.robust_px = robust_px
        self.mean = dh.BONE_RATIO_MEAN * height_m
        self.std = dh.BONE_RATIO_STD * height_m
        self.m = len(qpos)

    def unpack(self, p):
        p = np.asarray(p, dtype=np.float64).ravel()
        return p[:9], p[9], p[10:].reshape(self.m, 3)

    def _frames(self, bones, roots, with_jac):
        self.kin.set_bone_lengths(bones)
        for i in range(self.m):
            q = self.qpos[i].copy()
            q[:3] = roots[i]
            if with_jac:
                self.kin.keypoints_and_jacobian(q)
                yield i, self.kin.data.site_xpos[self.kin.site_ids].copy(), self.kin.bone_jacobian()
            else:
                yield i, self.kin.keypoints(q), None

    def _scale(self, e):
        if not self.robust_px:
            return np.ones((e.shape[0], 1))
        c2 = self.robust_px ** 2
        s = np.sum(e * e, axis=1, keepdims=True)
        return np.sqrt(np.where(s > 1e-12, c2 * np.log1p(s / c2) / np.maximum(s, 1e-12), 1.0))

    def residual(self, params):
        cols = np.asarray(params, dtype=np.float64).reshape(-1, np.asarray(params).shape[-1] if np.ndim(params) > 1
                                                              else 1)
        out = []
        for k in range(cols.shape[1]):
            bones, logf, roots = self.unpack(cols[:, k])
            f = np.exp(logf)
            parts = []
            for i, kp, _ in self._frames(bones, roots, False):
                vis = self.weights[i] > 0
                e = (f * kp[vis, :2] / np.maximum(kp[vis, 2:3], 1e-3) + self.pp - self.obs[i][vis])
                e = e * np.sqrt(self.weights[i][vis])[:, None]
                parts.append((e * self._scale(e)).ravel())
            h, _ = model_eye_height(self.kin)
            parts.append([(h - EYE_HEIGHT_FRACTION * self.height_m) / STATURE_SIGMA_M])
            parts.append(self.prior_weight * (bones - self.mean) / self.std)
            if self.estimate_focal:
                parts.append([(logf - self.log_focal0) / self.focal_sigma])
            out.append(np.concatenate([np.ravel(p) for p in parts]))
        return np.stack(out, axis=1)

    def jacobian(self, params, _r=None):
        bones, logf, roots = self.unpack(params)
        f = np.exp(logf)
        n = 10 + 3 * self.m
        rows = []
        for i, kp, dkp in self._frames(bones, roots, True):
            vis = np.flatnonzero(self.weights[i] > 0)
            p = kp[vis]
            z = np.maximum(p[:, 2], 1e-3)
            d = projection_jacobian(np.column_stack([p[:, :2], z]), f)
            sw = np.sqrt(self.weights[i][vis])[:, None]
            e = (f * p[:, :2] / z[:, None] + self.pp - self.obs[i][vis]) * sw
            s = (self._scale(e) * sw)[:, :, None]
            block = np.zeros((len(vis), 2, n))
            block[:, :, :9] = np.einsum("vij,vjk->vik", d, dkp[vis]) * s
            block[:, :, 9] = (f * p[:, :2] / z[:, None]) * s[:, :, 0]
            block[:, :, 10 + 3 * i:13 + 3 * i] = d * s
            rows.append(block.reshape(-1, n))
        _, grad = model_eye_height(self.kin)
        stature = np.zeros((1, n))
        stature[0, :9] = grad / STATURE_SIGMA_M
        rows.append(stature)
        prior = np.zeros((9, n))
        prior[:, :9] = np.diag(self.prior_weight / self.std)
        rows.append(prior)
        if self.estimate_focal:
            fp = np.zeros((1, n))
            fp[0, 9] = 1.0 / self.focal_sigma
            rows.append(fp)
        jac = np.concatenate(rows, axis=0)
        if not self.estimate_focal:
            jac[:, 9] = 0.0
        return jac


#: Bone -> (keypoint pairs whose distance measures it, factor): shoulder and hip are half-widths.
_BONE_PAIRS: dict[int, tuple[tuple[tuple[str, str], ...], float]] = {
    0: ((("neck", "mid_hip"),), 1.0),
    2: ((("right_shoulder", "left_shoulder"),), 0.5),
    3: ((("right_shoulder", "right_elbow"), ("left_shoulder", "left_elbow")), 1.0),
    4: ((("right_elbow", "right_wrist"), ("left_elbow", "left_wrist")), 1.0),
    5: ((("right_hip", "left_hip"),), 0.5),
    6: ((("right_hip", "right_knee"), ("left_hip", "left_knee")), 1.0),
    7: ((("right_knee", "right_ankle"), ("left_knee", "left_ankle")), 1.0),
}


def bones_from_projections(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, keypoints_cam: np.ndarray,
                           focal: float, height_m: float, percentile: float = 95.0) -> np.ndarray:
    """Bone lengths (9,) metres from the longest image projections of each bone over a tracked clip.

    A segment's image length, lifted to metres at its tracked depth (``|p_a - p_b| * (Z_a + Z_b) / (2 f)``), equals
    its 3D length when it lies parallel to the image and is shorter otherwise; over a dance clip each limb passes
    through that orientation, so the ``percentile`` of the lifted lengths (pooled over both sides) estimates it
    without the depth ambiguity that lets a least-squares fit lengthen limbs. Head and toe keep the stature-scaled
    table values; finally all bones are scaled so that the model's eye height is 0.936 x the stature.
    """
    bones = stature_scaled_bones(kin, height_m)
    for bone, (pairs, factor) in _BONE_PAIRS.items():
        samples = []
        for a, b in pairs:
            ia, ib = BODY25_NAMES.index(a), BODY25_NAMES.index(b)
            ok = (weights[:, ia] > 0) & (weights[:, ib] > 0)
            if not ok.any():
                continue
            px = np.linalg.norm(obs[ok, ia] - obs[ok, ib], axis=-1)
            depth = 0.5 * (keypoints_cam[ok, ia, 2] + keypoints_cam[ok, ib, 2])
            samples.append(px * depth / focal)
        if samples and sum(len(x) for x in samples) >= 10:
            bones[bone] = factor * float(np.percentile(np.concatenate(samples), percentile))
    lo = 0.3 * dh.BONE_RATIO_MEAN * height_m
    hi = 3.0 * dh.BONE_RATIO_MEAN * height_m
    bones = np.clip(bones, lo, hi)
    kin.set_bone_lengths(bones)
    eye, _ = model_eye_height(kin)
    bones = bones * (EYE_HEIGHT_FRACTION * height_m / eye)
    kin.set_bone_lengths(bones)
    return bones


def calibrate_from_poses(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, qpos_track: np.ndarray,
                         focal: float, principal_point, estimate_focal: bool, height_m: float, frames: int = 40,
                         rounds: int = 5, bone_prior_weight: float = 1.0, focal_prior_sigma: float = 0.7,
                         robust_px: float | None = 20.0, joint_limits: bool = True, fix_bones: bool = False
                         ) -> Calibration:
    """Like :func:`calibrate`, starting from tracked poses ``qpos_track`` (T, 41) instead of per-frame guesses.

    ``fix_bones``: keep the current bone lengths and estimate only the focal length (and root translations)."""
    idx = pick_frames(weights, frames)
    return _alternate(kin, obs[idx], weights[idx], idx, qpos_track[idx].copy(), focal, principal_point,
                      estimate_focal, height_m, rounds, bone_prior_weight, focal_prior_sigma, robust_px,
                      joint_limits, fix_bones)


def calibrate(kin: DancerKinematics, obs: np.ndarray, weights: np.ndarray, focal: float, principal_point,
              estimate_focal: bool, height_m: float, frames: int = 40, rounds: int = 5, bone_prior_weight: float = 1.0,
              focal_prior_sigma: float = 0.7, robust_px: float | None = 20.0, joint_limits: bool = True
              ) -> Calibration:
    """Estimate bone lengths (and focal) from ``obs`` (T, 25, 2) px with ``weights`` (T, 25); see module doc."""
    idx = pick_frames(weights, frames)
    kin.set_bone_lengths(stature_scaled_bones(kin, height_m))
    sub_obs, sub_w = obs[idx], weights[idx]
    qpos = np.stack([initial_pose(kin, sub_obs[i], sub_w[i], focal, principal_point, joint_limits,
                                  robust_px=robust_px)[0] for i in range(len(idx))])
    return _alternate(kin, sub_obs, sub_w, idx, qpos, focal, principal_point, estimate_focal, height_m, rounds,
                      bone_prior_weight, focal_prior_sigma, robust_px, joint_limits)


def _alternate(kin, sub_obs, sub_w, idx, qpos, focal, principal_point, estimate_focal, height_m, rounds,
               bone_prior_weight, focal_prior_sigma, robust_px, joint_limits, fix_bones=False) -> Calibration:
    log_f0 = np.log(focal)
    bones = kin.bone_lengths
    if fix_bones:
        bone_prior_weight = 0.0
    lo_b = 0.3 * dh.BONE_RATIO_MEAN * height_m
    hi_b = 3.0 * dh.BONE_RATIO_MEAN * height_m
    for _ in range(rounds):
        problem = _BoneProblem(kin, qpos, sub_obs, sub_w, principal_point, height_m, bone_prior_weight,
                               estimate_focal, log_f0, focal_prior_sigma, robust_px)
        p0 = np.concatenate([bones, [np.log(focal)], qpos[:, :3].ravel()])
        lo = np.concatenate([lo_b, [np.log(50.0)], np.tile([-200.0, -200.0, 0.2], len(idx))])
        hi = np.concatenate([hi_b, [np.log(50000.0)], np.full(3 * len(idx), 200.0)])
        if not estimate_focal:
            lo[9], hi[9] = np.log(focal) - 1e-9, np.log(focal) + 1e-9
        if fix_bones:
            lo[:9], hi[:9] = bones - 1e-9, bones + 1e-9
        p0 = np.clip(p0, lo + 1e-12, hi - 1e-12)
        p, _ = minimize.least_squares(p0, problem.residual, bounds=(lo, hi), jacobian=problem.jacobian,
                                      max_iter=10, verbose=0)
        bones, logf, roots = problem.unpack(p)
        focal = float(np.exp(logf)) if estimate_focal else focal
        kin.set_bone_lengths(bones)
        qpos[:, :3] = roots
        for i in range(len(idx)):
            x0, quat = tangent_from_qpos(qpos[i])
            fp = FrameProblem(kin, quat, sub_obs[i], sub_w[i], focal, np.asarray(principal_point),
                              robust_px=robust_px)
            sol = solve_frame(fp, x0, parameter_bounds(fp, kin.skeleton.lower, kin.skeleton.upper, joint_limits),
                              max_iter=8)
            qpos[i] = qpos_from_tangent(sol.params, quat)
    errors = []
    for i in range(len(idx)):
        x0, quat = tangent_from_qpos(qpos[i])
        fp = FrameProblem(kin, quat, sub_obs[i], sub_w[i], focal, np.asarray(principal_point))
        errors.append(fp.reprojection_error_px(x0))
    return Calibration(np.array(bones), float(focal), idx, qpos, float(np.nanmean(errors)))
