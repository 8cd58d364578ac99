"""``hdvr demo``: the main job on an embedded default, no arguments needed, no ../shared data.

1. The digital dancer sweeps every joint through its range (``dancer_joint_ranges.mp4``).
2. A synthetic two-dancer hip-hop clip is generated and rendered (``synthetic/``, with full ground truth).
3. The whole hierarchy runs on that video as on any other (``analysis/``): tracks, 2D poses, 3D fit of the
   MuJoCo dancer, BVH, movement labels and scores, a render of each fitted dancer, the genre.
4. The results are scored against the clip's ground truth (IDF1 of the tracks, P-MPJPE of the 3D fit, the genre).
"""

from __future__ import annotations

import json
from pathlib import Path

#: The embedded default: clip 1 of seed 5 (hip hop, two dancers, 4 s at 30 fps, 640x480).
DEMO_CLIP = {"index": 1, "seed": 5, "genres": ("hip_hop",), "dancers": (2, 2), "seconds": 4.0}


def register(subparsers) -> None:
    parser = subparsers.add_parser("demo", help="run the pipeline on a built-in example (no arguments needed)")
    parser.add_argument("--out", default="hdvr-demo", help="output folder (default: ./hdvr-demo)")
    parser.add_argument("--size", default="480x360", help="joint-range video size WxH in pixels (default 480x360)")
    parser.add_argument("--seconds-per-joint", type=float, default=0.5, help="sweep duration per joint group (s)")
    parser.add_argument("--quick", action="store_true", help="only the joint-range video (step 1)")
    parser.set_defaults(func=run)


def joint_range_video(out: Path, width: int, height: int, seconds_per_joint: float) -> Path:
    import cv2

    from hdvr.progress import progress
    from hdvr.render import DancerRenderer, joint_sweep
    from hdvr.skeleton import Skeleton
    from hdvr.video import VideoWriter

    fps = 30.0
    sk = Skeleton()
    qpos, labels = joint_sweep(sk, seconds_per_joint, fps)
    renderer = DancerRenderer(sk, width, height, shadows=False)
    renderer.set_camera(distance=2.7, azimuth=150.0, elevation=-10.0, lookat=(0.0, 0.0, 0.72))
    video = out / "dancer_joint_ranges.mp4"
    try:
        with VideoWriter(video, fps, (width, height)) as writer:
            for q, label in progress(zip(qpos, labels), total=len(qpos), desc="rendering joint ranges"):
                frame = cv2.cvtColor(renderer.render(q), cv2.COLOR_RGB2BGR)
                cv2.putText(frame, label, (10, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (20, 20, 20), 2, cv2.LINE_AA)
                writer.write(frame)
    finally:
        renderer.close()
    print(f"1. digital dancer: 34 hinges + free root swept through every joint range -> {video}")
    return video


def score_against_ground_truth(clip_dir: Path, result) -> dict:
    """IDF1/MOTA of the tracks and, per tracked dancer, 3D errors of the fit against the synthetic truth."""
    import numpy as np

    from hdvr.io.result3d import load_result3d
    from hdvr.metrics import evaluate
    from hdvr.tracking.boxes import read_mot
    from hdvr.tracking.evaluation import iou_matrix, evaluate_tracking

    gt = np.load(clip_dir / "gt.npz")
    gt_boxes = np.transpose(gt["boxes"], (1, 0, 2))  # (T, M, 4)
    tracked = read_mot(result.out_dir / "tracks.mot.txt", gt_boxes.shape[0])
    scores = {"tracking": evaluate_tracking(gt_boxes, tracked).as_dict(), "dancers": []}
    for d in result.dancers:
        if d.result3d is None:
            continue
        overlap = [np.nanmean([iou_matrix(g[None, m], t[None, d.index])[0, 0]
                               for g, t in zip(gt_boxes, tracked)]) for m in range(gt_boxes.shape[1])]
        match = int(np.nanargmax(overlap))
        fit = load_result3d(d.result3d)
        metrics = evaluate(fit.keypoints3d, gt["keypoints3d_camera"][match])
        scores["dancers"].append({"dancer": d.index, "ground_truth_dancer": match,
                                  **{k: round(float(v), 1) for k, v in metrics.items()}})
    return scores


def run(args) -> int:
    from hdvr.errors import HDVRError

    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        raise HDVRError(f"--size must look like 480x360, got {args.size!r}") from None
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    joint_range_video(out, width, height, args.seconds_per_joint)
    if args.quick:
        return 0

    from hdvr.commands.run import print_summary
    from hdvr.io.atomic import write_text_atomic
    from hdvr.pipeline import analyse_video, make_detector
    from hdvr.synth.groundtruth import clip_spec, make_clip

    spec = clip_spec(DEMO_CLIP["index"], DEMO_CLIP["seed"], DEMO_CLIP["genres"], DEMO_CLIP["dancers"],
                     DEMO_CLIP["seconds"])
    meta = make_clip(out / "synthetic", spec, render=True)
    clip_dir = out / "synthetic" / spec.name
    print(f"2. synthetic clip: {meta['genre']}, {meta['n_dancers']} dancers, {meta['frames']} frames "
          f"-> {clip_dir / 'video.mp4'} (+ ground truth)")
    print("3. hdvr run on that video: tracking, 2D pose, 3D fit, BVH, movements, genre ...")
    result = analyse_video(clip_dir / "video.mp4", out / "analysis", num_dancers=meta["n_dancers"],
                           detector=make_detector("yolo11n"), render_size=(320, 240))
    print_summary(result)
    scores = score_against_ground_truth(clip_dir, result)
    scores["genre"] = {"truth": meta["genre"], "predicted": result.genre.get("top"),
                       "available": bool(result.genre.get("available"))}
    write_text_atomic(out / "demo_scores.json", json.dumps(scores, indent=1))
    t = scores["tracking"]
    print(f"4. against the ground truth: tracks IDF1 {t['IDF1']:.2f}, MOTA {t['MOTA']:.2f}, "
          f"{t['IDSW']} identity switches")
    for d in scores["dancers"]:
        print(f"   dancer {d['dancer']} 3D fit: P-MPJPE {d['p_mpjpe_mm']:.0f} mm, MPJPE {d['mpjpe_mm']:.0f} mm "
              "(no 3D ground truth used)")
    if scores["genre"]["available"]:
        print(f"   genre: {scores['genre']['predicted']} recognised, the clip is {meta['genre']}")
    print(f"see {out / 'analysis'} (overlay.mp4, timeline.png, dancer_*.3d.mp4, *.bvh, *.score.png) and "
          f"{out / 'demo_scores.json'}")
    return 0
