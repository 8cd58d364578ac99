"""Algorithm 2* of the paper: for each tracked dancer, pick the detected pose that belongs to it.

Per frame, the candidates of dancer i are the detected poses whose box overlaps the dancer's tracked box
B_t^i. Among them the pose whose colour histogram (over the pixels its skeleton covers) correlates best with the
histogram of the pose chosen for dancer i before is taken; before any pose was chosen, the best box overlap decides.
Where the paper lets every dancer take its best candidate independently, here one assignment (Hungarian, scipy)
over all dancers is solved, so two dancers never take the same pose; with no conflict both rules agree. A dancer
that gives way to another (``yields``: it waits hidden behind that dancer, so its colour memory is that dancer's and
the histogram cannot tell them apart) is no candidate for a pose that fits the other's box about as well as its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.optimize import linear_sum_assignment

from hdvr.layouts import BODY25_BONES, BODY25_NAMES
from hdvr.pose2d.base import PersonPose
from hdvr.tracking.appearance import box_iou, box_overlap, clip_box, colour_histogram, histogram_similarity

_J = {n: i for i, n in enumerate(BODY25_NAMES)}
_BONE_INDEX = [(_J[a], _J[b]) for a, b in BODY25_BONES]


def skeleton_mask(keypoints25: np.ndarray, box, frame_size, thickness_fraction: float = 0.08):
    """uint8 mask (frame height, width) of the limbs of BODY_25 ``keypoints25`` (25, 3), drawn with a thickness of
    ``thickness_fraction`` x the box height, restricted to ``box``; None if no bone is visible."""
    r = clip_box(box, frame_size)
    if r is None:
        return None
    mask = np.zeros((frame_size[1], frame_size[0]), np.uint8)
    thick = max(2, int(thickness_fraction * box[3]))
    drawn = False
    for a, b in _BONE_INDEX:
        if keypoints25[a, 2] > 0 and keypoints25[b, 2] > 0:
            p = tuple(int(round(v)) for v in keypoints25[a, :2])
            q = tuple(int(round(v)) for v in keypoints25[b, :2])
            cv2.line(mask, p, q, 255, thick)
            drawn = True
    if not drawn:
        return None
    x0, y0, x1, y1 = r
    outside = np.ones_like(mask, bool)
    outside[y0:y1, x0:x1] = False
    mask[outside] = 0
    return mask


def pose_histogram(frame_bgr: np.ndarray, pose: PersonPose):
    """Colour histogram of the pixels covered by ``pose``'s skeleton (its box if no bone is visible)."""
    size = (frame_bgr.shape[1], frame_bgr.shape[0])
    mask = skeleton_mask(pose.body25(), pose.box, size)
    return colour_histogram(frame_bgr, pose.box, shrink=0.0, mask=mask)


@dataclass(frozen=True)
class SelectionConfig:
    min_overlap: float = 0.3  # intersection / smaller box area for a pose to be a candidate of a dancer
    min_similarity: float = 0.0  # histogram correlation below this: no pose for the dancer in this frame
    history_weight: float = 0.5  # the dancer's pose histogram = this x old + (1 - this) x newest chosen
    yield_iou_margin: float = 0.1  # a dancer that gives way to another (``yields``) cannot take a pose whose box
    # overlaps the other's box (IoU) at least as much as its own, less this


class PoseSelector:
    """Keeps the pose histogram of each dancer and assigns detected poses to tracked boxes."""

    def __init__(self, num_dancers: int, config: SelectionConfig | None = None):
        self.config = config or SelectionConfig()
        self.histograms: list[np.ndarray | None] = [None] * num_dancers
        # per dancer, after :meth:`select`: how much better the chosen pose's score is for this dancer than for
        # any other dancer (inf when no other dancer could take it; None when no pose was chosen)
        self.margins: list[float | None] = [None] * num_dancers

    def select(self, frame_bgr: np.ndarray, boxes, poses: list[PersonPose],
               not_rivals: np.ndarray | None = None, yields: np.ndarray | None = None) -> list[PersonPose | None]:
        """For each dancer's tracked box (x, y, w, h) px, its pose among ``poses``, or None. ``not_rivals``:
        optional (n, n) bool, True at [i, j] where dancer j's score for a pose says nothing about whether it is
        dancer i's (j waits hidden behind i with i's colours as memory); j is then left out of i's margin.
        ``yields``: optional (n, n) bool, True at [i, j] where dancer j gives way to dancer i: j cannot take a pose
        whose box overlaps i's box about as much as its own (``yield_iou_margin``)."""
        c = self.config
        n = len(boxes)
        chosen: list[PersonPose | None] = [None] * n
        self.margins = [None] * n
        if not poses:
            return chosen
        hists = [pose_histogram(frame_bgr, p) for p in poses]
        score = np.full((n, len(poses)), -np.inf)
        for i, box in enumerate(boxes):
            if not np.all(np.isfinite(box)):
                continue
            for k, p in enumerate(poses):
                if box_overlap(box, p.box) < c.min_overlap:
                    continue
                if self.histograms[i] is not None:
                    sim = histogram_similarity(hists[k], self.histograms[i])
                    if sim < c.min_similarity:
                        continue
                    # the histogram decides; overlap breaks near-ties
                    score[i, k] = sim + 0.1 * box_iou(box, p.box)
                else:
                    score[i, k] = box_iou(box, p.box)
        if not np.isfinite(score).any():
            return chosen
        if yields is not None:  # a pose that fits the box of the dancer given way to about as well is that dancer's
            for i, j in zip(*np.nonzero(np.asarray(yields, bool)[:n, :n])):
                for k in np.flatnonzero(np.isfinite(score[i]) & np.isfinite(score[j])):
                    if box_iou(boxes[i], poses[k].box) >= box_iou(boxes[j], poses[k].box) - c.yield_iou_margin:
                        score[j, k] = -np.inf
        cost = np.where(np.isfinite(score), -score, 1e6)
        ignored = np.zeros((n, n), bool) if not_rivals is None else np.asarray(not_rivals, bool)[:n, :n]
        rows, cols = linear_sum_assignment(cost)
        for i, k in zip(rows, cols):
            if np.isfinite(score[i, k]):
                chosen[i] = poses[k]
                counted = ~ignored[i]
                counted[i] = False
                rivals = score[counted, k]
                rivals = rivals[np.isfinite(rivals)]
                self.margins[i] = float(score[i, k] - rivals.max()) if rivals.size else float("inf")
                h = hists[k]
                if h is not None:
                    old = self.histograms[i]
                    self.histograms[i] = h if old is None else c.history_weight * old + (1 - c.history_weight) * h
        return chosen
