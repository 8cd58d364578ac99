"""A dancer's box adapted to its detection, and the foreground mask (:mod:`hdvr.tracking.adaptation`)."""

import numpy as np
import pytest

from hdvr.tracking.appearance import box_iou
from hdvr.tracking.multi import MultiDancerTracker, MultiTrackerConfig
from tracking_scenes import two_colour_frame, waiting_behind


def test_detection_cut_by_a_dancer_in_front_keeps_the_hidden_feet():
    """A detection of a dancer whose legs are hidden behind a dancer in front ends on that dancer's body: when the
    box adapts to it, the box keeps its bottom (the amodal extent); a detection cut anywhere else is taken as is."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    behind, front = (300.0, 100.0, 60.0, 200.0), (280.0, 180.0, 120.0, 260.0)  # front's feet lower in the image
    tracker = MultiDancerTracker(frame, [behind, front])
    d = tracker.dancers[0]
    cut = (302.0, 102.0, 58.0, 150.0)  # ends at y 252, on the front dancer's body
    assert tracker._feet_hidden(d, cut) == pytest.approx((302.0, 102.0, 58.0, 198.0))
    beside = (302.0, 102.0, 58.0, 150.0)
    tracker.dancers[1].box = (420.0, 180.0, 120.0, 260.0)  # the front dancer stands aside: nothing hides the legs
    assert tracker._feet_hidden(d, beside) == beside
    tracker.dancers[1].box = (280.0, 120.0, 120.0, 170.0)  # now it stands behind (feet higher): not hidden by it
    assert tracker._feet_hidden(d, cut) == cut
    off = MultiDancerTracker(frame, [behind, front], MultiTrackerConfig(keep_hidden_feet=False))
    off._adapt_box(off.dancers[0], frame, cut, weight=1.0, retrack=False)
    on = MultiDancerTracker(frame, [behind, front])
    on._adapt_box(on.dancers[0], frame, cut, weight=1.0, retrack=False)
    bottom = lambda box: box[1] + box[3]  # noqa: E731
    assert bottom(on.dancers[0].box) == pytest.approx(300.0) and off.dancers[0].box[3] == pytest.approx(150.0)


def test_detection_cut_sideways_by_a_dancer_in_front_keeps_the_hidden_side():
    """A partner behind the dancer in front shows only the part beside him: a detection narrower than her box whose
    side ends on his body keeps her box's width from the side seen (``keep_hidden_sides`` "tracked"; both sides on
    him: centred on it); one that ends clear of him, or a dancer standing behind her, is taken as is."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    behind, front = (260.0, 100.0, 110.0, 200.0), (300.0, 180.0, 120.0, 260.0)  # front's feet lower in the image
    config = MultiTrackerConfig(keep_hidden_sides="tracked")
    tracker = MultiDancerTracker(frame, [behind, front], config)
    d = tracker.dancers[0]
    cut = (262.0, 102.0, 60.0, 180.0)  # right side at x 322, on the front dancer's body
    assert tracker._sides_hidden(d, cut) == pytest.approx((262.0, 102.0, 110.0, 180.0))
    assert tracker._hidden_parts(d, cut) == pytest.approx((262.0, 102.0, 110.0, 198.0))  # and the feet
    cut_left = (330.0, 102.0, 50.0, 180.0)  # left side at x 330 on him, right side at 380 as well: centred
    assert tracker._sides_hidden(d, cut_left) == pytest.approx((300.0, 102.0, 110.0, 180.0))
    clear = (200.0, 102.0, 60.0, 180.0)  # ends at x 260, clear of him
    assert tracker._sides_hidden(d, clear) == clear
    tracker.dancers[1].box = (300.0, 120.0, 120.0, 170.0)  # now he stands behind her (feet higher): not hidden by him
    assert tracker._sides_hidden(d, cut) == cut
    off = MultiDancerTracker(frame, [behind, front])  # the default, "written", leaves the tracked box alone
    assert off.config.keep_hidden_sides == "written" and off._sides_hidden(off.dancers[0], cut) == cut
    on = MultiDancerTracker(frame, [behind, front], config)
    on.dancers[0].size_ratio, on.dancers[0].ratio_aspect = np.array([1.1, 1.0]), None  # box 1.1 x its detection
    for _ in range(3):  # adapting again and again keeps the width: the ratio is not applied on top of it each time
        on._adapt_box(on.dancers[0], frame, cut, weight=1.0, retrack=False)
    assert on.dancers[0].box[2] == pytest.approx(110.0)


