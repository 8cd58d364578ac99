#!/usr/bin/env python3
"""Train the amodal box refiner (hdvr/tracking/amodal.py) on tracked hdvr synth clips, cross-validate or score it.

The refiner learns, from clips whose ground truth is the whole (amodal) body, how far each seen dancer's box after
the other hindsight steps lies from it. Its inputs are the runs ``scripts/hindsight_runs.py save`` keeps (the
online tracker's boxes, statuses and keypoints, hindsight off) and the clips' ``gt.npz``. Each ``--data CLIPS:RUNS``
pair is one set of clips (one fold in ``--cross-validate``).

    # the shipped weights: all sets, written atomically
    python3 scripts/train_amodal_boxes.py train --data T_CLIPS:T_RUNS --data A_CLIPS:A_RUNS --data B_CLIPS:B_RUNS \\
        --out hdvr/data/amodal_boxes.pt
    # how it does on clips it was not trained on: each set scored with weights trained on the others
    python3 scripts/train_amodal_boxes.py cross-validate --data ... --data ... [--json F]
    # given weights on other clips (a fresh set)
    python3 scripts/train_amodal_boxes.py score --weights hdvr/data/amodal_boxes.pt --data C_CLIPS:C_RUNS

A clip fails when its IDF1 is below 0.9 or it has an identity switch (issue 5's target), at IoU 0.5. Deterministic
for ``--seed`` on the CPU. Takes about a minute per 500 clips to train (2 cores).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import SYNTH_CLIPS, _seen_truth  # noqa: E402
from compare_track_runs import failing  # noqa: E402
from hindsight_runs import kept_runs, load_run  # noqa: E402

from hdvr.io.atomic import atomic_path  # noqa: E402
from hdvr.tracking.amodal import (AmodalBoxRefiner, amodal_features, edge_targets, refine_boxes,  # noqa: E402
                                  train_refiner)
from hdvr.tracking.evaluation import evaluate_tracking  # noqa: E402
from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight  # noqa: E402

UNREFINED = HindsightSettings(amodal_boxes=False, follow_partner=False)  # the boxes the refiner is given


class Clip(NamedTuple):
    """One tracked clip: its kept run, its boxes after hindsight without the refiner (T, N, 4) px, and its ground
    truth (T, N, 4) px in the run's dancer order."""

    set_name: str
    key: str
    run: dict
    boxes: np.ndarray
    truth: np.ndarray


def load_set(spec: str) -> list[Clip]:
    """The clips of one ``CLIPS:RUNS`` pair (every ``SEED_INDEX.npz`` in RUNS with its clip in CLIPS)."""
    clips_dir, _, runs_dir = spec.partition(":")
    clips_dir, runs_dir = Path(clips_dir), Path(runs_dir)
    if not runs_dir.is_dir() or not clips_dir.is_dir():
        raise SystemExit(f"train_amodal_boxes: --data {spec}: need CLIPS:RUNS folders")
    out = []
    for path, _, _, clip in kept_runs(clips_dir, runs_dir, prog="train_amodal_boxes"):
        run = load_run(path)
        truth, _ = _seen_truth(clip)
        boxes = apply_hindsight(run["boxes"], run["status"], run["keypoints"], frame_width=float(run["width"]),
                                hidden_starts=run["hidden_starts"], settings=UNREFINED,
                                stopped_behind=run["stopped_behind"], returned_behind=run["returned_behind"])[0]
        out.append(Clip(str(runs_dir), path.stem, run, boxes, truth[:, run["order"]]))
    return out


def training_rows(clips: list[Clip]) -> tuple[np.ndarray, np.ndarray]:
    """Features and targets of every dancer-frame with a box and a ground-truth box (all statuses)."""
    xs, ys = [], []
    for c in clips:
        features, usable = amodal_features(c.boxes, c.run["status"], c.run["keypoints"])
        targets = edge_targets(c.boxes, c.truth)
        rows = usable & np.isfinite(targets).all(axis=2)
        xs.append(features[rows])
        ys.append(targets[rows])
    return np.concatenate(xs), np.concatenate(ys)


def score_clips(clips: list[Clip], refiner: AmodalBoxRefiner | None) -> dict:
    """Per clip IDF1, switches and HOTA of the boxes, refined by ``refiner`` (None: as hindsight leaves them)."""
    out = {}
    for c in clips:
        boxes = c.boxes if refiner is None else refine_boxes(c.boxes, c.run["status"], c.run["keypoints"], refiner)
        # the truth is in the run's order; the evaluation wants the boxes in the truth's
        s = evaluate_tracking(c.truth, boxes)
        index = int(c.key.split("_")[1])
        out[c.key] = {"genre": SYNTH_CLIPS[index][0], "idf1": s.idf1, "id_switches": s.id_switches, "hota": s.hota}
    return out


