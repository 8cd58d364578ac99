import os

import numpy as np

from hdvr.camera import project
from hdvr.skeleton import Skeleton
from hdvr.synth.render import (OCCLUDED, OUTSIDE, VISIBLE, keypoint_boxes, keypoint_visibility,
                               random_camera_path)

os.environ.setdefault("MUJOCO_GL", "egl")


def test_camera_path_looks_at_the_dancers_and_shakes_smoothly():
    rng = np.random.default_rng(0)
    xy = np.zeros((60, 2, 2))
    xy[:, 1] = [1.2, 0.0]
    cam = random_camera_path(rng, xy, 60, 30.0)
    assert np.allclose(np.einsum("tij,tkj->tik", cam.rotation, cam.rotation), np.eye(3), atol=1e-9)
    centre = np.array([0.6, 0.0, 1.0])
    p = cam.to_camera(np.broadcast_to(centre, (60, 3)))
    assert (p[:, 2] > 2.5).all()  # in front of the camera
    uv = project(p, cam.intrinsics.focal, cam.intrinsics.principal_point)
    assert (np.abs(uv - [320, 240]) < [200, 200]).all()
    assert np.linalg.norm(np.diff(cam.centre, axis=0), axis=1).max() < 0.02  # hand-held, not jumping


def test_rendered_segmentation_agrees_with_projected_keypoints():
    import mujoco

    from hdvr.synth.render import SceneRenderer
    from hdvr.synth.scene import build_scene_xml, random_looks, random_stage

    rng = np.random.default_rng(3)
    sk = Skeleton()
    q0, q1 = sk.rest_qpos(), sk.rest_qpos()
    q1[:2] = [2.0, 0.0]  # dancer 1 stands 2 m behind dancer 0 on the camera's axis: occluded
    model = mujoco.MjModel.from_xml_string(build_scene_xml([1.7, 1.7], random_looks(rng, 2), random_stage(rng)))
    renderer = SceneRenderer(model, 2, (320, 240))
    try:
        from hdvr.camera import Intrinsics, look_at

        ext = look_at([-4.0, 0.0, 1.0], [0.0, 0.0, 1.0])
        intr = Intrinsics.default_for(320, 240, 50)
        renderer.set_camera(ext.rotation, ext.centre, intr)
        image, dancer_map = renderer.render(np.r_[q0, q1])
    finally:
        renderer.close()
    assert image.shape == (240, 320, 3) and dancer_map.shape == (120, 160)
    kp0, kp1 = ext.to_camera(sk.keypoints(q0)), ext.to_camera(sk.keypoints(q1))
    uv0, vis0 = keypoint_visibility(kp0, dancer_map, 0, intr, (320, 240))
    uv1, vis1 = keypoint_visibility(kp1, dancer_map, 1, intr, (320, 240))
    from hdvr.layouts import BODY25_NAMES
    torso = [BODY25_NAMES.index(n) for n in ("neck", "mid_hip")]
    assert (vis0[torso] == VISIBLE).all()  # the front dancer's trunk is seen
    assert (vis1[torso] == OCCLUDED).all()  # the dancer behind is hidden by the front one
    # a point outside the image
    far = kp0.copy()
    far[:, 0] += 100.0
    assert (keypoint_visibility(far, dancer_map, 0, intr, (320, 240))[1] == OUTSIDE).all()
    boxes = keypoint_boxes(uv0[None], kp0[None], np.array([True]), intr, (320, 240))
    x, y, w, h = boxes[0]
    assert 0 <= x and x + w <= 320 and h > 2 * w  # a standing person's box is tall
