import numpy as np

import pytest

from hdvr.tracking.evaluation import iou_matrix
from hdvr.tracking.testclips import _bounce, default_crossing_specs, render_clip, troupe_specs
from hdvr.video import VideoReader


def test_clip_ground_truth_is_consistent_and_deterministic(tmp_path):
    specs = default_crossing_specs((320, 240), num_figures=3, seed=5)
    a = render_clip(tmp_path / "a.mp4", frames=12, size=(320, 240), specs=specs, seed=5)
    b = render_clip(tmp_path / "b.mp4", frames=12, size=(320, 240), specs=specs, seed=5)
    np.testing.assert_array_equal(a.boxes, b.boxes)
    assert a.boxes.shape == (12, 3, 4) and a.keypoints.shape == (12, 3, 25, 3)
    # every drawn joint lies inside its figure's box
    x, y, w, h = (a.boxes[..., k][..., None] for k in range(4))
    kp = a.keypoints
    seen = kp[..., 2] > 0
    inside = (kp[..., 0] >= x - 1) & (kp[..., 0] <= x + w + 1) & (kp[..., 1] >= y - 1) & (kp[..., 1] <= y + h + 1)
    assert inside[seen].all()
    frames = list(VideoReader(tmp_path / "a.mp4"))
    assert len(frames) == 12 and frames[0].shape == (240, 320, 3)


def test_bounce():
    assert _bounce(5, 0, 10) == 5
    assert _bounce(12, 0, 10) == 8
    assert _bounce(-3, 0, 10) == 3
    assert _bounce(25, 0, 10) == 5


def test_troupe_starts_side_by_side_in_two_rows_and_is_deterministic(tmp_path):
    specs = troupe_specs(num_figures=8, seed=3)
    assert specs == troupe_specs(num_figures=8, seed=3)
    back, front = [s for s in specs if s.depth >= 1.0], [s for s in specs if s.depth < 1.0]
    assert len(back) == len(front) == 4
    assert max(s.height for s in back) < min(s.height for s in front)  # the back row is farther: smaller
    assert len({s.colours for s in specs}) == 8
    truth = render_clip(tmp_path / "t.mp4", frames=3, specs=specs, seed=3)
    overlaps = iou_matrix(truth.boxes[0], truth.boxes[0])
    np.fill_diagonal(overlaps, 0)
    assert overlaps.max() < 0.2  # side by side in the first frame, not stacked
    with pytest.raises(ValueError):
        troupe_specs(num_figures=9)
