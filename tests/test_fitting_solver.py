"""The projected Levenberg-Marquardt solver and one frame's fit on the real dancer."""

import numpy as np

from hdvr.camera import project
from hdvr.fitting.kinematics import DancerKinematics, qpos_from_tangent, quat_from_rotvec, tangent_from_qpos
from hdvr.fitting.residuals import FrameProblem
from hdvr.fitting.solver import parameter_bounds, projected_lm, solve_frame
from hdvr.skeleton import Skeleton


def test_projected_lm_respects_bounds():
    target = np.array([2.0, -3.0, 0.5])
    x, cost, _ = projected_lm(lambda v: v - target, lambda v: np.eye(3), np.zeros(3), -np.ones(3), np.ones(3),
                              max_iter=20, tolerance=1e-12)
    assert np.allclose(x, [1.0, -1.0, 0.5], atol=1e-6)


def test_frame_fit_recovers_a_pose_from_a_nearby_start():
    sk = Skeleton()
    kin = DancerKinematics(sk)
    rng = np.random.default_rng(0)
    q = sk.random_qpos(rng, 0.2)
    q[:3] = [0.1, 0.0, 4.0]
    q[3:7] = quat_from_rotvec(np.array([1.6, 0.2, 0.1]))
    obs = project(kin.keypoints(q), 1500.0, (960.0, 540.0))
    x, quat = tangent_from_qpos(q)
    start = x + rng.normal(0, 0.03, 40)
    problem = FrameProblem(kin, quat, obs, np.ones(25), 1500.0, np.array([960.0, 540.0]))
    bounds = parameter_bounds(problem, sk.lower, sk.upper, True)
    sol = solve_frame(problem, start, bounds, max_iter=30, tolerance=1e-10)
    assert problem.reprojection_error_px(sol.params) < 0.5
    fitted = qpos_from_tangent(sol.params, quat)
    assert np.all(sk.limit_violation(fitted) == 0)
    err = np.linalg.norm(kin.keypoints(fitted) - kin.keypoints(q), axis=1)
    assert np.median(err) < 0.03
