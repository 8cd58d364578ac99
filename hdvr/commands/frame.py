"""``hdvr frame``: one frame of a video as a picture with a pixel grid (and the tracked boxes), to read the box or
point of a correction (``hdvr track --correct``) off it."""

from __future__ import annotations

import argparse
from pathlib import Path


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "frame", help="write frames as pictures with a pixel grid and the tracked boxes (for --correct)",
        description="Write frame FRAME (0-based, as the overlay video and --correct number frames; several "
                    "separated by commas, into a folder) of VIDEO as a picture with a pixel grid, and with --tracks "
                    "the boxes, ids and skeletons hdvr track found there; prints each box as a ready --correct "
                    "option. Read a dancer's box or a point on it off "
                    "the picture and give it to hdvr track --correct DANCER@FRAME:x,y,w,h (or :x,y).")
    p.add_argument("video", help="the video (as given to hdvr track)")
    p.add_argument("frame", help="0-based frame number, or several separated by commas (one pass over the video)")
    p.add_argument("--out", required=True, help="picture to write (.png or .jpg); for several frames a folder, "
                                                "which gets frame_<FRAME>.png each")
    p.add_argument("--tracks", help="output folder of hdvr track, or its tracks.json (the dancer_<i>.npz beside it "
                                    "give the skeletons)")
    p.add_argument("--grid", type=int, default=100, help="grid spacing in pixels (default 100; 0: no grid)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from hdvr.errors import HDVRError
    from hdvr.io import PICTURE_SUFFIXES
    from hdvr.tracking.boxes import read_tracks_json
    from hdvr.video import read_frames

    try:
        frames = sorted({int(v) for v in args.frame.split(",") if v.strip()})
    except ValueError:
        raise HDVRError(f"cannot read frame {args.frame!r}: expected a number or numbers separated by commas "
                        f"(e.g. 120 or 120,240)") from None
    if not frames:
        raise HDVRError("give a frame number")
    out = Path(args.out)
    image_suffix = out.suffix.lower() in PICTURE_SUFFIXES
    if len(frames) > 1 and image_suffix:
        raise HDVRError(f"--out {out}: for {len(frames)} frames give a folder (it gets frame_<FRAME>.png each)")
    if len(frames) == 1 and out.suffix and not image_suffix:
        raise HDVRError(f"--out {out}: give a .png or .jpg file name (or a folder)")
    if args.grid and args.grid < 10:
        raise HDVRError(f"--grid {args.grid}: give a spacing of at least 10 px, or 0 for none")
    tracks = read_tracks_json(args.tracks) if args.tracks else None
    if tracks is not None and frames[-1] >= len(tracks.boxes):
        raise HDVRError(f"frame {frames[-1]} was not tracked ({args.tracks} covers frames 0-"
                        f"{len(tracks.boxes) - 1})")
    keypoints = _keypoint_files(args.tracks, tracks)
    for index, image in read_frames(args.video, frames, show_progress=True):
        path = out if image_suffix else out / f"frame_{index:06d}.png"
        lines = _draw_and_write(image, index, path, args, tracks, keypoints)
        print(f"wrote {path} (frame {index}, {image.shape[1]}x{image.shape[0]} px)")
        if lines:
            print("boxes as tracked (x,y,w,h px, top-left corner); where one is wrong, give the right one:")
            print("\n".join(lines))
    return 0


def _keypoint_files(tracks_arg, tracks) -> list:
    """Each tracked dancer's (T, 25, 3) keypoints from the dancer_<i>.npz beside ``tracks_arg`` (None where
    missing or not BODY_25)."""
    from hdvr.io.keypoints2d import load_keypoints2d

    if tracks is None:
        return []
    folder = Path(tracks_arg) if Path(tracks_arg).is_dir() else Path(tracks_arg).parent
    out = []
    for i in range(tracks.boxes.shape[1]):
        path = folder / f"dancer_{i}.npz"
        kp = load_keypoints2d(path, require_visible=False).keypoints if path.is_file() else None
        out.append(kp if kp is not None and kp.shape[1] == 25 else None)
    return out


def _draw_and_write(image, index: int, path: Path, args, tracks, keypoints: list) -> list[str]:
    """Draw the grid, the frame number and (with ``tracks``) the boxes, ids and skeletons of frame ``index`` on
    ``image``, write it to ``path`` atomically, and return the lines naming each box as a --correct option."""
    import cv2
    import numpy as np

    from hdvr.errors import HDVRError
    from hdvr.io.atomic import atomic_path
    from hdvr.pose2d.draw import draw_overlay, draw_pixel_grid

    if tracks is not None and (image.shape[1], image.shape[0]) != tracks.image_size:
        raise HDVRError(f"{args.tracks} tracks a {tracks.image_size[0]}x{tracks.image_size[1]} video, but "
                        f"{args.video} is {image.shape[1]}x{image.shape[0]}: not the same video")
    if args.grid:
        draw_pixel_grid(image, args.grid)
    lines = []
    if tracks is None:
        draw_overlay(image, [], [], frame_index=index)
    else:
        boxes, status = tracks.boxes[index], tracks.status[index]
        poses = [None if kp is None or len(kp) <= index else kp[index] for kp in keypoints]
        draw_overlay(image, boxes, status, poses, frame_index=index)
        for i, (box, st) in enumerate(zip(boxes, status)):
            if np.isfinite(box).all():
                x, y, w, h = (int(round(v)) for v in box)
                lines.append(f"  dancer {i} ({st}): --correct {i}@{index}:{x},{y},{w},{h}")
            else:
                lines.append(f"  dancer {i} ({st}): no box in this frame")
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, suffix=path.suffix) as tmp:
        if not cv2.imwrite(str(tmp), image):
            raise HDVRError(f"cannot write picture {path}")
    return lines
