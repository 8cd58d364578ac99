"""Hindsight once a video is tracked: occluded stretches filled, boxes smoothed, hidden dancers kept near their
start offset (hdvr.tracking.hindsight)."""

import numpy as np
import pytest

from hdvr.tracking.hindsight import (HIDDEN_FEET_TOLERANCE, HIDDEN_FILL_WEIGHT, HOLD_WEIGHT, MIN_SEEN_AFTER,
                                     START_OFFSET_WEIGHT, START_PLACE_WEIGHT, HindsightSettings,
                                     apply_hindsight, enclose_keypoints, fill_hidden_until_seen, fill_occluded,
                                     follow_partner_in_hold, hold_last_seen, interpolate_boxes,
                                     keep_feet_behind_front, keep_start_offset, keep_start_place, occluded_stretches,
                                     scale_with_depth, smooth_boxes, start_feet, start_offsets, trim_above_pose)


def _walk(frames: int, speed: float = 4.0) -> np.ndarray:
    """(frames, 1, 4) boxes px of a dancer walking right at ``speed`` px/frame and growing 1 px/frame in height."""
    t = np.arange(frames, dtype=float)
    return np.stack([100 + speed * t, 50 - t / 2, 40 + 0 * t, 120 + t], axis=1)[:, None, :]


def _status(frames: int, occluded=(), other="tracked", **at) -> list[tuple[str]]:
    """One dancer's status per frame: ``occluded`` frames, ``at`` {status: frames} for others, else ``other``."""
    out = [("occluded",) if t in occluded else (other,) for t in range(frames)]
    for name, frames_of in at.items():
        for t in frames_of:
            out[t] = (name,)
    return out


def test_occluded_stretches_are_the_runs_of_occluded_frames():
    status = ["tracked", "occluded", "occluded", "tracked", "hidden", "out", "occluded"]
    assert occluded_stretches(status) == [(1, 2), (6, 6)]
    assert occluded_stretches(["tracked"] * 3) == []


def test_interpolated_boxes_move_their_centre_and_size_linearly():
    boxes = interpolate_boxes((0, 0, 10, 20), (80, 40, 30, 60), 3)  # centres (5, 10) -> (95, 70)
    centres = boxes[:, :2] + boxes[:, 2:] / 2
    np.testing.assert_allclose(centres, [[27.5, 25], [50, 40], [72.5, 55]])
    np.testing.assert_allclose(boxes[:, 2:], [[15, 30], [20, 40], [25, 50]])


def test_an_occluded_stretch_is_filled_between_where_the_dancer_was_seen_before_and_after():
    truth = _walk(30)
    boxes = truth.copy()
    boxes[10:20, 0] = truth[9, 0]  # predicted box stood still while the dancer walked on behind others
    filled, mask = fill_occluded(boxes, _status(30, range(10, 20)), min_seen_after=5)
    np.testing.assert_allclose(filled, truth, atol=1e-9)
    assert mask[:, 0].tolist() == [10 <= t < 20 for t in range(30)]
    np.testing.assert_array_equal(boxes[10:20, 0], np.repeat(truth[9], 10, axis=0))  # input unchanged


def test_a_stretch_ended_by_a_short_sighting_is_not_filled():
    """Seen again for fewer than min_seen_after frames (perhaps on the wrong person, hdvr synth seed 505
    hip-hop): the predicted boxes stay."""
    truth = _walk(30)
    boxes = truth.copy()
    boxes[10:20, 0] = truth[9, 0]
    boxes[20:22, 0] = truth[20, 0] - (0, 80, 0, 0)  # taken on someone else for two frames, lost again
    status = _status(30, list(range(10, 20)) + list(range(22, 30)))
    filled, mask = fill_occluded(boxes, status, min_seen_after=3)
    np.testing.assert_array_equal(filled, boxes)
    assert not mask.any()
    assert MIN_SEEN_AFTER >= 2  # the default trusts no single-frame sighting


def test_a_stretch_longer_than_max_frames_is_not_filled():
    """With ``max_frames`` (measured in session 87, not the default) a stretch longer than that keeps the
    prediction; by default, or with a cap it fits under, it is filled whatever its length."""
    truth = _walk(60)
    boxes = truth.copy()
    boxes[5:50, 0] = truth[4, 0]  # 45 frames occluded
    status = _status(60, range(5, 50))
    filled, mask = fill_occluded(boxes, status, max_frames=40)
    np.testing.assert_array_equal(filled, boxes)
    assert not mask.any()
    filled, mask = fill_occluded(boxes, status)
    np.testing.assert_allclose(filled, truth, atol=1e-9)
    assert mask[:, 0].sum() == 45
    assert fill_occluded(boxes, status, max_frames=45)[1].sum() == 45


def test_a_dancer_seen_again_to_the_end_of_the_video_counts_as_seen_again():
    truth = _walk(20)
    boxes = truth.copy()
    boxes[10:18, 0] = truth[9, 0]
    filled, mask = fill_occluded(boxes, _status(20, range(10, 18)), min_seen_after=5)  # seen on the last 2 frames
    np.testing.assert_allclose(filled, truth, atol=1e-9)
    assert mask[:, 0].sum() == 8


def test_stretches_with_nothing_seen_before_or_after_keep_their_boxes():
    boxes = _walk(24)
    boxes[1:3] = np.nan  # out of the frame
    status = _status(24, occluded=list(range(3, 8)) + list(range(20, 24)), out=[1, 2])
    filled, mask = fill_occluded(boxes, status, min_seen_after=3)
    np.testing.assert_array_equal(filled, boxes)  # frames 3-7 follow an exit, 20-23 end the clip occluded
    assert not mask.any()


def test_a_dancer_waiting_hidden_since_its_start_keeps_its_boxes():
    """Status "hidden" (started behind another, never seen): its box stays with the dancer in front, and an
    occluded stretch that follows it has no box seen before it."""
    boxes = _walk(20)
    status = _status(20, occluded=range(6, 10), hidden=range(0, 6))
    filled, mask = fill_occluded(boxes + 0.0, status)
    np.testing.assert_array_equal(filled, boxes)
    assert not mask.any()


def test_each_dancer_is_filled_on_its_own():
    a, b = _walk(20), _walk(20, speed=-3.0)
    boxes = np.concatenate([a, b], axis=1)
    boxes[5:9, 1] = b[4, 0]
    status = [("tracked", "occluded" if 5 <= t < 9 else "tracked") for t in range(20)]
    filled, mask = fill_occluded(boxes, status)
    np.testing.assert_allclose(filled[:, 1], b[:, 0], atol=1e-9)
    np.testing.assert_array_equal(filled[:, 0], a[:, 0])
    assert mask[:, 1].sum() == 4 and not mask[:, 0].any()


def test_wrong_shapes_and_settings_are_refused():
    with pytest.raises(ValueError, match=r"\(T, N, 4\)"):
        fill_occluded(np.zeros((5, 4)), [("tracked",)] * 5)
    with pytest.raises(ValueError, match="min_seen_after"):
        fill_occluded(np.zeros((5, 1, 4)), [("tracked",)] * 5, min_seen_after=0)


def test_smoothing_averages_jitter_away_and_keeps_a_steady_walk():
    rng = np.random.default_rng(0)
    truth = _walk(60)
    noisy = truth + np.concatenate([rng.normal(0, 4, (60, 1, 2)), np.zeros((60, 1, 2))], axis=2)  # jittery corner
    status = _status(60)
    smoothed = smooth_boxes(noisy, status, window=9)
    inner = slice(4, 56)  # away from the ends, a straight walk is kept exactly by a centred average
    np.testing.assert_allclose(smooth_boxes(truth, status, window=9)[inner], truth[inner], atol=1e-9)
    assert np.abs(smoothed[inner] - truth[inner]).mean() < 0.5 * np.abs(noisy[inner] - truth[inner]).mean()
    np.testing.assert_array_equal(noisy, truth + (noisy - truth))  # input unchanged


