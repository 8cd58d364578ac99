#!/usr/bin/env python3
"""Benchmark of the lifter trained on top of the unsupervised fit (no 3D ground truth in training).

Data: the real CMU mocap (../shared/data), BODY_25 at 30 fps, stature 1.70 m, projected through random virtual
cameras (1920x1080, focal 1000-2000 px, 3-8 m, azimuth 0-360 deg, elevation -5-30 deg), Gaussian noise
``--noise-px`` on the 2D. Split: salsa takes 01-05 (both dancers) train, takes 06-07 test ("unseen takes of the
same dancers"), the Indian takes a second test ("unseen style").

1. ``hdvr fit3d`` (focal estimated) on every clip: the pseudo-ground truth P* and the camera it found.
2. The lifter trains on (2D, P*) pairs of the training clips with Algorithm 4*'s loss.
3. On the test clips, the fit and the lifter are scored against the mocap (hdvr.metrics, mm, EVAL_JOINTS).

    python3 scripts/bench_lifter.py --workers 2 [--cameras 4] [--epochs 60] [--small]

On a GPU (the published size, receptive field 243 and 1024 channels), with the fits made beforehand on a CPU
machine (``--fits-cache``) and carried over with the converted mocap (``--write-gt-npz``):

    python3 scripts/bench_lifter.py --gt-npz gt.npz --fits-cache fits.npz --cameras 8 --batch-size 64 \
        --out-frames 32 --window-stride 4 --lr 1e-3 --flip-test --train-budget-seconds 350

(Session 48: many small steps; batch 256 learnt far less in the same time, docs/benchmarks.md "Lifter".)

``--gt-npz`` reads pre-converted mocap (``--write-gt-npz`` writes it) for machines without ../shared.
``--fits-cache FILE`` keeps the fitted views of step 1 (the slow part) for further lifter runs with the same
options.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import sys
import time
import zlib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("HDVR_NO_PROGRESS", "1")
REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import numpy as np  # noqa: E402

from hdvr.camera import look_at, project  # noqa: E402

IMAGE = (1920, 1080)
DATA = Path(os.environ.get("HDVR_SHARED_DATA", REPO.parent / "shared" / "data"))


def load_gt(gt_npz: str | None) -> dict[str, np.ndarray]:
    """{clip name: (T, 25, 3) world metres} for every salsa and Indian take."""
    if gt_npz:
        data = np.load(gt_npz)
        return {k: data[k] for k in data.files}
    from hdvr.io.bvh import load_mocap_body25

    out = {}
    for f in sorted((DATA / "cmu-salsa").glob("*.bvh")) + sorted((DATA / "cmu-indian").glob("*.bvh")):
        out[f.stem] = load_mocap_body25(f, fps=30)[0].astype(np.float32)
    return out


def split_of(name: str) -> str:
    if name.startswith("indian"):
        return "test_indian"
    take = int(name.split("_")[1])
    return "train" if take <= 5 else "test_salsa"


def make_view(gt_world: np.ndarray, seed: int, noise_px: float):
    rng = np.random.default_rng(seed)
    centre = np.nanmean(gt_world[:, 8, :2], axis=0)
    focal = rng.uniform(1000, 2000)
    d, az, el = rng.uniform(3, 8), np.deg2rad(rng.uniform(0, 360)), np.deg2rad(rng.uniform(-5, 30))
    target = np.array([centre[0], centre[1], 1.0])
    cam = look_at(target + d * np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)]), target)
    gt_cam = cam.to_camera(gt_world)
    px = project(gt_cam, focal, (IMAGE[0] / 2, IMAGE[1] / 2)) + rng.normal(0, noise_px, gt_cam.shape[:2] + (2,))
    kp = np.concatenate([px, np.ones(px.shape[:2] + (1,))], axis=-1).astype(np.float32)
    return kp, gt_cam.astype(np.float32), focal


def fit_one(job):
    """Worker: fit one (clip, camera) view; returns what training and evaluation need."""
    name, cam_index, gt_world, noise_px, max_frames = job
    from hdvr.fitting.presets import FitSettings
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.keypoints2d import Keypoints2D
    from hdvr.layouts import BODY25_NAMES

    gt_world = gt_world[:max_frames] if max_frames else gt_world
    kp, gt_cam, focal = make_view(gt_world, zlib.crc32(f"{name}/{cam_index}".encode()), noise_px)
    t0 = time.perf_counter()
    result, _ = fit_keypoints(Keypoints2D(kp, BODY25_NAMES, 30.0, IMAGE), FitSettings())
    seconds = time.perf_counter() - t0
    return {"name": name, "camera": cam_index, "keypoints": kp, "gt_cam": gt_cam, "true_focal": focal,
            "fit_cam": result.keypoints3d, "fit_focal": result.focal, "fit_pp": result.principal_point,
            "fit_seconds": seconds}


FIT_FIELDS = ("keypoints", "gt_cam", "true_focal", "fit_cam", "fit_focal", "fit_pp", "fit_seconds", "camera")


def write_fits(path: str, key: str, views: list[dict]) -> None:
    """Keep the fitted views (step 1, the slow part) for further lifter runs with the same options."""
    from hdvr.io.atomic import atomic_path

    arrays = {"key": np.array(key), "names": np.array([v["name"] for v in views])}
    for i, v in enumerate(views):
        arrays.update({f"{i}/{f}": np.asarray(v[f]) for f in FIT_FIELDS})
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays)


def read_fits(path: str, key: str) -> list[dict] | None:
    """The views :func:`write_fits` kept, or None if there is no such file or it was made with other options."""
    if not Path(path).is_file():
        return None
    with np.load(path, allow_pickle=False) as data:
        if str(data["key"]) != key:
            print(f"{path} was made with other options; fitting again")
            return None
        names = [str(n) for n in data["names"]]
        return [{"name": n, **{f: data[f"{i}/{f}"] for f in FIT_FIELDS}} for i, n in enumerate(names)]


def train(clips, model_cfg, cfg, args):
    """Train the lifter (the epochs chosen from a timed first epoch with ``--train-budget-seconds``); returns the
    model, its history and the training seconds."""
    from hdvr.lifter.train import train_lifter

    if args.train_budget_seconds:
        timing = dataclasses.replace(cfg, epochs=1, max_seconds=None)
        epoch_seconds = train_lifter(clips, model_cfg, timing)[1][0]["seconds"]
        cfg.epochs = max(1, int(args.train_budget_seconds / epoch_seconds))
        cfg.lr_decay = args.final_lr_fraction ** (1.0 / cfg.epochs)
        print(f"one epoch took {epoch_seconds:.1f} s: {cfg.epochs} epochs, learning rate x {cfg.lr_decay:.4f} "
              "per epoch", flush=True)

    def report_epoch(h: dict) -> None:
        if h["epoch"] % 5 == 0 or h["epoch"] == cfg.epochs - 1:
            print(f"epoch {h['epoch']}: " + ", ".join(f"{k} {v:.4g}" for k, v in h.items() if k != "epoch"),
                  flush=True)

    t0 = time.perf_counter()
    model, history = train_lifter(clips, model_cfg, cfg, on_epoch=report_epoch)
    return model, history, time.perf_counter() - t0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cameras", type=int, default=4, help="virtual cameras per training clip (test: 2)")
    parser.add_argument("--noise-px", type=float, default=3.0)
    parser.add_argument("--epochs", type=int, default=60)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--max-frames", type=int, default=0, help="truncate clips (0: whole takes)")
    parser.add_argument("--small", action="store_true", help="receptive field 27, 256 channels (quick runs)")
    parser.add_argument("--filter-widths", default=None,
                        help="comma-separated filter widths, e.g. 3,3,3,3 (receptive field 81; default 3,3,3,3,3, "
                        "or 3,3,3 with --small)")
    parser.add_argument("--channels", type=int, default=None, help="channels of the lifter (default 1024; 256 "
                        "with --small)")
    parser.add_argument("--batch-size", type=int, default=None, help="windows per step (default 64, on a GPU too: "
                        "many small steps learn more than few large ones)")
    parser.add_argument("--lr", type=float, default=1e-3)
    parser.add_argument("--root", choices=("learned", "solved"), default="solved",
                        help="the root's position: a second network, or solved from the pose and the 2D")
    parser.add_argument("--lr-decay", type=float, default=0.95, help="learning-rate factor per epoch")
    parser.add_argument("--max-train-seconds", type=float, default=None,
                        help="stop training after the epoch that passes this time (the epochs done are kept)")
    parser.add_argument("--train-budget-seconds", type=float, default=None,
                        help="choose the epochs from a timed first epoch to fill this much training time, and the "
                        "per-epoch decay so the learning rate ends at --final-lr-fraction of --lr (both recorded)")
    parser.add_argument("--final-lr-fraction", type=float, default=0.05)
    parser.add_argument("--out-frames", type=int, default=16, help="output frames per training window")
    parser.add_argument("--window-stride", type=int, default=2, help="frames between training windows' starts")
    parser.add_argument("--device", default="auto", help="auto, cpu or cuda")
    parser.add_argument("--mixed-precision", action="store_true", help="bf16 autocast on a GPU (default: float32, "
                        "which was faster on an H100)")
    parser.add_argument("--gt-npz", default=None)
    parser.add_argument("--write-gt-npz", default=None, help="write the converted mocap and exit")
    parser.add_argument("--out", default=str(REPO / "docs" / "lifter_bench.json"))
    parser.add_argument("--model-out", default=None, help="save the trained lifter here")
    parser.add_argument("--model-in", default=None, help="evaluate this saved lifter instead of training one")
    parser.add_argument("--flip-test", action="store_true", help="also score the lifter with test-time flipping")
    parser.add_argument("--raw-inputs", action="store_true",
                        help="feed the pose network the normalised 2D as given (default: centred and scaled)")
    parser.add_argument("--fits-cache", default=None,
                        help="NPZ of the fitted views: read if it exists (same options), else written after step 1")
    args = parser.parse_args()

    gt = load_gt(args.gt_npz)
    if args.write_gt_npz:
        np.savez_compressed(args.write_gt_npz, **gt)
        print(f"wrote {args.write_gt_npz}")
        return 0

    import torch

    from hdvr.lifter.data import LiftingClip, normalise_keypoints
    from hdvr.lifter.model import LifterConfig
    from hdvr.lifter.train import (TrainConfig, lift_sequence, load_checkpoint, pick_device, save_checkpoint,
                                   train_config_dict)
    from hdvr.metrics import evaluate

    jobs = []
    for name, world in gt.items():
        n_cams = args.cameras if split_of(name) == "train" else 2
        jobs += [(name, c, world, args.noise_px, args.max_frames) for c in range(n_cams)]
    t0 = time.perf_counter()
    key = f"cameras={args.cameras} noise={args.noise_px} max_frames={args.max_frames} clips={sorted(gt)}"
    views = read_fits(args.fits_cache, key) if args.fits_cache else None
    if views is None:
        with ProcessPoolExecutor(args.workers) as pool:
            views = list(pool.map(fit_one, jobs))
        if args.fits_cache:
            write_fits(args.fits_cache, key, views)
    fit_wall = time.perf_counter() - t0
    frames = sum(v["keypoints"].shape[0] for v in views)
    print(f"fitted {len(views)} views, {frames} frames in {fit_wall:.0f} s with {args.workers} workers")

    def clip_of(v, labels=False):
        inputs = normalise_keypoints(v["keypoints"], v["fit_focal"], v["fit_pp"])
        return LiftingClip(inputs, v["fit_cam"].astype(np.float32), v["gt_cam"] if labels else None)

    train_clips = [clip_of(v) for v in views if split_of(v["name"]) == "train"]
    model_cfg = (LifterConfig(filter_widths=(3, 3, 3), channels=256) if args.small else LifterConfig())
    if args.channels:
        model_cfg.channels = args.channels
    if args.filter_widths:
        model_cfg.filter_widths = tuple(int(w) for w in args.filter_widths.split(","))
    model_cfg.root = args.root
    model_cfg.centre_inputs = not args.raw_inputs
    device = str(pick_device(args.device))
    cfg = TrainConfig(epochs=args.epochs, batch_size=args.batch_size or 64,
                      learning_rate=args.lr, lr_decay=args.lr_decay, max_seconds=args.max_train_seconds,
                      mixed_precision=args.mixed_precision, device=device, out_frames=args.out_frames,
                      window_stride=args.window_stride)
    if args.model_in:
        model, meta = load_checkpoint(args.model_in, device)
        model_cfg, history, train_seconds = model.cfg, meta.get("history", []), 0.0
        print(f"evaluating {args.model_in} (not trained here)")
    else:
        model, history, train_seconds = train(train_clips, model_cfg, cfg, args)
        if args.model_out:
            save_checkpoint(args.model_out, model, {"receptive_field": model.receptive_field, "bench": "salsa",
                                                    "train": train_config_dict(cfg), "history": history})
    model = model.to(device)

    rows = []
    lift_seconds, lift_frames = 0.0, 0
    lifters = [("lifter (trained on the fit)", False)] + ([("lifter, flip test", True)] if args.flip_test else [])
    for split in ("train", "test_salsa", "test_indian"):
        sel = [v for v in views if split_of(v["name"]) == split]
        if not sel:
            continue
        scores: dict[str, list] = {"fit (Algorithm 3* + refinement)": [evaluate(v["fit_cam"], v["gt_cam"])
                                                                       for v in sel]}
        for method, flip_test in lifters:
            scores[method] = []
            for v in sel:
                t0 = time.perf_counter()
                lifted = lift_sequence(model, clip_of(v).inputs, flip_test=flip_test)
                if not flip_test:
                    lift_seconds, lift_frames = lift_seconds + time.perf_counter() - t0, lift_frames + len(lifted)
                scores[method].append(evaluate(lifted, v["gt_cam"]))
        for method, ms in scores.items():
            rows.append({"split": split, "method": method, "views": len(sel),
                         **{k: float(np.median([m[k] for m in ms])) for k in ms[0]}})
    gpu = f" ({torch.cuda.get_device_name()})" if device == "cuda" else ""
    report = {"machine": f"{platform.machine()}, {os.cpu_count()} CPUs, device {device}{gpu}",
              "noise_px": args.noise_px, "cameras_per_train_clip": args.cameras, "epochs": cfg.epochs,
              "epochs_done": len(history), "model": model_cfg.to_dict(), "train": train_config_dict(cfg),
              "receptive_field": model.receptive_field, "fit_frames": frames, "fit_wall_s": fit_wall,
              "train_frames": sum(c.inputs.shape[0] for c in train_clips), "train_seconds": train_seconds,
              "lift_frames_per_s": lift_frames / max(lift_seconds, 1e-9), "final_loss": history[-1] if history else None,
              "history": history, "rows": rows}
    Path(args.out).write_text(json.dumps(report, indent=2))
    print(f"{'split':<12} {'method':<34} {'MPJPE':>7} {'P-MPJPE':>8}")
    for r in rows:
        print(f"{r['split']:<12} {r['method']:<34} {r['mpjpe_mm']:7.1f} {r['p_mpjpe_mm']:8.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
