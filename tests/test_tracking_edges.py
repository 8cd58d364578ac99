"""Dancers leaving and re-entering the frame (:mod:`hdvr.tracking.edges`), on procedural clips."""

import numpy as np

from hdvr.tracking.evaluation import evaluate_tracking, iou_matrix
from hdvr.tracking.multi import MultiDancerTracker, MultiTrackerConfig
from hdvr.tracking.testclips import default_crossing_specs, render_clip
from hdvr.video import VideoReader
from tracking_scenes import run_tracker


def _exit_clip(path, frames=160, seed=0):
    """Figure 1 walks out on the right (frames ~62-119 off-frame) and back in; figure 0 walks in the frame."""
    from dataclasses import replace

    specs = default_crossing_specs(num_figures=2, seed=seed)
    specs[1] = replace(specs[1], start=(0.7 * 640, specs[1].start[1]), velocity=(abs(specs[1].velocity[0]), 0.0),
                       turn=(0.06, 1.2))
    return render_clip(path, frames=frames, specs=specs, seed=seed)


def test_dancer_leaving_the_frame_is_out_and_reidentified(tmp_path):
    """A dancer who walks out of the frame gets no box (status "out") instead of one stuck at the edge, and takes
    its box again from a detection when it comes back; boxes are clipped to the frame."""
    from hdvr.tracking.multi import OUT, TRACKED

    truth = _exit_clip(tmp_path / "clip.mp4")
    gone = ~np.isfinite(truth.boxes[:, 1, 0])
    assert 25 < gone.sum() < 60  # the clip does what the test needs
    dets = lambda t: [tuple(b) for b in truth.boxes[t] if np.isfinite(b).all()] if t % 3 == 0 else None  # noqa: E731
    boxes, status = run_tracker(tmp_path / "clip.mp4", truth, dets)
    out = np.array([s[1] == OUT for s in status])
    assert out[gone].mean() > 0.9, np.flatnonzero(out)
    assert np.isnan(boxes[out, 1]).all() and np.isfinite(boxes[~out, 1]).all()
    assert status[-1][1] == TRACKED and status[-1][0] == TRACKED
    end = boxes[-1, 1, :2] + boxes[-1, 1, 2:] / 2
    assert np.linalg.norm(end - (truth.boxes[-1, 1, :2] + truth.boxes[-1, 1, 2:] / 2)) < 30
    finite = np.isfinite(boxes).all(axis=-1)
    assert (boxes[finite][:, 0] >= 0).all() and (boxes[finite][:, 0] + boxes[finite][:, 2] <= 640 + 1e-6).all()
    scores = evaluate_tracking(truth.boxes, boxes)
    assert scores.id_switches == 0 and scores.idf1 > 0.8, scores  # re-entry starts on a partial detection


def test_dancer_leaving_without_detector_is_out(tmp_path):
    """Without detections a dancer walking out is marked out once its box, moved on with its velocity, has left
    and the box at the edge no longer matches its memory; the other dancer is not disturbed."""
    from hdvr.tracking.multi import OUT

    truth = _exit_clip(tmp_path / "clip.mp4", frames=100)
    boxes, status = run_tracker(tmp_path / "clip.mp4", truth)
    gone = ~np.isfinite(truth.boxes[:, 1, 0])
    out = np.array([s[1] == OUT for s in status])
    assert out[gone].all() and not out[:50].any(), np.flatnonzero(out)
    assert not any(s[0] == OUT for s in status)


def test_dancer_reenters_at_the_edge_without_detector(tmp_path):
    """Without detections a dancer who left on the right is re-identified on the strip at that edge when it comes
    back (its histogram matches the memory clearly better than the empty edge did), and followed in."""
    from hdvr.tracking.multi import OUT

    truth = _exit_clip(tmp_path / "clip.mp4")
    boxes, status = run_tracker(tmp_path / "clip.mp4", truth)
    gone = ~np.isfinite(truth.boxes[:, 1, 0])
    back = int(np.flatnonzero(gone)[-1]) + 1  # first frame with a part of it in the frame again
    out = np.array([s[1] == OUT for s in status])
    assert out[gone].all() and not out[:50].any(), np.flatnonzero(out)
    first_seen = back + int(np.argmin(out[back:]))
    assert not out[first_seen:].any() and first_seen - back <= 15, (back, first_seen)
    after = range(first_seen, first_seen + 20)  # the box follows it in
    assert np.mean([iou_matrix(truth.boxes[t, 1:], boxes[t, 1:])[0, 0] for t in after]) > 0.6
    scores = evaluate_tracking(truth.boxes, boxes)
    assert scores.id_switches == 0 and scores.idf1 > 0.9, scores