def test_smoothing_stays_within_each_run_of_boxes():
    """Frames out of the frame, absent or hidden since the start are left as they are and split the runs; a run
    shorter than the window is kept."""
    boxes = _walk(40)
    boxes[10:13] = np.nan
    boxes[30:40, 0, 0] += 50.0 * (np.arange(10) % 2)  # jitter in a run of 10 frames
    status = _status(40, hidden=range(0, 5), out=range(10, 13))
    status[20] = status[25] = ("hidden",)
    smoothed = smooth_boxes(boxes, status, window=9)
    np.testing.assert_array_equal(smoothed[:26], boxes[:26])  # runs 5-9, 13-19 and 21-24 are shorter than 9 frames
    assert np.isnan(smoothed[10:13]).all()
    assert np.ptp(smoothed[30:36, 0, 0] - boxes[30:36, 0, 0]) > 0  # run 26-39 (14 frames) is smoothed
    assert np.abs(np.diff(smoothed[30:40, 0, 0])).max() < np.abs(np.diff(boxes[30:40, 0, 0])).max()


def test_smoothing_refuses_wrong_shapes_and_windows():
    with pytest.raises(ValueError, match=r"\(T, N, 4\)"):
        smooth_boxes(np.zeros((5, 4)), [("tracked",)] * 5)
    with pytest.raises(ValueError, match="window"):
        smooth_boxes(np.zeros((5, 1, 4)), [("tracked",)] * 5, window=0)


def _skeleton(box, spread: float = 0.0, joints: int = 25, confidence: float = 0.9) -> np.ndarray:
    """(joints, 3) keypoints x px, y px, confidence spread evenly over ``box`` (x, y, w, h px), the first one (a
    wrist) ``spread`` px further left than the box if ``spread`` > 0."""
    x, y, w, h = box
    kp = np.stack([np.linspace(x + 0.2 * w, x + 0.8 * w, joints), np.linspace(y + 0.1 * h, y + 0.9 * h, joints),
                   np.full(joints, confidence)], axis=1)
    if spread > 0:
        kp[0, 0] = x - spread
    return kp


def test_a_box_is_widened_to_a_spread_arm_and_the_reach_beyond_it():
    boxes = np.array([[[100.0, 50, 40, 100], [300, 50, 40, 100]]])  # one frame, two dancers
    keypoints = np.stack([_skeleton(boxes[0, 0], spread=30), _skeleton(boxes[0, 1])])[None]
    out, widened = enclose_keypoints(boxes, [("tracked", "tracked")], keypoints, reach=0.06)
    np.testing.assert_allclose(out[0, 0], [100 - 30 - 6, 50, 40 + 36, 100])  # the wrist 30 px out, 0.06 x 100 px
    np.testing.assert_array_equal(out[0, 1], boxes[0, 1])  # its skeleton lies inside with room to spare
    np.testing.assert_array_equal(widened, [[True, False]])
    assert boxes[0, 0, 0] == 100.0  # input unchanged


def test_a_box_only_grows_and_only_sideways():
    box = np.array([100.0, 50, 40, 100])
    kp = _skeleton((110, 0, 20, 200))  # narrower than the box, but twice as tall
    out, widened = enclose_keypoints(box[None, None], [("tracked",)], kp[None, None])
    np.testing.assert_array_equal(out[0, 0], box)
    assert not widened.any()


def test_weak_few_or_missing_keypoints_and_boxes_without_a_dancer_change_nothing():
    box = np.array([100.0, 50, 40, 100])
    weak = _skeleton(box, spread=30, confidence=0.1)
    few = _skeleton(box, spread=30)
    few[4:, :2], few[4:, 2] = np.nan, 0.0  # 4 keypoints left
    spread = _skeleton(box, spread=30)
    boxes = np.tile(box, (5, 1, 1))
    status = [("tracked",), ("tracked",), ("occluded",), ("hidden",), ("out",)]
    out, widened = enclose_keypoints(boxes, status, np.stack([weak, few, spread, spread, spread])[:, None],
                                     min_keypoints=5)
    np.testing.assert_array_equal(out, boxes)  # only a dancer seen is widened, and only to keypoints it is sure of
    assert not widened.any()
    nan_box = np.full((1, 1, 4), np.nan)
    assert np.isnan(enclose_keypoints(nan_box, [("tracked",)], spread[None, None])[0]).all()


def test_a_pose_that_does_not_fit_the_box_is_someone_else_s():
    """A small dancer behind a tall one given the tall one's pose: its torso lies beside the box, or its keypoints
    run far below it; the box keeps its width. Within the height margin, a pose counts."""
    box = np.array([100.0, 50, 40, 100])
    beside = _skeleton((150, 50, 40, 100), spread=80)  # torso right of the box, a wrist far left of it
    taller = _skeleton((90, 50, 60, 200), spread=30)  # torso inside the box, but the legs reach 100 px below it
    raised = _skeleton(box, spread=30)
    raised[0, 1] = 42.0  # a hand 8 px above the box: within 0.1 x its height
    boxes = np.tile(box, (3, 1, 1))
    out, widened = enclose_keypoints(boxes, [("tracked",)] * 3, np.stack([beside, taller, raised])[:, None])
    np.testing.assert_array_equal(out[:2], boxes[:2])
    np.testing.assert_array_equal(widened[:, 0], [False, False, True])
    np.testing.assert_allclose(out[2, 0], [100 - 30 - 8, 50, 78, 100])  # the default reach: 0.08 x 100 px


def test_a_widened_box_stays_inside_the_frame():
    box = np.array([10.0, 50, 40, 100])
    out, widened = enclose_keypoints(box[None, None], [("tracked",)], _skeleton(box, spread=8)[None, None],
                                     frame_width=640)
    assert out[0, 0, 0] == 0.0 and out[0, 0, 0] + out[0, 0, 2] == 50.0 and widened.all()
    outside = np.array([-5.0, 50, 40, 100])  # a box already past the edge is not cut by the clipping
    out, _ = enclose_keypoints(outside[None, None], [("tracked",)], _skeleton(outside)[None, None], frame_width=640)
    np.testing.assert_array_equal(out[0, 0], outside)


def test_enclosing_refuses_wrong_shapes_and_settings():
    boxes, status = np.zeros((5, 1, 4)), [("tracked",)] * 5
    with pytest.raises(ValueError, match="keypoints"):
        enclose_keypoints(boxes, status, np.zeros((5, 2, 25, 3)))
    with pytest.raises(ValueError, match="BODY_25"):
        enclose_keypoints(boxes, status, np.zeros((5, 1, 17, 3)))
    with pytest.raises(ValueError, match="reach"):
        enclose_keypoints(boxes, status, np.zeros((5, 1, 25, 3)), reach=-0.1)
    with pytest.raises(ValueError, match="min_keypoints"):
        enclose_keypoints(boxes, status, np.zeros((5, 1, 25, 3)), min_keypoints=0)


def _full_pose(box, head_below_top: float, confidence: float = 0.9) -> np.ndarray:
    """(25, 3) BODY_25 keypoints of a dancer in ``box`` (x, y, w, h px), spread over it: its highest keypoint (the nose)
    ``head_below_top`` px below the box's top, the ankles at 0.85 of the box height; the feet (not in COCO-17) NaN."""
    x, y, w, h = box
    kp = np.full((25, 3), np.nan)
    rows = np.linspace(y + head_below_top, y + 0.85 * h, 19)  # 19 joints of BODY_25 that COCO-17 gives
    for k, row in zip(range(19), rows):
        kp[k] = (x + w * (0.3 + 0.4 * (k % 2)), row, confidence)
    return kp


