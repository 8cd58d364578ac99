#!/usr/bin/env python3
"""What each part of the tracker contributes: hdvr synth clips tracked with one part switched off at a time.

Each variant is the full tracker (``hdvr track``'s defaults) with one part off: an online part of Algorithm 1* (a
:class:`hdvr.tracking.multi.MultiTrackerConfig` field, or the detector crops about single dancers), or an offline
step after it (a :class:`hdvr.tracking.hindsight.HindsightSettings` field, or hindsight as a whole). Online variants
track every clip again, on the detections of the full run (kept under ``WORK/detections``, so the whole-frame
detector runs once per clip); offline variants are scored on the full run's kept runs. Scored as
``bench_track.py --sections synth`` scores (IoU 0.5 against the amodal ground-truth boxes; a clip fails with IDF1
below 0.9 or an identity switch), and compared clip by clip with the full tracker.

    python3 scripts/ablate_tracking.py --clips-dir CLIPS --seeds $(seq -s, 2701 2720) --work WORK \\
        --out-md ablation.md --out-json ablation.json --plot ablation.png [--variants full,no_cone_patches] \\
        [--procs 2]

CLIPS holds ``synth-SEED/clip_0000I`` folders (rendered there when missing, 6 clips per seed as the benchmark's);
WORK keeps ``detections/`` and one ``runs-VARIANT/`` folder of ``SEED_INDEX.npz`` runs per online variant, so an
interrupted ablation goes on where it stopped (a clip whose run is there is not tracked again).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import NamedTuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import SYNTH_CLIPS, _seen_truth, parse_tracker_config  # noqa: E402
from compare_track_runs import failing  # noqa: E402
from hindsight_runs import kept_runs, load_run, parse_settings, save, score_run  # noqa: E402

from hdvr.io.atomic import atomic_path  # noqa: E402


class Variant(NamedTuple):
    """One row of the ablation: ``tracker`` MultiTrackerConfig fields ("name=value,..."), ``zoom`` (the detector
    crops about single dancers), ``hindsight`` HindsightSettings fields, or no hindsight at all."""

    name: str
    what: str
    tracker: str = ""
    zoom: bool = True
    hindsight_settings: tuple[str, ...] = ()
    hindsight: bool = True

    @property
    def online(self) -> bool:
        """Whether the clips are tracked again for this variant (else scored on the full run)."""
        return bool(self.tracker) or not self.zoom


VARIANTS = (
    Variant("full", "the full tracker, hdvr track's defaults"),
    Variant("no_cone_patches", "relocation (Algorithm 1*) takes detections and the dancer's own tracker's box only, "
            "not the patches of the cone search", tracker="relocate_patches=false"),
    Variant("no_velocity", "no velocity memory (stored velocity capped at 0): a hidden dancer is predicted, and "
            "looked for, where it was last seen", tracker="max_speed=0"),
    Variant("no_zoom", "no detector crops about dancers waiting hidden or seen without a pose, nor about a group",
            zoom=False),
    Variant("no_amodal_boxes", "hindsight without the learned whole-body box refiner",
            hindsight_settings=("amodal_boxes=false",)),
    Variant("no_follow_partner", "hindsight without carrying a couple's hidden partner with the dancer in front",
            hindsight_settings=("follow_partner=false",)),
    Variant("no_hindsight", "the online tracker's boxes as they are (no offline step)", hindsight=False),
)
VARIANTS_BY_NAME = {v.name: v for v in VARIANTS}


def parse_variants(text: str) -> list[Variant]:
    """The variants named in ``text`` (comma-separated; "full" always comes first); SystemExit naming an unknown
    one."""
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in VARIANTS_BY_NAME]
    if unknown:
        raise SystemExit(f"ablate_tracking: unknown variant(s) {', '.join(unknown)}; known: "
                         f"{', '.join(VARIANTS_BY_NAME)}")
    return [VARIANTS_BY_NAME["full"]] + [VARIANTS_BY_NAME[n] for n in names if n != "full"]


def runs_folder(work: Path, variant: Variant) -> Path:
    """Where ``variant``'s kept runs are: its own folder when it tracks again, else the full tracker's."""
    return work / f"runs-{variant.name if variant.online else 'full'}"


def _save_seed(job) -> int:
    """Track the six clips of one seed for one variant (a worker process); returns how many were tracked."""
    clips_dir, work, seed, variant_name = job
    variant = VARIANTS_BY_NAME[variant_name]
    runs = runs_folder(work, variant)
    todo = [i for i in range(len(SYNTH_CLIPS)) if not (runs / f"{seed}_{i}.npz").is_file()]
    if not todo:
        return 0
    args = argparse.Namespace(keys=",".join(f"{seed}_{i}" for i in todo), seeds=None, clips=None,
                              clips_dir=clips_dir, runs=runs, seconds=4.0, tracker_config=variant.tracker,
                              detections=work / "detections", no_zoom=not variant.zoom,
                              zoom_group=variant.zoom)
    save(args)
    return len(todo)


def score_variant(clips_dir: Path, work: Path, variant: Variant) -> dict:
    """Per-clip scores ("SEED:INDEX" -> genre, idf1, id_switches, hota, mota) of ``variant`` on its kept runs."""
    settings = parse_settings(list(variant.hindsight_settings))
    scores = {}
    for path, seed, index, clip in kept_runs(clips_dir, runs_folder(work, variant), prog="ablate_tracking"):
        truth_boxes, _ = _seen_truth(clip)
        row = score_run(load_run(path), truth_boxes, settings if variant.hindsight else None)
        scores[f"{seed}:{index}"] = {"genre": SYNTH_CLIPS[index][0], **{k: row[k] for k in
                                                                         ("idf1", "id_switches", "mota", "hota")}}
    return scores


def summarise(scores: dict, full: dict) -> dict:
    """Mean IDF1, HOTA and MOTA, clips failing (IDF1 < 0.9 or a switch), switches, and clips up / down by more than
    0.005 IDF1 against ``full`` (the same keys)."""
    rows = list(scores.values())
    keys = [k for k in scores if k in full]
    return {"clips": len(rows), "mean_idf1": statistics.fmean(r["idf1"] for r in rows),
            "mean_hota": statistics.fmean(r["hota"] for r in rows),
            "mean_mota": statistics.fmean(r["mota"] for r in rows),
            "failing": sum(failing(r) for r in rows), "switches": sum(r["id_switches"] for r in rows),
            "up": sum(scores[k]["idf1"] > full[k]["idf1"] + 0.005 for k in keys),
            "down": sum(scores[k]["idf1"] < full[k]["idf1"] - 0.005 for k in keys)}


def markdown_table(variants: list[Variant], summaries: dict) -> str:
    """The ablation as a markdown table, one row per variant."""
    lines = ["| variant | what is off | mean IDF1 | failing clips | switches | mean HOTA | mean MOTA | "
             "clips up / down vs full |", "|---|---|---|---|---|---|---|---|"]
    for v in variants:
        s = summaries[v.name]
        updown = "-" if v.name == "full" else f"{s['up']} / {s['down']}"
        lines.append(f"| `{v.name}` | {v.what} | {s['mean_idf1']:.4f} | {s['failing']} of {s['clips']} | "
                     f"{s['switches']} | {s['mean_hota']:.4f} | {s['mean_mota']:.4f} | {updown} |")
    return "\n".join(lines) + "\n"


def plot(path: Path, variants: list[Variant], summaries: dict) -> None:
    """Bars of failing clips and mean HOTA per variant, written atomically."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [v.name for v in variants]
    fig, axes = plt.subplots(1, 2, figsize=(10, 0.45 * len(names) + 1.5), sharey=True)
    y = np.arange(len(names))
    axes[0].barh(y, [summaries[n]["failing"] for n in names], color="#c0504d")
    axes[0].set_xlabel("clips failing (IDF1 < 0.9 or a switch)")
    axes[1].barh(y, [summaries[n]["mean_hota"] for n in names], color="#4f81bd")
    axes[1].set_xlabel("mean HOTA")
    axes[1].set_xlim(min(summaries[n]["mean_hota"] for n in names) - 0.02, 1.0)
    axes[0].set_yticks(y, names)
    axes[0].invert_yaxis()
    clips = summaries["full"]["clips"]
    fig.suptitle(f"Tracker ablation, {clips} hdvr synth clips (one part off at a time)")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clips-dir", type=Path, required=True)
    parser.add_argument("--seeds", required=True, help="comma-separated seeds (6 clips each)")
    parser.add_argument("--work", type=Path, required=True, help="folder for detections and kept runs")
    parser.add_argument("--variants", default=",".join(VARIANTS_BY_NAME),
                        help="comma-separated variants (default all: " + ", ".join(VARIANTS_BY_NAME) + ")")
    parser.add_argument("--procs", type=int, default=2, help="seeds tracked at once")
    parser.add_argument("--out-md", type=Path, help="write the table here")
    parser.add_argument("--out-json", type=Path, help="write summaries and per-clip scores here")
    parser.add_argument("--plot", type=Path, help="write a bar chart here (PNG)")
    args = parser.parse_args(argv)
    variants = parse_variants(args.variants)
    for v in variants:
        parse_tracker_config(v.tracker)  # a wrong field name fails before any tracking
    try:
        seeds = [int(s) for s in args.seeds.split(",") if s.strip()]
    except ValueError:
        raise SystemExit(f"ablate_tracking: --seeds takes comma-separated integers, got {args.seeds!r}") from None
    if not seeds or args.procs < 1:
        raise SystemExit("ablate_tracking: give at least one seed and --procs >= 1")
    for v in variants:
        if v.name != "full" and not v.online:
            continue
        jobs = [(args.clips_dir, args.work, seed, v.name) for seed in seeds]
        print(f"{v.name}: tracking {len(seeds) * len(SYNTH_CLIPS)} clips", file=sys.stderr)
        if args.procs == 1:
            for job in jobs:
                _save_seed(job)
        else:
            with ProcessPoolExecutor(args.procs) as pool:
                list(pool.map(_save_seed, jobs))
    wanted = {f"{seed}:{i}" for seed in seeds for i in range(len(SYNTH_CLIPS))}
    scores = {v.name: {k: r for k, r in score_variant(args.clips_dir, args.work, v).items() if k in wanted}
              for v in variants}
    summaries = {v.name: summarise(scores[v.name], scores["full"]) for v in variants}
    table = markdown_table(variants, summaries)
    print(table)
    if args.out_md:
        with atomic_path(args.out_md) as tmp:
            tmp.write_text(table)
    if args.out_json:
        with atomic_path(args.out_json) as tmp:
            tmp.write_text(json.dumps({"seeds": seeds, "summaries": summaries, "clips": scores}, indent=1))
    if args.plot:
        plot(args.plot, variants, summaries)
    return 0


if __name__ == "__main__":
    sys.exit(main())
