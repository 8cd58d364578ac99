"""``hdvr fit3d KEYPOINTS.npz --out RESULT.npz``: fit the MuJoCo dancer to a dancer's 2D keypoints."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from hdvr.errors import HDVRError


def add_fit_arguments(p: argparse.ArgumentParser) -> None:
    """Options shared by ``fit3d`` and ``ablate``."""
    p.add_argument("--paper", action="store_true",
                   help="Algorithm 3* as published (window per frame, random seeds, omega per window); "
                        "the other options override its values")
    p.add_argument("--delta", type=int, default=None, help="window half-width Delta (windows of 2 Delta + 1 frames)")
    p.add_argument("--seeds", type=int, default=None, help="K seeds per window (default 2)")
    p.add_argument("--stride", type=int, default=None, help="frames between windows (default 2 Delta + 1; paper 1)")
    p.add_argument("--focal", type=float, default=None, help="focal length in pixels (default: estimated)")
    p.add_argument("--principal-point", type=float, nargs=2, default=None, metavar=("CX", "CY"),
                   help="principal point in pixels (default: image centre)")
    p.add_argument("--height", type=float, default=None, help="dancer stature in metres (default 1.70)")
    p.add_argument("--physics", action="store_true", help="enforce floor penetration and foot skating terms")
    p.add_argument("--no-joint-limits", action="store_true", help="ablation: no hinge bounds")
    p.add_argument("--no-bone-prior", action="store_true",
                   help="ablation: no per-dancer bone lengths (each window draws its own from mean +- std)")
    p.add_argument("--no-temporal", action="store_true", help="ablation: no temporal smoothness")
    p.add_argument("--smooth-2d", choices=("auto", "on", "off"), default=None,
                   help="temporal smoothing of the 2D tracks before the fit (default auto: when their estimated "
                        "jitter exceeds 2.5 px)")
    p.add_argument("--no-pose-prior", action="store_true", help="ablation: no learned hinge-angle prior")
    p.add_argument("--pose-prior-weight", type=float, default=None,
                   help="weight of the learned hinge-angle prior (default 3; 2 fits clean, e.g. synthetic, 2D "
                        "better and detector-like noise worse: docs/fitting.md)")
    p.add_argument("--pose-prior", default=None, metavar="NAME|NPZ",
                   help="the pose prior: 'all' (default: the nine genres), 'partner' (rumba, swing, tango, waltz: "
                        "for salsa and ballroom) or an NPZ built for the style (scripts/build_pose_prior.py "
                        "--genres ...)")
    p.add_argument("--no-upright", action="store_true",
                   help="ablation: no trunk tilt prior (for dancers who lean far towards or away from the camera "
                        "for long stretches, e.g. floor work)")
    p.add_argument("--no-limb-depth", action="store_true",
                   help="ablation: keep the arms' depth (which side of the image plane) as the windows chose it, "
                        "instead of choosing it for the whole clip by the arms' steadiness in the trunk frame")
    p.add_argument("--joint-ranges", choices=("anatomical", "paper"), default=None,
                   help="hinge ranges: the paper's, or widened to normal human motion (default)")
    p.add_argument("--refine-sweeps", type=int, default=None, help="sequence refinement sweeps (default 3)")
    p.add_argument("--seed", type=int, default=None, help="random seed (default 0)")
    p.add_argument("--workers", type=int, default=None,
                   help="processes fitting chunks of a long clip at once (default: the CPU cores available)")
    p.add_argument("--chunk-frames", type=int, default=None,
                   help="frames per chunk of a long clip (default 900; results depend on it, not on --workers)")


def prior_argument(value: str) -> str:
    """``--pose-prior``: a shipped prior's name as it is, a file as an absolute path (chunk workers may run
    elsewhere), loaded once here so that a missing or wrong file stops the command with one line."""
    from hdvr.fitting.prior import NAMED_PRIORS, load_prior

    resolved = value if value in NAMED_PRIORS else str(Path(value).resolve())
    load_prior(resolved)
    return resolved


def settings_from_args(args: argparse.Namespace, **extra):
    """FitSettings from parsed options (``--paper`` first, explicit options on top)."""
    from hdvr.fitting.presets import FitSettings, paper_settings

    overrides = {}
    for key, attr in (("delta", "delta"), ("seeds", "seeds"), ("stride", "stride"), ("focal", "focal"),
                      ("height_m", "height"), ("joint_ranges", "joint_ranges"),
                      ("refine_sweeps", "refine_sweeps"), ("random_seed", "seed"), ("workers", "workers"),
                      ("chunk_frames", "chunk_frames"), ("smooth_2d", "smooth_2d"),
                      ("pose_prior_weight", "pose_prior_weight"), ("pose_prior_path", "pose_prior")):
        value = getattr(args, attr, None)
        if value is not None:
            overrides[key] = value
    if getattr(args, "principal_point", None) is not None:
        overrides["principal_point"] = tuple(args.principal_point)
    if getattr(args, "physics", False):
        overrides["physics"] = True
    if getattr(args, "no_joint_limits", False):
        overrides["joint_limits"] = False
    if getattr(args, "no_bone_prior", False):
        overrides["bone_prior"] = False
    if getattr(args, "no_temporal", False):
        overrides["temporal"] = False
        overrides.setdefault("smooth_2d", "off")
    if getattr(args, "no_pose_prior", False):
        overrides["pose_prior_weight"] = 0.0
    if getattr(args, "no_upright", False):
        overrides["upright_weight"] = 0.0
    if getattr(args, "no_limb_depth", False):
        overrides["limb_depth"] = False
    if overrides.get("pose_prior_path") is not None:
        overrides["pose_prior_path"] = prior_argument(overrides["pose_prior_path"])
    overrides.update(extra)
    return paper_settings(**overrides) if getattr(args, "paper", False) else FitSettings(**overrides)


def register(subparsers) -> None:
    p = subparsers.add_parser("fit3d", help="fit the 3D digital dancer to 2D keypoints (Algorithm 3*)",
                              description="Fit the MuJoCo digital dancer to one dancer's 2D keypoints (any "
                                          "layout that maps to BODY_25) and write a 3D result NPZ.")
    p.add_argument("keypoints", help="2D keypoint NPZ (see hdvr.io.keypoints2d)")
    p.add_argument("--out", required=True, help="output 3D result NPZ")
    add_fit_arguments(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.io.result3d import save_result3d
    from hdvr.plausibility import summarize_result
    from hdvr.skeleton import Skeleton

    src = Path(args.keypoints)
    if not src.is_file():
        raise HDVRError(f"2D keypoint file not found: {src}")
    kp = load_keypoints2d(src)
    settings = settings_from_args(args)
    skeleton = Skeleton()
    result, report = fit_keypoints(kp, settings, skeleton)
    figures = summarize_result(skeleton, result)
    result.meta["plausibility"] = figures
    save_result3d(args.out, result)
    print(json.dumps({"frames": result.num_frames, "frames_per_second": round(report.frames_per_second, 1),
                      "focal_px": round(report.focal, 1), "focal_estimated": report.focal_estimated,
                      "reprojection_error_px": round(float(result.reprojection_error_px.mean()), 2),
                      "bone_lengths_m": [round(float(b), 3) for b in report.bone_lengths],
                      "plausibility": {k: round(float(v), 3) for k, v in figures.items()}, "out": str(args.out)}))
    return 0
