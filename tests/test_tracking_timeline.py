"""hdvr.tracking.timeline: the picture of each dancer's status and found keypoints over the frames."""

import cv2
import numpy as np
import pytest

from hdvr.tracking.evaluation import track_on_truth
from hdvr.tracking.timeline import (STATUS_STYLE, dancer_rgb, draw_tracks_timeline, draw_truth_timeline, pose_fraction,
                                   status_image)


def _run(T=90):
    status = [("tracked", "absent")] * 10 + [("tracked", "hidden")] * 20 + [("occluded", "tracked")] * 30 \
        + [("out", "tracked")] * (T - 60)
    kp = np.full((T, 2, 25, 3), np.nan)
    kp[..., 2] = 0
    kp[:, 0, :19] = [100.0, 200.0, 0.9]  # 19 joints found, as a COCO-17 detector fills BODY_25
    kp[40:50, 0] = [np.nan, np.nan, 0.0]  # none while hidden behind the other
    kp[30:, 1, :10] = [300.0, 200.0, 0.5]
    return status, kp


def test_status_colours_the_dancer_s_own_where_seen_paler_where_guessed_grey_while_waiting():
    status, _ = _run()
    image = status_image(status, 2)
    assert image.shape == (2, 90, 3)
    np.testing.assert_allclose(image[0, 0], dancer_rgb(0))  # tracked
    pale = image[0, 35]  # occluded: between the dancer's colour and white
    assert (pale >= dancer_rgb(0) - 1e-9).all() and (pale <= 1).all() and not np.allclose(pale, dancer_rgb(0))
    np.testing.assert_allclose(image[1, 15], [0xA0 / 255] * 3)  # hidden
    np.testing.assert_allclose(image[1, 0], [1, 1, 1])  # absent: blank
    assert set(STATUS_STYLE) == {"tracked", "occluded", "hidden", "out", "absent"}
    assert not np.allclose(dancer_rgb(0), dancer_rgb(1))


def test_pose_fraction_counts_the_keypoints_with_a_position_and_a_confidence():
    _, kp = _run()
    fraction = pose_fraction(kp)
    assert fraction.shape == (90, 2)
    assert fraction[0, 0] == pytest.approx(19 / 25) and fraction[45, 0] == 0 and fraction[0, 1] == 0
    assert fraction[60, 1] == pytest.approx(10 / 25)


def test_the_timeline_is_written_as_a_picture_with_every_dancer_s_colour(tmp_path):
    status, kp = _run()
    path = draw_tracks_timeline(tmp_path / "timeline.png", status, kp, fps=30.0, corrections=[(30, 1)],
                                swaps=[(70, 0, 1)], hidden_starts=[(10, 1, 0)], title="test")
    assert path == tmp_path / "timeline.png" and not list(tmp_path.glob(".*"))  # written atomically
    image = cv2.imread(str(path))[..., ::-1] / 255.0  # RGB
    assert image.shape[1] > 1000 and image.shape[0] > 400
    for i in range(2):
        close = np.abs(image - dancer_rgb(i)).max(axis=2) < 0.02
        assert close.sum() > 2000, f"dancer {i}'s band is missing"
    with pytest.raises(ValueError, match="status rows"):
        draw_tracks_timeline(tmp_path / "bad.png", status[:-1], kp, fps=30.0)


def test_the_truth_timeline_colours_each_true_dancer_by_the_track_on_it(tmp_path):
    gt = np.array([[[0, 0, 10, 20], [50, 0, 10, 20]]] * 60, float)
    tracks = gt.copy()
    tracks[30:] = tracks[30:, ::-1]  # a switch half-way
    tracks[10:20, 0] = np.nan  # dancer 0 missed for 10 frames
    owner, best = track_on_truth(gt, tracks)
    path = draw_truth_timeline(tmp_path / "cover.png", owner, best, fps=30.0, title="test")
    image = cv2.imread(str(path))[..., ::-1] / 255.0
    for track in (0, 1):
        assert (np.abs(image - dancer_rgb(track)).max(axis=2) < 0.02).sum() > 2000
    assert (np.abs(image - 0xA0 / 255).max(axis=2) < 0.01).sum() > 500  # the miss, grey
    with pytest.raises(ValueError, match="same"):
        draw_truth_timeline(tmp_path / "bad.png", owner, best[:-1])
