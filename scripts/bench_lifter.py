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

``--gt-npz`` reads pre-converted mocap (``--write-gt-npz`` writes it) for machines without ../shared.
``--fits-cache FILE`` keeps the fitted views of step 1 (the slow part) for further lifter runs with the same
options.
"""

from __future__ import annotations

import argparse
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cameras", type=int, default=4, help="virtual cameras per training clip (test: 2)")
    parser.add_argument("--noise-px", type=float, default=3.0)
    parser.add_argument("--epochs", type=int, default=60)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--max-frames", type=int, default=0, help="truncate clips (0: whole takes)")
    parser.add_argument("--small", action="store_true", help="receptive field 27, 256 channels (quick runs)")
    parser.add_argument("--gt-npz", default=None)
    parser.add_argument("--write-gt-npz", default=None, help="write the converted mocap and exit")
    parser.add_argument("--out", default=str(REPO / "docs" / "lifter_bench.json"))
    parser.add_argument("--model-out", default=None, help="save the trained lifter here")
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
    from hdvr.lifter.train import TrainConfig, lift_sequence, save_checkpoint, train_lifter
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

    train = [clip_of(v) for v in views if split_of(v["name"]) == "train"]
    model_cfg = (LifterConfig(filter_widths=(3, 3, 3), channels=256) if args.small else LifterConfig())
    device = "cuda" if torch.cuda.is_available() else "cpu"
    cfg = TrainConfig(epochs=args.epochs, batch_size=256 if device == "cuda" else 64, device=device)
    t0 = time.perf_counter()
    model, history = train_lifter(train, model_cfg, cfg)
    train_seconds = time.perf_counter() - t0
    if args.model_out:
        save_checkpoint(args.model_out, model, {"receptive_field": model.receptive_field, "bench": "salsa"})
    model = model.to(device)

    rows = []
    for split in ("train", "test_salsa", "test_indian"):
        sel = [v for v in views if split_of(v["name"]) == split]
        if not sel:
            continue
        fit_m, lift_m = [], []
        for v in sel:
            lifted = lift_sequence(model, clip_of(v).inputs)
            fit_m.append(evaluate(v["fit_cam"], v["gt_cam"]))
            lift_m.append(evaluate(lifted, v["gt_cam"]))
        for method, ms in (("fit (Algorithm 3* + refinement)", fit_m), ("lifter (trained on the fit)", lift_m)):
            rows.append({"split": split, "method": method, "views": len(sel),
                         **{k: float(np.median([m[k] for m in ms])) for k in ms[0]}})
    report = {"machine": f"{platform.machine()}, {os.cpu_count()} CPUs, device {device}",
              "noise_px": args.noise_px, "cameras_per_train_clip": args.cameras, "epochs": args.epochs,
              "receptive_field": model.receptive_field, "fit_frames": frames, "fit_wall_s": fit_wall,
              "train_seconds": train_seconds, "final_loss": history[-1], "rows": rows}
    Path(args.out).write_text(json.dumps(report, indent=2))
    print(f"{'split':<12} {'method':<34} {'MPJPE':>7} {'P-MPJPE':>8}")
    for r in rows:
        print(f"{r['split']:<12} {r['method']:<34} {r['mpjpe_mm']:7.1f} {r['p_mpjpe_mm']:8.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
