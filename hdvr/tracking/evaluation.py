"""Tracking and 2D keypoint metrics.

MOTA, IDF1, identity switches and HOTA come from ``trackeval`` (the maintained implementation of the MOT and HOTA
benchmarks' metrics), fed with per-frame IoU similarities; nothing of the metrics is re-implemented here.
PCK@alpha for keypoints: a predicted joint is correct when it lies within alpha x the torso diameter (the larger
of the two shoulder-to-opposite-hip distances, LSP convention) of the ground truth; joints missing in the
ground truth do not count, joints missing in the prediction count as wrong.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.errors import HDVRError
from hdvr.layouts import BODY25, BODY25_NAMES, convert, guess_layout


@dataclass(frozen=True)
class TrackingScores:
    """Scores of tracked boxes against ground-truth boxes (fractions in [0, 1], MOTA may be negative)."""

    mota: float
    idf1: float
    hota: float
    id_switches: int
    recall: float
    precision: float
    frames: int

    def as_dict(self) -> dict:
        return {"MOTA": self.mota, "IDF1": self.idf1, "HOTA": self.hota, "IDSW": self.id_switches,
                "recall": self.recall, "precision": self.precision, "frames": self.frames}


def iou_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """IoU between (n, 4) and (m, 4) (x, y, w, h) boxes."""
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)))
    ax0, ay0, ax1, ay1 = a[:, 0], a[:, 1], a[:, 0] + a[:, 2], a[:, 1] + a[:, 3]
    bx0, by0, bx1, by1 = b[:, 0], b[:, 1], b[:, 0] + b[:, 2], b[:, 1] + b[:, 3]
    iw = np.clip(np.minimum(ax1[:, None], bx1[None]) - np.maximum(ax0[:, None], bx0[None]), 0, None)
    ih = np.clip(np.minimum(ay1[:, None], by1[None]) - np.maximum(ay0[:, None], by0[None]), 0, None)
    inter = iw * ih
    union = (a[:, 2] * a[:, 3])[:, None] + (b[:, 2] * b[:, 3])[None] - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0.0)


ABSENT = -2  # :func:`track_on_truth`: the ground-truth dancer has no box in this frame
MISSED = -1  # :func:`track_on_truth`: no tracked box lies on the dancer


def track_on_truth(gt_boxes: np.ndarray, tracked_boxes: np.ndarray,
                   iou_threshold: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Which tracked id lies on each ground-truth dancer, frame by frame: (T, M) int, the tracked box (second index
    of ``tracked_boxes`` (T, N, 4)) with the highest IoU with dancer m's box in ``gt_boxes`` (T, M, 4) where that
    IoU reaches ``iou_threshold``, :data:`MISSED` where none does, :data:`ABSENT` where the dancer has no box; and
    (T, M) that highest IoU (NaN where absent). Boxes (x, y, w, h) px, NaN rows absent. A change of id along a
    dancer's row is an identity switch, as the pictures of ``hdvr evaluate tracks --plot`` show it."""
    gt_boxes = np.asarray(gt_boxes, float)
    tracked_boxes = np.asarray(tracked_boxes, float)
    if gt_boxes.ndim != 3 or tracked_boxes.ndim != 3 or gt_boxes.shape[0] != tracked_boxes.shape[0]:
        raise HDVRError(f"expected (T, M, 4) and (T, N, 4) boxes over the same frames, got {gt_boxes.shape} and "
                        f"{tracked_boxes.shape}")
    T, M = gt_boxes.shape[:2]
    owner = np.full((T, M), ABSENT, int)
    best = np.full((T, M), np.nan)
    for t in range(T):
        present = np.isfinite(gt_boxes[t]).all(axis=1)
        tracked = np.flatnonzero(np.isfinite(tracked_boxes[t]).all(axis=1))
        owner[t, present] = MISSED
        best[t, present] = 0.0
        if not present.any() or not len(tracked):
            continue
        iou = iou_matrix(gt_boxes[t, present], tracked_boxes[t, tracked])
        rows = np.flatnonzero(present)
        best[t, rows] = iou.max(axis=1)
        hit = iou.max(axis=1) >= iou_threshold
        owner[t, rows[hit]] = tracked[iou.argmax(axis=1)[hit]]
    return owner, best


