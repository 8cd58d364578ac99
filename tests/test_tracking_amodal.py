"""hdvr.tracking.amodal: the features' layout and invariances, edges and boxes, the refiner's weights and training,
what it leaves alone, bad input; and on a real rendered clip tracked with the real detector, the shipped weights
bring the seen dancers' boxes nearer their whole-body truth."""

import numpy as np
import pytest
import torch

from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import BODY25_NAMES
from hdvr.tracking.amodal import (DEFAULT_WEIGHTS, FEATURE_VERSION, NUM_FEATURES, AmodalBoxRefiner, amodal_features,
                                  apply_edges, edge_targets, mirror_rows, refine_boxes, train_refiner)

K = 4  # first keypoint feature: after the 3 status one-hots and the aspect


def _pair(frames=3):
    """Two dancers: 0 at (100, 50, 40, 100) with a neck and a left wrist, 1 in front of it (lower bottom) and to its
    right, without keypoints; both seen."""
    boxes = np.zeros((frames, 2, 4))
    boxes[:, 0] = [100, 50, 40, 100]
    boxes[:, 1] = [120, 60, 50, 120]
    keypoints = np.zeros((frames, 2, 25, 3))
    keypoints[:, 0, 1] = [120, 70, 0.9]  # neck: on the centre line, 0.2 box heights below the top
    keypoints[:, 0, 7] = [90, 80, 0.5]  # left wrist: 0.3 heights left of the centre, beyond the box
    status = np.full((frames, 2), "tracked", dtype="<U8")
    return boxes, status, keypoints


def test_features_follow_the_documented_layout():
    boxes, status, keypoints = _pair()
    status[1] = ["tracked", "occluded"]
    f, usable = amodal_features(boxes, status, keypoints)
    assert f.shape == (3, 2, NUM_FEATURES) and f.dtype == np.float32 and usable.all()
    a = f[0, 0]
    np.testing.assert_array_equal(a[:3], [1, 0, 0])
    np.testing.assert_array_equal(f[1, 1, :3], [0, 1, 0])
    assert a[3] == pytest.approx(0.4)
    assert a[K + 1] == pytest.approx(0.0) and a[K + 25 + 1] == pytest.approx(0.2)  # neck x, y
    assert a[K + 7] == pytest.approx(-0.3) and a[K + 25 + 7] == pytest.approx(0.3)  # wrist x, y
    given = a[K + 50:K + 75]
    assert given[[1, 7]].tolist() == [1, 1] and given.sum() == 2
    assert a[K + 2] == 0 and a[K + 25 + 2] == 0  # not given: zeros
    # its neighbour, dancer 1: centre 25 px right (0.25 h), top 10 px lower, 0.5 x 1.2 h, in front, IoU
    inter = 20 * 90
    iou = inter / (40 * 100 + 50 * 120 - inter)
    np.testing.assert_allclose(a[K + 75:K + 81], [0.25, 0.1, 0.5, 1.2, 1.0, iou], rtol=1e-6)
    assert not a[K + 81:].any()  # no second or third neighbour
    b = f[0, 1]  # dancer 1's neighbour, dancer 0, stands behind it
    assert b[K + 75 + 4] == 0.0 and b[K + 75 + 5] == pytest.approx(iou)


def test_features_do_not_depend_on_where_the_dancers_are_or_on_the_video_size():
    boxes, status, keypoints = _pair()
    f, _ = amodal_features(boxes, status, keypoints)
    moved_boxes, moved_keypoints = boxes.copy(), keypoints.copy()
    moved_boxes[..., :2] += [37.0, -12.0]
    moved_keypoints[..., :2] += [37.0, -12.0]
    np.testing.assert_allclose(amodal_features(moved_boxes, status, moved_keypoints)[0], f, atol=1e-5)
    np.testing.assert_allclose(amodal_features(boxes * 2.5, status, keypoints * [2.5, 2.5, 1.0])[0], f, atol=1e-5)


def test_dancers_without_a_box_or_out_of_the_frame_have_no_features_and_are_not_neighbours():
    boxes, status, keypoints = _pair()
    boxes[1, 1] = np.nan
    status[2, 1] = "out"
    f, usable = amodal_features(boxes, status, keypoints)
    assert usable.tolist() == [[True, True], [True, False], [True, False]]
    assert not f[1, 1].any() and not f[2, 1].any()
    assert not f[1, 0, K + 75:].any() and not f[2, 0, K + 75:].any()
    assert f[0, 0, K + 75:].any()


