#!/usr/bin/env python3
"""Benchmark of ``hdvr fit3d`` on real mocap (CMU salsa, both dancers) seen through random virtual cameras.

For each clip (a BVH take of ../shared/data/cmu-salsa, resampled to 30 fps, stature normalised to 1.70 m), a
random pinhole camera (1920x1080, focal 1000-2000 px, 3-8 m from the dancer's mean position, azimuth 0-360 deg,
elevation -5-30 deg) projects the BODY_25 mocap keypoints. Conditions: clean 2D, Gaussian noise sigma = 3 px,
10 % of keypoints dropped (confidence 0). Each condition is fitted with the focal given and estimated.
Metrics (hdvr.metrics, mm, EVAL_JOINTS, root-relative) against the mocap in the camera frame, plausibility
figures (hdvr.plausibility), frames/s (wall time of fit_keypoints / frames) and peak traced memory.

    python3 scripts/bench_fit3d.py                       # default clips and seconds, writes docs/benchmarks.md
    python3 scripts/bench_fit3d.py --ablate              # plus the ablation table on the clean condition
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import platform
import sys
import time
import resource
import subprocess
from pathlib import Path

os.environ.setdefault("HDVR_NO_PROGRESS", "1")
REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import numpy as np  # noqa: E402

from hdvr.camera import look_at, project  # noqa: E402
from hdvr.fitting.ablation import markdown_table, run_ablation  # noqa: E402
from hdvr.fitting.presets import FitSettings  # noqa: E402
from hdvr.fitting.sequence import fit_keypoints  # noqa: E402
from hdvr.io.atomic import write_text_atomic  # noqa: E402
from benchdoc import cpu_name, write_section  # noqa: E402
from hdvr.io.bvh import load_mocap_body25  # noqa: E402
from hdvr.io.keypoints2d import Keypoints2D  # noqa: E402
from hdvr.layouts import BODY25_NAMES  # noqa: E402
from hdvr.metrics import evaluate  # noqa: E402
from hdvr.plausibility import summarize_result  # noqa: E402
from hdvr.skeleton import Skeleton  # noqa: E402

IMAGE = (1920, 1080)
DATA = Path(os.environ.get("HDVR_SHARED_DATA", REPO.parent / "shared" / "data")) / "cmu-salsa"
CONDITIONS = ("clean", "noise3px", "drop10pct")
SPEED_TAKES = ("01", "02", "03", "04", "05")  # concatenated (both dancers) for the one- and two-minute clips


def random_camera(rng: np.random.Generator, centre_xy: np.ndarray):
    """(extrinsics, focal) of a random virtual camera around a dancer whose mean floor position is centre_xy."""
    focal = rng.uniform(1000, 2000)
    distance = rng.uniform(3, 8)
    azimuth = np.deg2rad(rng.uniform(0, 360))
    elevation = np.deg2rad(rng.uniform(-5, 30))
    target = np.array([centre_xy[0], centre_xy[1], 1.0])
    offset = distance * np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                                  np.sin(elevation)])
    return look_at(target + offset, target), float(focal)


def make_clip(mocap: np.ndarray, rng: np.random.Generator, condition: str):
    """(Keypoints2D, ground truth camera-frame (T, 25, 3), focal) for one clip and condition."""
    cam, focal = random_camera(rng, np.nanmean(mocap[:, BODY25_NAMES.index("mid_hip"), :2], axis=0))
    gt = cam.to_camera(mocap)
    uv = project(gt, focal, (IMAGE[0] / 2, IMAGE[1] / 2))
    conf = np.ones(uv.shape[:2])
    if condition == "noise3px":
        uv = uv + rng.normal(0, 3.0, uv.shape)
    elif condition == "drop10pct":
        drop = rng.random(conf.shape) < 0.10
        conf[drop] = 0.0
        uv[drop] = np.nan
    kp = np.concatenate([uv, conf[..., None]], axis=-1)
    return Keypoints2D(kp, BODY25_NAMES, 30.0, IMAGE), gt, focal


def fit_and_score(kp, gt, settings):
    skeleton = Skeleton()
    start = time.perf_counter()
    result, report = fit_keypoints(kp, settings, skeleton)
    seconds = time.perf_counter() - start
    row = evaluate(result.keypoints3d, gt)
    row.update(summarize_result(skeleton, result))
    row.update(frames=result.num_frames, seconds=seconds, frames_per_second=result.num_frames / seconds,
               peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
               peak_rss_worker_mb=resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
               focal_fit=report.focal, reinit=report.reinitialisations,
               reprojection_px=float(np.nanmean(result.reprojection_error_px)))
    return row


def fit_job(job) -> dict:
    """One accuracy row: (keypoints, ground truth, settings, labels) -> metrics and plausibility figures."""
    kp, gt, settings, labels = job
    row = fit_and_score(kp, gt, settings)
    row.update(labels)
    return row


def print_row(row: dict) -> None:
    """One result row as a JSON line (floats to 2 decimals), flushed: progress for long runs."""
    print(json.dumps({k: (round(v, 2) if isinstance(v, float) else v) for k, v in row.items()}), flush=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--takes", nargs="*", default=["01", "02", "03", "04", "05", "06", "07"],
                    help="salsa take numbers (both dancers each; default 01-07: 14 clips)")
    ap.add_argument("--seconds", type=float, default=10.0, help="seconds per clip (from 1 s into the take)")
    ap.add_argument("--conditions", nargs="*", default=list(CONDITIONS))
    ap.add_argument("--focal-modes", nargs="*", default=["given", "estimated"])
    ap.add_argument("--speed-seconds", type=float, default=60.0, help="length of the speed/memory clip")
    ap.add_argument("--speed-repeats", type=int, default=3, help="runs per speed clip; the median is reported")
    ap.add_argument("--ablate", action="store_true", help="also run the ablation table (clean, focal given)")
    ap.add_argument("--procs", type=int, default=1,
                    help="clips fitted at once for the accuracy and ablation tables (each fit then on one worker; "
                         "results are identical, their frames/s is per fit); the speed runs use every core")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--accuracy-from", default=None,
                    help="take the accuracy and ablation rows from this earlier --out-json (same code, clips and "
                         "options) and measure only speed and memory again, e.g. once the machine is quiet")
    ap.add_argument("--speed-only", type=float, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--figures", action="store_true", help="write docs/img/fitting_skeleton.png and _error.png")
    ap.add_argument("--out-json", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "hdvr_bench_fit3d.json"),
                    help="all rows, per clip (default: in the temporary folder)")
    ap.add_argument("--out-md", default=str(REPO / "docs" / "benchmarks.md"))
    args = ap.parse_args()

    if not DATA.is_dir():
        print(f"mocap folder {DATA} is absent", file=sys.stderr)
        return 2
    mocap = {}
    for take in args.takes:
        for subject in ("60", "61"):
            pos, _ = load_mocap_body25(DATA / f"{subject}_{take}_scaled.bvh", fps=30)
            mocap[f"{subject}_{take}"] = pos
    if args.speed_only is not None:  # child process: one speed/memory run, JSON on stdout
        pos = np.concatenate([mocap[k] for k in mocap])[: int(args.speed_only * 30)]
        kp, gt, focal = make_clip(pos, np.random.default_rng(args.seed), "clean")
        row = fit_and_score(kp, gt, FitSettings(focal=focal))
        row.update(clip=f"{len(pos) / 30:.0f} s of salsa", condition="clean", focal="given")
        print("SPEED " + json.dumps(row, default=float))
        return 0
    if args.figures:
        name = next(iter(mocap))
        figures(mocap[name][30:30 + int(args.seconds * 30)], name, args.seed)
    rows = []
    clips_clean = []
    jobs = []
    for condition in args.conditions:
        for name, pos in mocap.items():
            clip = pos[30:30 + int(args.seconds * 30)]
            kp, gt, focal = make_clip(clip, np.random.default_rng([args.seed, int(name.replace("_", ""))]), condition)
            if condition == "clean":
                clips_clean.append((name, kp, gt, focal))
            for mode in args.focal_modes:
                settings = FitSettings(focal=focal if mode == "given" else None, random_seed=args.seed,
                                       workers=1 if args.procs > 1 else None)
                jobs.append((kp, gt, settings, dict(clip=name, condition=condition, focal=mode, focal_true=focal)))
    earlier = json.loads(Path(args.accuracy_from).read_text()) if args.accuracy_from else None
    if earlier is not None:
        rows = earlier["rows"]
    else:
        with multiprocessing.Pool(max(1, args.procs)) as pool:
            for row in pool.imap(fit_job, jobs):
                rows.append(row)
                print_row(row)

    # speed and memory: one-minute and two-minute clips (clean, focal given), each in a fresh process so that the
    # peak resident memory (ru_maxrss) is that fit's
    speed = []
    for seconds in (args.speed_seconds, 2 * args.speed_seconds):
        runs = []
        for _ in range(max(1, args.speed_repeats)):
            cmd = [sys.executable, __file__, "--speed-only", str(seconds), "--seed", str(args.seed), "--takes",
                   *SPEED_TAKES]
            out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
            runs.append(json.loads(next(line for line in out.splitlines() if line.startswith("SPEED "))[6:]))
            print_row(runs[-1])
        runs.sort(key=lambda r: r["frames_per_second"])
        row = dict(runs[(len(runs) - 1) // 2])  # the median run (the lower middle one for an even count)
        row["frames_per_second_runs"] = [r["frames_per_second"] for r in runs]
        row["peak_rss_mb"] = max(r["peak_rss_mb"] for r in runs)
        row["peak_rss_worker_mb"] = max(r.get("peak_rss_worker_mb", 0.0) for r in runs)
        speed.append(row)

    ablation = None if earlier is None else earlier["ablation"]
    if args.ablate and earlier is None:
        clips = [(n, kp, gt) for n, kp, gt, _ in clips_clean]
        ablation = run_ablation(clips, ["full", "no_joint_limits", "no_bone_prior", "no_temporal", "no_pose_prior",
                                        "no_upright", "no_limb_depth", "physics", "paper"],
                                FitSettings(random_seed=args.seed), focal_per_clip=[f for *_, f in clips_clean],
                                processes=max(1, args.procs))

    reference = mocap_reference(mocap, args.seconds)
    summary = summarise(rows)
    Path(args.out_json).parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(args.out_json, json.dumps({"rows": rows, "speed": speed, "ablation": ablation,
                                                 "summary": summary, "reference": reference, "machine": machine()}, indent=1,
                                                default=float))
    write_section(Path(args.out_md), "## 3D fitting", markdown(summary, speed, ablation, args, reference))
    print(f"wrote {args.out_md} and {args.out_json}")
    return 0


def figures(clip: np.ndarray, name: str, seed: int) -> None:
    """A fitted frame beside the mocap (two views) and the per-frame error over the clip."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hdvr.layouts import BODY25_BONES, EVAL_JOINTS
    from hdvr.metrics import procrustes_align, root_relative

    kp, gt, focal = make_clip(clip, np.random.default_rng([seed, int(name.replace("_", ""))]), "clean")
    result, _ = fit_keypoints(kp, FitSettings(focal=focal, random_seed=seed), Skeleton())
    pred, ref = root_relative(result.keypoints3d), root_relative(gt)
    err = np.linalg.norm(pred - ref, axis=-1).mean(axis=1) * 1000
    perr = np.linalg.norm(procrustes_align(pred, ref) - ref, axis=-1).mean(axis=1) * 1000
    out = REPO / "docs" / "img"
    out.mkdir(parents=True, exist_ok=True)
    t = int(np.argsort(err)[len(err) // 2])  # a median frame
    fit_t = result.keypoints3d[t] - result.keypoints3d[t, 8]
    gt_t = gt[t] - gt[t, 8]
    fig, axes = plt.subplots(1, 2, figsize=(9, 5))
    for ax, (i, j, title) in zip(axes, ((0, 1, "camera view (x right, y down)"), (2, 1, "side view (z = depth)"))):
        for a, b in BODY25_BONES:
            ia, ib = BODY25_NAMES.index(a), BODY25_NAMES.index(b)
            ax.plot(gt_t[[ia, ib], i], gt_t[[ia, ib], j], color="0.6", lw=3)
            ax.plot(fit_t[[ia, ib], i], fit_t[[ia, ib], j], color="tab:red", lw=1.5)
        ax.set_title(title)
        ax.set_aspect("equal")
        ax.invert_yaxis()
        ax.set_xlabel("m")
    axes[0].plot([], [], color="0.6", lw=3, label="mocap")
    axes[0].plot([], [], color="tab:red", lw=1.5, label="fit3d")
    axes[0].legend(loc="lower left")
    fig.suptitle(f"salsa {name}, frame {t}: MPJPE {err[t]:.0f} mm (median frame)")
    fig.tight_layout()
    fig.savefig(out / "fitting_skeleton.png", dpi=80)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(9, 3.2))
    ax.plot(np.arange(len(err)) / 30.0, err, label="MPJPE")
    ax.plot(np.arange(len(err)) / 30.0, perr, label="P-MPJPE")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"error on {len(EVAL_JOINTS)} joints (mm)")
    ax.set_title(f"salsa {name}, clean 2D, focal given: per-frame error")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "fitting_error.png", dpi=80)
    plt.close(fig)


