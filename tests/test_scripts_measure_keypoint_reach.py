"""scripts/measure_keypoint_reach.py: the gaps between a ground-truth box and a pose's keypoints, and a real run of
the detector on a rendered synthetic dancer."""

import numpy as np
import pytest
from script_loader import load_script

from hdvr.synth.groundtruth import clip_spec, make_clip


def _pose(xs, ys, confidence=0.9):
    return np.stack([np.asarray(xs, float), np.asarray(ys, float), np.full(len(xs), confidence)], axis=1)


def test_gaps_are_measured_from_the_box_sides_and_top_in_box_heights():
    script = load_script("measure_keypoint_reach")
    xs = np.linspace(110, 170, 17)  # outermost keypoints 10 px inside the left side, 20 px inside the right
    ys = np.linspace(30, 180, 17)   # highest 10 px below the top
    reach = script.reach_beyond_keypoints((100, 20, 90, 200), _pose(xs, ys))
    np.testing.assert_allclose(reach, [10 / 200, 20 / 200, 10 / 200])


def test_poses_that_are_not_the_dancers_alone_are_left_out():
    script = load_script("measure_keypoint_reach")
    xs, ys = np.linspace(110, 170, 17), np.linspace(30, 180, 17)
    box = (100, 20, 90, 200)
    wide = xs.copy()
    wide[0] = 100 - 0.2 * 200  # a wrist 40 px beyond the box: another dancer's arm
    assert script.reach_beyond_keypoints(box, _pose(wide, ys)) is None
    few = _pose(xs, ys)
    few[3:, 2] = 0.1  # only 3 confident keypoints
    assert script.reach_beyond_keypoints(box, few) is None
    nan = _pose(xs, ys)
    nan[:, 0] = np.nan
    assert script.reach_beyond_keypoints(box, nan) is None


def test_the_detector_finds_keypoints_inside_a_rendered_dancers_box(tmp_path, capsys):
    """One rendered ballet dancer, 1 s: every measured gap lies within the box (keypoints inside the amodal box)
    and below half its height, and the report prints percentiles."""
    script = load_script("measure_keypoint_reach")
    spec = clip_spec(0, 3, ("ballet",), (1, 1), 1.0)
    make_clip(tmp_path, spec, render=True)
    assert script.main([str(tmp_path / spec.name), "--every", "5"]) == 0
    out = capsys.readouterr().out
    assert "dancer-frames seen whole" in out and "sides (left and right)" in out
    from bench_track import default_tracking_detector

    detector = default_tracking_detector()
    reaches = np.array(script.measure_clip(tmp_path / spec.name, detector, every=5))
    assert len(reaches) >= 3
    assert (reaches > -0.1).all() and (reaches < 0.5).all()


def test_a_folder_that_is_not_a_clip_is_a_one_line_error(tmp_path):
    with pytest.raises(SystemExit, match="is not an hdvr synth clip folder"):
        load_script("measure_keypoint_reach").main([str(tmp_path)])
