"""The CLI is a thin layer: help, model info, demo, and one-line errors."""

import json

import cv2
import pytest

from hdvr.cli import main


def test_help_lists_commands(capsys):
    assert main([]) == 0
    out = capsys.readouterr().out
    assert "demo" in out and "model" in out


def test_model_info_json(capsys):
    assert main(["model", "info", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["dof"] == {"nq": 41, "nv": 40, "hinges": 34, "free_root": 1}
    assert len(info["joints"]) == 34 and len(info["keypoint_sites"]) == 25
    assert info["total_mass_kg"] == pytest.approx(65.0)


def test_model_info_table(capsys):
    assert main(["model", "info", "--height", "1.6"]) == 0
    out = capsys.readouterr().out
    assert "right_knee_flex" in out and "paper (theta_22)" in out and "height 1.60 m" in out


def test_demo_writes_a_video(tmp_path):
    assert main(["demo", "--out", str(tmp_path), "--size", "96x72", "--seconds-per-joint", "0.15", "--quick"]) == 0
    cap = cv2.VideoCapture(str(tmp_path / "dancer_joint_ranges.mp4"))
    frames = 0
    while True:
        ok, frame = cap.read()
        if not ok:
            break
        frames += 1
        assert frame.shape == (72, 96, 3)
    assert frames > 50


def test_user_errors_are_one_line(capsys):
    assert main(["demo", "--size", "big"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hdvr: error:") and "\n" not in err


def test_convert_openpose_and_bvh(tmp_path, capsys):
    import numpy as np

    from hdvr.io.bvh import read_bvh
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.io.result3d import Result3D, save_result3d
    from hdvr.skeleton import Skeleton

    folder = tmp_path / "op"
    folder.mkdir()
    for t in range(3):
        flat = [v for j in range(25) for v in (100.0 + j, 200.0 + t, 0.9)]
        (folder / f"v_{t:012d}_keypoints.json").write_text(json.dumps({"people": [{"pose_keypoints_2d": flat}]}))
    assert main(["convert", "openpose", str(folder), "--fps", "25", "--size", "640x480",
                 "--out", str(tmp_path / "kp.npz")]) == 0
    kp = load_keypoints2d(tmp_path / "kp.npz")
    assert kp.num_frames == 3 and kp.fps == 25 and kp.image_size == (640, 480)

    sk = Skeleton()
    q = np.stack([sk.rest_qpos()] * 5)
    r = Result3D(sk.keypoints(q), q, 1000.0, (320, 240), sk.bone_lengths, np.zeros(5), fps=25.0)
    save_result3d(tmp_path / "r.npz", r)
    assert main(["convert", "bvh", str(tmp_path / "r.npz"), "--out", str(tmp_path / "d.bvh")]) == 0
    motion = read_bvh(tmp_path / "d.bvh")
    assert motion.num_frames == 5 and motion.fps == pytest.approx(25)
    assert main(["convert", "bvh", str(tmp_path / "missing.npz"), "--out", str(tmp_path / "x.bvh")]) == 2
    assert "3D result file not found" in capsys.readouterr().err
