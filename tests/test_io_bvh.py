import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.io.bvh import load_mocap_body25, read_bvh, write_dancer_bvh
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import Skeleton


@pytest.mark.shared_data
def test_every_salsa_file_reads_with_plausible_height(shared_data):
    files = sorted((shared_data / "cmu-salsa").glob("*.bvh"))
    assert len(files) == 14
    for f in files:
        motion = read_bvh(f)
        n_declared = int(next(line for line in f.read_text().splitlines() if line.startswith("Frames:")).split()[1])
        assert motion.num_frames == n_declared and motion.fps == pytest.approx(120, rel=1e-4)
        pos, fps = load_mocap_body25(f, fps=30)
        assert fps == 30 and pos.shape == (len(np.arange(0, (n_declared - 1) / motion.fps + 1e-9, 1 / 30)), 25, 3)
        assert np.isfinite(pos).all()
        # stature normalised to 1.70 m: eyes about 1.59 m above the feet when standing
        eyes = pos[:, [BODY25_NAMES.index("left_eye"), BODY25_NAMES.index("right_eye")], 2].mean(axis=1)
        feet = pos[:, [BODY25_NAMES.index("left_ankle"), BODY25_NAMES.index("right_ankle")], 2].min(axis=1)
        standing = np.median(eyes - feet)
        assert 1.35 < standing < 1.65, (f.name, standing)
        upper_arm = np.linalg.norm(pos[:, BODY25_NAMES.index("left_shoulder")] - pos[:, BODY25_NAMES.index(
            "left_elbow")], axis=-1)
        assert 0.22 < upper_arm.mean() < 0.36 and upper_arm.std() < 1e-3  # rigid bones (up to resampling)


@pytest.mark.shared_data
def test_indian_t_pose_frame_is_dropped(shared_data):
    f = shared_data / "cmu-indian" / "indian_04.bvh"
    raw = read_bvh(f)
    pos, fps = load_mocap_body25(f)
    assert pos.shape[0] == raw.num_frames - 1 and fps == pytest.approx(120, rel=1e-4)


def test_dancer_bvh_round_trip(tmp_path):
    sk = Skeleton()
    rng = np.random.default_rng(0)
    qpos = np.stack([sk.random_qpos(rng) for _ in range(6)])
    qpos[:, :3] += rng.normal(scale=0.3, size=(6, 3))
    path = tmp_path / "dance.bvh"
    write_dancer_bvh(path, sk, qpos, fps=30)
    motion = read_bvh(path)
    assert motion.num_frames == 6 and motion.fps == pytest.approx(30)
    pos = motion.positions(unit_scale=0.01)
    for t in range(6):
        sk.kinematics(qpos[t])
        for j, joint in enumerate(motion.joints):
            if joint.is_end_site:
                continue
            np.testing.assert_allclose(pos[t, j], sk.data.body(joint.name).xpos, atol=2e-5)
        tip = motion.index("left_hand_end")
        np.testing.assert_allclose(pos[t, tip], sk.data.site("left_hand_tip").xpos, atol=2e-5)


def test_bad_bvh(tmp_path):
    with pytest.raises(HDVRError, match="not found"):
        read_bvh(tmp_path / "none.bvh")
    (tmp_path / "a.bvh").write_text("HIERARCHY\nROOT hip\n{\nOFFSET 0 0 0\n")
    with pytest.raises(HDVRError, match="MOTION"):
        read_bvh(tmp_path / "a.bvh")
    (tmp_path / "b.bvh").write_text("HIERARCHY\nROOT hip\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition "
                                    "Zposition\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0\n")
    with pytest.raises(HDVRError, match="declares 2 frames"):
        read_bvh(tmp_path / "b.bvh")


@pytest.mark.shared_data
def test_heel_rides_on_the_foot(shared_data):
    """The heel keeps its distance to the ankle and rises above the toes when the foot points."""
    pos, _ = load_mocap_body25(shared_data / "cmu-salsa" / "61_01_scaled.bvh", fps=30)
    for side in ("left", "right"):
        heel, ankle, toe = (pos[:, BODY25_NAMES.index(f"{side}_{j}")] for j in ("heel", "ankle", "big_toe"))
        d = np.linalg.norm(heel - ankle, axis=-1)
        assert d.std() < 1e-3 and 0.03 < d.mean() < 0.15  # rigid (up to 120 -> 30 fps resampling)
        lift = heel[:, 2] - toe[:, 2]
        assert lift.max() > 0.03  # on the balls of the feet at some point
