"""Colour histograms, their per-pixel bins and the foreground mask (hdvr.tracking.appearance)."""

import numpy as np

from hdvr.tracking.appearance import (HUE_BINS, SAT_BINS, VALUE_BINS, colour_bins, colour_histogram,
                                      foreground_mask, histogram_similarity)


def test_colour_bins_counted_in_a_box_give_its_colour_histogram():
    """Counting :func:`colour_bins` over a box's pixels gives :func:`colour_histogram` of that box (no shrink):
    the bins are the histogram's, chromatic and dark or grey pixels alike, so a histogram looked up at them is a
    back-projection."""
    rng = np.random.default_rng(0)
    frame = rng.integers(0, 256, (120, 160, 3), dtype=np.uint8)
    frame[:40, :60] = (30, 30, 30)  # dark: value bins
    frame[40:80, :60] = (200, 200, 200)  # grey: value bins
    bins = colour_bins(frame)
    assert bins.shape == (120, 160)
    assert bins.min() >= 0 and bins.max() < HUE_BINS * SAT_BINS + VALUE_BINS
    assert (bins[:80, :60] >= HUE_BINS * SAT_BINS).all()
    for box in [(20, 10, 80, 90), (0, 0, 60, 80), (100, 50, 60, 70)]:
        x, y, w, h = box
        counts = np.bincount(bins[y:y + h, x:x + w].ravel(), minlength=HUE_BINS * SAT_BINS + VALUE_BINS)
        np.testing.assert_allclose(counts / counts.sum(), colour_histogram(frame, box, shrink=0.0), atol=1e-6)


def test_histogram_similarity_tells_colours_apart_and_is_minus_one_without_a_histogram():
    rng = np.random.default_rng(1)
    frame = rng.integers(90, 160, (100, 200, 3), dtype=np.uint8)
    frame[20:80, 10:50] = (0, 0, 220)  # red
    frame[20:80, 110:150] = (220, 0, 0)  # blue
    frame[20:80, 160:200] = (0, 0, 200)  # red again
    red, blue, red2 = (colour_histogram(frame, (x, 20, 40, 60)) for x in (10, 110, 160))
    assert histogram_similarity(red, red2) > 0.9
    assert histogram_similarity(red, blue) < 0.2
    assert histogram_similarity(red, None) == -1.0
    assert colour_histogram(frame, (500, 20, 40, 60)) is None  # outside the frame


def test_foreground_mask_marks_colours_rare_outside_the_boxes():
    """Pixels whose colour is rare outside the (widened) boxes are foreground: a red figure on a noisy grey
    background, whatever box it is in; the background is not."""
    rng = np.random.default_rng(2)
    frame = rng.integers(90, 160, (240, 320, 3), dtype=np.uint8)
    frame[60:200, 40:80] = (0, 0, 220)
    mask = foreground_mask(frame, [(30, 50, 60, 160)])
    assert mask[70:190, 45:75].mean() > 0.95
    assert mask[:, 200:].mean() < 0.01


def test_with_ring_common_a_floor_the_widened_boxes_cover_stays_background_and_an_arm_in_it_does_not():
    """Where the dancers' widened boxes cover every pixel of the floor's colour, that colour is missing from the
    background sample and the whole floor would come out as foreground. With ``ring_common`` a colour that fills
    more than that fraction of the ring between the boxes and the widened boxes is background: the floor is, a
    thin arm reaching into the ring (a small part of it) is still foreground."""
    frame = np.zeros((400, 320, 3), np.uint8)
    frame[:200] = (120, 60, 40)  # wall
    frame[200:] = (60, 140, 60)  # floor, all of it within the widened boxes below
    frame[230:370, 40:80] = (0, 0, 220)  # a red figure in the first box
    frame[230:370, 200:240] = (220, 0, 220)  # a magenta one in the second
    frame[260:266, 80:130] = (140, 170, 230)  # the first one's arm, out into the ring
    boxes = [(40, 230, 40, 140), (200, 230, 40, 140)]
    margin = (1.0, 0.4)  # the widened boxes reach the frame's bottom and sides
    plain = foreground_mask(frame, boxes, margin=margin)
    assert plain[380:, :].mean() > 0.95  # without: the floor is foreground
    mask = foreground_mask(frame, boxes, margin=margin, ring_common=0.02)
    assert mask[380:, :].mean() < 0.01 and mask[200:, 100:180].mean() < 0.05
    assert mask[261:265, 82:128].mean() > 0.95  # the arm
    assert mask[240:360, 45:75].mean() > 0.95 and mask[240:360, 205:235].mean() > 0.95  # the figures
    assert mask[:150, :].mean() < 0.01  # the wall


def test_with_ring_common_a_person_beside_a_dancer_stays_foreground():
    """A colour common in the ring is background only where it shows on both sides of some box (the floor and the
    wall do): a person no box holds, standing on one side of a dancer inside her widened box, fills as much of the
    ring as a floor would and stays foreground, and so do legs below a box that holds only the upper body."""
    frame = np.zeros((400, 320, 3), np.uint8)
    frame[:200] = (120, 60, 40)  # wall
    frame[200:] = (60, 140, 60)  # floor, all of it within the widened boxes below
    frame[230:370, 40:80] = (0, 0, 220)  # a red figure in the first box
    frame[230:370, 200:240] = (220, 0, 220)  # a magenta one in the second
    frame[220:370, 100:130] = (0, 200, 230)  # a yellow person beside the first, no one's box
    boxes = [(40, 230, 40, 140), (200, 230, 40, 140)]
    mask = foreground_mask(frame, boxes, margin=(1.0, 0.4), ring_common=0.02)
    assert mask[230:360, 105:125].mean() > 0.95  # the person
    assert mask[380:, :].mean() < 0.01 and mask[:150, :].mean() < 0.01  # floor and wall
    upper = foreground_mask(frame, [(40, 230, 40, 60)], margin=(1.0, 2.5), ring_common=0.02)  # rows 80-440
    assert upper[300:360, 45:75].mean() > 0.95  # the first figure's legs, below her box


def test_with_arm_margin_a_bare_forearm_past_the_margin_stays_foreground():
    """A figure's arm reaches out past the widened box at arm height, its bare forearm a colour found nowhere
    else: without ``arm_margin`` the part beyond the margin makes that colour background, and the whole forearm
    with it; with it those rows are left out of the sample further sideways and the forearm is foreground. Below
    the arm rows the sample is as before: a patch of the same colour at leg height, beyond the margin, stays
    background."""
    frame = np.zeros((240, 320, 3), np.uint8)
    frame[:] = (60, 140, 60)
    frame[60:200, 150:170] = (0, 0, 220)  # a red figure
    frame[80:84, 170:180] = (0, 0, 220)  # its sleeve
    frame[80:84, 180:220] = (140, 170, 230)  # its forearm, out to x 220: 0.36 x 140 px beyond the box
    box = (150, 60, 20, 140)  # margin 0.3: the widened box ends at x 212
    plain = foreground_mask(frame, [box], opening=1)
    assert plain[80:84, 170:180].all() and not plain[80:84, 180:212].any()  # the arm ends at the sleeve
    mask = foreground_mask(frame, [box], opening=1, arm_margin=0.45)
    assert mask[80:84, 170:220].all()
    frame[180:184, 180:220] = (140, 170, 230)  # the same colour at leg height
    low = foreground_mask(frame, [box], opening=1, arm_margin=0.45)
    assert not low[180:184, 215:220].any()