def test_a_box_reaching_far_above_a_full_pose_comes_down_to_the_head_s_reach():
    """A tracked box whose top lies 50 px above the nose of a 200 px dancer (0.25 of its height: a size ratio
    learned from a detection that left the legs out) comes down to 0.12 x its height above it, keeping its bottom;
    a box 20 px above (0.10: within the head's reach) stays."""
    far, near = np.array([100.0, 50, 80, 200]), np.array([300.0, 50, 80, 200])
    keypoints = np.stack([_full_pose(far, 50), _full_pose(near, 20)])[None]
    out, lowered = trim_above_pose(np.stack([far, near])[None], [("tracked", "tracked")], keypoints)
    new_top = 50 + 50 - 0.12 * 200
    np.testing.assert_allclose(out[0, 0], [100, new_top, 80, 250 - new_top])
    np.testing.assert_array_equal(out[0, 1], near)
    np.testing.assert_array_equal(lowered, [[True, False]])
    assert far[1] == 50.0  # input unchanged


def test_only_a_full_pose_of_a_dancer_seen_inside_its_box_lowers_it():
    """A pose without its face (the highest keypoint would be a shoulder), weak keypoints, a pose reaching beside
    the box (someone else's), and dancers not seen (occluded, hidden) keep their boxes."""
    box = np.array([100.0, 50, 80, 200])
    full = _full_pose(box, 60)
    faceless = full.copy()
    faceless[[0, 15, 16, 17, 18], :2], faceless[[0, 15, 16, 17, 18], 2] = np.nan, 0.0  # nose, eyes, ears gone
    weak = _full_pose(box, 60, confidence=0.2)
    beside = full.copy()
    beside[4, 0] = 200.0  # a wrist 20 px right of the box
    poses = [faceless, weak, beside, full, full, full]
    status = [("tracked",)] * 4 + [("occluded",), ("hidden",)]
    boxes = np.tile(box, (len(poses), 1, 1))
    out, lowered = trim_above_pose(boxes, status, np.stack(poses)[:, None])
    np.testing.assert_array_equal(lowered[:, 0], [False, False, False, True, False, False])
    np.testing.assert_array_equal(np.delete(out, 3, axis=0), np.delete(boxes, 3, axis=0))


def test_trimming_keeps_at_least_half_the_box_and_refuses_wrong_settings():
    box = np.array([100.0, 50, 80, 200])
    out, lowered = trim_above_pose(box[None, None], [("tracked",)], _full_pose(box, 150)[None, None])
    np.testing.assert_array_equal(out[0, 0], box)  # the nose 150 px down: lowering would leave under half
    assert not lowered.any()
    boxes, status = np.zeros((5, 1, 4)), [("tracked",)] * 5
    with pytest.raises(ValueError, match="BODY_25"):
        trim_above_pose(boxes, status, np.zeros((5, 1, 17, 3)))
    with pytest.raises(ValueError, match="reach"):
        trim_above_pose(boxes, status, np.zeros((5, 1, 25, 3)), reach=-0.1)
    with pytest.raises(ValueError, match="min_joints"):
        trim_above_pose(boxes, status, np.zeros((5, 1, 25, 3)), min_joints=0)


def test_a_stretch_not_seen_after_holds_the_box_where_the_dancer_was_last_seen():
    """Hidden to the end of the video: the online prediction runs on with the velocity the dancer had when it went
    behind the others; with hindsight the box stays where it was last seen. A stretch filled between two sightings
    keeps its filled boxes, and a frame predicted out of the frame (no box) stays without one."""
    boxes = _walk(12)
    status = _status(12, occluded=range(6, 12))
    _, filled = fill_occluded(boxes, status)
    assert not filled.any()  # nothing seen after: nothing filled
    boxes[11, 0] = np.nan  # predicted out of the frame on the last one
    out, held = hold_last_seen(boxes, status, filled, min_cover=0.0)  # no dancer in front here: the plain hold
    np.testing.assert_array_equal(out[6:11, 0], np.tile(boxes[5, 0], (5, 1)))
    assert np.isnan(out[11, 0]).all()
    np.testing.assert_array_equal(held[:, 0], [False] * 6 + [True] * 5 + [False])
    np.testing.assert_array_equal(out[:6], boxes[:6])
    both = _status(12, occluded=range(3, 6))
    refilled, mask = fill_occluded(_walk(12), both)
    out, held = hold_last_seen(refilled, both, mask, min_cover=0.0)  # seen again after: filled, not held
    np.testing.assert_array_equal(out, refilled)
    assert not held.any()


def test_a_held_stretch_mixes_in_the_online_prediction_by_the_hold_weight():
    """``weight`` 1 holds the last box seen, 0 keeps the online prediction, between them a blend of the two
    (measured in sessions 56 and 72, docs/benchmarks.md); :func:`apply_hindsight` blends by ``HOLD_WEIGHT`` (0.75,
    session 72) unless told otherwise."""
    boxes = _walk(12)
    status = _status(12, occluded=range(6, 12))
    filled = np.zeros((12, 1), bool)
    for weight in (1.0, 0.5, 0.0):
        out, held = hold_last_seen(boxes, status, filled, weight=weight, min_cover=0.0)
        np.testing.assert_allclose(out[6:, 0], weight * boxes[5, 0] + (1 - weight) * boxes[6:, 0])
        assert held[6:, 0].all()
    settings = HindsightSettings(hold_weight=0.0, amodal_boxes=False, smooth_window=1, hold_min_cover=0.0)
    online = apply_hindsight(boxes, status, np.full((12, 1, 25, 3), np.nan), settings=settings)[0]
    np.testing.assert_allclose(online[6:, 0], boxes[6:, 0])
    default = HindsightSettings(amodal_boxes=False, smooth_window=1, hold_min_cover=0.0)
    blended = apply_hindsight(boxes, status, np.full((12, 1, 25, 3), np.nan), settings=default)[0]
    assert HOLD_WEIGHT == 0.75
    np.testing.assert_allclose(blended[6:, 0], 0.75 * boxes[5, 0] + 0.25 * boxes[6:, 0])


def test_a_stretch_the_tracker_stopped_behind_the_dancers_in_front_keeps_its_online_boxes():
    """Where the online tracker stopped the dancer's predicted box behind the dancers in front (``stopped``, from
    ``TrackRun.stopped_behind``: its prediction ran on only while hidden, then stayed where it was hidden best), the
    stretch keeps its online boxes instead of the box last seen; other stretches are held as before. Through
    :func:`apply_hindsight` that is ``stopped_behind``, switched off by ``keep_stopped=False``."""
    boxes = np.concatenate([_walk(12), _walk(12)], axis=1)
    status = [a + b for a, b in zip(_status(12, occluded=range(6, 12)), _status(12, occluded=range(4, 12)))]
    filled = np.zeros((12, 2), bool)
    stopped = np.zeros((12, 2), bool)
    stopped[9:, 0] = True  # dancer 0 stopped on frame 9 of its stretch 6-11
    out, held = hold_last_seen(boxes, status, filled, stopped=stopped, min_cover=0.0)
    np.testing.assert_array_equal(out[:, 0], boxes[:, 0])  # the whole stretch online, also before the stop
    assert not held[:, 0].any()
    np.testing.assert_array_equal(out[4:, 1], np.tile(boxes[3, 1], (8, 1)))  # not stopped: held
    with pytest.raises(ValueError, match="stopped"):
        hold_last_seen(boxes, status, filled, stopped=np.zeros((12, 1), bool))
    keypoints = np.full((12, 2, 25, 3), np.nan)
    for keep, expected in ((True, boxes[6:, 0]), (False, np.tile(boxes[5, 0], (6, 1)))):
        settings = HindsightSettings(keep_stopped=keep, amodal_boxes=False, smooth_window=1, hold_min_cover=0.0,
                                     hold_weight=1.0)
        written = apply_hindsight(boxes, status, keypoints, settings=settings, stopped_behind=stopped)[0]
        np.testing.assert_allclose(written[6:, 0], expected)


