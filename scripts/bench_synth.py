"""Benchmark of the synthetic data pipeline; writes the "## Synthetic data" section of docs/benchmarks.md.

Measures (medians over repeats, on this machine):

1. Rendering: a 2-dancer clip at 640x480 through the whole per-frame pipeline of ``hdvr synth`` (scene update,
   RGB render, half-resolution segmentation render where dancers overlap, keypoint visibility, H.264 encoding in
   a thread); frames per second of the frame loop (wall clock, and per CPU-second of the process: a lower bound
   of the rate on 2 dedicated cores), and of the whole clip including motion generation, scene compilation and
   file writing.
2. ``--no-render``: frames per second of a whole 2-dancer clip (motion, labels, camera, projection, boxes, files).
3. Scenes (:func:`bench_scenes`): inter-dancer penetration, closest approach, floor paths per genre.
4. Pose detector on rendered clips (:func:`detector_check`): how often YOLO11n-pose finds the dancers.
5. The labeller against the generator's declared labels (:func:`hdvr.synth.evaluate.evaluate_labeller`):
   per-part micro and macro F-scores, labels never produced, joint-limit violations, foot penetration and
   skating; clean and with 2 mm / 5 mm keypoint noise.

Usage: ``python3 scripts/bench_synth.py [--quick] [--no-detector-check] [--write docs/benchmarks.md]``
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HDVR_NO_PROGRESS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hdvr.synth.evaluate import evaluate_labeller  # noqa: E402
from hdvr.synth.groundtruth import clip_spec, make_clip  # noqa: E402
from benchdoc import cpu_name, write_section  # noqa: E402


def machine() -> str:
    cpu = cpu_name()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{os.cpu_count()} CPU cores ({cpu}), {platform.system()} {platform.release()}, load average {load:.1f}"


def bench_render(repeats: int, seconds: float) -> dict:
    """Wall-clock frame rate of the render loop, and frames per CPU-second of it (all threads of the process:
    llvmpipe's and the encoder's). On a machine shared with other jobs the wall rate drops; the CPU rate does
    not, and it is a lower bound of the wall rate on 2 dedicated cores (wall time <= CPU time there)."""
    loop, whole, cpu, occluded = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(repeats):
            spec = clip_spec(r, 100, ("tango", "ballet", "hip_hop"), (2, 2), seconds)
            t0 = time.perf_counter()
            meta = make_clip(tmp, spec, render=True)
            whole.append(meta["frames"] / (time.perf_counter() - t0))
            loop.append(meta["render_fps"])
            cpu.append(meta["frames"] / meta["render_cpu_seconds"])
            occluded.append(meta["occluded_fraction"])
    return {"loop_fps": statistics.median(loop), "clip_fps": statistics.median(whole), "all_loop": loop,
            "cpu_fps": statistics.median(cpu), "all_cpu": cpu, "occluded": occluded}


def bench_scenes(clips_per_genre: int, seconds: float, seed: int = 11) -> dict:
    """Motion-only clips of every genre with 2-4 dancers: the deepest penetration between two dancers' geoms
    (MuJoCo contacts), the closest approach of two dancers' geoms (capsule surface distance is not measured:
    root-to-root distance instead), and the floor paths: root path length and largest distance from the start
    per genre (metres)."""
    import numpy as np

    from hdvr.synth.genres import GENRES

    pen, closest, paths = 0.0, np.inf, {}
    with tempfile.TemporaryDirectory() as tmp:
        for gi, genre in enumerate(GENRES):
            for c in range(clips_per_genre):
                spec = clip_spec(gi * clips_per_genre + c, seed, (genre,), (2, 4), seconds)
                meta = make_clip(tmp, spec, render=False)
                pen = max(pen, meta["inter_dancer_penetration_m"])
                q = np.load(Path(tmp) / spec.name / "gt.npz")["qpos"]
                for a in range(q.shape[0]):
                    for b in range(a + 1, q.shape[0]):
                        closest = min(closest, float(np.linalg.norm(q[a, :, :2] - q[b, :, :2], axis=1).min()))
                step = np.linalg.norm(np.diff(q[:, :, :2], axis=1), axis=-1).sum(1)
                reach = np.linalg.norm(q[:, :, :2] - q[:, :1, :2], axis=-1).max(1)
                paths.setdefault(genre, []).append((float(step.mean()), float(reach.max())))
    return {"penetration_m": pen, "closest_roots_m": closest,
            "paths": {g: (max(p for p, _ in v), max(r for _, r in v)) for g, v in paths.items()},
            "clips": clips_per_genre * len(GENRES), "seconds": seconds}


def bench_no_render(repeats: int, seconds: float) -> dict:
    """Frames per second of whole motion-only clips (wall clock), and per CPU-second of the process (the work is
    single-threaded: the rate on a dedicated core)."""
    fps, cpu = [], []
    with tempfile.TemporaryDirectory() as tmp:
        make_clip(tmp, clip_spec(99, 200, ("tango",), (2, 2), 2.0), render=False)  # imports, caches
        for r in range(repeats):
            spec = clip_spec(r, 200, ("tango", "ballet", "belly_dance", "swing"), (2, 2), seconds)
            t0, c0 = time.perf_counter(), time.process_time()
            meta = make_clip(tmp, spec, render=False)
            fps.append(meta["frames"] / (time.perf_counter() - t0))
            cpu.append(meta["frames"] / (time.process_time() - c0))
    return {"clip_fps": statistics.median(fps), "all": fps, "cpu_fps": statistics.median(cpu), "all_cpu": cpu}


def _iou(a, b) -> float:
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[0] + a[2], b[0] + b[2]), min(a[1] + a[3], b[1] + b[3])
    inter = max(0.0, x1 - x0) * max(0.0, y1 - y0)
    union = a[2] * a[3] + b[2] * b[3] - inter
    return inter / union if union > 0 else 0.0


def detector_check(seconds: float = 3.0, stride: int = 3, seed: int = 7, genres=None, clips_per_genre: int = 2) -> dict:
    """How human the rendered dancers look to a COCO-trained pose detector (YOLO11n-pose, the pipeline's
    default): per genre, ``clips_per_genre`` rendered 2-dancer clips of ``seconds``; on every ``stride``-th frame, the fraction of
    ground-truth dancers (box at least 24 x 48 px, at least 60 % of keypoints in the image) that a detected
    person matches (box IoU >= 0.5, greedy), and the fraction of frames with at least one pose found."""
    import numpy as np

    from hdvr.pipeline import make_detector
    from hdvr.synth.dataset import read_frames
    from hdvr.synth.genres import GENRES

    det = make_detector()
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for genre in genres or GENRES:
            found = total = any_pose = n_frames = 0
            for c in range(clips_per_genre):
                spec = clip_spec(GENRES.index(genre) * clips_per_genre + c, seed, (genre,), (2, 2), seconds)
                make_clip(tmp, spec, render=True)
                folder = Path(tmp) / spec.name
                gt = np.load(folder / "gt.npz")
                frames = read_frames(folder / "video.mp4", 0, int(gt["boxes"].shape[1]))
                for t in range(0, frames.shape[0], stride):
                    people = det.detect(np.ascontiguousarray(frames[t][..., ::-1]), t)
                    n_frames += 1
                    any_pose += bool(people)
                    used = set()
                    for k in range(gt["boxes"].shape[0]):
                        box = gt["boxes"][k, t]
                        if (not np.isfinite(box).all() or box[2] < 24 or box[3] < 48
                                or (gt["visibility"][k, t] > 0).mean() < 0.6):
                            continue
                        total += 1
                        ious = [(_iou(box, p.box), i) for i, p in enumerate(people) if i not in used]
                        best = max(ious, default=(0.0, -1))
                        if best[0] >= 0.5:
                            found += 1
                            used.add(best[1])
            out[genre] = {"recall": found / max(total, 1), "frames_with_pose": any_pose / max(n_frames, 1),
                          "dancer_frames": total}
            print(f"detector {genre}: dancers found {out[genre]['recall']:.2f}, frames with a pose "
                  f"{out[genre]['frames_with_pose']:.2f} ({total} dancer-frames)", flush=True)
    return out


def table(report: dict) -> list[str]:
    rows = ["| part | micro F1 | macro F1 |", "|---|---|---|"]
    for part, micro in report["per_part_micro_f1"].items():
        rows.append(f"| {part} | {micro:.3f} | {report['per_part_macro_f1'][part]:.3f} |")
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats and shorter clips")
    ap.add_argument("--write", help="markdown file to write the section to (replaces it)")
    ap.add_argument("--no-detector-check", dest="detector", action="store_false",
                    help="skip the pose-detector check on rendered clips (needs the YOLO11n-pose weights)")
    args = ap.parse_args()
    reps = 2 if args.quick else 3
    render = bench_render(reps, 4.0 if args.quick else 10.0)
    print(f"render: loop {render['loop_fps']:.1f} fps wall, {render['cpu_fps']:.1f} frames per CPU-s, whole clip "
          f"{render['clip_fps']:.1f} fps", flush=True)
    norender = bench_no_render(reps + 2, 20.0)
    print(f"no-render: {norender['clip_fps']:.0f} fps wall, {norender['cpu_fps']:.0f} per CPU-s", flush=True)
    scenes = bench_scenes(1 if args.quick else 2, 10.0)
    print(f"scenes: inter-dancer penetration {scenes['penetration_m'] * 100:.2f} cm", flush=True)
    detection = detector_check(2.0 if args.quick else 3.0) if args.detector else None
    secs, per_genre = (30.0, 2) if args.quick else (60.0, 2)
    clean = evaluate_labeller(seconds=secs, clips_per_genre=per_genre, seed=0)
    noisy = evaluate_labeller(seconds=secs, clips_per_genre=per_genre, seed=0, noise_m=0.002, smoothing_s=0.2)
    noisy5 = evaluate_labeller(seconds=secs, clips_per_genre=per_genre, seed=0, noise_m=0.005, smoothing_s=0.3)
    print("clean micro", {k: round(v, 3) for k, v in clean["per_part_micro_f1"].items()}, flush=True)
    print("noisy micro", {k: round(v, 3) for k, v in noisy["per_part_micro_f1"].items()}, flush=True)
    low = sorted(((k, v, clean["support"][k]) for k, v in clean["per_label_f1"].items() if v < 0.9),
                 key=lambda x: x[1])
    lines = [
        "## Synthetic data",
        "",
        f"Measured by `python3 scripts/bench_synth.py{' --quick' if args.quick else ''} --write docs/benchmarks.md` "
        f"on {machine()} (the machine is shared: other jobs ran at the same time, so speeds are lower bounds).",
        "",
        "| measure | median | target |",
        "|---|---|---|",
        f"| rendering, 2-dancer scene, 640x480, frame loop (RGB + segmentation + visibility + H.264): frames per "
        f"CPU-second of the process (= lower bound of frames/s on 2 dedicated cores) | {render['cpu_fps']:.1f} "
        f"(runs: {', '.join(f'{v:.1f}' for v in render['all_cpu'])}) | >= 20 |",
        f"| same, wall clock on this shared machine | {render['loop_fps']:.1f} frames/s "
        f"(runs: {', '.join(f'{v:.1f}' for v in render['all_loop'])}) | |",
        f"| rendering, whole clip incl. motion, scene compile, files | {render['clip_fps']:.1f} frames/s | |",
        f"| `--no-render`, 2-dancer clip, whole clip incl. files (motion, declared labels, collision check, "
        f"camera, projection, files): frames per CPU-second (single-threaded: the rate on a dedicated core) | "
        f"{norender['cpu_fps']:.0f} (runs: {', '.join(f'{v:.0f}' for v in norender['all_cpu'])}) | >= 2000 |",
        f"| same, wall clock on this shared machine | {norender['clip_fps']:.0f} frames/s "
        f"(runs: {', '.join(f'{v:.0f}' for v in norender['all'])}) | |",
        f"| joint-limit violations ({clean['frames']} frames, 9 genres) | {clean['joint_limit_violation_rad']:.3g} rad "
        f"| 0 |",
        f"| foot penetration | {clean['foot_penetration_m'] * 100:.2f} cm | <= 1 cm |",
        f"| skating of weight-bearing feet (max) | {clean['foot_skate_max_m_s'] * 100:.2f} cm/s | 0 |",
        f"| skating of any foot in contact, incl. gesture feet brushing the floor (max) | "
        f"{clean['foot_skate_all_feet_max_m_s'] * 100:.1f} cm/s | |",
        f"| labels never produced by the generator | {len(clean['missing_labels'])} of 154 "
        f"{clean['missing_labels'] if clean['missing_labels'] else ''} | 0 |",
        f"| deepest penetration between two dancers' body geoms (MuJoCo contacts, {scenes['clips']} clips x "
        f"{scenes['seconds']:.0f} s, 2-4 dancers, every frame) | {scenes['penetration_m'] * 100:.2f} cm | <= 1 cm |",
        f"| closest approach of two dancers' roots (pelvis) | {scenes['closest_roots_m']:.2f} m | |",
        f"| keypoints occluded by another dancer in the rendered 2-dancer clips (of those in the image) | "
        f"{', '.join(f'{100 * v:.0f} %' for v in render['occluded'])} | > 0 (dancers occlude each other) |",
        "",
        "Floor paths (root path length and farthest distance from the start, largest dancer of the clips, m): "
        + ", ".join(f"{g} {p:.1f} / {r:.1f}" for g, (p, r) in scenes["paths"].items()) + ".",
        "",
        *(["Pose detector on rendered clips (YOLO11n-pose, the pipeline's default; two 2-dancer clips of "
           f"{2.0 if args.quick else 3.0:.0f} s per genre, every 3rd frame): dancers found = ground-truth dancers "
           "(box >= 24 x 48 px, >= 60 % of keypoints in the image) matched by a detection with box IoU >= 0.5.",
           "",
           "| genre | dancers found | frames with a pose |", "|---|---|---|",
           *[f"| {g} | {v['recall']:.2f} | {v['frames_with_pose']:.2f} |" for g, v in detection.items()],
           f"| mean | {sum(v['recall'] for v in detection.values()) / len(detection):.2f} | "
           f"{sum(v['frames_with_pose'] for v in detection.values()) / len(detection):.2f} |", ""]
          if detection else []),
        f"Labeller vs the labels the generator's primitives declare (hdvr.synth.declare: intents and planned "
        f"trajectories, not the labeller; see docs/movements.md), per part ({clean['frames']} frames: 9 genres x "
        f"{per_genre} dancers x {secs:.0f} s, random stature 1.5-1.9 m, keypoints in a random camera frame). One "
        "label per part and frame, so micro F1 = frame accuracy; macro F1 = mean F1 of the labels that occur. "
        "Target: >= 0.95 per part.",
        "",
        "Clean keypoints:",
        "",
        *table(clean),
        "",
        "With 2 mm Gaussian noise on every keypoint coordinate (labeller smoothing 0.2 s instead of 0.1 s; the "
        "reference labels stay those of the clean motion):",
        "",
        *table(noisy),
        "",
        "With 5 mm noise (smoothing 0.3 s): per-part micro F1 "
        + ", ".join(f"{k} {v:.2f}" for k, v in noisy5["per_part_micro_f1"].items())
        + ". The labeller needs clean 3D (mocap-grade) input; noisy fitted 3D needs smoothing first.",
        "",
        "Labels below F1 0.9 on clean keypoints (label, F1, frames): "
        + (", ".join(f"{k} {v:.2f} ({n})" for k, v, n in low) if low else "none") + ".",
        "",
    ]
    text = "\n".join(lines)
    print(text)
    if args.write:
        write_section(Path(args.write), "## Synthetic data", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
