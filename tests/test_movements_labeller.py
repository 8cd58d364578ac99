import numpy as np
import pytest

from hdvr import dh
from hdvr.errors import HDVRError
from hdvr.movements.labeller import MovementLabeller, label_keypoints
from hdvr.skeleton import Skeleton

FPS = 30.0
JI = {n: i + 7 for i, n in enumerate(dh.JOINT_NAMES)}


def _motion(changes, seconds=3.0, sk=None):
    """Rest pose; ``changes`` = {joint: (start_s, end_s, delta_rad)} linear ramps."""
    sk = sk or Skeleton()
    T = int(seconds * FPS)
    q = np.tile(sk.rest_qpos(), (T, 1))
    t = np.arange(T) / FPS
    for joint, (a, b, delta) in changes.items():
        q[:, JI[joint]] += delta * np.clip((t - a) / (b - a), 0, 1)
    return sk.keypoints(q)


def _names(labels, part, frames):
    return set(labels.names(part)[frames])


def test_still_and_head_turn():
    kp = _motion({"neck_twist": (1.0, 1.5, 0.8)})
    lab = label_keypoints(kp, FPS)
    head = lab.names("head")
    assert head[10] == "Head Keeping Still" and head[80] == "Head Keeping Still"
    assert head[37] == "Head Turning Left"
    assert set(lab.names("torso")) == {"Torso Keeping Still"}
    assert set(lab.names("left_foot")) == {"Left Foot Relaxed"}


def test_arm_raise_sideways_and_hold_high():
    kp = _motion({"left_shoulder_abduct": (0.5, 1.3, 1.65)})
    names = label_keypoints(kp, FPS).names("left_upper_arm")
    assert names[20] == "Left Upper Arm Moving Left"  # first half of a side raise: the elbow moves out
    assert names[35] == "Left Upper Arm Moving Upward"  # second half: it rises
    assert names[80] == "Left Upper Arm Holding High"
    assert set(label_keypoints(kp, FPS).names("right_upper_arm")) == {"Right Upper Arm Keeping Still"}


def test_frame_and_stature_invariance():
    sk = Skeleton(height_m=1.55)
    kp = _motion({"lumbar_flex": (0.5, 1.0, 0.35), "right_knee_flex": (1.5, 2.0, 1.0)}, sk=sk)
    world = label_keypoints(kp, FPS).ids
    # the same motion seen from a camera: P_cam = R (P - C), up = -y of a level camera
    rot = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])  # looks along +x... any rotation
    cam = (kp - np.array([-4.0, 0.5, 1.2])) @ rot.T
    up_cam = rot @ np.array([0.0, 0.0, 1.0])
    assert np.array_equal(label_keypoints(cam, FPS, up=up_cam).ids, world)
    names = label_keypoints(kp, FPS).names("torso")
    assert names[22] == "Torso Bending"
    assert label_keypoints(kp, FPS).names("right_lower_leg")[52] == "Right Lower Leg Moving Backward"


def test_missing_keypoints_are_unknown_and_bad_input():
    kp = _motion({})
    kp[30:40, 7] = np.nan  # left wrist
    lab = label_keypoints(kp, FPS)
    assert set(lab.names("left_lower_arm")[30:40]) == {"Unknown"}
    assert lab.names("left_upper_arm")[35] == "Left Upper Arm Keeping Still"
    with pytest.raises(HDVRError, match="BODY_25"):
        label_keypoints(np.zeros((10, 17, 3)), FPS)
    with pytest.raises(HDVRError, match="missing"):
        label_keypoints(np.full((10, 25, 3), np.nan), FPS)
    with pytest.raises(HDVRError, match="fps"):
        label_keypoints(kp, 0.0)


def test_circling_and_jitter_patterns():
    sk = Skeleton()
    T = int(4 * FPS)
    q = np.tile(sk.rest_qpos(), (T, 1))
    t = np.arange(T) / FPS
    env = np.clip(t / 0.3, 0, 1) * np.clip((4 - t) / 0.3, 0, 1)
    q[:, JI["neck_twist"]] = 0.35 * env * np.sin(2 * np.pi * 1.2 * t)
    q[:, JI["head_nod"]] = 0.3 * env * np.cos(2 * np.pi * 1.2 * t) - 0.3 * env
    rng = np.random.default_rng(0)
    q[:, JI["lumbar_twist"]] = 0.06 * env * sum(np.sin(2 * np.pi * rng.uniform(4, 5) * t + rng.uniform(0, 6))
                                                for _ in range(2)) / 1.6
    lab = label_keypoints(sk.keypoints(q), FPS)
    assert lab.names("head")[40:80].count("Head Circling") == 40
    torso = [n for n in lab.names("torso")[20:100] if n != "Torso Keeping Still"]  # beats of the two sines rest
    assert len(torso) > 40 and torso.count("Unknown") >= 0.9 * len(torso)


def test_segments_and_multi_hot():
    kp = _motion({"neck_bend": (1.0, 1.4, -0.5)})
    lab = MovementLabeller().label(kp, FPS)
    segs = [s for s in lab.segments() if s["part"] == "neck"]
    assert [s["label"] for s in segs] == ["Neck Keeping Still", "Neck Moving Left", "Neck Keeping Still"]
    assert segs[0]["start"] == 0 and segs[-1]["end"] == kp.shape[0]
    assert lab.multi_hot().sum(1).tolist() == [16] * kp.shape[0]


@pytest.mark.shared_data
def test_salsa_mocap_labels(shared_data):
    from hdvr.io.bvh import load_mocap_body25

    kp, fps = load_mocap_body25(shared_data / "cmu-salsa" / "60_01_scaled.bvh", fps=30)
    lab = label_keypoints(kp, fps)
    hips = lab.names("hips")
    # a salsa lead turns and steps: the hips are not still most of the time, the feet stay on the floor
    assert hips.count("Hips Keeping Still") < 0.5 * len(hips)
    assert "Hips Turning" in hips
    legs = lab.names("left_upper_leg")
    assert sum(n.startswith("Left Upper Leg Moving") or n.endswith("Swinging") for n in legs) > 0.3 * len(legs)
