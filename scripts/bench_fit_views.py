#!/usr/bin/env python3
"""The 3D fit alone over many random views of whole mocap takes, per dance style: the measure behind the pose-prior
choices of docs/fitting.md ("Learned pose prior", session 44).

Each salsa and Indian take of ../shared/data (or ``--gt-npz``, as written by ``scripts/bench_lifter.py
--write-gt-npz``) is seen by ``--cameras-salsa`` / ``--cameras-indian`` random virtual cameras (the cameras of
scripts/bench_lifter.py, numbered from 100 so they are not its training views), with 3 px Gaussian noise on the
2D, and fitted with the default settings (focal estimated) and the chosen pose prior. Prints P-MPJPE and MPJPE
(mm, medians and means over views) per style; with ``--compare`` a previous run's JSON, the paired differences
view by view (how many views got better or worse by more than 1 mm).

    python3 scripts/bench_fit_views.py --out before.json
    python3 scripts/bench_fit_views.py --pose-prior partner --cameras-indian 0 --compare before.json
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import zlib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("HDVR_NO_PROGRESS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

import bench_lifter  # noqa: E402

FIRST_CAMERA = 100


def style_of(name: str) -> str:
    return "indian" if name.startswith("indian") else "salsa"


def fit_view(job) -> dict:
    """Worker: fit one (take, camera) view with the prior ``pose_prior`` (name or NPZ; None: the shipped one)."""
    name, camera, world, noise_px, max_frames, pose_prior = job
    from hdvr.fitting.presets import FitSettings
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.keypoints2d import Keypoints2D
    from hdvr.layouts import BODY25_NAMES
    from hdvr.metrics import evaluate

    world = world[:max_frames] if max_frames else world
    kp, gt_cam, _ = bench_lifter.make_view(world, zlib.crc32(f"{name}/{camera}".encode()), noise_px)
    start = time.perf_counter()
    result, _ = fit_keypoints(Keypoints2D(kp, BODY25_NAMES, 30.0, bench_lifter.IMAGE),
                              FitSettings(pose_prior_path=pose_prior))
    scores = evaluate(result.keypoints3d, gt_cam)
    return {"name": name, "camera": camera, "style": style_of(name), "frames": int(len(kp)),
            "p_mpjpe_mm": float(scores["p_mpjpe_mm"]), "mpjpe_mm": float(scores["mpjpe_mm"]),
            "seconds": time.perf_counter() - start}


def summarise(rows: list[dict]) -> dict:
    """{style: {views, p_mpjpe_median, p_mpjpe_mean, mpjpe_median, mpjpe_mean}} (mm)."""
    out = {}
    for style in sorted({r["style"] for r in rows}):
        p = np.array([r["p_mpjpe_mm"] for r in rows if r["style"] == style])
        m = np.array([r["mpjpe_mm"] for r in rows if r["style"] == style])
        out[style] = {"views": int(len(p)), "p_mpjpe_median": float(np.median(p)), "p_mpjpe_mean": float(p.mean()),
                      "mpjpe_median": float(np.median(m)), "mpjpe_mean": float(m.mean())}
    return out


def paired(rows: list[dict], before: list[dict]) -> dict:
    """{style: {views, better, worse, median_diff, mean_diff}}: P-MPJPE of ``rows`` minus ``before``, view by view
    (better / worse: by more than 1 mm)."""
    old = {(r["name"], r["camera"]): r["p_mpjpe_mm"] for r in before}
    out = {}
    for style in sorted({r["style"] for r in rows}):
        d = np.array([r["p_mpjpe_mm"] - old[(r["name"], r["camera"])] for r in rows
                      if r["style"] == style and (r["name"], r["camera"]) in old])
        if d.size:
            out[style] = {"views": int(d.size), "better": int((d < -1).sum()), "worse": int((d > 1).sum()),
                          "median_diff": float(np.median(d)), "mean_diff": float(d.mean())}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cameras-salsa", type=int, default=2, help="views per salsa take")
    ap.add_argument("--cameras-indian", type=int, default=8, help="views per Indian take")
    ap.add_argument("--pose-prior", default=None, help="prior name (all, partner) or NPZ (default: the shipped one)")
    ap.add_argument("--noise-px", type=float, default=3.0)
    ap.add_argument("--max-frames", type=int, default=0, help="truncate takes (0: whole takes)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--gt-npz", default=None, help="pre-converted mocap (scripts/bench_lifter.py --write-gt-npz)")
    ap.add_argument("--compare", default=None, help="a previous run's JSON: paired differences view by view")
    ap.add_argument("--out", default=None, help="write the views' scores and the summary here (JSON)")
    args = ap.parse_args(argv)
    from hdvr.commands.fit3d import prior_argument
    from hdvr.errors import HDVRError

    try:  # a missing or wrong prior stops here
        prior = None if args.pose_prior is None else prior_argument(args.pose_prior)
    except HDVRError as exc:
        print(f"bench_fit_views: {exc}", file=sys.stderr)
        return 2
    gt = bench_lifter.load_gt(args.gt_npz)
    if not gt:
        print("no mocap found (../shared/data or --gt-npz)", file=sys.stderr)
        return 2
    cams = {"salsa": args.cameras_salsa, "indian": args.cameras_indian}
    jobs = [(name, FIRST_CAMERA + c, world, args.noise_px, args.max_frames, prior)
            for name, world in gt.items() for c in range(cams[style_of(name)])]
    start = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(fit_view, jobs))
    summary = summarise(rows)
    for style, s in summary.items():
        print(f"{style}: {s['views']} views, P-MPJPE median {s['p_mpjpe_median']:.1f} mean {s['p_mpjpe_mean']:.1f}, "
              f"MPJPE median {s['mpjpe_median']:.1f} mean {s['mpjpe_mean']:.1f} (mm)")
    report = {"pose_prior": args.pose_prior or "all", "noise_px": args.noise_px, "summary": summary, "views": rows,
              "seconds": time.perf_counter() - start}
    if args.compare:
        report["paired"] = paired(rows, json.loads(Path(args.compare).read_text())["views"])
        for style, p in report["paired"].items():
            print(f"{style} against {args.compare}: better on {p['better']} of {p['views']} views, worse on "
                  f"{p['worse']}; P-MPJPE difference median {p['median_diff']:+.1f}, mean {p['mean_diff']:+.1f} mm")
    if args.out:
        tmp = Path(args.out).with_suffix(".partial")
        tmp.write_text(json.dumps(report, indent=1))
        tmp.replace(args.out)
    print(f"{len(rows)} views in {report['seconds']:.0f} s with {args.workers} workers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