def test_a_stretch_whose_last_seen_place_comes_open_to_view_keeps_its_online_boxes():
    """``min_cover``: a stretch is held only while the place the dancer was last seen stays behind the dancers
    followed in front (its body core at least ``min_cover`` inside theirs) in every frame of it. Where the dancer in
    front walks off and leaves that place open, the dancer would have been seen there, so it walked on: the online
    prediction is kept (the procedural crossings of ``bench_track.py --sections identity``, figures walking on
    behind another and never found again, were held where they went behind). Through :func:`apply_hindsight` that is
    ``HindsightSettings.hold_min_cover``."""
    frames = 12
    hidden = _walk(frames)[:, 0]  # dancer 0 walks right, occluded from frame 6 to the end
    front_stays = np.tile(hidden[5], (frames, 1))  # dancer 1 stands on the place dancer 0 was last seen
    front_walks = front_stays.copy()
    front_walks[9:, 0] -= 150  # ... or walks off it on frame 9
    status = [a + ("tracked",) for a in _status(frames, occluded=range(6, frames))]
    filled = np.zeros((frames, 2), bool)
    for front, held_expected in ((front_stays, True), (front_walks, False)):
        boxes = np.stack([hidden, front], axis=1)
        out, held = hold_last_seen(boxes, status, filled)  # HOLD_MIN_COVER
        expected = np.tile(hidden[5], (6, 1)) if held_expected else hidden[6:]
        np.testing.assert_array_equal(out[6:, 0], expected)
        assert held[6:, 0].all() == held_expected
        off = hold_last_seen(boxes, status, filled, min_cover=0.0)[0]
        np.testing.assert_array_equal(off[6:, 0], np.tile(hidden[5], (6, 1)))  # off: held either way
        settings = HindsightSettings(amodal_boxes=False, smooth_window=1, hold_weight=1.0)
        written = apply_hindsight(boxes, status, np.full((frames, 2, 25, 3), np.nan), settings=settings)[0]
        np.testing.assert_allclose(written[6:, 0], expected)


def test_only_a_stretch_right_after_a_sighting_is_held():
    """A stretch at the very start, or after the dancer was out of the frame or waiting hidden since its start, has
    no box of the dancer seen to hold."""
    boxes = _walk(8)
    for status in (_status(8, occluded=range(0, 4)), [("out",)] * 2 + [("occluded",)] * 6,
                   [("hidden",)] * 3 + [("occluded",)] * 5):
        out, held = hold_last_seen(boxes, status, np.zeros((8, 1), bool))
        np.testing.assert_array_equal(out, boxes)
        assert not held.any()
    with pytest.raises(ValueError, match="filled"):
        hold_last_seen(boxes, _status(8), np.zeros((8, 2), bool))


def _stack(frames: int = 12) -> tuple[np.ndarray, list[tuple[str, str]]]:
    """Dancer 0 walking right in front; dancer 1 (box 100 px tall) starting 20 px to his right, mostly behind him,
    and waiting hidden there for 8 frames while its box drifts onto his (as a tracker following the stack does),
    then seen again clear of him."""
    front = _walk(frames)[:, 0]
    behind = front.copy()
    behind[:, 3] = 100.0
    behind[:, 0] += np.linspace(20.0, 0.0, frames)  # the box's centre drifts from +20 px to his centre
    behind[:, 0] += (front[:, 2] - behind[:, 2]) / 2
    status = [("tracked", "hidden" if t < 8 else "tracked") for t in range(frames)]
    return np.stack([front, behind], axis=1), status


def test_start_offsets_are_measured_in_the_hidden_dancer_s_box_heights():
    boxes, _ = _stack()
    assert start_offsets(boxes, [(0, 1, 0)]) == {(1, 0): (0, pytest.approx(0.2))}
    assert start_offsets(boxes, []) == {}
    gone = boxes.copy()
    gone[0, 0] = np.nan  # no box in front at the start frame: no offset
    assert start_offsets(gone, [(0, 1, 0)]) == {}


def test_a_hidden_dancer_s_box_moves_part_of_the_way_back_to_its_start_offset():
    """Only frames with status "hidden" move, sideways only, by ``weight`` of the gap between the box's offset
    from the front dancer's box and the start offset; weight 1 restores the start offset, 0 changes nothing."""
    boxes, status = _stack()
    offsets = start_offsets(boxes, [(0, 1, 0)])
    moved = keep_start_offset(boxes, status, offsets, weight=0.25)
    centre = lambda b: b[..., 0] + b[..., 2] / 2  # noqa: E731
    gap = 20.0 - (centre(boxes[:, 1]) - centre(boxes[:, 0]))  # px, start offset minus offset now
    np.testing.assert_allclose(centre(moved[:8, 1]) - centre(boxes[:8, 1]), 0.25 * gap[:8])
    np.testing.assert_array_equal(moved[8:], boxes[8:])  # seen again: not moved
    np.testing.assert_array_equal(moved[:, 0], boxes[:, 0])  # the front dancer is not moved
    np.testing.assert_array_equal(moved[..., 1:], boxes[..., 1:])  # sideways only
    full = keep_start_offset(boxes, status, offsets, weight=1.0)
    np.testing.assert_allclose(centre(full[:8, 1]) - centre(full[:8, 0]), 20.0)
    np.testing.assert_array_equal(keep_start_offset(boxes, status, offsets, weight=0.0), boxes)
    np.testing.assert_array_equal(keep_start_offset(boxes, status, {}), boxes)
    with pytest.raises(ValueError, match="weight"):
        keep_start_offset(boxes, status, offsets, weight=1.5)


def test_a_hidden_dancer_without_a_box_in_front_keeps_its_box():
    boxes, status = _stack()
    offsets = start_offsets(boxes, [(0, 1, 0)])
    boxes[3:5, 0] = np.nan  # the front dancer left the frame for two frames
    moved = keep_start_offset(boxes, status, offsets)
    np.testing.assert_array_equal(moved[3:5], boxes[3:5])
    assert (moved[[1, 2, 5, 6, 7], 1, 0] != boxes[[1, 2, 5, 6, 7], 1, 0]).all()



def test_start_feet_are_the_bottoms_of_both_boxes_at_the_start():
    boxes, _ = _stack()
    front, behind = boxes[0, 0], boxes[0, 1]
    assert start_feet(boxes, [(0, 1, 0)]) == {(1, 0): (0, pytest.approx(behind[1] + behind[3]),
                                                       pytest.approx(front[1] + front[3]))}
    gone = boxes.copy()
    gone[0, 1] = np.nan
    assert start_feet(gone, [(0, 1, 0)]) == {} and start_feet(boxes, []) == {}


