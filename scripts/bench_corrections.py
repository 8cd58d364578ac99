#!/usr/bin/env python3
"""Benchmark of ``hdvr track --correct``: how many box corrections a user needs to mend a clip the tracker fails.

A simulated user, played by the ground truth of rendered ``hdvr.synth`` clips, looks at each run as a person looks
at the overlay video and corrects it, then the clip is tracked again with all corrections so far, up to
``--max-rounds`` times, until it passes (IDF1 >= 0.9 and no identity switch, the target of the tracking issue):

- a box is *wrong* where it lies on its dancer's ground-truth (amodal) box at IoU below 0.5 for at least
  ``--min-stretch`` frames in a row (shorter slips are left: nobody corrects a few frames);
- the user corrects only where the dancer can be seen, at the first frame of a wrong stretch in which it shows at
  least ``--min-visible`` of its 25 keypoints (a dancer hidden all through the stretch cannot be drawn), giving its
  ground-truth box;
- each round takes the earliest such frame over all dancers and corrects there every dancer that is wrong and
  seen in it (after an identity switch both dancers' boxes are wrong, and both are corrected); with ``--swaps``,
  two dancers each of whose boxes lies on the other's ground truth (IoU >= 0.5) there are swapped instead
  (``hdvr track --swap A,B@FRAME``: one action, no box drawn).

With ``--points`` the user clicks on the dancer instead of drawing its box (``--correct DANCER@FRAME:x,y``): on
the visible ground-truth keypoint nearest the middle of its visible keypoints; where the detector finds nobody
there, the user draws the box after all (counted once), and where the box found is still wrong in the next run, the
user draws it then (one more action).

The count of a round is the user's actions so far: boxes drawn or points clicked, plus swaps.

Tracks start from the ground-truth first boxes (as ``bench_track.py --sections synth``), YOLO11n-pose at 480 px
on every 3rd frame, sure finds from 0.3, weak from 0.2, hindsight on: what ``hdvr track`` writes.

Usage: python3 scripts/bench_corrections.py --clips SEED:INDEX,... [--clips-dir DIR] [--max-rounds 5]
                                            [--min-stretch 10] [--min-visible 0.5] [--swaps]
                                            [--per-clip-json FILE] [--markdown FILE]
``INDEX`` indexes ``bench_track.SYNTH_CLIPS`` (0 tango couple, 1 swing couple, 2 hip-hop trio, 3 flamenco trio,
4 hip-hop quartet, 5 ballet quartet); a clip already rendered under ``--clips-dir`` is reused.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "scripts"))
os.environ.setdefault("HDVR_NO_PROGRESS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402

from hdvr.pose2d.cache import CachingDetector  # noqa: E402
from hdvr.tracking.appearance import box_iou  # noqa: E402
from hdvr.errors import HDVRError  # noqa: E402
from hdvr.tracking.evaluation import evaluate_tracking  # noqa: E402
from hdvr.tracking.hindsight import _runs  # noqa: E402  (runs of True in a mask: the stretches hindsight fills)
from hdvr.tracking.pipeline import BoxCorrection, IdentitySwap, track_video  # noqa: E402
from hdvr.video import probe_video  # noqa: E402
from benchdoc import cpu_name  # noqa: E402


def passes(idf1: float, switches: int) -> bool:
    """The tracking issue's target on one clip."""
    return idf1 >= 0.9 and switches == 0


def wrong_frames(gt: np.ndarray, boxes: np.ndarray, min_stretch: int) -> np.ndarray:
    """(T, N) bool: frames where a dancer's box (``boxes`` (T, N, 4) px) lies on its ground-truth box (``gt``, same
    shape, NaN where absent) at IoU < 0.5 (or is missing while the dancer is there), in stretches of at least
    ``min_stretch`` frames."""
    present = np.isfinite(gt).all(axis=2)
    iou = np.zeros(present.shape)
    both = present & np.isfinite(boxes).all(axis=2)
    iou[both] = [box_iou(g, b) for g, b in zip(gt[both], boxes[both])]
    bad = present & (iou < 0.5)
    out = np.zeros_like(bad)
    for j in range(bad.shape[1]):
        for first, last in _runs(bad[:, j]):
            if last + 1 - first >= min_stretch:
                out[first:last + 1, j] = True
    return out


