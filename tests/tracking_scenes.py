"""Small hand-made tracking scenes shared by the tests of the multi-dancer tracker's modules."""

import numpy as np

from hdvr.tracking.multi import MultiDancerTracker


def two_colour_frame(rng, boxes_colours, split: float = 0.5):
    """A noisy grey frame (480 x 640) with each (x, y, w, h) box painted in two BGR colours (top, bottom), the top
    one down to ``split`` x the box height."""
    frame = rng.integers(90, 160, (480, 640, 3), dtype=np.uint8)
    for (x, y, w, h), (top, bottom) in boxes_colours:
        x, y, w, h = int(x), int(y), int(w), int(h)
        frame[y:y + int(split * h), x:x + w] = top
        frame[y + int(split * h):y + h, x:x + w] = bottom
    return frame


def waiting_behind(frame, config=None):
    """A tracker with dancer 0 started hidden behind dancer 1 (box bottom lower), on ``frame``."""
    behind, front = (300.0, 100.0, 60.0, 200.0), (280.0, 180.0, 120.0, 260.0)
    tracker = MultiDancerTracker(frame, [behind, front], config)
    assert tracker.dancers[0].hidden_behind == 1
    return tracker