def test_a_waiting_dancer_s_feet_stay_near_where_the_front_dancer_s_feet_put_them():
    """On its hidden frames a waiting dancer's box moves up or down only as far as needed to bring its bottom
    within ``tolerance`` x its height (100 px here) of its start bottom moved by the front dancer's: with 0.25 a box
    that slid 60 px down ends 25 px below (20 px with the default, 0.2), one 10 px off is left alone, and when the
    front dancer walks 30 px down the image (towards the camera) the dancer behind is expected 30 px lower too.
    Frames seen, the front dancer and the box's size and sideways place are not changed; an infinite tolerance
    changes nothing."""
    boxes, status = _stack()
    feet = start_feet(boxes, [(0, 1, 0)])
    start_bottom = boxes[0, 1, 1] + boxes[0, 1, 3]
    slid = boxes.copy()
    slid[2:5, 1, 1] += 60.0  # its tracker slid down off the stack
    slid[5, 1, 1] += 10.0
    slid[6:8, 0, 1] += 30.0  # the front dancer comes 30 px nearer the camera
    kept = keep_feet_behind_front(slid, status, feet, tolerance=0.25)
    bottom = kept[:, 1, 1] + kept[:, 1, 3]
    front_moved = slid[:, 0, 1] + slid[:, 0, 3] - (boxes[0, 0, 1] + boxes[0, 0, 3])  # px down since the start
    expected = start_bottom + front_moved
    np.testing.assert_allclose(bottom[2:5], expected[2:5] + 25.0)
    np.testing.assert_allclose(bottom[5], slid[5, 1, 1] + slid[5, 1, 3])  # within 25 px: left alone
    assert abs(bottom[5] - expected[5]) < 25.0
    np.testing.assert_allclose(bottom[6:8], expected[6:8] - 25.0)  # it stood still: pulled down to 25 px above
    assert (front_moved[6:8] > 29.0).all()
    np.testing.assert_array_equal(kept[8:], slid[8:])  # seen again
    np.testing.assert_array_equal(kept[:, 0], slid[:, 0])
    np.testing.assert_array_equal(kept[..., [0, 2, 3]], slid[..., [0, 2, 3]])
    np.testing.assert_array_equal(keep_feet_behind_front(slid, status, feet, tolerance=np.inf), slid)
    np.testing.assert_array_equal(keep_feet_behind_front(slid, status, {}), slid)
    # the default, HIDDEN_FEET_TOLERANCE (0.2 since session 73; 0.25 before): 20 px
    default = keep_feet_behind_front(slid, status, feet)
    np.testing.assert_allclose(default[2:5, 1, 1] + default[2:5, 1, 3], expected[2:5] + 20.0)
    assert HIDDEN_FEET_TOLERANCE == 0.2
    with pytest.raises(ValueError, match="tolerance"):
        keep_feet_behind_front(slid, status, feet, tolerance=-0.1)


def test_a_wait_that_ends_seen_is_filled_by_a_line_from_the_start_to_the_first_sighting():
    """A dancer waiting hidden from frame 0 and seen at frame 8: frames 1-7 lie on the straight line (centre and
    size) from its frame-0 box to its frame-8 box; half way with weight 0.5; unchanged with weight 0, for a wait
    never followed by a sighting, and for the front dancer and the frames seen."""
    boxes, status = _stack()
    boxes[8:, 1, 0] += 40.0  # it comes out 40 px further right than its box had drifted
    filled = fill_hidden_until_seen(boxes, status, [(0, 1, 0)])
    np.testing.assert_allclose(filled[1:8, 1], interpolate_boxes(boxes[0, 1], boxes[8, 1], 7))
    np.testing.assert_array_equal(filled[[0, 8, 9, 10, 11], 1], boxes[[0, 8, 9, 10, 11], 1])
    np.testing.assert_array_equal(filled[:, 0], boxes[:, 0])
    half = fill_hidden_until_seen(boxes, status, [(0, 1, 0)], weight=0.5)
    np.testing.assert_allclose(half[1:8, 1], (boxes[1:8, 1] + filled[1:8, 1]) / 2)
    np.testing.assert_array_equal(fill_hidden_until_seen(boxes, status, [(0, 1, 0)], weight=0.0), boxes)
    never_seen = [("tracked", "hidden")] * len(boxes)
    np.testing.assert_array_equal(fill_hidden_until_seen(boxes, never_seen, [(0, 1, 0)]), boxes)
    np.testing.assert_array_equal(fill_hidden_until_seen(boxes, status, []), boxes)
    with pytest.raises(ValueError, match="weight"):
        fill_hidden_until_seen(boxes, status, [(0, 1, 0)], weight=2.0)


def test_a_dancer_waiting_longer_than_its_walk_stands_behind_the_front_dancer_then_walks_out():
    """Seen at frame 8 after waiting from frame 0, with a walk of 3 frames: frames 1-4 keep their boxes (it stood
    behind the dancer in front), frames 5-7 lie on the line from the frame-4 box to the frame-8 box; a walk as long
    as the wait or longer draws the line from the start box; an unknown box where the walk begins draws it from the
    start box too; a walk under 1 frame is refused; ``apply_hindsight`` passes the setting on."""
    boxes, status = _stack()
    boxes[8:, 1, 0] += 40.0
    walked = fill_hidden_until_seen(boxes, status, [(0, 1, 0)], walk_frames=3)
    np.testing.assert_array_equal(walked[:5, 1], boxes[:5, 1])
    np.testing.assert_allclose(walked[5:8, 1], interpolate_boxes(boxes[4, 1], boxes[8, 1], 3))
    np.testing.assert_array_equal(walked[8:], boxes[8:])
    np.testing.assert_array_equal(walked[:, 0], boxes[:, 0])
    whole = fill_hidden_until_seen(boxes, status, [(0, 1, 0)], walk_frames=7)
    np.testing.assert_allclose(whole[1:8, 1], interpolate_boxes(boxes[0, 1], boxes[8, 1], 7))
    np.testing.assert_array_equal(fill_hidden_until_seen(boxes, status, [(0, 1, 0)], walk_frames=100), whole)
    unknown = boxes.copy()
    unknown[4, 1] = np.nan
    from_start = fill_hidden_until_seen(unknown, status, [(0, 1, 0)], walk_frames=3)
    line = interpolate_boxes(boxes[0, 1], boxes[8, 1], 7)
    np.testing.assert_allclose(from_start[[1, 2, 3, 5, 6, 7], 1], line[[0, 1, 2, 4, 5, 6]])
    assert np.isnan(from_start[4, 1]).all()
    with pytest.raises(ValueError, match="walk_frames"):
        fill_hidden_until_seen(boxes, status, [(0, 1, 0)], walk_frames=0)
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    short, long_ = (apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                                    settings=HindsightSettings(hidden_walk_frames=k))[0] for k in (3, 100))
    assert np.abs(short[1:5, 1] - long_[1:5, 1]).max() > 1.0

