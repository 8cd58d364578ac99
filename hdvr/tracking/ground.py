"""The floor seen in perspective: the image row of the horizon, fitted to the dancers' boxes, and how much larger a
dancer looks where its feet lie lower in the image.

A pinhole camera sees a dancer of height ``H`` standing on a flat floor at depth ``Z`` with a box height
``h = f H / Z`` px, and its feet ``f c / Z`` px below the horizon (``c``: the camera's height above the floor, ``f``:
the focal length in px). So ``h = k (b - y_h)`` for the box bottom ``b`` and the horizon row ``y_h``, with ``k = H / c``
one number per dancer: a dancer coming nearer the camera moves its feet down the image and grows in proportion to
their distance below the horizon. This holds exactly for a level camera and nearly so for the tilts dance videos are
filmed with (the horizon is then a line across the image, nearly level).

:func:`fit_horizon` finds ``y_h`` from the boxes of the dancers seen: the row that makes each dancer's ``log h -
log(b - y_h)`` most nearly constant over its frames. Poses move a box's height by more than a small step in depth
moves it (arms raised, a crouch, a jump lifts the bottom), so a horizon is fitted only when some dancer's feet range
over ``min_spread`` x its height up and down the image, and never nearer the lowest feet than ``min_depth`` x the
dancers' height (a camera at least that high above the floor); otherwise it is ``-inf``, a horizon infinitely far up:
sizes that do not change with the feet. Chosen on 497 hdvr synth clips (docs/benchmarks.md "Session 74"): with a
spread of 0.05, steps and jumps of dancers standing in place fitted horizons just above their feet, and waiting
dancers' boxes scaled by them broke 4 clips (21 -> 24 failing); 0.08 broke one, 0.1, 0.15 and 0.2 none. The fit is
rough: on those clips a horizon is fitted on 215, and lies a median 0.33 of a box height from the camera's true
horizon, mostly too high (quartiles -0.67 and +0.08 heights), which errs towards sizes that change too little.

Boxes are (x, y, w, h) pixels, top-left origin, y down; arrays are indexed (frame, dancer).
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.state import TRACKED

#: least range of a dancer's box bottoms (max - min over the frames it is seen), in its median box height, for a
#: horizon to be fitted: a step in depth must show beyond the bottom's jitter from steps and jumps in place
HORIZON_MIN_SPREAD = 0.1
#: least distance of the horizon above the lowest box bottom, in the dancers' median box height: a camera at least
#: 0.2 x a dancer's height above the floor (hdvr synth's cameras stand 0.6-2.4 m high)
HORIZON_MIN_DEPTH = 0.2
#: every how many frames a dancer's box is sampled (neighbouring frames add little but time)
SAMPLE_STEP = 3
#: least samples of a dancer for its boxes to count
MIN_SAMPLES = 5
#: a sample's deviation from its dancer's fitted size counts at most this much (natural log of the height ratio): a
#: raised arm or a box left on a neighbour's body pulls the fit no further
MAX_LOG_DEVIATION = 0.15
#: candidate horizons: this many distances above the lowest feet, geometrically spaced from ``min_depth`` to
#: ``FARTHEST`` x the median height, and -inf (sizes constant)
CANDIDATES = 200
FARTHEST = 50.0


def _samples(boxes: np.ndarray, status: np.ndarray, step: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per dancer seen on at least ``MIN_SAMPLES`` sampled frames: its box bottoms and heights (px) there."""
    out = []
    for dancer in range(boxes.shape[1]):
        seen = (status[:, dancer] == TRACKED) & np.isfinite(boxes[:, dancer]).all(axis=1) & (boxes[:, dancer, 3] > 0)
        frames = np.flatnonzero(seen)[::step]
        if len(frames) >= MIN_SAMPLES:
            box = boxes[frames, dancer]
            out.append((box[:, 1] + box[:, 3], box[:, 3]))
    return out


