"""VideoPose3D metric definitions on known transforms."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hdvr import metrics
from hdvr.errors import HDVRError


@pytest.fixture
def poses():
    rng = np.random.default_rng(0)
    return rng.normal(0, 0.3, (20, 14, 3))


def test_identical_poses_have_zero_error(poses):
    assert metrics.mpjpe(poses, poses) == 0.0
    assert metrics.p_mpjpe(poses, poses) < 1e-9
    assert metrics.mpjve(poses, poses) == 0.0
    assert metrics.acceleration_error(poses, poses) == 0.0


def test_mpjpe_is_mean_distance_in_mm(poses):
    shifted = poses + np.array([0.003, 0.004, 0.0])  # 5 mm everywhere
    assert metrics.mpjpe(shifted, poses) == pytest.approx(5.0)
    assert metrics.mpjve(shifted, poses) == pytest.approx(0.0, abs=1e-9)  # constant offset: same velocities


def test_p_mpjpe_removes_similarity_but_not_reflection(poses):
    rot = Rotation.from_euler("xyz", [0.3, -0.5, 1.1]).as_matrix()
    moved = 1.7 * poses @ rot.T + np.array([1.0, -2.0, 0.5])
    assert metrics.mpjpe(moved, poses) > 100
    assert metrics.p_mpjpe(moved, poses) == pytest.approx(0.0, abs=1e-6)
    mirrored = poses * np.array([-1.0, 1.0, 1.0])
    assert metrics.p_mpjpe(mirrored, poses) > 10  # a reflection is not a rotation


def test_n_mpjpe_removes_scale_only(poses):
    assert metrics.n_mpjpe(0.8 * poses, poses) == pytest.approx(0.0, abs=1e-9)
    rot = Rotation.from_euler("z", 0.5).as_matrix()
    assert metrics.n_mpjpe(poses @ rot.T, poses) > 10


def test_acceleration_error_sees_jitter(poses):
    still = np.repeat(poses[:1], 10, axis=0)
    jitter = still.copy()
    jitter[5] += 0.01
    assert metrics.acceleration_error(jitter, still) > 0
    assert metrics.mpjve(jitter, still) == pytest.approx(10.0 * np.sqrt(3) * 2 / 9)


def test_evaluate_uses_eval_joints_root_relative():
    rng = np.random.default_rng(1)
    gt = rng.normal(0, 0.3, (5, 25, 3))
    out = metrics.evaluate(gt + np.array([2.0, 0.0, 0.0]), gt)  # global translation only
    assert out["mpjpe_mm"] == pytest.approx(0.0, abs=1e-9)
    assert set(out) == {"mpjpe_mm", "p_mpjpe_mm", "n_mpjpe_mm", "mpjve_mm", "accel_error_mm"}


def test_shape_mismatch_is_one_line_error():
    with pytest.raises(HDVRError):
        metrics.mpjpe(np.zeros((2, 3, 3)), np.zeros((2, 4, 3)))


def test_frames_without_a_pose_are_left_out_and_no_velocity_spans_them():
    rng = np.random.default_rng(3)
    gt = rng.normal(0, 0.3, (8, 25, 3))
    pred = gt + rng.normal(0, 0.02, gt.shape)
    pred[3] = np.nan
    scored = metrics.scored_frames(pred, gt)
    assert scored.tolist() == [True] * 3 + [False] + [True] * 4
    full = metrics.evaluate(pred, gt)
    kept = metrics.evaluate(pred[scored], gt[scored])
    for key in ("mpjpe_mm", "p_mpjpe_mm", "n_mpjpe_mm"):
        assert full[key] == pytest.approx(kept[key])
    # velocity: the 5 pairs of neighbouring scored frames, not the pair (2, 4) that dropping frame 3 would make
    assert full["mpjve_mm"] != pytest.approx(kept["mpjve_mm"])
    pairs = [(t, t + 1) for t in range(7) if scored[t] and scored[t + 1]]
    p, g = metrics.root_relative(pred), metrics.root_relative(gt)
    expected = np.mean([np.linalg.norm((p[b] - p[a]) - (g[b] - g[a]), axis=-1).mean() for a, b in pairs]) * 1000
    assert full["mpjve_mm"] == pytest.approx(expected)
