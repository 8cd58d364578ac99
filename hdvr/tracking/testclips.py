"""Procedural test videos with known trajectories: textured stick figures that walk, swing their arms, cross
and occlude each other in front of a textured background.

Figures walk in straight lines and turn back at the left and right edges (by default 6 % of the width from them),
so a long clip has many crossings; a figure whose turning point lies outside the frame walks out and back in
(its ground-truth box is NaN while nothing of it is in the frame, and covers the part inside the frame). Each
figure has a skeleton (BODY_25 joints, pixels) animated per frame; its ground-truth box is the amodal (x, y, w, h)
box of the drawn figure, occluded parts included, as in the MOT challenge. Figures are drawn back
to front in a fixed depth order, so at a crossing the nearer figure hides the farther one.
Everything is deterministic by ``seed``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import cv2
import numpy as np

from hdvr.layouts import BODY25_NAMES
from hdvr.video import VideoWriter

_J = {name: i for i, name in enumerate(BODY25_NAMES)}
_LIMBS = (("neck", "mid_hip", 0.16), ("right_shoulder", "left_shoulder", 0.10), ("right_hip", "left_hip", 0.10),
          ("right_shoulder", "right_elbow", 0.07), ("right_elbow", "right_wrist", 0.06),
          ("left_shoulder", "left_elbow", 0.07), ("left_elbow", "left_wrist", 0.06),
          ("right_hip", "right_knee", 0.08), ("right_knee", "right_ankle", 0.07),
          ("left_hip", "left_knee", 0.08), ("left_knee", "left_ankle", 0.07), ("neck", "nose", 0.06))


@dataclass
class FigureSpec:
    """One figure: start centre (x, y) px, velocity (vx, vy) px/frame, height px, colours (BGR), depth."""

    start: tuple[float, float]
    velocity: tuple[float, float]
    height: float
    colours: tuple[tuple[int, int, int], tuple[int, int, int]]  # two stripe colours of its texture
    depth: float  # larger = farther (drawn first)
    phase: float = 0.0  # of the arm/leg swing, radians
    turn: tuple[float, float] = (0.06, 0.94)  # x of the left and right turning points, fractions of the width;
    # outside (0, 1) the figure walks out of the frame and back in


@dataclass
class ClipTruth:
    """Ground truth of a procedural clip."""

    boxes: np.ndarray  # (T, N, 4) float: amodal (x, y, w, h) pixels
    keypoints: np.ndarray  # (T, N, 25, 3) float32: BODY_25 x_px, y_px, confidence (1 visible joint, NaN missing)
    fps: float
    size: tuple[int, int]  # (width, height)
    specs: list[FigureSpec] = field(default_factory=list)


def skeleton(center: tuple[float, float], height: float, t: float, phase: float) -> np.ndarray:
    """BODY_25 joints (25, 2) px of a walking figure of ``height`` px centred at ``center`` at time ``t`` frames.
    Toes and heels, eyes and ears are left NaN (the drawn figure has none)."""
    cx, cy = center
    s = height
    swing = 0.3 * np.sin(2 * np.pi * t / 30.0 + phase)
    pts = np.full((25, 2), np.nan)
    top = cy - 0.5 * s

    def put(name, x, y):
        pts[_J[name]] = (x, y)

    put("nose", cx, top + 0.07 * s)
    put("neck", cx, top + 0.17 * s)
    put("right_shoulder", cx - 0.11 * s, top + 0.2 * s)
    put("left_shoulder", cx + 0.11 * s, top + 0.2 * s)
    for side, sign in (("right", -1), ("left", 1)):
        a = sign * swing
        sh = pts[_J[f"{side}_shoulder"]]
        el = sh + 0.16 * s * np.array([np.sin(a) + sign * 0.15, np.cos(a)])
        put(f"{side}_elbow", *el)
        put(f"{side}_wrist", *(el + 0.15 * s * np.array([np.sin(1.6 * a) + sign * 0.1, np.cos(1.6 * a)])))
    put("mid_hip", cx, top + 0.52 * s)
    put("right_hip", cx - 0.07 * s, top + 0.52 * s)
    put("left_hip", cx + 0.07 * s, top + 0.52 * s)
    for side, sign in (("right", 1), ("left", -1)):
        a = sign * swing * 0.7
        hip = pts[_J[f"{side}_hip"]]
        kn = hip + 0.24 * s * np.array([np.sin(a), np.cos(a)])
        put(f"{side}_knee", *kn)
        put(f"{side}_ankle", *(kn + 0.24 * s * np.array([np.sin(a * 0.5), 1.0])))
    return pts


def _bounce(x: float, lo: float, hi: float) -> float:
    """``x`` reflected into [lo, hi] (a walk that turns back at the edges)."""
    span = hi - lo
    u = (x - lo) % (2 * span)
    return lo + (u if u <= span else 2 * span - u)


def _texture(colours, size, seed) -> np.ndarray:
    rng = np.random.default_rng(seed)
    h, w = size
    yy, xx = np.mgrid[0:h, 0:w]
    stripes = ((xx + yy) // 6) % 2
    tex = np.where(stripes[..., None] == 0, np.array(colours[0]), np.array(colours[1])).astype(np.float32)
    tex += rng.normal(0, 18, tex.shape)
    return np.clip(tex, 0, 255).astype(np.uint8)


def _background(size, seed) -> np.ndarray:
    rng = np.random.default_rng(seed)
    w, h = size
    bg = cv2.GaussianBlur(rng.integers(60, 200, (h, w, 3), dtype=np.uint8), (0, 0), 6)
    return cv2.normalize(bg, None, 70, 190, cv2.NORM_MINMAX)


#: clothes of clearly different colours (BGR stripe pairs), one per figure: the crossing clips use the first 4, the
#: groups up to all 8 (a dancer dressed like the background is not a re-identification test)
FIGURE_PALETTE = (((30, 30, 200), (40, 200, 230)), ((200, 60, 30), (230, 220, 90)), ((30, 170, 30), (20, 20, 20)),
                  ((240, 240, 240), (150, 30, 150)), ((0, 120, 255), (90, 0, 60)), ((200, 200, 0), (60, 60, 140)),
                  ((120, 0, 160), (0, 230, 140)), ((20, 80, 20), (220, 160, 255)))


def default_crossing_specs(size=(640, 480), num_figures: int = 2, seed: int = 0) -> list[FigureSpec]:
    """Up to 4 figures, clear of each other in the first frame, that then cross: figure 0 walks right from the
    left edge, 1 walks left from the right edge (they cross head-on), 2 and 3 walk slowly between them (they are
    overtaken and crossed)."""
    if not 1 <= num_figures <= 4:
        raise ValueError("1 to 4 figures")
    rng = np.random.default_rng(seed)
    w, h = size
    layout = [(0.1, 1.0), (0.9, -1.0), (0.42, 0.35), (0.66, -0.35)]  # start x / width, speed factor
    specs = []
    for i in range(num_figures):
        x_frac, speed_factor = layout[i]
        speed = rng.uniform(2.8, 3.6) * speed_factor
        y0 = h * 0.55 + rng.uniform(-0.04, 0.04) * h
        specs.append(FigureSpec((w * x_frac, y0), (speed, rng.uniform(-0.1, 0.1)), h * rng.uniform(0.55, 0.65),
                                FIGURE_PALETTE[i], depth=float((i * 7 + seed) % num_figures),
                                phase=rng.uniform(0, 6.3)))
    return specs



def troupe_specs(size=(640, 480), num_figures: int = 6, seed: int = 0) -> list[FigureSpec]:
    """A group of 5 to 8 figures in two rows, side by side in the first frame (start positions spread evenly
    across the width, alternately in the back row, smaller and higher in the image: farther from the camera, and
    in the front row), every figure walking left or right at its own speed (1.2-3.2 px/frame) and turning back at
    the edges: figures of one row cross head-on and overtake each other, and the front row hides the legs and
    bodies of the back row as they pass."""
    if not 5 <= num_figures <= len(FIGURE_PALETTE):
        raise ValueError(f"5 to {len(FIGURE_PALETTE)} figures")
    rng = np.random.default_rng(seed)
    w, h = size
    specs = []
    for i in range(num_figures):
        back = i % 2 == 0
        height_frac, y_frac, depth = (0.40, 0.42, 1.0) if back else (0.52, 0.62, 0.0)
        x0 = w * (0.08 + 0.84 * (i + 0.5) / num_figures)
        speed = rng.uniform(1.2, 3.2) * rng.choice([-1.0, 1.0])
        height = h * height_frac * rng.uniform(0.95, 1.05)
        specs.append(FigureSpec((x0, h * y_frac + rng.uniform(-0.02, 0.02) * h), (speed, 0.0), height,
                                FIGURE_PALETTE[i], depth=depth + 0.01 * i, phase=rng.uniform(0, 6.3)))
    return specs


def render_clip(path: str | os.PathLike, frames: int = 150, size=(640, 480), fps: float = 30.0,
                specs: list[FigureSpec] | None = None, seed: int = 0, crf: int = 18) -> ClipTruth:
    """Write an H.264 clip to ``path`` and return its ground truth."""
    specs = specs if specs is not None else default_crossing_specs(size, seed=seed)
    bg = _background(size, seed + 101)
    textures = [_texture(s.colours, (size[1], size[0]), seed + 7 * i) for i, s in enumerate(specs)]
    n = len(specs)
    boxes = np.zeros((frames, n, 4))
    kps = np.full((frames, n, 25, 3), np.nan, np.float32)
    order = sorted(range(n), key=lambda i: -specs[i].depth)  # far to near
    with VideoWriter(path, fps, size, crf=crf) as writer:
        for t in range(frames):
            frame = bg.copy()
            for i in order:
                s = specs[i]
                c = (_bounce(s.start[0] + s.velocity[0] * t, s.turn[0] * size[0], s.turn[1] * size[0]),
                     s.start[1] + s.velocity[1] * t)
                pts = skeleton(c, s.height, t, s.phase)
                mask = np.zeros((size[1], size[0]), np.uint8)
                for a, b, thick in _LIMBS:
                    p, q = pts[_J[a]], pts[_J[b]]
                    cv2.line(mask, tuple(np.round(p).astype(int)), tuple(np.round(q).astype(int)), 255,
                             max(2, int(thick * s.height)), cv2.LINE_AA)
                head = pts[_J["nose"]]
                cv2.circle(mask, tuple(np.round(head).astype(int)), int(0.07 * s.height), 255, -1, cv2.LINE_AA)
                alpha = (mask.astype(np.float32) / 255.0)[..., None]
                frame = (frame * (1 - alpha) + textures[i] * alpha).astype(np.uint8)
                ys, xs = np.nonzero(mask)
                boxes[t, i] = (xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1) if len(xs) \
                    else (np.nan,) * 4
                kps[t, i, :, :2] = pts
                kps[t, i, :, 2] = np.where(np.isfinite(pts[:, 0]), 1.0, 0.0)
            writer.write(frame)
    return ClipTruth(boxes, kps, fps, tuple(size), specs)
