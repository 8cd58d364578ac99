#!/usr/bin/env python3
"""Plot per-clip IDF1 with the real detector against IDF1 with a perfect one: which failures are the detector's.

Reads ``scripts/bench_track.py --sections synth --per-clip-json`` files: the first ``--run`` (x axis) is the real
detector's (YOLO11n-pose), each further ``--run`` (one panel each, y axis) the same clips tracked with
``--synth-detector truth`` or ``truth-amodal``. Clips are matched by seed and clip index (the threshold part of the
keys differs between runs). A dot per clip, orange where a dancer starts hidden behind another, a black ring where
the run on that axis has identity switches; the lines mark the target (IDF1 0.9). A clip below or left of a line
fails the target with that detector; the panel's title counts the clips failing with each, and with both.

    python3 scripts/plot_detector_bound.py --run YOLO11n-pose=yolo_a.json,yolo_b.json \\
        --run "perfect, visible boxes=truth_a.json,truth_b.json" --out docs/img/tracking_detector_bound.png
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_track_runs import load_clips  # noqa: E402

TARGET = 0.9


def clip_key(key: str) -> str:
    """"seed:index[:groups]" of a per-clip key "seed:index[:groups]:threshold"."""
    return key.rsplit(":", 1)[0]


def load_run(spec: str) -> tuple[str, dict[str, dict]]:
    """(label, clip -> scores) from "LABEL=FILE[,FILE...]"; files are merged."""
    label, sep, files = spec.partition("=")
    if not sep or not files:
        raise SystemExit(f"plot_detector_bound: --run takes LABEL=FILE[,FILE...], got {spec!r}")
    clips: dict[str, dict] = {}
    for name in files.split(","):
        clips.update({clip_key(k): v for k, v in load_clips(Path(name)).items()})
    return label, clips


def fails(scores: dict) -> bool:
    """Whether a clip misses the target: IDF1 below 0.9 or an identity switch."""
    return scores["idf1"] < TARGET or scores["id_switches"] > 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", action="append", required=True, help="LABEL=FILE[,FILE...]; first: the x axis")
    parser.add_argument("--out", type=Path, default=Path("docs/img/tracking_detector_bound.png"))
    args = parser.parse_args(argv)
    if len(args.run) < 2:
        raise SystemExit("plot_detector_bound: give at least two --run (the real detector, then a perfect one)")
    runs = [load_run(spec) for spec in args.run]

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (x_label, x_clips), panels = runs[0], runs[1:]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 5.2), squeeze=False)
    for ax, (y_label, y_clips) in zip(axes[0], panels):
        common = [k for k in x_clips if k in y_clips]
        if not common:
            raise SystemExit(f"plot_detector_bound: no clip in both '{x_label}' and '{y_label}'")
        for hidden, colour in ((False, "tab:blue"), (True, "tab:orange")):
            keys = [k for k in common if (x_clips[k]["hidden_starts"] > 0) == hidden]
            ax.scatter([x_clips[k]["idf1"] for k in keys], [y_clips[k]["idf1"] for k in keys], s=14, c=colour,
                       alpha=0.7, label="a dancer starts hidden" if hidden else "every dancer starts seen")
        ringed = [k for k in common if y_clips[k]["id_switches"] > 0 or x_clips[k]["id_switches"] > 0]
        ax.scatter([x_clips[k]["idf1"] for k in ringed], [y_clips[k]["idf1"] for k in ringed], s=60,
                   facecolors="none", edgecolors="black", linewidths=0.8, label="identity switches")
        ax.axvline(TARGET, color="grey", lw=0.8, ls="--")
        ax.axhline(TARGET, color="grey", lw=0.8, ls="--")
        ax.plot([0, 1], [0, 1], color="grey", lw=0.5)  # the same IDF1 with both detectors
        fx, fy = ({k for k in common if fails(c[k])} for c in (x_clips, y_clips))
        ax.set_title(f"{len(common)} clips failing: {len(fx)} with {x_label},\n{len(fy)} with {y_label}, "
                     f"{len(fx & fy)} with both", fontsize=9)
        ax.set_xlabel(f"IDF1, {x_label}")
        ax.set_ylabel(f"IDF1, {y_label}")
        low = min(0.5, *(c[k]["idf1"] for c in (x_clips, y_clips) for k in common)) - 0.02  # the spread above 0.5
        ax.set_xlim(low, 1.01)
        ax.set_ylim(low, 1.01)
        ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_name(args.out.stem + ".tmp" + args.out.suffix)
    fig.savefig(tmp, dpi=110)
    tmp.replace(args.out)  # written whole or not at all
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