def test_a_wait_never_followed_by_a_sighting_is_pulled_towards_the_start_place():
    """A dancer waiting hidden to the end of the video (or whose wait ends occluded, or out of the frame) while its
    box drifts onto the dancer in front: each box of the wait moves sideways ``weight`` of the way from its centre to
    its start box's centre (size, height and top kept); weight 1 holds it at the start place, 0 moves nothing. A wait
    that ends seen is left alone (:func:`fill_hidden_until_seen` draws its line), and so are the front dancer and
    frames without a box. The start box may be read from other boxes (the online ones)."""
    boxes, _ = _stack()
    never_seen = [("tracked", "hidden")] * len(boxes)
    start_cx = boxes[0, 1, 0] + boxes[0, 1, 2] / 2
    centre = boxes[:, 1, 0] + boxes[:, 1, 2] / 2
    kept = keep_start_place(boxes, never_seen, [(0, 1, 0)], weight=0.5)
    np.testing.assert_allclose(kept[1:, 1, 0] + kept[1:, 1, 2] / 2, (centre[1:] + start_cx) / 2)
    np.testing.assert_array_equal(kept[:, 1, 1:], boxes[:, 1, 1:])
    np.testing.assert_array_equal(kept[:, 0], boxes[:, 0])
    assert abs(kept[-1, 1, 0] - boxes[0, 1, 0]) == pytest.approx(abs(boxes[-1, 1, 0] - boxes[0, 1, 0]) / 2)
    held = keep_start_place(boxes, never_seen, [(0, 1, 0)], weight=1.0)
    np.testing.assert_allclose(held[:, 1, 0], np.full(len(boxes), boxes[0, 1, 0]))
    np.testing.assert_array_equal(keep_start_place(boxes, never_seen, [(0, 1, 0)], weight=0.0), boxes)
    ends_occluded = [("tracked", "hidden" if t < 8 else "occluded") for t in range(len(boxes))]
    np.testing.assert_allclose(keep_start_place(boxes, ends_occluded, [(0, 1, 0)], weight=1.0)[1:8, 1, 0],
                               np.full(7, boxes[0, 1, 0]))
    np.testing.assert_array_equal(keep_start_place(boxes, ends_occluded, [(0, 1, 0)])[8:], boxes[8:])
    _, ends_seen = _stack()
    np.testing.assert_array_equal(keep_start_place(boxes, ends_seen, [(0, 1, 0)]), boxes)
    np.testing.assert_array_equal(keep_start_place(boxes, never_seen, []), boxes)
    gaps = boxes.copy()
    gaps[5, 1] = np.nan
    assert np.isnan(keep_start_place(gaps, never_seen, [(0, 1, 0)])[5, 1]).all()
    elsewhere = boxes.copy()
    elsewhere[0, 1, 0] += 30.0  # the start box read from other boxes
    np.testing.assert_allclose(keep_start_place(boxes, never_seen, [(0, 1, 0)], 1.0, start_boxes=elsewhere)[1:, 1, 0],
                               np.full(len(boxes) - 1, elsewhere[0, 1, 0]))
    again = keep_start_place(boxes, never_seen, [(0, 1, 0), (6, 1, 0)], weight=1.0)  # corrected behind him at 6
    np.testing.assert_array_equal(again[1:7, 1], boxes[1:7, 1])
    np.testing.assert_allclose(again[7:, 1, 0], np.full(len(boxes) - 7, boxes[6, 1, 0]))
    with pytest.raises(ValueError, match="weight"):
        keep_start_place(boxes, never_seen, [(0, 1, 0)], weight=1.5)
    with pytest.raises(ValueError, match="start_boxes"):
        keep_start_place(boxes, never_seen, [(0, 1, 0)], start_boxes=boxes[:3])


def test_apply_hindsight_pulls_a_wait_never_seen_towards_the_start_place_last():
    """``apply_hindsight`` on a wait never followed by a sighting: its other steps' boxes, then
    :func:`keep_start_place` towards the online start box with ``start_place_weight`` (0: off)."""
    boxes, _ = _stack()
    never_seen = [("tracked", "hidden")] * len(boxes)
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    off = apply_hindsight(boxes, never_seen, keypoints, hidden_starts=[(0, 1, 0)],
                          settings=HindsightSettings(start_place_weight=0.0))[0]
    kept = apply_hindsight(boxes, never_seen, keypoints, hidden_starts=[(0, 1, 0)])[0]
    np.testing.assert_allclose(kept, keep_start_place(off, never_seen, [(0, 1, 0)], START_PLACE_WEIGHT,
                                                      start_boxes=boxes))
    assert np.abs(kept[1:, 1, 0] - off[1:, 1, 0]).max() > 1.0


def test_a_wait_the_online_tracker_sent_back_behind_the_front_dancer_is_not_pulled_to_the_start_place():
    """A wait in some frame of which the online tracker found the waiting dancer's box on the empty floor and put it
    back behind the dancer in front (``returned``, ``TrackRun.returned_behind``) keeps its boxes: her start place
    showed nobody, so she had not stayed there. Another dancer's mark, or none, changes nothing; in
    ``apply_hindsight`` ``keep_returned=False`` pulls it as before. A mask of the wrong shape is a clear error."""
    boxes, _ = _stack()
    never_seen = [("tracked", "hidden")] * len(boxes)
    returned = np.zeros(boxes.shape[:2], bool)
    returned[6, 1] = True
    np.testing.assert_array_equal(keep_start_place(boxes, never_seen, [(0, 1, 0)], returned=returned), boxes)
    pulled = keep_start_place(boxes, never_seen, [(0, 1, 0)])
    assert np.abs(pulled[1:, 1, 0] - boxes[1:, 1, 0]).max() > 1.0
    other = np.zeros(boxes.shape[:2], bool)
    other[6, 0] = True
    np.testing.assert_array_equal(keep_start_place(boxes, never_seen, [(0, 1, 0)], returned=other), pulled)
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    kept, without = (apply_hindsight(boxes, never_seen, keypoints, hidden_starts=[(0, 1, 0)], returned_behind=returned,
                                     settings=HindsightSettings(keep_returned=k))[0] for k in (True, False))
    off = apply_hindsight(boxes, never_seen, keypoints, hidden_starts=[(0, 1, 0)],
                          settings=HindsightSettings(start_place_weight=0.0))[0]
    np.testing.assert_allclose(kept, off)
    assert np.abs(without[1:, 1, 0] - kept[1:, 1, 0]).max() > 1.0
    with pytest.raises(ValueError, match="returned"):
        keep_start_place(boxes, never_seen, [(0, 1, 0)], returned=returned[:3])


def test_apply_hindsight_keeps_a_hidden_start_s_offset_after_the_other_steps():
    """``apply_hindsight`` with the hidden starts moves the hidden frames of the boxes its other steps wrote, with
    the start offsets of the online boxes it was given; without them nothing moves."""
    boxes, status = _stack()
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    plain, filled = apply_hindsight(boxes, status, keypoints)
    kept, filled_too = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)])
    np.testing.assert_array_equal(filled, filled_too)
    np.testing.assert_allclose(kept, fill_hidden_until_seen(keep_feet_behind_front(
        keep_start_offset(plain, status, {(1, 0): (0, 0.2)}, START_OFFSET_WEIGHT), status,
        start_feet(boxes, [(0, 1, 0)]), HIDDEN_FEET_TOLERANCE), status, [(0, 1, 0)], HIDDEN_FILL_WEIGHT))
    assert np.abs(kept[:8, 1, 0] - plain[:8, 1, 0]).max() > 1.0


def test_apply_hindsight_takes_its_steps_settings():
    """The default settings are the module's; other settings reach their steps (with the wait's fill off, a
    start-offset weight of 0 moves nothing, a weight of 1 moves the hidden dancer all the way to its start offset; the
    fill's weight reaches its step)."""
    boxes, status = _stack()
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    default = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)])[0]
    np.testing.assert_array_equal(default, apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                                                           settings=HindsightSettings())[0])
    plain = apply_hindsight(boxes, status, keypoints)[0]
    none = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                           settings=HindsightSettings(start_offset_weight=0.0, hidden_fill_weight=0.0))[0]
    np.testing.assert_allclose(none, plain)
    full = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                           settings=HindsightSettings(start_offset_weight=1.0, hidden_fill_weight=0.0))[0]
    np.testing.assert_allclose(full, keep_start_offset(plain, status, {(1, 0): (0, 0.2)}, 1.0))
    half = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                           settings=HindsightSettings(hidden_fill_weight=0.5))[0]
    unfilled = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                               settings=HindsightSettings(hidden_fill_weight=0.0))[0]
    np.testing.assert_allclose(half, fill_hidden_until_seen(unfilled, status, [(0, 1, 0)], 0.5))


def test_a_dancer_hidden_again_from_a_later_start_keeps_the_offset_of_that_start():
    """A dancer with two hidden starts (its start, then a user's correction behind the same dancer) is held at
    the offset of the latest start before each hidden frame."""
    boxes, _ = _stack()
    status = [("tracked", "hidden") for _ in range(len(boxes))]
    later = 5
    boxes[later:, 1, 0] += 10.0  # from frame 5 on it stands further right
    offsets = start_offsets(boxes, [(0, 1, 0), (later, 1, 0)])
    assert set(offsets) == {(1, 0), (1, later)} and offsets[(1, later)][1] > offsets[(1, 0)][1]
    full = keep_start_offset(boxes, status, offsets, weight=1.0)
    centre = lambda b: b[..., 0] + b[..., 2] / 2  # noqa: E731
    gap = centre(full[:, 1]) - centre(full[:, 0])
    np.testing.assert_allclose(gap[:later], offsets[(1, 0)][1] * boxes[:later, 1, 3])
    np.testing.assert_allclose(gap[later:], offsets[(1, later)][1] * boxes[later:, 1, 3])


