"""``hdvr convert``: between HDVR's file contracts and other tools' formats.

- ``hdvr convert openpose DIR --fps 30 --size 1920x1080 --out kp.npz``: OpenPose JSON folder -> 2D keypoint NPZ
- ``hdvr convert coco FILE.json --fps 30 --out kp.npz``: COCO keypoint JSON -> 2D keypoint NPZ
- ``hdvr convert bvh RESULT.npz --out dance.bvh``: a 3D result (fitted dancer) -> BVH for Blender and other tools
"""

from __future__ import annotations

from pathlib import Path


def _size(text: str) -> tuple[int, int]:
    from hdvr.errors import HDVRError

    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise HDVRError(f"image size must look like 1920x1080, got {text!r}") from None
    return w, h


def register(subparsers) -> None:
    parser = subparsers.add_parser("convert", help="convert OpenPose/COCO keypoints to NPZ, 3D results to BVH")
    sub = parser.add_subparsers(dest="convert_command", metavar="FORMAT")

    op = sub.add_parser("openpose", help="OpenPose --write_json folder -> 2D keypoint NPZ (BODY_25)")
    op.add_argument("folder")
    op.add_argument("--fps", type=float, required=True, help="frames per second of the source video")
    op.add_argument("--size", required=True, help="image size WxH in pixels")
    op.add_argument("--person", type=int, default=0, help="index in each file's 'people' list")
    op.add_argument("--out", required=True)
    op.set_defaults(func=run_openpose)

    coco = sub.add_parser("coco", help="COCO keypoint JSON -> 2D keypoint NPZ (BODY_25)")
    coco.add_argument("file")
    coco.add_argument("--fps", type=float, required=True)
    coco.add_argument("--track-id", type=int, default=None, help="keep annotations with this track_id")
    coco.add_argument("--out", required=True)
    coco.set_defaults(func=run_coco)

    bvh = sub.add_parser("bvh", help="3D result NPZ (fitted dancer) -> BVH (Y up, centimetres)")
    bvh.add_argument("result")
    bvh.add_argument("--out", required=True)
    bvh.add_argument("--fps", type=float, default=None, help="override the result's frame rate")
    bvh.set_defaults(func=run_bvh)
    parser.set_defaults(func=lambda args: parser.print_help())


def run_openpose(args) -> int:
    from hdvr.io.keypoints2d import read_openpose_folder, save_keypoints2d

    kp = read_openpose_folder(args.folder, args.fps, _size(args.size), args.person)
    save_keypoints2d(args.out, kp)
    print(f"wrote {args.out}: {kp.num_frames} frames, {100 * kp.visible_fraction():.0f}% keypoints visible")
    return 0


def run_coco(args) -> int:
    from hdvr.io.keypoints2d import read_coco_json, save_keypoints2d

    kp = read_coco_json(args.file, args.fps, args.track_id)
    save_keypoints2d(args.out, kp)
    print(f"wrote {args.out}: {kp.num_frames} frames, {100 * kp.visible_fraction():.0f}% keypoints visible")
    return 0


def run_bvh(args) -> int:
    from hdvr.io.bvh import write_dancer_bvh
    from hdvr.io.result3d import load_result3d
    from hdvr.skeleton import Skeleton

    result = load_result3d(args.result)
    sk = Skeleton()
    sk.set_bone_lengths(result.bone_lengths)
    fps = args.fps or result.fps
    write_dancer_bvh(args.out, sk, result.qpos, fps)
    print(f"wrote {Path(args.out)}: {result.num_frames} frames at {fps:g} fps (Y up, centimetres)")
    return 0
