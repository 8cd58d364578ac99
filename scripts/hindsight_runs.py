#!/usr/bin/env python3
"""Measure hindsight settings on synthetic clips tracked once: the online tracker's runs kept, hindsight scored on them.

Hindsight (:mod:`hdvr.tracking.hindsight`) runs after the online tracker and never changes it, so a setting of it
can be scored on runs kept from one tracking pass, in seconds per setting for 504 clips instead of the 20 minutes of
``bench_track.py --sections synth``, and without the chaos of online changes (a start box moved by 0.01 px can move a
clip's IDF1 by 0.3: docs/benchmarks.md, session 47). With the default settings the scores are exactly those of
``bench_track.py --sections synth --synth-thresholds 0.3`` (same clips, same detector, same starts).

    # track each clip once (YOLO11n-pose at 480 px every 3rd frame, as the benchmark), hindsight off
    python3 scripts/hindsight_runs.py save --clips-dir CLIPS --seeds 201,202 --runs RUNS \\
        [--detections DETS] [--tracker-config NAME=VALUE,...] [--no-zoom-group]
    # or only some clips again, by their runs' names
    python3 scripts/hindsight_runs.py save --clips-dir CLIPS --keys 2624_2,2507_3 --runs RUNS --detections DETS
    # or only those where a dancer starts hidden (in an earlier score file; a rule for such dancers changes no other)
    python3 scripts/hindsight_runs.py save --clips-dir CLIPS --hidden-starts-of SCORES.json --runs RUNS \\
        --detections DETS
    # or the same told from the truth's start boxes, before anything is rendered
    python3 scripts/hindsight_runs.py save --clips-dir CLIPS --seeds 2801,2802 --hidden-starts-only --runs RUNS
    # score hindsight settings on the kept runs
    python3 scripts/hindsight_runs.py score --clips-dir CLIPS --runs RUNS [--set keypoint_reach=0.1 ...] \\
        [--per-clip-json F.json]
    # where each dancer's box lies below IoU 0.5 with its truth (after hindsight, or --online)
    python3 scripts/hindsight_runs.py stretches --clips-dir CLIPS --runs RUNS [--keys 2844_0,2922_3] [--online]
    # a picture of some frames of one kept run: each written box (after hindsight, or --online) over its truth
    python3 scripts/hindsight_runs.py picture --clips-dir CLIPS --runs RUNS --key 3100_0 --frames 30,40,50,70 \\
        --out 3100_0.png [--online]
    # per status, the dancer-frames hindsight moved off their dancer and onto it; the clips it moved off most
    python3 scripts/hindsight_runs.py harm --clips-dir CLIPS --runs RUNS [--set ...] [--top 20]

CLIPS holds ``synth-SEED/clip_0000I`` folders as ``bench_track.py --clips-dir`` writes them (rendered here when
missing); RUNS one ``SEED_INDEX.npz`` per clip (keys: boxes, status, keypoints, order, hidden_starts, width).
``--set`` takes the fields of :class:`hdvr.tracking.hindsight.HindsightSettings` (``amodal_boxes=false``: without
the learned whole-body refiner, whose shipped weights were trained on the runs of seeds 201-212, 301-312, 2101-2512
and 2601-2680, so that their scores with it are in-sample: compare other settings there with it off, or train it
again with ``scripts/train_amodal_boxes.py cross-validate``). ``--per-clip-json`` writes the
format of ``bench_track.py --per-clip-json``, for ``scripts/compare_track_runs.py``.

An online rule (a ``MultiTrackerConfig`` field, ``--tracker-config`` as in ``bench_track.py``) changes the runs
themselves: save them again with it and score. ``--detections DETS`` keeps each clip's detector output
(``DETS/SEED_INDEX/detections.npz``, with the outputs of ``hdvr track``) and reuses it on later saves, which then run
the tracker alone (and the detector on the zoomed-in crops about waiting dancers): 504 clips in about 10 minutes on
2 cores, two saves of different seeds side by side. The runs are the same with or without it.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import (SYNTH_CLIPS, _seen_truth, _starts_from_truth, default_tracking_detector,  # noqa: E402
                         parse_tracker_config, synth_clip_folder, track_synth_clip)
from compare_track_runs import failing, summary  # noqa: E402

from hdvr.io.atomic import atomic_path  # noqa: E402
from hdvr.tracking.evaluation import evaluate_tracking  # noqa: E402
from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight  # noqa: E402

RUN_KEYS = ("boxes", "status", "keypoints", "order", "hidden_starts", "width")


def clip_spec(seed: int, index: int, seconds: float = 4.0):
    """The benchmark's clip ``index`` (into ``SYNTH_CLIPS``) of seed ``seed``, as a
    :class:`hdvr.synth.groundtruth.ClipSpec`."""
    from hdvr.synth.groundtruth import ClipSpec

    genre, n = SYNTH_CLIPS[index]
    return ClipSpec(index, seed, genre, n, seconds)


def save_run(path: Path, run, order) -> None:
    """Keep what hindsight needs of a ``track_video(..., hindsight=False)`` run (``TrackRun``), with the dancers'
    ``order`` (written id -> ground-truth index, as ``bench_track``'s starts), in NPZ ``path`` (written atomically)."""
    with atomic_path(path) as tmp:
        np.savez_compressed(tmp, boxes=run.boxes,
                            status=np.array(run.status, dtype="U10").reshape(run.boxes.shape[:2]),
                            keypoints=run.keypoints, order=np.asarray(order, int),
                            hidden_starts=np.array(run.hidden_starts, int).reshape(-1, 3), width=float(run.size[0]),
                            stopped_behind=np.asarray(run.stopped_behind, bool),
                            returned_behind=np.asarray(run.returned_behind, bool))


def load_run(path: Path) -> dict:
    """A run kept by :func:`save_run`: its arrays, with ``status`` as T tuples of N strings, ``hidden_starts``
    as (frame, dancer, front) tuples, ``stopped_behind`` and ``returned_behind`` (T, N) bool (None in a run kept
    before each was)."""
    try:
        with np.load(path) as data:
            run = {k: data[k] for k in RUN_KEYS}
            # runs kept before session 57 have no stopped_behind (the tracker stopped no prediction then)
            run["stopped_behind"] = data["stopped_behind"] if "stopped_behind" in data.files else None
            # and before session 75 no returned_behind (no waiting dancer was put back behind the front one)
            run["returned_behind"] = data["returned_behind"] if "returned_behind" in data.files else None
    except (OSError, ValueError, KeyError) as exc:
        raise SystemExit(f"hindsight_runs: {path} is not a kept run ({type(exc).__name__}: {exc})")
    run["status"] = [tuple(str(s) for s in row) for row in run["status"]]
    run["hidden_starts"] = [tuple(int(v) for v in row) for row in run["hidden_starts"]]
    return run


def written_boxes(run: dict, settings: HindsightSettings | None) -> np.ndarray:
    """The (T, N, 4) px boxes a kept run (:func:`load_run`) writes after hindsight with ``settings`` (None: the
    online tracker's boxes as they are), in its written order."""
    if settings is None:
        return np.asarray(run["boxes"], float)
    return apply_hindsight(run["boxes"], run["status"], run["keypoints"], frame_width=float(run["width"]),
                           hidden_starts=run["hidden_starts"], settings=settings,
                           stopped_behind=run.get("stopped_behind"), returned_behind=run.get("returned_behind"))[0]


def score_run(run: dict, truth_boxes: np.ndarray, settings: HindsightSettings | None,
              boxes: np.ndarray | None = None) -> dict:
    """IDF1, switches, MOTA and HOTA at IoU 0.5 and IDF1 and switches at IoU 0.4 of a kept run (:func:`load_run`)
    after hindsight with ``settings`` (None: the online tracker's boxes as they are), against (T, N, 4) px
    ground-truth boxes. ``boxes``: :func:`written_boxes` of the run and settings, if computed already."""
    boxes = written_boxes(run, settings) if boxes is None else boxes
    tracked = boxes[:, np.argsort(run["order"])]
    strict, loose = evaluate_tracking(truth_boxes, tracked), evaluate_tracking(truth_boxes, tracked, iou_threshold=0.4)
    return {"dancers": int(truth_boxes.shape[1]), "idf1": strict.idf1, "id_switches": strict.id_switches,
            "hidden_starts": len(run["hidden_starts"]), "mota": strict.mota, "hota": strict.hota,
            "idf1_iou04": loose.idf1, "id_switches_iou04": loose.id_switches}


def weak_stretches(boxes: np.ndarray, truth_boxes: np.ndarray, order, status, threshold: float = 0.5) -> list[dict]:
    """Where each written dancer's box lies below IoU ``threshold`` with its own ground-truth box: the stretches of
    frames a failing clip loses, to look at. ``boxes`` (T, N, 4) px written boxes, ``truth_boxes`` (T, N, 4) px
    amodal truth (NaN where absent), ``order`` written id -> ground-truth index, ``status`` T tuples of N strings.
    Returns dicts with keys dancer, truth, start, end (exclusive), median_iou, statuses (sorted) and on_truth (the
    ground-truth index the box lies on at IoU >= ``threshold`` at the stretch's start, or None), by dancer and start."""
    from hdvr.tracking.evaluation import iou_matrix

    # (T, N written, M truth) IoU, 0 where either box is absent (NaN)
    ious = np.stack([iou_matrix(np.asarray(b, float), np.asarray(g, float)) for b, g in zip(boxes, truth_boxes)])
    out = []
    for w, g in enumerate(order):
        own = ious[:, w, g]
        weak = np.isfinite(truth_boxes[:, g]).all(axis=1) & (own < threshold)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], weak.astype(int), [0]])))
        for start, end in zip(edges[::2], edges[1::2]):
            best = int(np.argmax(ious[start, w]))
            out.append({"dancer": w, "truth": int(g), "start": int(start), "end": int(end),
                        "median_iou": float(np.median(own[start:end])),
                        "statuses": sorted({status[t][w] for t in range(start, end)}),
                        "on_truth": best if ious[start, w, best] >= threshold else None})
    return out