def _couple_coming_nearer(frames: int = 40) -> tuple[np.ndarray, list[tuple[str, str]], np.ndarray]:
    """A couple walking from 7 m to 4.5 m in front of a level pinhole camera (focal 500 px, 1.4 m high, horizon at
    row 180 px): dancer 0 (1.8 m) in front, dancer 1 (1.6 m) 0.4 m behind him, hidden all along. Returns the boxes as a
    tracker has them (hers keep her start size while her feet follow his down the image, as
    :func:`keep_feet_behind_front` leaves them), the status and her true boxes."""
    def box(depth, stature):
        height, bottom = 500.0 * stature / depth, 180.0 + 500.0 * 1.4 / depth
        return np.array([300.0 - 0.2 * height, bottom - height, 0.4 * height, height])

    depths = np.linspace(7.0, 4.5, frames)
    front = np.stack([box(z, 1.8) for z in depths])
    truth = np.stack([box(z + 0.4, 1.6) for z in depths])
    tracked = truth.copy()
    tracked[:, 2:] = truth[0, 2:]  # her start size
    tracked[:, 0] = truth[:, 0] + (truth[:, 2] - truth[0, 2]) / 2  # her centre
    tracked[:, 1] = truth[:, 1] + truth[:, 3] - truth[0, 3]  # her feet
    return np.stack([front, tracked], axis=1), [("tracked", "hidden")] * frames, truth


def test_a_waiting_dancer_s_box_grows_as_her_feet_come_down_the_image():
    """With the horizon at row 180 px her box is given her start height times :func:`depth_scale` of her bottom:
    her true size, as the couple comes nearer; bottom and centre kept, width scaled alike. Limits clip the scale; a
    horizon at ``-inf``, the dancer in front and frames seen are not changed."""
    boxes, status, truth = _couple_coming_nearer()
    feet = start_feet(boxes, [(0, 1, 0)])
    scaled = scale_with_depth(boxes, status, feet, 180.0)
    np.testing.assert_allclose(scaled[:, 1, 3], truth[:, 3], rtol=1e-9)
    np.testing.assert_allclose(scaled[:, 1, 2], truth[:, 2], rtol=1e-9)
    np.testing.assert_allclose(scaled[:, 1, 1] + scaled[:, 1, 3], boxes[:, 1, 1] + boxes[:, 1, 3])
    np.testing.assert_allclose(scaled[:, 1, 0] + scaled[:, 1, 2] / 2, boxes[:, 1, 0] + boxes[:, 1, 2] / 2)
    np.testing.assert_array_equal(scaled[:, 0], boxes[:, 0])
    assert truth[-1, 3] / truth[0, 3] > 1.4  # a real change of size
    clipped = scale_with_depth(boxes, status, feet, 180.0, limits=(0.9, 1.1))
    assert clipped[:, 1, 3].max() == pytest.approx(1.1 * boxes[0, 1, 3])
    np.testing.assert_array_equal(scale_with_depth(boxes, status, feet, -np.inf), boxes)
    seen = [("tracked", "tracked")] * len(boxes)
    np.testing.assert_array_equal(scale_with_depth(boxes, seen, feet, 180.0), boxes)
    # her start box against the horizon gives 1.6 / 1.4 px of height per px of feet below it; dancers seen with a
    # ratio within 1.5 times that let her be scaled, others (the horizon and her start disagree) leave her as she is
    np.testing.assert_array_equal(scale_with_depth(boxes, status, feet, 180.0, seen_ratio=1.8 / 1.4), scaled)
    np.testing.assert_array_equal(scale_with_depth(boxes, status, feet, 180.0, seen_ratio=1.6 / 1.4 * 1.6), boxes)
    np.testing.assert_array_equal(scale_with_depth(boxes, status, feet, 180.0, seen_ratio=1.6 / 1.4 / 1.6), boxes)
    np.testing.assert_array_equal(scale_with_depth(boxes, status, feet, 180.0, seen_ratio=1.6 / 1.4 * 1.6,
                                                   stature_factor=1.7), scaled)
    with pytest.raises(ValueError, match="limits"):
        scale_with_depth(boxes, status, feet, 180.0, limits=(1.2, 1.6))
    with pytest.raises(ValueError, match="stature_factor"):
        scale_with_depth(boxes, status, feet, 180.0, stature_factor=0.5)
    with pytest.raises(ValueError, match="start_boxes"):
        scale_with_depth(boxes, status, feet, 180.0, start_boxes=boxes[:3])


def test_apply_hindsight_scales_a_waiting_dancer_with_the_horizon_the_seen_dancers_show():
    """``apply_hindsight`` fits the horizon to the dancer seen walking nearer and scales the waiting dancer's box
    with it (``HindsightSettings.scale_with_depth``, on by default): her boxes come far nearer her true size."""
    boxes, status, truth = _couple_coming_nearer()
    keypoints = np.full(boxes.shape[:2] + (25, 3), np.nan)
    keypoints[..., 2] = 0
    off = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                          settings=HindsightSettings(scale_with_depth=False))[0]
    scaled = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)])[0]
    error_off, error = np.abs(off[:, 1, 3] - truth[:, 3]), np.abs(scaled[:, 1, 3] - truth[:, 3])
    assert error_off.max() > 30.0 and error.max() < 0.1 * error_off.max()
    np.testing.assert_array_equal(scaled[:, 0], off[:, 0])


def _couple_in_hold(frames: int = 10):
    """A couple: (frames, 2, 4) px boxes of the dancer in front (0: coming nearer and spreading his arms, 4 px
    taller and 10 px wider a frame) and of his partner waiting hidden behind him (1: her start box, held by her own
    tracker), their (frames, 2) status, and BODY_25 keypoints: his 17 COCO-17 joints seen (confidence 0.9) but on
    frame 5, none of hers but 5 on frame 7."""
    t = np.arange(frames, dtype=float)
    front = np.stack([100 - 5 * t, 50 - 2 * t, 60 + 10 * t, 200 + 4 * t], axis=1)
    behind = np.tile([120.0, 80.0, 40.0, 160.0], (frames, 1))
    status = [("tracked", "hidden")] * frames
    keypoints = np.zeros((frames, 2, 25, 3))
    keypoints[..., :2] = 150.0
    keypoints[:, 0, :19, 2] = 0.9  # the 15 body joints and the 4 ears and eyes of BODY_25: all of COCO-17
    keypoints[5, 0, :, 2] = 0.0
    keypoints[7, 1, :5, 2] = 0.9
    return np.stack([front, behind], axis=1), status, keypoints