def machine() -> str:
    """CPU, cores, Python and the load average when the results were written (the speed rows depend on it)."""
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    return (f"{cpu_name()}, {os.cpu_count()} CPU cores, Python {platform.python_version()}; load average "
            f"(1, 5, 15 min) at the end of the run {load}")


def summarise(rows):
    out = []
    keys = sorted({(r["condition"], r["focal"]) for r in rows}, key=lambda k: (CONDITIONS.index(k[0]), k[1]))
    for cond, mode in keys:
        sel = [r for r in rows if r["condition"] == cond and r["focal"] == mode]
        med = {k: float(np.median([r[k] for r in sel])) for k in (
            "mpjpe_mm", "p_mpjpe_mm", "n_mpjpe_mm", "mpjve_mm", "accel_error_mm", "foot_penetration_p95_cm",
            "foot_skating_mean_cm_s", "self_penetration_frames_pct", "limit_violations", "bone_cv_max_pct",
            "jitter_m_s3", "frames_per_second", "reprojection_px")}
        med.update(condition=cond, focal=mode, clips=len(sel),
                   mpjpe_mean_mm=float(np.mean([r["mpjpe_mm"] for r in sel])),
                   p_mpjpe_mean_mm=float(np.mean([r["p_mpjpe_mm"] for r in sel])),
                   p_mpjpe_range_mm=(float(np.min([r["p_mpjpe_mm"] for r in sel])),
                                     float(np.max([r["p_mpjpe_mm"] for r in sel]))))
        out.append(med)
    return out


