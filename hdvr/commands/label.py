"""``hdvr label``: movement labels of a 3D motion (BVH mocap, 3D result NPZ or synthetic gt.npz) + its score."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError


def load_motion(path: str | Path, dancer: int = 0, fps: float = 30.0) -> tuple[np.ndarray, float, tuple]:
    """BODY_25 world keypoints (T, 25, 3) metres, fps and the world's up vector from a .bvh (CMU skeleton,
    resampled to ``fps``), a 3D result NPZ (``hdvr fit3d``: world keypoints from its qpos and bone lengths) or a
    synthetic clip's gt.npz (``keypoints3d_world`` of dancer ``dancer``)."""
    p = Path(path)
    if not p.is_file():
        raise HDVRError(f"motion file not found: {p}")
    if p.suffix.lower() == ".bvh":
        from hdvr.io.bvh import load_mocap_body25

        kp, f = load_mocap_body25(p, fps=fps)
        return kp, f, (0.0, 0.0, 1.0)
    if p.suffix.lower() != ".npz":
        raise HDVRError(f"unsupported motion file {p}: expected .bvh or .npz (3D result or synthetic gt.npz)")
    from hdvr.io.npz import open_npz

    data = open_npz(p, (), "motion")
    if "keypoints3d_world" in data.files:
        kp = data["keypoints3d_world"]
        if not 0 <= dancer < kp.shape[0]:
            raise HDVRError(f"{p} has {kp.shape[0]} dancers; --dancer {dancer} does not exist")
        return kp[dancer].astype(np.float64), float(data["fps"]), (0.0, 0.0, 1.0)
    from hdvr.io.result3d import load_result3d
    from hdvr.skeleton import Skeleton

    r = load_result3d(p)
    sk = Skeleton()
    sk.set_bone_lengths(r.bone_lengths)
    return sk.keypoints(r.qpos), float(r.fps), (0.0, 0.0, 1.0)


def register(subparsers) -> None:
    p = subparsers.add_parser("label", help="label body-part movements of a 3D motion and draw its score",
                              description="Label the movements of 16 body parts (154 labels) of a 3D motion: "
                                          "CMU-skeleton BVH, a 3D result NPZ or a synthetic clip's gt.npz. Writes "
                                          "the segments as JSON and a Labanotation-like score picture.")
    p.add_argument("motion", help=".bvh, 3D result .npz or synthetic gt.npz")
    p.add_argument("--out", required=True, help="labels JSON to write (segments per body part)")
    p.add_argument("--score", help="score picture to write (.png or .jpg)")
    p.add_argument("--dancer", type=int, default=0, help="dancer index in a synthetic gt.npz")
    p.add_argument("--fps", type=float, default=30.0, help="frame rate BVH files are resampled to")
    p.add_argument("--start", type=float, default=0.0, help="score start (s)")
    p.add_argument("--end", type=float, default=None, help="score end (s), default: the whole motion")
    p.add_argument("--smoothing", type=float, default=None,
                   help="temporal smoothing of the keypoints in seconds (default 0.1 for mocap-grade input; 0.2-0.3 "
                        "for noisy fitted 3D, which hides fast shakes)")
    p.set_defaults(func=_main)


def _main(args) -> int:
    from hdvr.io.atomic import write_text_atomic
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.movements.score import draw_score

    kp, fps, up = load_motion(args.motion, args.dancer, args.fps)
    if args.smoothing is not None and not 0 <= args.smoothing <= 2:
        raise HDVRError(f"--smoothing must be between 0 and 2 seconds, got {args.smoothing}")
    labels = MovementLabeller(smoothing_s=args.smoothing).label(kp, fps, up)
    doc = {"source": str(args.motion), "fps": fps, "frames": int(kp.shape[0]),
           "parts": list(labels.taxonomy.part_names), "segments": labels.segments()}
    write_text_atomic(args.out, json.dumps(doc, indent=1))
    if args.score:
        draw_score(labels, args.score, title=f"{Path(args.motion).name}", start_s=args.start, end_s=args.end)
    print(f"{len(doc['segments'])} segments over {kp.shape[0]} frames -> {args.out}"
          + (f", score -> {args.score}" if args.score else ""))
    return 0
