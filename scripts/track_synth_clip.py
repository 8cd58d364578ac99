#!/usr/bin/env python3
"""Track one ``hdvr synth`` clip exactly as ``scripts/bench_track.py --sections synth`` does, for debugging a rule.

The benchmark starts each dancer from its unrounded ground-truth box in its first frame and runs YOLO11n-pose at
480 px on every 3rd frame (sure 0.3, weak 0.2), hindsight on. ``hdvr track --boxes-file CLIP/mot.txt`` reads start
boxes rounded to 0.01 px, and that alone can change a clip's figures (seed 212 hip-hop: IDF1 0.606 with the
benchmark's starts, 0.881 with the rounded ones; docs/benchmarks.md "session 47"), so a clip that fails in the
benchmark is best looked at with this script. It writes ``hdvr track``'s outputs to OUT (tracks.json,
tracks.mot.txt, dancer_*.npz and detections.npz, which a second run on the same OUT reuses), prints IDF1 and
identity switches at IoU 0.5, and with ``--frames`` a table: for each frame and ground-truth dancer, the tracked
dancer whose box overlaps its ground-truth box most (``.`` when below IoU 0.5), the IoU of its own tracked box and
the fraction of its keypoints seen, e.g. ``2>1 0.54 v0.4``: dancer 2's truth is best covered by tracked dancer 1.

Usage: python3 scripts/track_synth_clip.py CLIP_DIR OUT [--tracker-config NAME=VALUE,...] [--frames [EVERY]]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import (_seen_truth, _starts_from_truth, default_tracking_detector,  # noqa: E402
                         parse_tracker_config, track_synth_clip)

from hdvr.errors import HDVRError  # noqa: E402
from hdvr.tracking.evaluation import evaluate_tracking, iou_matrix  # noqa: E402


def frame_table(truth_boxes: np.ndarray, tracked: np.ndarray, seen: np.ndarray, every: int = 1) -> list[str]:
    """One line per ``every``-th frame: for each ground-truth dancer (``truth_boxes`` and ``tracked`` (T, N, 4) px,
    the same dancer order, NaN = absent; ``seen`` (T, N) fraction of keypoints seen) 'n>j iou vS', j the tracked
    dancer whose box overlaps n's truth most ('.' below IoU 0.5), iou that of n's own tracked box."""
    lines = []
    for t in range(0, truth_boxes.shape[0], every):
        cells = []
        for n, box in enumerate(truth_boxes[t]):
            if not np.isfinite(box).all():
                cells.append(f"{n}>- ---- v{seen[t, n]:.1f}")
                continue
            ious = iou_matrix(box[None], np.nan_to_num(tracked[t], nan=-1e6))[0]
            best = int(np.argmax(ious))
            cells.append(f"{n}>{best if ious[best] >= 0.5 else '.'} {ious[n]:.2f} v{seen[t, n]:.1f}")
        lines.append(f"{t:4d}  " + "  ".join(cells))
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("clip", type=Path, help="an hdvr synth clip folder (video.mp4, gt.npz)")
    parser.add_argument("out", type=Path, help="output folder (hdvr track's files)")
    parser.add_argument("--tracker-config", default="", help="MultiTrackerConfig overrides, NAME=VALUE,...")
    parser.add_argument("--frames", type=int, nargs="?", const=1, default=0, metavar="EVERY",
                        help="print the per-frame table (every EVERY-th frame; default every frame)")
    args = parser.parse_args(argv)
    if not (args.clip / "video.mp4").is_file() or not (args.clip / "gt.npz").is_file():
        raise SystemExit(f"track_synth_clip: {args.clip} is not an hdvr synth clip folder (video.mp4, gt.npz)")
    config = parse_tracker_config(args.tracker_config)
    truth_boxes, truth = _seen_truth(args.clip)
    order, starts = _starts_from_truth(truth_boxes)
    detector = default_tracking_detector()
    try:
        run = track_synth_clip(args.clip, args.out, detector, starts, config, write=True)
    except HDVRError as exc:
        raise SystemExit(f"track_synth_clip: {exc}")
    tracked = run.boxes[:, np.argsort(order)]
    scores = evaluate_tracking(truth_boxes, tracked)
    if args.frames:
        print("\n".join(frame_table(truth_boxes, tracked, truth[..., 2].mean(axis=-1), args.frames)))
    print(f"IDF1 {scores.idf1:.3f}  identity switches {scores.id_switches}  MOTA {scores.mota:.3f}  "
          f"HOTA {scores.hota:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