def next_corrections(gt: np.ndarray, boxes: np.ndarray, shown: np.ndarray, min_stretch: int = 10,
                     min_visible: float = 0.5, swaps: bool = False
                     ) -> tuple[list[tuple[int, int, tuple[float, float, float, float]]], list[tuple[int, int, int]]]:
    """The simulated user's next corrections, as (frame, dancer, box px), and swaps, as (frame, dancer, dancer), in
    the ground truth's dancer order: at the earliest frame where a dancer is wrong (:func:`wrong_frames`) and shows
    at least ``min_visible`` of its keypoints (``shown`` (T, N), fraction of keypoints visible), every dancer wrong
    and shown there gets its ground-truth box, except (``swaps``) pairs whose boxes each lie on the other's ground
    truth (IoU >= 0.5), which are swapped. Both empty when nothing wrong can be seen."""
    candidates = wrong_frames(gt, boxes, min_stretch) & (shown >= min_visible)
    frames = np.flatnonzero(candidates.any(axis=1))
    if not frames.size:
        return [], []
    t = int(frames[0])
    wrong = [int(j) for j in np.flatnonzero(candidates[t])]
    pairs = []
    if swaps:
        def on(j, k):  # dancer j's box on dancer k's ground truth
            return np.isfinite(boxes[t, j]).all() and box_iou(boxes[t, j], gt[t, k]) >= 0.5
        for a in wrong:
            for b in wrong:
                if a < b and on(a, b) and on(b, a) and not any({a, b} & set(p[1:]) for p in pairs):
                    pairs.append((t, a, b))
    swapped = {j for p in pairs for j in p[1:]}
    return [(t, j, tuple(float(v) for v in gt[t, j])) for j in wrong if j not in swapped], pairs


def click_point(keypoints: np.ndarray) -> tuple[float, float] | None:
    """Where the simulated user clicks on a dancer: of its visible keypoints (``keypoints`` (25, 3) px with
    confidence, 0 where hidden), the one nearest their mean; None if none is visible."""
    seen = keypoints[(keypoints[:, 2] > 0) & np.isfinite(keypoints[:, :2]).all(axis=1), :2]
    if not len(seen):
        return None
    nearest = seen[np.argmin(np.hypot(*(seen - seen.mean(axis=0)).T))]
    return float(nearest[0]), float(nearest[1])


def track_with_fallback(video: Path, out, detector, starts, corrections: list, swaps: list):
    """``track_video`` with the user's corrections; a point on which the detector finds nobody is replaced by the
    box it stood for (the ``box`` kept in ``BoxCorrection.box`` of ``corrections`` entries is then used: points are
    given as (correction, box) pairs). Returns the run and the corrections as finally given."""
    given = list(corrections)
    while True:
        try:
            run = track_video(video, out, detector=detector, starts=starts, detect_every=3, overlay=False,
                              write=False, corrections=[c for c, _ in given], swaps=swaps)
            return run, given
        except HDVRError as exc:
            failed = [k for k, (c, _) in enumerate(given) if c.point is not None
                      and f"correction of dancer {c.dancer} at frame {c.frame}: nobody detected" in str(exc)]
            if not failed:
                raise
            c, box = given[failed[0]]
            given[failed[0]] = (BoxCorrection(c.frame, c.dancer, box), box)