def evaluate_tracking(gt_boxes: np.ndarray, tracked_boxes: np.ndarray, iou_threshold: float = 0.5) -> TrackingScores:
    """Score ``tracked_boxes`` (T, N, 4) against ``gt_boxes`` (T, M, 4); (x, y, w, h) pixels, NaN rows = absent.

    Ids are the second index of each array. MOTA and IDF1 use ``iou_threshold``; HOTA averages over trackeval's
    thresholds 0.05 .. 0.95.
    """
    from trackeval.metrics import CLEAR, HOTA, Identity

    gt_boxes = np.asarray(gt_boxes, float)
    tracked_boxes = np.asarray(tracked_boxes, float)
    if gt_boxes.ndim != 3 or tracked_boxes.ndim != 3 or gt_boxes.shape[0] != tracked_boxes.shape[0]:
        raise HDVRError(f"box arrays must be (T, N, 4) with the same T; got {gt_boxes.shape} and "
                        f"{tracked_boxes.shape}")
    data = {"gt_ids": [], "tracker_ids": [], "similarity_scores": [], "num_gt_dets": 0, "num_tracker_dets": 0,
            "num_gt_ids": gt_boxes.shape[1], "num_tracker_ids": tracked_boxes.shape[1],
            "num_timesteps": gt_boxes.shape[0]}
    for g, p in zip(gt_boxes, tracked_boxes):
        gi = np.flatnonzero(np.isfinite(g).all(axis=1))
        pi = np.flatnonzero(np.isfinite(p).all(axis=1))
        data["gt_ids"].append(gi.astype(int))
        data["tracker_ids"].append(pi.astype(int))
        data["similarity_scores"].append(iou_matrix(g[gi], p[pi]))
        data["num_gt_dets"] += len(gi)
        data["num_tracker_dets"] += len(pi)
    config = {"THRESHOLD": iou_threshold, "PRINT_CONFIG": False}
    clear = CLEAR(config).eval_sequence(data)
    ident = Identity(config).eval_sequence(data)
    hota = HOTA().eval_sequence(data)
    return TrackingScores(mota=float(clear["MOTA"]), idf1=float(ident["IDF1"]), hota=float(np.mean(hota["HOTA"])),
                          id_switches=int(clear["IDSW"]), recall=float(clear["CLR_Re"]),
                          precision=float(clear["CLR_Pr"]), frames=int(gt_boxes.shape[0]))


#: Visibility classes of :func:`miss_causes`: the fraction of a dancer's keypoints seen (not hidden by another
#: dancer, inside the image) at least 0.9, at least 0.4, below 0.4.
VISIBILITY_CLASSES = ("visible", "partly", "hidden")
#: Causes of :func:`miss_causes`, in the order they are tested.
MISS_CAUSES = ("matched", "other_dancer", "extent", "elsewhere", "no_box")


def miss_causes(gt_boxes: np.ndarray, tracked_boxes: np.ndarray, seen_fraction: np.ndarray,
                iou_threshold: float = 0.5, extent_iou: float = 0.25) -> dict[tuple[str, str], int]:
    """Where each dancer's ground-truth box goes unmatched: counts of dancer-frames by (visibility class, cause).

    ``gt_boxes`` and ``tracked_boxes`` (T, N, 4) (x, y, w, h) px with the same dancer order (tracks started
    from the ground truth), NaN rows = absent; ``seen_fraction`` (T, N): fraction of each dancer's keypoints
    seen, classed by :data:`VISIBILITY_CLASSES`. Causes (:data:`MISS_CAUSES`), for each ground-truth box: its
    dancer's tracked box overlaps it at least ``iou_threshold`` (IoU; "matched"); else overlaps another dancer's
    ground-truth box that much ("other_dancer": on the wrong dancer); else overlaps its own at least
    ``extent_iou`` ("extent": on the right dancer, but too small, too large or shifted); else is elsewhere; or
    there is no tracked box. A diagnosis of what IDF1 misses, not a metric of its own."""
    gt_boxes = np.asarray(gt_boxes, float)
    tracked_boxes = np.asarray(tracked_boxes, float)
    seen_fraction = np.asarray(seen_fraction, float)
    if gt_boxes.ndim != 3 or gt_boxes.shape != tracked_boxes.shape or seen_fraction.shape != gt_boxes.shape[:2]:
        raise HDVRError(f"expected boxes (T, N, 4) alike and seen fractions (T, N); got {gt_boxes.shape}, "
                        f"{tracked_boxes.shape} and {seen_fraction.shape}")
    counts = {(v, c): 0 for v in VISIBILITY_CLASSES for c in MISS_CAUSES}
    for truth, tracked, seen in zip(gt_boxes, tracked_boxes, seen_fraction):
        present = np.isfinite(truth).all(axis=1)
        iou = iou_matrix(np.nan_to_num(tracked, nan=-1e6), np.where(present[:, None], truth, -1e6))
        for j in np.flatnonzero(present):
            visibility = VISIBILITY_CLASSES[0 if seen[j] >= 0.9 else 1 if seen[j] >= 0.4 else 2]
            own = iou[j]
            if not np.isfinite(tracked[j]).all():
                cause = "no_box"
            elif own[j] >= iou_threshold:
                cause = "matched"
            elif np.delete(own, j).max(initial=0.0) >= iou_threshold:
                cause = "other_dancer"
            elif own[j] >= extent_iou:
                cause = "extent"
            else:
                cause = "elsewhere"
            counts[(visibility, cause)] += 1
    return counts


