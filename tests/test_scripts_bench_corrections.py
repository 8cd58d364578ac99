"""scripts/bench_corrections.py: the simulated user's choice of corrections and the summary table."""

from types import SimpleNamespace

import numpy as np
from script_loader import load_script


def _swap_clip():
    """Two dancers 20 frames long whose tracked boxes swap at frame 8 (an identity switch) and a third box that
    slips off its dancer for 3 frames only."""
    t = np.arange(20, dtype=float)
    gt = np.zeros((20, 3, 4))
    gt[:, 0] = np.stack([100 + 2 * t, np.full(20, 50.0), np.full(20, 40.0), np.full(20, 100.0)], axis=1)
    gt[:, 1] = np.stack([300 - 2 * t, np.full(20, 50.0), np.full(20, 40.0), np.full(20, 100.0)], axis=1)
    gt[:, 2] = [500.0, 200.0, 40.0, 100.0]
    boxes = gt.copy()
    boxes[8:, 0], boxes[8:, 1] = gt[8:, 1], gt[8:, 0]
    boxes[3:6, 2, 0] += 60  # a short slip: left alone
    return gt, boxes


def test_wrong_frames_keep_only_long_stretches():
    bc = load_script("bench_corrections")
    gt, boxes = _swap_clip()
    wrong = bc.wrong_frames(gt, boxes, min_stretch=5)
    assert wrong[:, :2].sum(axis=0).tolist() == [12, 12] and wrong[8:, :2].all()
    assert not wrong[:, 2].any()
    assert bc.wrong_frames(gt, boxes, min_stretch=3)[3:6, 2].all()
    missing = boxes.copy()
    missing[:, 2] = np.nan  # a dancer there without a box is wrong too
    assert bc.wrong_frames(gt, missing, min_stretch=5)[:, 2].all()


def test_next_corrections_fix_both_dancers_of_a_switch_where_they_are_seen():
    bc = load_script("bench_corrections")
    gt, boxes = _swap_clip()
    shown = np.ones((20, 3))
    fixes, swaps = bc.next_corrections(gt, boxes, shown, min_stretch=5)
    assert [(t, j) for t, j, _ in fixes] == [(8, 0), (8, 1)] and swaps == []
    np.testing.assert_allclose(fixes[0][2], gt[8, 0])
    # a user who swaps: one swap instead of two boxes
    assert bc.next_corrections(gt, boxes, shown, min_stretch=5, swaps=True) == ([], [(8, 0, 1)])
    shown[8:11, 0] = 0.1  # dancer 0 hidden for 3 frames after the switch: only dancer 1 corrected then
    fixes, swaps = bc.next_corrections(gt, boxes, shown, min_stretch=5, min_visible=0.5, swaps=True)
    assert [(t, j) for t, j, _ in fixes] == [(8, 1)] and swaps == []
    assert bc.next_corrections(gt, gt, shown) == ([], [])


def test_summary_counts_the_clips_passing_after_each_number_of_corrections():
    bc = load_script("bench_corrections")
    per_clip = {
        "1:2": {"rounds": [{"idf1": 0.8, "switches": 0, "corrections": 0}, {"idf1": 0.95, "switches": 0,
                                                                            "corrections": 2}], "passes": True},
        "3:4": {"rounds": [{"idf1": 0.7, "switches": 1, "corrections": 0}], "passes": False},
        "5:0": {"rounds": [{"idf1": 1.0, "switches": 0, "corrections": 0}], "passes": True},
    }
    lines = bc.summary(per_clip, SimpleNamespace(min_stretch=10, min_visible=0.5), 60.0)
    assert lines[0].startswith("3 clips, 2 failing without corrections")
    assert "| <= 0 | 0 of 2 | 0.7500 |" in lines and "| <= 1 | 0 of 2 | 0.7500 |" in lines
    assert "| <= 2 | 1 of 2 | 0.8250 |" in lines
    assert lines[-1] == "Not mended: 3:4"


def test_the_user_clicks_on_the_visible_keypoint_nearest_the_middle_of_the_body():
    bc = load_script("bench_corrections")
    kp = np.zeros((25, 3))
    kp[[1, 8, 11], :2] = [(100.0, 50.0), (100.0, 110.0), (100.0, 250.0)]  # neck, mid-hip, ankle
    kp[[1, 8, 11], 2] = 1.0
    assert bc.click_point(kp) == (100.0, 110.0)  # the mid-hip: nearest the mean (100, 136.7)
    kp[8, 2] = 0.0  # the hip hidden, a knee seen: the knee, nearest the mean (100, 170)
    kp[10] = (100.0, 200.0, 1.0)
    kp[11, :2] = (100.0, 260.0)
    assert bc.click_point(kp) == (100.0, 200.0)
    assert bc.click_point(np.zeros((25, 3))) is None
