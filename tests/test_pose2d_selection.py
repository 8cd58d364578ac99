"""Algorithm 2*: choosing each tracked dancer's pose among all detected poses, on a procedural crossing clip
whose skeletons are known (the "detector" returns the true poses of all figures, shuffled)."""

import numpy as np

from hdvr.layouts import BODY25_NAMES
from hdvr.pose2d.base import PersonPose, box_from_keypoints
from hdvr.pose2d.selection import PoseSelector, pose_histogram
from hdvr.tracking.evaluation import pck
from hdvr.tracking.testclips import default_crossing_specs, render_clip
from hdvr.video import VideoReader


def _true_poses(truth, t, rng):
    poses = []
    for i in rng.permutation(truth.keypoints.shape[1]):
        kp = truth.keypoints[t, i].copy()
        kp[..., :2] += rng.normal(0, 1.5, kp[..., :2].shape)
        poses.append(PersonPose(kp, box_from_keypoints(kp), 0.9, BODY25_NAMES))
    return poses


def test_selection_keeps_identities_through_crossing(tmp_path):
    truth = render_clip(tmp_path / "clip.mp4", frames=120, specs=default_crossing_specs(num_figures=2, seed=3))
    rng = np.random.default_rng(0)
    selector = PoseSelector(2)
    chosen = np.full((120, 2, 25, 3), np.nan, np.float32)
    for t, frame in enumerate(VideoReader(tmp_path / "clip.mp4")):
        # the true boxes stand in for the tracker here: Algorithm 2* alone is under test
        for i, pose in enumerate(selector.select(frame, truth.boxes[t], _true_poses(truth, t, rng))):
            if pose is not None:
                chosen[t, i] = pose.body25()
    for i in range(2):
        assert pck(chosen[:, i], truth.keypoints[:, i], alpha=0.2) > 0.97


def test_pose_histogram_and_no_candidate(tmp_path):
    truth = render_clip(tmp_path / "clip.mp4", frames=2, specs=default_crossing_specs(num_figures=2, seed=0))
    frame = next(iter(VideoReader(tmp_path / "clip.mp4")))
    poses = _true_poses(truth, 0, np.random.default_rng(1))
    h = pose_histogram(frame, poses[0])
    assert h is not None and abs(h.sum() - 1) < 1e-5
    selector = PoseSelector(1)
    assert selector.select(frame, [(5, 5, 10, 10)], poses) == [None]  # no pose overlaps that box
    assert selector.select(frame, [(5, 5, 10, 10)], []) == [None]


def test_a_dancer_waiting_behind_another_gives_way_to_it(tmp_path):
    """``yields[i, j]``: dancer j (waiting hidden behind dancer i, with i's colours as its memory) cannot take a pose
    whose box overlaps i's box about as much as its own; one that fits j's box clearly better stays j's."""
    truth = render_clip(tmp_path / "clip.mp4", frames=2, specs=default_crossing_specs(num_figures=2, seed=0))
    frame = next(iter(VideoReader(tmp_path / "clip.mp4")))
    pose = PersonPose(truth.keypoints[0, 0], box_from_keypoints(truth.keypoints[0, 0]), 0.9, BODY25_NAMES)
    x, y, w, h = pose.box
    waits_behind = np.array([[False, False], [True, False]])  # [1, 0]: dancer 0 waits behind dancer 1
    # the boxes nearly coincide (IoU with the pose's box 1.0 and 0.92): the waiting dancer's fits a little better
    boxes = [pose.box, (x + 0.04 * w, y, w, h)]
    assert PoseSelector(2).select(frame, boxes, [pose]) == [pose, None]
    assert PoseSelector(2).select(frame, boxes, [pose], yields=waits_behind) == [None, pose]
    # the front dancer's box is well off the pose (IoU 0.54): the pose is the waiting dancer's
    boxes = [pose.box, (x + 0.3 * w, y, w, h)]
    assert PoseSelector(2).select(frame, boxes, [pose], yields=waits_behind) == [pose, None]
    assert PoseSelector(2).select(frame, boxes[::-1], [pose], yields=waits_behind.T) == [None, pose]
