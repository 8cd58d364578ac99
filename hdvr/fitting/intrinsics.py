"""Camera intrinsics omega = {f, c} when the user does not give them (pixels)."""

from __future__ import annotations

import numpy as np

from hdvr.camera import Intrinsics

DEFAULT_FOV_DEG = 50.0  # horizontal field of view of the initial guess (typical phone/camcorder at 1x zoom)


def initial_intrinsics(image_size: tuple[int, int], focal: float | None = None,
                       principal_point: tuple[float, float] | None = None) -> Intrinsics:
    """The given focal/principal point, else a guess: principal point at the image centre, 50 deg horizontal FOV.

    The focal guess is refined per dancer by :func:`hdvr.fitting.calibration.calibrate` (perspective foreshortening
    of a body of known stature over many frames), with a log-normal prior around this guess.
    """
    width, height = image_size
    guess = Intrinsics.default_for(width, height, fov_deg=DEFAULT_FOV_DEG)
    f = float(focal) if focal is not None else guess.focal
    c = tuple(float(v) for v in principal_point) if principal_point is not None else guess.principal_point
    return Intrinsics(f, c, (int(width), int(height)))


def smooth_focal(focals: np.ndarray) -> float:
    """The paper's omega smoothing: the running mean of the per-frame optima over the window so far."""
    return float(np.exp(np.mean(np.log(np.asarray(focals, dtype=np.float64)))))
