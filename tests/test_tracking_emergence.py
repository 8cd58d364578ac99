"""Dancers waiting hidden behind others coming out (:mod:`hdvr.tracking.emergence`)."""

import dataclasses

import numpy as np
import pytest

from hdvr.tracking.appearance import box_iou, colour_histogram, histogram_similarity
from hdvr.tracking.multi import OCCLUDED, TRACKED, MultiDancerTracker, MultiTrackerConfig
from tracking_scenes import two_colour_frame, waiting_behind


def _red_blue_green_dancers(config=None):
    """A frame in three colour bands (red, blue, green, 200 px wide each), a tracker with one dancer on each band
    (their memories those colours), and the three boxes; the green dancer waits behind the red one."""
    frame = np.zeros((480, 640, 3), np.uint8)
    frame[:, :200] = (0, 0, 200)  # red figure region
    frame[:, 200:400] = (200, 60, 0)  # blue
    frame[:, 400:] = (40, 200, 40)  # green
    boxes = (50.0, 100.0, 80.0, 250.0), (250.0, 100.0, 80.0, 250.0), (450.0, 100.0, 80.0, 250.0)
    tracker = MultiDancerTracker(frame, list(boxes), config)
    for d, box in zip(tracker.dancers, boxes):
        d.stored_histogram = colour_histogram(frame, box)
    tracker.dancers[2].hidden_behind = tracker.dancers[0].dancer_id
    return frame, tracker, boxes


def test_a_waiting_dancer_emerges_on_a_person_dressed_partly_like_the_dancer_in_front():
    """A dancer waiting behind another (``hidden_behind``) takes a detection clear of every dancer that looks
    like the dancer in front's memory less than ``reid_similarity``; with ``emerge_relative`` also one that looks
    like it more, if by ``reid_margin`` less than the dancer in front's own box does: a person in a shirt of the
    same colour but other trousers is someone else (hdvr synth seed 504 flamenco: IDF1 0.728 -> 0.975)."""
    rng = np.random.default_rng(5)
    front_box, person = (280.0, 180.0, 120.0, 260.0), (150.0, 110.0, 60.0, 190.0)
    green, magenta, yellow = (60, 170, 80), (170, 40, 170), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    later = two_colour_frame(rng, [(person, (green, yellow))], split=0.7)  # a long green shirt
    later[180:440, 280:400] = frame[180:440, 280:400]
    emerged = {}
    for relative in (True, False):
        tracker = waiting_behind(frame, MultiTrackerConfig(emerge_relative=relative))
        waiting, front = tracker.dancers
        c = tracker.config
        looks_like_front = histogram_similarity(colour_histogram(later, person), front.stored_histogram)
        front_itself = histogram_similarity(colour_histogram(later, front.box), front.stored_histogram)
        assert c.reid_similarity <= looks_like_front < front_itself - c.reid_margin
        tracker._emerge(later, [front_box, person])
        emerged[relative] = waiting.hidden_behind is None
        if emerged[relative]:
            assert box_iou(waiting.box, person) > 0.8
    assert emerged == {True: True, False: False}
    # the dancer in front itself, seen again beside its drifted box, matches its memory as well: it does not
    tracker = waiting_behind(frame)
    front = tracker.dancers[1]
    front.box = (450.0, 180.0, 120.0, 260.0)  # its tracker slid onto the background
    moved = two_colour_frame(rng, [((150.0, 180.0, 120.0, 260.0), (green, magenta))])
    tracker._emerge(moved, [front.box, (150.0, 180.0, 120.0, 260.0)])
    assert tracker.dancers[0].hidden_behind == 1


