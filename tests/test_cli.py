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
    assert main(["demo", "--out", str(tmp_path), "--size", "96x72", "--seconds-per-joint", "0.15"]) == 0
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
