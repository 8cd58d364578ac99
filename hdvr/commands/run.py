"""``hdvr run VIDEO --out DIR``: the whole hierarchy on one video (tracks, 2D poses, 3D fit, BVH, movements)."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "run", help="video -> tracks -> 2D poses -> 3D fit -> movements, for every dancer",
        description="Track every dancer, estimate 2D poses, fit the MuJoCo digital dancer in 3D, export BVH, and "
                    "label the movements of 16 body parts. See hdvr/pipeline.py for the files written.")
    p.add_argument("video")
    p.add_argument("--out", required=True, help="output folder")
    init = p.add_mutually_exclusive_group(required=True)
    init.add_argument("--boxes", help="dancers' boxes in the first frame: 'x,y,w,h;x,y,w,h' (pixels)")
    init.add_argument("--dancers", type=int, help="find this many dancers automatically")
    p.add_argument("--detector", default="yolo11n", help="yolo11n (default), onnx, openpose")
    p.add_argument("--pose-model", help="ONNX pose model for --detector onnx")
    p.add_argument("--openpose-json", help="precomputed OpenPose JSON folder for --detector openpose")
    p.add_argument("--detector-size", type=int, default=480)
    p.add_argument("--detect-every", type=int, default=3)
    p.add_argument("--focal", type=float, default=None, help="focal length in pixels if known (else estimated)")
    p.add_argument("--render", action="store_true", help="also render each fitted dancer to dancer_<i>.3d.mp4")
    p.set_defaults(func=run)


def run(args) -> int:
    from hdvr.fitting.presets import FitSettings
    from hdvr.pipeline import analyse_video, make_detector
    from hdvr.tracking.boxes import parse_boxes

    detector = make_detector(args.detector, args.detector_size, args.pose_model, args.openpose_json)
    settings = FitSettings(focal=args.focal) if args.focal else FitSettings()
    result = analyse_video(args.video, args.out, num_dancers=args.dancers,
                           boxes=parse_boxes(args.boxes) if args.boxes else None, detector=detector,
                           detect_every=args.detect_every, fit_settings=settings,
                           render_size=(320, 240) if args.render else None)
    print_summary(result)
    return 0


def print_summary(result) -> None:
    print(f"{len(result.dancers)} dancers, {result.frames} frames at {result.fps:g} fps -> {result.out_dir}")
    for d in result.dancers:
        if d.skipped:
            print(f"  dancer {d.index}: 3D skipped ({d.skipped})")
            continue
        moves = ", ".join(f"{part} {label}" for part, label in list(d.movements.items())[:4])
        print(f"  dancer {d.index}: pose on {100 * d.pose_coverage:.0f}% of frames, fit "
              f"{d.fit['frames_per_second']:.0f} frames/s, reprojection {d.fit['median_reprojection_px']:.1f} px; "
              f"{moves} ...")
        print(f"    {d.result3d.name}, {d.bvh.name}, {d.labels.name}, {d.score.name}"
              + (f", {d.render.name}" if d.render else ""))
