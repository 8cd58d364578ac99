"""Tests of :mod:`hdvr.tracking.geometry`: box geometry helpers of the multi-dancer tracker."""

import numpy as np
import pytest

from hdvr.tracking.geometry import (angle_between, box_behind, chain_length, height_misfit, height_within,
                                    likely_windows, offset_behind, shifted)


def test_angle_between_is_in_degrees_and_zero_for_a_standstill():
    assert angle_between(np.array([1.0, 0.0]), np.array([0.0, 2.0])) == pytest.approx(90.0)
    assert angle_between(np.array([1.0, 1.0]), np.array([-3.0, -3.0])) == pytest.approx(180.0)
    assert angle_between(np.array([0.0, 0.0]), np.array([1.0, 0.0])) == 0.0


def test_height_within_and_misfit_treat_taller_and_shorter_alike():
    box, reference = (0.0, 0.0, 40.0, 300.0), (10.0, 10.0, 50.0, 200.0)
    assert height_within(box, reference, 1.5) and not height_within(box, reference, 1.49)
    assert not height_within(reference, box, 1.49)
    assert height_misfit(box, reference) == pytest.approx(height_misfit(reference, box)) == pytest.approx(np.log(1.5))
    assert height_misfit(box, box) == 0.0


def test_a_chain_of_detections_counts_the_detector_frames_a_person_lay_there():
    before = [((100.0, 100.0, 50.0, 150.0), 3), ((400.0, 100.0, 50.0, 150.0), 1)]
    assert chain_length(before, (102.0, 101.0, 50.0, 150.0)) == 4  # on the chain of three
    assert chain_length(before, (250.0, 100.0, 50.0, 150.0)) == 1  # nowhere before
    assert chain_length([], (100.0, 100.0, 50.0, 150.0)) == 1


def test_shifted_moves_a_box_keeping_its_size():
    assert shifted((10.0, 20.0, 30.0, 40.0), np.array([5.0, -5.0])) == (15.0, 15.0, 30.0, 40.0)


def test_a_box_placed_behind_a_moved_front_dancer_keeps_its_offset_in_its_own_heights():
    offset = offset_behind((310.0, 170.0, 50.0, 180.0), (300.0, 150.0, 70.0, 220.0))
    np.testing.assert_allclose(offset, (0.0, -20 / 180))
    offset = offset_behind((330.0, 170.0, 50.0, 180.0), (300.0, 150.0, 70.0, 220.0))  # 20 px right of his centre
    np.testing.assert_allclose(box_behind((0.0, 0.0, 50.0, 180.0), (400.0, 100.0, 80.0, 240.0), offset),
                               (440 + 20 - 25, 340 - 20 - 180, 50.0, 180.0))


def test_likely_windows_are_the_window_sized_places_with_the_highest_mean_weight():
    """:func:`likely_windows`: centres of the windows with the highest mean weight, best first, at least
    ``min_mean``, not two on the same place; a patch smaller than the window scores its share of it."""
    weights = np.zeros((480, 640), np.float32)
    weights[100:300, 200:260] = 1.0  # a figure 60 x 200 px, centre (230, 200)
    weights[250:450, 480:540] = 0.7  # a fainter one, centre (510, 350)
    weights[20:60, 20:40] = 1.0  # a speck
    centres = likely_windows(weights, (60, 200), 0.5)
    assert len(centres) == 2
    np.testing.assert_allclose(centres[0], (230, 200), atol=6)
    np.testing.assert_allclose(centres[1], (510, 350), atol=6)
    assert len(likely_windows(weights, (60, 200), 0.8)) == 1
    assert likely_windows(np.zeros((480, 640), np.float32), (60, 200), 0.1) == []
