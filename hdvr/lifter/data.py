"""Training windows for the lifter from (2D keypoints, 3D fit) pairs of one dancer's clip (:class:`WindowBatcher`).

A :class:`LiftingClip` holds, per frame: BODY_25 2D keypoints in normalised camera coordinates with confidence
(T, 25, 3), the fit's 3D keypoints P* in the camera frame (T, 25, 3) metres, and optionally 3D labels for
semi-supervised training. Windows are padded at the clip's ends by repeating the first/last frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES

#: BODY_25 index of each joint's mirror image (left <-> right), for flip augmentation.
FLIP_INDEX = np.array([BODY25_NAMES.index(n.replace("left_", "@").replace("right_", "left_").replace("@", "right_"))
                       for n in BODY25_NAMES])


def normalise_keypoints(keypoints_px: np.ndarray, focal, principal_point) -> np.ndarray:
    """(T, J, 3) pixels + confidence -> (T, J, 3) normalised ((u - c_x) / f, (v - c_y) / f) + confidence.

    ``focal`` scalar or (T,); ``principal_point`` (2,) or (T, 2). Missing keypoints (confidence 0 or NaN) become
    zeros with confidence 0.
    """
    kp = np.asarray(keypoints_px, dtype=np.float64)
    f = np.broadcast_to(np.asarray(focal, dtype=np.float64), kp.shape[:1])[:, None, None]
    c = np.broadcast_to(np.asarray(principal_point, dtype=np.float64), kp.shape[:1] + (2,))[:, None, :]
    out = np.zeros_like(kp)
    out[..., :2] = (kp[..., :2] - c) / f
    conf = np.where(np.isfinite(kp[..., 2]), kp[..., 2], 0.0)
    missing = (conf <= 0) | ~np.isfinite(out[..., :2]).all(-1)
    out[missing, :2] = 0.0
    out[..., 2] = np.where(missing, 0.0, conf)
    return out.astype(np.float32)


@dataclass
class LiftingClip:
    """One dancer's clip: ``inputs`` (T, 25, 3) normalised 2D + confidence, ``fit3d`` (T, 25, 3) metres camera
    frame (the unsupervised fit, P*), optional ``labels3d`` (T, 25, 3) metres camera frame."""

    inputs: np.ndarray
    fit3d: np.ndarray
    labels3d: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = self.inputs.shape[0]
        if self.inputs.shape[1:] != (25, 3) or self.fit3d.shape != (t, 25, 3):
            raise HDVRError(f"lifting clip needs inputs (T, 25, 3) and fit3d (T, 25, 3), got {self.inputs.shape} "
                            f"and {self.fit3d.shape}")
        if self.labels3d is not None and self.labels3d.shape != (t, 25, 3):
            raise HDVRError(f"labels3d must be (T={t}, 25, 3), got {self.labels3d.shape}")


def mirror(points):
    """(..., 25, C) keypoints (numpy array or torch tensor) mirrored through the camera's vertical plane: x -> -x,
    left and right exchanged (normalised 2D, whose x is measured from the principal point, or camera-frame 3D)."""
    if isinstance(points, torch.Tensor):
        out = points[..., torch.as_tensor(FLIP_INDEX, device=points.device), :].clone()
    else:
        out = points[..., FLIP_INDEX, :].copy()
    out[..., 0] *= -1
    return out


class WindowBatcher:
    """Training windows of ``receptive_field + out_frames - 1`` input frames predicting ``out_frames`` outputs,
    one starting every ``stride`` frames of every clip, gathered a batch at a time by tensor indexing.

    All clips are concatenated once onto ``device``; a batch is one gather, so feeding a GPU costs no Python loop
    per window (a per-item dataset kept the GPU waiting). Windows are padded at a clip's ends by repeating its
    first / last frame. Batch keys: ``inputs`` (B, T_in, 25, 3), ``keypoints2d`` (B, L, 25, 2), ``confidence``
    (B, L), ``fit3d`` (B, L, 25, 3), ``labels3d`` (B, L, 25, 3) (zeros where a clip has none) and ``has_labels``
    (B,) bool. ``flip`` mirrors half the windows (x -> -x, left <-> right), chosen with the order by
    (seed, epoch), so a run is the same for a seed on any device.
    """

    def __init__(self, clips: list[LiftingClip], receptive_field: int, out_frames: int = 16, flip: bool = True,
                 seed: int = 0, stride: int = 2, device: str | torch.device = "cpu"):
        if not clips:
            raise HDVRError("no training clips")
        self.rf, self.out_frames, self.flip, self.seed = receptive_field, out_frames, flip, seed
        self.device = torch.device(device)
        lengths = [c.inputs.shape[0] for c in clips]
        offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])

        def stacked(arrays) -> torch.Tensor:
            return torch.from_numpy(np.ascontiguousarray(np.concatenate(arrays), dtype=np.float32)).to(self.device)

        self.inputs = stacked([c.inputs for c in clips])
        self.fit3d = stacked([c.fit3d for c in clips])
        self.labels3d = stacked([c.labels3d if c.labels3d is not None else np.zeros_like(c.fit3d) for c in clips])
        self.frame_has_labels = torch.from_numpy(np.concatenate(
            [np.full(n, c.labels3d is not None) for n, c in zip(lengths, clips)])).to(self.device)
        # one row per window: (first output frame's index in the concatenation, clip's first index, clip's last)
        rows = [(o + s, o, o + n - 1) for o, n in zip(offsets, lengths) for s in range(0, n, stride)]
        self.windows = torch.tensor(rows, dtype=torch.long, device=self.device)

    def __len__(self) -> int:
        return len(self.windows)

    def order(self, epoch: int) -> tuple[torch.Tensor, torch.Tensor]:
        """The epoch's window order and flip flags (B,), from a CPU generator seeded by (seed, epoch)."""
        generator = torch.Generator().manual_seed(int(np.random.SeedSequence((self.seed, epoch)).generate_state(1)[0]))
        order = torch.randperm(len(self), generator=generator)
        flips = (torch.rand(len(self), generator=generator) < 0.5) & self.flip
        return order.to(self.device), flips.to(self.device)

    def batches(self, epoch: int, batch_size: int, drop_last: bool = True):
        """Yield the epoch's batches (see the class docstring); a last partial batch only if not ``drop_last``
        or if it is the only one."""
        order, flips = self.order(epoch)
        n = len(self)
        stop = n - n % batch_size if drop_last and n > batch_size else n
        for s in range(0, stop, batch_size):
            yield self.gather(order[s:s + batch_size], flips[order[s:s + batch_size]])

    def gather(self, windows: torch.Tensor, flips: torch.Tensor) -> dict[str, torch.Tensor]:
        """The batch of the given window indices (B,), mirrored where ``flips`` (B,) is true."""
        first, lo, hi = self.windows[windows].T
        pad = (self.rf - 1) // 2
        steps_in = torch.arange(self.rf + self.out_frames - 1, device=self.device)
        idx_in = (first[:, None] - pad + steps_in).clamp(lo[:, None], hi[:, None])
        idx_out = (first[:, None] + steps_in[:self.out_frames]).clamp(lo[:, None], hi[:, None])
        inputs, kp = self.inputs[idx_in], self.inputs[idx_out]
        fit, labels = self.fit3d[idx_out], self.labels3d[idx_out]
        if bool(flips.any()):
            f = flips[:, None, None, None]
            inputs, kp, fit, labels = (torch.where(f, mirror(a), a) for a in (inputs, kp, fit, labels))
        return {"inputs": inputs, "keypoints2d": kp[..., :2].contiguous(), "confidence": kp[..., 2].contiguous(),
                "fit3d": fit, "labels3d": labels, "has_labels": self.frame_has_labels[first]}