def test_a_waiting_dancer_comes_out_past_another_dancer_still_waiting_where_it_is():
    """Two dancers start hidden behind the same one: dancer 0 (tall) and dancer 2 (short, further back). The dancer in
    front walks away and dancer 0 is detected where it waits; dancer 2's box, a guess at its start, lies on that
    detection. With ``emerge_past_waiting`` (the default, session 50) a dancer still waiting does not stand in the
    way of a detection that fits it less well than the emerging dancer's box: dancer 0 comes out on it and dancer 2
    keeps waiting (hdvr synth seed 2624 hip-hop: IDF1 0.767 -> 1.000). Without, dancer 0 waits on. The dancer hiding
    the emerging one stands in the way even while it waits itself."""
    rng = np.random.default_rng(3)
    front_box, tall, short = (280.0, 180.0, 120.0, 260.0), (300.0, 100.0, 60.0, 200.0), (305.0, 150.0, 50.0, 150.0)
    green, magenta, blue, yellow = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    walked = (450.0, 180.0, 120.0, 260.0)
    later = two_colour_frame(rng, [(walked, (green, magenta)), (tall, (blue, yellow))])
    for past_waiting in (True, False):
        tracker = MultiDancerTracker(frame, [tall, front_box, short],
                                     MultiTrackerConfig(emerge_past_waiting=past_waiting))
        waiting, front, further = tracker.dancers
        assert waiting.hidden_behind == 1 and further.hidden_behind == 1
        assert tracker._bodies_overlap(tall, further.box) > tracker.config.overlap_threshold
        front.box = walked
        tracker._emerge(later, [walked, tall])
        assert (waiting.hidden_behind is None) == past_waiting
        assert further.hidden_behind == 1
        if past_waiting:
            assert box_iou(waiting.box, tall) > 0.9
    # the dancer hiding the emerging one stands in the way even while it waits itself (a stack of three)
    tracker = MultiDancerTracker(frame, [tall, front_box, short])
    waiting, front, further = tracker.dancers
    waiting.hidden_behind = further.dancer_id
    front.box = walked
    tracker._emerge(later, [walked, tall])
    assert waiting.hidden_behind == further.dancer_id


def test_a_waiting_dancer_comes_out_past_an_occluded_dancer_plainly_not_the_person_there():
    """A third dancer, occluded, is predicted onto the spot where a person steps out beside the dancer in front. With
    ``emerge_past_unlike_occluded`` (the default, session 72) its predicted box does not stand in the way when the
    person's colours match its memory less than ``emerge_beside_similarity``: the waiting dancer comes out on the first
    detector frame (hdvr synth seed 2844 hip-hop: 15 frames earlier, 0.887 -> 0.963). Without, it waits on; and a
    person dressed like the occluded dancer may be that dancer, so it waits on then too."""
    rng = np.random.default_rng(11)
    front_box, behind, third = (280.0, 180.0, 120.0, 260.0), (300.0, 100.0, 60.0, 200.0), (40.0, 110.0, 60.0, 190.0)
    person = (160.0, 110.0, 60.0, 190.0)  # clear of the front dancer, within a box height of the waiting one
    green, magenta, blue, yellow, red, white = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220), \
        (40, 60, 200), (235, 235, 235)
    frame = two_colour_frame(rng, [(front_box, (green, magenta)), (third, (blue, yellow))])

    def comes_out(person_colours, past_unlike: bool = True) -> bool:
        later = two_colour_frame(rng, [(front_box, (green, magenta)), (person, person_colours)])
        tracker = MultiDancerTracker(frame, [behind, front_box, third],
                                     MultiTrackerConfig(emerge_past_unlike_occluded=past_unlike))
        waiting, front, occluded = tracker.dancers
        assert waiting.hidden_behind == 1 and occluded.hidden_behind is None
        occluded.status, occluded.box = OCCLUDED, person  # predicted onto the person
        assert tracker._bodies_overlap(person, occluded.box) > tracker.config.emerge_beside_overlap
        tracker._emerge(later, [front_box, person])
        if waiting.hidden_behind is None:
            assert box_iou(waiting.box, person) > 0.8
        return waiting.hidden_behind is None

    assert comes_out((red, white))
    assert not comes_out((red, white), past_unlike=False)
    assert not comes_out((blue, yellow))  # dressed like the occluded dancer: it may be her


