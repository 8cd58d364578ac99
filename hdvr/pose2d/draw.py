"""Overlay drawing: tracked boxes with dancer ids and BODY_25 skeletons on a video frame."""

from __future__ import annotations

import cv2
import numpy as np

from hdvr.layouts import BODY25_BONES, BODY25_NAMES

_J = {n: i for i, n in enumerate(BODY25_NAMES)}
_BONES = [(_J[a], _J[b]) for a, b in BODY25_BONES]
# distinct BGR colours per dancer id (colour-blind-friendly Okabe-Ito palette)
PALETTE = ((0, 159, 230), (233, 180, 86), (115, 158, 0), (66, 228, 240), (178, 114, 0), (0, 94, 213),
           (167, 121, 204), (0, 0, 0))


def dancer_colour(dancer_id: int) -> tuple[int, int, int]:
    return PALETTE[dancer_id % len(PALETTE)]


def draw_overlay(frame_bgr: np.ndarray, boxes, status, keypoints25=None, ids=None,
                 frame_index: int | None = None) -> np.ndarray:
    """Draw in place and return ``frame_bgr``: for dancer i its box (thick when tracked, thin with a "?" when its
    position is predicted or filled through an occlusion, or held while it waits hidden behind another), its
    id, and its skeleton from ``keypoints25[i]`` (25, 3) if given; with ``frame_index``, "frame N" (0-based, as
    ``hdvr track --correct`` counts) in the top-left corner."""
    h = frame_bgr.shape[0]
    scale = max(h / 720.0, 0.5)
    if frame_index is not None:
        text = f"frame {frame_index}"
        size, base = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.7 * scale, max(1, int(2 * scale)))
        pad = max(2, int(4 * scale))
        cv2.rectangle(frame_bgr, (0, 0), (size[0] + 2 * pad, size[1] + base + 2 * pad), (0, 0, 0), -1)
        cv2.putText(frame_bgr, text, (pad, pad + size[1]), cv2.FONT_HERSHEY_SIMPLEX, 0.7 * scale, (255, 255, 255),
                    max(1, int(2 * scale)), cv2.LINE_AA)
    ids = list(range(len(boxes))) if ids is None else ids
    for i, box in enumerate(boxes):
        colour = dancer_colour(ids[i])
        if keypoints25 is not None and keypoints25[i] is not None:
            kp = keypoints25[i]
            for a, b in _BONES:
                if kp[a, 2] > 0 and kp[b, 2] > 0 and np.isfinite(kp[[a, b], :2]).all():
                    cv2.line(frame_bgr, tuple(int(v) for v in kp[a, :2]), tuple(int(v) for v in kp[b, :2]),
                             colour, max(1, int(3 * scale)), cv2.LINE_AA)
            for j in range(kp.shape[0]):
                if kp[j, 2] > 0 and np.isfinite(kp[j, :2]).all():
                    cv2.circle(frame_bgr, tuple(int(v) for v in kp[j, :2]), max(2, int(3 * scale)), (255, 255, 255),
                               -1, cv2.LINE_AA)
        if not np.all(np.isfinite(box)):
            continue
        x, y, w, bh = (int(round(v)) for v in box)
        tracked = status[i] == "tracked"
        cv2.rectangle(frame_bgr, (x, y), (x + w, y + bh), colour, max(1, int((3 if tracked else 1) * scale)))
        label = f"{ids[i]}" + ("" if tracked else " ?")
        cv2.putText(frame_bgr, label, (x + 4, max(y - 6, int(20 * scale))), cv2.FONT_HERSHEY_SIMPLEX, 0.9 * scale,
                    colour, max(1, int(2 * scale)), cv2.LINE_AA)
    return frame_bgr


def draw_pixel_grid(frame_bgr: np.ndarray, step: int = 100) -> np.ndarray:
    """Draw in place and return ``frame_bgr``: thin lines every ``step`` pixels (fainter ones half-way between),
    each labelled with its pixel coordinate along the bottom and left edges, so that a box or point can be read off
    the picture for ``hdvr track --correct``."""
    if step < 10:
        raise ValueError(f"grid step must be >= 10 px, got {step}")
    h, w = frame_bgr.shape[:2]
    scale = max(h / 720.0, 0.5)
    thin = frame_bgr.copy()
    for x in range(step // 2, w, step // 2):
        cv2.line(thin, (x, 0), (x, h - 1), (255, 255, 255), 1)
    for y in range(step // 2, h, step // 2):
        cv2.line(thin, (0, y), (w - 1, y), (255, 255, 255), 1)
    cv2.addWeighted(thin, 0.25, frame_bgr, 0.75, 0, dst=frame_bgr)
    for x in range(step, w, step):
        cv2.line(frame_bgr, (x, 0), (x, h - 1), (255, 255, 255), 1)
    for y in range(step, h, step):
        cv2.line(frame_bgr, (0, y), (w - 1, y), (255, 255, 255), 1)

    size = max(0.4, 0.45 * scale)

    def label(text, org):  # white on a dark outline: legible on any background
        for colour, width in (((0, 0, 0), max(3, int(3 * scale))), ((255, 255, 255), max(1, int(scale)))):
            cv2.putText(frame_bgr, text, org, cv2.FONT_HERSHEY_SIMPLEX, size, colour, width, cv2.LINE_AA)

    for x in range(step, w, step):
        label(str(x), (x + 3, h - int(8 * scale)))
    for y in range(step, h, step):
        label(str(y), (3, y - 4))
    return frame_bgr
