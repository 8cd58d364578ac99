import numpy as np
import pytest

from hdvr.camera import Intrinsics, look_at, orbit_camera, project, projection_jacobian
from hdvr.errors import HDVRError


def test_projection_and_frame_convention():
    uv = project(np.array([[0.0, 0.0, 2.0], [1.0, 0.5, 2.0], [0.0, 0.0, -1.0]]), 1000.0, (960, 540))
    np.testing.assert_allclose(uv[0], [960, 540])
    np.testing.assert_allclose(uv[1], [1460, 790])  # x right, y down
    assert np.isnan(uv[2]).all()  # behind the camera


def test_projection_jacobian_matches_finite_differences():
    rng = np.random.default_rng(0)
    p = rng.normal(size=(5, 3)) + [0, 0, 4]
    jac = projection_jacobian(p, 1200.0)
    eps = 1e-7
    for k in range(3):
        dp = p.copy()
        dp[:, k] += eps
        fd = (project(dp, 1200.0, (0, 0)) - project(p, 1200.0, (0, 0))) / eps
        np.testing.assert_allclose(jac[:, :, k], fd, rtol=1e-5, atol=1e-3)


def test_look_at_world_up_is_image_up():
    cam = look_at([5.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    head, feet = cam.to_camera(np.array([[0, 0, 1.7], [0, 0, 0.0]]))
    assert head[1] < feet[1]  # y down: the head is higher in the image
    assert head[2] == pytest.approx(5.0)
    np.testing.assert_allclose(cam.to_world(cam.to_camera(np.eye(3))), np.eye(3), atol=1e-12)
    front = orbit_camera(4.0, 0.0, 0.0)
    left, right = front.to_camera(np.array([[0, 0.2, 1.0], [0, -0.2, 1.0]]))
    assert left[0] > right[0]  # seen from the front, the dancer's left is on the image's right
    with pytest.raises(HDVRError):
        look_at([0, 0, 1], [0, 0, 1])


def test_default_intrinsics():
    k = Intrinsics.default_for(1920, 1080)
    assert k.principal_point == (960, 540) and 1500 < k.focal < 2000
    assert k.matrix()[0, 0] == k.focal