def test_of_two_dancers_waiting_near_a_person_coming_out_the_one_of_its_height_takes_it():
    """Two dancers start hidden behind the same one: dancer 0, 200 px tall, and dancer 2, 150 px. A person 150 px tall
    comes out beside the dancer in front, within reach of both. Dancer 0 chooses first (the dancers' order) and took
    it; with ``emerge_height_yield`` m it leaves it to the waiting dancer whose box height fits the person's better by
    more than m in |log(height ratio)|, and dancer 2 comes out on it (hdvr synth seed 2906 flamenco, a stack of three:
    the middle dancer, 185 px, took the one at the back, 123 px, as she came out and kept her; 0.606 with a switch ->
    0.972)."""
    rng = np.random.default_rng(4)
    front_box, tall, short = (280.0, 180.0, 120.0, 260.0), (300.0, 100.0, 60.0, 200.0), (305.0, 150.0, 50.0, 150.0)
    person = (180.0, 150.0, 50.0, 150.0)
    green, magenta, blue, yellow = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    later = two_colour_frame(rng, [(front_box, (green, magenta)), (person, (blue, yellow))])
    for margin in (0.0, 0.1):
        tracker = MultiDancerTracker(frame, [tall, front_box, short], MultiTrackerConfig(emerge_height_yield=margin))
        waiting_tall, front, waiting_short = tracker.dancers
        assert waiting_tall.hidden_behind == 1 and waiting_short.hidden_behind == 1
        tracker._emerge(later, [front_box, person])
        came_out = waiting_short if margin else waiting_tall
        stayed = waiting_tall if margin else waiting_short
        assert came_out.hidden_behind is None and abs(came_out.box[0] - person[0]) < 1.0  # (the height it keeps)
        assert stayed.hidden_behind == 1
    tracker = MultiDancerTracker(frame, [tall, front_box, short], MultiTrackerConfig(emerge_height_yield=0.1))
    fits_other = lambda d, box, image: tracker._fits_other_waiting(  # noqa: E731
        image, tracker.dancers[d], 1, box, tracker.waiting(), {}, {})
    assert fits_other(0, person, later) and not fits_other(2, person, later)
    far = (20.0, 150.0, 50.0, 150.0)  # beyond the short dancer's reach (emerge_distance x 150 px): not hers to take
    assert not fits_other(0, far, two_colour_frame(rng, [(front_box, (green, magenta)), (far, (blue, yellow))]))
    # a person the short dancer may not come out on (in the front dancer's colours) is not left to her
    alike = two_colour_frame(rng, [(front_box, (green, magenta)), (person, (green, magenta))])
    assert not fits_other(0, person, alike)
    assert MultiTrackerConfig().emerge_height_yield == 0.1


def test_a_dancer_in_front_walking_out_of_its_stack_takes_its_own_detection_and_the_waiting_one_comes_out():
    """A dancer 260 px tall starts in front of one 200 px tall waiting behind it. He walks away while his box stays on
    her (his tracker learned their stack), so the detection given to him lies on her box and she, waiting, cannot
    take it; the detection of him beside them looks like him, so she does not take that either. With
    ``emerge_front_leaves`` m he moves to the detection that looks like him whose height fits his box better and hers
    worse (by more than m in |log(height ratio)|, summed), and she comes out on the one his box held (hdvr synth seed
    2870 ballet: his box stayed on her 100 frames, another dancer later took him; 0.658 with a switch -> 0.946). Not
    onto a person who does not look like him."""
    rng = np.random.default_rng(6)
    front_box, behind = (290.0, 180.0, 80.0, 260.0), (305.0, 220.0, 50.0, 200.0)
    green, magenta, blue, yellow = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    stayed_on_her = (300.0, 205.0, 60.0, 230.0)  # his box, adapted part of the way to her
    # him, walked away; and a person in his colours of her height, whom the heights do not give to him
    for walked, leaves in (((440.0, 180.0, 80.0, 260.0), True), ((440.0, 240.0, 60.0, 200.0), False)):
        later = two_colour_frame(rng, [(walked, (green, magenta)), (behind, (blue, yellow))])
        for margin in (0.0, 0.05):
            tracker = MultiDancerTracker(frame, [behind, front_box], MultiTrackerConfig(emerge_front_leaves=margin))
            waiting, front = tracker.dancers
            assert waiting.hidden_behind == 1
            front.box = stayed_on_her
            tracker._emerge(later, [behind, walked])
            moved = bool(margin) and leaves
            assert (waiting.hidden_behind is None) == moved
            assert box_iou(front.box, walked if moved else stayed_on_her) > 0.9
            if moved:
                assert box_iou(waiting.box, behind) > 0.9
                assert histogram_similarity(waiting.stored_histogram, colour_histogram(later, behind)) > 0.9
    assert MultiTrackerConfig().emerge_front_leaves == 0.05


