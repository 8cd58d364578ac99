"""``hdvr evaluate``: tracks (MOTA, IDF1, HOTA via trackeval), 2D keypoints (PCK) and 3D poses (MPJPE) against a
user's ground truth."""

import json

import numpy as np
import pytest

from hdvr.cli import main
from hdvr.commands.evaluate import load_boxes, score_keypoints, score_pose3d, score_tracks
from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
from hdvr.layouts import BODY25_NAMES
from hdvr.tracking.boxes import write_mot
from hdvr.tracking.evaluation import evaluate_tracking


def _walking_boxes(frames=40):
    """Two dancers walking apart, (T, 2, 4) px."""
    t = np.arange(frames, dtype=float)
    a = np.stack([100 + 2 * t, np.full(frames, 80.0), np.full(frames, 60.0), np.full(frames, 150.0)], axis=1)
    b = np.stack([400 - 2 * t, np.full(frames, 90.0), np.full(frames, 55.0), np.full(frames, 140.0)], axis=1)
    return np.stack([a, b], axis=1)


def test_tracks_with_a_swap_and_a_gap_score_as_trackeval_does(tmp_path, capsys):
    gt = _walking_boxes()
    tracks = gt.copy()
    tracks[20:] = tracks[20:, ::-1]  # the two ids exchanged half-way
    tracks[5:10, 0] = np.nan  # dancer 0 missed for 5 frames
    tracks = tracks[:35]  # and the tracks end 5 frames early
    write_mot(tmp_path / "gt.txt", gt)
    out = tmp_path / "run"
    write_mot(out / "tracks.mot.txt", tracks)
    expected = evaluate_tracking(gt, np.concatenate([tracks, np.full((5, 2, 4), np.nan)]))
    scores = score_tracks(tmp_path / "gt.txt", out)
    assert scores["IDSW"] == expected.id_switches == 2
    assert scores["IDF1"] == pytest.approx(expected.idf1) and scores["MOTA"] == pytest.approx(expected.mota)
    assert scores["frames"] == 40 and scores["gt_ids"] == scores["tracked_ids"] == 2
    assert scores["recall"] == pytest.approx((80 - 5 - 10) / 80)
    assert main(["evaluate", "tracks", "--gt", str(tmp_path / "gt.txt"), "--tracks", str(out), "--json",
                 str(tmp_path / "s.json")]) == 0
    assert "identity switches 2" in capsys.readouterr().out
    assert json.loads((tmp_path / "s.json").read_text())["IDSW"] == 2
    assert main(["evaluate", "tracks", "--gt", str(tmp_path / "gt.txt"), "--tracks", str(out), "--plot",
                 str(tmp_path / "cover.png")]) == 0
    assert f"wrote {tmp_path / 'cover.png'}" in capsys.readouterr().out and (tmp_path / "cover.png").stat().st_size
    assert main(["evaluate", "tracks", "--gt", str(tmp_path / "gt.txt"), "--tracks", str(out), "--plot",
                 str(tmp_path / "cover.gif")]) == 2
    err = capsys.readouterr().err
    assert "give a .png or .jpg" in err and len(err.strip().splitlines()) == 1


def test_ground_truth_from_an_hdvr_synth_gt_npz_or_its_folder(tmp_path):
    gt = _walking_boxes()
    clip = tmp_path / "clip_00000"
    clip.mkdir()
    np.savez(clip / "gt.npz", boxes=np.transpose(gt, (1, 0, 2)))
    np.testing.assert_array_equal(load_boxes(clip, ground_truth=True), gt)
    np.testing.assert_array_equal(load_boxes(clip / "gt.npz", ground_truth=True), gt)
    write_mot(tmp_path / "tracks.txt", gt[:, ::-1])  # same boxes, other ids: a perfect run
    scores = score_tracks(clip, tmp_path / "tracks.txt")
    assert scores["IDF1"] == pytest.approx(1.0) and scores["MOTA"] == pytest.approx(1.0) and scores["IDSW"] == 0


def _keypoint_file(path, keypoints):
    save_keypoints2d(path, Keypoints2D(keypoints, BODY25_NAMES, 30.0, (640, 480)))


def test_keypoints_pck_counts_joints_off_by_more_than_alpha_torso_diameters(tmp_path, capsys):
    rng = np.random.default_rng(0)
    frames = 10
    truth = np.zeros((frames, 25, 3))
    truth[..., 0] = 300 + rng.uniform(-40, 40, (frames, 25))
    truth[..., 1] = 200 + rng.uniform(-80, 80, (frames, 25))
    truth[..., 2] = 1.0
    names = list(BODY25_NAMES)
    truth[:, names.index("right_shoulder"), :2] = (280, 120)
    truth[:, names.index("left_shoulder"), :2] = (320, 120)
    truth[:, names.index("right_hip"), :2] = (285, 220)
    truth[:, names.index("left_hip"), :2] = (315, 220)
    torso = np.hypot(30, 100)  # shoulder to opposite hip
    predicted = truth.copy()
    wrist = names.index("left_wrist")
    predicted[:, wrist, 0] += 0.3 * torso  # beyond 0.2 torso: wrong
    predicted[:, names.index("nose"), 0] += 0.1 * torso  # within: right
    predicted[:5, names.index("left_ankle")] = np.nan  # missing in the prediction: wrong
    _keypoint_file(tmp_path / "gt.npz", truth)
    _keypoint_file(tmp_path / "pred.npz", predicted)
    scores = score_keypoints(tmp_path / "gt.npz", tmp_path / "pred.npz")
    assert scores["pck"] == pytest.approx(1 - (frames + 5) / (frames * 25))
    assert scores["per_joint"]["left_wrist"] == 0.0 and scores["per_joint"]["nose"] == 1.0
    assert scores["per_joint"]["left_ankle"] == pytest.approx(0.5)
    coco = score_keypoints(tmp_path / "gt.npz", tmp_path / "pred.npz", detector_joints=True)
    assert "left_big_toe" not in coco["per_joint"] and len(coco["per_joint"]) == 19
    assert main(["evaluate", "keypoints", "--gt", str(tmp_path / "gt.npz"), "--pred",
                 str(tmp_path / "pred.npz")]) == 0
    assert "weakest joints: left_wrist 0.00, left_ankle 0.50" in capsys.readouterr().out


