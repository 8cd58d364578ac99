#!/usr/bin/env python3
"""Benchmark of ``hdvr track``: speed, what a cheaper detector setting costs in accuracy, memory vs video length.

Runs on this machine's CPU with the detector limited to 2 threads (the target machine has 2 cores). Writes a
markdown section (``## Tracking and 2D pose``) to stdout and, with ``--markdown PATH``, to that file.

1. Speed: a procedural 640x480 clip with 2 dancers that cross (hdvr.tracking.testclips), full ``track_video``
   (decode, detector, Algorithm 1* and 2*, overlay H.264 encode, outputs), median frames/s over ``--repeats`` runs
   for each detector setting (input size, every k-th frame). Load average is printed: other processes on the
   machine slow every wall-clock figure down. Frames per CPU second (this process's CPU time, all threads) is
   also given: it hardly depends on other load, and on an otherwise idle machine the wall-clock rate is at
   least that high (the detector's 2 threads overlap).
2. Accuracy: per setting, MOTA/IDF1/HOTA/ID switches of the tracks against the clip's ground truth (trackeval),
   and PCK@0.2 of the 2D keypoints against the reference setting (640 px input on every frame) on the real video
   ../shared/data/video/two-people-tree (scaled to 640 px wide), dancers found automatically once.
3. Memory: peak resident memory of ``hdvr track`` (own process) on a short and a 4x longer clip.
4. Detector alone: PCK@0.2 of each input size's poses against the 640 px poses on the same frames of the real
   video (poses matched by box overlap; a reference pose without a match counts as all wrong), separating the
   cost of the smaller input from that of tracking and interpolation.
5. Identity: procedural crossing clips with 2, 3 and 4 dancers over several seeds (``--seeds``), tracker alone
   and full ``track_video`` with the default detector setting; IDF1, MOTA, HOTA, identity switches per seed and
   the median. ``troupe``: the same for groups of 6 and 8 dancers in two rows (``troupe_specs``).
6. Synthetic dancers: small multi-dancer clips rendered by ``hdvr.synth`` (couple and group genres, 2-4
   dancers) in a temporary folder, tracked from their ground-truth first boxes and scored against their MOT
   ground truth; per clip also the fraction of detector frames in which each dancer got a pose, at two detector
   confidence thresholds, and PCK@0.2 of each dancer's keypoints against its visible ground-truth keypoints.
   ``crowd``: the same for groups of ``--synth-crowd`` dancers (default 6 and 8) in four group genres.
   To measure one tracker rule on many clips: render them once into ``--clips-dir``, run once with the defaults
   and once with ``--tracker-config NAME=VALUE`` (e.g. ``reid_from_holder=false``), each with ``--per-clip-json``,
   and list the clips that changed with ``scripts/compare_track_runs.py``. ``--synth-detector truth`` runs the
   tracker on a perfect detector instead (:class:`hdvr.synth.truth_detector.GroundTruthDetector`: every dancer
   showing enough of its keypoints, its box the visible part of its body; ``truth-amodal``: its whole ground-truth
   box, hidden parts included): what fails with it is the tracker's own doing, the rest the detector's.
7. ``cache``: the speed clip tracked once with a detections cache (``hdvr track``'s ``detections.npz``) and then
   ``--repeats`` times again from it, as after a user's correction: frames/s of both, and whether the outputs are
   the same.

Usage: python3 scripts/bench_track.py [--repeats 3] [--quick] [--seeds 6] [--seed-start 0]
                                      [--synth-seeds 7,11,23] [--synth-thresholds 0.3,0.15]
                                      [--sections speed,real,memory,detector,identity,troupe,synth,cache]
                                      [--clips-dir DIR] [--tracker-config NAME=VALUE,...]
                                      [--synth-detector yolo|truth|truth-amodal]
                                      [--per-clip-json FILE] [--markdown docs/benchmarks.md]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
os.environ.setdefault("HDVR_NO_PROGRESS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")  # hdvr.synth renders headless

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from hdvr.pose2d.models import default_pose_model  # noqa: E402
from hdvr.pipeline import WEAK_DETECTION_THRESHOLD  # noqa: E402
from hdvr.pose2d.onnx_pose import OnnxPoseDetector  # noqa: E402
from hdvr.layouts import COCO17_NAMES  # noqa: E402
from hdvr.tracking.evaluation import (  # noqa: E402
    MISS_CAUSES, VISIBILITY_CLASSES, body25_joints_of, evaluate_tracking, miss_causes, pck, visible_truth_keypoints)
from hdvr.tracking.multi import MultiTrackerConfig  # noqa: E402
from hdvr.tracking.pipeline import DancerStart, find_dancers, track_video  # noqa: E402
from hdvr.tracking.testclips import default_crossing_specs, render_clip, troupe_specs  # noqa: E402
from hdvr.video import VideoReader, VideoWriter  # noqa: E402
from benchdoc import cpu_name  # noqa: E402

SETTINGS = [(640, 1), (320, 1), (320, 2), (320, 3), (256, 2)]  # (detector input px, detector every k frames)
REAL_VIDEO = REPO.parent / "shared" / "data" / "video" / "two-people-tree" / "video.mp4"


def scaled_copy(src: Path, dst: Path, width: int = 640) -> None:
    reader = VideoReader(src)
    w, h = reader.info.size
    size = (width, int(round(h * width / w / 2)) * 2)
    with VideoWriter(dst, reader.info.fps, size, crf=18) as writer:
        for frame in reader:
            writer.write(cv2.resize(frame, size, interpolation=cv2.INTER_AREA))


def peak_rss_mb(video: Path, out: Path, boxes: str) -> float:
    code = ("import resource, sys; from hdvr.cli import main; "
            f"rc = main(['track', {str(video)!r}, '--out', {str(out)!r}, '--boxes', {boxes!r}, "
            "'--detect-every', '2', '--threads', '2']); "
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)")
    proc = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(REPO), HDVR_NO_PROGRESS="1"), check=True)
    return float(proc.stdout.strip().splitlines()[-1])


class TrackingModel(NamedTuple):
    """The pose model (ONNX file) the tracking sections run, the threshold down to which their detectors
    report weak finds (``--weak-threshold``; as ``hdvr track`` by default), and whether they look at the mirrored
    frame too (``--flip-test``, as ``hdvr track --flip-test``)."""

    path: Path
    weak_threshold: float = WEAK_DETECTION_THRESHOLD
    flip_test: bool = False


def tracking_detector(model: TrackingModel, size: int = 480, score_threshold: float = 0.3) -> OnnxPoseDetector:
    """The detector a tracking section runs, with weak finds as ``hdvr track`` has them (``model.weak_threshold``)."""
    return OnnxPoseDetector(model.path, input_size=size, threads=2, score_threshold=score_threshold,
                            weak_threshold=min(model.weak_threshold, score_threshold), flip_test=model.flip_test)


def default_tracking_detector() -> OnnxPoseDetector:
    """The synth section's detector with the default model and settings (YOLO11n-pose at 480 px, sure 0.3, weak
    finds as ``hdvr track``, no flip test): the one the helper scripts track and measure with."""
    return tracking_detector(TrackingModel(default_pose_model()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--frames", type=int, default=300, help="length of the procedural clip")
    parser.add_argument("--quick", action="store_true", help="1 repeat, 150 frames, no memory test")
    parser.add_argument("--markdown", type=Path, help="also write the markdown section to this file")
    parser.add_argument("--settings", help="detector settings SIZExEVERY, comma-separated (default "
                        + ",".join(f"{a}x{b}" for a, b in SETTINGS) + "); the first is the reference")
    parser.add_argument("--sections", default="speed,real,memory,detector,identity,troupe,synth",
                        help="comma-separated subset of speed, real, memory, detector, identity, troupe, synth, "
                             "crowd, zoom")
    parser.add_argument("--seeds", type=int, default=6, help="procedural clips per dancer count (identity)")
    parser.add_argument("--seed-start", type=int, default=0, help="first seed of the identity clips (seeds 0-5 "
                        "were used while tuning; 6 and up are held out)")
    parser.add_argument("--synth-seeds", default="7", help="comma-separated seeds of the synthetic clips (synth; "
                        "7 was used while tuning, 11 and 23 are held out)")
    parser.add_argument("--synth-crowd", default="6,8", help="comma-separated dancer counts of the synthetic group "
                        "clips (crowd: ballet, hip-hop, flamenco and tap groups, beyond hdvr synth's 1-4)")
    parser.add_argument("--synth-thresholds", default="0.3,0.15",
                        help="comma-separated detector confidence thresholds for the synthetic clips (synth)")
    parser.add_argument("--clips-dir", type=Path, help="render the synthetic clips (synth, crowd) into this folder "
                        "and reuse those already there (default: a fresh temporary folder)")
    parser.add_argument("--synth-detector", choices=("yolo", "truth", "truth-amodal"), default="yolo",
                        help="synth, crowd: YOLO11n-pose (default), or the clip's ground truth as a perfect detector "
                             "(hdvr.synth.truth_detector: the visible part of each dancer as its box, or with "
                             "truth-amodal its whole ground-truth box; --synth-thresholds is then not used)")
    parser.add_argument("--tracker-config", default="", help="identity, troupe, synth, crowd: MultiTrackerConfig "
                        "fields to change, "
                        "e.g. reid_from_holder=false,reid_margin=0.25 (to measure one rule against the defaults)")
    parser.add_argument("--no-hindsight", action="store_true", help="synth, crowd: score the online tracker's "
                        "boxes, without filling the stretches a dancer was unseen (hdvr track --no-hindsight)")
    parser.add_argument("--per-clip-json", type=Path, help="synth, crowd: also write each clip's IDF1, ID switches "
                        "and hidden starts to this JSON file (compare two runs with scripts/compare_track_runs.py)")
    parser.add_argument("--weak-threshold", type=float, default=WEAK_DETECTION_THRESHOLD,
                        help="the tracking sections' detectors report people scoring from this up to their threshold "
                             "as weak finds (default %(default)s, as hdvr track; 0.3 turns them off)")
    parser.add_argument("--flip-test", action="store_true", help="the tracking sections' detectors also look at the "
                        "mirrored frame (hdvr track --flip-test)")
    args = parser.parse_args()
    if args.quick:
        args.repeats, args.frames = 1, 150
    sections = set(args.sections.split(","))
    config = parse_tracker_config(args.tracker_config)  # a wrong field fails here, before any section runs
    if args.settings:
        SETTINGS[:] = [tuple(int(v) for v in item.split("x")) for item in args.settings.split(",")]
    model = TrackingModel(default_pose_model(), args.weak_threshold, args.flip_test)
    tmp = Path(tempfile.mkdtemp(prefix="hdvr-bench-"))
    clip = tmp / "crossing.mp4"
    truth = render_clip(clip, frames=args.frames, specs=default_crossing_specs(num_figures=2, seed=0))
    boxes = truth.boxes[0]
    load_before = os.getloadavg()
    lines = ["## Tracking and 2D pose", "",
             f"Measured by `python3 scripts/bench_track.py{' --quick' if args.quick else ''}` on {cpu_name()}, "
             f"{os.cpu_count()} cores visible, detector (onnxruntime) limited to 2 threads; load average "
             f"{load_before[0]:.1f} at the start (other processes share the machine: figures are lower bounds). "
             f"Python {platform.python_version()}.", ""]

    # 1-2: speed and tracking accuracy on the procedural clip
    speed = {}
    if "speed" in sections:
        lines += speed_section(args, clip, truth, boxes, model, tmp, speed)
    if "real" in sections and REAL_VIDEO.is_file():
        lines += real_section(model, tmp)
    if "memory" in sections and not args.quick:
        lines += memory_section(args, clip, boxes, tmp)
    if "detector" in sections and REAL_VIDEO.is_file():
        lines += detector_section(model.path)
    if "identity" in sections:
        lines += identity_section(args, model, tmp, config)
    if "troupe" in sections:
        lines += identity_section(args, model, tmp, config, troupe=True)
    if "zoom" in sections:
        lines += zoom_section(model, tmp, repeats=args.repeats)
    if "cache" in sections:
        lines += cache_section(args, clip, boxes, model, tmp)
    per_clip: dict = {}
    if "synth" in sections:
        lines += synth_section(model, tmp, seeds=[int(v) for v in args.synth_seeds.split(",")],
                               thresholds=[float(v) for v in args.synth_thresholds.split(",")],
                               clips_dir=args.clips_dir, config=config, per_clip=per_clip,
                               hindsight=not args.no_hindsight, detector=args.synth_detector)
    if "crowd" in sections:
        counts = [int(v) for v in args.synth_crowd.split(",")]
        lines += synth_section(model, tmp, seeds=[int(v) for v in args.synth_seeds.split(",")],
                               thresholds=[float(v) for v in args.synth_thresholds.split(",")],
                               clips=[(genre, n) for n in counts for genre in CROWD_GENRES], groups=True,
                               clips_dir=args.clips_dir, config=config, per_clip=per_clip,
                               hindsight=not args.no_hindsight, detector=args.synth_detector)
    if args.per_clip_json:
        args.per_clip_json.parent.mkdir(parents=True, exist_ok=True)
        args.per_clip_json.write_text(json.dumps({"tracker_config": args.tracker_config,
                                                  "hindsight": not args.no_hindsight, "clips": per_clip},
                                                 indent=1))
    load_after = os.getloadavg()
    lines.append(f"Load average at the end: {load_after[0]:.1f}.")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.markdown:
        args.markdown.parent.mkdir(parents=True, exist_ok=True)
        args.markdown.write_text(text)
    (tmp / "summary.json").write_text(json.dumps({f"{k[0]}-{k[1]}": v for k, v in speed.items()}))
    return 0


def speed_section(args, clip, truth, boxes, model, tmp, speed) -> list[str]:
    """Frames/s per detector setting on the procedural clip, and the tracks' scores against its ground truth."""
    lines = [f"### Speed: 640x480, 2 dancers, {args.frames} frames (procedural crossing clip), overlay included", "",
             "| detector input | detector every | frames/s wall (median) | frames per CPU second (median) | "
             "wall ms/frame decode / detect / track / select / overlay | MOTA | IDF1 | HOTA | ID switches |",
             "|---|---|---|---|---|---|---|---|---|"]
    for size, every in SETTINGS:
        detector = tracking_detector(model, size)
        fps, cpu_fps, stages, run = [], [], None, None
        for _ in range(args.repeats):
            run = track_video(clip, tmp / f"out-{size}-{every}", detector=detector, boxes=boxes,
                              detect_every=every)
            n = run.boxes.shape[0]
            fps.append(n / run.seconds)
            cpu_fps.append(n / run.cpu_seconds)
            stages = {k: 1000 * v / n for k, v in run.stage_seconds.items()}
        scores = evaluate_tracking(truth.boxes, run.boxes)
        speed[(size, every)] = statistics.median(fps)
        stage_text = " / ".join(f"{stages[k]:.1f}" for k in ("decode", "detect", "track", "select", "overlay"))
        lines.append(f"| {size} px | {every} | {statistics.median(fps):.1f} | {statistics.median(cpu_fps):.1f} | "
                     f"{stage_text} | {scores.mota:.3f} | "
                     f"{scores.idf1:.3f} | {scores.hota:.3f} | {scores.id_switches} |")
        print(lines[-1], file=sys.stderr)
    lines.append("")
    return lines