def test_written_hidden_sides_widen_only_the_written_box():
    """With ``keep_hidden_sides`` "written" the tracked box of the partner behind follows the part seen beside the
    dancer in front, and only her written box reaches back behind him to the width she had (as an aspect of her
    height); a detection no longer cut, or the dancer in front gone from her box, ends it."""
    frame = np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    behind, front = (260.0, 100.0, 110.0, 200.0), (300.0, 180.0, 120.0, 260.0)  # front's feet lower in the image
    tracker = MultiDancerTracker(frame, [behind, front], MultiTrackerConfig(keep_hidden_sides="written"))
    d = tracker.dancers[0]
    d.size_ratio, d.ratio_aspect = np.array([1.0, 1.0]), None
    cut = (262.0, 102.0, 60.0, 180.0)  # right side at x 322, on the front dancer's body
    tracker._adapt_box(d, frame, cut, weight=1.0, retrack=False)
    assert d.box[2] == pytest.approx(60.0) and d.box[3] == pytest.approx(180.0)  # tracked: the part seen
    assert d.hidden_aspect == pytest.approx(110.0 / 200.0) and d.hidden_sides == (False, True)
    assert tracker._hidden_sides_reach(d) == pytest.approx([0.0, 0.0, 0.55 * 180.0 - 60.0, 0.0])
    written = tracker.extend_to_poses(frame, [None, None], [0.0, 0.0]).boxes[0]
    assert written[0] == pytest.approx(d.box[0]) and written[2] >= 0.55 * 180.0 - 1e-6  # reaches right, behind him
    assert MultiDancerTracker(frame, [behind, front]).result().boxes[0][2] == pytest.approx(110.0)
    off = MultiDancerTracker(frame, [behind, front], MultiTrackerConfig(keep_hidden_sides="off"))
    off.dancers[0].size_ratio, off.dancers[0].ratio_aspect = np.array([1.0, 1.0]), None
    off._adapt_box(off.dancers[0], frame, cut, weight=1.0, retrack=False)
    assert off.dancers[0].hidden_aspect is None and not any(off._hidden_sides_reach(off.dancers[0]))
    tracker._adapt_box(d, frame, cut, weight=1.0, retrack=False)  # cut again: narrower than the noted width still
    assert d.hidden_sides == (False, True) and d.hidden_aspect == pytest.approx(0.55)
    clear = (200.0, 102.0, 60.0, 180.0)  # ends at x 260, clear of him: the note is gone
    tracker._adapt_box(d, frame, clear, weight=1.0, retrack=False)
    assert d.hidden_aspect is None and not any(tracker._hidden_sides_reach(d))
    d.box = behind  # her arms out again, then cut once more
    tracker._adapt_box(d, frame, cut, weight=1.0, retrack=False)
    assert d.hidden_aspect is not None
    tracker.dancers[1].box = (500.0, 180.0, 120.0, 260.0)  # he steps off her box: nothing of her is hidden any more
    assert not any(tracker._hidden_sides_reach(d)) and d.hidden_aspect is None
    with pytest.raises(ValueError, match="keep_hidden_sides"):
        MultiTrackerConfig(keep_hidden_sides="yes")


