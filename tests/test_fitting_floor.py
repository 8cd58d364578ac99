"""Floor plane, camera pose in the world and the move of qpos from the camera frame to the floor world."""

import numpy as np

from hdvr.camera import look_at
from hdvr.fitting.floor import camera_pose_in_world, estimate_floor, qpos_to_world
from hdvr.skeleton import Skeleton


def _walking_dancer(sk, frames=40):
    q = np.tile(sk.rest_qpos(), (frames, 1))
    q[:, 0] = np.linspace(-1.0, 1.0, frames)  # travels 2 m forward
    q[:, 1] = 0.5 * np.sin(np.linspace(0, 3, frames))
    return q


def test_floor_and_camera_pose_recover_a_known_camera():
    sk = Skeleton()
    q_world = _walking_dancer(sk)
    cam = look_at([4.0, 3.0, 2.5], [0.0, 0.0, 1.0])
    kp_cam = cam.to_camera(sk.keypoints(q_world))
    floor = estimate_floor(kp_cam)
    true_up = cam.rotation @ np.array([0.0, 0.0, 1.0])
    assert np.degrees(np.arccos(np.clip(floor.normal @ true_up, -1, 1))) < 1.0
    assert abs(floor.height(cam.to_camera(np.zeros(3)))) < 0.01  # the world origin lies on the floor
    rotation, centre = camera_pose_in_world(floor, kp_cam[0, 8])
    assert np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9)
    assert abs(centre[2] - 2.5) < 0.02  # camera height above the floor


def test_qpos_to_world_matches_keypoints():
    sk = Skeleton()
    q_cam = _walking_dancer(sk, 5)
    rotation = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    centre = np.array([-5.0, 0.3, 1.4])
    q_world = qpos_to_world(q_cam, rotation, centre)
    expected = sk.keypoints(q_cam) @ rotation + centre  # P_world = R^T P_cam + C
    assert np.allclose(sk.keypoints(q_world), expected, atol=1e-9)
    assert np.allclose(q_world[:, 7:], q_cam[:, 7:])
