"""Seed choice of the windowed fit (hdvr.fitting.window)."""

import numpy as np

from hdvr import dh
from hdvr.camera import project
from hdvr.fitting.kinematics import DancerKinematics
from hdvr.fitting.presets import FitSettings
from hdvr.fitting.seeds import root_rotation_facing, upright_qpos
from hdvr.fitting.window import WindowFitter
from hdvr.skeleton import Skeleton


def test_mirror_seeds_start_with_the_segments_parallel_to_the_image_plane():
    kin = DancerKinematics(Skeleton())
    q = upright_qpos(kin, np.array([0.0, 0.0, 4.0]), 0.0)  # facing the camera, arms hanging
    q[7 + dh.JOINT_NAMES.index("right_elbow_flex")] = -np.pi / 2  # right forearm points at the camera
    kp = kin.keypoints(q)
    obs = project(kp, 1500.0, (960.0, 540.0))[None]
    fitter = WindowFitter(kin, obs, np.ones((1, 25)), 1500.0, (960.0, 540.0), FitSettings(), False)
    ranked = fitter.rank_segments(0, q, 0, 1500.0)
    assert ranked[-1] == "right_forearm"
    assert sorted(ranked) == sorted(set(ranked)) and len(ranked) == 8
    forearm = kp[4] - kp[3]
    assert abs(forearm[2]) > 0.8 * np.linalg.norm(forearm)  # the set-up is what the test says


def test_upright_seed_orientation_follows_the_vertical_even_from_straight_above():
    for vertical in (np.array([0.0, -0.9, 0.3]), np.array([0.0, 0.0, -1.0])):  # tilted camera; looking down
        vertical = vertical / np.linalg.norm(vertical)
        for yaw in (0.0, 1.3):
            rot = root_rotation_facing(yaw, vertical)
            assert np.all(np.isfinite(rot)) and np.allclose(rot.T @ rot, np.eye(3), atol=1e-9)
            assert np.allclose(rot[:, 2], vertical) and np.isclose(np.linalg.det(rot), 1.0)
    # no vertical given: the image's up axis, facing the camera at yaw 0
    assert np.allclose(root_rotation_facing(0.0)[:, 0], [0.0, 0.0, -1.0])
