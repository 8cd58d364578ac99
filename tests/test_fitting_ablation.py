"""`hdvr ablate` on a short real clip: a table with a row per setting, metrics against the ground truth."""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

from hdvr.camera import orbit_camera, project
from hdvr.commands.fit3d import add_fit_arguments, settings_from_args
from hdvr.fitting.ablation import markdown_table, run_ablation, settings_for
from hdvr.fitting.presets import FitSettings
from hdvr.io.bvh import load_mocap_body25
from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
from hdvr.layouts import BODY25_NAMES


def test_ablation_switches_change_the_settings():
    base = FitSettings(focal=1000.0)
    assert not settings_for("no_joint_limits", base).joint_limits
    assert not settings_for("no_temporal", base).temporal
    assert settings_for("physics", base).physics
    assert base.pose_prior_weight > 0 and settings_for("no_pose_prior", base).pose_prior_weight == 0
    assert settings_for("paper", base).stride == 1 and settings_for("paper", base).focal == 1000.0
    assert settings_for("paper", base).pose_prior_weight == 0


def test_ablate_command_writes_markdown_and_json(shared_data, tmp_path):
    pos, _ = load_mocap_body25(shared_data / "cmu-salsa" / "61_02_scaled.bvh", fps=30)
    clip = pos[40:64]
    cam = orbit_camera(4.0, -60.0, 15.0, target=(*clip[:, 8, :2].mean(axis=0), 1.0))
    gt = cam.to_camera(clip)
    uv = project(gt, 1200.0, (960.0, 540.0))
    kp = Keypoints2D(np.concatenate([uv, np.ones(uv.shape[:2] + (1,))], -1), BODY25_NAMES, 30.0, (1920, 1080))
    save_keypoints2d(tmp_path / "clip.npz", kp)
    np.savez(tmp_path / "gt.npz", keypoints3d=gt)
    proc = subprocess.run([sys.executable, "-m", "hdvr", "ablate", str(tmp_path / "clip.npz"), "--ground-truth",
                           str(tmp_path / "gt.npz"), "--settings", "full", "no_temporal", "--focal", "1200",
                           "--out-dir", str(tmp_path / "abl")], capture_output=True, text=True,
                          env={**os.environ, "HDVR_NO_PROGRESS": "1"})
    assert proc.returncode == 0, proc.stderr
    rows = json.loads((tmp_path / "abl" / "ablation.json").read_text())
    assert [r["setting"] for r in rows] == ["full", "no_temporal"]
    assert all(np.isfinite(r["mpjpe_mm"]) and r["frames_per_second"] > 0 for r in rows)
    table = (tmp_path / "abl" / "ablation.md").read_text()
    assert "| full |" in table and "p_mpjpe_mm" in table


def test_ablation_in_parallel_processes_gives_the_same_rows(shared_data):
    pos, _ = load_mocap_body25(shared_data / "cmu-salsa" / "60_03_scaled.bvh", fps=30)
    clips = []
    for start, azimuth in ((40, 30.0), (90, 200.0)):
        clip = pos[start:start + 20]
        cam = orbit_camera(5.0, azimuth, 10.0, target=(*clip[:, 8, :2].mean(axis=0), 1.0))
        gt = cam.to_camera(clip)
        uv = project(gt, 1500.0, (960.0, 540.0))
        kp = Keypoints2D(np.concatenate([uv, np.ones(uv.shape[:2] + (1,))], -1), BODY25_NAMES, 30.0, (1920, 1080))
        clips.append((f"clip{start}", kp, gt))
    base = FitSettings(focal=1500.0, workers=1)
    serial = run_ablation(clips, ["full"], base)
    parallel = run_ablation(clips, ["full"], base, processes=2)
    assert [c["clip"] for c in parallel[0]["per_clip"]] == ["clip40", "clip90"]
    for a, b in zip(serial[0]["per_clip"], parallel[0]["per_clip"]):
        assert a["p_mpjpe_mm"] == b["p_mpjpe_mm"] and a["mpjpe_mm"] == b["mpjpe_mm"]
    row = parallel[0]
    assert row["p_mpjpe_mm_mean"] == np.mean([c["p_mpjpe_mm"] for c in row["per_clip"]])
    assert "p_mpjpe_mm (mean)" in markdown_table(parallel)


def test_fit_options_map_to_settings():
    parser = argparse.ArgumentParser()
    add_fit_arguments(parser)
    s = settings_from_args(parser.parse_args(["--smooth-2d", "on", "--no-upright", "--no-pose-prior"]))
    assert (s.smooth_2d, s.upright_weight, s.pose_prior_weight) == ("on", 0.0, 0.0)
    assert not settings_from_args(parser.parse_args(["--no-limb-depth"])).limb_depth
    assert settings_from_args(parser.parse_args(["--pose-prior-weight", "2"])).pose_prior_weight == 2.0
    s = settings_from_args(parser.parse_args(["--no-temporal"]))
    assert not s.temporal and s.smooth_2d == "off"  # 2D smoothing is temporal too
    s = settings_from_args(parser.parse_args(["--paper"]))
    assert s.smooth_2d == "off" and s.upright_weight == 0.0 and s.pose_prior_weight == 0.0 and not s.limb_depth
    s = settings_from_args(parser.parse_args([]))
    assert s.smooth_2d == "auto" and s.upright_weight > 0 and s.pose_prior_weight > 0
    assert s.limb_depth and not settings_for("no_limb_depth", s).limb_depth
    assert settings_for("no_upright", s).upright_weight == 0 and settings_for("no_temporal", s).smooth_2d == "off"
