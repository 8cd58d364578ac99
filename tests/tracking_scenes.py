"""Small hand-made tracking scenes shared by the tests of the multi-dancer tracker's modules."""

import numpy as np

from hdvr.tracking.appearance import box_iou
from hdvr.tracking.multi import MultiDancerTracker, MultiTrackerConfig
from hdvr.tracking.testclips import default_crossing_specs, render_clip
from hdvr.video import VideoReader


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


def run_tracker(path, truth, detections=None):
    """Algorithm 1* over the video at ``path`` from ``truth``'s first-frame boxes (``detections(t)``: person boxes
    of frame t, or None): (T, N, 4) px boxes and per-frame statuses."""
    tracker, boxes, status = None, [], []
    for t, frame in enumerate(VideoReader(path)):
        if tracker is None:
            tracker = MultiDancerTracker(frame, truth.boxes[0])
            result = tracker.result()
        else:
            result = tracker.step(frame, detections(t) if detections else None)
        boxes.append(result.boxes)
        status.append(result.status)
    return np.array(boxes), status


def crossing_with_a_lost_dancer(tmp_path, frames: int):
    """The procedural crossing of 2 figures (seed 0, ``frames`` frames; apart from frame 1 on) as true boxes per
    frame, and a function that tracks it with a ``MultiTrackerConfig``, dancer 0 lost on dancer 1 in frame 1 (its box
    and last clear box left on the other dancer, occluded there), the true boxes given as detections or not:
    (dancer 0's status in frames 2 on, its last box)."""
    truth = render_clip(tmp_path / "clip.mp4", frames=frames, specs=default_crossing_specs(num_figures=2, seed=0))
    video = list(VideoReader(tmp_path / "clip.mp4"))
    boxes = [[tuple(float(v) for v in b) for b in frame_boxes] for frame_boxes in truth.boxes]
    assert box_iou(boxes[1][0], boxes[1][1]) == 0.0

    def track_lost(config: MultiTrackerConfig, detections: bool) -> tuple[list[str], tuple]:
        tracker = MultiDancerTracker(video[0], boxes[0], config)
        tracker.step(video[1], boxes[1] if detections else None)
        lost, other = tracker.dancers
        lost.box = lost.stored_box = other.box  # it went off with the other dancer and failed there
        lost.tracker.center = other.tracker.center
        tracker._occlude(lost, [other])
        seen = []
        for t in range(2, frames):
            tracker.step(video[t], boxes[t] if detections else None)
            seen.append(lost.status)
        return seen, lost.box

    return boxes, track_lost
