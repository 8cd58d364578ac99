"""The forward model and the frame residuals: analytic Jacobians against finite differences."""

import numpy as np
import pytest

from hdvr.camera import project
from hdvr.fitting.kinematics import DancerKinematics, qpos_from_tangent, quat_from_rotvec, tangent_from_qpos
from hdvr.fitting.residuals import FloorTerms, FrameProblem, LinearTerm, collapse_terms
from hdvr.skeleton import Skeleton
from numeric import numeric_jacobian


@pytest.fixture(scope="module")
def kin():
    return DancerKinematics(Skeleton())


def _pose(kin, seed=0):
    rng = np.random.default_rng(seed)
    q = kin.skeleton.random_qpos(rng, 0.05)
    q[:3] = [0.2, -0.1, 4.0]
    q[3:7] = quat_from_rotvec(np.array([1.9, 0.3, -0.2]))
    return q


def test_tangent_round_trip(kin):
    q = _pose(kin)
    x, quat = tangent_from_qpos(q)
    assert np.allclose(qpos_from_tangent(x, quat), q)


def test_keypoint_jacobian_matches_finite_differences(kin):
    q = _pose(kin)
    x, quat = tangent_from_qpos(q)
    x[3:6] = [0.2, -0.1, 0.3]  # non-zero rotation increment exercises the SO(3) right Jacobian
    _, jac = kin.keypoints_and_jacobian(qpos_from_tangent(x, quat), x[3:6])
    num = numeric_jacobian(lambda v: kin.keypoints(qpos_from_tangent(v, quat)), x)
    assert np.abs(jac - num).max() < 1e-6


def test_bone_offsets_are_linear_and_bone_jacobian_is_exact(kin):
    q = _pose(kin, 1)
    bones = kin.bone_lengths
    kin.keypoints_and_jacobian(q)
    jac = kin.bone_jacobian()

    def kp_of(b):
        kin.set_bone_lengths(b)
        return kin.keypoints(q)

    num = numeric_jacobian(kp_of, bones, eps=1e-4)
    kin.set_bone_lengths(bones)
    assert np.abs(jac - num).max() < 1e-7


def test_frame_residual_jacobian_matches_finite_differences(kin):
    q = _pose(kin, 2)
    kp = kin.keypoints(q)
    obs = project(kp, 1500.0, (960.0, 540.0)) + 3.0
    x, quat = tangent_from_qpos(q)
    floor = FloorTerms(np.array([0.0, -1.0, 0.0]), -kp[:, 1].max() + 0.02, 100.0, 30.0, kp[19:25] + 0.01)
    problem = FrameProblem(kin, quat, obs, np.ones(25), 1500.0, np.array([960.0, 540.0]),
                           terms3d=[LinearTerm(1.0, -kp * 0.98, 5.0), LinearTerm(-2.0, kp, 3.0)],
                           terms2d=[LinearTerm(1.0, -obs, 0.5)], hinge_terms=[LinearTerm(1.0, -q[7:] + 0.1, 2.0)],
                           floor=floor, estimate_focal=True, focal_prior=(np.log(1500.0), 0.5))
    params = np.concatenate([x + 0.01, [np.log(1450.0)]])
    jac = problem.jacobian(params)
    num = numeric_jacobian(lambda v: problem.residual(v)[:, 0], params)
    assert np.abs(jac - num).max() < 1e-4 * max(1.0, np.abs(jac).max())


def test_collapsed_terms_keep_the_minimiser():
    rng = np.random.default_rng(3)
    terms = [LinearTerm(c, rng.normal(size=(25, 3)), w) for c, w in ((1.0, 2.0), (-2.0, 1.0), (1.0, 0.5))]
    merged, const = collapse_terms(terms)
    p = rng.normal(size=(25, 3))
    full = sum(np.sum((t.weight * (t.coef * p + t.const)) ** 2) for t in terms)
    m = merged[0]
    assert np.sum((m.weight * (m.coef * p + m.const) * m.mask[:, None]) ** 2) + const == pytest.approx(full)


def test_pose_prior_loads_and_its_jacobian_matches_finite_differences(kin):
    from hdvr.fitting.prior import shipped_prior

    prior = shipped_prior()
    assert prior.means.shape == (prior.num_components, 34) and prior.num_components >= 2
    assert prior.sqrt_precision.shape[2] == 34 and np.all(prior.log_norm >= 0)
    q = _pose(kin, 3)
    e = prior.energies(q[7:])
    assert np.isfinite(e).all() and prior.energy(q[7:]) == e.min()
    kp = kin.keypoints(q)
    x, quat = tangent_from_qpos(q)
    problem = FrameProblem(kin, quat, project(kp, 1500.0, (960.0, 540.0)), np.ones(25), 1500.0,
                           np.array([960.0, 540.0]), pose_prior=prior.term(q[7:], 0.7))
    parts = problem.residual_parts(x)
    # the prior rows are 0.7^2 times the chosen component's energy
    assert np.isclose(np.sum(parts["pose_prior"] ** 2), 0.49 * e.min())
    params = x + 0.01
    num = numeric_jacobian(lambda v: problem.residual(v)[:, 0], params)
    assert np.abs(problem.jacobian(params) - num).max() < 1e-4 * max(1.0, np.abs(num).max())