def test_a_waiting_dancer_comes_out_half_beside_the_dancer_in_front_once_seen_there_three_times():
    """With ``emerge_beside_persist`` 3, a dancer waiting behind another takes a detection whose body core half
    overlaps the front dancer's (0.3 of it: no clear detection) when its colours are unlike the front dancer's memory
    and such a detection lay there on the two detector frames before (hdvr synth seed 1302 flamenco: the dancer
    behind stands half beside the taller one in front from frame 84 on, and never came out). Not on the first two,
    not after a detector frame that did not show it, and never with the rule off (0). Detector frames count, not
    frames: every 8th frame it comes out on the third as well."""
    rng = np.random.default_rng(9)
    front_box, person = (280.0, 180.0, 120.0, 260.0), (270.0, 110.0, 60.0, 190.0)
    green, magenta, red, yellow = (60, 170, 80), (170, 40, 170), (40, 60, 200), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    later = two_colour_frame(rng, [(front_box, (green, magenta)), (person, (red, yellow))])
    # (persist, detector frames, the frames among them that show the person, frame it comes out on)
    for persist, frames, shown, emerged_at in ((3, (3, 6, 9), (3, 6, 9), 9), (3, (8, 16, 24), (8, 16, 24), 24),
                                               (3, (3, 6, 9, 12, 15), (3, 6, 12, 15), None),
                                               (0, (3, 6, 9), (3, 6, 9), None)):
        tracker = waiting_behind(frame, MultiTrackerConfig(emerge_beside_persist=persist))
        waiting, front = tracker.dancers
        assert 0.05 < tracker._bodies_overlap(person, front.box) < 0.5
        for t in frames:
            tracker.frame_index = t
            tracker._count_detector_frame()  # as step does on a frame with detections
            tracker._emerge(later, [front_box, person] if t in shown else [front_box])
            assert (waiting.hidden_behind is None) == (emerged_at is not None and t >= emerged_at), (persist, t)
        if emerged_at is not None:
            assert box_iou(waiting.box, person) > 0.8


def test_a_waiting_dancer_comes_out_on_its_own_box_once_seen_there_three_times_unlike_the_front_dancer():
    """With ``emerge_own_margin`` m (0.35 by default since session 51), a dancer waiting behind another also takes a
    detection on its own box (IoU >= 0.5) whose body core overlaps the front dancer's too much to count as beside him,
    when its colours match the front dancer's memory by m less than his own box does now, on ``emerge_beside_persist``
    (3) detector frames in a row (hdvr synth seed 2665 hip-hop: the dancer behind, seen on her own box for 90 frames,
    never came out; 2 switches -> none). Not on the first two frames, not for a person dressed like the dancer in
    front (a part of him that the detector drew as a person), and never with the rule off (0)."""
    rng = np.random.default_rng(11)
    front_box, own = (280.0, 180.0, 120.0, 260.0), (300.0, 100.0, 60.0, 200.0)
    green, magenta, red, yellow = (60, 170, 80), (170, 40, 170), (40, 60, 200), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    for margin, colours, comes_out in ((0.35, (red, yellow), True), (0.35, (green, magenta), False),
                                       (0.0, (red, yellow), False)):
        later = two_colour_frame(rng, [(front_box, (green, magenta)), (own, colours)])
        tracker = waiting_behind(frame, MultiTrackerConfig(emerge_own_margin=margin))
        waiting, front = tracker.dancers
        assert tracker._bodies_overlap(own, front.box) >= 0.5 and box_iou(own, waiting.box) >= 0.5
        for t in (3, 6, 9):
            tracker.frame_index = t
            tracker._count_detector_frame()
            tracker._emerge(later, [front_box, own])
            assert (waiting.hidden_behind is None) == (comes_out and t == 9), (margin, colours, t)
    assert MultiTrackerConfig().emerge_own_margin == 0.35


