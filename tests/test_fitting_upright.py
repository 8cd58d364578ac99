"""The trunk tilt prior (hdvr.fitting.residuals.UprightTerm) and the clip's vertical it is measured from."""

import numpy as np
import pytest

from hdvr import dh
from hdvr.camera import look_at, project
from hdvr.fitting.kinematics import DancerKinematics, quat_from_rotvec, tangent_from_qpos
from hdvr.fitting.presets import FitSettings
from hdvr.fitting.residuals import FrameProblem, UprightTerm
from hdvr.fitting.sequence import clip_vertical, fit_keypoints
from hdvr.io.keypoints2d import Keypoints2D
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import Skeleton
from numeric import numeric_jacobian

NECK, MID_HIP = BODY25_NAMES.index("neck"), BODY25_NAMES.index("mid_hip")


@pytest.fixture(scope="module")
def kin():
    return DancerKinematics(Skeleton())


def _frame_problem(kin, robust):
    rng = np.random.default_rng(4)
    q = kin.skeleton.random_qpos(rng, 0.05)
    q[:3] = [0.1, -0.2, 4.0]
    q[3:7] = quat_from_rotvec(np.array([1.7, 0.4, -0.3]))
    kp = kin.keypoints(q)
    x, quat = tangent_from_qpos(q)
    vertical = np.array([0.05, -0.99, 0.1]) / np.linalg.norm([0.05, -0.99, 0.1])
    term = UprightTerm(vertical, 64.0, 0.5, np.sin(np.radians(30)) if robust else None)
    problem = FrameProblem(kin, quat, project(kp, 1500.0, (960.0, 540.0)), np.ones(25), 1500.0,
                           np.array([960.0, 540.0]), upright=term)
    return problem, x, kp, term


def test_upright_residual_is_the_weighted_sine_of_the_tilt_and_its_jacobian_is_exact(kin):
    problem, x, kp, term = _frame_problem(kin, robust=False)
    trunk = kp[NECK] - kp[MID_HIP]
    sine = np.linalg.norm(np.cross(trunk / np.linalg.norm(trunk), term.vertical))
    r = problem.residual_parts(x)["upright"]
    assert np.linalg.norm(r) == pytest.approx(64.0 * sine * np.linalg.norm(trunk) / 0.5, rel=1e-9)
    params = x + 0.01
    num = numeric_jacobian(lambda v: problem.residual(v)[:, 0], params)
    assert np.abs(problem.jacobian(params) - num).max() < 1e-4 * max(1.0, np.abs(num).max())


def test_robust_upright_prior_gives_way_for_large_tilts(kin):
    problem, x, kp, term = _frame_problem(kin, robust=True)
    plain = term.projector @ (kp[NECK] - kp[MID_HIP])
    s = float(plain @ plain)
    c2 = (64.0 * np.sin(np.radians(30))) ** 2
    r = problem.residual_parts(x)["upright"]
    assert float(r @ r) == pytest.approx(c2 * np.log1p(s / c2), rel=1e-9)  # Cauchy: grows as log, not squared
    assert float(r @ r) < s


def _bow_clip(seconds_upright=2.0, seconds_bow=2.0, fps=30.0, bow_deg=60.0):
    """Camera-frame BODY_25 (T, 25, 3) of a dancer facing a camera 4 m away who sways upright, then bows towards
    it (trunk flexion ramping to ``bow_deg`` and held), and its 2D keypoints (focal 1400 px, 1920x1080)."""
    sk = Skeleton()
    flex = dh.JOINT_NAMES.index("lumbar_flex")
    shoulder = dh.JOINT_NAMES.index("left_shoulder_abduct")
    n_up, n_bow = int(seconds_upright * fps), int(seconds_bow * fps)
    t = np.arange(n_up + n_bow)
    q = np.tile(sk.rest_qpos(), (len(t), 1))
    q[:, 7 + shoulder] = 0.6 + 0.4 * np.sin(t / 9.0)  # an arm moves throughout
    ramp = np.clip((t - n_up) / (0.5 * n_bow), 0.0, 1.0)
    q[:, 7 + flex] = np.radians(bow_deg) * ramp
    world = sk.keypoints(q)
    camera = look_at(np.array([4.0, 0.5, 1.3]), np.array([0.0, 0.0, 1.0]))
    cam = camera.to_camera(world)
    uv = project(cam, 1400.0, (960.0, 540.0))
    kp = Keypoints2D(np.concatenate([uv, np.ones(uv.shape[:2] + (1,))], axis=-1), BODY25_NAMES, fps, (1920, 1080))
    vertical = camera.to_camera(np.array([[0.0, 0.0, 1.0]]))[0] - camera.to_camera(np.zeros((1, 3)))[0]
    return kp, cam, vertical, n_up + n_bow // 2


def _tilt_deg(points, vertical):
    trunk = points[:, NECK] - points[:, MID_HIP]
    trunk = trunk / np.linalg.norm(trunk, axis=1, keepdims=True)
    return np.degrees(np.arccos(np.clip(trunk @ vertical, -1.0, 1.0)))


def test_clip_vertical_ignores_a_held_bow():
    kp, cam, vertical, hold = _bow_clip()
    up = clip_vertical(cam)
    assert np.degrees(np.arccos(up @ vertical)) < 3.0
    # the plain mean is pulled towards the bow
    trunk = cam[:, NECK] - cam[:, MID_HIP]
    mean = (trunk / np.linalg.norm(trunk, axis=1, keepdims=True)).mean(axis=0)
    assert np.degrees(np.arccos(mean @ vertical / np.linalg.norm(mean))) > 5.0


def test_a_deep_bow_towards_the_camera_is_kept_by_the_fit():
    kp, cam, vertical, hold = _bow_clip()
    true_tilt = _tilt_deg(cam[hold:], vertical)
    assert true_tilt.min() > 50.0
    result, _ = fit_keypoints(kp, FitSettings(focal=1400.0, workers=1))
    fitted_tilt = _tilt_deg(result.keypoints3d[hold:], vertical)
    assert np.median(np.abs(fitted_tilt - true_tilt)) < 12.0, (np.median(fitted_tilt), np.median(true_tilt))
    assert np.median(_tilt_deg(result.keypoints3d[:hold - 40], vertical)) < 12.0