def hindsight_moves(online: np.ndarray, written: np.ndarray, truth_boxes: np.ndarray, order, status,
                    threshold: float = 0.5) -> dict[str, tuple[int, int]]:
    """Per status (``tracked``, ``occluded``, ``hidden``, ...): how many dancer-frames hindsight moved off their own
    dancer (the ``online`` box at IoU >= ``threshold`` with its truth, the ``written`` box below) and onto it (the
    other way round), as (harmed, mended). ``online`` and ``written`` (T, N, 4) px in the written order,
    ``truth_boxes`` (T, M, 4) px amodal truth (NaN where absent; such frames are not counted), ``order`` written id ->
    ground-truth index, ``status`` (T, N) strings. Hindsight's steps are chosen by the clips they mend and break; this
    says where, by status, a step that helps on the whole still moves good boxes off (session 75)."""
    from hdvr.tracking.evaluation import iou_matrix

    def own_iou(boxes):
        return np.stack([iou_matrix(np.asarray(b, float), np.asarray(g, float))[np.arange(len(order)), order]
                         for b, g in zip(boxes, truth_boxes)])

    before, after = own_iou(online), own_iou(written)
    status = np.asarray(status)
    known = np.isfinite(np.asarray(truth_boxes, float)[:, order]).all(axis=2)
    out = {}
    for name in sorted(set(status.ravel().tolist())):
        here = known & (status == name)
        out[name] = (int((here & (before >= threshold) & (after < threshold)).sum()),
                     int((here & (before < threshold) & (after >= threshold)).sum()))
    return out