def test_a_waiting_dancer_emerging_on_its_upper_body_keeps_its_height():
    """A dancer that comes out from behind on a detection shorter than its start box (the detector sees only the
    part already out) keeps the box's height, with ``emerge_keeps_height`` (hdvr synth seed 705 tango, a couple in
    hold: IDF1 0.533 -> 0.812); without, it shrinks to the detection."""
    rng = np.random.default_rng(6)
    front_box, upper = (280.0, 180.0, 120.0, 260.0), (200.0, 100.0, 60.0, 140.0)
    frame = two_colour_frame(rng, [(front_box, ((60, 170, 80), (170, 40, 170)))])
    later = two_colour_frame(rng, [(front_box, ((60, 170, 80), (170, 40, 170))),
                                   (upper, ((200, 60, 40), (40, 200, 220)))])
    for keep, height in ((True, 200.0), (False, 140.0)):
        tracker = waiting_behind(frame, MultiTrackerConfig(emerge_keeps_height=keep))
        waiting = tracker.dancers[0]
        tracker._emerge(later, [front_box, upper])
        assert waiting.hidden_behind is None and waiting.status == TRACKED
        assert waiting.box[:3] == pytest.approx(upper[:3]) and waiting.box[3] == pytest.approx(height), keep


def test_a_waiting_dancer_does_not_emerge_on_a_wide_part_drawn_as_a_person():
    """A detection much wider for its height than the waiting dancer's box (``emerge_max_aspect``: 2 x) is a part of
    a dancer that YOLO drew as a person, e.g. the spread arm of the dancer in front (hdvr synth seed 1308 hip-hop: a
    box 175 x 93 px taken for a dancer 51 px wide), not the waiting dancer coming out."""
    rng = np.random.default_rng(8)
    front_box, wide = (280.0, 180.0, 120.0, 260.0), (150.0, 120.0, 130.0, 140.0)  # aspects 0.46 and 0.93
    frame = two_colour_frame(rng, [(front_box, ((60, 170, 80), (170, 40, 170)))])
    later = two_colour_frame(rng, [(front_box, ((60, 170, 80), (170, 40, 170))),
                                   (wide, ((200, 60, 40), (40, 200, 220)))])
    for aspect, emerged in ((2.0, False), (float("inf"), True)):
        tracker = waiting_behind(frame, MultiTrackerConfig(emerge_max_aspect=aspect))
        waiting = tracker.dancers[0]  # box 60 x 200 px: aspect 0.3
        tracker._emerge(later, [front_box, wide])
        assert (waiting.hidden_behind is None) == emerged, aspect


def test_a_waiting_dancer_does_not_come_out_on_a_person_who_plainly_is_another_dancer():
    """A dancer waiting behind another since its start has no colours of its own, so it used to take any person
    coming out near it that did not look like the dancer in front. With ``emerge_yields_to_known`` (the default
    since session 47) a person whose colours match another dancer's memory (at least ``reid_similarity``, by
    ``reid_margin`` over every other known dancer) is left to that dancer (:meth:`_shows_known_dancer`)."""
    frame, tracker, (red, blue, green) = _red_blue_green_dancers()
    front, known, waiting = tracker.dancers
    shows = lambda box: tracker._shows_known_dancer(colour_histogram(frame, box), front)  # noqa: E731
    assert shows(blue)  # the blue dancer, plainly
    assert not shows(red)  # the front dancer's colours: tested separately, by the front's own rule
    assert not shows(green)  # only the waiting dancer's (borrowed) memory: nobody known
    config = tracker.config
    tracker.config = dataclasses.replace(config, emerge_yields_to_known=False)
    assert not shows(blue)
    tracker.config = config
    front.stored_histogram = known.stored_histogram.copy()  # two known dancers dressed alike: no plain match
    assert not shows(blue)


