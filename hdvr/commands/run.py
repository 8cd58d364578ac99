"""``hdvr run VIDEO --out DIR``: the whole hierarchy on one video (tracks, 2D poses, 3D fit, BVH, movements,
genre)."""

from __future__ import annotations

from hdvr.commands.track import add_dancer_arguments, dancer_arguments


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "run", help="video -> tracks -> 2D poses -> 3D fit -> movements -> genre, for every dancer",
        description="Track every dancer, estimate 2D poses, fit the MuJoCo digital dancer in 3D, export BVH, "
                    "label the movements of 16 body parts and recognise the dance genre (nine genres; the shipped "
                    "model is trained on synthetic choreographies only, see docs/recognition.md). See "
                    "hdvr/pipeline.py for the files written.")
    p.add_argument("video")
    p.add_argument("--out", required=True, help="output folder")
    add_dancer_arguments(p)  # as hdvr track's: start boxes, --dancers N, corrections
    p.add_argument("--detector", default="yolo11n", help="yolo11n (default), onnx, openpose")
    p.add_argument("--pose-model", help="ONNX pose model for --detector onnx")
    p.add_argument("--openpose-json", help="precomputed OpenPose JSON folder for --detector openpose")
    p.add_argument("--detector-size", type=int, default=480)
    p.add_argument("--detect-every", type=int, default=3)
    p.add_argument("--focal", type=float, default=None, help="focal length in pixels if known (else estimated)")
    p.add_argument("--render", action="store_true", help="also render each fitted dancer to dancer_<i>.3d.mp4")
    p.add_argument("--pose-prior", default=None, metavar="NAME|NPZ",
                   help="the 3D fit's pose prior: 'all' (default: the nine genres), 'partner' (rumba, swing, "
                        "tango, waltz: for salsa and ballroom) or an NPZ built for the style "
                        "(scripts/build_pose_prior.py --genres ...)")
    genre = p.add_mutually_exclusive_group()
    genre.add_argument("--recogniser", metavar="PATH", help="genre recogniser checkpoint (default: the one shipped "
                                                            "in hdvr/data/recognisers.pt)")
    genre.add_argument("--no-genre", action="store_true", help="skip genre recognition")
    p.set_defaults(func=run)


def run(args) -> int:
    from hdvr.fitting.presets import FitSettings
    from hdvr.pipeline import analyse_video, make_detector

    detector = make_detector(args.detector, args.detector_size, args.pose_model, args.openpose_json)
    overrides = {"focal": args.focal} if args.focal else {}
    if args.pose_prior:
        from hdvr.commands.fit3d import prior_argument

        overrides["pose_prior_path"] = prior_argument(args.pose_prior)  # checked here, before the tracking
    settings = FitSettings(**overrides)
    result = analyse_video(args.video, args.out, detector=detector, **dancer_arguments(args),
                           detect_every=args.detect_every, fit_settings=settings,
                           render_size=(320, 240) if args.render else None,
                           recogniser=None if args.no_genre else (args.recogniser or "default"))
    print_summary(result)
    return 0


def print_summary(result) -> None:
    print(f"{len(result.dancers)} dancers, {result.frames} frames at {result.fps:g} fps -> {result.out_dir}")
    for d in result.dancers:
        if d.skipped:
            print(f"  dancer {d.index}: 3D skipped ({d.skipped})")
            continue
        moves = ", ".join(f"{label} {100 * share:.0f}%" for label, share in d.active_movements) or \
            "every part mostly keeping still"
        print(f"  dancer {d.index}: pose on {100 * d.pose_coverage:.0f}% of frames, fit "
              f"{d.fit['frames_per_second']:.0f} frames/s, reprojection {d.fit['median_reprojection_px']:.1f} px; "
              f"most frequent movements: {moves}")
        print(f"    {d.result3d.name}, {d.bvh.name}, {d.labels.name}, {d.score.name}"
              + (f", {d.render.name}" if d.render else ""))
        if d.genre:
            print(f"    genre {format_genre(d.genre)}")
    g = result.genre
    if g.get("available"):
        print(f"genre of the video: {format_genre(g)} (mean of {g['dancers']} dancers; experimental: trained on "
              "synthetic choreographies only, right for about 1 dancer in 4 through the 3D fit of held-out synthetic "
              "clips, untested on real video; docs/recognition.md)")
    else:
        print(f"genre: unavailable ({g.get('reason', 'unknown reason')})")


def format_genre(genre: dict, top: int = 3) -> str:
    """``hip_hop 62% (tap 15%, swing 9%)`` from a ``{"top", "probabilities"}`` dict."""
    ranked = sorted(genre["probabilities"].items(), key=lambda kv: -kv[1])
    rest = ", ".join(f"{g} {100 * p:.0f}%" for g, p in ranked[1:top])
    return f"{ranked[0][0]} {100 * ranked[0][1]:.0f}%" + (f" ({rest})" if rest else "")
