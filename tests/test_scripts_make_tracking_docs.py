"""scripts/make_tracking_docs.py: the drawing of a case (boxes, crop) and the before/after picture."""

import importlib.util
import os
from pathlib import Path

import numpy as np

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "make_tracking_docs.py"


def _script(monkeypatch):
    # the script sets MUJOCO_GL for its renders when absent; undone after the test
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))
    spec = importlib.util.spec_from_file_location("make_tracking_docs", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


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