def torso_diameter(keypoints: np.ndarray) -> np.ndarray:
    """(...,) px: the larger of |left_shoulder - right_hip| and |right_shoulder - left_hip| of BODY_25 keypoints
    (..., 25, >=2); NaN where neither is available."""
    j = {n: i for i, n in enumerate(BODY25_NAMES)}
    a = np.linalg.norm(keypoints[..., j["left_shoulder"], :2] - keypoints[..., j["right_hip"], :2], axis=-1)
    b = np.linalg.norm(keypoints[..., j["right_shoulder"], :2] - keypoints[..., j["left_hip"], :2], axis=-1)
    return np.fmax(a, b)


def pck(predicted: np.ndarray, truth: np.ndarray, alpha: float = 0.2, joints=None) -> float:
    """PCK@alpha of BODY_25 keypoints (T, 25, 2 or 3) px against the ground truth (same shape); see module doc.

    ``joints``: indices to score (default: every joint that the ground truth has). Frames where the torso
    diameter is unknown do not count. Returns NaN when nothing can be scored.
    """
    predicted = np.asarray(predicted, float)
    truth = np.asarray(truth, float)
    if predicted.shape[:-1] != truth.shape[:-1]:
        raise HDVRError(f"keypoint arrays differ in shape: {predicted.shape} vs {truth.shape}")
    ref = torso_diameter(truth)  # (T,) from the full skeleton, before selecting joints
    if joints is not None:
        predicted, truth = predicted[..., joints, :], truth[..., joints, :]
    has_truth = np.isfinite(truth[..., :2]).all(axis=-1)
    if truth.shape[-1] >= 3:
        has_truth &= truth[..., 2] > 0
    has_truth &= np.isfinite(ref)[..., None]
    if not has_truth.any():
        return float("nan")
    dist = np.linalg.norm(predicted[..., :2] - truth[..., :2], axis=-1)
    valid_pred = np.isfinite(dist)
    if predicted.shape[-1] >= 3:
        valid_pred &= predicted[..., 2] > 0
    correct = valid_pred & (np.where(valid_pred, dist, np.inf) <= alpha * ref[..., None])
    return float(correct[has_truth].mean())


def visible_truth_keypoints(keypoints2d: np.ndarray, visibility: np.ndarray) -> np.ndarray:
    """Ground truth for :func:`pck` from a synthetic clip's ``gt.npz`` arrays ``keypoints2d`` (N, T, 25, 2) px and
    ``visibility`` (N, T, 25) (2 visible, 1 hidden by another dancer, 0 outside the image): (T, N, 25, 3) x_px,
    y_px, 1 where visible and 0 elsewhere, so that only visible keypoints are scored."""
    keypoints2d = np.asarray(keypoints2d, float)
    visibility = np.asarray(visibility)
    if keypoints2d.ndim != 4 or keypoints2d.shape[-1] != 2 or visibility.shape != keypoints2d.shape[:-1]:
        raise HDVRError(f"expected keypoints2d (N, T, J, 2) and visibility (N, T, J); got {keypoints2d.shape} and "
                        f"{visibility.shape}")
    visible = (visibility == 2).astype(float)[..., None]
    return np.transpose(np.concatenate([keypoints2d, visible], axis=-1), (1, 0, 2, 3))


def body25_joints_of(joint_names) -> np.ndarray:
    """Indices of the BODY_25 joints that keypoints in the layout named by ``joint_names`` (e.g. a COCO-17
    detector's) give after conversion to BODY_25 (:func:`hdvr.layouts.convert`): PCK's ``joints`` for scoring a
    detector only on what it can output (COCO-17: 19 joints, no feet)."""
    layout = guess_layout(tuple(joint_names))
    ones = np.ones((len(joint_names), 3))
    return np.flatnonzero(convert(ones, layout, BODY25, has_confidence=True)[:, 2] > 0)