def test_a_waiting_dancer_is_not_kept_from_a_person_too_short_to_be_the_known_dancer_like_her():
    """``emerge_yields_to_known`` leaves a person who looks like a known dancer to that dancer; with
    ``emerge_known_height`` only if that dancer could take it, its box's height within ``reid_height_change`` of the
    person's (:meth:`_height_fits`). hdvr synth seed 2826 ballet: the waiting dancer walked out clear, detected for
    40 frames, 117 px tall; an occluded dancer 171 px tall matched her colours 0.62-0.72, could not take her, and
    the waiting dancer's box stayed at her start (IoU 0.12)."""
    frame, tracker, (red, blue, green) = _red_blue_green_dancers(MultiTrackerConfig(emerge_known_height=True))
    front = tracker.dancers[0]
    short = (260.0, 200.0, 60.0, 150.0)  # in blue's colours, 0.6 x its height
    shows = lambda box: tracker._shows_known_dancer(colour_histogram(frame, box), front, box)  # noqa: E731
    assert shows(blue)  # the blue dancer's height: left to her
    assert not shows(short)  # too short to be her
    tracker.config = dataclasses.replace(tracker.config, emerge_known_height=False)
    assert shows(short)  # before: left to her all the same
    assert MultiTrackerConfig().emerge_known_height is True


def test_a_person_coming_out_of_a_chain_is_offered_first_to_the_dancer_hidden_by_one():
    """Three dancers start in a chain: dancer 0 waits behind dancer 1, who waits behind dancer 2, followed. A person
    comes out beside them, unlike dancer 2. Dancer 1 is hidden by one dancer, dancer 0 by two: with
    ``emerge_front_first`` the person is offered to dancer 1 first; before, the dancers' numbers decided and dancer
    0 took her (hdvr synth G 2766 ballet: 5 switches)."""
    rng = np.random.default_rng(11)
    front_box, middle, back = (280.0, 180.0, 120.0, 260.0), (300.0, 150.0, 70.0, 230.0), (310.0, 130.0, 60.0, 200.0)
    person = (170.0, 160.0, 65.0, 220.0)
    green, magenta, blue, yellow = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    later = two_colour_frame(rng, [(front_box, (green, magenta)), (person, (blue, yellow))])
    came_out = {}
    for first in (True, False):
        tracker = MultiDancerTracker(frame, [back, middle, front_box], MultiTrackerConfig(emerge_front_first=first))
        d_back, d_middle, d_front = tracker.dancers
        d_back.hidden_behind, d_middle.hidden_behind, d_front.hidden_behind = 1, 2, None
        tracker._emerge(later, [front_box, person])
        came_out[first] = [d.dancer_id for d in (d_back, d_middle) if d.hidden_behind is None]
    assert came_out == {True: [1], False: [0]}
    assert MultiTrackerConfig().emerge_front_first


def test_a_waiting_dancer_seen_side_on_comes_out_facing_the_camera():
    """``emerge_max_aspect`` refuses a detection more than 2 x as wide for its height as the waiting dancer's box (a
    part of a dancer drawn as a person). A start box seen side-on is thin (hdvr synth G 2766 ballet: 38 x 143 px,
    0.27), and the dancer, turning to the camera as she came out, was "too wide" (0.54). With
    ``emerge_min_aspect`` (0.3) the box counts as at least that wide: she comes out; a spread arm (0.93) still
    does not."""
    rng = np.random.default_rng(12)
    front_box, thin = (280.0, 180.0, 120.0, 260.0), (320.0, 120.0, 45.0, 200.0)  # aspect 0.225
    person, wide = (150.0, 130.0, 110.0, 200.0), (150.0, 120.0, 130.0, 140.0)  # aspects 0.55 and 0.93
    green, magenta, blue, yellow = (60, 170, 80), (170, 40, 170), (200, 90, 30), (40, 200, 220)
    frame = two_colour_frame(rng, [(front_box, (green, magenta))])
    for box, min_aspect, emerged in ((person, 0.3, True), (person, 0.0, False), (wide, 0.3, False)):
        later = two_colour_frame(rng, [(front_box, (green, magenta)), (box, (blue, yellow))])
        tracker = MultiDancerTracker(frame, [thin, front_box], MultiTrackerConfig(emerge_min_aspect=min_aspect))
        waiting = tracker.dancers[0]
        assert waiting.hidden_behind == 1
        tracker._emerge(later, [front_box, box])
        assert (waiting.hidden_behind is None) == emerged, (box, min_aspect)
    assert MultiTrackerConfig().emerge_min_aspect == 0.3
