"""3D pose metrics with VideoPose3D's definitions (Pavllo et al., CVPR 2019), in millimetres.

All functions take predicted and ground-truth joint positions ``(T, J, 3)`` in metres, in the same frame and
joint order, and return millimetres. :func:`evaluate` selects :data:`hdvr.layouts.EVAL_JOINTS` from BODY_25 and
makes both root-relative (root :data:`hdvr.layouts.ROOT_JOINT`) first: Protocol 1.

- MPJPE: mean Euclidean distance per joint and frame.
- P-MPJPE (Protocol 2): per frame, the prediction is aligned to the ground truth by the similarity transform
  (rotation, uniform scale, translation) minimising the squared error (orthogonal Procrustes; reflections are
  excluded by the sign correction of the SVD), then MPJPE.
- N-MPJPE: per frame, the prediction is scaled by ``s = <pred, gt> / <pred, pred>`` (the least-squares scale), then
  MPJPE.
- MPJVE: mean Euclidean distance between the first differences (per frame, not per second) of prediction and
  ground truth.
- Acceleration error: mean Euclidean distance between the second differences ``P_{t+1} - 2 P_t + P_{t-1}``.
"""

from __future__ import annotations

import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25, EVAL_JOINTS, ROOT_JOINT

MM = 1000.0


def _check(pred: np.ndarray, gt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(pred, dtype=np.float64)
    g = np.asarray(gt, dtype=np.float64)
    if p.shape != g.shape or p.ndim != 3 or p.shape[-1] != 3:
        raise HDVRError(f"metrics need matching (T, J, 3) arrays, got {p.shape} and {g.shape}")
    return p, g


def mpjpe(pred: np.ndarray, gt: np.ndarray) -> float:
    """Mean per-joint position error (mm)."""
    p, g = _check(pred, gt)
    return float(np.nanmean(np.linalg.norm(p - g, axis=-1)) * MM)


def procrustes_align(pred: np.ndarray, gt: np.ndarray) -> np.ndarray:
    """``pred`` (T, J, 3) aligned per frame to ``gt`` by rotation, scale and translation (no reflection)."""
    p, g = _check(pred, gt)
    mu_p = p.mean(axis=1, keepdims=True)
    mu_g = g.mean(axis=1, keepdims=True)
    x, y = p - mu_p, g - mu_g
    norm_x = np.sqrt(np.sum(x ** 2, axis=(1, 2), keepdims=True))
    norm_y = np.sqrt(np.sum(y ** 2, axis=(1, 2), keepdims=True))
    x = x / np.maximum(norm_x, 1e-12)
    y = y / np.maximum(norm_y, 1e-12)
    h = np.einsum("tji,tjk->tik", x, y)  # (T, 3, 3)
    u, s, vt = np.linalg.svd(h)
    v = np.transpose(vt, (0, 2, 1))
    sign = np.sign(np.linalg.det(np.einsum("tij,tkj->tik", v, u)))  # det(V U^T)
    v[:, :, -1] *= sign[:, None]
    s[:, -1] *= sign
    rot = np.einsum("tij,tkj->tik", v, u)  # R = V U^T, maps x to y
    trace = s.sum(axis=1)[:, None, None]
    scale = trace * norm_y / np.maximum(norm_x, 1e-12)
    return scale * np.einsum("tij,tkj->tki", rot, p - mu_p) + mu_g


def p_mpjpe(pred: np.ndarray, gt: np.ndarray) -> float:
    """MPJPE after per-frame similarity (Procrustes) alignment, Protocol 2 (mm)."""
    p, g = _check(pred, gt)
    return mpjpe(procrustes_align(p, g), g)


def n_mpjpe(pred: np.ndarray, gt: np.ndarray) -> float:
    """MPJPE after per-frame least-squares scaling of the prediction (mm)."""
    p, g = _check(pred, gt)
    scale = np.sum(p * g, axis=(1, 2), keepdims=True) / np.maximum(np.sum(p * p, axis=(1, 2), keepdims=True), 1e-12)
    return mpjpe(scale * p, g)


def mpjve(pred: np.ndarray, gt: np.ndarray) -> float:
    """Mean per-joint velocity error (mm per frame). Differences touching a NaN frame (left out) do not count."""
    p, g = _check(pred, gt)
    err = np.linalg.norm(np.diff(p, axis=0) - np.diff(g, axis=0), axis=-1)
    return float(np.nanmean(err) * MM) if np.isfinite(err).any() else float("nan")


def acceleration_error(pred: np.ndarray, gt: np.ndarray) -> float:
    """Mean per-joint acceleration error (mm per frame^2). Differences touching a NaN frame do not count."""
    p, g = _check(pred, gt)
    err = np.linalg.norm(np.diff(p, 2, axis=0) - np.diff(g, 2, axis=0), axis=-1)
    return float(np.nanmean(err) * MM) if np.isfinite(err).any() else float("nan")


def root_relative(body25: np.ndarray) -> np.ndarray:
    """BODY_25 (T, 25, 3) -> EVAL_JOINTS minus the root joint, (T, len(EVAL_JOINTS), 3)."""
    x = np.asarray(body25, dtype=np.float64)
    if x.ndim != 3 or x.shape[1:] != (25, 3):
        raise HDVRError(f"expected BODY_25 keypoints (T, 25, 3), got {x.shape}")
    root = x[:, BODY25.index(ROOT_JOINT)][:, None]
    return x[:, BODY25.indices(EVAL_JOINTS)] - root


def scored_frames(pred_body25: np.ndarray, gt_body25: np.ndarray) -> np.ndarray:
    """(T,) bool: the frames :func:`evaluate` scores, where both BODY_25 (T, 25, 3) poses have every one of
    :data:`EVAL_JOINTS` and the root (a frame without a pose is NaN, e.g. one the 3D fit had no 2D keypoints for)."""
    return _both_finite(root_relative(pred_body25), root_relative(gt_body25))


def _both_finite(p: np.ndarray, g: np.ndarray) -> np.ndarray:
    """(T,) bool: frames where both root-relative (T, J, 3) arrays are finite throughout."""
    return np.isfinite(p).all(axis=(1, 2)) & np.isfinite(g).all(axis=(1, 2))


def evaluate(pred_body25: np.ndarray, gt_body25: np.ndarray) -> dict[str, float]:
    """All metrics (mm) on :data:`EVAL_JOINTS`, root-relative, for BODY_25 (T, 25, 3) metres in one frame.

    Frames left out by :func:`scored_frames` count in no per-frame metric, and velocity and acceleration errors
    only span frames that both are scored."""
    p, g = root_relative(pred_body25), root_relative(gt_body25)
    scored = _both_finite(p, g)  # = scored_frames(pred_body25, gt_body25), without converting twice
    gap = np.where(scored[:, None, None], 0.0, np.nan)
    ps, gs = p[scored], g[scored]
    return {"mpjpe_mm": mpjpe(ps, gs), "p_mpjpe_mm": p_mpjpe(ps, gs), "n_mpjpe_mm": n_mpjpe(ps, gs),
            "mpjve_mm": mpjve(p + gap, g + gap), "accel_error_mm": acceleration_error(p + gap, g + gap)}
