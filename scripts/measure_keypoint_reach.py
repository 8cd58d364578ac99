#!/usr/bin/env python3
"""How far a dancer's body reaches beyond the keypoints the pose detector finds, in box heights.

``hdvr track``'s hindsight widens each seen dancer's box to its keypoints plus ``KEYPOINT_REACH`` x the box height
(the hand beyond the wrist, the foot beyond the ankle, the limb's thickness) and lowers a box whose top lies more
than ``HEAD_REACH`` above the highest keypoint (:mod:`hdvr.tracking.hindsight`). This script measures both on
``hdvr synth`` clips: it runs the tracking detector (YOLO11n-pose at 480 px, as ``hdvr track``) on every
``--every``-th frame, and for each dancer the camera shows whole (every keypoint seen) takes the detection whose
box overlaps the dancer's ground-truth amodal box most (IoU >= 0.5) and whose confident keypoints (>= 0.3) number
at least 15 and lie within 0.1 box heights of it. Per such dancer-frame: the left and right gaps between the
ground-truth box's sides and the outermost keypoints, and the gap between its top and the highest keypoint, each
over the ground-truth box height. Prints percentiles.

    python3 scripts/measure_keypoint_reach.py CLIP_DIR [CLIP_DIR ...] [--every 3]

CLIP_DIR: an ``hdvr synth`` clip folder (video.mp4, gt.npz), e.g. those ``bench_track.py --clips-dir`` keeps.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import _seen_truth, default_tracking_detector  # noqa: E402

from hdvr.tracking.evaluation import iou_matrix  # noqa: E402
from hdvr.video import VideoReader  # noqa: E402

MIN_CONFIDENCE = 0.3
MIN_KEYPOINTS = 15
MARGIN = 0.1
MIN_IOU = 0.5


def reach_beyond_keypoints(truth_box, keypoints, min_confidence: float = MIN_CONFIDENCE,
                           min_keypoints: int = MIN_KEYPOINTS, margin: float = MARGIN) -> np.ndarray | None:
    """(left, right, top) gaps between the sides and top of ``truth_box`` (x, y, w, h px) and the outermost and
    highest of ``keypoints`` (J, 3: x px, y px, confidence), over the box height; None when fewer than
    ``min_keypoints`` keypoints reach ``min_confidence`` or any of them lies more than ``margin`` box heights outside
    the box (the pose is not this dancer's alone)."""
    x, y, w, h = (float(v) for v in truth_box)
    kp = np.asarray(keypoints, float)
    good = (kp[:, 2] >= min_confidence) & np.isfinite(kp[:, :2]).all(axis=1)
    if good.sum() < min_keypoints or h <= 0:
        return None
    kx, ky = kp[good, 0], kp[good, 1]
    if kx.min() < x - margin * h or kx.max() > x + w + margin * h or ky.min() < y - margin * h \
            or ky.max() > y + h + margin * h:
        return None
    return np.array([kx.min() - x, x + w - kx.max(), ky.min() - y]) / h


def measure_clip(clip: Path, detector, every: int = 3) -> list[np.ndarray]:
    """Reaches (:func:`reach_beyond_keypoints`) of the dancers seen whole in an hdvr synth clip folder, on every
    ``every``-th frame, each taken from the detection that overlaps its ground-truth box most."""
    truth_boxes, truth = _seen_truth(clip)
    whole = truth[..., 2].min(axis=-1) >= 1.0  # (T, N) every keypoint seen
    out = []
    for t, frame in enumerate(VideoReader(clip / "video.mp4")):
        if t >= len(truth_boxes):
            break
        if t % every or not whole[t].any():
            continue
        people = detector.detect(frame, t)
        if not people:
            continue
        ious = iou_matrix(np.nan_to_num(truth_boxes[t], nan=-1e6), np.array([p.box for p in people], float))
        for i in np.flatnonzero(whole[t] & np.isfinite(truth_boxes[t]).all(axis=1)):
            j = int(np.argmax(ious[i]))
            if ious[i, j] >= MIN_IOU:
                reach = reach_beyond_keypoints(truth_boxes[t, i], people[j].keypoints)
                if reach is not None:
                    out.append(reach)
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("clips", type=Path, nargs="+", help="hdvr synth clip folders (video.mp4, gt.npz)")
    parser.add_argument("--every", type=int, default=3, help="run the detector on every k-th frame (default 3)")
    args = parser.parse_args(argv)
    bad = [c for c in args.clips if not (c / "video.mp4").is_file() or not (c / "gt.npz").is_file()]
    if bad:
        raise SystemExit(f"measure_keypoint_reach: {bad[0]} is not an hdvr synth clip folder (video.mp4, gt.npz)")
    detector = default_tracking_detector()
    reaches = []
    for k, clip in enumerate(args.clips):
        reaches += measure_clip(clip, detector, args.every)
        print(f"\r{k + 1}/{len(args.clips)} clips, {len(reaches)} dancer-frames", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    if not reaches:
        raise SystemExit("measure_keypoint_reach: no dancer seen whole with a matching pose in these clips")
    r = np.array(reaches)
    q = (10, 25, 50, 75, 90)
    print(f"{len(r)} dancer-frames seen whole; gaps in ground-truth box heights, percentiles {q}:")
    for name, values in (("sides (left and right)", r[:, :2].ravel()), ("top above the highest keypoint", r[:, 2])):
        print(f"  {name}: " + " / ".join(f"{v:.3f}" for v in np.percentile(values, q)) + f"; mean {values.mean():.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
