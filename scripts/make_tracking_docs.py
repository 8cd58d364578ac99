"""Pictures of where the tracker falls short, for docs/tracking.md ("Limits").

Renders held-out hdvr.synth clips (deterministic by seed), tracks them as ``scripts/bench_track.py --sections synth``
does (ground-truth start boxes, YOLO11n-pose at 480 px on every 3rd frame) and draws chosen frames: each dancer's
amodal ground-truth box thin, its tracked box thick in the same colour, with the IoU between them; the detector's
person boxes of that frame in white. Writes one JPEG per (seed, clip, frame) into docs/img.

    MUJOCO_GL=egl python3 scripts/make_tracking_docs.py
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")

#: (seed, clip index, genre, dancers, frame, what it shows)
CASES = (
    (113, 5, "ballet", 4, 60, "dancer 1 straight behind dancer 2: its spread arms and raised leg lie behind dancer 2, "
                              "its box keeps the arms-down width"),
    (97, 5, "ballet", 4, 57, "a clump of three: no pose is chosen for dancer 2 (narrow box), and the predicted box of "
                             "dancer 3, hidden behind them, matches dancer 2's ground truth better"),
)
COLOURS = [(0, 0, 255), (0, 190, 0), (255, 60, 0), (0, 200, 220)]  # BGR


def draw_case(frame: np.ndarray, gt: np.ndarray, tracked: np.ndarray, detections, crop_margin: int = 40):
    """Frame with ground-truth (thin) and tracked (thick) boxes, IoU labels, detections in white; cropped."""
    import cv2

    from hdvr.tracking.appearance import box_iou

    img = frame.copy()  # BGR, as decoded
    labels = []  # written in a strip above the picture: stacked dancers' labels would cover each other
    for det in detections:
        x, y, w, h = (int(round(v)) for v in det.box)
        cv2.rectangle(img, (x, y), (x + w, y + h), (255, 255, 255), 1)
    for i in range(gt.shape[0]):
        colour = COLOURS[i % len(COLOURS)]
        if np.isfinite(gt[i]).all():
            x, y, w, h = (int(round(v)) for v in gt[i])
            cv2.rectangle(img, (x, y), (x + w, y + h), colour, 1)
        if np.isfinite(tracked[i]).all():
            x, y, w, h = (int(round(v)) for v in tracked[i])
            cv2.rectangle(img, (x, y), (x + w, y + h), colour, 3)
            iou = box_iou(gt[i], tracked[i]) if np.isfinite(gt[i]).all() else 0.0
            labels.append((f"dancer {i}: IoU {iou:.2f}", colour))
    boxes = np.concatenate([gt[np.isfinite(gt).all(axis=1)], tracked[np.isfinite(tracked).all(axis=1)]])
    x0 = max(0, int(boxes[:, 0].min()) - crop_margin)
    y0 = max(0, int(boxes[:, 1].min()) - crop_margin)
    x1 = min(img.shape[1], int((boxes[:, 0] + boxes[:, 2]).max()) + crop_margin)
    y1 = min(img.shape[0], int((boxes[:, 1] + boxes[:, 3]).max()) + crop_margin)
    crop = img[y0:y1, x0:x1]
    picture = cv2.resize(crop, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST)
    picture = cv2.copyMakeBorder(picture, 30, 0, 0, 0, cv2.BORDER_CONSTANT, value=(40, 40, 40))
    x = 8
    for text, colour in labels:
        cv2.putText(picture, text, (x, 21), cv2.FONT_HERSHEY_SIMPLEX, 0.5, colour, 2)
        x += cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 2)[0][0] + 18
    return picture


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs/img"))
    args = parser.parse_args(argv)

    import cv2

    from hdvr.io.atomic import atomic_path
    from hdvr.pose2d.models import default_pose_model
    from hdvr.pose2d.onnx_pose import OnnxPoseDetector
    from hdvr.synth.groundtruth import ClipSpec, make_clip
    from hdvr.tracking.pipeline import DancerStart, track_video
    from hdvr.video import VideoReader

    detector = OnnxPoseDetector(default_pose_model(), input_size=480, threads=2, score_threshold=0.3)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for seed, index, genre, n, frame_index, what in CASES:
            spec = ClipSpec(index, seed, genre, n, 4.0)
            make_clip(tmp, spec, render=True)
            clip = tmp / spec.name
            with np.load(clip / "gt.npz") as g:
                gt = np.transpose(g["boxes"], (1, 0, 2)).astype(float)
            first = [int(np.flatnonzero(np.isfinite(gt[:, i]).all(axis=1))[0]) for i in range(n)]
            order = sorted(range(n), key=lambda i: first[i])
            starts = [DancerStart(first[i], tuple(gt[first[i], i])) for i in order]
            run = track_video(clip / "video.mp4", tmp / "out", detector=detector, starts=starts, detect_every=3,
                              overlay=False, write=False)
            tracked = run.boxes[:, np.argsort(order)]
            detector_frame = frame_index - frame_index % 3  # the detector frame the tracker used last
            frames = {k: f for k, f in enumerate(VideoReader(clip / "video.mp4")) if k in (frame_index, detector_frame)}
            frame, detections = frames[frame_index], detector.detect(frames[detector_frame], detector_frame)
            picture = draw_case(frame, gt[frame_index], tracked[frame_index], detections)
            path = args.out / f"tracking_limit_s{seed}_{genre}_{frame_index:03d}.jpg"
            path.parent.mkdir(parents=True, exist_ok=True)
            ok, data = cv2.imencode(".jpg", picture, [cv2.IMWRITE_JPEG_QUALITY, 88])
            if not ok:
                raise SystemExit(f"make_tracking_docs: error: cannot encode {path.name} as JPEG")
            with atomic_path(path) as tmp_path:
                tmp_path.write_bytes(data.tobytes())
            print(f"wrote {path}: {what}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
