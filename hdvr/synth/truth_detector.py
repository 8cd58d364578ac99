"""A pose detector that reports an hdvr synth clip's ground truth: what tracking would do with a perfect detector.

The tracking benchmark (``scripts/bench_track.py --synth-detector truth``) runs Algorithm 1* and 2* with it in place
of YOLO11n-pose, to tell the clips a tracker loses because the detector misses or misplaces dancers from those it
loses with every visible dancer found. It sees what a perfect person detector would see, no more:

- a dancer is found on a frame when at least ``weak_fraction`` of its 25 BODY_25 keypoints are visible (not hidden
  by another dancer, inside the image: ``gt.npz`` ``visibility`` 2); from ``sure_fraction`` on the find is sure,
  below it weak (:attr:`hdvr.pose2d.base.PersonPose.weak`, as a detector's low-score finds of partly hidden people);
  its score is that fraction;
- its box is the visible part of the body: the box of its visible keypoints grown on every side by ``margin`` x the
  dancer's amodal ground-truth box height (the head above the face points, the hand beyond the wrist, the limb's
  own thickness), and kept inside that amodal box; a fully visible dancer gets about its amodal box. With
  ``amodal=True`` it is the amodal box itself, the whole body with its hidden parts, which no detector sees: then
  the tracker gets every dancer it could find and exactly where it is, and what it still gets wrong is its own
  association and occlusion reasoning;
- its keypoints are the visible ground-truth ones (confidence 1), the others missing (confidence 0, NaN).

Who is who is never reported: the finds come in the dancers' order in ``gt.npz``, which the tracker does not use.
Frames are (x, y) pixels, top-left origin; ``gt.npz`` arrays are indexed (dancer, frame, ...).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import BODY25_NAMES
from hdvr.pose2d.base import PersonPose
from hdvr.tracking.evaluation import visible_truth_keypoints

#: a dancer showing at least this fraction of its keypoints is a sure find
SURE_FRACTION = 0.5
#: ... and at least this fraction a weak one (fewer: not found)
WEAK_FRACTION = 0.3
#: x the amodal box height: how far the box reaches beyond the outermost visible keypoints
BOX_MARGIN = 0.15


class GroundTruthDetector:
    """:class:`hdvr.pose2d.base.PoseDetector` over a synthetic clip's ground truth (module docstring).

    ``keypoints2d`` (N, T, 25, 2) px, ``visibility`` (N, T, 25) codes (2 visible, 1 hidden by a dancer, 0 outside
    the image) and ``boxes`` (N, T, 4) amodal (x, y, w, h) px, NaN where a dancer is absent: ``gt.npz``'s arrays."""

    name = "ground-truth"
    supports_crops = False  # it reports frames by index; a crop has none

    def __init__(self, keypoints2d, visibility, boxes, sure_fraction: float = SURE_FRACTION,
                 weak_fraction: float = WEAK_FRACTION, margin: float = BOX_MARGIN, amodal: bool = False):
        keypoints2d, visibility, boxes = (np.asarray(a) for a in (keypoints2d, visibility, boxes))
        if keypoints2d.ndim != 4 or keypoints2d.shape[2:] != (len(BODY25_NAMES), 2) \
                or visibility.shape != keypoints2d.shape[:3] or boxes.shape != keypoints2d.shape[:2] + (4,):
            raise HDVRError(f"ground truth must be keypoints2d (N, T, 25, 2), visibility (N, T, 25) and boxes "
                            f"(N, T, 4); got {keypoints2d.shape}, {visibility.shape} and {boxes.shape}")
        if not 0 < weak_fraction <= sure_fraction <= 1:
            raise HDVRError(f"need 0 < weak_fraction <= sure_fraction <= 1, got {weak_fraction} and {sure_fraction}")
        if margin < 0:
            raise HDVRError(f"margin must be >= 0, got {margin}")
        # (T, N, 25, 3): x px, y px, 1 where visible, as the benchmark's PCK scores them
        self.truth = visible_truth_keypoints(keypoints2d, visibility)
        self.boxes = np.transpose(boxes, (1, 0, 2)).astype(float)  # (T, N, 4)
        self.sure_fraction, self.weak_fraction, self.margin = sure_fraction, weak_fraction, margin
        self.amodal = amodal

    @classmethod
    def from_clip(cls, clip: str | os.PathLike, **settings) -> GroundTruthDetector:
        """The detector for the clip folder ``clip`` (its ``gt.npz``, as :func:`hdvr.synth.groundtruth.make_clip`
        writes it); ``settings`` as the constructor's."""
        path = Path(clip) / "gt.npz"
        if not path.is_file():
            raise HDVRError(f"{path}: no such ground-truth file (render the clip with hdvr.synth first)")
        with np.load(path) as gt:
            return cls(gt["keypoints2d"], gt["visibility"], gt["boxes"], **settings)

    @property
    def num_frames(self) -> int:
        return self.truth.shape[0]

    def detect(self, frame_bgr: np.ndarray, frame_index: int) -> list[PersonPose]:
        """The dancers a perfect detector finds on frame ``frame_index`` (``frame_bgr`` is not looked at)."""
        if not 0 <= frame_index < self.num_frames:
            raise HDVRError(f"frame {frame_index} is outside the ground truth's {self.num_frames} frames")
        found = []
        for truth, amodal in zip(self.truth[frame_index], self.boxes[frame_index]):
            visible = truth[:, 2] > 0
            shown = float(visible.mean())
            if shown < self.weak_fraction or not np.isfinite(amodal).all() or amodal[3] <= 0:
                continue
            box = tuple(float(v) for v in amodal) if self.amodal else self._visible_box(truth[visible, :2], amodal)
            if box is None:
                continue
            keypoints = truth.astype(np.float32)
            keypoints[~visible, :2] = np.nan
            found.append(PersonPose(keypoints, box, shown, joint_names=tuple(BODY25_NAMES),
                                    weak=shown < self.sure_fraction))
        return found

    def _visible_box(self, points: np.ndarray, amodal: np.ndarray) -> tuple[float, float, float, float] | None:
        """(x, y, w, h) px: the box of the visible keypoints ``points`` (K, 2) grown by ``margin`` x the amodal
        box's height on every side, inside the ``amodal`` box; None if nothing of it is left."""
        reach = self.margin * amodal[3]
        x0, y0 = np.maximum(points.min(axis=0) - reach, amodal[:2])
        x1, y1 = np.minimum(points.max(axis=0) + reach, amodal[:2] + amodal[2:])
        if x1 <= x0 or y1 <= y0:
            return None
        return float(x0), float(y0), float(x1 - x0), float(y1 - y0)
