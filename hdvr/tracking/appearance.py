"""Colour histograms of image regions, the appearance memory of Algorithms 1* and 2*.

A histogram is hue x saturation (HSV, 16 x 8 bins, L1-normalised) of the pixels inside a box or mask; pixels too
dark or too unsaturated to have a meaningful hue still count through a separate value-only part (8 bins), so that
black and white clothes are told apart too. Similarity is OpenCV's histogram correlation in [-1, 1].
"""

from __future__ import annotations

import cv2
import numpy as np

HUE_BINS, SAT_BINS, VALUE_BINS = 16, 8, 8
#: saturation and value (0-255) above which a pixel's hue counts (hue x saturation bins); below, its value bin
MIN_CHROMA = 40


def clip_box(box, size) -> tuple[int, int, int, int] | None:
    """Integer (x0, y0, x1, y1) of ``box`` = (x, y, w, h) px clipped to an image of ``size`` = (w, h); None if
    nothing of it is inside."""
    x, y, w, h = box
    if not np.all(np.isfinite([x, y, w, h])):
        return None
    x0, y0 = max(int(np.floor(x)), 0), max(int(np.floor(y)), 0)
    x1, y1 = min(int(np.ceil(x + w)), size[0]), min(int(np.ceil(y + h)), size[1])
    if x1 - x0 < 2 or y1 - y0 < 2:
        return None
    return x0, y0, x1, y1


def colour_histogram(frame_bgr: np.ndarray, box, shrink: float | tuple[float, float] = 0.15,
                     mask: np.ndarray | None = None):
    """Histogram of ``box`` = (x, y, w, h) px in ``frame_bgr``, after shrinking the box by ``shrink`` of its
    size on each side (less background); a pair is (left and right, top and bottom). ``mask`` (same size as the
    frame, uint8) restricts it further. Returns a float32 vector, or None if the box is outside the frame or has no
    pixels."""
    x, y, w, h = box
    sx, sy = (shrink, shrink) if np.isscalar(shrink) else shrink
    inner = (x + sx * w, y + sy * h, w * (1 - 2 * sx), h * (1 - 2 * sy))
    r = clip_box(inner, (frame_bgr.shape[1], frame_bgr.shape[0]))
    if r is None:
        return None
    x0, y0, x1, y1 = r
    hsv = cv2.cvtColor(frame_bgr[y0:y1, x0:x1], cv2.COLOR_BGR2HSV)
    sub_mask = None if mask is None else np.ascontiguousarray(mask[y0:y1, x0:x1])
    if sub_mask is not None and not sub_mask.any():
        return None
    chromatic = ((hsv[..., 1] > MIN_CHROMA) & (hsv[..., 2] > MIN_CHROMA)).astype(np.uint8) * 255
    achromatic = 255 - chromatic
    if sub_mask is not None:
        chromatic &= sub_mask
        achromatic &= sub_mask
    hs = cv2.calcHist([hsv], [0, 1], chromatic, [HUE_BINS, SAT_BINS], [0, 180, 0, 256]).ravel()
    v = cv2.calcHist([hsv], [2], achromatic, [VALUE_BINS], [0, 256]).ravel()
    hist = np.concatenate([hs, v]).astype(np.float32)
    total = hist.sum()
    return hist / total if total > 0 else None


def colour_bins(frame_bgr: np.ndarray) -> np.ndarray:
    """(height, width) int index of each pixel's bin in the layout of :func:`colour_histogram`: hue x saturation
    (``hue_bin * SAT_BINS + sat_bin``) for pixels with a meaningful hue, ``HUE_BINS * SAT_BINS + value_bin`` for the
    others. A histogram looked up at these indices gives each pixel the weight of its colour (a back-projection)."""
    hsv = cv2.cvtColor(frame_bgr, cv2.COLOR_BGR2HSV)
    h, s, v = (hsv[..., k].astype(np.int32) for k in range(3))
    chromatic = (s > MIN_CHROMA) & (v > MIN_CHROMA)
    hue_sat = np.minimum(h * HUE_BINS // 180, HUE_BINS - 1) * SAT_BINS + s * SAT_BINS // 256
    return np.where(chromatic, hue_sat, HUE_BINS * SAT_BINS + v * VALUE_BINS // 256)


def histogram_similarity(a, b) -> float:
    """Correlation of two histograms in [-1, 1]; -1 when either is missing."""
    if a is None or b is None:
        return -1.0
    return float(cv2.compareHist(a, b, cv2.HISTCMP_CORREL))


def _intersection(a, b) -> float:
    """Area (px^2) of the intersection of two (x, y, w, h) boxes."""
    ix = max(0.0, min(a[0] + a[2], b[0] + b[2]) - max(a[0], b[0]))
    iy = max(0.0, min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1]))
    return ix * iy


def box_iou(a, b) -> float:
    """Intersection over union of two (x, y, w, h) boxes."""
    inter = _intersection(a, b)
    union = a[2] * a[3] + b[2] * b[3] - inter
    return float(inter / union) if union > 0 else 0.0


def box_overlap(a, b) -> float:
    """Intersection over the smaller box's area, in [0, 1] (1 when one box lies inside the other)."""
    smaller = min(a[2] * a[3], b[2] * b[3])
    return float(_intersection(a, b) / smaller) if smaller > 0 else 0.0


