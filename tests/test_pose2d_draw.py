"""hdvr.pose2d.draw: the overlay of boxes, ids, skeletons and the frame number; the pixel grid."""

import numpy as np
import pytest

from hdvr.pose2d.draw import dancer_colour, draw_overlay, draw_pixel_grid


def _frame():
    return np.full((240, 320, 3), 128, np.uint8)


def test_boxes_are_drawn_in_the_dancer_s_colour_thick_when_tracked():
    boxes = np.array([[40.0, 60.0, 60.0, 120.0], [180.0, 60.0, 60.0, 120.0]])
    frame = draw_overlay(np.full((720, 960, 3), 128, np.uint8), boxes, ("tracked", "occluded"))  # lines 3 / 1 px
    for i, (x, y, w, h) in enumerate(boxes.astype(int)):
        column = frame[y + h // 2, x - 3:x + 4]  # across the left edge, half-way down
        drawn = (column == dancer_colour(i)).all(axis=1)
        assert drawn.any()
        assert drawn.sum() >= 2 if i == 0 else drawn.sum() == 1  # tracked: thick, predicted: thin
    untouched = draw_overlay(_frame(), np.full((1, 4), np.nan), ("out",))
    np.testing.assert_array_equal(untouched, _frame())  # no box where there is none


def test_the_frame_number_is_stamped_top_left_only_when_given():
    boxes = np.array([[200.0, 100.0, 50.0, 100.0]])
    plain = draw_overlay(_frame(), boxes, ("tracked",))
    stamped = draw_overlay(_frame(), boxes, ("tracked",), frame_index=123)
    corner = stamped[:20, :60]
    assert (corner == 0).all(axis=2).any() and (corner == 255).all(axis=2).any()  # white text on black
    np.testing.assert_array_equal(plain[:20, :60], _frame()[:20, :60])
    np.testing.assert_array_equal(stamped[60:], plain[60:])  # the rest is the same


def test_the_pixel_grid_draws_white_lines_at_every_step_and_labels_them():
    frame = draw_pixel_grid(_frame(), step=100)
    assert (frame[:, 100] == 255).all() and (frame[:, 200] == 255).all()  # full lines at x = 100, 200
    assert (frame[100, :] == 255).all() and (frame[200, 10:] == 255).all()
    faint = frame[10:90, 50]  # the half-way line is a blend, lighter than the frame
    assert (faint > 128).all() and (faint < 255).all()
    assert (frame[30:40, 120:130] == 128).all()  # between lines the frame is untouched
    labels = frame[225:240, 100:140]  # "100" at the bottom edge, white on a dark outline
    assert (labels < 64).all(axis=2).any() and (labels > 200).all(axis=2).any()
    with pytest.raises(ValueError, match="grid step"):
        draw_pixel_grid(_frame(), step=5)