def test_mirror_rows_are_the_features_and_targets_of_the_mirrored_video():
    """Mirroring the video (x -> width - x, left and right joints exchanged) gives the features and edge targets
    that :func:`mirror_rows` makes from the unmirrored ones."""
    boxes, status, keypoints = _pair()
    keypoints[:, 0, 2] = [115, 68, 0.7]  # right shoulder, beside the neck
    truth = boxes + [-12.0, -3.0, 30.0, 8.0]
    width = 640.0
    names = list(BODY25_NAMES)
    swapped = [names.index(n.replace("left_", "#").replace("right_", "left_").replace("#", "right_")) for n in names]
    mirrored_boxes, mirrored_truth = boxes.copy(), truth.copy()
    mirrored_boxes[..., 0] = width - boxes[..., 0] - boxes[..., 2]
    mirrored_truth[..., 0] = width - truth[..., 0] - truth[..., 2]
    mirrored_keypoints = keypoints[:, :, swapped].copy()
    mirrored_keypoints[..., 0] = np.where(mirrored_keypoints[..., 2] > 0, width - mirrored_keypoints[..., 0], 0.0)
    f, usable = amodal_features(boxes, status, keypoints)
    mf, _ = amodal_features(mirrored_boxes, status, mirrored_keypoints)
    x, y = mirror_rows(f[usable], edge_targets(boxes, truth)[usable])
    np.testing.assert_allclose(x, mf[usable], atol=1e-5)
    np.testing.assert_allclose(y, edge_targets(mirrored_boxes, mirrored_truth)[usable], atol=1e-6)
    twice = mirror_rows(*mirror_rows(f[usable], y))  # mirrored twice: itself
    np.testing.assert_allclose(twice[0], f[usable], atol=1e-6)
    np.testing.assert_allclose(twice[1], y, atol=1e-6)


def test_edges_move_a_box_onto_its_truth_and_back():
    box = np.array([[100.0, 50.0, 40.0, 100.0]])
    truth = np.array([[90.0, 45.0, 70.0, 110.0]])
    edges = edge_targets(box, truth)
    np.testing.assert_allclose(edges, [[-0.1, -0.05, 0.2, 0.05]])
    np.testing.assert_allclose(apply_edges(box, edges), truth)
    assert np.isnan(edge_targets(box, np.full((1, 4), np.nan))).all()
    np.testing.assert_allclose(apply_edges(box, np.array([[0.5, 0.0, -0.5, 0.0]]))[0, 2], 2.0)  # never below 2 px


def _refiner_moving_every_edge(by=(-0.1, -0.05, 0.1, 0.05)):
    """A refiner whose network says ``by`` whatever it is shown (last layer's weights zero, bias ``by``)."""
    payload = train_refiner(np.zeros((4, NUM_FEATURES), np.float32), np.zeros((4, 4), np.float32), hidden=4,
                            epochs=1, members=1)
    state = payload["members"][0]
    last = max(k for k in state if k.endswith(".weight"))
    state[last].zero_()
    state[last.replace("weight", "bias")].copy_(torch.tensor(by))
    return AmodalBoxRefiner(payload)


def test_refine_moves_only_the_boxes_of_dancers_seen_in_a_run_with_poses():
    boxes, status, keypoints = _pair(frames=4)
    status[1, 1], status[2, 1], status[3, 1] = "occluded", "hidden", "out"
    boxes[0, 1] = np.nan
    refiner = _refiner_moving_every_edge()
    out = refine_boxes(boxes, status, keypoints, refiner)
    np.testing.assert_allclose(out[:, 0], apply_edges(boxes[:, 0], np.tile([-0.1, -0.05, 0.1, 0.05], (4, 1))))
    assert np.isnan(out[0, 1]).all()
    np.testing.assert_array_equal(out[1:, 1], boxes[1:, 1])  # occluded, hidden, out: kept
    assert not np.shares_memory(out, boxes)
    # a frame of a seen dancer without keypoints in a run with poses is refined; a run without any is not
    np.testing.assert_allclose(refine_boxes(boxes, np.full((4, 2), "tracked"), keypoints, refiner)[1:, 1],
                               apply_edges(boxes[1:, 1], np.tile([-0.1, -0.05, 0.1, 0.05], (3, 1))))
    no_poses = np.zeros_like(keypoints)
    np.testing.assert_array_equal(refine_boxes(boxes, status, no_poses, refiner), boxes)
    np.testing.assert_allclose(refine_boxes(boxes, status, keypoints, refiner, statuses=("tracked", "occluded"))[1, 1],
                               apply_edges(boxes[1, 1], np.array([-0.1, -0.05, 0.1, 0.05])))


def test_the_shipped_weights_load_safely_and_refine_deterministically():
    refiner = AmodalBoxRefiner.load()
    assert DEFAULT_WEIGHTS.name == "amodal_boxes.pt" and refiner.payload["feature_version"] == FEATURE_VERSION
    assert len(refiner.networks) == refiner.payload["members"].__len__() >= 1
    assert all("clips" in s for s in refiner.payload["trained_on"])  # what it learned from is recorded
    boxes, status, keypoints = _pair()
    first = refine_boxes(boxes, status, keypoints)
    np.testing.assert_array_equal(first, refine_boxes(boxes, status, keypoints, AmodalBoxRefiner.load()))
    np.testing.assert_array_equal(first, refine_boxes(boxes, status, keypoints, weights=DEFAULT_WEIGHTS))
    # weights are read only when a box is to be moved: a run without poses never opens them
    np.testing.assert_array_equal(refine_boxes(boxes, status, np.zeros_like(keypoints), weights="/no/such.pt"), boxes)
    with pytest.raises(HDVRError, match="not found"):
        refine_boxes(boxes, status, keypoints, weights="/no/such.pt")
    assert np.isfinite(first).all() and (first[..., 2:] > 0).all()
    # small corrections: a box is moved by a fraction of its height, not onto another place
    assert np.abs(edge_targets(boxes, first)).max() < 0.5


