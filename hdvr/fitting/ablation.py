"""Kinematic-constraint ablations: the same clips fitted under each setting, one table.

Settings (:data:`ABLATIONS`): ``full`` (HDVR defaults), ``no_joint_limits``, ``no_bone_prior`` (no per-dancer bone
lengths: each window draws its own from mean +- std), ``no_temporal``, ``no_pose_prior``, ``no_upright``,
``no_limb_depth``, ``physics`` (floor penetration and skating terms on), and ``paper`` (Algorithm 3* as
published). Each row: MPJPE, P-MPJPE (mm, when ground truth is given), plausibility figures
(:func:`hdvr.plausibility.summarize`) and frames per second, as medians over clips (metrics; MPJPE and P-MPJPE also
as means) or totals (speed).
"""

from __future__ import annotations

import json
import multiprocessing
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.fitting.presets import FitSettings, paper_settings
from hdvr.fitting.sequence import fit_keypoints
from hdvr.io.atomic import write_text_atomic
from hdvr.io.keypoints2d import Keypoints2D
from hdvr.metrics import evaluate
from hdvr.plausibility import summarize_result
from hdvr.skeleton import Skeleton

ABLATIONS: dict[str, str] = {
    "full": "HDVR defaults: hard joint limits, per-dancer bones, temporal smoothness",
    "no_joint_limits": "hinges unbounded",
    "no_bone_prior": "no per-dancer bone lengths (random per window, mean +- std)",
    "no_temporal": "no temporal smoothness terms, no 2D track smoothing",
    "no_pose_prior": "no learned hinge-angle prior (hdvr.fitting.prior)",
    "no_upright": "no trunk tilt prior (residuals.UprightTerm)",
    "no_limb_depth": "arm depth as the windows chose it (no clip-level choice, hdvr.fitting.limb_depth)",
    "physics": "defaults + floor penetration and foot-skating residuals",
    "paper": "Algorithm 3* as published (window per frame, random seeds)",
}
COLUMNS = ("mpjpe_mm", "p_mpjpe_mm", "n_mpjpe_mm", "accel_error_mm", "foot_penetration_p95_cm",
           "foot_skating_mean_cm_s", "self_penetration_frames_pct", "limit_violations", "bone_cv_max_pct",
           "jitter_m_s3", "frames_per_second")
MEAN_COLUMNS = ("mpjpe_mm", "p_mpjpe_mm")  # also reported as means over clips (``<name>_mean``)


def settings_for(name: str, base: FitSettings) -> FitSettings:
    """The settings of ablation ``name`` on top of ``base``."""
    if name == "full":
        return base
    if name == "no_joint_limits":
        return replace(base, joint_limits=False)
    if name == "no_bone_prior":
        return replace(base, bone_prior=False, calibrate=False, seed_strategy="random")
    if name == "no_temporal":
        return replace(base, temporal=False, refine_sweeps=0, smooth_2d="off")
    if name == "no_pose_prior":
        return replace(base, pose_prior_weight=0.0)
    if name == "no_upright":
        return replace(base, upright_weight=0.0)
    if name == "no_limb_depth":
        return replace(base, limb_depth=False)
    if name == "physics":
        return replace(base, physics=True)
    if name == "paper":
        return paper_settings(focal=base.focal, height_m=base.height_m, random_seed=base.random_seed)
    raise HDVRError(f"unknown ablation {name!r}; choose from {', '.join(ABLATIONS)}")


def _fit_one(job: tuple[str, str, Keypoints2D, np.ndarray | None, FitSettings]) -> tuple[dict, int, float]:
    """(figures, frames, seconds) of one clip under one ablation's settings."""
    name, clip_name, kp, gt, settings = job
    skeleton = Skeleton()
    start = time.perf_counter()
    result, _ = fit_keypoints(kp, settings, skeleton)
    seconds = time.perf_counter() - start
    figures = summarize_result(skeleton, result)
    if gt is not None:
        figures.update(evaluate(result.keypoints3d, gt))
    figures["clip"] = clip_name
    return figures, result.num_frames, seconds


def run_ablation(clips: list[tuple[str, Keypoints2D, np.ndarray | None]], names, base: FitSettings,
                 focal_per_clip: list[float | None] | None = None, processes: int = 1) -> list[dict]:
    """Fit every clip ``(name, keypoints, ground truth camera-frame BODY_25 (T, 25, 3) or None)`` under each
    ablation; one row per ablation with medians over clips. ``processes`` > 1 fits that many clips at once (each
    fit then on one worker; results are identical, frames/s is per fit)."""
    jobs = []
    for name in names:
        for c, (clip_name, kp, gt) in enumerate(clips):
            settings = settings_for(name, base)
            if focal_per_clip is not None and focal_per_clip[c] is not None:
                settings = replace(settings, focal=focal_per_clip[c])
            if processes > 1:
                settings = replace(settings, workers=1)
            jobs.append((name, clip_name, kp, gt, settings))
    if processes > 1:
        with multiprocessing.Pool(processes) as pool:
            done = pool.map(_fit_one, jobs, chunksize=1)
    else:
        done = [_fit_one(job) for job in jobs]
    rows = []
    for name in names:
        per_clip, frames, seconds = [], 0, 0.0
        for job, (figures, n, sec) in zip(jobs, done):
            if job[0] == name:
                per_clip.append(figures)
                frames += n
                seconds += sec
        row = {"setting": name, "description": ABLATIONS[name], "clips": len(per_clip),
               "frames_per_second": frames / seconds if seconds else 0.0}
        for col in COLUMNS:
            if col == "frames_per_second":
                continue
            values = [r[col] for r in per_clip if col in r]
            row[col] = float(np.median(values)) if values else float("nan")
        for col in MEAN_COLUMNS:
            values = [r[col] for r in per_clip if col in r]
            row[f"{col}_mean"] = float(np.mean(values)) if values else float("nan")
        row["per_clip"] = per_clip
        rows.append(row)
    return rows


def markdown_table(rows: list[dict]) -> str:
    """A markdown table of ablation rows (medians over clips; means of MPJPE and P-MPJPE where present)."""
    means = [c for c in MEAN_COLUMNS if all(f"{c}_mean" in r for r in rows)]
    head = "| setting | " + " | ".join(COLUMNS) + "".join(f" | {c} (mean)" for c in means) + " |"
    sep = "|---|" + "---|" * (len(COLUMNS) + len(means))
    lines = [head, sep]
    for r in rows:
        cells = []
        for col in COLUMNS:
            v = r.get(col, float("nan"))
            cells.append(f"{v:.0f}" if col == "limit_violations" else f"{v:.1f}")
        cells += [f"{r[f'{c}_mean']:.1f}" for c in means]
        lines.append(f"| {r['setting']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def write_tables(rows: list[dict], out_dir: str | Path, stem: str = "ablation") -> tuple[Path, Path]:
    """Write ``stem.md`` and ``stem.json`` into ``out_dir`` (atomically); returns their paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    md, js = out / f"{stem}.md", out / f"{stem}.json"
    write_text_atomic(md, markdown_table(rows))
    write_text_atomic(js, json.dumps(rows, indent=1, default=float))
    return md, js
