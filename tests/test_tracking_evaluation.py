import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25_NAMES, COCO17_NAMES
from hdvr.tracking.evaluation import (ABSENT, MISSED, body25_joints_of, evaluate_tracking, pck, torso_diameter,
                                      track_on_truth, visible_truth_keypoints)


def _gt(frames=20):
    t = np.arange(frames)[:, None]
    a = np.hstack([10 + 5 * t, np.full_like(t, 50), np.full_like(t, 40), np.full_like(t, 100)])
    b = np.hstack([200 - 5 * t, np.full_like(t, 300), np.full_like(t, 40), np.full_like(t, 100)])
    return np.stack([a, b], axis=1).astype(float)


def test_perfect_tracks():
    gt = _gt()
    s = evaluate_tracking(gt, gt.copy())
    assert s.mota == pytest.approx(1.0) and s.idf1 == pytest.approx(1.0) and s.hota == pytest.approx(1.0)
    assert s.id_switches == 0


def test_identity_swap_counts():
    gt = _gt()
    swapped = gt.copy()
    swapped[10:] = swapped[10:, ::-1]
    s = evaluate_tracking(gt, swapped)
    assert s.id_switches == 2
    assert s.idf1 == pytest.approx(0.5)
    assert s.hota < 0.8


def test_missing_boxes_lower_recall():
    gt = _gt()
    pred = gt.copy()
    pred[:5, 0] = np.nan
    s = evaluate_tracking(gt, pred)
    assert s.recall == pytest.approx(35 / 40)
    assert s.precision == pytest.approx(1.0)


def test_shape_mismatch():
    with pytest.raises(HDVRError):
        evaluate_tracking(_gt(10), _gt(12))


def test_pck():
    rng = np.random.default_rng(0)
    truth = rng.uniform(100, 300, (10, 25, 3))
    truth[..., 2] = 1
    ref = torso_diameter(truth)
    pred = truth.copy()
    assert pck(pred, truth) == 1.0
    pred[:, 0, :2] += (0.3 * ref)[:, None]  # nose off by 0.42 x torso: wrong
    assert pck(pred, truth) == pytest.approx(24 / 25)
    pred[:, 1, 2] = 0  # a joint the prediction misses counts as wrong
    assert pck(pred, truth) == pytest.approx(23 / 25)
    truth2 = truth.copy()
    truth2[:, 1, :] = np.nan  # a joint the truth lacks does not count
    assert pck(pred, truth2) == pytest.approx(23 / 24)


def test_pck_scores_visible_synthetic_keypoints_only():
    """gt.npz layout (N, T, 25, 2) + visibility: hidden (1) and outside (0) keypoints do not count."""
    rng = np.random.default_rng(1)
    kp = rng.uniform(100, 300, (2, 6, 25, 2))
    vis = np.full((2, 6, 25), 2, np.int8)
    vis[0, :, 4] = 1  # dancer 0's right wrist hidden by dancer 1
    vis[1, :, 7] = 0  # dancer 1's left wrist outside the image
    truth = visible_truth_keypoints(kp, vis)
    assert truth.shape == (6, 2, 25, 3)
    pred = truth.copy()
    pred[..., 2] = 1
    pred[:, 0, 4, :2] += 1000  # wrong where hidden: not scored
    pred[:, 1, 7, :2] += 1000
    assert pck(pred[:, 0], truth[:, 0]) == 1.0
    assert pck(pred[:, 1], truth[:, 1]) == 1.0
    pred[:, 0, 3, :2] += 1000  # wrong where visible: scored
    assert pck(pred[:, 0], truth[:, 0]) == pytest.approx(23 / 24)
    with pytest.raises(HDVRError):
        visible_truth_keypoints(kp, vis[0])


def test_pck_on_the_joints_a_coco_detector_gives():
    joints = body25_joints_of(COCO17_NAMES)
    names = {BODY25_NAMES[j] for j in joints}
    assert len(joints) == 19 and {"neck", "mid_hip", "left_ankle", "nose"} <= names
    assert not names & {"left_big_toe", "right_heel"}
    assert len(body25_joints_of(BODY25_NAMES)) == 25
    rng = np.random.default_rng(2)
    truth = rng.uniform(100, 300, (4, 25, 3))
    truth[..., 2] = 1
    pred = truth.copy()
    pred[:, [j for j in range(25) if j not in joints], 2] = 0  # feet missing, as from a COCO-17 detector
    assert pck(pred, truth) == pytest.approx(19 / 25)
    assert pck(pred, truth, joints=joints) == 1.0


def test_miss_causes_name_where_each_dancer_frame_goes_unmatched():
    """Frame by frame: matched; both on the other dancer (swapped boxes); dancer 0 at a third of its width
    (IoU 1/3: extent); dancer 0 far away; dancer 1 without a box. Visibility classes come from the seen
    fraction: dancer 0 visible, dancer 1 partly seen, then hidden."""
    from hdvr.tracking.evaluation import MISS_CAUSES, miss_causes

    gt = _gt(5)
    tracked = gt.copy()
    tracked[1] = gt[1, ::-1]
    tracked[2, 0, 2] = gt[2, 0, 2] / 3
    tracked[3, 0, :2] += 500
    tracked[4, 1] = np.nan
    seen = np.full((5, 2), 1.0)
    seen[:, 1] = 0.5
    seen[4, 1] = 0.1
    counts = miss_causes(gt, tracked, seen)
    expected = {("visible", "matched"): 2, ("visible", "other_dancer"): 1, ("visible", "extent"): 1,
                ("visible", "elsewhere"): 1, ("partly", "matched"): 3, ("partly", "other_dancer"): 1,
                ("hidden", "no_box"): 1}
    assert {k: v for k, v in counts.items() if v} == expected
    assert set(c for _, c in counts) == set(MISS_CAUSES)
    with pytest.raises(HDVRError, match="seen fractions"):
        miss_causes(gt, tracked, seen[:, :1])


def test_track_on_truth_names_the_track_on_each_true_dancer_per_frame():
    gt = np.array([[[0, 0, 10, 20], [50, 0, 10, 20]]] * 6, float)
    tracks = gt.copy()
    tracks[3:] = tracks[3:, ::-1]  # ids exchanged from frame 3
    tracks[1, 0] = [4, 0, 10, 20]  # IoU 6/14 with dancer 0: no match at 0.5
    gt[5, 1] = np.nan  # dancer 1 leaves
    owner, best = track_on_truth(gt, tracks)
    np.testing.assert_array_equal(owner[:, 0], [0, MISSED, 0, 1, 1, 1])
    np.testing.assert_array_equal(owner[:, 1], [1, 1, 1, 0, 0, ABSENT])
    assert best[1, 0] == pytest.approx(6 / 14) and np.isnan(best[5, 1]) and best[0, 0] == 1
    with pytest.raises(HDVRError, match="same frames"):
        track_on_truth(gt, tracks[:4])