def test_training_is_deterministic_by_seed_and_learns_the_offsets():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(2000, NUM_FEATURES)).astype(np.float32)
    y = np.stack([-0.1 * np.ones(2000), 0.05 * x[:, 3], 0.2 * np.tanh(x[:, 10]), np.zeros(2000)], axis=1)
    losses = []
    a = train_refiner(x, y, hidden=32, dropout=0.0, epochs=15, members=2, mirror=False, seed=3,
                      progress=lambda m, e, loss: losses.append((m, e, loss)))
    b = train_refiner(x, y, hidden=32, dropout=0.0, epochs=15, members=2, mirror=False, seed=3)
    for sa, sb in zip(a["members"], b["members"]):
        for k in sa:
            assert torch.equal(sa[k], sb[k])
    assert [(m, e) for m, e, _ in losses] == [(m, e) for m in range(2) for e in range(15)]
    assert losses[14][2] < losses[0][2] / 3
    predicted = AmodalBoxRefiner(a).edges(x[:200])
    assert np.abs(predicted - y[:200]).mean() < 0.03
    assert a["rows"] == 2000 and train_refiner(x[:50], y[:50], hidden=4, epochs=1, members=1)["rows"] == 100  # mirrored


def test_bad_input_gives_one_line_errors(tmp_path):
    boxes, status, keypoints = _pair()
    with pytest.raises(HDVRError, match=r"expected \(T, N, 4\) boxes"):
        amodal_features(boxes[..., :3], status, keypoints)
    with pytest.raises(HDVRError, match="keypoints for 3 frames of 2 dancers"):
        amodal_features(boxes, status, keypoints[:, :, :17])
    with pytest.raises(HDVRError, match="features and"):
        train_refiner(np.zeros((3, 5), np.float32), np.zeros((3, 4), np.float32))
    with pytest.raises(HDVRError, match="finite"):
        train_refiner(np.full((3, NUM_FEATURES), np.nan, np.float32), np.zeros((3, 4), np.float32))
    refiner = _refiner_moving_every_edge()
    with pytest.raises(HDVRError, match="amodal features"):
        refiner.edges(np.zeros((2, 5)))
    with pytest.raises(HDVRError, match="not found"):
        AmodalBoxRefiner.load(tmp_path / "none.pt")
    corrupt = tmp_path / "corrupt.pt"
    corrupt.write_bytes(b"not a torch file")
    with pytest.raises(HDVRError, match="cannot read amodal box weights"):
        AmodalBoxRefiner.load(corrupt)
    torch.save({"something": 1}, tmp_path / "other.pt")
    with pytest.raises(HDVRError, match="no amodal box weights"):
        AmodalBoxRefiner.load(tmp_path / "other.pt")
    old = dict(refiner.payload, feature_version=FEATURE_VERSION + 1)
    with pytest.raises(HDVRError, match="train them again"):
        AmodalBoxRefiner(old)


def test_on_a_real_clip_the_seen_dancers_boxes_come_nearer_their_whole_body(tmp_path):
    """A rendered hdvr synth clip (seed 5, the 1-second swing couple) tracked with the real detector: after the
    other hindsight steps the shipped refiner raises the mean IoU of the seen dancers' boxes with the ground truth."""
    from script_loader import load_script

    script = load_script("hindsight_runs")
    from bench_track import _seen_truth

    from hdvr.tracking.evaluation import iou_matrix
    from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight

    clips, runs = tmp_path / "clips", tmp_path / "runs"
    assert script.main(["save", "--clips-dir", str(clips), "--seeds", "5", "--clips", "1", "--runs", str(runs),
                        "--seconds", "1"]) == 0
    run = script.load_run(runs / "5_1.npz")
    truth, _ = _seen_truth(script.synth_clip_folder(clips, script.clip_spec(5, 1)))
    truth = truth[:, run["order"]]
    args = (run["boxes"], run["status"], run["keypoints"])
    plain = apply_hindsight(*args, frame_width=float(run["width"]), settings=HindsightSettings(amodal_boxes=False))[0]
    refined = apply_hindsight(*args, frame_width=float(run["width"]))[0]
    np.testing.assert_array_equal(refined, refine_boxes(plain, run["status"], run["keypoints"]))
    seen = [(t, d) for t, row in enumerate(run["status"]) for d, s in enumerate(row)
            if s == "tracked" and np.isfinite(truth[t, d]).all()]
    assert len(seen) > 20

    def mean_iou(boxes):
        return np.mean([iou_matrix(truth[t, d][None], boxes[t, d][None])[0, 0] for t, d in seen])

    assert mean_iou(refined) > mean_iou(plain) + 0.005  # 0.864 -> 0.871 with the weights of session 52

    def matched(boxes):
        return np.mean([iou_matrix(truth[t, d][None], boxes[t, d][None])[0, 0] >= 0.5 for t, d in seen])

    assert matched(refined) >= matched(plain)
