"""``hdvr ablate CLIP.npz... --out-dir DIR``: fit clips under each kinematic-constraint setting, write a table."""

from __future__ import annotations

import argparse
from pathlib import Path

from hdvr.errors import HDVRError


def register(subparsers) -> None:
    from hdvr.commands.fit3d import add_fit_arguments

    p = subparsers.add_parser("ablate", help="3D fit ablations: each constraint on/off, table of metrics",
                              description="Fit 2D keypoint clips with each constraint switched off in turn and "
                                          "write ablation.md and ablation.json (MPJPE, P-MPJPE when ground truth "
                                          "is given, plausibility figures, frames/s).")
    p.add_argument("clips", nargs="+", help="2D keypoint NPZ files")
    p.add_argument("--ground-truth", nargs="*", default=None,
                   help="per clip, an NPZ with 'keypoints3d' (T, 25, 3) metres in the camera frame (BODY_25)")
    p.add_argument("--settings", nargs="*", default=None,
                   help="ablations to run (default: all but paper: full no_joint_limits no_bone_prior no_temporal "
                        "no_pose_prior no_upright no_limb_depth physics)")
    p.add_argument("--out-dir", required=True, help="folder for ablation.md and ablation.json")
    p.add_argument("--processes", type=int, default=1,
                   help="clips fitted at once (default 1; each fit then uses one worker)")
    add_fit_arguments(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from hdvr.commands.fit3d import settings_from_args
    from hdvr.fitting.ablation import ABLATIONS, markdown_table, run_ablation, write_tables
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.io.npz import open_npz

    if args.ground_truth is not None and len(args.ground_truth) not in (0, len(args.clips)):
        raise HDVRError(f"--ground-truth needs one file per clip ({len(args.clips)}), got {len(args.ground_truth)}")
    names = args.settings or [n for n in ABLATIONS if n != "paper"]
    for n in names:
        if n not in ABLATIONS:
            raise HDVRError(f"unknown ablation {n!r}; choose from {', '.join(ABLATIONS)}")
    clips = []
    for i, path in enumerate(args.clips):
        if not Path(path).is_file():
            raise HDVRError(f"2D keypoint file not found: {path}")
        kp = load_keypoints2d(path)
        gt = None
        if args.ground_truth:
            gt = open_npz(args.ground_truth[i], ("keypoints3d",), "ground-truth 3D")["keypoints3d"]
            if gt.shape != (kp.num_frames, 25, 3):
                raise HDVRError(f"{args.ground_truth[i]}: keypoints3d must be ({kp.num_frames}, 25, 3), "
                                f"got {gt.shape}")
            gt = np.asarray(gt, dtype=np.float64)
        clips.append((Path(path).stem, kp, gt))
    rows = run_ablation(clips, names, settings_from_args(args), processes=max(1, args.processes))
    md, js = write_tables(rows, args.out_dir)
    print(markdown_table(rows), end="")
    print(f"wrote {md} and {js}")
    return 0