def test_dancer_walking_out_slowly_behind_its_detections_is_out(tmp_path):
    """A dancer who walks out slowly on the left is detected by the part still in the frame; its box adapts to
    those narrowing detections and, when nothing of it is left, would stay on the background at the edge. The
    last detection was cut by the edge and none follows: it is out (no box) for the rest of the clip."""
    from dataclasses import replace

    from hdvr.tracking.multi import OUT

    specs = default_crossing_specs(num_figures=2, seed=1)
    specs[1] = replace(specs[1], start=(0.25 * 640, specs[1].start[1]), velocity=(-2.5, 0.0), turn=(-0.3, 0.94))
    truth = render_clip(tmp_path / "clip.mp4", frames=130, specs=specs, seed=1)
    gone = ~np.isfinite(truth.boxes[:, 1, 0])
    assert 30 < gone.sum() and not gone[:80].any()  # the clip does what the test needs

    def detections(t):  # the detector finds the part in the frame while it is at least 0.15 x as wide as tall
        if t % 3:
            return None
        cut = [(max(b[0], 0.0), b[1], min(b[0] + b[2], 640.0) - max(b[0], 0.0), b[3]) for b in truth.boxes[t]
               if np.isfinite(b).all()]
        return [b for b in cut if b[2] >= 0.15 * b[3]]

    boxes, status = run_tracker(tmp_path / "clip.mp4", truth, detections)
    out = np.array([s[1] == OUT for s in status])
    assert out[gone].all(), np.flatnonzero(out)
    assert np.isnan(boxes[gone, 1]).all()
    assert not any(s[0] == OUT for s in status)


def test_dancer_at_the_edge_missed_by_the_detector_is_not_out(tmp_path):
    """A dancer who turns back partly out of the frame, and whom the detector stops finding after a detection cut
    by the edge, is still there: its box holds foreground, so it is not marked out (without that test it is)."""
    from dataclasses import replace

    from hdvr.tracking.multi import OUT

    specs = default_crossing_specs(num_figures=2, seed=1)
    specs[1] = replace(specs[1], start=(0.2 * 640, specs[1].start[1]), velocity=(-2.5, 0.0), turn=(0.04, 0.94))
    truth = render_clip(tmp_path / "clip.mp4", frames=90, specs=specs, seed=1)
    assert np.isfinite(truth.boxes[:, 1]).all() and (truth.boxes[:, 1, 0] < 1).any()  # cut by the edge, never out

    def detections(t):  # the figure is found until it reaches the edge, then missed
        if t % 3:
            return None
        cut = [(max(b[0], 0.0), b[1], min(b[0] + b[2], 640.0) - max(b[0], 0.0), b[3]) for b in truth.boxes[t]]
        return cut if truth.boxes[:t + 1, 1, 0].min() >= 1 or truth.boxes[t, 1, 0] < 1 else cut[:1]

    boxes, status = run_tracker(tmp_path / "clip.mp4", truth, detections)
    assert not any(s[1] == OUT for s in status), [t for t, s in enumerate(status) if s[1] == OUT]
    scores = evaluate_tracking(truth.boxes, boxes)
    assert scores.idf1 > 0.9, scores
    config = MultiTrackerConfig(exit_max_foreground=1.01)  # every box counts as background
    tracker, outs = None, []
    for t, frame in enumerate(VideoReader(tmp_path / "clip.mp4")):
        tracker = tracker or MultiDancerTracker(frame, truth.boxes[0], config)
        outs.append(tracker.step(frame, detections(t)).status[1] == OUT if t else False)
    assert any(outs)
