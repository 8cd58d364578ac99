#!/usr/bin/env python3
"""Genre recognition through the whole pipeline: rendered synthetic clips -> ``hdvr run`` -> genre vs the truth.

    OMP_NUM_THREADS=1 python3 scripts/eval_genre_video.py --clips 9 --seconds 6 --out /tmp/genre-video

Each clip (seed ``--seed``, genres in turn, 1-2 dancers, 640x480) is rendered with hdvr.synth and analysed like any
video (YOLO11n-pose at 480 px on every 3rd frame, tracking, 3D fit, labels, the shipped genre recogniser, one
thread). Slow: about a minute per clip on 2 cores. Writes ``report.json`` in ``--out`` and prints a table.
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
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True)
    p.add_argument("--seed", type=int, default=3000)
    p.add_argument("--clips", type=int, default=9)
    p.add_argument("--seconds", type=float, default=6.0)
    p.add_argument("--dancers", default="1-2")
    p.add_argument("--recogniser", default="default", help="checkpoint (default: the shipped one)")
    args = p.parse_args(argv)
    import torch

    torch.set_num_threads(1)
    from hdvr.commands.synth import _parse_range
    from hdvr.io.atomic import write_text_atomic
    from hdvr.pipeline import analyse_video, load_genre_recogniser, make_detector
    from hdvr.synth.genres import GENRES
    from hdvr.synth.groundtruth import clip_spec, is_done, make_clip

    recogniser, reason = load_genre_recogniser(args.recogniser)
    if recogniser is None:
        raise SystemExit(f"no genre recogniser: {reason}")
    out = Path(args.out)
    detector = make_detector("yolo11n", 480, threads=1)
    rows = []
    for i in range(args.clips):
        t0 = time.perf_counter()
        spec = clip_spec(i, args.seed, GENRES, _parse_range(args.dancers), args.seconds)
        if not is_done(out / "synthetic", spec, True):
            make_clip(out / "synthetic", spec, render=True)
        result = analyse_video(out / "synthetic" / spec.name / "video.mp4", out / "analysis" / spec.name,
                               num_dancers=spec.n_dancers, detector=detector, recogniser=recogniser)
        g = result.genre
        row = {"clip": spec.name, "genre": spec.genre, "dancers": spec.n_dancers,
               "predicted": g.get("top"), "probability_of_truth": g.get("probabilities", {}).get(spec.genre),
               "dancer_predictions": [d.genre.get("top") for d in result.dancers],
               "seconds": round(time.perf_counter() - t0, 1)}
        rows.append(row)
        print(json.dumps(row), flush=True)
    videos = [r for r in rows if r["predicted"]]
    dancers = [(r["genre"], p) for r in rows for p in r["dancer_predictions"] if p]
    report = {"command": "python3 scripts/eval_genre_video.py " + " ".join(sys.argv[1:] if argv is None else argv),
              "recogniser": recogniser.source, "clips": rows,
              "video_accuracy": sum(r["predicted"] == r["genre"] for r in videos) / max(len(videos), 1),
              "dancer_accuracy": sum(t == p for t, p in dancers) / max(len(dancers), 1),
              "videos_with_genre": len(videos), "dancers_with_genre": len(dancers)}
    write_text_atomic(out / "report.json", json.dumps(report, indent=1))
    print(f"video accuracy {100 * report['video_accuracy']:.0f}% ({len(videos)} clips), dancer accuracy "
          f"{100 * report['dancer_accuracy']:.0f}% ({len(dancers)} dancers) -> {out / 'report.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
