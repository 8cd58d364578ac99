"""The MJCF encodes the paper's DH table: structure, bounds, FK equivalence, bone lengths, simulation."""

import mujoco
import numpy as np
import pytest

from hdvr import dh
from hdvr.dancer_model import build_mjcf
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import MODEL_PATH, Skeleton


@pytest.fixture(scope="module")
def sk():
    return Skeleton()


def test_model_file_is_generated_from_code():
    assert MODEL_PATH.read_text() == build_mjcf(), "run scripts/build_dancer_model.py"


def test_structure(sk):
    m = sk.model
    types = [m.jnt_type[j] for j in range(m.njnt)]
    assert types.count(mujoco.mjtJoint.mjJNT_HINGE) == 34 and types.count(mujoco.mjtJoint.mjJNT_FREE) == 1
    assert m.nq == 41 and m.nv == 40
    names = [m.site(i).name for i in sk.keypoint_site_ids]
    assert names == list(BODY25_NAMES)


def test_dm_control_loads_model():
    from dm_control import mjcf

    root = mjcf.from_path(str(MODEL_PATH))
    assert len(root.find_all("joint")) == 35
    physics = mjcf.Physics.from_mjcf_model(root)
    assert physics.model.nq == 41


def test_bounded_ranges_equal_the_paper_table(sk):
    for j in dh.JOINTS:
        lo, hi = sk.model.jnt_range[sk.hinge_joint_ids[j.row]]
        if j.theta_index in dh.PAPER_BOUNDS and j.row not in dh.ANATOMICAL_BOUNDS:
            assert (lo, hi) == pytest.approx(dh.PAPER_BOUNDS[j.theta_index], abs=1e-8), j.name
        else:
            assert j.row in dh.ANATOMICAL_BOUNDS and lo < 0 < hi or lo <= 0 <= hi
    bounded_rows = [j.row for j in dh.JOINTS if j.row not in dh.ANATOMICAL_BOUNDS]
    assert {dh.JOINTS[r].theta_index for r in bounded_rows} == set(dh.PAPER_BOUNDS)


def test_rest_pose_within_bounds_and_standing(sk):
    q = sk.rest_qpos()
    assert (sk.limit_violation(q) == 0).all()
    kp = sk.keypoints(q)
    z = kp[:, 2]
    assert z.min() == pytest.approx(0.0, abs=1e-9)  # soles on the floor
    assert z[BODY25_NAMES.index("nose")] > z[BODY25_NAMES.index("neck")] > z[BODY25_NAMES.index("mid_hip")]
    left, right = BODY25_NAMES.index("left_shoulder"), BODY25_NAMES.index("right_shoulder")
    assert kp[left, 1] > 0 > kp[right, 1]  # y is the dancer's left
    assert kp[BODY25_NAMES.index("nose"), 0] > 0  # faces +x


def test_dh_fk_equals_mujoco_fk(sk):
    rng = np.random.default_rng(0)
    bones = sk.bone_lengths
    for _ in range(25):
        q = sk.random_qpos(rng)
        q[:3] = rng.normal(size=3)
        quat = rng.normal(size=4)
        q[3:7] = quat / np.linalg.norm(quat)
        root = np.eye(4)
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, q[3:7])
        root[:3, :3] = rot.reshape(3, 3)
        root[:3, 3] = q[:3]
        ref = dh.forward_kinematics(q[7:], bones, root)
        anchors, axes = sk.hinge_anchors_and_axes(q)
        np.testing.assert_allclose(anchors, ref["hinge_pos"], atol=1e-6)
        np.testing.assert_allclose(axes, ref["hinge_axis"], atol=1e-6)
        # chain ends: frames after the last row of the head, hands and toes
        ends = sk.site_positions(q, ["nose", "left_hand_tip", "right_hand_tip", "right_toe_tip", "left_toe_tip"])
        np.testing.assert_allclose(ends, ref["frames"][[8, 14, 20, 27, 34], :3, 3], atol=1e-6)


def test_mirror_symmetry(sk):
    """Equal angles on both sides give mirror-image limbs (reflection through the sagittal plane y = 0)."""
    rng = np.random.default_rng(1)
    q = sk.rest_qpos()
    q[7:] = 0.0
    arm = rng.uniform(sk.lower[8:14], sk.upper[8:14])
    leg = rng.uniform(sk.lower[20:27], sk.upper[20:27])
    q[7 + 8:7 + 14] = arm
    q[7 + 14:7 + 20] = arm
    q[7 + 20:7 + 27] = leg
    q[7 + 27:7 + 34] = leg
    kp = sk.keypoints(q)
    for name in BODY25_NAMES:
        if name.startswith("left_"):
            mirrored = kp[BODY25_NAMES.index(name.replace("left_", "right_"))] * np.array([1, -1, 1])
            np.testing.assert_allclose(kp[BODY25_NAMES.index(name)], mirrored, atol=1e-9, err_msg=name)


