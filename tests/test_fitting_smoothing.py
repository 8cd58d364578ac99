"""Noise-adaptive smoothing of 2D keypoint tracks (hdvr.fitting.smoothing)."""

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.fitting.presets import FitSettings
from hdvr.fitting.sequence import fit_keypoints
from hdvr.fitting.smoothing import adaptive_smooth, estimate_noise_px, smooth_tracks
from hdvr.io.keypoints2d import Keypoints2D


def _tracks(n=300, joints=25, seed=0):
    """Smooth synthetic tracks (pixels): each keypoint on its own slow ellipse."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)[:, None]
    phase, speed, radius = rng.uniform(0, 6, joints), rng.uniform(0.02, 0.08, joints), rng.uniform(20, 80, joints)
    centre = rng.uniform(200, 800, (joints, 2))
    return np.stack([centre[:, 0] + radius * np.cos(speed * t + phase),
                     centre[:, 1] + radius * np.sin(speed * t + phase)], axis=-1)


def test_noise_estimate_recovers_the_added_jitter_and_ignores_smooth_motion():
    xy = _tracks()
    valid = np.ones(xy.shape[:2], dtype=bool)
    assert estimate_noise_px(xy, valid) < 0.5
    noisy = xy + np.random.default_rng(1).normal(0, 3.0, xy.shape)
    assert estimate_noise_px(noisy, valid) == pytest.approx(3.0, rel=0.1)
    assert np.isnan(estimate_noise_px(xy[:3, :2], valid[:3, :2]))


def test_smoothing_halves_the_noise_and_leaves_gaps_alone():
    xy = _tracks()
    noisy = xy + np.random.default_rng(2).normal(0, 3.0, xy.shape)
    valid = np.ones(xy.shape[:2], dtype=bool)
    valid[100:104, 5] = False  # a gap: runs on each side are smoothed separately
    valid[200:205, 6] = False
    valid[205:209, 6] = True
    valid[209:220, 6] = False  # a run of 4 frames, shorter than the window: unchanged
    noisy[100:104, 5] = np.nan
    out = smooth_tracks(noisy, valid, window=9)
    ok = valid & np.isfinite(noisy).all(axis=2)
    err_before = np.sqrt(np.mean((noisy[ok] - xy[ok]) ** 2))
    err_after = np.sqrt(np.mean((out[ok] - xy[ok]) ** 2))
    assert err_after < 0.6 * err_before
    assert np.isnan(out[100:104, 5]).all()
    assert np.array_equal(out[205:209, 6], noisy[205:209, 6])
    with pytest.raises(ValueError):
        smooth_tracks(noisy, valid, window=8)


def test_adaptive_smoothing_only_above_the_threshold():
    xy = _tracks()
    valid = np.ones(xy.shape[:2], dtype=bool)
    _, noise, smoothed = adaptive_smooth(xy + np.random.default_rng(3).normal(0, 1.0, xy.shape), valid)
    assert not smoothed and noise < 2.5
    _, noise, smoothed = adaptive_smooth(xy + np.random.default_rng(3).normal(0, 4.0, xy.shape), valid)
    assert smoothed and noise > 2.5


def test_fit_reports_the_estimated_jitter_and_smooths_noisy_input(salsa_view):
    kp, gt = salsa_view("01", 5, 65, 30.0)
    noisy = kp.keypoints.copy()
    noisy[..., :2] += np.random.default_rng(4).normal(0, 4.0, noisy[..., :2].shape)
    noisy_kp = Keypoints2D(noisy, kp.joint_names, kp.fps, kp.image_size)
    result, report = fit_keypoints(noisy_kp, FitSettings(focal=1500.0, workers=1, refine_sweeps=0))
    assert report.smoothed_2d and report.keypoint_noise_px > 3.0
    assert result.meta["smoothed_2d"] is True
    # the reprojection error is reported against the keypoints given, not the smoothed ones: about the noise
    assert np.nanmean(result.reprojection_error_px) > 3.0
    _, clean_report = fit_keypoints(kp, FitSettings(focal=1500.0, workers=1, refine_sweeps=0))
    assert not clean_report.smoothed_2d and clean_report.keypoint_noise_px < 2.5


def test_smoothing_setting_is_checked():
    with pytest.raises(HDVRError):
        FitSettings(smooth_2d="sometimes")
    with pytest.raises(HDVRError):
        FitSettings(smooth_2d_window=8)