def main() -> int:
    import bench_track as bt
    from hdvr.pose2d.models import default_pose_model
    from hdvr.synth.groundtruth import ClipSpec, make_clip

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clips", required=True, help="SEED:INDEX,... (INDEX into bench_track.SYNTH_CLIPS)")
    parser.add_argument("--clips-dir", type=Path, help="where clips are rendered (reused when there)")
    parser.add_argument("--max-rounds", type=int, default=5)
    parser.add_argument("--min-stretch", type=int, default=10)
    parser.add_argument("--min-visible", type=float, default=0.5)
    parser.add_argument("--swaps", action="store_true", help="swap pairs of dancers each on the other's place")
    parser.add_argument("--points", action="store_true", help="click on each dancer instead of drawing its box")
    parser.add_argument("--per-clip-json", type=Path)
    parser.add_argument("--markdown", type=Path)
    args = parser.parse_args()
    todo = [tuple(int(v) for v in item.split(":")) for item in args.clips.split(",") if item]
    clips_dir = args.clips_dir or Path(tempfile.mkdtemp(prefix="hdvr-corrections-"))
    model = bt.TrackingModel(Path(default_pose_model()))
    detector = bt.tracking_detector(model, size=480, score_threshold=0.3)
    per_clip = {}
    started = time.perf_counter()
    for k, (seed, index) in enumerate(todo):
        genre, n = bt.SYNTH_CLIPS[index]
        spec = ClipSpec(index, seed, genre, n, 4.0)
        root = clips_dir / f"synth-{seed}"
        clip = root / spec.name
        if not (clip / "gt.npz").is_file() or not (clip / "video.mp4").is_file():
            make_clip(root, spec, render=True)
        gt, truth = bt._seen_truth(clip)
        shown = (truth[..., 2] > 0).mean(axis=2)
        order, starts = bt._starts_from_truth(gt)
        tracker_id = {j: k for k, j in enumerate(order)}
        corrections: list[tuple[BoxCorrection, tuple]] = []  # (as given, the box it stands for)
        swaps: list[IdentitySwap] = []
        rounds, actions = [], 0
        # the detector's people on whole frames are kept from round to round, as hdvr track's detections.npz keeps
        # them between a user's runs: the same tracks, faster
        cached = CachingDetector(detector, probe_video(clip / "video.mp4").size)
        with tempfile.TemporaryDirectory() as out:
            for _ in range(args.max_rounds + 1):
                run, corrections = track_with_fallback(clip / "video.mp4", out, cached, starts, corrections, swaps)
                cached.stored = cached.all_found()
                boxes = run.boxes[:, np.argsort(order)]  # written ids keep their ground-truth dancers: the
                scores = evaluate_tracking(gt, boxes)  # swaps put the persons under them
                rounds.append({"idf1": round(scores.idf1, 4), "switches": scores.id_switches,
                               "corrections": actions, "swaps": len(swaps),
                               "points": sum(c.point is not None for c, _ in corrections)})
                if passes(scores.idf1, scores.id_switches):
                    break
                new, pairs = next_corrections(gt, boxes, shown, args.min_stretch, args.min_visible, args.swaps)
                if not (new or pairs) or len(rounds) > args.max_rounds:
                    break
                for t, j, box in new:
                    actions += 1
                    same = [k for k, (c, _) in enumerate(corrections) if (c.frame, c.dancer) == (t, tracker_id[j])]
                    if same:  # a point there gave the wrong box: the user draws the box after all
                        corrections[same[0]] = (BoxCorrection(t, tracker_id[j], box), box)
                        continue
                    point = click_point(truth[t, j]) if args.points else None
                    given = BoxCorrection(t, tracker_id[j], None if point else box, point)
                    corrections.append((given, box))
                actions += len(pairs)
                swaps += [IdentitySwap(t, tracker_id[a], tracker_id[b]) for t, a, b in pairs]
        name = f"{seed}:{index}"
        per_clip[name] = {"genre": genre, "dancers": n, "rounds": rounds,
                          "passes": passes(rounds[-1]["idf1"], rounds[-1]["switches"])}
        print(f"[{k + 1}/{len(todo)}] {name} {genre}: " + " -> ".join(
            f"{r['idf1']:.3f}/{r['switches']}sw ({r['corrections']})" for r in rounds), file=sys.stderr, flush=True)
    lines = summary(per_clip, args, time.perf_counter() - started)
    print("\n".join(lines))
    if args.per_clip_json:
        args.per_clip_json.write_text(json.dumps(per_clip, indent=1))
    if args.markdown:
        args.markdown.write_text("\n".join(lines) + "\n")
    return 0


def summary(per_clip: dict, args, seconds: float) -> list[str]:
    """Markdown lines: how many clips pass after 0, 1, 2, ... corrections."""
    failing = {k: v for k, v in per_clip.items() if not passes(v["rounds"][0]["idf1"], v["rounds"][0]["switches"])}
    lines = [f"{len(per_clip)} clips, {len(failing)} failing without corrections (min stretch {args.min_stretch} "
             f"frames, dancer showing >= {args.min_visible:g} of its keypoints"
             f"{', swaps' if getattr(args, 'swaps', False) else ''}"
             f"{', points clicked' if getattr(args, 'points', False) else ''}; {cpu_name()}, {seconds / 60:.0f} min)",
             "", "| user actions (boxes, points, swaps) | failing clips passing | IDF1 mean of the failing clips |",
             "|---|---|---|"]
    most = max((r["corrections"] for v in failing.values() for r in v["rounds"]), default=0)
    for c in range(most + 1):
        def at(v):  # the last round with at most c corrections
            return [r for r in v["rounds"] if r["corrections"] <= c][-1]
        ok = sum(passes(at(v)["idf1"], at(v)["switches"]) for v in failing.values())
        mean = statistics.fmean(at(v)["idf1"] for v in failing.values()) if failing else float("nan")
        lines.append(f"| <= {c} | {ok} of {len(failing)} | {mean:.4f} |")
    never = [k for k, v in failing.items() if not v["passes"]]
    lines += ["", f"Not mended: {', '.join(never) or 'none'}"]
    return lines


if __name__ == "__main__":
    raise SystemExit(main())