def mocap_reference(mocap: dict, seconds: float) -> dict:
    """Plausibility figures of the mocap itself (same clips; its soles are derived points), for scale."""
    from hdvr.plausibility import bone_length_cv, foot_penetration, foot_skating, jitter

    clips = [pos[30:30 + int(seconds * 30)] for pos in mocap.values()]
    return {"foot_penetration_p95_cm": float(np.median([np.percentile(foot_penetration(c), 95) * 100 for c in clips])),
            "foot_skating_mean_cm_s": float(np.nanmedian([foot_skating(c, 30.0, contact_m=0.05).mean() * 100
                                                       if len(foot_skating(c, 30.0, contact_m=0.05)) else np.nan
                                                       for c in clips])),
            "bone_cv_max_pct": float(np.median([max(bone_length_cv(c).values()) * 100 for c in clips])),
            "jitter_m_s3": float(np.median([jitter(c, 30.0) for c in clips]))}


def markdown(summary, speed, ablation, args, reference) -> str:
    lines = ["## 3D fitting", "",
             f"`hdvr fit3d` on CMU salsa mocap (takes {', '.join(args.takes)}, lead 60_XX and follow 61_XX: "
             f"{2 * len(args.takes)} clips of {args.seconds:.0f} s at 30 fps), each seen by a random virtual camera "
             "(1920x1080, focal 1000-2000 px, 3-8 m, azimuth 0-360 deg, elevation -5-30 deg). Medians over clips; "
             "errors in mm on EVAL_JOINTS, root-relative (MPJPE = Protocol 1, P-MPJPE = Protocol 2). "
             f"Machine: {machine()}. Command: `python3 scripts/bench_fit3d.py {' '.join(sys.argv[1:])}`. "
             "Single clips move by a few mm with any change to the fit; the means (and the P-MPJPE range over clips) "
             "are given beside the medians."
             + (f" The accuracy and ablation tables fitted {args.procs} clips at once, each on one worker: their "
                "frames/s is per fit; the speed table below measures speed." if args.procs > 1 else ""), "",
             "| 2D input | focal | clips | MPJPE | P-MPJPE | MPJPE (mean) | P-MPJPE (mean) | P-MPJPE range | N-MPJPE | "
             "MPJVE | accel err | reproj px | "
             "foot pen. p95 cm | skating cm/s | self-pen. % frames | limit viol. | bone CV % | jitter m/s^3 | "
             "frames/s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in summary:
        lines.append(f"| {s['condition']} | {s['focal']} | {s['clips']} | {s['mpjpe_mm']:.1f} | "
                     f"{s['p_mpjpe_mm']:.1f} | {s['mpjpe_mean_mm']:.1f} | {s['p_mpjpe_mean_mm']:.1f} | "
                     f"{s['p_mpjpe_range_mm'][0]:.0f}-{s['p_mpjpe_range_mm'][1]:.0f} | {s['n_mpjpe_mm']:.1f} | "
                     f"{s['mpjve_mm']:.1f} | "
                     f"{s['accel_error_mm']:.1f} | {s['reprojection_px']:.2f} | {s['foot_penetration_p95_cm']:.2f} | "
                     f"{s['foot_skating_mean_cm_s']:.1f} | {s['self_penetration_frames_pct']:.1f} | "
                     f"{s['limit_violations']:.0f} | {s['bone_cv_max_pct']:.3f} | {s['jitter_m_s3']:.0f} | "
                     f"{s['frames_per_second']:.1f} |")
    lines += ["", f"For scale, the mocap itself (same clips, 30 fps): foot penetration p95 "
              f"{reference['foot_penetration_p95_cm']:.2f} cm, skating {reference['foot_skating_mean_cm_s']:.1f} cm/s "
              f"(contact below 5 cm: its soles are derived points 1-3 cm above the floor), bone CV {reference['bone_cv_max_pct']:.2f} %, jitter "
              f"{reference['jitter_m_s3']:.0f} m/s^3."]
    lines += ["", "Speed and memory (clean 2D, focal given, K = 2, Delta = 3, default chunks of 900 frames fitted by "
              "one worker process per core; one fresh process per run, the median of the runs reported; peak "
              "resident memory of the main process and of the largest worker):",
              "", "| clip | frames | frames/s (median) | runs, frames/s | peak RSS MB (main / worker) | MPJPE | P-MPJPE |",
              "|---|---|---|---|---|---|---|"]
    for s in speed:
        runs = ", ".join(f"{v:.1f}" for v in s.get("frames_per_second_runs", [s["frames_per_second"]]))
        lines.append(f"| {s['clip']} | {s['frames']} | {s['frames_per_second']:.1f} | {runs} | "
                     f"{s['peak_rss_mb']:.0f} / "
                     f"{s.get('peak_rss_worker_mb', 0.0):.0f} | {s['mpjpe_mm']:.1f} | {s['p_mpjpe_mm']:.1f} |")
    if ablation:
        lines += ["", "Ablations (clean 2D, focal given, same clips; medians over clips, and means of MPJPE and "
                  "P-MPJPE):", "",
                  markdown_table(ablation).rstrip()]
    lines += ["", "![fit vs mocap](img/fitting_skeleton.png)", "", "![per-frame error](img/fitting_error.png)", "",
              "Reproduce (2 CPU cores):", "", "```",
              f"python3 scripts/bench_fit3d.py --takes {' '.join(args.takes)} --seconds {args.seconds:g}"
              + (f" --procs {args.procs}" if args.procs > 1 else "")
              + (" --ablate" if args.ablate else "") + (" --figures" if args.figures else ""), "```", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