def test_a_couple_s_hidden_partner_is_carried_with_the_dancer_in_front():
    """Her box is his box mapped as his start box maps onto hers: frame 4, his box (80, 42, 100, 216), 1.08 his
    start height: height 160 x 1.08, width 100 x 40 / 60 (her start width over his), centre 10 px right of his and
    bottom 10 px above his, each x 1.08. Frames where his whole pose is not seen (5) or hers is (7) keep her box, and
    so do his boxes, other dancers' and the frames where she is seen. His height frame by frame
    (``scale_window`` 0; his box grows steadily here)."""
    boxes, status, keypoints = _couple_in_hold()
    carried = follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints, scale_window=0)
    np.testing.assert_allclose(carried[4, 1], [140.8 - 100 / 3, 74.4, 200 / 3, 172.8])
    np.testing.assert_allclose(carried[0, 1], boxes[0, 1])  # at her start, her start box
    np.testing.assert_array_equal(carried[[5, 7], 1], boxes[[5, 7], 1])
    np.testing.assert_array_equal(carried[:, 0], boxes[:, 0])
    assert carried[9, 1, 2] > 1.5 * boxes[9, 1, 2]  # her arms spread with his
    seen = [("tracked", "hidden")] * 3 + [("tracked", "tracked")] * 7
    np.testing.assert_array_equal(follow_partner_in_hold(boxes, seen, [(0, 1, 0)], keypoints)[3:], boxes[3:])
    np.testing.assert_array_equal(follow_partner_in_hold(boxes, status, [], keypoints), boxes)


def test_a_couple_s_hidden_partner_keeps_her_height_while_his_box_loses_his_raised_arms():
    """His box (refined or not) drops his raised arms on two frames, 40 px shorter with its bottom where it was
    (2950 tango): carried with his height frame by frame (``scale_window`` 0), her box shrinks to 0.8 of her height
    there; with the median of his heights over 3 frames on each side it keeps her start box throughout."""
    frames = 10
    front = np.tile([100.0, 50.0, 60.0, 200.0], (frames, 1))
    front[4:6, 1] += 40.0
    front[4:6, 3] -= 40.0
    behind = np.tile([120.0, 80.0, 40.0, 160.0], (frames, 1))
    boxes = np.stack([front, behind], axis=1)
    status = [("tracked", "hidden")] * frames
    keypoints = np.zeros((frames, 2, 25, 3))
    keypoints[..., :2] = 150.0
    keypoints[:, 0, :19, 2] = 0.9  # all of his COCO-17 joints seen
    each = follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints, scale_window=0)
    np.testing.assert_allclose(each[4, 1, 3], 0.8 * 160.0)
    steady = follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints, scale_window=3)
    np.testing.assert_allclose(steady[:, 1], behind)
    np.testing.assert_array_equal(steady[:, 0], front)
    with pytest.raises(ValueError, match="scale_window"):
        follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints, scale_window=-1)


def test_only_a_couple_s_hidden_partner_is_carried():
    """With a third dancer (a group: the dancer in front spreads his arms on his own) nothing changes, for a dancer
    waiting hidden since her start or occluded after being seen."""
    boxes, status, keypoints = _couple_in_hold()
    trio = np.concatenate([boxes, boxes[:, :1] + [300, 0, 0, 0]], axis=1)
    trio_keypoints = np.concatenate([keypoints, keypoints[:, :1]], axis=1)
    trio_status = [row + ("tracked",) for row in status]
    np.testing.assert_array_equal(follow_partner_in_hold(trio, trio_status, [(0, 1, 0)], trio_keypoints), trio)
    occluded_status = [("tracked", "tracked", "tracked")] * 3 + [("tracked", "occluded", "tracked")] * 7
    np.testing.assert_array_equal(follow_partner_in_hold(trio, occluded_status, [], trio_keypoints), trio)
    with pytest.raises(ValueError, match="front_joints"):
        follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints, front_joints=0)


def test_apply_hindsight_carries_a_couple_s_hidden_partner_last():
    """``HindsightSettings.follow_partner`` (on by default) ends ``apply_hindsight`` with
    :func:`follow_partner_in_hold` on the boxes of its other steps; off, her box is those steps' alone."""
    boxes, status, keypoints = _couple_in_hold()
    off = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)],
                          settings=HindsightSettings(follow_partner=False))[0]
    on = apply_hindsight(boxes, status, keypoints, hidden_starts=[(0, 1, 0)])[0]
    np.testing.assert_allclose(on, follow_partner_in_hold(off, status, [(0, 1, 0)], keypoints))
    assert np.abs(on[:, 1] - off[:, 1]).max() > 10.0


def test_a_couple_s_waiting_partner_with_a_pose_of_her_own_is_centred_on_her_torso():
    """On frame 7 she shows a pose (5 keypoints, neck and right shoulder among them): where its torso lies 50 px from
    his (more than 0.1 of her height), her box is moved sideways onto it, size and height kept; where it lies on his
    (Algorithm 2* gave her his pose) it is left as it was."""
    boxes, status, keypoints = _couple_in_hold()
    own = keypoints.copy()
    own[7, 1, :, 0] = 200.0
    centred = follow_partner_in_hold(boxes, status, [(0, 1, 0)], own)
    np.testing.assert_allclose(centred[7, 1], [180.0, 80.0, 40.0, 160.0])
    np.testing.assert_array_equal(follow_partner_in_hold(boxes, status, [(0, 1, 0)], keypoints)[7, 1], boxes[7, 1])
    own[7, 0, :, 2] = 0.0  # his torso unseen: hers is her own
    np.testing.assert_allclose(follow_partner_in_hold(boxes, status, [(0, 1, 0)], own)[7, 1], [180, 80, 40, 160])


def _couple_occluded(seen_again: bool):
    """The couple of :func:`_couple_in_hold`, but she is seen (status ``tracked``, box (120, 80, 40, 160)) on frames
    0-2 and occluded from frame 3, to the end or (``seen_again``) until frame 7, where she is seen where the couple
    moved her (her box at frame 2 carried with his) but 20 px further right."""
    boxes, _, keypoints = _couple_in_hold()
    keypoints[5, 0, :, 2] = 0.9
    boxes[:, 1] = [120.0, 80.0, 40.0, 160.0]
    status = [("tracked", "tracked")] * 3 + [("tracked", "occluded")] * 7
    if seen_again:
        status[7:] = [("tracked", "tracked")] * 3
        his2, his7 = boxes[2, 0], boxes[7, 0]
        scale = his7[3] / his2[3]
        centre = his7[0] + his7[2] / 2 + 10 * scale + 20
        height, width = 160 * scale, his7[2] / 2
        boxes[7:, 1] = [centre - width / 2, his7[1] + his7[3] - 14 * scale - height, width, height]
    return boxes, status, keypoints


def test_a_couple_s_occluded_partner_is_carried_with_the_dancer_in_front():
    """Occluded after frame 2, to the end: frame 4, his box (80, 42, 100, 216), 216 / 208 his height at frame 2: her
    centre 10 px right of his and bottom 14 px above his, each x 216 / 208, height 160 x 216 / 208, width 100 x 40 / 80
    (hers over his at frame 2). Seen again at frame 7, 20 px right of where the couple would have carried her: the
    stretch blends towards that: at frame 6, 4 / 5 of the way to 20 px right, scaled with his height (224 / 228). His
    height frame by frame (``scale_window`` 0)."""
    boxes, status, keypoints = _couple_occluded(seen_again=False)
    carried = follow_partner_in_hold(boxes, status, [], keypoints, scale_window=0)
    np.testing.assert_allclose(carried[4, 1], [115.3846, 77.3077, 50.0, 166.1538], rtol=1e-5)
    np.testing.assert_array_equal(carried[:3], boxes[:3])
    np.testing.assert_array_equal(carried[:, 0], boxes[:, 0])
    boxes_again, status_again, _ = _couple_occluded(seen_again=True)
    again = follow_partner_in_hold(boxes_again, status_again, [], keypoints, scale_window=0)
    np.testing.assert_allclose(again[6, 1], carried[6, 1] + [16.0 * 224 / 228, 0, 0, 0], rtol=1e-9)
    np.testing.assert_array_equal(again[7:], boxes_again[7:])
    unposed = keypoints.copy()
    unposed[4, 0, :, 2] = 0.0  # his pose not seen on frame 4: her box there as it was
    np.testing.assert_array_equal(follow_partner_in_hold(boxes, status, [], unposed)[4], boxes[4])
