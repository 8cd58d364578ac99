"""hdvr.pose2d.cache: the detector's people per frame kept in a file, and a second run that takes them from it."""

import numpy as np
import pytest

from hdvr.pose2d.base import PersonPose
from hdvr.pose2d.cache import (CachingDetector, detector_signature, load_detections, save_detections,
                              video_signature)
from hdvr.tracking.pipeline import track_video
from hdvr.tracking.testclips import default_crossing_specs, render_clip


def _person(x, score=0.8, weak=False):
    kp = np.full((17, 3), np.nan, np.float32)
    kp[:, 2] = 0
    kp[:12] = [x + 20.5, 100.25, 0.9]
    return PersonPose(kp, (x + 0.125, 50.0, 40.0, 120.0), score, weak=weak)


class _CountingDetector:
    """Finds a person wherever the frame's brightest column is, and counts what it is asked."""

    name = "counting"

    def __init__(self, setting=1):
        self.setting = setting
        self.whole, self.crops = 0, 0

    def cache_key(self):
        return {"setting": self.setting}

    def detect(self, frame_bgr, frame_index):
        if frame_bgr.shape[:2] == (480, 640):
            self.whole += 1
        else:
            self.crops += 1
        column = float(np.argmax(frame_bgr.sum(axis=(0, 2))))
        return [_person(column - 20, score=0.5 + 0.001 * frame_index)] if frame_index % 4 else []


def test_people_read_back_exactly_and_only_under_the_signature_they_were_written_with(tmp_path):
    found = {0: [_person(10), _person(200, 0.25, weak=True)], 3: [], 6: [_person(300)]}
    signature = {"video": {"name": "v.mp4"}, "detector": {"input_size": (480, 480)}}
    path = save_detections(tmp_path / "d.npz", signature, found)
    back = load_detections(path, signature)
    assert sorted(back) == [0, 3, 6] and back[3] == []  # a frame where nobody was found is remembered too
    for t in found:
        for a, b in zip(found[t], back[t]):
            np.testing.assert_array_equal(a.keypoints, b.keypoints)
            assert (a.box, a.score, a.weak, a.joint_names) == (b.box, b.score, b.weak, b.joint_names)
    assert load_detections(path, {**signature, "detector": {"input_size": (640, 640)}}) == {}
    assert load_detections(tmp_path / "missing.npz", signature) == {}
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    assert load_detections(tmp_path / "junk.npz", signature) == {}
    save_detections(tmp_path / "empty.npz", signature, {0: [], 3: []})  # nobody found anywhere
    assert load_detections(tmp_path / "empty.npz", signature) == {0: [], 3: []}
    assert detector_signature(_CountingDetector(2)) == {"name": "counting", "setting": 2}
    assert detector_signature(object()) is None  # no cache_key: not cached


def test_the_caching_detector_answers_whole_frames_it_holds_and_passes_crops_on():
    inner = _CountingDetector()
    cached = CachingDetector(inner, (640, 480), stored={5: [_person(1)]})
    frame, crop = np.zeros((480, 640, 3), np.uint8), np.zeros((100, 100, 3), np.uint8)
    assert cached.detect(frame, 5)[0].box == _person(1).box and inner.whole == 0 and cached.reused == 1
    cached.detect(frame, 6)
    cached.detect(crop, 5)
    assert (inner.whole, inner.crops) == (1, 1)
    assert sorted(cached.found) == [5, 6] and sorted(cached.all_found()) == [5, 6]


def test_the_caching_detector_gives_the_wrapped_one_at_another_input_size_for_crops():
    """Crops never come from the file, so ``at_input_size`` hands out the wrapped detector's own resized view
    (where it has one; else the caching detector itself)."""

    class Resizable(_CountingDetector):
        def at_input_size(self, size):
            view = Resizable(self.setting)
            view.size = size
            return view

    view = CachingDetector(Resizable(), (640, 480)).at_input_size(320)
    assert isinstance(view, Resizable) and view.size == 320
    plain = CachingDetector(_CountingDetector(), (640, 480))
    assert plain.at_input_size(320) is plain


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    path = tmp_path_factory.mktemp("cache") / "clip.mp4"
    truth = render_clip(path, frames=24, specs=default_crossing_specs(num_figures=2, seed=4))
    return path, truth.boxes[0]


def test_a_second_run_takes_the_detector_s_people_from_the_cache_and_writes_the_same_outputs(clip, tmp_path):
    path, boxes = clip
    cache = tmp_path / "detections.npz"
    first, again, other = _CountingDetector(), _CountingDetector(), _CountingDetector(setting=2)
    runs = [track_video(path, tmp_path / "a", detector=d, boxes=boxes, detect_every=2, overlay=False,
                        timeline=False, detections_cache=cache) for d in (first, again)]
    # every 2nd of 24 frames and the last
    assert first.whole == 13 and again.whole == 0 and runs[1].detections_reused == 13
    assert cache in runs[0].outputs
    np.testing.assert_array_equal(runs[0].boxes, runs[1].boxes)
    np.testing.assert_array_equal(runs[0].keypoints, runs[1].keypoints)
    track_video(path, tmp_path / "b", detector=other, boxes=boxes, detect_every=2, overlay=False, timeline=False,
                detections_cache=cache)
    assert other.whole == 13  # other settings: the file does not hold their people, and is replaced
    assert load_detections(cache, {"video": {}, "detector": {}}) == {}
    more = _CountingDetector()
    track_video(path, tmp_path / "c", detector=more, boxes=boxes, detect_every=1, overlay=False, timeline=False,
                detections_cache=cache, max_frames=10)
    assert more.whole == 10  # setting 1 again: its file was replaced by setting 2's
    last = _CountingDetector()
    track_video(path, tmp_path / "d", detector=last, boxes=boxes, detect_every=1, overlay=False, timeline=False,
                detections_cache=cache)
    assert last.whole == 14  # frames 0-9 from the file, 10-23 found now
    signature = {"video": video_signature(path, (640, 480)), "detector": detector_signature(last)}
    assert sorted(load_detections(cache, signature)) == list(range(24))
