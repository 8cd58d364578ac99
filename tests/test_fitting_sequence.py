"""End to end on real mocap: a short CMU salsa clip projected through one virtual camera, fitted from 2D.

Loose thresholds; the benchmark (scripts/bench_fit3d.py) carries the real numbers.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from hdvr.camera import orbit_camera, project
from hdvr.errors import HDVRError
from hdvr.fitting.calibration import bones_from_projections
from hdvr.fitting.kinematics import DancerKinematics
from hdvr.fitting.limits import apply_ranges
from hdvr.fitting.presets import FitSettings, paper_settings
from hdvr.fitting.sequence import calibrate_dancer, clip_vertical, fit_keypoints, observation_weights
from hdvr.io.bvh import load_mocap_body25
from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
from hdvr.io.result3d import load_result3d
from hdvr.layouts import BODY25_NAMES, COCO17_NAMES, convert
from hdvr.metrics import evaluate
from hdvr.plausibility import bone_length_cv, limit_violations
from hdvr.skeleton import Skeleton

FOCAL = 1500.0
PP = (960.0, 540.0)


@pytest.fixture(scope="module")
def salsa(salsa_view):
    return salsa_view("01", 5, 65, 30.0)


def test_fit_with_given_focal_is_close_and_plausible(salsa):
    kp, gt = salsa
    sk = Skeleton()
    result, report = fit_keypoints(kp, FitSettings(focal=FOCAL), sk)
    scores = evaluate(result.keypoints3d, gt)
    assert scores["mpjpe_mm"] < 150 and scores["p_mpjpe_mm"] < 120, scores
    assert np.nanmean(result.reprojection_error_px) < 8.0
    assert limit_violations(sk, result.qpos)[0] == 0
    assert max(bone_length_cv(sk.keypoints(result.qpos)).values()) < 0.01
    # the world qpos reproduces the camera-frame keypoints through the reported camera pose
    world = sk.keypoints(result.qpos)
    assert np.allclose((world - result.camera_centre) @ result.camera_rotation.T, result.keypoints3d, atol=1e-4)
    assert report.frames == 60 and report.frames_per_second > 0
    assert 0 <= report.arm_depth_frames <= 60 and result.meta["arm_depth_frames"] == report.arm_depth_frames
    _, off = fit_keypoints(kp, FitSettings(focal=FOCAL, limb_depth=False), Skeleton())
    assert off.arm_depth_frames == 0


def test_bones_from_projections_match_the_mocap(salsa):
    kp, gt = salsa
    sk = Skeleton()
    kin = DancerKinematics(sk)
    obs = kp.keypoints[..., :2].astype(float)
    bones = bones_from_projections(kin, obs, np.ones(obs.shape[:2]), gt, FOCAL, 1.70)
    i = {n: BODY25_NAMES.index(n) for n in BODY25_NAMES}
    upper_leg = np.linalg.norm(gt[:, i["right_hip"]] - gt[:, i["right_knee"]], axis=1).mean()
    spine = np.linalg.norm(gt[:, i["neck"]] - gt[:, i["mid_hip"]], axis=1).mean()
    assert bones[6] == pytest.approx(upper_leg, rel=0.08)
    assert bones[0] == pytest.approx(spine, rel=0.08)


def test_clip_vertical_comes_from_a_track_with_the_dancers_own_bones(shared_data):
    """Salsa 60_06 seen level from 8 m (the benchmark's camera for that clip): with the table's mean proportions
    the quick track leans the trunk and its mean trunk direction is 17 deg from the true vertical; refitted with
    the calibrated bones it is 7 deg."""
    pos, _ = load_mocap_body25(shared_data / "cmu-salsa" / "60_06_scaled.bvh", fps=30)
    clip = pos[30:330]
    cam = orbit_camera(7.984, 256.69, 1.468, target=(*np.nanmean(clip[:, 8, :2], axis=0), 1.0))
    uv = project(cam.to_camera(clip), 1955.2, PP)
    kp = Keypoints2D(np.concatenate([uv, np.ones(uv.shape[:2] + (1,))], -1), BODY25_NAMES, 30.0, (1920, 1080))
    true_up = cam.to_camera(np.array([[0.0, 0.0, 1.0]]))[0] - cam.to_camera(np.zeros((1, 3)))[0]
    settings = FitSettings(focal=1955.2, workers=1)
    obs, weights = observation_weights(kp, settings)
    skeleton = Skeleton()
    apply_ranges(skeleton, settings.joint_ranges)
    kin = DancerKinematics(skeleton)
    cal = calibrate_dancer(kin, obs, weights, 1955.2, np.array(PP), settings, estimate_focal=False)
    assert np.allclose(kin.bone_lengths, cal.bone_lengths) and cal.focal == 1955.2
    error_deg = np.degrees(np.arccos(np.clip(cal.vertical @ true_up, -1, 1)))
    assert error_deg < 10.0, error_deg
    # the clip vertical estimator itself is exact on the mocap's upright frames
    assert np.degrees(np.arccos(clip_vertical(cam.to_camera(clip)) @ true_up)) < 3.0


def test_paper_preset_runs_algorithm_3(salsa):
    kp, gt = salsa
    short = Keypoints2D(kp.keypoints[:12], kp.joint_names, kp.fps, kp.image_size)
    result, _ = fit_keypoints(short, paper_settings(focal=None), Skeleton())
    assert result.num_frames == 12 and np.isfinite(result.keypoints3d).all()
    assert np.isfinite(result.focal).all() and np.ptp(result.focal) >= 0


def test_cli_fits_coco17_with_missing_keypoints(salsa, tmp_path):
    kp, _ = salsa
    coco = convert(kp.keypoints[:20], "body25", "coco17", has_confidence=True)
    coco[3, 9] = [np.nan, np.nan, 0.0]  # a missing wrist
    coco[5:8, :, 2] = 0.02  # low-confidence frames
    src = tmp_path / "coco.npz"
    save_keypoints2d(src, Keypoints2D(coco.astype(np.float32), COCO17_NAMES, 30.0, (1920, 1080)))
    out = tmp_path / "result.npz"
    proc = subprocess.run([sys.executable, "-m", "hdvr", "fit3d", str(src), "--out", str(out), "--focal", "1500",
                           "--refine-sweeps", "1", "--chunk-frames", "8", "--workers", "2"], capture_output=True, text=True, env={"HDVR_NO_PROGRESS": "1",
                                                                                        **__import__("os").environ})
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout.strip().splitlines()[-1])
    assert summary["frames"] == 20
    result = load_result3d(out)
    assert result.keypoints3d.shape == (20, 25, 3) and np.isfinite(result.qpos).all()
    assert "plausibility" in result.meta


def test_nan_only_keypoints_are_a_one_line_error():
    kp = Keypoints2D(np.full((5, 25, 3), np.nan, dtype=np.float32), BODY25_NAMES, 30.0, (640, 480))
    with pytest.raises(HDVRError, match="visible"):
        fit_keypoints(kp, FitSettings(focal=500.0))


def test_cli_reports_missing_file(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "hdvr", "fit3d", str(tmp_path / "none.npz"), "--out",
                           str(tmp_path / "o.npz")], capture_output=True, text=True)
    assert proc.returncode == 2 and "not found" in proc.stderr and "Traceback" not in proc.stderr


def test_cli_takes_a_named_pose_prior_and_reports_a_missing_one(tmp_path):
    sk = Skeleton()
    cam = sk.keypoints(sk.rest_qpos())[None].repeat(6, 0)  # world metres, x forward, z up
    px = np.stack([320 - 400 * cam[..., 1], 400 - 400 * cam[..., 2], np.ones(cam.shape[:2])], axis=-1)
    src = tmp_path / "kp.npz"
    save_keypoints2d(src, Keypoints2D(px.astype(np.float32), BODY25_NAMES, 30.0, (640, 480)))
    proc = subprocess.run([sys.executable, "-m", "hdvr", "fit3d", str(src), "--out", str(tmp_path / "o.npz"),
                           "--pose-prior", str(tmp_path / "ballet.npz")], capture_output=True, text=True)
    assert proc.returncode == 2 and "pose prior" in proc.stderr and "not found" in proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "o.npz").exists()
    proc = subprocess.run([sys.executable, "-m", "hdvr", "fit3d", str(src), "--out", str(tmp_path / "o.npz"),
                           "--focal", "400", "--refine-sweeps", "1", "--workers", "1", "--pose-prior", "partner"],
                          capture_output=True, text=True, env={**__import__("os").environ, "HDVR_NO_PROGRESS": "1"})
    assert proc.returncode == 0, proc.stderr
    assert load_result3d(tmp_path / "o.npz").meta["settings"]["pose_prior_path"] == "partner"