def cache_section(args, clip, boxes, model, tmp) -> list[str]:
    """A run again over the same video with the detections cache (``hdvr track`` after a correction): frames/s
    of the first run (detector on every frame it is due, cache written) and of the next runs (people from the
    cache), and whether their outputs are the same."""
    lines = [f"### Tracking again with the detections cache: 640x480, 2 dancers, {args.frames} frames, overlay "
             f"included", "",
             "| detector input | detector every | first run frames/s | again, from the cache, frames/s (median) | "
             "speed-up | detect ms/frame first / again | outputs the same |", "|---|---|---|---|---|---|---|"]
    for size, every in SETTINGS:
        detector = tracking_detector(model, size)
        cache = tmp / f"detections-{size}-{every}.npz"
        cache.unlink(missing_ok=True)
        runs = [track_video(clip, tmp / f"cache-{size}-{every}-{k}", detector=detector, boxes=boxes,
                            detect_every=every, detections_cache=cache) for k in range(1 + args.repeats)]
        n = runs[0].boxes.shape[0]
        first, again = n / runs[0].seconds, statistics.median(n / r.seconds for r in runs[1:])
        same = all(np.array_equal(r.boxes, runs[0].boxes, equal_nan=True)
                   and np.array_equal(r.keypoints, runs[0].keypoints, equal_nan=True) for r in runs[1:])
        detect = [1000 * r.stage_seconds["detect"] / n for r in (runs[0], runs[-1])]
        lines.append(f"| {size} px | {every} | {first:.1f} | {again:.1f} | {again / first:.1f} x | "
                     f"{detect[0]:.1f} / {detect[1]:.1f} | {'yes' if same else 'NO'} |")
        print(lines[-1], file=sys.stderr)
    lines.append("")
    return lines


