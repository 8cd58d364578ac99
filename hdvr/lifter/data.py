"""Training windows for the lifter from (2D keypoints, 3D fit) pairs of one dancer's clip.

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


def _padded_window(arr: np.ndarray, start: int, length: int) -> np.ndarray:
    idx = np.clip(np.arange(start, start + length), 0, arr.shape[0] - 1)
    return arr[idx]


class WindowDataset(torch.utils.data.Dataset):
    """Windows of ``receptive_field + out_frames - 1`` input frames predicting ``out_frames`` outputs, starting
    every ``stride`` frames.

    Each item: ``inputs`` (T_in, 25, 3), ``keypoints2d`` (L, 25, 2), ``confidence`` (L, 25), ``fit3d`` (L, 25, 3),
    ``labels3d`` (L, 25, 3) (zeros when absent) and ``has_labels`` (bool). ``flip`` mirrors at random
    (x -> -x, left <-> right), deterministic per (seed, epoch, index) via the generator passed to sampling.
    """

    def __init__(self, clips: list[LiftingClip], receptive_field: int, out_frames: int = 16, flip: bool = True,
                 seed: int = 0, stride: int = 2):
        if not clips:
            raise HDVRError("no training clips")
        self.clips, self.rf, self.out_frames, self.flip = clips, receptive_field, out_frames, flip
        self.seed = seed
        self.epoch = 0
        # overlapping windows (a new one every ``stride`` frames): many more optimisation steps per epoch
        self.index = [(c, s) for c, clip in enumerate(clips) for s in range(0, clip.inputs.shape[0], stride)]

    def __len__(self) -> int:
        return len(self.index)

    def __getitem__(self, i: int) -> dict:
        c, start = self.index[i]
        clip = self.clips[c]
        pad = (self.rf - 1) // 2
        inputs = _padded_window(clip.inputs, start - pad, self.rf + self.out_frames - 1).copy()
        kp = _padded_window(clip.inputs, start, self.out_frames).copy()
        fit = _padded_window(clip.fit3d, start, self.out_frames).copy()
        labels = (_padded_window(clip.labels3d, start, self.out_frames).copy() if clip.labels3d is not None
                  else np.zeros_like(fit))
        rng = np.random.default_rng((self.seed, self.epoch, i))
        if self.flip and rng.random() < 0.5:
            inputs, kp, fit, labels = (a[:, FLIP_INDEX] for a in (inputs, kp, fit, labels))
            for a in (inputs, kp, fit, labels):
                a[..., 0] *= -1
        return {"inputs": torch.from_numpy(np.ascontiguousarray(inputs, dtype=np.float32)),
                "keypoints2d": torch.from_numpy(np.ascontiguousarray(kp[..., :2], dtype=np.float32)),
                "confidence": torch.from_numpy(np.ascontiguousarray(kp[..., 2], dtype=np.float32)),
                "fit3d": torch.from_numpy(np.ascontiguousarray(fit, dtype=np.float32)),
                "labels3d": torch.from_numpy(np.ascontiguousarray(labels, dtype=np.float32)),
                "has_labels": torch.tensor(clip.labels3d is not None)}