def parse_settings(pairs: list[str]) -> HindsightSettings:
    """:class:`HindsightSettings` with ``NAME=VALUE`` overrides; a clear error for an unknown name or bad value."""
    fields = {f.name: f.type for f in dataclasses.fields(HindsightSettings)}
    values = {}
    for pair in pairs:
        name, _, value = pair.partition("=")
        if name not in fields:
            raise SystemExit(f"hindsight_runs: unknown setting {name!r} (known: {', '.join(fields)})")
        if fields[name] in (str, "str"):
            values[name] = value
            continue
        if fields[name] in (bool, "bool"):
            if value.lower() not in ("true", "false", "1", "0"):
                raise SystemExit(f"hindsight_runs: setting {name} needs true or false, got {value!r}")
            values[name] = value.lower() in ("true", "1")
            continue
        try:
            values[name] = int(value) if fields[name] in (int, "int") else float(value)
        except ValueError:
            raise SystemExit(f"hindsight_runs: setting {name} needs a number, got {value!r}")
    return HindsightSettings(**values)


def _integers(text: str) -> list[int]:
    """Comma-separated integers (seeds or clip indices)."""
    try:
        return [int(s) for s in text.split(",") if s]
    except ValueError:
        raise SystemExit(f"hindsight_runs: --seeds and --clips take comma-separated integers, got {text!r}")