def real_section(model, tmp) -> list[str]:
    """Keypoint accuracy of cheaper settings against the reference, on the real video."""
    lines = []
    real = tmp / "two-people-640.mp4"
    scaled_copy(REAL_VIDEO, real)
    reference_detector = tracking_detector(model, 640)
    starts = find_dancers(real, reference_detector, 2)
    runs = {}
    for size, every in SETTINGS:
        detector = reference_detector if size == 640 else tracking_detector(model, size)
        runs[(size, every)] = track_video(real, tmp / f"real-{size}-{every}", detector=detector, starts=starts,
                                          detect_every=every, overlay=False)
    ref = runs[SETTINGS[0]]
    lines += ["### Keypoint accuracy of cheaper settings (real video two-people-tree scaled to 640x360)", "",
              "PCK@0.2 (torso) of each dancer's keypoints against the reference setting (640 px input, every "
              "frame), over the frames where the reference has the joint; frames/s as measured on this clip.", "",
              "| detector input | detector every | PCK@0.2 vs reference | frames/s wall | frames per CPU second |",
              "|---|---|---|---|---|"]
    for key, run in runs.items():
        n = run.boxes.shape[0]
        scores = [pck(run.keypoints[:, i], ref.keypoints[:, i]) for i in range(ref.keypoints.shape[1])]
        scores = [s for s in scores if np.isfinite(s)]
        lines.append(f"| {key[0]} px | {key[1]} | {np.mean(scores):.3f} | {n / run.seconds:.1f} | "
                     f"{n / run.cpu_seconds:.1f} |")
        print(lines[-1], file=sys.stderr)
    lines.append("")
    return lines