def summarise(name: str, before: dict, after: dict) -> dict:
    """Failing clips (:func:`compare_track_runs.failing`), mean IDF1 and HOTA before and after, and the clips mended
    and broken."""
    keys = sorted(before)
    return {"set": name, "clips": len(keys),
            "failing_before": sum(failing(before[k]) for k in keys),
            "failing_after": sum(failing(after[k]) for k in keys),
            "idf1_before": float(np.mean([before[k]["idf1"] for k in keys])),
            "idf1_after": float(np.mean([after[k]["idf1"] for k in keys])),
            "hota_before": float(np.mean([before[k]["hota"] for k in keys])),
            "hota_after": float(np.mean([after[k]["hota"] for k in keys])),
            "mended": [k for k in keys if failing(before[k]) and not failing(after[k])],
            "broken": [k for k in keys if not failing(before[k]) and failing(after[k])]}


def print_summary(s: dict) -> None:
    print(f"{s['set']}: {s['clips']} clips, failing {s['failing_before']} -> {s['failing_after']}, "
          f"mean IDF1 {s['idf1_before']:.4f} -> {s['idf1_after']:.4f}, HOTA {s['hota_before']:.4f} -> "
          f"{s['hota_after']:.4f}; mended {', '.join(s['mended']) or '-'}; broken {', '.join(s['broken']) or '-'}",
          flush=True)


def train(clips: list[Clip], args) -> dict:
    x, y = training_rows(clips)
    print(f"training on {len(x)} dancer-frames of {len(clips)} clips"
          f"{'' if args.no_mirror else ' and their mirror images'}", flush=True)
    started = time.perf_counter()
    payload = train_refiner(x, y, hidden=args.hidden, dropout=args.dropout, epochs=args.epochs,
                            members=args.members, mirror=not args.no_mirror, seed=args.seed,
                            progress=lambda m, e, loss: print(f"  network {m + 1}/{args.members} epoch "
                                                              f"{e + 1}/{args.epochs}: loss {loss:.4f}", flush=True))
    print(f"  {time.perf_counter() - started:.0f} s", flush=True)
    return payload


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=("train", "cross-validate", "score"))
    parser.add_argument("--data", action="append", required=True, metavar="CLIPS:RUNS",
                        help="clips folder (bench_track.py --clips-dir layout) and kept runs (hindsight_runs.py save)")
    parser.add_argument("--out", type=Path, help="train: where to write the weights")
    parser.add_argument("--weights", type=Path, help="score: the weights (default: the shipped ones)")
    parser.add_argument("--hidden", type=int, default=64)
    parser.add_argument("--dropout", type=float, default=0.2)
    parser.add_argument("--epochs", type=int, default=10)
    parser.add_argument("--members", type=int, default=3, help="networks in the ensemble")
    parser.add_argument("--no-mirror", action="store_true", help="train without the mirror images of the rows")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, help="write the summaries (and per-clip scores) here")
    args = parser.parse_args(argv)
    import torch

    torch.set_num_threads(max(1, min(2, os.cpu_count() or 1)))
    sets = {spec: load_set(spec) for spec in args.data}
    print(f"loaded {sum(len(v) for v in sets.values())} clips in {len(sets)} sets", flush=True)
    report = {"summaries": [], "per_clip": {}}
    if args.command == "train":
        if args.out is None:
            raise SystemExit("train_amodal_boxes: train needs --out")
        payload = train([c for v in sets.values() for c in v], args)
        payload["trained_on"] = [f"{spec} ({len(v)} clips)" for spec, v in sets.items()]
        with atomic_path(args.out) as tmp:  # the folder is made if missing
            torch.save(payload, tmp)
        print(f"wrote {args.out}")
    elif args.command == "cross-validate":
        if len(sets) < 2:
            raise SystemExit("train_amodal_boxes: cross-validate needs two --data sets or more")
        for held, clips in sets.items():
            print(f"fold: {held} held out", flush=True)
            refiner = AmodalBoxRefiner(train([c for s, v in sets.items() if s != held for c in v], args))
            before, after = score_clips(clips, None), score_clips(clips, refiner)
            summary = summarise(held, before, after)
            print_summary(summary)
            report["summaries"].append(summary)
            report["per_clip"][held] = {"before": before, "after": after}
    else:
        refiner = AmodalBoxRefiner.load(args.weights) if args.weights else AmodalBoxRefiner.load()
        for name, clips in sets.items():
            before, after = score_clips(clips, None), score_clips(clips, refiner)
            summary = summarise(name, before, after)
            print_summary(summary)
            report["summaries"].append(summary)
            report["per_clip"][name] = {"before": before, "after": after}
    if args.json:
        args.json.write_text(json.dumps(report, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
