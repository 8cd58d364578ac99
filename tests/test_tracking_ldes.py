"""The LDES-style tracker against synthetic targets whose motion, rotation and scale are known."""

import cv2
import numpy as np
import pytest

from hdvr.errors import HDVRError
from hdvr.tracking.ldes import LDESConfig, LDESTracker, hog_colour_features

H, W = 360, 480


def _scene(seed=1):
    rng = np.random.default_rng(seed)
    bg = cv2.GaussianBlur(rng.integers(0, 255, (H, W, 3), dtype=np.uint8), (0, 0), 4)
    bg = cv2.normalize(bg, None, 0, 255, cv2.NORM_MINMAX)
    tex = cv2.GaussianBlur(rng.integers(0, 255, (120, 120, 3), dtype=np.uint8), (0, 0), 2)
    tex = cv2.normalize(tex, None, 0, 255, cv2.NORM_MINMAX)
    mask = np.zeros((120, 120), np.uint8)
    cv2.ellipse(mask, (60, 60), (30, 50), 0, 0, 360, 255, -1)

    def render(cx, cy, angle_deg, scale):
        m = cv2.getRotationMatrix2D((60, 60), angle_deg, scale)
        m[:, 2] += [cx - 60, cy - 60]
        obj = cv2.warpAffine(tex, m, (W, H))
        inside = cv2.warpAffine(mask, m, (W, H)) > 127
        frame = bg.copy()
        frame[inside] = obj[inside]
        return frame

    return render


@pytest.mark.parametrize("dx,dy,dangle,dscale", [
    (3.0, 1.0, 0.0, 1.0),     # translation only
    (0.0, 0.0, 0.5, 1.0),     # rotation only: 0.5 degree per frame
    (0.0, 0.0, 0.0, 1.006),   # scale only: +0.6 % per frame
    (3.0, 1.0, 0.5, 1.006),   # all together
])
def test_recovers_known_similarity_motion(dx, dy, dangle, dscale):
    render = _scene()
    frames = 60
    tracker = None
    for t in range(frames):
        cx, cy, angle, scale = 150 + dx * t, 180 + dy * t, dangle * t, dscale ** t
        frame = render(cx, cy, angle, scale)
        if tracker is None:
            tracker = LDESTracker(frame, (cx - 30, cy - 50, 60, 100))
            continue
        state = tracker.update(frame)
    assert np.hypot(state.center[0] - cx, state.center[1] - cy) < 6.0
    assert state.angle == pytest.approx(angle, abs=2.5)
    assert state.scale == pytest.approx(scale, rel=0.04)
    assert state.size[0] == pytest.approx(60 * scale, rel=0.04)
    assert state.confidence > 8


def test_box_and_disabled_estimation():
    render = _scene()
    tracker = LDESTracker(render(150, 180, 0, 1), (120, 130, 60, 100),
                          LDESConfig(estimate_scale=False, estimate_rotation=False))
    for t in range(1, 20):
        state = tracker.update(render(150 + 2 * t, 180, 10 * np.sin(t), 1.1))
    assert state.scale == 1.0 and state.angle == 0.0
    x, y, w, h = state.box
    assert (w, h) == (60, 100)
    assert abs(x + w / 2 - (150 + 2 * 19)) < 5


def test_learn_false_keeps_model():
    render = _scene()
    tracker = LDESTracker(render(150, 180, 0, 1), (120, 130, 60, 100))
    before = tracker._model_x.copy()
    tracker.update(render(152, 180, 0, 1), learn=False)
    np.testing.assert_array_equal(before, tracker._model_x)


def test_features_shape():
    patch = np.random.default_rng(0).integers(0, 255, (64, 40, 3), dtype=np.uint8)
    f = hog_colour_features(patch, 4, 9)
    assert f.shape == (16, 10, 12) and f.dtype == np.float32


def test_bad_boxes():
    frame = np.zeros((100, 100, 3), np.uint8)
    with pytest.raises(HDVRError, match="outside"):
        LDESTracker(frame, (200, 10, 20, 20))
    with pytest.raises(HDVRError, match="too small"):
        LDESTracker(frame, (10, 10, 2, 20))
