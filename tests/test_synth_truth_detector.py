import os

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.synth.truth_detector import GroundTruthDetector

os.environ.setdefault("MUJOCO_GL", "egl")


def _standing(x: float, height: float = 200.0) -> np.ndarray:
    """(25, 2) px: 25 keypoints of a dancer standing at x, feet at y 400, spread over a box 0.3 x height wide."""
    ys = np.linspace(400 - 0.9 * height, 400, 25)
    xs = x + np.linspace(-0.15, 0.15, 25) * height
    return np.stack([xs, ys], axis=1)


def _truth(visible_counts, frames: int = 2):
    """gt.npz-like arrays for dancers at x 100, 300, ... each showing its first ``visible_counts[i]`` keypoints
    (the rest hidden by another dancer, code 1), on every frame; amodal boxes 0.4 x 200 px wide, 200 px tall."""
    n = len(visible_counts)
    keypoints = np.stack([np.repeat(_standing(100 + 200 * i)[None], frames, axis=0) for i in range(n)])
    visibility = np.ones((n, frames, 25), np.int8)
    for i, count in enumerate(visible_counts):
        visibility[i, :, :count] = 2
    boxes = np.stack([np.repeat([[100 + 200 * i - 40, 200, 80, 200]], frames, axis=0) for i in range(n)]).astype(float)
    return keypoints, visibility, boxes


def test_a_fully_visible_dancer_is_a_sure_find_with_its_amodal_box_and_keypoints():
    keypoints, visibility, boxes = _truth([25])
    (person,) = GroundTruthDetector(keypoints, visibility, boxes).detect(np.zeros((480, 640, 3), np.uint8), 1)
    assert not person.weak and person.score == 1.0
    # keypoints span x 70-130, y 220-400; grown by 0.15 x 200 = 30 px and kept inside the amodal box 60-140, 200-400
    assert person.box == pytest.approx((60.0, 200.0, 80.0, 200.0))
    assert np.allclose(person.keypoints[:, :2], keypoints[0, 1]) and (person.keypoints[:, 2] == 1).all()
    assert person.joint_names[8] == "mid_hip" and np.allclose(person.body25(), person.keypoints)


def test_partly_hidden_dancers_are_weak_finds_or_none_and_show_only_their_visible_part():
    keypoints, visibility, boxes = _truth([10, 5])  # 40 % and 20 % of the keypoints seen
    people = GroundTruthDetector(keypoints, visibility, boxes).detect(np.zeros((480, 640, 3), np.uint8), 0)
    assert len(people) == 1
    person = people[0]
    assert person.weak and person.score == pytest.approx(0.4)
    # the first 10 keypoints reach down to y 200 + 0.9*200*9/24 = 287.5 (+30 px), not the feet
    x, y, w, h = person.box
    assert y == pytest.approx(200.0) and y + h == pytest.approx(220 + 180 * 9 / 24 + 30)
    assert (person.keypoints[:10, 2] == 1).all() and (person.keypoints[10:, 2] == 0).all()
    assert np.isnan(person.keypoints[10:, :2]).all()


def test_keypoints_outside_the_image_do_not_count_as_seen():
    keypoints, visibility, boxes = _truth([25])
    visibility[0, :, :20] = 0  # outside the image: 5 of 25 seen
    assert GroundTruthDetector(keypoints, visibility, boxes).detect(None, 0) == []
    assert len(GroundTruthDetector(keypoints, visibility, boxes, weak_fraction=0.2).detect(None, 0)) == 1


def test_bad_ground_truth_and_frames_are_refused_with_clear_errors(tmp_path):
    keypoints, visibility, boxes = _truth([25])
    with pytest.raises(HDVRError, match="keypoints2d"):
        GroundTruthDetector(keypoints[..., :1], visibility, boxes)
    with pytest.raises(HDVRError, match="weak_fraction"):
        GroundTruthDetector(keypoints, visibility, boxes, sure_fraction=0.2, weak_fraction=0.3)
    with pytest.raises(HDVRError, match="frame 2 is outside"):
        GroundTruthDetector(keypoints, visibility, boxes).detect(None, 2)
    with pytest.raises(HDVRError, match="no such ground-truth file"):
        GroundTruthDetector.from_clip(tmp_path)


def test_tracking_a_rendered_clip_with_its_truth_finds_each_dancer_s_visible_keypoints(tmp_path):
    """A rendered hdvr synth couple tracked with its own ground truth as detector: the boxes follow the dancers and
    each dancer's keypoint file holds its visible ground-truth keypoints on the detector frames."""
    from hdvr.synth.groundtruth import clip_spec, make_clip
    from hdvr.tracking.evaluation import evaluate_tracking
    from hdvr.tracking.pipeline import DancerStart, track_video

    spec = clip_spec(0, 3, ("swing",), (2, 2), 1.0, size=(320, 240))
    make_clip(tmp_path, spec, render=True)
    folder = tmp_path / spec.name
    detector = GroundTruthDetector.from_clip(folder)
    with np.load(folder / "gt.npz") as gt:
        boxes, visible, points = gt["boxes"], gt["visibility"] == 2, gt["keypoints2d"]
    starts = [DancerStart(0, tuple(float(v) for v in boxes[i, 0])) for i in range(2)]
    run = track_video(folder / "video.mp4", tmp_path / "out", detector=detector, starts=starts, detect_every=3,
                      overlay=False, write=False)
    assert evaluate_tracking(np.transpose(boxes, (1, 0, 2)), run.boxes).idf1 > 0.9
    for i in range(2):
        for t in np.flatnonzero(run.detected):
            seen = visible[i, t] & (run.keypoints[t, i, :, 2] > 0)
            assert seen.sum() >= 0.5 * visible[i, t].sum()
            assert np.allclose(run.keypoints[t, i, seen, :2], points[i, t, seen], atol=1e-3)