def test_detection_that_leaves_out_legs_in_foreground_ends_where_they_end():
    """The detector may leave out legs whose colours it does not take for a person (yellow chequered trousers):
    a clear dancer's detection that ends above foreground running on down in its columns ends where that
    foreground ends (``foreground_feet``), at most that share of its height lower or down to the box's bottom;
    legs the colour of the background, or columns in another dancer's box, leave it as it is."""
    rng = np.random.default_rng(2)
    frame = rng.integers(90, 160, (480, 640, 3), dtype=np.uint8)  # grey noise: red and yellow are rare colours
    frame[100:200, 300:360] = (0, 0, 255)  # upper body, red
    frame[200:290, 315:345] = (0, 255, 255)  # legs, yellow, down to y 290
    box, upper = (300.0, 100.0, 60.0, 200.0), (300.0, 100.0, 60.0, 100.0)
    tracker = MultiDancerTracker(frame, [box])  # on by default, 0.6
    d = tracker.dancers[0]
    assert tracker._feet_in_foreground(d, frame, upper) == pytest.approx((300.0, 100.0, 60.0, 190.0))
    assert tracker._feet_in_foreground(d, frame, (300.0, 100.0, 60.0, 40.0)) == \
        pytest.approx((300.0, 100.0, 60.0, 190.0))  # down within the box, more than 0.6 x 40 px
    d.box = (300.0, 100.0, 60.0, 150.0)
    assert tracker._feet_in_foreground(d, frame, upper) == pytest.approx((300.0, 100.0, 60.0, 160.0))  # 0.6 x 100
    d.box = box
    tracker._adapt_box(d, frame, upper, weight=1.0, retrack=False)
    assert d.box[1] + d.box[3] == pytest.approx(290.0, abs=1.0)
    off = MultiDancerTracker(frame, [box], MultiTrackerConfig(foreground_feet=None))
    assert off._feet_in_foreground(off.dancers[0], frame, upper) == upper
    grey = frame.copy()
    grey[200:290, 315:345] = rng.integers(90, 160, (90, 30, 3), dtype=np.uint8)  # legs like the background
    assert tracker._feet_in_foreground(d, grey, upper) == upper
    beside = MultiDancerTracker(frame, [box, (320.0, 150.0, 80.0, 200.0)])
    assert beside._feet_in_foreground(beside.dancers[0], frame, upper) == upper  # that foreground may be hers


def test_a_dancer_beside_a_partner_follows_her_detection_s_height():
    """A clear dancer's one detection is refused as hers alone when its body core overlaps another dancer's (a box
    around two people). Beside a partner with an arm out towards her, the detection is still hers when the partner
    is tracked clear of her, does not stand in front of her, and holds a detection of her own; then the box's height
    follows it (``adapt_beside_partner``), keeping its bottom and width. A swing couple side by side walking towards
    the camera kept boxes 187 px tall while the dancers grew to 256 px (hdvr synth seed 1207 swing: 0.808 -> 0.975)."""
    frame = np.random.default_rng(5).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    her, partner = (200.0, 100.0, 60.0, 180.0), (290.0, 110.0, 60.0, 170.0)
    detection, partners_own = (200.0, 80.0, 130.0, 220.0), (292.0, 108.0, 58.0, 172.0)
    tracker = MultiDancerTracker(frame, [her, partner])
    d = tracker.dancers[0]
    assert not tracker._single_person(d, detection)  # its core reaches the partner's
    assert tracker._beside_partner(d, detection, [detection, partners_own])
    assert not tracker._beside_partner(d, detection, [detection])  # perhaps a box around both
    wide = (0.0, 80.0, 630.0, 220.0)  # wider than 2 x her height: YOLO's box across the frame
    assert not tracker._beside_partner(d, wide, [wide, partners_own])
    assert not tracker._beside_partner(d, (200.0, 0.0, 130.0, 300.0), [(200.0, 0.0, 130.0, 300.0), partners_own])
    low = (200.0, 300.0, 60.0, 180.0)  # the same with her feet on the frame's bottom edge: the detection is cut
    at_edge = MultiDancerTracker(frame, [low, (290.0, 310.0, 60.0, 170.0)])
    assert not at_edge._beside_partner(at_edge.dancers[0], (200.0, 280.0, 130.0, 200.0),
                                       [(200.0, 280.0, 130.0, 200.0), (292.0, 308.0, 58.0, 172.0)])
    closer = MultiDancerTracker(frame, [her, (290.0, 110.0, 60.0, 200.0)])  # the partner's feet 30 px lower
    assert not closer._beside_partner(closer.dancers[0], detection, [detection, (292.0, 108.0, 58.0, 202.0)])
    tracker._adapt_height(d, detection)
    x, y, w, h = d.box
    assert (x, w, y + h) == (200.0, 60.0, 280.0)
    assert h == pytest.approx(0.7 * 180.0 + 0.3 * 220.0)  # box_adaptation 0.3 of the way


