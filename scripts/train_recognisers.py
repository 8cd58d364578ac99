#!/usr/bin/env python3
"""Train the genre recogniser that ``hdvr run`` ships with, and measure it on held-out synthetic clips.

    OMP_NUM_THREADS=1 python3 scripts/train_recognisers.py            # -> hdvr/data/recognisers.pt (CPU, 1 thread)

1. Training data: ``--train-clips`` synthetic clips of seed ``--seed`` (hdvr.synth, the nine genres in turn,
   ``--seconds`` long, 1-2 dancers; motion only, nothing rendered). Each dancer's 3D motion is labelled by the
   pipeline's labeller (hdvr.movements, smoothing as in ``hdvr run``) once exactly and ``--augment`` times after
   disturbing it like a 3D fit (hdvr.recognition.genre.perturb_motion, level drawn in 0.2-1.2).
2. The genre LSTM learns the genre from those label sequences (random 4 s crops at 15 fps).
3. Held out (other seeds): ``--eval-clips`` clips labelled from exact 3D and from 3D disturbed at level 0.6, and
   ``--fitted-clips`` clips whose 2D keypoints (the 19 joints a COCO-17 detector gives, 3 px noise) go through
   the real 3D fit (hdvr.fitting) before labelling. Per-genre accuracy and confusion matrices go to ``--report``
   (JSON) and ``--figure`` (PNG, when matplotlib is installed); the headline figures go into the checkpoint.

Deterministic for a seed (same data, same initial weights, same crops; one torch thread). Movement LSTMs are not
trained: ``hdvr run`` labels movements with the rule-based labeller, which is also what the genre LSTM reads.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("MUJOCO_GL", "egl")
REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import numpy as np  # noqa: E402


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=str(REPO / "hdvr" / "data" / "recognisers.pt"), help="checkpoint to write")
    p.add_argument("--seed", type=int, default=0, help="training seed; held-out clips use seed+1000 and seed+2000")
    p.add_argument("--train-clips", type=int, default=900)
    p.add_argument("--seconds", type=float, default=8.0, help="length of the training and held-out clips")
    p.add_argument("--augment", type=int, default=3, help="disturbed copies of each training dancer")
    p.add_argument("--epochs", type=int, default=16)
    p.add_argument("--hidden", type=int, default=128)
    p.add_argument("--layers", type=int, default=1)
    p.add_argument("--input-dropout", type=float, default=0.2, help="fraction of label entries dropped in training")
    p.add_argument("--weight-decay", type=float, default=0.01)
    p.add_argument("--eval-clips", type=int, default=90, help="held-out clips labelled from exact/disturbed 3D")
    p.add_argument("--fitted-clips", type=int, default=27, help="held-out clips through the real 3D fit (slow, "
                                                                 "about 8 s each)")
    p.add_argument("--report", default=str(REPO / "docs" / "genre_eval.json"))
    p.add_argument("--figure", default=str(REPO / "docs" / "img" / "genre_confusion.png"))
    p.add_argument("--threads", type=int, default=1, help="torch threads")
    return p.parse_args(argv)


def confusion_figure(path: Path, panels: list[tuple[str, dict]], genres: list[str]) -> bool:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no confusion picture")
        return False
    from hdvr.io.atomic import atomic_path

    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 5.0), squeeze=False)
    for ax, (title, res) in zip(axes[0], panels):
        conf = np.array(res["confusion"], dtype=float)
        rows = conf / np.maximum(conf.sum(1, keepdims=True), 1)
        ax.imshow(rows, cmap="Blues", vmin=0, vmax=1)
        for i in range(len(genres)):
            for j in range(len(genres)):
                if conf[i, j]:
                    ax.text(j, i, int(conf[i, j]), ha="center", va="center", fontsize=7,
                            color="white" if rows[i, j] > 0.5 else "black")
        ax.set_xticks(range(len(genres)), genres, rotation=60, ha="right", fontsize=8)
        ax.set_yticks(range(len(genres)), genres, fontsize=8)
        ax.set_xlabel("predicted")
        ax.set_ylabel("true")
        ax.set_title(f"{title}\naccuracy {100 * res['accuracy']:.0f}% ({res['sequences']} dancers)", fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return True


def main(argv=None) -> int:
    args = parse_args(argv)
    import torch

    torch.set_num_threads(args.threads)
    from hdvr.io.atomic import write_text_atomic
    from hdvr.recognition.genre import GENRE_FPS, GENRE_WINDOW, PIPELINE_SMOOTHING_S
    from hdvr.recognition.genre_data import evaluate, fitted_sequences, synthetic_sequences, train_genre
    from hdvr.recognition.train import save_recognisers
    from hdvr.synth.genres import GENRES

    clock = time.perf_counter()
    command = ("python3 scripts/train_recognisers.py " + " ".join(sys.argv[1:] if argv is None else argv)).strip()
    print(f"1/4 training data: {args.train_clips} synthetic clips (seed {args.seed}), exact + {args.augment} "
          "disturbed labellings per dancer", flush=True)
    train = synthetic_sequences(args.seed, args.train_clips, args.seconds, levels=(0.0,),
                                random_levels=args.augment, desc="training clips")
    held = synthetic_sequences(args.seed + 1000, args.eval_clips, args.seconds, levels=(0.0, 0.6),
                               desc="held-out clips")
    exact = [s for s in held if s.level == 0.0]
    noisy = [s for s in held if s.level == 0.6]
    print(f"   {len(train)} training sequences, {len(exact)} held-out dancers "
          f"({time.perf_counter() - clock:.0f} s)", flush=True)

    print(f"2/4 training the genre LSTM ({args.epochs} epochs, hidden {args.hidden}, {args.layers} layer(s))",
          flush=True)
    t0 = time.perf_counter()
    model, history = train_genre(train, len(GENRES), epochs=args.epochs, hidden=args.hidden, layers=args.layers,
                                 seed=args.seed, validation=noisy, input_dropout=args.input_dropout,
                                 weight_decay=args.weight_decay)
    train_s = time.perf_counter() - t0

    print(f"3/4 held-out evaluation ({args.fitted_clips} clips through the real 3D fit)", flush=True)
    results = {"held_out_exact_3d": evaluate(model, exact, len(GENRES)),
               "held_out_disturbed_3d": evaluate(model, noisy, len(GENRES))}
    if args.fitted_clips > 0:
        fitted = fitted_sequences(args.seed + 2000, args.fitted_clips, args.seconds)
        results["held_out_fitted_3d"] = evaluate(model, fitted, len(GENRES))
    for name, res in results.items():
        per = ", ".join(f"{g} {100 * a:.0f}%" for g, a in zip(GENRES, res["per_genre_accuracy"]))
        print(f"   {name}: accuracy {100 * res['accuracy']:.1f}% on {res['sequences']} dancers ({per})")

    print("4/4 writing the checkpoint, report and figure", flush=True)
    seconds = time.perf_counter() - clock
    meta = {"genres": list(GENRES), "genre_fps": GENRE_FPS, "genre_window": GENRE_WINDOW,
            "labeller_smoothing_s": PIPELINE_SMOOTHING_S, "seed": args.seed, "train_clips": args.train_clips,
            "train_sequences": len(train), "seconds": args.seconds, "augment": args.augment, "epochs": args.epochs,
            "hidden": args.hidden, "layers": args.layers, "input_dropout": args.input_dropout,
            "command": command, "torch": str(torch.__version__),
            "held_out_accuracy": {k: round(v["accuracy"], 4) for k, v in results.items()}}
    save_recognisers(args.out, {}, model, {}, meta)
    report = {"command": command, "seconds": round(seconds, 1), "training_seconds": round(train_s, 1),
              "threads": args.threads, "genres": list(GENRES), "checkpoint": str(args.out),
              "checkpoint_bytes": os.path.getsize(args.out), "history": history, "results": results}
    write_text_atomic(args.report, json.dumps(report, indent=1))
    panels = [("held out, 3D disturbed like a fit", results["held_out_disturbed_3d"])]
    if "held_out_fitted_3d" in results:
        panels.append(("held out, real 3D fit of 2D keypoints", results["held_out_fitted_3d"]))
    confusion_figure(Path(args.figure), panels, list(GENRES))
    print(f"done in {seconds / 60:.1f} min: {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB), "
          f"{args.report}, {args.figure}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
