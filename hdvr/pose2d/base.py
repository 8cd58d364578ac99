"""The detector interface: a frame in, the people found in it out."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from hdvr.layouts import BODY25, COCO17_NAMES, convert, guess_layout


@dataclass(frozen=True)
class PersonPose:
    """One person found in one frame.

    ``keypoints`` (J, 3): x_px, y_px, confidence in [0, 1] in the detector's layout (``joint_names``); missing
    joints have confidence 0 and NaN coordinates. ``box`` is (x, y, w, h) px; ``score`` the detection confidence.
    ``weak``: the score is below the detector's threshold for a sure find but above its weak threshold (often a
    person partly hidden by another); the tracker uses such a find only to update a dancer it already follows.
    """

    keypoints: np.ndarray
    box: tuple[float, float, float, float]
    score: float
    joint_names: tuple[str, ...] = COCO17_NAMES
    weak: bool = False

    def body25(self) -> np.ndarray:
        """Keypoints (25, 3) in BODY_25 order (neck and mid-hip derived; feet missing for COCO-17 input)."""
        layout = guess_layout(self.joint_names)
        kp = np.asarray(self.keypoints, np.float32)
        if layout is BODY25:
            return kp
        return convert(kp, layout, BODY25, has_confidence=True).astype(np.float32)


class PoseDetector(Protocol):
    """Anything that finds people and their 2D keypoints in a BGR frame. A detector may set ``supports_crops =
    False`` when it cannot look at a crop of a frame (precomputed output); the tracking pipeline then does not ask
    it to (:func:`hdvr.tracking.pipeline.zoom_detections`); one that can run at another input size may have
    ``at_input_size(px)``, returning itself at that size, which the pipeline uses on those crops
    (:data:`hdvr.tracking.pipeline.ZOOM_INPUT_SIZE`)."""

    name: str

    def detect(self, frame_bgr: np.ndarray, frame_index: int) -> list[PersonPose]:
        """People in ``frame_bgr`` (uint8, (H, W, 3)); ``frame_index`` is the 0-based frame number in the video
        (precomputed detectors look their results up by it)."""
        ...


def box_from_keypoints(keypoints: np.ndarray, min_confidence: float = 0.05, margin: float = 0.1):
    """(x, y, w, h) px around the confident keypoints, enlarged by ``margin`` of its size; None if fewer than 2."""
    ok = (keypoints[:, 2] > min_confidence) & np.isfinite(keypoints[:, :2]).all(axis=1)
    if ok.sum() < 2:
        return None
    pts = keypoints[ok, :2]
    x0, y0 = pts.min(axis=0)
    x1, y1 = pts.max(axis=0)
    w, h = x1 - x0, y1 - y0
    return (float(x0 - margin * w), float(y0 - margin * h), float(w * (1 + 2 * margin)), float(h * (1 + 2 * margin)))
