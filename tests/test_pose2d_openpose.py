import json

import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.pose2d.openpose_json import OpenPoseJsonDetector


def test_reads_people_per_frame(tmp_path):
    rng = np.random.default_rng(0)
    for t in range(3):
        people = []
        for k in range(t):  # frame t has t people
            kp = np.column_stack([rng.uniform(100, 200, 25), rng.uniform(50, 400, 25), np.full(25, 0.8)])
            kp[3] = 0  # a missing joint
            people.append({"pose_keypoints_2d": kp.ravel().tolist()})
        (tmp_path / f"clip_{t:012d}_keypoints.json").write_text(json.dumps({"people": people}))
    det = OpenPoseJsonDetector(tmp_path)
    frame = np.zeros((480, 640, 3), np.uint8)
    assert det.detect(frame, 0) == []
    two = det.detect(frame, 2)
    assert len(two) == 2
    assert np.isnan(two[0].keypoints[3, 0]) and two[0].keypoints[3, 2] == 0
    x, y, w, h = two[0].box
    assert 80 < x < 110 and w > 80
    assert two[0].body25().shape == (25, 3)
    assert det.detect(frame, 99) == []
    assert det.supports_crops is False  # results are looked up by frame index: the tracker does not zoom into it


def test_bad_folder(tmp_path):
    with pytest.raises(HDVRError, match="no OpenPose JSON"):
        OpenPoseJsonDetector(tmp_path)
    (tmp_path / "a_keypoints.json").write_text("{broken")
    with pytest.raises(HDVRError, match="corrupt"):
        OpenPoseJsonDetector(tmp_path).detect(np.zeros((4, 4, 3), np.uint8), 0)
