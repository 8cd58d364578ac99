"""Overlapping dancers adapted together (:mod:`hdvr.tracking.groups`): unambiguous detections, group scaling."""

import numpy as np
import pytest

from hdvr.tracking.multi import OCCLUDED, MultiDancerTracker, MultiTrackerConfig
from hdvr.tracking.testclips import default_crossing_specs, render_clip
from hdvr.video import VideoReader


def test_overlapping_dancer_box_adapts_to_its_detection(tmp_path):
    """With ``adapt_in_groups``, a dancer overlapping another adapts its box to a detection that fits it clearly
    better than anyone else, and not to an ambiguous one."""
    truth = render_clip(tmp_path / "clip.mp4", frames=2, specs=default_crossing_specs(num_figures=2, seed=0))
    frames = list(VideoReader(tmp_path / "clip.mp4"))
    a = (300.0, 120.0, 80.0, 280.0)
    tracker = MultiDancerTracker(frames[0], [a, (330.0, 200.0, 60.0, 200.0)])
    d = tracker.dancers[0]
    wide = (285.0, 118.0, 140.0, 284.0)  # dancer 0 with spread arms: fits it, not the smaller dancer 1
    tracker._adapt_in_group(frames[1], [d], [wide, (332.0, 198.0, 58.0, 204.0)])
    assert d.box[2] > a[2] + 20  # half-way towards the detected width
    tracker2 = MultiDancerTracker(frames[0], [a, (305.0, 125.0, 78.0, 275.0)])
    before = tracker2.dancers[0].box
    tracker2._adapt_in_group(frames[1], [tracker2.dancers[0]], [wide])  # fits both dancers alike: ambiguous
    assert tracker2.dancers[0].box == before
    assert truth.boxes.shape == (2, 2, 4)


def test_a_couple_that_walks_away_together_shrinks_together():
    """Two dancers who overlap all along keep the box size they met with unless their group scales: as both
    detections shrink alike the boxes shrink with them, keeping their own size convention (a box 10 % larger than
    the detector's stays so); a change seen on one dancer's detection alone (cut by the one in front) scales
    nothing. (The second starts straight behind the first, so ``front_of_waiting_clear`` would make the first
    clear of it, not a group: off for the run through ``step``.)"""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    boxes = [(300.0, 100.0, 70.0, 250.0), (330.0, 110.0, 66.0, 220.0)]  # cores overlap: one group
    tracker = MultiDancerTracker(frame, boxes)
    group = list(tracker.dancers)
    assert len(tracker._groups(group)) == 1

    def detections(scale_a, scale_b):  # detector boxes 10 % smaller than the dancers' boxes, scaled about them
        out = []
        for (x, y, w, h), s in zip(boxes, (scale_a, scale_b)):
            cx, cy, dw, dh = x + w / 2, y + h / 2, w / 1.1 * s, h / 1.1 * s
            out.append((cx - dw / 2, cy - dh / 2, dw, dh))
        return out

    tracker._scale_groups(group, detections(1.0, 1.0))  # the first frame together only records the reference
    assert [d.box for d in tracker.dancers] == boxes
    for _ in range(20):
        tracker._scale_groups(group, detections(0.8, 0.8))
    for d, box in zip(tracker.dancers, boxes):
        assert d.box[3] == pytest.approx(0.8 * box[3], rel=0.02) and d.box[2] == pytest.approx(0.8 * box[2], rel=0.02)
        assert d.center == pytest.approx([box[0] + box[2] / 2, box[1] + box[3] / 2])  # about the centre
    alone = MultiDancerTracker(frame, boxes)
    alone._scale_groups(list(alone.dancers), detections(1.0, 1.0))
    for _ in range(5):
        alone._scale_groups(list(alone.dancers), detections(1.0, 0.7))  # only the one behind: cut, not receding
    assert [d.box for d in alone.dancers] == boxes
    alone._scale_groups([], detections(1.0, 1.0))  # apart: the reference is dropped
    assert all(d.group_reference is None for d in alone.dancers)
    heights = {}
    for rule in (True, False):  # through step(): the group scales with the rule, keeps its size without
        stepped = MultiDancerTracker(frame, boxes, MultiTrackerConfig(group_scale=rule, front_of_waiting_clear=False))
        for scale in (1.0,) + (0.8,) * 6:
            stepped.step(frame, detections(scale, scale))
        heights[rule] = [d.box[3] for d in stepped.dancers]
    assert all(h < 0.9 * b[3] for h, b in zip(heights[True], boxes)), heights[True]
    assert heights[False] == pytest.approx([b[3] for b in boxes], abs=1e-6)


