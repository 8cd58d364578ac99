"""scripts/make_tracking_docs.py: the drawing of a case (boxes, crop) and the before/after picture."""

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "make_tracking_docs.py"


def _script(monkeypatch):
    # the script sets MUJOCO_GL for its renders when absent; undone after the test
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))
    spec = importlib.util.spec_from_file_location("make_tracking_docs", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class _FindsNoOne:
    """A detector that runs on every frame it is given and finds no one."""

    def detect(self, frame, frame_index=0):
        return []


def _assert_two_panels(path: Path, min_aspect: float = 1.5) -> None:
    """The picture at ``path`` is two panels side by side (wider than ``min_aspect`` x its height)."""
    import cv2

    picture = cv2.imread(str(path))
    assert picture is not None and picture.shape[1] > min_aspect * picture.shape[0]


def test_two_pictures_of_a_case_are_cropped_alike_and_set_side_by_side(monkeypatch):
    script = _script(monkeypatch)
    frame = np.full((480, 640, 3), 90, np.uint8)
    gt = np.array([[200.0, 100.0, 80.0, 200.0], [260.0, 110.0, 60.0, 190.0]])
    narrow = np.array([[200.0, 100.0, 80.0, 200.0], [270.0, 110.0, 30.0, 190.0]])
    wide = np.array([[200.0, 100.0, 80.0, 200.0], [150.0, 110.0, 200.0, 190.0]])  # reaches further left
    alone = script.draw_case(frame, gt, narrow, [])
    both = np.concatenate([narrow, wide])
    left = script.draw_case(frame, gt, narrow, [], crop_boxes=both)
    right = script.draw_case(frame, gt, wide, [], crop_boxes=both)
    assert left.shape == right.shape  # the same region of the frame
    assert left.shape[1] > alone.shape[1]  # widened to the other picture's boxes (2x scale)
    assert (left[40:, :, 2] > 200).any() and (left[40:, :, 1] > 150).any()  # dancer 0 red, dancer 1 green drawn
    picture = script._side_by_side(left, right, ("rule off", "rule on"))
    assert picture.shape[0] == left.shape[0] + 26 and picture.shape[1] == 2 * (left.shape[1] + 6)


def test_the_procedural_hold_picture_shows_the_held_and_the_written_boxes_side_by_side(monkeypatch, tmp_path):
    """``--only procedural-hold``: a procedural crossing clip (3 figures, seed 2) tracked as ``hdvr track`` does,
    drawn with the boxes held where a figure went behind (left) and as written (right). With a detector that finds
    no one (the tracker alone, as the benchmark's first row), figure 0 walks on behind figure 1 and is not taken
    again: held, its box stays 200 px behind it; written, it follows."""
    from hdvr.tracking.evaluation import iou_matrix

    script = _script(monkeypatch)
    path = tmp_path / "hold.jpg"
    truth, (held, written) = script._write_procedural_hold(path, tmp_path, _FindsNoOne(), 3, 2, 110)
    assert iou_matrix(held[110, :1], truth[110, :1])[0, 0] < 0.3
    # a match as the benchmark counts it (the box, trimmed to the figure with its arms in, is narrower than the
    # figure with its arms out: ``foreground_trim``, session 60)
    assert iou_matrix(written[110, :1], truth[110, :1])[0, 0] > 0.5
    _assert_two_panels(path)


def test_the_procedural_trim_picture_shows_the_boxes_without_and_with_foreground_trim(monkeypatch, tmp_path):
    """``--only procedural-trim``: the procedural crossing clip of 2 figures, seed 9, tracked as ``hdvr track``
    does without (left) and with (right) ``foreground_trim``. With a detector that runs but finds no one, figure 1's
    box keeps its start width (the figure with its arms out) without the trim, and comes in to the figure with it."""
    from hdvr.tracking.evaluation import iou_matrix

    script = _script(monkeypatch)
    path = tmp_path / "trim.jpg"
    clip = script._render_crossing(tmp_path, 2, 9)
    truth, (kept, trimmed) = script._write_procedural_rule(path, tmp_path, _FindsNoOne(), clip, "foreground_trim", 40)
    assert truth[40, 1, 2] < 0.85 * truth[0, 1, 2]  # the figure's arms are in by then
    assert kept[40, 1, 2] > trimmed[40, 1, 2]
    assert iou_matrix(trimmed[40, 1:], truth[40, 1:])[0, 0] > iou_matrix(kept[40, 1:], truth[40, 1:])[0, 0] + 0.1
    _assert_two_panels(path)


@pytest.mark.slow  # 50-60 s (a troupe of 8 tracked twice); CI runs the crossing pictures of the same drawing
def test_the_procedural_lost_picture_shows_the_troupe_without_and_with_the_whole_frame_search(monkeypatch, tmp_path):
    """``--only procedural-lost``: the procedural troupe of 8 figures, seed 1, tracked as ``hdvr track`` does
    without (left) and with (right) ``lost_search_after``. With a detector that runs but finds no one (the tracker
    alone), figure 5 comes out of the group at the left and stands alone there: without the search its box stays
    in the group; with it, the box is on the figure."""
    from hdvr.tracking.evaluation import iou_matrix

    script = _script(monkeypatch)
    path = tmp_path / "lost.jpg"
    clip = script._render_troupe(tmp_path, 8, 1)
    truth, (stayed, found) = script._write_procedural_rule(path, tmp_path, _FindsNoOne(), clip, "lost_search_after", 86)
    assert iou_matrix(stayed[86, 5:6], truth[86, 5:6])[0, 0] < 0.1
    assert iou_matrix(found[86, 5:6], truth[86, 5:6])[0, 0] > 0.5
    _assert_two_panels(path)


def test_the_procedural_vertical_picture_shows_the_crossing_without_and_with_the_fading_vertical_prediction(
        monkeypatch, tmp_path):
    """``--only procedural-vertical``: the procedural crossing of 4 figures, seed 14 (held out by the benchmark),
    tracked as ``hdvr track`` does, with YOLO11n-pose at 480 px on every 3rd frame, without (left) and with (right)
    ``vertical_prediction_frames``. Figure 3 walks level and is hidden behind the others from frame 28: predicted
    with the vertical velocity of its few clear frames its box sinks below it (IoU under 0.35 by frame 80, its top
    40 px or more below the figure's); with the fading it stays level with the figure and on it."""
    from hdvr.pipeline import make_detector
    from hdvr.tracking.evaluation import iou_matrix

    script = _script(monkeypatch)
    path = tmp_path / "vertical.jpg"
    clip = script._render_crossing(tmp_path, 4, 14)
    detector = make_detector("yolo11n", 480, threads=2)
    truth, (sank, level) = script._write_procedural_rule(path, tmp_path, detector, clip,
                                                         "vertical_prediction_frames", 80)
    assert iou_matrix(sank[80, 3:4], truth[80, 3:4])[0, 0] < 0.35
    assert sank[80, 3, 1] > truth[80, 3, 1] + 40
    assert iou_matrix(level[80, 3:4], truth[80, 3:4])[0, 0] > 0.5
    assert abs(level[80, 3, 1] - truth[80, 3, 1]) < 15
    _assert_two_panels(path, 1.3)  # crops of figures 320 px tall: each panel nearly as tall as wide


@pytest.mark.slow  # 50-60 s (a troupe of 8 tracked twice); CI runs the crossing pictures of the same drawing
def test_the_procedural_vertical_cap_picture_shows_the_troupe_without_and_with_the_cap(monkeypatch, tmp_path):
    """``--only procedural-vertical-cap``: the procedural troupe of 8 figures, seed 1, tracked as ``hdvr track``
    does, with YOLO11n-pose at 480 px on every 3rd frame, without (left) and with (right) ``max_vertical_speed``.
    Figure 0 walks level; its tracker, taken again on a patch beside it, jumped back to it over a few clear frames,
    and without the cap the vertical velocity of those frames carries its hidden box down: over 80 px below the
    figure by frame 100 (IoU under 0.2); with the cap its box is on the figure (IoU over 0.5)."""
    from hdvr.pipeline import make_detector
    from hdvr.tracking.evaluation import iou_matrix

    script = _script(monkeypatch)
    path = tmp_path / "cap.jpg"
    clip = script._render_troupe(tmp_path, 8, 1)
    detector = make_detector("yolo11n", 480, threads=2)
    truth, (sank, capped) = script._write_procedural_rule(path, tmp_path, detector, clip, "max_vertical_speed", 100)
    assert iou_matrix(sank[100, 0:1], truth[100, 0:1])[0, 0] < 0.2
    assert sank[100, 0, 1] > truth[100, 0, 1] + 80
    assert iou_matrix(capped[100, 0:1], truth[100, 0:1])[0, 0] > 0.5
    _assert_two_panels(path, 2.0)


def test_a_before_after_rule_is_switched_off_as_its_field_allows(monkeypatch):
    """The left picture's config turns the rule off: None for a test that may be switched off so
    (``front_feet_max_off``: 0.0 would be the strictest test, not none), else 0, 0.0 or False; the right one is the
    default, and the titles say which."""
    module = _script(monkeypatch)
    from hdvr.tracking.multi import MultiTrackerConfig

    default = MultiTrackerConfig()
    (off, on), titles = module._field_off_and_default("front_feet_max_off")
    assert off.front_feet_max_off is None and on == default
    assert titles == ("front_feet_max_off off", f"front_feet_max_off = {default.front_feet_max_off}")
    (off, _), _ = module._field_off_and_default("front_follows_feet")
    assert off.front_follows_feet == 0.0 and off.front_feet_max_off == default.front_feet_max_off
    (off, _), _ = module._field_off_and_default("front_narrows")
    assert off.front_narrows is False