def _key(text: str) -> tuple[int, int]:
    """(seed, clip index) of a kept run's name ``SEED_INDEX``; a clear error otherwise."""
    try:
        seed, index = (int(v) for v in text.strip().split("_"))
    except ValueError:
        raise SystemExit(f"hindsight_runs: --keys takes SEED_INDEX names (as the kept runs'), got {text!r}")
    return seed, index


def hidden_start_clips(path: Path) -> list[tuple[int, int]]:
    """(seed, clip index) of the clips of a per-clip score file (``score --per-clip-json``, ``bench_track.py
    --per-clip-json``; keys ``SEED:INDEX:THRESHOLD``) in which a dancer starts hidden behind another
    (``hidden_starts`` > 0), once each, in the file's order: the only clips a rule for such dancers can change. A
    one-line error where the file is missing, not such a file, or has no ``hidden_starts``."""
    try:
        clips = json.loads(Path(path).read_text())["clips"]
        pairs = []
        for key, row in clips.items():
            seed, index = (int(v) for v in key.split(":")[:2])
            if row["hidden_starts"] > 0 and (seed, index) not in pairs:
                pairs.append((seed, index))
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise SystemExit(f"hindsight_runs: {path} is no per-clip score file with hidden_starts "
                         f"({type(exc).__name__}: {exc})")
    return pairs


def starts_hidden(truth_boxes: np.ndarray, config=None) -> bool:
    """Whether a dancer of (T, N, 4) px ground-truth boxes starts hidden behind another by the tracker's own test
    (``MultiDancerTracker.add_dancer``: :func:`hdvr.tracking.state.straight_in_front`, with ``MultiTrackerConfig``
    ``config``, default the default one): at its start,
    another dancer started then or before covers more than ``hidden_start_overlap`` of its body core (intersection /
    smaller core) and stands in front (box bottom ``pixel_front`` x its height lower). Start boxes stand for the
    others' tracked boxes, which the tracker has there."""
    from hdvr.tracking.multi import MultiTrackerConfig
    from hdvr.tracking.state import straight_in_front

    c = config or MultiTrackerConfig()
    _, starts = _starts_from_truth(truth_boxes)
    return any(straight_in_front(front.box, start.box, c.core_aspect, c.hidden_start_overlap, c.pixel_front)
               for start in starts for front in starts if front is not start and front.frame <= start.frame)


def truth_hidden_start_clips(pairs, seconds: float = 4.0) -> list[tuple[int, int]]:
    """The (seed, clip index) of ``pairs`` in which a dancer starts hidden behind another (:func:`starts_hidden`),
    from the clips' motion and camera alone (generated without rendering, about 0.5 s a clip): the only clips a rule
    for such dancers can change, chosen before any is rendered or tracked."""
    import tempfile

    from hdvr.synth.groundtruth import make_clip

    kept = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed, index in pairs:
            spec = clip_spec(seed, index, seconds)
            make_clip(tmp, spec, render=False)
            truth_boxes, _ = _seen_truth(Path(tmp) / spec.name)
            if starts_hidden(truth_boxes):
                kept.append((seed, index))
    return kept