def memory_section(args, clip, boxes, tmp) -> list[str]:
    """Peak memory for a short and a 4x longer clip."""
    lines = []
    long_clip = tmp / "long.mp4"
    render_clip(long_clip, frames=4 * args.frames, specs=default_crossing_specs(num_figures=2, seed=0))
    box_arg = ";".join(",".join(f"{v:g}" for v in b) for b in boxes)
    short_mb = peak_rss_mb(clip, tmp / "mem-short", box_arg)
    long_mb = peak_rss_mb(long_clip, tmp / "mem-long", box_arg)
    lines += ["### Memory", "",
              f"Peak resident memory of `hdvr track` (detector 320 px every 2nd frame, overlay on): "
              f"{short_mb:.0f} MB for {args.frames} frames, {long_mb:.0f} MB for {4 * args.frames} frames.", ""]
    print(lines[-2], file=sys.stderr)
    return lines


def detector_section(model, every: int = 3, sizes=(480, 320, 256)) -> list[str]:
    """PCK@0.2 of smaller detector inputs against 640 px on the same frames (real video, every 3rd frame)."""
    from scipy.optimize import linear_sum_assignment

    from hdvr.tracking.appearance import box_iou

    reference = OnnxPoseDetector(model, input_size=640, threads=2)
    others = {size: OnnxPoseDetector(model, input_size=size, threads=2) for size in sizes}
    correct = {size: [] for size in sizes}
    for t, frame in enumerate(VideoReader(REAL_VIDEO)):
        if t % every:
            continue
        ref = reference.detect(frame)
        for size, det in others.items():
            got = det.detect(frame)
            iou = np.array([[box_iou(r.box, g.box) for g in got] for r in ref]).reshape(len(ref), len(got))
            match = {}
            if iou.size:
                for r, g in zip(*linear_sum_assignment(-iou)):
                    if iou[r, g] >= 0.3:
                        match[r] = g
            for r, pose in enumerate(ref):
                truth = pose.body25()[None]
                pred = got[match[r]].body25()[None] if r in match else np.full_like(truth, np.nan)
                score = pck(pred, truth)
                if np.isfinite(score):
                    correct[size].append(score)
    lines = ["### Detector input size alone (real video two-people-tree, 1768x994, every 3rd frame)", "",
             "PCK@0.2 of the poses found at a smaller input against those at 640 px on the same frames (matched by "
             "box overlap; a 640 px pose without a match counts as all wrong).", "",
             "| detector input | PCK@0.2 vs 640 px |", "|---|---|"]
    for size in sizes:
        lines.append(f"| {size} px | {np.mean(correct[size]):.3f} |")
        print(lines[-1], file=sys.stderr)
    lines.append("")
    return lines