def test_bad_input_is_one_error_line(tmp_path, capsys):
    write_mot(tmp_path / "gt.txt", _walking_boxes())
    (tmp_path / "empty").mkdir()
    with pytest.raises(HDVRError, match="neither tracks.mot.txt"):
        load_boxes(tmp_path / "empty", ground_truth=False)
    with pytest.raises(HDVRError, match="--iou"):
        score_tracks(tmp_path / "gt.txt", tmp_path / "gt.txt", iou_threshold=1.5)
    assert main(["evaluate", "tracks", "--gt", str(tmp_path / "gt.txt"), "--tracks",
                 str(tmp_path / "missing.txt")]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        f"hdvr: error: tracks file not found: {tmp_path / 'missing.txt'}"]
    _keypoint_file(tmp_path / "a.npz", np.ones((5, 25, 3)))
    _keypoint_file(tmp_path / "b.npz", np.ones((6, 25, 3)))
    with pytest.raises(HDVRError, match="6 frames, the ground truth .* 5"):
        score_keypoints(tmp_path / "a.npz", tmp_path / "b.npz")


def _synth_gt(path, keypoints3d):
    """A minimal hdvr synth gt.npz: ``keypoints3d_camera`` (dancers, T, 25, 3) m."""
    np.savez(path, keypoints3d_camera=keypoints3d)


def test_pose3d_scores_root_relative_and_after_alignment_and_skips_missing_frames(tmp_path, capsys):
    from hdvr.layouts import EVAL_JOINTS

    rng = np.random.default_rng(1)
    frames = 12
    truth = rng.normal(0, 0.3, (2, frames, 25, 3)) + np.array([0.0, 0.0, 4.0])
    _synth_gt(tmp_path / "gt.npz", truth)
    names = list(BODY25_NAMES)
    moved = truth[1:2].copy() + np.array([0.5, -0.2, 1.0])  # dancer 1, translated: nothing changes root-relative
    wrist = names.index("left_wrist")
    moved[0, :, wrist, 0] += 0.1  # one of the evaluated joints 10 cm off on every frame
    _synth_gt(tmp_path / "pred.npz", moved)
    scores = score_pose3d(tmp_path / "gt.npz", tmp_path / "pred.npz", dancer=1)
    assert scores["mpjpe_mm"] == pytest.approx(100.0 / len(EVAL_JOINTS), abs=0.01)
    assert scores["mpjve_mm"] == pytest.approx(0.0, abs=0.01) and scores["frames_left_out"] == 0
    assert 0 < scores["p_mpjpe_mm"] < 100.0  # after per-frame similarity alignment the error spreads over joints
    moved[0, 5] = np.nan  # a frame without a pose: left out, and no velocity across it
    moved[0, 6, wrist, 0] += 0.2
    _synth_gt(tmp_path / "pred.npz", moved)
    scores = score_pose3d(tmp_path / "gt.npz", tmp_path / "pred.npz", dancer=1)
    assert scores["frames"] == frames - 1 and scores["frames_left_out"] == 1
    # velocity error: 0.2 m on the wrist in the pair (6, 7) only; (4, 5) and (5, 6) touch the gap: 9 of 11 count
    assert scores["mpjve_mm"] == pytest.approx(200.0 / len(EVAL_JOINTS) / 9, abs=0.01)
    assert main(["evaluate", "pose3d", "--gt", str(tmp_path / "gt.npz"), "--pred", str(tmp_path / "pred.npz"),
                 "--dancer", "1"]) == 0
    assert "1 without a full pose left out" in capsys.readouterr().out
    assert main(["evaluate", "pose3d", "--gt", str(tmp_path / "gt.npz"), "--pred", str(tmp_path / "pred.npz"),
                 "--dancer", "2"]) == 2
    assert "2 dancers; --dancer 2 does not exist" in capsys.readouterr().err


def test_ground_truth_rows_marked_ignored_are_left_out(tmp_path):
    """MOT challenge / CVAT ground truth: frame,id,x,y,w,h,consider,class,visibility; consider 0 = ignored box."""
    gt = _walking_boxes(10)
    rows = [f"{t + 1},{i + 1},{b[0]},{b[1]},{b[2]},{b[3]},1,1,1.0" for t in range(10) for i, b in enumerate(gt[t])]
    rows.append("3,3,10,10,20,40,0,8,0.5")  # a distractor the annotator marked ignored
    (tmp_path / "gt.txt").write_text("\n".join(rows) + "\n")
    loaded = load_boxes(tmp_path / "gt.txt", ground_truth=True)
    assert loaded.shape == (10, 2, 4)
    np.testing.assert_allclose(loaded, gt)
    write_mot(tmp_path / "tracks.txt", gt)
    assert score_tracks(tmp_path / "gt.txt", tmp_path / "tracks.txt")["precision"] == pytest.approx(1.0)
    # in tracks the 7th column is a confidence: a box written with confidence 0 stays
    (tmp_path / "t0.txt").write_text("1,1,10,10,20,40,0.000,-1,-1,-1\n2,1,12,10,20,40,1.000,-1,-1,-1\n")
    assert np.isfinite(load_boxes(tmp_path / "t0.txt", ground_truth=False)).all()