def save(args) -> int:
    from hdvr.synth.groundtruth import make_clip

    if args.hidden_starts_of:
        pairs = hidden_start_clips(args.hidden_starts_of)
    elif args.keys:
        pairs = [_key(k) for k in args.keys.split(",") if k.strip()]
    elif args.seeds:
        indices = _integers(args.clips) if args.clips else list(range(len(SYNTH_CLIPS)))
        pairs = [(seed, index) for seed in _integers(args.seeds) for index in indices]
    else:
        raise SystemExit("hindsight_runs: save needs --seeds (and optionally --clips), --keys or --hidden-starts-of")
    if any(not 0 <= i < len(SYNTH_CLIPS) for _, i in pairs):
        given = args.clips or args.keys or str(args.hidden_starts_of)
        raise SystemExit(f"hindsight_runs: clip indices are 0-{len(SYNTH_CLIPS) - 1}, got {given!r}")
    if args.hidden_starts_only:
        pairs = truth_hidden_start_clips(pairs, args.seconds)
        print(f"{len(pairs)} clips with a hidden start: {','.join(f'{s}_{i}' for s, i in pairs)}", file=sys.stderr)
    config = parse_tracker_config(args.tracker_config)
    args.runs.mkdir(parents=True, exist_ok=True)
    detector = default_tracking_detector()
    total, done = len(pairs), 0
    for seed, index in pairs:
        spec = clip_spec(seed, index, args.seconds)
        clip = synth_clip_folder(args.clips_dir, spec)
        if not (clip / "gt.npz").is_file() or not (clip / "video.mp4").is_file():
            make_clip(clip.parent, spec, render=True)
        truth_boxes, _ = _seen_truth(clip)
        order, starts = _starts_from_truth(truth_boxes)
        cached = args.detections / f"{seed}_{index}" if args.detections else None  # outputs and detections
        run = track_synth_clip(clip, cached or args.runs / "work", detector, starts, config, hindsight=False,
                               write=cached is not None, zoom=not args.no_zoom,
                               zoom_group=args.zoom_group)  # --no-zoom turns it off too (track_synth_clip)
        save_run(args.runs / f"{seed}_{index}.npz", run, order)
        done += 1
        print(f"\r{done}/{total} clips tracked", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    return 0


def kept_runs(clips_dir: Path, runs_dir: Path, prog: str = "hindsight_runs") -> list[tuple[Path, int, int, Path]]:
    """(run path, seed, clip index, clip folder) of every kept run ``SEED_INDEX.npz`` in ``runs_dir``, in seed and
    index order, each with its clip in ``clips_dir``; a one-line error (``prog: ...``) where there is none, or where
    a clip's ``gt.npz`` is missing."""
    paths = sorted(Path(runs_dir).glob("*_*.npz"), key=lambda p: tuple(int(v) for v in p.stem.split("_")))
    if not paths:
        raise SystemExit(f"{prog}: no kept runs (SEED_INDEX.npz) in {runs_dir}")
    out = []
    for path in paths:
        seed, index = (int(v) for v in path.stem.split("_"))
        clip = synth_clip_folder(clips_dir, clip_spec(seed, index))
        if not (clip / "gt.npz").is_file():
            raise SystemExit(f"{prog}: no ground truth for run {path.name}: {clip / 'gt.npz'} is missing")
        out.append((path, seed, index, clip))
    return out


def score(args) -> int:
    settings = parse_settings(args.set or [])
    scores = {}
    for path, seed, index, clip in kept_runs(args.clips_dir, args.runs):
        truth_boxes, _ = _seen_truth(clip)
        scores[f"{seed}:{index}:0.3"] = {"genre": SYNTH_CLIPS[index][0],
                                         **score_run(load_run(path), truth_boxes, settings)}
    print(f"{dataclasses.asdict(settings)}")
    print(summary(scores, scores))
    print("failing: " + " ".join(f"{k.rsplit(':', 1)[0]} {v['idf1']:.3f}/{v['id_switches']}"
                                 for k, v in scores.items() if failing(v)))
    if args.per_clip_json:
        with atomic_path(args.per_clip_json) as tmp:
            tmp.write_text(json.dumps({"hindsight": dataclasses.asdict(settings), "clips": scores}, indent=1))
    return 0


def stretches(args) -> int:
    settings = None if args.online else parse_settings(args.set or [])
    wanted = {k.strip() for k in args.keys.split(",") if k.strip()} if args.keys else None
    kept = kept_runs(args.clips_dir, args.runs)
    missing = sorted(wanted - {path.stem for path, *_ in kept}) if wanted else []
    if missing:
        raise SystemExit(f"hindsight_runs: no kept run for {', '.join(missing)} in {args.runs}")
    for path, seed, index, clip in kept:
        if wanted is not None and path.stem not in wanted:
            continue
        run = load_run(path)
        truth_boxes, _ = _seen_truth(clip)
        boxes = written_boxes(run, settings)
        scores = score_run(run, truth_boxes, settings, boxes)
        print(f"{path.stem} {SYNTH_CLIPS[index][0]}: IDF1 {scores['idf1']:.3f}, {scores['id_switches']} switches")
        for s in weak_stretches(boxes, truth_boxes, run["order"], run["status"]):
            on = "" if s["on_truth"] is None else f", on truth dancer {s['on_truth']}"
            print(f"  dancer {s['dancer']} (truth {s['truth']}) frames {s['start']}-{s['end'] - 1}: IoU "
                  f"{s['median_iou']:.2f} ({'/'.join(s['statuses'])}{on})")
    return 0


#: colour of the ground-truth boxes in :func:`draw_run_frames` (BGR; the dancers' own colours are
#: :func:`hdvr.pose2d.draw.dancer_colour`'s, none of them this green)
TRUTH_COLOUR = (0, 200, 0)


def draw_run_frames(frames: dict[int, np.ndarray], boxes: np.ndarray, truth_boxes: np.ndarray, order, status,
                    title: str = "", columns: int = 2) -> np.ndarray:
    """One BGR picture of ``frames`` (frame index -> BGR image of the clip), tiled ``columns`` a row in frame
    order: on each, every ground-truth box of ``truth_boxes`` (T, M, 4) px thin in green, labelled ``T<k>`` below
    it, and every written box of ``boxes`` (T, N, 4) px thick in its dancer's colour, labelled ``<dancer>-><truth
    index> <status>`` above it (``order``: written id -> ground-truth index; ``status``: T tuples of N strings),
    with ``title`` and the frame index in the corner; NaN boxes are left out. To see what :func:`weak_stretches`
    lists."""
    import cv2

    from hdvr.pose2d.draw import dancer_colour

    if not frames:
        raise ValueError("no frames to draw")
    font = cv2.FONT_HERSHEY_SIMPLEX
    tiles = []
    for t in sorted(frames):
        image = np.ascontiguousarray(frames[t]).copy()
        for k, g in enumerate(np.asarray(truth_boxes, float)[t]):
            if np.isfinite(g).all():
                x, y, w, h = (int(round(v)) for v in g)
                cv2.rectangle(image, (x, y), (x + w, y + h), TRUTH_COLOUR, 1)
                cv2.putText(image, f"T{k}", (x, y + h + 12), font, 0.4, TRUTH_COLOUR, 1)
        for i, b in enumerate(np.asarray(boxes, float)[t]):
            if np.isfinite(b).all():
                x, y, w, h = (int(round(v)) for v in b)
                colour = dancer_colour(i)
                cv2.rectangle(image, (x, y), (x + w, y + h), colour, 2)
                cv2.putText(image, f"{i}->{int(order[i])} {status[t][i]}", (x, max(y - 4, 10)), font, 0.45, colour, 1)
        cv2.putText(image, f"{title} frame {t}".strip(), (6, 16), font, 0.5, (255, 255, 255), 1)
        tiles.append(image)
    while len(tiles) % columns:
        tiles.append(np.zeros_like(tiles[0]))
    return np.concatenate([np.concatenate(tiles[r:r + columns], axis=1) for r in range(0, len(tiles), columns)])


def picture(args) -> int:
    import cv2

    from hdvr.video import read_frames

    settings = None if args.online else parse_settings(args.set or [])
    kept = {path.stem: (path, index, clip) for path, _, index, clip in kept_runs(args.clips_dir, args.runs)}
    if args.key not in kept:
        raise SystemExit(f"hindsight_runs: no kept run for {args.key} in {args.runs}")
    path, index, clip = kept[args.key]
    run = load_run(path)
    try:
        wanted = sorted({int(v) for v in args.frames.split(",") if v.strip()})
    except ValueError:
        raise SystemExit(f"hindsight_runs: --frames takes comma-separated frame numbers, got {args.frames!r}")
    count = len(run["status"])
    if not wanted or wanted[0] < 0 or wanted[-1] >= count:
        raise SystemExit(f"hindsight_runs: --frames must lie in 0-{count - 1} for {args.key}")
    suffix = args.out.suffix.lower()
    if suffix not in (".png", ".jpg", ".jpeg"):
        raise SystemExit(f"hindsight_runs: --out must end in .png or .jpg, got {args.out.name}")
    truth_boxes, _ = _seen_truth(clip)
    frames = dict(read_frames(clip / "video.mp4", wanted))
    image = draw_run_frames(frames, written_boxes(run, settings), truth_boxes, run["order"], run["status"],
                            title=f"{args.key} {SYNTH_CLIPS[index][0]}{' online' if args.online else ''}")
    ok, encoded = cv2.imencode(suffix, image)
    if not ok:
        raise SystemExit(f"hindsight_runs: could not encode {args.out.name}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(args.out) as tmp:
        tmp.write_bytes(encoded.tobytes())
    print(f"{args.out}: frames {','.join(map(str, wanted))} of {args.key}")
    return 0


def harm(args) -> int:
    settings = parse_settings(args.set or [])
    totals: dict[str, list[int]] = {}
    per_clip = []
    for path, _, _, clip in kept_runs(args.clips_dir, args.runs):
        run = load_run(path)
        truth_boxes, _ = _seen_truth(clip)
        moves = hindsight_moves(run["boxes"], written_boxes(run, settings), truth_boxes, run["order"], run["status"])
        for name, (harmed, mended) in moves.items():
            total = totals.setdefault(name, [0, 0])
            total[0] += harmed
            total[1] += mended
            per_clip.append((harmed - mended, harmed, mended, path.stem, name))
    print("dancer-frames hindsight moved off their dancer (IoU >= 0.5 online, below written) / onto it:")
    for name, (harmed, mended) in sorted(totals.items()):
        print(f"  {name}: {harmed} off, {mended} on")
    worst = sorted((row for row in per_clip if row[1] > 0), key=lambda row: (-row[0], row[3], row[4]))[:args.top]
    if worst:
        print(f"clips whose boxes it moved off most (net of those it moved on), top {len(worst)}:")
    for _, harmed, mended, key, name in worst:
        print(f"  {key} {name}: {harmed} off, {mended} on")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sv = sub.add_parser("save", help="track clips once with hindsight off and keep the runs")
    sv.add_argument("--clips-dir", type=Path, required=True)
    sv.add_argument("--seeds", help="comma-separated seeds (6 clips each, bench_track's SYNTH_CLIPS)")
    sv.add_argument("--keys", help="comma-separated SEED_INDEX clips to track instead of --seeds/--clips (e.g. again "
                                   "only those a rule can change)")
    sv.add_argument("--hidden-starts-of", type=Path, metavar="SCORES.json",
                    help="track instead the clips of this per-clip score file (score --per-clip-json) in which a "
                         "dancer starts hidden behind another: the only ones a rule for such dancers can change")
    sv.add_argument("--hidden-starts-only", action="store_true",
                    help="of the clips chosen, track only those in which a dancer starts hidden behind another, "
                         "told from their truth's start boxes before any is rendered (no score file needed)")
    sv.add_argument("--runs", type=Path, required=True, help="folder for the kept runs")
    sv.add_argument("--clips", help="comma-separated clip indices per seed (default all: "
                    + ", ".join(f"{i} {g} {n}" for i, (g, n) in enumerate(SYNTH_CLIPS)) + ")")
    sv.add_argument("--seconds", type=float, default=4.0, help="length of clips rendered here (benchmark: 4)")
    sv.add_argument("--tracker-config", default="", metavar="NAME=VALUE,...",
                    help="MultiTrackerConfig fields changed for these runs (as bench_track.py --tracker-config)")
    sv.add_argument("--detections", type=Path, help="folder keeping each clip's detections (SEED_INDEX/), reused by "
                                                    "later saves")
    sv.add_argument("--no-zoom", action="store_true", help="no detector crops about waiting or unposed dancers "
                                                           "nor about a group (hdvr track --no-zoom)")
    sv.add_argument("--zoom-group", action=argparse.BooleanOptionalAction, default=True,
                    help="the detector also on a crop about the group of dancers (default, as hdvr track; "
                         "--no-zoom-group: as hdvr track --no-zoom-group, the default before session 90)")
    sv.set_defaults(func=save)
    sc = sub.add_parser("score", help="score hindsight settings on kept runs")
    sc.add_argument("--clips-dir", type=Path, required=True)
    sc.add_argument("--runs", type=Path, required=True)
    sc.add_argument("--set", action="append", metavar="NAME=VALUE", help="a HindsightSettings field (repeatable)")
    sc.add_argument("--per-clip-json", type=Path, help="write per-clip scores here (bench_track's format)")
    sc.set_defaults(func=score)
    st = sub.add_parser("stretches", help="print where each dancer's box lies below IoU 0.5 with its truth, per "
                                          "kept run (median IoU, statuses, the truth dancer it lies on)")
    st.add_argument("--clips-dir", type=Path, required=True)
    st.add_argument("--runs", type=Path, required=True)
    st.add_argument("--keys", help="comma-separated SEED_INDEX runs (default: all kept)")
    st.add_argument("--set", action="append", metavar="NAME=VALUE", help="a HindsightSettings field (repeatable)")
    st.add_argument("--online", action="store_true", help="the online tracker's boxes, without hindsight")
    st.set_defaults(func=stretches)
    pc = sub.add_parser("picture", help="draw some frames of one kept run: each written box, coloured by dancer "
                                        "and labelled with its truth index and status, over the truth's boxes")
    pc.add_argument("--clips-dir", type=Path, required=True)
    pc.add_argument("--runs", type=Path, required=True)
    pc.add_argument("--key", required=True, help="the SEED_INDEX run")
    pc.add_argument("--frames", required=True, help="comma-separated frame numbers (0-based), two a row")
    pc.add_argument("--out", type=Path, required=True, help="picture to write (.png or .jpg)")
    pc.add_argument("--set", action="append", metavar="NAME=VALUE", help="a HindsightSettings field (repeatable)")
    pc.add_argument("--online", action="store_true", help="the online tracker's boxes, without hindsight")
    pc.set_defaults(func=picture)
    hm = sub.add_parser("harm", help="count, per status, the dancer-frames hindsight moved off their dancer (IoU 0.5) "
                                     "and onto it, and list the clips it moved off most")
    hm.add_argument("--clips-dir", type=Path, required=True)
    hm.add_argument("--runs", type=Path, required=True)
    hm.add_argument("--set", action="append", metavar="NAME=VALUE", help="a HindsightSettings field (repeatable)")
    hm.add_argument("--top", type=int, default=20, help="clips listed (default 20)")
    hm.set_defaults(func=harm)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