def _score_row(dancers: int, mode: str, scores: list) -> str:
    """One markdown row: IDF1, MOTA, HOTA and identity switches per seed, and the medians."""
    def per_seed(key, fmt):
        return " ".join(format(getattr(s, key), fmt) for s in scores)

    med = [statistics.median(getattr(s, k) for s in scores) for k in ("idf1", "mota", "hota")]
    return (f"| {dancers} | {mode} | {per_seed('idf1', '.2f')} | {per_seed('id_switches', 'd')} | "
            f"{per_seed('mota', '.2f')} | {per_seed('hota', '.2f')} | {med[0]:.3f} / {med[1]:.3f} / {med[2]:.3f} |")


def identity_section(args, model, tmp, config: MultiTrackerConfig, frames: int = 150,
                     troupe: bool = False) -> list[str]:
    """Identity through crossings of 2-4 procedural dancers (``troupe``: groups of 6 and 8 in two rows,
    :func:`hdvr.tracking.testclips.troupe_specs`), tracker alone and with the default detector, with ``config``
    (``--tracker-config``)."""
    detector = tracking_detector(model)
    seeds = range(args.seed_start, args.seed_start + args.seeds)
    counts = (6, 8) if troupe else (2, 3, 4)
    what = "groups of 6 and 8 dancers in two rows" if troupe else "2-4 dancers"
    lines = [f"### Identity through crossings: procedural clips, {what}, {frames} frames, seeds {seeds[0]}-"
             f"{seeds[-1]}", "",
             "Tracker alone (Algorithm 1*, no detector) and `hdvr track`'s default (YOLO11n-pose at 480 px on every "
             "3rd frame; it finds the stick figures on few frames), started from the true first-frame boxes"
             + (f"; tracker config changed: `{args.tracker_config}`" if args.tracker_config else "") + ".", "",
             "| dancers | mode | IDF1 per seed | ID switches per seed | MOTA per seed | HOTA per seed | "
             "median IDF1 / MOTA / HOTA |", "|---|---|---|---|---|---|---|"]
    for n in counts:
        clips = []
        for seed in seeds:
            path = tmp / f"identity-{n}-{seed}.mp4"
            specs = troupe_specs(num_figures=n, seed=seed) if troupe else default_crossing_specs(num_figures=n,
                                                                                                 seed=seed)
            clips.append((path, render_clip(path, frames=frames, specs=specs, seed=seed)))
        for mode, det in (("tracker only", None), ("detector 480 px / 3rd frame", detector)):
            scores = [evaluate_tracking(truth.boxes, track_video(path, tmp / "identity-out", detector=det,
                                                                 boxes=truth.boxes[0], detect_every=3,
                                                                 overlay=False, write=False, config=config).boxes)
                      for path, truth in clips]
            lines.append(_score_row(n, mode, scores))
            print(lines[-1], file=sys.stderr)
    lines.append("")
    return lines


SYNTH_CLIPS = (("tango", 2), ("swing", 2), ("hip_hop", 3), ("flamenco", 3), ("hip_hop", 4), ("ballet", 4))
CROWD_GENRES = ("ballet", "hip_hop", "flamenco", "tap")  # group genres rendered with --synth-crowd dancers


def tracker_field_may_be_none(name: str) -> bool:
    """Whether the ``MultiTrackerConfig`` field ``name`` may be None: a test that can be switched off so (its
    annotation names None; 0 would be its strictest setting, not off)."""
    return "None" in str(next(f.type for f in dataclasses.fields(MultiTrackerConfig) if f.name == name))


def parse_tracker_config(text: str) -> MultiTrackerConfig:
    """MultiTrackerConfig with the fields named in ``text`` ("name=value,name=value") changed; a value takes the
    type of the field's default (booleans: true/false/1/0; a pair of numbers, such as ``pixel_margin``, as
    "a:b"; a mode, such as ``keep_hidden_sides``, as its name); a field that may be None (a test that can be
    switched off) also takes none."""
    config = MultiTrackerConfig()
    changes = {}
    for item in filter(None, (v.strip() for v in text.split(","))):
        name, sep, value = item.partition("=")
        if not sep or not hasattr(config, name):
            raise SystemExit(f"bench_track: --tracker-config: {item!r} is not FIELD=VALUE of MultiTrackerConfig")
        default = getattr(config, name)
        optional = tracker_field_may_be_none(name)
        if optional and value.lower() == "none":  # a test that can be switched off
            changes[name] = None
        elif isinstance(default, bool):
            if value.lower() not in ("true", "false", "1", "0"):
                raise SystemExit(f"bench_track: --tracker-config: {name} takes true or false, got {value!r}")
            changes[name] = value.lower() in ("true", "1")
        elif isinstance(default, (int, float)) or (default is None and optional):
            try:
                changes[name] = float(value) if default is None else type(default)(value)
            except ValueError:
                raise SystemExit(f"bench_track: --tracker-config: {name} takes a number, got {value!r}") from None
        elif isinstance(default, str):  # a mode, such as ``keep_hidden_sides``
            changes[name] = value
        elif isinstance(default, tuple) and all(isinstance(v, (int, float)) for v in default):
            try:
                numbers = tuple(type(d)(v) for d, v in zip(default, value.split(":"), strict=True))
            except ValueError:
                raise SystemExit(f"bench_track: --tracker-config: {name} takes {len(default)} numbers "
                                 f"separated by ':', got {value!r}") from None
            changes[name] = numbers
        else:
            raise SystemExit(f"bench_track: --tracker-config: {name} cannot be set from the command line")
    try:
        return dataclasses.replace(config, **changes)
    except ValueError as error:  # a mode not known
        raise SystemExit(f"bench_track: --tracker-config: {error}") from None


