"""Box geometry of dancers relative to one another and to the detector's finds (helpers of Algorithm 1*).

Boxes are (x, y, w, h) pixels, top-left corner; heights and offsets in pixels unless a docstring says "box heights".
"""

from __future__ import annotations

import cv2
import numpy as np

from hdvr.tracking.appearance import box_iou


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """Angle (degrees, 0-180) between 2D vectors ``a`` and ``b``; 0 when either is (almost) zero."""
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    if na < 1e-9 or nb < 1e-9:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(np.dot(a, b) / (na * nb), -1.0, 1.0))))


def chain_length(before, box) -> int:
    """Detector frames in a row on which a person lay at ``box`` (x, y, w, h px), this one included: 1 + the count
    of the chain of the detector frame before (``before``: (box, count) pairs) on which it lies (IoU >= 0.5)."""
    return 1 + max([n for b, n in before if box_iou(b, box) >= 0.5], default=0)


def height_within(box, reference, factor: float) -> bool:
    """Whether (x, y, w, h px) ``box`` is at most ``factor`` x taller or shorter than ``reference``."""
    return 1 / factor <= box[3] / reference[3] <= factor


def height_misfit(box, reference) -> float:
    """|log(height ratio)| of two (x, y, w, h px) boxes: 0 for the same height, as much for twice as for half."""
    return abs(float(np.log(box[3] / reference[3])))


def likely_windows(weights: np.ndarray, window, min_mean: float, count: int = 3,
                   step: int = 4) -> list[np.ndarray]:
    """Centres (x, y) px of up to ``count`` windows of ``window`` = (width, height) px whose mean of ``weights``
    (an image, e.g. a back-projected colour histogram) is highest and at least ``min_mean``, best first, no two
    closer than a window's size. Computed on the image shrunk ``step`` times (a box filter: one pass whatever the
    window); a window is not scored beyond the image's border (counted as 0 there)."""
    height, width = weights.shape
    small = cv2.resize(weights.astype(np.float32), (max(1, width // step), max(1, height // step)),
                       interpolation=cv2.INTER_AREA)
    kw, kh = max(1, int(round(window[0] / step))), max(1, int(round(window[1] / step)))
    mean = cv2.boxFilter(small, -1, (kw, kh), normalize=True, borderType=cv2.BORDER_CONSTANT)
    centres = []
    for _ in range(count):
        i, j = np.unravel_index(int(np.argmax(mean)), mean.shape)
        if mean[i, j] < min_mean:
            break
        centres.append(np.array([(j + 0.5) * width / small.shape[1], (i + 0.5) * height / small.shape[0]]))
        mean[max(0, i - kh):i + kh + 1, max(0, j - kw):j + kw + 1] = -1.0
    return centres


def offset_behind(box, front) -> tuple[float, float]:
    """Where (x, y, w, h) px ``box`` stands relative to the box ``front`` of the dancer it waits behind: the offsets
    of its centre x and its bottom from ``front``'s, in ``box`` heights (positive: right, down)."""
    x, y, w, h = box
    fx, fy, fw, fh = front
    return (x + w / 2 - fx - fw / 2) / h, (y + h - fy - fh) / h


def box_behind(box, front, offset) -> tuple[float, float, float, float]:
    """``box`` (x, y, w, h px; its size kept) placed at ``offset`` (:func:`offset_behind`) from the box ``front``."""
    _, _, w, h = box
    fx, fy, fw, fh = front
    cx, bottom = fx + fw / 2 + offset[0] * h, fy + fh + offset[1] * h
    return (cx - w / 2, bottom - h, w, h)


def shifted(box, d) -> tuple[float, float, float, float]:
    """(x, y, w, h px) ``box`` moved by ``d`` = (dx, dy) px."""
    return (box[0] + float(d[0]), box[1] + float(d[1]), box[2], box[3])
