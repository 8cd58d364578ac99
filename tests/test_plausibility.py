"""Plausibility figures on poses with known answers."""

import numpy as np
import pytest

from hdvr import plausibility
from hdvr.dh import JOINT_NAMES
from hdvr.skeleton import Skeleton


@pytest.fixture(scope="module")
def skeleton():
    return Skeleton()


def test_rest_pose_is_plausible(skeleton):
    q = np.tile(skeleton.rest_qpos(), (10, 1))
    kp = skeleton.keypoints(q)
    assert plausibility.foot_penetration(kp).max() < 1e-6
    assert plausibility.self_penetration(skeleton, q).max() == 0.0
    assert plausibility.limit_violations(skeleton, q) == (0, 0.0)
    assert max(plausibility.bone_length_cv(kp).values()) < 1e-9
    assert plausibility.jitter(kp, 30.0) == pytest.approx(0.0, abs=1e-9)
    summary = plausibility.summarize(skeleton, kp, q, 30.0)
    assert summary["foot_penetration_p95_cm"] < 1e-6 and summary["limit_violations"] == 0


def test_sinking_dancer_penetrates_the_floor(skeleton):
    q = np.tile(skeleton.rest_qpos(), (4, 1))
    q[:, 2] -= np.array([0.0, 0.01, 0.02, 0.05])
    pen = plausibility.foot_penetration(skeleton.keypoints(q))
    assert pen == pytest.approx([0.0, 0.01, 0.02, 0.05], abs=1e-6)


def test_sliding_feet_in_contact_skate(skeleton):
    q = np.tile(skeleton.rest_qpos(), (5, 1))
    q[:, 0] = np.arange(5) * 0.01  # 1 cm per frame at 30 fps = 0.3 m/s
    speeds = plausibility.foot_skating(skeleton.keypoints(q), fps=30.0)
    assert len(speeds) == 4 * 6
    assert speeds == pytest.approx(0.3)
    q[:, 2] += 0.2  # in the air: no contact, no skating
    assert len(plausibility.foot_skating(skeleton.keypoints(q), fps=30.0)) == 0


def test_crossed_thighs_self_penetrate(skeleton):
    q = skeleton.rest_qpos()
    q[7 + JOINT_NAMES.index("right_hip_adduct")] = skeleton.upper[JOINT_NAMES.index("right_hip_adduct")]
    q[7 + JOINT_NAMES.index("left_hip_adduct")] = skeleton.upper[JOINT_NAMES.index("left_hip_adduct")]
    assert plausibility.self_penetration(skeleton, q[None])[0] > 0.01


def test_limit_violation_and_bone_variation_are_counted(skeleton):
    q = np.tile(skeleton.rest_qpos(), (3, 1))
    j = JOINT_NAMES.index("left_knee_flex")
    q[1, 7 + j] = skeleton.lower[j] - 0.1
    count, worst = plausibility.limit_violations(skeleton, q)
    assert count == 1 and worst == pytest.approx(0.1)
    kp = skeleton.keypoints(np.tile(skeleton.rest_qpos(), (2, 1)))
    kp[1, 3] += np.array([0.0, 0.0, -0.05])  # stretch the right upper arm
    assert plausibility.bone_length_cv(kp)["right_shoulder-right_elbow"] > 0.05
