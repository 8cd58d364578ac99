"""Per-dancer state and box helpers of Algorithm 1* (hdvr.tracking.state)."""

import numpy as np

from hdvr.tracking.appearance import colour_histogram, histogram_similarity
from hdvr.tracking.state import (TRACKED, DancerTrack, box_at, box_centre, covered_fraction, stands_in_front,
                                 straight_in_front)


def test_box_at_keeps_the_size_and_centres_it():
    box = box_at((100.0, 50.0), (0.0, 0.0, 40.0, 80.0))
    assert box == (80.0, 10.0, 40.0, 80.0)
    np.testing.assert_allclose(box_centre(box), [100.0, 50.0])


def test_dancer_centre_is_the_box_centre_and_starts_tracked_without_growth():
    class Tracker:  # only the attribute DancerTrack reads for body_center
        center = (12.0, 34.0)

    d = DancerTrack(dancer_id=0, tracker=Tracker(), box=(10.0, 20.0, 30.0, 60.0))
    assert d.status == TRACKED
    np.testing.assert_allclose(d.center, [25.0, 50.0])
    np.testing.assert_allclose(d.body_center, [12.0, 34.0])
    assert not d.growth.any() and d.growth.shape == (4,)


def test_recent_motion_is_the_mean_step_of_the_recent_centres():
    d = DancerTrack(0, None, (0.0, 0.0, 10.0, 20.0))
    assert np.allclose(d.recent_motion, 0.0)  # fewer than 2 centres: no motion
    d.centers = [np.array([10.0, 5.0]), np.array([12.0, 5.0]), np.array([16.0, 8.0])]
    assert np.allclose(d.recent_motion, [3.0, 1.5])


def test_memory_match_compares_a_box_s_colours_with_the_stored_histogram():
    frame = np.zeros((100, 200, 3), np.uint8)
    frame[:, :100] = (30, 40, 200)  # red half (BGR)
    frame[:, 100:] = (200, 60, 20)  # blue half
    d = DancerTrack(0, None, (10.0, 10.0, 60.0, 80.0))
    assert d.memory_match(frame) == -1.0  # nothing stored yet
    d.stored_histogram = colour_histogram(frame, d.box)
    assert d.memory_match(frame) > 0.99  # its own box, the colours it stored
    assert d.memory_match(frame, (120.0, 10.0, 60.0, 80.0)) < 0.1  # another box: other colours


def test_a_histogram_shrunk_more_at_the_sides_leaves_out_what_stands_beside_the_body():
    """``shrink`` as a pair leaves out (left and right, top and bottom) of the box: a box whose outer quarters
    show the wall matches a body-only memory with the sides shrunk by 0.25, not with 0.15."""
    frame = np.zeros((100, 200, 3), np.uint8)
    frame[:] = (200, 60, 20)  # blue wall (BGR)
    frame[:, 75:125] = (30, 40, 200)  # a red body in the middle half of the box below
    box = (50.0, 10.0, 100.0, 80.0)
    body = colour_histogram(frame, (80.0, 10.0, 40.0, 80.0), shrink=0.0)
    assert histogram_similarity(colour_histogram(frame, box, shrink=(0.25, 0.15)), body) > 0.99
    assert histogram_similarity(colour_histogram(frame, box), body) < 0.95  # 30 % of it is wall
    np.testing.assert_allclose(colour_histogram(frame, box, shrink=(0.15, 0.15)), colour_histogram(frame, box))
    d = DancerTrack(0, None, box)
    d.stored_histogram = body
    assert d.memory_match(frame, shrink=(0.25, 0.15)) > 0.99 > d.memory_match(frame)


def test_a_box_stands_in_front_when_its_bottom_is_lower_by_the_margin_of_the_other_s_height():
    behind = (100.0, 100.0, 40.0, 200.0)  # bottom at 300 px; margin 0.05 x 200 px = 10 px
    assert stands_in_front((90.0, 120.0, 60.0, 191.0), behind, 0.05)  # bottom 311
    assert not stands_in_front((90.0, 120.0, 60.0, 190.0), behind, 0.05)  # bottom 310: level
    assert not stands_in_front(behind, (90.0, 120.0, 60.0, 191.0), 0.05)


def test_a_box_stands_straight_in_front_when_the_body_cores_overlap_and_its_bottom_is_lower():
    """``straight_in_front``: body cores (0.3 x the height wide) overlapping by more than the given share of the
    smaller, and the front box's bottom lower by the margin; spread arms (a wide box) do not make an overlap."""
    behind = (100.0, 100.0, 40.0, 200.0)  # core x 100-140, bottom 300
    assert straight_in_front((95.0, 110.0, 60.0, 210.0), behind, 0.3, 0.5, 0.05)  # core 93.5-156.5, bottom 320
    assert not straight_in_front((95.0, 90.0, 60.0, 210.0), behind, 0.3, 0.5, 0.05)  # bottom level: not in front
    assert not straight_in_front((125.0, 110.0, 60.0, 210.0), behind, 0.3, 0.5, 0.05)  # cores overlap 15 of 40 px
    assert not straight_in_front((80.0, 110.0, 300.0, 210.0), behind, 0.3, 0.5, 0.05)  # arms over her, core beside


def test_covered_fraction_is_the_share_of_the_body_core_inside_the_others_body_cores():
    """Body cores at most 0.3 x the box height wide: a box of 100 x 200 px has its core at x 120-180. A narrow front
    (its core is all of it) over the core's left half covers half of it, two over both halves all of it, one half as
    tall a quarter; a front's spread arms (box wider than its core) do not cover; NaN rows and no fronts cover
    nothing."""
    box = (100.0, 0.0, 100.0, 200.0)
    assert covered_fraction(box, [box], 0.3) == 1.0
    assert covered_fraction(box, [(90.0, 0.0, 60.0, 200.0)], 0.3) == 0.5  # x 90-150
    assert covered_fraction(box, [(90.0, 0.0, 60.0, 200.0), (150.0, 0.0, 60.0, 200.0)], 0.3) == 1.0
    assert covered_fraction(box, [(120.0, 0.0, 30.0, 100.0)], 0.3) == 0.25  # x 120-150, the upper half
    assert covered_fraction(box, [(-100.0, 0.0, 260.0, 200.0)], 0.3) == 0.0  # core x 0-60: arms reach over it
    assert covered_fraction(box, np.full((1, 4), np.nan), 0.3) == 0.0
    assert covered_fraction(box, [], 0.3) == 0.0