def box_inside(inner, outer) -> float:
    """Fraction of box ``inner``'s area inside box ``outer`` (both x, y, w, h px), in [0, 1]."""
    area = inner[2] * inner[3]
    return float(_intersection(inner, outer) / area) if area > 0 else 0.0


def foreground_mask(frame_bgr: np.ndarray, boxes, margin=(0.3, 0.3), rarity: float = 1e-4,
                    min_background: float = 0.1, opening: int = 3,
                    margin_fallbacks: tuple[float, ...] = (0.5, 0.25),
                    ring_common: float | None = None, arm_rows: tuple[float, float] = (0.05, 0.6),
                    arm_margin: float | None = None) -> np.ndarray | None:
    """bool mask (frame height, width) of the pixels whose colour is rare in the background: the background is
    every pixel outside ``boxes`` (x, y, w, h px, NaN rows ignored), each widened by ``margin`` = (sideways, up and
    down) x its height on each side (a dancer's spread arms reach beyond its box); a pixel is foreground when the
    fraction of background pixels in its colour bin (16 levels per BGR channel) is below ``rarity``. An opening
    (``opening`` x ``opening`` px square) removes thinner specks and lines. Where the widened boxes leave less than
    ``min_background`` of the frame (dancers close to the camera), the margin is scaled by each of
    ``margin_fallbacks`` in turn; None when even then too little is background to tell. ``ring_common``: a colour
    that fills more than this fraction of the ring between the boxes and the widened boxes, and of the ring on both
    sides of some box (left and right of it within its widened box), is background too: the floor where the widened
    boxes cover all of it shows on both sides of a dancer, a person whom no box holds, standing beside her, on one
    side only (:func:`_spread`); None: off. ``arm_margin``: the rows ``arm_rows`` of each box (x its height from its
    top) are left out of the background further sideways, this x its height on each side: a spread arm's hand and
    forearm reach past ``margin``, and in the sample their colour (skin) would be background, so that the arm
    seemed to end at the sleeve (hdvr synth seed 3136 tango); None: off.
    Needs no frame history, so it works with a moving camera, as long as the dancers' clothes and skin differ in
    colour from the floor and walls around them.

    The 4096-bin colour histogram is counted and looked up with numpy (``np.bincount`` and a uint8 table): OpenCV's
    ``calcBackProject`` returned an all-zero image for a normalised 3-D float histogram here (OpenCV 5.0)."""
    h, w = frame_bgr.shape[:2]
    for shrink in (1.0, *margin_fallbacks):
        background = np.ones((h, w), bool)
        widened = []  # (box, widened box as clip_box's (x0, y0, x1, y1)), for the ring's sides
        for box in boxes:
            x, y, bw, bh = (float(v) for v in box)
            if not np.isfinite([x, y, bw, bh]).all():
                continue
            mx, my = margin[0] * bh * shrink, margin[1] * bh * shrink
            r = clip_box((x - mx, y - my, bw + 2 * mx, bh + 2 * my), (w, h))
            if r is not None:
                background[r[1]:r[3], r[0]:r[2]] = False
                widened.append((box, r))
            if arm_margin is not None:
                ma = arm_margin * bh * shrink
                a = clip_box((x - ma, y + arm_rows[0] * bh, bw + 2 * ma, (arm_rows[1] - arm_rows[0]) * bh), (w, h))
                if a is not None:
                    background[a[1]:a[3], a[0]:a[2]] = False
        count = int(background.sum())
        if count >= min_background * h * w:
            break
    if count < min_background * h * w:
        return None
    q = (frame_bgr >> 4).astype(np.uint16)
    index = (q[..., 0] << 8) | (q[..., 1] << 4) | q[..., 2]
    rare = np.bincount(index[background], minlength=4096) < rarity * count
    if ring_common is not None:
        ring = ~background
        corners = [(clip_box(box, (w, h)), outer) for box, outer in widened]
        for inner, _ in corners:
            if inner is not None:
                ring[inner[1]:inner[3], inner[0]:inner[2]] = False
        if ring.any():
            rare &= ~(_common(index, ring, ring_common) & _spread(index, ring, corners, ring_common))
    rare = rare.astype(np.uint8)
    fg = rare[index]
    return cv2.morphologyEx(fg, cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_RECT, (opening, opening))) > 0


def _common(index: np.ndarray, where: np.ndarray, fraction: float) -> np.ndarray:
    """(4096,) bool: the colour bins (``index``, per pixel) that fill more than ``fraction`` of the pixels
    ``where`` is True (all False where it is nowhere True)."""
    n = int(where.sum())
    return np.bincount(index[where], minlength=4096) > fraction * n if n else np.zeros(4096, bool)


def _spread(index: np.ndarray, ring: np.ndarray, widened, fraction: float) -> np.ndarray:
    """(4096,) bool: the colour bins that fill more than ``fraction`` of the ring's pixels on both sides of some
    box, left of it and right of it within its widened box (``widened``: (box, widened box) pairs of
    :func:`clip_box` corners). The floor and the wall show on both sides of a dancer; a person standing beside
    her, or her legs below a box of her upper body, on one side or under it only."""
    spread = np.zeros(4096, bool)
    for inner, outer in widened:
        if inner is None:
            continue
        rows = slice(outer[1], outer[3])
        sides = [(index[rows, a:b], ring[rows, a:b]) for a, b in ((outer[0], inner[0]), (inner[2], outer[2]))]
        spread |= _common(*sides[0], fraction) & _common(*sides[1], fraction)
    return spread
