"""Noise-adaptive temporal smoothing of 2D keypoint tracks before the fit (pixels, image frame).

Detectors jitter: a keypoint's position carries per-frame noise of a few pixels that the fit would otherwise
follow in depth. The noise level of a clip is estimated from the second differences of its keypoint tracks:
for a track sampled fast enough that its motion is locally linear, ``x_{t+1} - 2 x_t + x_{t-1}`` is three
noise samples with weights 1, -2, 1, so ``sigma = 1.4826 MAD / sqrt(6)`` (MAD: median absolute value, robust to
the frames where the dancer really accelerates). Motion itself adds to the estimate (0.5-2.1 px on clean
projections of 14 salsa mocap clips at 1920x1080, 30 fps, the fast-spinning follower highest; 3.2-4.0 px with 3 px
of added noise), so tracks are smoothed only when the estimate exceeds a threshold (default 2.5 px): a
Savitzky-Golay filter (local quadratic, default 7 frames; scipy's ``savgol_filter``) over each run of frames
where the keypoint is seen.

Measured (``python3 scripts/fit_clips.py --condition noise3px --settings smooth_2d_window=W``: 14 salsa clips of
10 s, focal given, 3 px noise; P-MPJPE / MPJPE mm): none 63.8 / 72.4; window 5:
63.0 / 71.4; 7 (default): 57.9 / 64.4; 9: 59.4 / 66.1; 13: 63.9 / 71.1. Smoothing clean keypoints (window 9) costs
4-6 mm (fast motion is blurred), hence the threshold.
"""

from __future__ import annotations

import numpy as np


def estimate_noise_px(xy: np.ndarray, valid: np.ndarray) -> float:
    """Robust per-coordinate noise (pixels) of keypoint tracks ``xy`` (T, J, 2) where ``valid`` (T, J) is True;
    NaN when fewer than 10 second differences exist (three consecutive valid frames of a keypoint)."""
    ok = valid[2:] & valid[1:-1] & valid[:-2]
    d2 = (xy[2:] - 2 * xy[1:-1] + xy[:-2])[ok]
    if d2.size < 20:
        return float("nan")
    return float(1.4826 * np.median(np.abs(d2)) / np.sqrt(6.0))


def smooth_tracks(xy: np.ndarray, valid: np.ndarray, window: int = 7, order: int = 2) -> np.ndarray:
    """Savitzky-Golay filtered copy of ``xy`` (T, J, 2) pixels, per keypoint over each run of valid frames at
    least ``window`` long (shorter runs and invalid frames are returned unchanged)."""
    if window % 2 == 0 or window <= order:
        raise ValueError(f"window must be odd and larger than the order, got window={window}, order={order}")
    from scipy.signal import savgol_filter  # imported here: scipy.signal adds ~70 MB, clean clips never need it
    out = np.array(xy, dtype=np.float64, copy=True)
    for j in range(xy.shape[1]):
        v = np.concatenate([[False], valid[:, j], [False]]).astype(np.int8)
        starts = np.flatnonzero(np.diff(v) == 1)
        stops = np.flatnonzero(np.diff(v) == -1)
        for a, b in zip(starts, stops):
            if b - a >= window:
                out[a:b, j] = savgol_filter(xy[a:b, j], window, order, axis=0, mode="interp")
    return out


def adaptive_smooth(xy: np.ndarray, valid: np.ndarray, threshold_px: float = 2.5, window: int = 7,
                    order: int = 2, mode: str = "auto") -> tuple[np.ndarray, float, bool]:
    """(keypoints, estimated noise px, smoothed?). ``mode`` "auto": :func:`smooth_tracks` when the clip's
    estimated noise exceeds ``threshold_px``, else the keypoints unchanged; "on": always smoothed; "off": never
    (the noise is still estimated)."""
    noise = estimate_noise_px(xy, valid)
    if mode == "on" or (mode == "auto" and np.isfinite(noise) and noise > threshold_px):
        return smooth_tracks(xy, valid, window, order), noise, True
    return xy, noise, False