def test_changing_a_bone_moves_descendants_by_exactly_that_length():
    sk = Skeleton()
    rng = np.random.default_rng(2)
    q = sk.random_qpos(rng)
    base = sk.keypoints(q)
    delta = 0.05
    cases = {3: ("left_elbow", "left_wrist", "right_elbow", "right_wrist"),
             6: ("left_knee", "left_ankle", "left_heel", "left_big_toe", "left_small_toe",
                 "right_knee", "right_ankle", "right_heel", "right_big_toe", "right_small_toe"),
             0: tuple(n for n in BODY25_NAMES if n in ("neck", "nose") or n.endswith(("eye", "ear", "shoulder",
                                                                                      "elbow", "wrist")))}
    for bone, moved in cases.items():
        bones = sk.bone_lengths
        bones[bone] += delta
        sk.set_bone_lengths(bones)
        shift = np.linalg.norm(sk.keypoints(q) - base, axis=-1)
        for i, name in enumerate(BODY25_NAMES):
            expected = delta if name in moved else 0.0
            assert shift[i] == pytest.approx(expected, abs=1e-9), (bone, name)
        bones[bone] -= delta
        sk.set_bone_lengths(bones)


def test_jacobian_matches_finite_differences(sk):
    rng = np.random.default_rng(3)
    q = sk.random_qpos(rng, margin=0.05)
    jac = sk.keypoint_jacobians(q)
    eps = 1e-6
    for col in (0, 4, 6, 15, 30, 39):
        v = np.zeros(sk.model.nv)
        v[col] = eps
        qp = q.copy()
        mujoco.mj_integratePos(sk.model, qp, v, 1.0)
        fd = (sk.keypoints(qp) - sk.keypoints(q)) / eps
        np.testing.assert_allclose(jac[:, :, col], fd, atol=1e-5)


def test_two_seconds_of_simulation_stay_finite():
    sk = Skeleton()
    d = mujoco.MjData(sk.model)
    d.qpos[:] = sk.rest_qpos()
    d.qpos[2] += 0.05
    for _ in range(int(2.0 / sk.model.opt.timestep)):
        mujoco.mj_step(sk.model, d)
    assert np.isfinite(d.qpos).all() and np.isfinite(d.qvel).all()
    assert d.qpos[2] > 0.0 and np.abs(d.qvel).max() < 100.0


def test_documented_joint_signs(sk):
    """A positive angle does what hdvr.dh.JOINTS says, measured on keypoints from the rest pose."""
    idx = {n: i for i, n in enumerate(BODY25_NAMES)}

    def moved(joint, angle, keypoint):
        q = sk.rest_qpos()
        before = sk.keypoints(q)[idx[keypoint]]
        q[7 + dh.JOINT_NAMES.index(joint)] += angle
        return sk.keypoints(q)[idx[keypoint]] - before

    assert moved("lumbar_flex", 0.3, "neck")[0] > 0.05  # forward
    assert moved("lumbar_bend", 0.3, "neck")[1] < -0.05  # to the right (-y)
    assert moved("lumbar_twist", 0.3, "left_shoulder")[0] < -0.01  # left shoulder goes back: turns left
    assert moved("left_shoulder_flex", 1.0, "left_wrist")[0] > 0.3  # arm raises forward
    assert moved("left_shoulder_abduct", 0.8, "left_wrist")[1] > 0.2  # away from the body
    assert moved("right_shoulder_abduct", 0.8, "right_wrist")[1] < -0.2
    assert moved("left_elbow_flex", -1.2, "left_wrist")[0] > 0.15  # elbow flexes forward
    assert moved("right_knee_flex", 1.0, "right_ankle")[0] < -0.15  # shank moves back
    assert moved("left_hip_extend", -1.0, "left_knee")[0] > 0.15  # negative: forward kick
    assert moved("right_hip_adduct", -0.6, "right_ankle")[1] < -0.1  # negative: abduction (outward)
    assert moved("right_ankle_plantarflex", 0.8, "right_big_toe")[2] < -0.02  # toes down
    assert moved("neck_twist", 0.5, "nose")[1] > 0.03  # head turns left
    assert moved("head_nod", 0.4, "nose")[2] < -0.02  # nods forward/down


def test_humeral_rotation_sign(sk):
    """With the elbow flexed 90 deg, a positive shoulder rotation swings the forearm toward the midline."""
    q = sk.rest_qpos()
    q[7 + dh.JOINT_NAMES.index("left_elbow_flex")] = -np.pi / 2
    q[7 + dh.JOINT_NAMES.index("right_elbow_flex")] = -np.pi / 2
    wrists = [BODY25_NAMES.index("left_wrist"), BODY25_NAMES.index("right_wrist")]
    before = sk.keypoints(q)[wrists]
    q[7 + dh.JOINT_NAMES.index("left_shoulder_rotate")] += 0.5
    q[7 + dh.JOINT_NAMES.index("right_shoulder_rotate")] += 0.5
    after = sk.keypoints(q)[wrists]
    assert after[0, 1] < before[0, 1] - 0.05 and after[1, 1] > before[1, 1] + 0.05
