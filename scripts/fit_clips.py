#!/usr/bin/env python3
"""Mean accuracy of ``hdvr fit3d`` settings over many mocap clips: the harness behind the tuning tables of
docs/fitting.md (the benchmark, scripts/bench_fit3d.py, reports medians of four clips; means over 14 clips move
less with chance mode choices).

Each clip is a salsa (``60_02``) or Indian (``indian_04``) take from ../shared/data, 1 s in, seen by the same
random camera as in bench_fit3d.py (seeded by the clip name), fitted with the focal given. Prints P-MPJPE and
MPJPE (mm) per clip and their means.

    python3 scripts/fit_clips.py --settings upright_weight=0 --condition noise3px
    python3 scripts/fit_clips.py --clips 60_02 61_02 --seconds 8 --settings pose_prior_weight=2 seeds=3
"""

from __future__ import annotations

import argparse
import ast
import os
import sys
import time
from multiprocessing import Pool
from pathlib import Path

os.environ.setdefault("HDVR_NO_PROGRESS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

import bench_fit3d  # noqa: E402
from hdvr.errors import HDVRError  # noqa: E402
from hdvr.fitting.presets import FitSettings  # noqa: E402
from hdvr.fitting.sequence import fit_keypoints  # noqa: E402
from hdvr.io.bvh import load_mocap_body25  # noqa: E402
from hdvr.metrics import evaluate  # noqa: E402
from hdvr.skeleton import Skeleton  # noqa: E402

SALSA_14 = [f"{s}_{t:02d}" for t in range(1, 8) for s in ("60", "61")]


def clip_path(name: str) -> Path:
    if name.startswith("indian"):
        return bench_fit3d.DATA.parent / "cmu-indian" / f"{name}.bvh"
    return bench_fit3d.DATA / f"{name}_scaled.bvh"


def fit_one(job: tuple[str, float, str, dict]) -> tuple[str, float, float, float]:
    """(clip, P-MPJPE mm, MPJPE mm, frames/s) of one clip."""
    name, seconds, condition, overrides = job
    pos, _ = load_mocap_body25(clip_path(name), fps=30)
    clip = pos[30:30 + int(seconds * 30)]
    rng = np.random.default_rng([0, int(name.replace("_", "").replace("indian", "9"))])
    kp, gt, focal = bench_fit3d.make_clip(clip, rng, condition)
    start = time.perf_counter()
    result, _ = fit_keypoints(kp, FitSettings(focal=focal, workers=1, **overrides), Skeleton())
    seconds_taken = time.perf_counter() - start
    row = evaluate(result.keypoints3d, gt)
    return name, row["p_mpjpe_mm"], row["mpjpe_mm"], len(clip) / seconds_taken


def parse_setting(text: str) -> tuple[str, object]:
    key, _, value = text.partition("=")
    try:
        return key, ast.literal_eval(value)
    except (ValueError, SyntaxError):
        return key, value


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--clips", nargs="*", default=SALSA_14, help="take names (default: salsa 01-07, both dancers)")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--condition", choices=bench_fit3d.CONDITIONS, default="clean")
    ap.add_argument("--settings", nargs="*", default=[], help="FitSettings overrides, key=value")
    ap.add_argument("--procs", type=int, default=os.cpu_count() or 1, help="clips fitted at once")
    args = ap.parse_args()
    missing = [c for c in args.clips if not clip_path(c).is_file()]
    if missing:
        print(f"mocap take(s) not found: {', '.join(str(clip_path(c)) for c in missing)}", file=sys.stderr)
        return 2
    overrides = dict(parse_setting(s) for s in args.settings)
    try:
        FitSettings(**overrides)  # bad keys or values fail here, not in a worker
    except (TypeError, HDVRError) as exc:
        print(f"bad --settings: {exc}", file=sys.stderr)
        return 2
    jobs = [(c, args.seconds, args.condition, overrides) for c in args.clips]
    with Pool(max(1, args.procs)) as pool:
        rows = pool.map(fit_one, jobs)
    for name, p, m, fps in rows:
        print(f"{name} P-MPJPE {p:.1f} MPJPE {m:.1f} ({fps:.0f} frames/s)")
    print(f"MEAN P-MPJPE {np.mean([r[1] for r in rows]):.1f} MPJPE {np.mean([r[2] for r in rows]):.1f}  "
          f"{args.condition} {overrides}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