def synth_section(model, tmp, seconds: float = 4.0, seeds=(7,), thresholds=(0.3, 0.15),
                  clips=SYNTH_CLIPS, groups: bool = False, clips_dir: Path | None = None,
                  config: MultiTrackerConfig | None = None, per_clip: dict | None = None,
                  hindsight: bool = True, detector: str = "yolo") -> list[str]:
    """Tracking on rendered hdvr.synth clips against their MOT ground truth (boxes from gt.npz) and PCK@0.2 of the
    per-dancer keypoints against their visible ground-truth keypoints. ``clips``: (genre, dancers) per clip
    (``groups``: the crowd section's, rendered in folders of their own); a dancer the camera never sees is left out
    of the scoring. ``clips_dir``: where the clips are rendered (one already there, with its gt.npz, is reused);
    ``config``: the tracker's; ``per_clip``: filled with "seed:index[:groups]:threshold" -> IDF1, switches,
    hidden starts; ``hindsight``: as :func:`hdvr.tracking.pipeline.track_video`'s; ``detector``: "yolo"
    (YOLO11n-pose), or "truth" / "truth-amodal", each clip's ground truth as a perfect detector
    (:class:`hdvr.synth.truth_detector.GroundTruthDetector`, the visible part or the whole amodal box of each dancer
    found as its box; ``thresholds`` are then not used)."""
    from hdvr.synth.groundtruth import ClipSpec, make_clip
    from hdvr.synth.truth_detector import GroundTruthDetector

    if detector not in ("yolo", "truth", "truth-amodal"):
        raise ValueError(f"synth_section: detector must be yolo, truth or truth-amodal, got {detector!r}")
    truth_detector, amodal_truth = detector != "yolo", detector == "truth-amodal"
    if truth_detector:
        thresholds = (0,)

    detector_name = (f"the clip's ground truth ({'amodal' if amodal_truth else 'visible'} boxes: a perfect detector, "
                     "hdvr.synth.truth_detector; threshold column: 0)" if truth_detector else "YOLO11n-pose at 480 px")
    lines = [f"### Synthetic {'groups' if groups else 'dancers'} (hdvr.synth, 640x480, {seconds:g} s at 30 "
             f"frames/s, seed {', '.join(str(s) for s in seeds)})", "",
             f"Tracked from the ground-truth box where each dancer first appears, detector {detector_name} on "
             "every 3rd frame; scored against the clip's amodal ground-truth boxes (trackeval). \"pose\": fraction "
             "of detector frames in which each dancer got a pose. \"PCK@0.2\": per dancer, the fraction of its "
             "visible ground-truth keypoints (not hidden by another dancer, inside the image) that its keypoint file "
             "(`dancer_<i>.npz`: detector frames and the frames interpolated in between) has within 0.2 torso "
             "diameters; a keypoint the file lacks counts as wrong. Scored on the 19 BODY_25 joints a COCO-17 "
             "detector (YOLO11n-pose) gives; \"25\": on all BODY_25 joints (the 6 foot points never found count "
             "as wrong); \"mean\" pools the clip's dancers. \"at IoU 0.4\": IDF1 and ID switches again with boxes "
             "matched from IoU 0.4 on (IDF1, MOTA and switches before it: from 0.5), which tells a box that is right "
             "but misses hidden limbs of the amodal ground truth from a lost identity. \"starts hidden\": dancers "
             "whose start box lies mostly behind another dancer's (`TrackRun.hidden_starts`, the warning of "
             "`hdvr track`).",
             "",
             "| seed | clip | dancers | detector threshold | IDF1 | MOTA | HOTA | ID switches | pose per dancer | "
             "PCK@0.2 per dancer | PCK@0.2 mean | PCK@0.2 mean, 25 | IDF1 / switches at IoU 0.4 | starts hidden |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    scores = {thr: [] for thr in thresholds}  # (IDF1, switches, dancers starting hidden) per clip
    causes = {thr: {} for thr in thresholds}  # (visibility class, cause) -> dancer-frames, pooled over clips
    joints = body25_joints_of(COCO17_NAMES)
    detectors = {} if truth_detector else {thr: tracking_detector(model, score_threshold=thr) for thr in thresholds}
    for seed in seeds:
        for index, (genre, n) in enumerate(clips):
            spec = ClipSpec(index, seed, genre, n, seconds)
            clip = synth_clip_folder(clips_dir or tmp, spec, groups)
            if clips_dir is None or not (clip / "gt.npz").is_file() or not (clip / "video.mp4").is_file():
                make_clip(clip.parent, spec, render=True)
            gt, truth = _seen_truth(clip)
            n = gt.shape[1]
            order, starts = _starts_from_truth(gt)
            shown = _fewest_frames_shown(truth)
            if truth_detector:
                detectors = {0: GroundTruthDetector.from_clip(clip, amodal=amodal_truth)}
            for thr, detector in detectors.items():
                run = track_synth_clip(clip, tmp / "synth-out", detector, starts, config, hindsight)
                tracked = run.boxes[:, np.argsort(order)]
                keypoints = run.keypoints[:, np.argsort(order)]
                s = evaluate_tracking(gt, tracked)
                loose = evaluate_tracking(gt, tracked, iou_threshold=0.4)
                posed = (run.keypoints[run.detected][..., 2] > 0).any(axis=-1).mean(axis=0)[np.argsort(order)]
                pcks = [pck(keypoints[:, i], truth[:, i], joints=joints) for i in range(n)]
                pooled = pck(keypoints.reshape(-1, 25, 3), truth.reshape(-1, 25, 3), joints=joints)
                pooled25 = pck(keypoints.reshape(-1, 25, 3), truth.reshape(-1, 25, 3))
                lines.append(f"| {seed} | {spec.name} {genre} | {n} | {thr:g} | {s.idf1:.3f} | {s.mota:.3f} | "
                             f"{s.hota:.3f} | {s.id_switches} | {' / '.join(f'{p:.2f}' for p in posed)} | "
                             f"{' / '.join(f'{p:.2f}' for p in pcks)} | {pooled:.3f} | {pooled25:.3f} | "
                             f"{loose.idf1:.3f} / {loose.id_switches} | {len(run.hidden_starts)} |")
                scores[thr].append((s.idf1, s.id_switches, len(run.hidden_starts), shown))
                for key, count in miss_causes(gt, tracked, truth[..., 2].mean(axis=-1)).items():
                    causes[thr][key] = causes[thr].get(key, 0) + count
                if per_clip is not None:
                    per_clip[f"{seed}:{index}{':groups' if groups else ''}:{thr:g}"] = {
                        "genre": genre, "dancers": n, "idf1": s.idf1, "id_switches": s.id_switches,
                        "hidden_starts": len(run.hidden_starts), "fewest_frames_shown": shown,
                        "mota": s.mota, "hota": s.hota, "idf1_iou04": loose.idf1,
                        "id_switches_iou04": loose.id_switches}
                print(lines[-1], file=sys.stderr)
    lines.append("")
    for thr, rows in scores.items():
        hidden, clear = [r for r in rows if r[2]], [r for r in rows if not r[2]]
        shown, never = [r for r in rows if r[3] > 0], [r for r in rows if not r[3]]
        lines += [f"Threshold {thr:g}: {_idf1_summary(rows)}; clips where a dancer starts hidden: "
                  f"{_idf1_summary(hidden)}; the others: {_idf1_summary(clear)}. Clips where every dancer shows "
                  f"at least half its keypoints on some frame: {_idf1_summary(shown)}; clips with a dancer the "
                  f"camera never shows so: {_idf1_summary(never)}.", ""]
    for thr, counts in causes.items():
        lines += _miss_cause_table(thr, counts)
    return lines


def _miss_cause_table(threshold: float, counts: dict) -> list[str]:
    """Markdown table of :func:`hdvr.tracking.evaluation.miss_causes` counts pooled over clips: per visibility
    class, each cause's share of all ground-truth dancer-frames."""
    total = sum(counts.values())
    if not total:
        return []
    lines = [f"Where the ground-truth boxes go unmatched at IoU 0.5 (threshold {threshold:g}; % of all {total} "
             "dancer-frames; a dancer is visible with >= 90 % of its keypoints seen, partly with >= 40 %):", "",
             "| dancer | dancer-frames | " + " | ".join(MISS_CAUSES) + " |", "|---|" + "---|" * (len(MISS_CAUSES) + 1)]
    for v in VISIBILITY_CLASSES:
        row = [100 * counts.get((v, c), 0) / total for c in MISS_CAUSES]
        lines.append(f"| {v} | {sum(counts.get((v, c), 0) for c in MISS_CAUSES)} | "
                     + " | ".join(f"{x:.2f}" for x in row) + " |")
    return lines + [""]


def synth_clip_folder(clips_dir: Path, spec, groups: bool = False) -> Path:
    """Where the synth section keeps a clip (``--clips-dir`` layout): ``synth-SEED[-groups]/clip_0000I`` under
    ``clips_dir``, for a :class:`hdvr.synth.groundtruth.ClipSpec` ``spec``."""
    return Path(clips_dir) / f"synth-{spec.seed}{'-groups' if groups else ''}" / spec.name


def track_synth_clip(clip: Path, out: Path, detector, starts, config=None, hindsight: bool = True,
                     write: bool = False, zoom: bool = True, zoom_group: bool = True):
    """``track_video`` on an hdvr synth clip folder as the synth section runs it: from ``starts``
    (:func:`_starts_from_truth`), the detector on every 3rd frame, no overlay nor timeline; with ``write`` the
    outputs of ``hdvr track`` go to ``out`` (with a detections cache there, reused by a second run). ``zoom=False``:
    no detector crops at all, about waiting or unposed dancers nor about a group (``hdvr track --no-zoom``);
    ``zoom_group=False``: no crop about the group of dancers (``hdvr track --no-zoom-group``)."""
    return track_video(clip / "video.mp4", out, detector=detector, starts=starts, detect_every=3, overlay=False,
                       write=write, config=config, hindsight=hindsight, timeline=False,
                       detections_cache=out / "detections.npz" if write else None, zoom_hidden=zoom,
                       zoom_unposed=zoom, zoom_group=zoom and zoom_group)


def _seen_truth(clip: Path) -> tuple[np.ndarray, np.ndarray]:
    """Ground truth of an hdvr synth clip folder for the dancers the camera sees (a group may have some it never
    does): (T, N, 4) amodal boxes x, y, w, h px (NaN where absent) and (T, N, 25, 3) visible keypoints."""
    with np.load(clip / "gt.npz") as gt_file:
        gt = np.transpose(gt_file["boxes"], (1, 0, 2)).astype(float)
        truth = visible_truth_keypoints(gt_file["keypoints2d"], gt_file["visibility"])
    seen = np.isfinite(gt).all(axis=2).any(axis=0)
    return gt[:, seen], truth[:, seen]


def _fewest_frames_shown(truth: np.ndarray, min_visible: float = 0.5) -> int:
    """The fewest frames on which any one dancer shows at least ``min_visible`` of its keypoints, from (T, N, 25, 3)
    visible ground-truth keypoints (:func:`hdvr.tracking.evaluation.visible_truth_keypoints`): 0 when a dancer
    stays hidden behind others (or mostly out of the frame) for the whole clip, so that nothing in the video
    tells where it is."""
    return int((truth[..., 2].mean(axis=-1) >= min_visible).sum(axis=0).min())


def _starts_from_truth(gt: np.ndarray):
    """Each dancer's start (its first frame with a ground-truth box, and that box) from (T, N, 4) boxes of dancers
    the camera sees: (order, starts), ``order`` the dancers' indices by start, as track_video numbers them."""
    first = [int(np.flatnonzero(np.isfinite(gt[:, i]).all(axis=1))[0]) for i in range(gt.shape[1])]
    order = sorted(range(gt.shape[1]), key=lambda i: first[i])
    return order, [DancerStart(first[i], tuple(gt[first[i], i])) for i in order]


#: hdvr synth clips where dancers start hidden behind others for long: (seed, clip index), clip index into
#: SYNTH_CLIPS (seed 308 ballet: one dancer waits 30 frames; seed 304 ballet: two wait the whole clip)
ZOOM_CLIPS = ((308, 5), (304, 5), (3070, 0), (2721, 4))  # and two that the crop about the group mends (session 89)


def zoom_section(model, tmp, repeats: int = 3, seconds: float = 4.0) -> list[str]:
    """What looking again, zoomed in, for dancers that wait hidden behind another and for dancers in view without a
    detection costs (``zoom_hidden``, ``zoom_unposed``: off with ``hdvr track --no-zoom``), and what the crop about
    the group adds (``zoom_group``, default since session 90; off with ``hdvr track --no-zoom-group``): the
    default, the default without the crop about the group, all off."""
    from hdvr.synth.groundtruth import ClipSpec, make_clip

    lines = ["### Zoomed-in search for waiting dancers: cost", "",
             "`track_video(zoom_hidden=True, zoom_unposed=True, zoom_group=True)` (default: `on`) against the same "
             "with `zoom_group=False` (`on, no group`, `hdvr track --no-zoom-group`) and all `False` (`off`, "
             "`--no-zoom`) on "
             "hdvr synth clips where dancers start hidden behind others or dance in a group, 640x480, detector 480 "
             f"px every 3rd frame, no overlay; median of {repeats} runs; IDF1 against the amodal ground truth.", "",
             "| seed | clip | dancers starting hidden | zoom | detect ms/frame | frames/s wall | IDF1 | ID switches |",
             "|---|---|---|---|---|---|---|---|"]
    detector = tracking_detector(model)
    for seed, index in ZOOM_CLIPS:
        genre, n = SYNTH_CLIPS[index]
        spec = ClipSpec(index, seed, genre, n, seconds)
        make_clip(tmp / f"zoom-{seed}", spec, render=True)
        clip = tmp / f"zoom-{seed}" / spec.name
        gt, _ = _seen_truth(clip)
        order, starts = _starts_from_truth(gt)
        for zoom, group in ((True, True), (True, False), (False, False)):
            runs = [track_video(clip / "video.mp4", tmp / "zoom-out", detector=detector, starts=starts,
                                detect_every=3, overlay=False, write=False, zoom_hidden=zoom, zoom_unposed=zoom,
                                zoom_group=group)
                    for _ in range(repeats)]
            frames = runs[0].boxes.shape[0]
            s = evaluate_tracking(gt, runs[0].boxes[:, np.argsort(order)])
            detect = 1000 * np.median([r.stage_seconds["detect"] for r in runs]) / frames
            wall = np.median([frames / r.seconds for r in runs])
            setting = "on" if group else "on, no group" if zoom else "off"
            lines.append(f"| {seed} | {spec.name} {genre} | {len(runs[0].hidden_starts)} | {setting} "
                         f"| {detect:.1f} | {wall:.1f} | {s.idf1:.3f} | {s.id_switches} |")
            print(lines[-1], file=sys.stderr)
    return lines + [""]


def _idf1_summary(rows) -> str:
    """'N clips, mean IDF1 m (median), k below 0.9, s switches on c clips' for (IDF1, switches, ...) rows."""
    if not rows:
        return "no clip"
    idf1 = [r[0] for r in rows]
    return (f"{len(rows)} clips, mean IDF1 {np.mean(idf1):.3f} (median {np.median(idf1):.3f}), "
            f"{sum(v < 0.9 for v in idf1)} below 0.9, {sum(r[1] for r in rows)} ID switches on "
            f"{sum(r[1] > 0 for r in rows)} clips")


if __name__ == "__main__":
    sys.exit(main())
