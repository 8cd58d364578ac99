"""``hdvr lift``: train the temporal lifter on (2D, fit) pairs and apply it to a clip.

    hdvr lift train --pair kp.npz fit.npz [--pair ...] --out lifter.pt [--epochs 40] [--small] [--max-minutes M]
    hdvr lift apply kp.npz --fit fit.npz --model lifter.pt --out lifted.npz [--flip-test]

The lifter never sees 3D ground truth: its targets are the unsupervised fits (``hdvr fit3d``). ``apply`` takes
the camera intrinsics from the fit and writes a 3D result whose
``keypoints3d`` are the lifter's (camera frame, metres); ``qpos``, bones and camera pose stay those of the fit
(``meta.keypoints3d_source = "lifter"``).
"""

from __future__ import annotations


def register(subparsers) -> None:
    parser = subparsers.add_parser("lift", help="train / apply the temporal 2D-to-3D lifter")
    sub = parser.add_subparsers(dest="lift_command", metavar="ACTION")
    tr = sub.add_parser("train", help="train on (2D keypoints, 3D fit) pairs")
    tr.add_argument("--pair", nargs=2, action="append", metavar=("KEYPOINTS", "FIT"), required=True)
    tr.add_argument("--out", required=True, help="checkpoint path (.pt)")
    tr.add_argument("--epochs", type=int, default=40)
    tr.add_argument("--small", action="store_true", help="receptive field 27 frames, 256 channels (CPU-friendly)")
    tr.add_argument("--seed", type=int, default=0)
    tr.add_argument("--batch-size", type=int, default=None,
                    help="training windows per step (default 32 on the CPU, 64 on a GPU: where each was measured best, "
                         "docs/benchmarks.md \"Lifter\")")
    tr.add_argument("--learning-rate", type=float, default=1e-3)
    tr.add_argument("--max-minutes", type=float, default=None,
                    help="stop after the epoch that passes this much training time, keeping what was learnt")
    tr.add_argument("--root", choices=("solved", "learned"), default="solved",
                    help="the root's position: solved from the pose and the 2D (default), or a second network")
    tr.add_argument("--device", default="auto", help="auto, cpu or cuda")
    tr.set_defaults(func=run_train)
    ap = sub.add_parser("apply", help="lift one dancer's 2D keypoints")
    ap.add_argument("keypoints")
    ap.add_argument("--fit", required=True, help="the clip's 3D fit (intrinsics, qpos, bones)")
    ap.add_argument("--model", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--flip-test", action="store_true",
                    help="also lift the mirrored clip and average (test-time augmentation; twice the work)")
    ap.set_defaults(func=run_apply)
    parser.set_defaults(func=lambda args: parser.print_help())


def _clip(kp_path, fit_path):
    from hdvr.errors import HDVRError
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.io.result3d import load_result3d
    from hdvr.lifter.data import LiftingClip, normalise_keypoints

    kp = load_keypoints2d(kp_path).to_body25()
    fit = load_result3d(fit_path)
    if fit.num_frames != kp.num_frames:
        raise HDVRError(f"{kp_path} has {kp.num_frames} frames but {fit_path} has {fit.num_frames}")
    inputs = normalise_keypoints(kp.keypoints, fit.focal, fit.principal_point)
    return LiftingClip(inputs, fit.keypoints3d.astype("float32")), fit


def default_batch_size(device: str) -> int:
    """Training windows per step where none is given: 64 on a GPU, 32 on the CPU. On the CPU a step of 32 windows
    costs half one of 64 and more steps learn more in the same time (session 43); on an H100 small steps cost about
    the same, and 64 learnt far more than 256 in the same time (session 48)."""
    return 64 if device.startswith("cuda") else 32


def run_train(args) -> int:
    from hdvr.lifter.model import LifterConfig
    from hdvr.lifter.train import TrainConfig, pick_device, save_checkpoint, train_config_dict, train_lifter

    clips = [_clip(k, f)[0] for k, f in args.pair]
    model_cfg = LifterConfig(filter_widths=(3, 3, 3), channels=256) if args.small else LifterConfig()
    model_cfg.root = args.root
    batch_size = args.batch_size or default_batch_size(str(pick_device(args.device)))
    cfg = TrainConfig(epochs=args.epochs, seed=args.seed, device=args.device, batch_size=batch_size,
                      learning_rate=args.learning_rate,
                      max_seconds=None if args.max_minutes is None else 60.0 * args.max_minutes)
    model, history = train_lifter(clips, model_cfg, cfg)
    save_checkpoint(args.out, model, {"train": train_config_dict(cfg), "final_loss": history[-1],
                                      "clips": [list(p) for p in args.pair]})
    print(f"wrote {args.out}: receptive field {model.receptive_field} frames, {len(history)} epochs, "
          f"{sum(c.inputs.shape[0] for c in clips)} training frames, final loss "
          + ", ".join(f"{k} {v:.3g}" for k, v in history[-1].items() if k != "epoch"))
    return 0


def run_apply(args) -> int:
    import numpy as np

    from hdvr.io.result3d import save_result3d
    from hdvr.lifter.train import lift_sequence, load_checkpoint

    clip, fit = _clip(args.keypoints, args.fit)
    model, _ = load_checkpoint(args.model)
    lifted = lift_sequence(model, clip.inputs, flip_test=args.flip_test)
    fit.keypoints3d = lifted.astype(np.float32)
    fit.meta = {**fit.meta, "keypoints3d_source": "lifter", "lifter": str(args.model)}
    save_result3d(args.out, fit)
    moved = np.linalg.norm(lifted - clip.fit3d, axis=-1)
    print(f"wrote {args.out}: {len(lifted)} frames; lifter vs fit: median {1000 * np.median(moved):.0f} mm")
    return 0