def _misfit(samples, horizon: float) -> float:
    """How far the samples lie from ``h = k (b - horizon)`` with one ``k`` per dancer (each dancer's median log
    ratio): the sum of squared log deviations, each capped at ``MAX_LOG_DEVIATION``."""
    total = 0.0
    for bottoms, heights in samples:
        deviation = np.log(heights) - (np.log(bottoms - horizon) if np.isfinite(horizon) else 0.0)
        deviation -= np.median(deviation)
        total += float(np.sum(np.minimum(deviation ** 2, MAX_LOG_DEVIATION ** 2)))
    return total


def fit_horizon(boxes: np.ndarray, status, min_spread: float = HORIZON_MIN_SPREAD,
                min_depth: float = HORIZON_MIN_DEPTH, step: int = SAMPLE_STEP) -> float:
    """The image row (y px) of the horizon that best explains the heights of the boxes ``boxes`` (T, N, 4) px of
    the dancers seen (``status`` (T, N) ``tracked``) by their bottoms (module docstring), or ``-inf`` where the boxes
    do not tell it: no dancer's bottoms range over ``min_spread`` x the median height, nor any dancer is seen on
    ``MIN_SAMPLES`` sampled frames, or sizes that do not change with the feet fit best. The fit is a search over
    candidate rows, not a local optimiser: the capped misfit has flat stretches and several minima."""
    boxes = np.asarray(boxes, float)
    status = np.asarray(status)
    if boxes.ndim != 3 or boxes.shape[-1] != 4 or status.shape != boxes.shape[:2]:
        raise ValueError(f"boxes must be (T, N, 4) and status (T, N), got {boxes.shape} and {status.shape}")
    if not (min_spread >= 0 and min_depth > 0 and step >= 1):
        raise ValueError(f"min_spread must be >= 0, min_depth > 0 and step >= 1, got {min_spread}, {min_depth}, {step}")
    samples = _samples(boxes, status, int(step))
    if not samples:
        return -np.inf
    height = float(np.median(np.concatenate([h for _, h in samples])))
    if max(float(np.ptp(b)) for b, _ in samples) < min_spread * height:
        return -np.inf
    lowest = float(min(b.min() for b, _ in samples))
    candidates = np.append(lowest - height * np.geomspace(min_depth, FARTHEST, CANDIDATES), -np.inf)
    misfits = [_misfit(samples, float(y)) for y in candidates]
    return float(candidates[int(np.argmin(misfits))])  # the first (nearest the feet) of equal misfits


def height_ratio(boxes: np.ndarray, status, horizon: float, step: int = SAMPLE_STEP) -> float:
    """The box height per pixel of feet below the horizon row ``horizon`` px of the dancers seen in ``boxes``
    (T, N, 4) px (``status`` (T, N) ``tracked``): ``k = H / c``, a dancer's stature over the camera's height above
    the floor (module docstring); the median over the dancers (each seen on ``MIN_SAMPLES`` sampled frames) of each
    one's median. NaN for a horizon at ``-inf`` or no dancer seen so long."""
    boxes = np.asarray(boxes, float)
    samples = _samples(boxes, np.asarray(status), int(step)) if np.isfinite(horizon) else []
    ratios = [np.median(h[b > horizon] / (b[b > horizon] - horizon)) for b, h in samples if (b > horizon).any()]
    return float(np.median(ratios)) if ratios else np.nan


def depth_scale(bottom, start_bottom: float, horizon: float) -> np.ndarray:
    """How many times larger a dancer looks with its feet at image row ``bottom`` (px, any shape) than at
    ``start_bottom`` (px), for the horizon at row ``horizon`` (:func:`fit_horizon`): ``(bottom - horizon) /
    (start_bottom - horizon)``; 1 for a horizon at ``-inf``. Bottoms at or above the horizon are not on the floor in
    front of the camera: NaN."""
    bottom = np.asarray(bottom, float)
    if not np.isfinite(horizon):
        return np.ones_like(bottom)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = (bottom - horizon) / (start_bottom - horizon)
    return np.where((bottom > horizon) & (start_bottom > horizon), scale, np.nan)
