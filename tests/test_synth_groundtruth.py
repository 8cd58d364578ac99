import json
import os

import numpy as np
import pytest

from hdvr.io.keypoints2d import load_keypoints2d
from hdvr.synth.groundtruth import GT_KEYS, clip_spec, is_done, make_clip, write_index

os.environ.setdefault("MUJOCO_GL", "egl")


def test_clip_spec_is_deterministic_and_couples_are_even():
    a = [clip_spec(i, 5, ("tango", "ballet"), (1, 4), 3.0) for i in range(20)]
    b = [clip_spec(i, 5, ("tango", "ballet"), (1, 4), 3.0) for i in range(20)]
    assert a == b
    assert all(s.n_dancers % 2 == 0 for s in a if s.genre == "tango" and s.n_dancers > 1)
    assert {s.genre for s in a} == {"tango", "ballet"}


def test_rendered_clip_has_full_ground_truth(tmp_path):
    import cv2

    spec = clip_spec(0, 1, ("swing",), (2, 2), 1.0, size=(320, 240))
    meta = make_clip(tmp_path, spec, render=True)
    folder = tmp_path / spec.name
    assert meta["n_dancers"] == 2 and meta["frames"] == 30
    assert meta["joint_limit_violation_rad"] == 0 and meta["foot_penetration_m"] <= 0.01
    gt = np.load(folder / "gt.npz")
    assert set(GT_KEYS) <= set(gt.files)
    assert gt["keypoints3d_camera"].shape == (2, 30, 25, 3) and gt["labels"].shape == (2, 30, 16)
    assert set(np.unique(gt["visibility"])) <= {0, 1, 2} and (gt["visibility"] == 2).mean() > 0.5
    # camera frame = R (world - C)
    expect = np.einsum("tij,ktnj->ktni", gt["camera_rotation"], gt["keypoints3d_world"] - gt["camera_centre"][None, :, None])
    assert np.allclose(gt["keypoints3d_camera"], expect, atol=1e-4)
    cap = cv2.VideoCapture(str(folder / "video.mp4"))
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == 30 and int(cap.get(cv2.CAP_PROP_FRAME_WIDTH)) == 320
    cap.release()
    kp = load_keypoints2d(folder / "dancer_1.keypoints2d.npz")
    assert kp.keypoints.shape == (30, 25, 3) and kp.image_size == (320, 240)
    rows = [line.split(",") for line in (folder / "mot.txt").read_text().splitlines()]
    assert len(rows[0]) == 9 and {r[1] for r in rows} == {"1", "2"} and rows[0][0] == "1"
    labels = json.loads((folder / "labels.json").read_text())
    assert labels["genre"] == "swing" and len(labels["dancers"]) == 2
    assert is_done(tmp_path, spec, render=True)
    assert not is_done(tmp_path, clip_spec(0, 2, ("swing",), (2, 2), 1.0, size=(320, 240)), render=True)
    index = write_index(tmp_path)
    assert index["clips"][0]["clip"] == "clip_00000" and index["label_count"] == 154


def test_no_render_is_deterministic(tmp_path):
    spec = clip_spec(3, 7, ("belly_dance",), (1, 3), 2.0)
    make_clip(tmp_path / "a", spec, render=False)
    make_clip(tmp_path / "b", spec, render=False)
    a, b = np.load(tmp_path / "a" / spec.name / "gt.npz"), np.load(tmp_path / "b" / spec.name / "gt.npz")
    for key in ("qpos", "keypoints2d", "labels", "camera_rotation", "boxes"):
        assert np.array_equal(a[key], b[key], equal_nan=True), key
    assert not (tmp_path / "a" / spec.name / "video.mp4").exists()
    assert not is_done(tmp_path / "a", spec, render=True) and is_done(tmp_path / "a", spec, render=False)
