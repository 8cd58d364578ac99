"""``hdvr frame``: one frame of a video as a picture with a pixel grid (and the tracked boxes), to read the box or
point of a correction (``hdvr track --correct``) off it."""

from __future__ import annotations

import argparse


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "frame", help="write one frame as a picture with a pixel grid and the tracked boxes (for --correct)",
        description="Write frame FRAME (0-based, as the overlay video and --correct number frames) of VIDEO as a "
                    "picture with a pixel grid, and with --tracks the boxes, ids and skeletons hdvr track found "
                    "there; prints each box as a ready --correct option. Read a dancer's box or a point on it off "
                    "the picture and give it to hdvr track --correct DANCER@FRAME:x,y,w,h (or :x,y).")
    p.add_argument("video", help="the video (as given to hdvr track)")
    p.add_argument("frame", type=int, help="0-based frame number")
    p.add_argument("--out", required=True, help="picture to write (.png or .jpg)")
    p.add_argument("--tracks", help="output folder of hdvr track, or its tracks.json (the dancer_<i>.npz beside it "
                                    "give the skeletons)")
    p.add_argument("--grid", type=int, default=100, help="grid spacing in pixels (default 100; 0: no grid)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    import cv2
    import numpy as np

    from hdvr.errors import HDVRError
    from hdvr.io.atomic import atomic_path
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.pose2d.draw import draw_overlay, draw_pixel_grid
    from hdvr.tracking.boxes import read_tracks_json
    from hdvr.video import read_frame

    out = Path(args.out)
    if out.suffix.lower() not in (".png", ".jpg", ".jpeg"):
        raise HDVRError(f"--out {out}: give a .png or .jpg file name")
    if args.grid and args.grid < 10:
        raise HDVRError(f"--grid {args.grid}: give a spacing of at least 10 px, or 0 for none")
    tracks = read_tracks_json(args.tracks) if args.tracks else None
    if tracks is not None and args.frame >= len(tracks.boxes):
        raise HDVRError(f"frame {args.frame} was not tracked ({args.tracks} covers frames 0-{len(tracks.boxes) - 1})")
    image = read_frame(args.video, args.frame, show_progress=True)
    if tracks is not None and (image.shape[1], image.shape[0]) != tracks.image_size:
        raise HDVRError(f"{args.tracks} tracks a {tracks.image_size[0]}x{tracks.image_size[1]} video, but "
                        f"{args.video} is {image.shape[1]}x{image.shape[0]}: not the same video")
    if args.grid:
        draw_pixel_grid(image, args.grid)
    lines = []
    if tracks is None:
        draw_overlay(image, [], [], frame_index=args.frame)
    else:
        folder = Path(args.tracks) if Path(args.tracks).is_dir() else Path(args.tracks).parent
        boxes, status = tracks.boxes[args.frame], tracks.status[args.frame]
        keypoints = []
        for i in range(len(boxes)):
            path = folder / f"dancer_{i}.npz"
            kp = load_keypoints2d(path, require_visible=False).keypoints if path.is_file() else None
            keypoints.append(kp[args.frame] if kp is not None and len(kp) > args.frame and kp.shape[1] == 25
                             else None)
        draw_overlay(image, boxes, status, keypoints, frame_index=args.frame)
        for i, (box, st) in enumerate(zip(boxes, status)):
            if np.isfinite(box).all():
                x, y, w, h = (int(round(v)) for v in box)
                lines.append(f"  dancer {i} ({st}): --correct {i}@{args.frame}:{x},{y},{w},{h}")
            else:
                lines.append(f"  dancer {i} ({st}): no box in this frame")
    with atomic_path(out, suffix=out.suffix) as tmp:
        if not cv2.imwrite(str(tmp), image):
            raise HDVRError(f"cannot write picture {out}")
    print(f"wrote {out} (frame {args.frame}, {image.shape[1]}x{image.shape[0]} px)")
    if lines:
        print("boxes as tracked (x,y,w,h px, top-left corner); where one is wrong, give the right one:")
        print("\n".join(lines))
    return 0
