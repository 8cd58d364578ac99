"""The floor seen in perspective: the horizon fitted to dancers' boxes, and the size change of a dancer whose feet
move down or up the image (hdvr.tracking.ground)."""

import numpy as np
import pytest

from hdvr.tracking.ground import HORIZON_MIN_SPREAD, depth_scale, fit_horizon, height_ratio

FOCAL = 500.0  # px
HORIZON = 180.0  # image row of the horizon, px
CAMERA_HEIGHT = 1.4  # m above the floor


def _box(x_centre: float, depth: float, stature: float) -> np.ndarray:
    """(x, y, w, h) px of a dancer ``stature`` m tall standing ``depth`` m in front of a level pinhole camera."""
    height = FOCAL * stature / depth
    bottom = HORIZON + FOCAL * CAMERA_HEIGHT / depth
    return np.array([x_centre - 0.2 * height, bottom - height, 0.4 * height, height])


def _walk_towards_camera(frames: int = 90) -> np.ndarray:
    """(frames, 2, 4) boxes: a dancer 1.7 m tall walking from 7 m to 4 m, another 1.6 m tall standing at 5 m."""
    depths = np.linspace(7.0, 4.0, frames)
    return np.stack([np.stack([_box(250.0, z, 1.7) for z in depths]),
                     np.stack([_box(420.0, 5.0, 1.6) for _ in depths])], axis=1)


def test_the_horizon_is_found_from_a_dancer_walking_towards_the_camera():
    boxes = _walk_towards_camera()
    status = np.full(boxes.shape[:2], "tracked")
    lowest_feet = (boxes[..., 1] + boxes[..., 3]).min()
    # the candidate rows lie 2.8 % of their distance from the feet apart
    assert fit_horizon(boxes, status) == pytest.approx(HORIZON, abs=0.03 * (lowest_feet - HORIZON))


def test_the_horizon_survives_pose_noise_and_a_wrong_box():
    """Box heights jittered by 4 % (arms raised and lowered) and one frame in ten on a wrong, much taller box."""
    rng = np.random.default_rng(7)
    boxes = _walk_towards_camera()
    taller = boxes[..., 3] * rng.normal(0.0, 0.04, boxes.shape[:2])  # the top moves, the feet stay
    taller[::10, 0] = 0.5 * boxes[::10, 0, 3]
    boxes[..., 1] -= taller
    boxes[..., 3] += taller
    status = np.full(boxes.shape[:2], "tracked")
    lowest_feet = (boxes[..., 1] + boxes[..., 3]).min()
    assert abs(fit_horizon(boxes, status) - HORIZON) < 0.05 * (lowest_feet - HORIZON)


def test_dancers_that_keep_their_depth_give_no_horizon():
    """Standing in place, steps and jumps move the feet by less than ``HORIZON_MIN_SPREAD`` of the height while poses
    change the heights: no horizon (-inf); a dancer's boxes while not seen count for nothing."""
    rng = np.random.default_rng(3)
    boxes = np.stack([np.stack([_box(250.0, 5.0, 1.7)] * 60), np.stack([_box(420.0, 6.0, 1.6)] * 60)], axis=1)
    jitter = 0.8 * HORIZON_MIN_SPREAD * boxes[0, 0, 3] * rng.uniform(-0.5, 0.5, (60, 2))
    boxes[..., 1] += jitter
    taller = boxes[..., 3] * rng.normal(0.0, 0.05, (60, 2))  # poses: the top moves, the feet stay
    boxes[..., 1] -= taller
    boxes[..., 3] += taller
    status = np.full(boxes.shape[:2], "tracked")
    assert fit_horizon(boxes, status) == -np.inf
    walking = _walk_towards_camera(60)
    assert np.isfinite(fit_horizon(walking, status))
    hidden = status.copy()
    hidden[:, 0] = "hidden"  # the walking dancer never seen: only the one standing still counts
    assert fit_horizon(walking, hidden) == -np.inf
    assert fit_horizon(walking[:3], status[:3]) == -np.inf  # too few frames to sample
    assert fit_horizon(walking, status, min_spread=10.0) == -np.inf


def test_fitting_refuses_wrong_shapes_and_settings():
    boxes = _walk_towards_camera(10)
    status = np.full(boxes.shape[:2], "tracked")
    with pytest.raises(ValueError, match="boxes must be"):
        fit_horizon(boxes[..., :3], status)
    with pytest.raises(ValueError, match="boxes must be"):
        fit_horizon(boxes, status[:5])
    with pytest.raises(ValueError, match="min_depth"):
        fit_horizon(boxes, status, min_depth=0.0)


def test_depth_scale_is_the_ratio_of_the_feet_s_distances_below_the_horizon():
    """A dancer at 4 m looks 7/4 as large as at 7 m, and its feet lie 7/4 as far below the horizon."""
    near, far = _box(0.0, 4.0, 1.7), _box(0.0, 7.0, 1.7)
    scale = depth_scale(near[1] + near[3], far[1] + far[3], HORIZON)
    assert scale == pytest.approx(near[3] / far[3]) == pytest.approx(7 / 4)
    np.testing.assert_allclose(depth_scale([300.0, 400.0], 300.0, -np.inf), [1.0, 1.0])
    assert np.isnan(depth_scale(HORIZON - 5.0, 300.0, HORIZON))  # above the horizon: not on the floor
    assert np.isnan(depth_scale(300.0, HORIZON, HORIZON))


def test_height_ratio_is_the_dancers_stature_over_the_camera_height():
    """Box height per px of feet below the horizon: 1.7 / 1.4 and 1.6 / 1.4 for the two dancers, their median the
    mean of both; NaN for a horizon at -inf or no dancer seen."""
    boxes = _walk_towards_camera()
    status = np.full(boxes.shape[:2], "tracked")
    assert height_ratio(boxes, status, HORIZON) == pytest.approx((1.7 + 1.6) / 2 / CAMERA_HEIGHT)
    only_first = status.copy()
    only_first[:, 1] = "occluded"
    assert height_ratio(boxes, only_first, HORIZON) == pytest.approx(1.7 / CAMERA_HEIGHT)
    assert np.isnan(height_ratio(boxes, status, -np.inf))
    assert np.isnan(height_ratio(boxes, np.full(boxes.shape[:2], "hidden"), HORIZON))
