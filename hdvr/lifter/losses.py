"""Loss terms of the paper's Algorithm 4* (eq. L), as small pure functions on torch tensors.

Shapes: 3D poses (B, T, J, 3) camera-frame metres; 2D (B, T, J, 2) normalised camera coordinates
(pixels minus principal point, divided by the focal length); weights (B, T, J) in [0, 1] (detector confidence).

    L = w_2d |Psi(P_hat_t) - p_t|^2 + w_fit |P_hat_t - P*_t|^2 + w_t3d |P_hat_t - P_hat_{t-1}|^2
        + w_t2d |Psi(P_hat_t) - Psi(P_hat_{t-1})|^2 (+ w_sup |P_hat_t - P_t|^2 where 3D labels exist)
"""

from __future__ import annotations

import torch


#: Nearest depth (m) the losses accept: a filmed dancer is never closer to the camera than this.
MIN_DEPTH_M = 0.3


def project_normalised(points_cam: torch.Tensor) -> torch.Tensor:
    """Pinhole projection to normalised coordinates (x / z, y / z); depth clamped at :data:`MIN_DEPTH_M`."""
    return points_cam[..., :2] / points_cam[..., 2:3].clamp(min=MIN_DEPTH_M)


def weighted_mean(err: torch.Tensor, weight: torch.Tensor | None) -> torch.Tensor:
    if weight is None:
        return err.mean()
    return (err * weight).sum() / weight.sum().clamp(min=1e-6)


def reprojection_loss(pred_cam: torch.Tensor, keypoints2d: torch.Tensor, confidence: torch.Tensor) -> torch.Tensor:
    """Confidence-weighted squared reprojection error (normalised units).

    Computed as ``|(x, y) - p z| / z_ref`` with ``z_ref`` the frame's mean depth (no gradient): equal to the
    image-plane error where a joint's depth is near the frame's mean, and free of the 1/z blow-up that makes the
    plain form unstable while the network's depth is still wrong.
    """
    z = pred_cam[..., 2:3]
    z_ref = z.detach().mean(dim=-2, keepdim=True).clamp(min=MIN_DEPTH_M)
    err = (((pred_cam[..., :2] - keypoints2d * z) / z_ref) ** 2).sum(-1)
    return weighted_mean(err, confidence)


def fit_consistency_loss(pred_cam: torch.Tensor, fit_cam: torch.Tensor, weight: torch.Tensor | None = None):
    """Squared distance (m^2) to the unsupervised fit's 3D pose P* (Algorithm 3*'s output)."""
    return weighted_mean(((pred_cam - fit_cam) ** 2).sum(-1), weight)


def temporal_3d_loss(pred_cam: torch.Tensor) -> torch.Tensor:
    """Squared frame-to-frame 3D motion (m^2), mean over joints and frames."""
    return ((pred_cam[:, 1:] - pred_cam[:, :-1]) ** 2).sum(-1).mean()


def temporal_2d_loss(pred_cam: torch.Tensor) -> torch.Tensor:
    """Squared frame-to-frame motion of the projected prediction (normalised units^2)."""
    proj = project_normalised(pred_cam)
    return ((proj[:, 1:] - proj[:, :-1]) ** 2).sum(-1).mean()


def mpjpe(pred: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """Mean per-joint position error (same units as the inputs)."""
    return torch.linalg.norm(pred - target, dim=-1).mean()
