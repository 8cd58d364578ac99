#!/usr/bin/env python3
"""Compare two ``scripts/bench_track.py --per-clip-json`` runs of the synthetic clips: the clips whose IDF1 or
identity switches changed, and each run's summary (mean IDF1, clips below 0.9, switches) over the clips both hold.

Usage: python3 scripts/compare_track_runs.py BEFORE.json AFTER.json [--tolerance 0.0005]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path


def load_clips(path: Path) -> dict[str, dict]:
    """The per-clip scores ("seed:index[:groups]:threshold" -> {genre, dancers, idf1, id_switches,
    hidden_starts, and since session 47 mota, hota, idf1_iou04, id_switches_iou04}) of one run's JSON file."""
    try:
        data = json.loads(Path(path).read_text())
        return data["clips"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SystemExit(f"compare_track_runs: {path} is not a bench_track --per-clip-json file ({exc})")


def changed_clips(before: dict, after: dict, tolerance: float = 5e-4) -> list[tuple[str, dict, dict]]:
    """(clip, before, after) for the clips in both runs whose IDF1 moved by more than ``tolerance`` or whose
    identity switches differ, in the order of ``before``."""
    return [(k, before[k], after[k]) for k in before if k in after
            and (abs(before[k]["idf1"] - after[k]["idf1"]) > tolerance
                 or before[k]["id_switches"] != after[k]["id_switches"])]


def failing(row: dict, idf1: str = "idf1", switches: str = "id_switches") -> bool:
    """Whether a clip misses the tracking target: IDF1 below 0.9 or an identity switch."""
    return row[idf1] < 0.9 or row[switches] > 0


def summary(clips: dict, keys) -> str:
    """'N clips, mean IDF1 m, k below 0.9, s switches on c clips, f failing' over ``keys``; with mean HOTA and
    the failing clips at IoU 0.4 when every clip has them (runs since session 47). A clip's figure moves with tiny
    changes of its start (docs/benchmarks.md "session 47"): the counts and means are the figures to compare."""
    rows = [clips[k] for k in keys]
    if not rows:
        return "no clip"
    mean = statistics.fmean(r["idf1"] for r in rows)
    switches = sum(r["id_switches"] for r in rows)
    text = (f"{len(rows)} clips, mean IDF1 {mean:.4f}, {sum(r['idf1'] < 0.9 for r in rows)} below 0.9, "
            f"{switches} switches on {sum(r['id_switches'] > 0 for r in rows)} clips, "
            f"{sum(failing(r) for r in rows)} failing")
    if all("hota" in r and "idf1_iou04" in r for r in rows):
        text += (f"; mean HOTA {statistics.fmean(r['hota'] for r in rows):.4f}, "
                 f"{sum(failing(r, 'idf1_iou04', 'id_switches_iou04') for r in rows)} failing at IoU 0.4")
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--tolerance", type=float, default=5e-4, help="IDF1 change below which a clip is the same")
    args = parser.parse_args(argv)
    before, after = load_clips(args.before), load_clips(args.after)
    common = [k for k in before if k in after]
    for key, b, a in changed_clips(before, after, args.tolerance):
        print(f"{key} {b['genre']}: IDF1 {b['idf1']:.3f} -> {a['idf1']:.3f}, "
              f"switches {b['id_switches']} -> {a['id_switches']}")
    print(f"{args.before}: {summary(before, common)}")
    print(f"{args.after}: {summary(after, common)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
