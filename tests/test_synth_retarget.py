import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.skeleton import Skeleton
from hdvr.synth.retarget import bone_lengths_from_body25, retarget, stature_from_body25


def test_retarget_recovers_the_dancers_own_motion():
    from hdvr.synth.choreography import ChoreographyGenerator

    chor = ChoreographyGenerator().generate("flamenco", 2, np.random.default_rng(0))
    sk = Skeleton()
    qpos, info = retarget(chor.keypoints, sk)
    assert info["mean_error_m"] < 0.01
    assert sk.limit_violation(qpos).max() == 0
    assert abs(stature_from_body25(chor.keypoints) - 1.70) < 0.05
    assert np.allclose(bone_lengths_from_body25(chor.keypoints)[[3, 4, 6, 7]], sk.bone_lengths[[3, 4, 6, 7]],
                       atol=0.01)


def test_retarget_rejects_bad_input():
    with pytest.raises(HDVRError, match="BODY_25"):
        retarget(np.zeros((4, 17, 3)))
    with pytest.raises(HDVRError, match="NaN"):
        retarget(np.full((4, 25, 3), np.nan))


@pytest.mark.shared_data
def test_salsa_couple_clip(shared_data, tmp_path):
    from hdvr.commands.synth import mocap_groups
    from hdvr.synth.groundtruth import ClipSpec, make_clip, mocap_motion

    groups = mocap_groups(shared_data / "cmu-salsa")
    assert len(groups) == 7 and all(len(g) == 2 for g in groups)  # 60_XX lead + 61_XX follow
    spec = ClipSpec(0, 0, "salsa", 2, 1.0, prefix="mocap")
    motion = mocap_motion(spec, groups[0])
    meta = make_clip(tmp_path, spec, render=False, motion=motion)
    assert meta["n_dancers"] == 2 and meta["joint_limit_violation_rad"] < 1e-9
    assert meta["foot_penetration_m"] <= 0.01
    gt = np.load(tmp_path / "mocap_00000" / "gt.npz")
    assert int(gt["genre_index"]) == -1 and gt["labels"].shape == (2, 30, 16)
    # the two dancers keep the take's shared world frame: partners stay within arm's reach
    gap = np.linalg.norm(gt["keypoints3d_world"][0, :, 8, :2] - gt["keypoints3d_world"][1, :, 8, :2], axis=-1)
    assert gap.max() < 2.0