def test_a_dancer_in_front_follows_the_person_whose_feet_are_lowest_when_a_stack_parts():
    """Two dancers start in a stack, one waiting hidden straight behind the other. The front dancer's tracker
    learned both, and as they part it can follow the one behind (hdvr synth seed 2762 ballet: the front dancer's
    box went with the dancer behind her and the two were swapped for the rest of the clip, 2 switches). With
    ``front_follows_feet`` (0.05), when two people are detected on its box, the front dancer restarts on the one
    whose feet are lowest, nearest the camera, if its box has slid off that one; not when its box is on it, nor
    when the feet are level within 0.05 box heights, nor on a box around two people (D 2719 hip-hop: 0.958 -> 0.564
    when such a box, 1.5 x the dancer's height, counted)."""
    rng = np.random.default_rng(6)
    frame = two_colour_frame(rng, [((280.0, 180.0, 120.0, 260.0), ((60, 170, 80), (170, 40, 170)))])
    in_front, behind = (300.0, 185.0, 120.0, 255.0), (235.0, 120.0, 70.0, 230.0)  # feet at 440 and 350 px
    slid = (230.0, 180.0, 120.0, 260.0)

    def follows(limit: float, box, people) -> tuple[bool, tuple]:
        tracker = waiting_behind(frame, MultiTrackerConfig(front_follows_feet=limit))
        front = tracker.dancers[1]
        front.box = box
        return tracker._follow_front_feet(front, frame, people), front.box

    moved, box = follows(0.05, slid, [behind, in_front])
    assert moved and box_iou(box, in_front) > 0.7 and box[1] + box[3] > 430
    assert follows(0.0, slid, [behind, in_front]) == (False, slid)  # off: the box stays where it slid
    assert follows(0.05, (295.0, 182.0, 120.0, 258.0), [behind, in_front])[0] is False  # already on it
    level = (235.0, 205.0, 70.0, 230.0)  # feet at 435 px, within 0.05 x 260 of 440
    assert follows(0.05, slid, [level, in_front])[0] is False
    assert follows(0.05, slid, [in_front])[0] is False  # one person: nothing parts
    around_both = (230.0, 140.0, 190.0, 340.0)  # feet lowest, but 1.3 x the box's height: a box around two people
    moved, box = follows(0.05, slid, [behind, around_both, in_front])
    assert moved and box_iou(box, in_front) > 0.7
    assert MultiTrackerConfig().front_follows_feet == 0.05


def test_a_dancer_in_front_does_not_follow_a_person_standing_beside_its_box():
    """With ``front_feet_max_off`` (0.5), the person whose feet are lowest is followed only if its centre lies
    within half the box's width of the box's columns: a third dancer's wide detection, an arm spread onto the box,
    is not the dancer in front (hdvr synth seed 2819 hip-hop: the front dancer restarted on the dancer beside it,
    34 px beyond its box, and followed her for 85 frames; IDF1 0.823 -> 1.000)."""
    rng = np.random.default_rng(6)
    frame = two_colour_frame(rng, [((280.0, 180.0, 120.0, 260.0), ((60, 170, 80), (170, 40, 170)))])
    slid = (230.0, 180.0, 80.0, 260.0)  # columns 230-310 px
    behind = (235.0, 120.0, 70.0, 230.0)  # feet at 350 px
    beside = (260.0, 185.0, 200.0, 255.0)  # feet at 440 px, centre at 360 px: 50 px beyond the columns
    on_box = (250.0, 185.0, 100.0, 255.0)  # centre at 300 px, within them

    def follows(max_off, person) -> bool:
        tracker = waiting_behind(frame, MultiTrackerConfig(front_feet_max_off=max_off))
        front = tracker.dancers[1]
        front.box = slid
        return tracker._follow_front_feet(front, frame, [behind, person])

    assert follows(0.5, beside) is False
    assert follows(None, beside) is True  # without the test it went to her
    assert follows(0.5, on_box) is True
    assert MultiTrackerConfig().front_feet_max_off == 0.5