def test_a_couple_seen_as_one_person_shrinks_with_that_person_box():
    """The detector often draws one person box over a couple in hold. When that one box holds both body cores and
    no other detection touches them, the couple's boxes scale as it does (``group_scale_shared``; seed 201 tango of
    hdvr synth, a couple receding from 285 to 205 px: IDF1 0.867 -> 1.000); a box over one dancer's core only, or
    a second detection on the group, scales nothing."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    boxes = [(300.0, 100.0, 70.0, 250.0), (330.0, 110.0, 66.0, 220.0)]  # cores overlap: one group

    def couple(scale):  # one box around both dancers, scaled about its centre
        x0, y0, x1, y1 = 295.0, 95.0, 401.0, 355.0
        cx, cy, w, h = (x0 + x1) / 2, (y0 + y1) / 2, (x1 - x0) * scale, (y1 - y0) * scale
        return [(cx - w / 2, cy - h / 2, w, h)]

    for config, dets, shrinks in ((MultiTrackerConfig(), couple, True),
                                  (MultiTrackerConfig(group_scale_shared=False), couple, False),
                                  (MultiTrackerConfig(), lambda s: [(290.0, 90.0, 60.0 * s, 270.0 * s)], False),
                                  (MultiTrackerConfig(), lambda s: couple(s) + [(340.0, 120.0, 40.0, 200.0)], False)):
        tracker = MultiDancerTracker(frame, boxes, config)
        group = list(tracker.dancers)
        tracker._scale_groups(group, dets(1.0))  # records the reference
        for _ in range(20):
            tracker._scale_groups(group, dets(0.8))
        heights = [d.box[3] for d in tracker.dancers]
        if shrinks:
            assert heights == pytest.approx([0.8 * b[3] for b in boxes], rel=0.02), heights
        else:
            assert heights == pytest.approx([b[3] for b in boxes]), heights
    # a group that held a detection each and then one shared box starts a new reference: no jump in between
    tracker = MultiDancerTracker(frame, boxes)
    group = list(tracker.dancers)
    own = [(b[0] + 3, b[1] + 10, b[2] - 6, b[3] - 20) for b in boxes]
    tracker._scale_groups(group, own)
    assert all(d.group_reference[2] is False for d in tracker.dancers)
    tracker._scale_groups(group, couple(1.0))
    assert all(d.group_reference[2] is True for d in tracker.dancers)
    assert [d.box for d in tracker.dancers] == boxes


def test_a_dancer_in_a_group_without_a_sure_detection_takes_its_weak_one(tmp_path):
    """In a group, weak detections are assigned after the sure ones, to the dancers that got none: a dancer takes
    its weak detection, and a weak one never displaces a sure one."""
    render_clip(tmp_path / "clip.mp4", frames=2, specs=default_crossing_specs(num_figures=2, seed=0))
    frames = list(VideoReader(tmp_path / "clip.mp4"))
    a, b = (300.0, 120.0, 80.0, 280.0), (330.0, 200.0, 60.0, 200.0)
    wide = (285.0, 118.0, 140.0, 284.0)  # dancer 0 with spread arms
    sure_b = (332.0, 198.0, 58.0, 204.0)
    tracker = MultiDancerTracker(frames[0], [a, b])
    assert tracker._unambiguous_detections([sure_b], [wide, (331.0, 190.0, 62.0, 215.0)]) == {0: wide, 1: sure_b}
    tracker._adapt_in_group(frames[1], tracker.dancers, [sure_b], [wide])
    assert tracker.dancers[0].box[2] > a[2] + 20


def test_a_dancer_in_front_of_a_hidden_one_scales_with_its_detection():
    """A couple walking towards the camera, one hidden behind the other since the start: the one in front overlaps
    the hidden one, so it is never clear to adapt to its detection, and a group needs two dancers followed. With
    ``group_scale_front`` a lone dancer whose overlapping dancers all wait hidden behind it since their start scales
    with its own detection as a group does (relative change, its box's size convention kept); without, it keeps its
    size, and so it does in front of a dancer occluded later (that one may come out any time) or of one hidden in
    front of it (lower in the image)."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    front, behind = (300.0, 120.0, 70.0, 250.0), (305.0, 100.0, 60.0, 210.0)

    def detection(scale):  # the front dancer's detector box, 10 % smaller than its box, scaled about it
        x, y, w, h = front
        cx, cy, dw, dh = x + w / 2, y + h / 2, w / 1.1 * scale, h / 1.1 * scale
        return [(cx - dw / 2, cy - dh / 2, dw, dh)]

    def scaled(rule=True, waiting=True, hidden_box=behind):
        tracker = MultiDancerTracker(frame, [front, hidden_box], MultiTrackerConfig(group_scale_front=rule))
        hidden = tracker.dancers[1]
        tracker._occlude(hidden, [tracker.dancers[0]])
        hidden.hidden_behind = tracker.dancers[0].dancer_id if waiting else None
        assert hidden.status == OCCLUDED
        group = [tracker.dancers[0]]
        tracker._scale_groups(group, detection(1.0))  # records the reference
        for _ in range(20):
            tracker._scale_groups(group, detection(1.2))
        return tracker.dancers[0].box

    box = scaled()
    assert box[3] == pytest.approx(1.2 * front[3], rel=0.02) and box[2] == pytest.approx(1.2 * front[2], rel=0.02)
    assert scaled(rule=False) == front
    assert scaled(waiting=False) == front
    assert scaled(hidden_box=(305.0, 160.0, 60.0, 250.0)) == front


def test_a_dancer_in_front_gets_up_from_the_floor_shape_its_box_kept_in_a_group():
    """A box that took a floor shape (wider than tall: a dancer down, or two dancers drawn as one person) keeps its
    aspect while it overlaps others (group scaling keeps it). When the dancer's unambiguous detection has shown an
    upright person on ``group_reshape_after`` detector frames in a row, and the dancer stands in front of every
    dancer it overlaps, the box takes the detection's aspect at its own height (hdvr synth seed 1512 hip-hop: a box
    206 x 171 px kept for 100 frames around a dancer 97 x 227 px)."""
    frame = np.random.default_rng(3).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    floor, behind = (250.0, 200.0, 200.0, 170.0), (300.0, 120.0, 60.0, 150.0)
    upright, behind_det = (300.0, 180.0, 100.0, 210.0), (300.0, 118.0, 62.0, 152.0)
    tracker = MultiDancerTracker(frame, [floor, behind], MultiTrackerConfig(group_reshape_after=2))
    front = tracker.dancers[0]
    tracker._reshape_in_group(tracker.dancers, [upright, behind_det])
    assert front.box == floor  # one detector frame is not enough
    tracker._reshape_in_group(tracker.dancers, [upright, behind_det])
    x, y, w, h = front.box
    assert (y, h) == (200.0, 170.0) and w == pytest.approx(170.0 * 100.0 / 210.0)
    assert x + w / 2 == pytest.approx(350.0)  # centred on the detection
    assert tracker.dancers[1].box == behind  # upright already, and behind the other
    # a box of an upright shape is not reshaped: spread arms change a dancer's width from frame to frame
    upright_box = (270.0, 200.0, 120.0, 170.0)
    tracker = MultiDancerTracker(frame, [upright_box, behind], MultiTrackerConfig(group_reshape_after=2))
    for _ in range(3):
        tracker._reshape_in_group(tracker.dancers, [(300.0, 180.0, 60.0, 210.0), behind_det])
    assert tracker.dancers[0].box == upright_box
    # nor that of a dancer with another standing in front of it (the detection may show only its part above)
    closer, further = (290.0, 160.0, 40.0, 230.0), (290.0, 140.0, 40.0, 200.0)  # box bottoms 20 px lower, 30 higher
    for other, reshaped in ((closer, False), (further, True)):
        tracker = MultiDancerTracker(frame, [floor, other], MultiTrackerConfig(group_reshape_after=2))
        for _ in range(2):  # the detection does not cover the other dancer's centre line: it is the floor dancer's
            tracker._reshape_in_group(tracker.dancers, [(335.0, 180.0, 90.0, 210.0), other])
        assert (tracker.dancers[0].box != floor) == reshaped, other


def test_the_dancer_in_front_of_a_group_follows_its_detection():
    """A dancer standing in front of every dancer it overlaps (box bottom lower) is seen whole, so with
    ``group_front_adapts`` its box follows its unambiguous detection in a group (its tracker had drifted 20 px up
    towards the partner behind: seed 3100 tango of the session-82 clips); the rule leaves the dancer behind as it
    was, and without it the front box stays where its tracker puts it."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    front, behind = (300.0, 130.0, 70.0, 250.0), (320.0, 100.0, 66.0, 220.0)
    detections = [(300.0, 150.0, 70.0, 250.0), behind]  # the front dancer's detection 20 px lower than its box
    moved = {}
    for rule in (0.5, None):
        tracker = MultiDancerTracker(frame, [front, behind],
                                     MultiTrackerConfig(group_front_adapts=rule, front_of_waiting_clear=False))
        boxes = tracker._boxes_now(tracker.dancers)
        assert [tracker._in_front_of_group(d, boxes) for d in tracker.dancers] == [True, False]
        for _ in range(6):
            tracker.step(frame, detections)
        moved[rule] = [np.subtract(d.box, b) for d, b in zip(tracker.dancers, (front, behind))]
    assert moved[0.5][0][1] > 15 and abs(moved[0.5][0][3]) < 2  # moved down, its height kept
    assert np.abs(moved[None][0]).max() < 5
    assert moved[0.5][1] == pytest.approx(moved[None][1])  # the rule leaves the dancer behind as it was


def test_what_of_the_front_box_follows_its_detection():
    """``group_front_parts``: "centre" moves the front box's centre towards its detection and keeps its size;
    "vertical" moves only the centre's height and the box's height; "height" only the height, the bottom kept; an
    unknown mode is refused. With ``group_front_match``, a box whose colours match the dancer's memory as well as
    its detection does stays; with ``group_front_after``, so does a box placed for sure fewer frames ago; with
    ``group_front_aspect``, so does one whose detection is narrower for its height; with ``group_front_max_iou``,
    one that overlaps its detection that much."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    front, behind = (300.0, 130.0, 70.0, 250.0), (320.0, 100.0, 66.0, 220.0)
    detection = (312.0, 150.0, 60.0, 230.0)  # centre 7 px right and 10 px lower, 20 px shorter

    def followed(**fields):
        tracker = MultiDancerTracker(frame, [front, behind], MultiTrackerConfig(group_front_adapts=1.0, **fields))
        d = tracker.dancers[0]
        tracker._adapt_front_in_group(frame, tracker.dancers, [detection, behind])
        return np.subtract(d.box, front)

    centre, vertical = followed(group_front_parts="centre"), followed(group_front_parts="vertical")
    assert centre[2:] == pytest.approx([0, 0]) and centre[:2] == pytest.approx([7, 10], abs=0.5)  # its size kept
    assert vertical[0] == pytest.approx(0) and vertical[2] == pytest.approx(0)  # nothing moves sideways
    assert vertical[3] == pytest.approx(-20, abs=0.5) and vertical[1] == pytest.approx(20, abs=0.5)  # centre +10
    height = followed(group_front_parts="height")
    assert height == pytest.approx([0, 20, 0, -20], abs=0.5)  # its bottom kept
    assert followed(group_front_match=0.5) == pytest.approx([0, 0, 0, 0])  # random colours: no better match
    assert followed(group_front_after=1) == pytest.approx([0, 0, 0, 0])  # placed for sure in this frame (its start)
    assert np.abs(followed(group_front_after=0)).max() > 5  # size and centre ("box", the default)
    assert followed(group_front_aspect=1.0) == pytest.approx([0, 0, 0, 0])  # 0.26 wide for its height, the box 0.28
    assert np.abs(followed(group_front_aspect=0.9)).max() > 5
    assert followed(group_front_max_iou=0.7) == pytest.approx([0, 0, 0, 0])  # IoU 0.74: a little off only
    assert np.abs(followed(group_front_max_iou=0.8)).max() > 5
    with pytest.raises(ValueError, match="group_front_parts"):
        MultiTrackerConfig(group_front_parts="feet")
