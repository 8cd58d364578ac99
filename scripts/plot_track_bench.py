"""Plot the synthetic-dancer tracking benchmark: IDF1 per clip, per seed, against the target.

Reads the synthetic-clip tables that ``scripts/bench_track.py --sections synth`` writes (markdown rows
``| seed | clip_XXXXX genre | dancers | threshold | IDF1 | MOTA | HOTA | ID switches | ...``) from the named sections
of a markdown file (default docs/benchmarks.md) and draws one dot per clip: x = clip (genre and dancer count),
y = IDF1, one colour per seed (past 10 seeds the colours repeat with another marker), a ring around clips with
identity switches, the 0.9 target as a line. ``--colour-by hidden`` colours the clips instead by whether a dancer
starts hidden (the "starts hidden" column of the tables since session 14). Where the table has the column
"IDF1 / switches at IoU 0.4" (since session 12), a clip below the target or with switches also gets a grey tick at
that IDF1: how much of its loss is box extent rather than identity.

``--per-clip-json F ...`` plots the per-clip scores that ``scripts/hindsight_runs.py score --per-clip-json`` and
``scripts/bench_track.py --per-clip-json`` write instead of the markdown tables (a fresh set of hundreds of clips is
kept as such a file, not as a table); the clips are then coloured by whether a dancer starts hidden unless
``--colour-by seed`` is given.

    python3 scripts/plot_track_bench.py [--markdown docs/benchmarks.md] [--out docs/img/tracking_synth_idf1.png]
                                        [--sections HEADING ...] [--colour-by seed|hidden]
    python3 scripts/plot_track_bench.py --per-clip-json RUN.json [...] --out PNG [--title TEXT]
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

DEFAULT_SECTIONS = ("### Synthetic dancers, seeds 7-139 (session 13)",
                    "### Synthetic dancers, fresh seeds 151, 163 and 173 (session 13)")
NUMBER = r"\s*(-?[\d.]+)\s*\|"
# seed | clip_XXXXX genre | dancers | threshold | IDF1 | MOTA | HOTA | ID switches |
ROW = re.compile(r"^\|\s*(\d+)\s*\|\s*(clip_\d+)\s+(\w+)\s*\|" + NUMBER * 6)
# ... | IDF1 / switches at IoU 0.4 |: a column of the tables since session 12 (absent before), the only one with an
# integer after the slash
LOOSE = re.compile(r"\|\s*([-\d.]+)\s*/\s*(\d+)\s*\|")
# ... | starts hidden |: the last column since session 14 (dancers whose start box lies mostly behind another's)
HIDDEN = re.compile(r"\|\s*(\d+)\s*\|\s*$")


def read_rows(text: str, heading: str) -> list[dict]:
    """The synthetic-clip rows of the section whose heading starts with ``heading``."""
    start = text.find(heading)
    if start < 0:
        raise SystemExit(f"plot_track_bench: error: no section '{heading}' in the markdown file")
    end = text.find("\n### ", start + len(heading))
    rows, header = [], ""
    for line in text[start:end if end > 0 else None].splitlines():
        m = ROW.match(line)
        if m:
            loose = LOOSE.findall(line) if "at IoU 0.4" in header else None
            hidden = HIDDEN.search(line) if "starts hidden" in header else None
            rows.append({"seed": int(m[1]), "clip": m[2], "genre": m[3], "dancers": int(m[4]),
                         "idf1": float(m[6]), "switches": int(float(m[9])),
                         "idf1_loose": float(loose[-1][0]) if loose else None,
                         "hidden": int(hidden[1]) if hidden else None})
        elif line.startswith("| seed |"):
            header = line
    if not rows:
        raise SystemExit(f"plot_track_bench: error: section '{heading}' has no synthetic-clip rows")
    return rows


def read_json_rows(path: Path) -> list[dict]:
    """The rows (as :func:`read_rows` gives them) of a per-clip JSON file: ``{"clips": {"SEED:INDEX:THRESHOLD":
    {genre, dancers, idf1, id_switches, and where present idf1_iou04, hidden_starts}}}``."""
    try:
        clips = json.loads(Path(path).read_text())["clips"]
        rows = []
        for key, c in clips.items():
            seed, index = (int(v) for v in key.split(":")[:2])
            rows.append({"seed": seed, "clip": f"clip_{index:05d}", "genre": str(c["genre"]),
                         "dancers": int(c["dancers"]), "idf1": float(c["idf1"]), "switches": int(c["id_switches"]),
                         "idf1_loose": float(c["idf1_iou04"]) if "idf1_iou04" in c else None,
                         "hidden": int(c["hidden_starts"]) if "hidden_starts" in c else None})
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise SystemExit(f"plot_track_bench: error: {path} is not a per-clip JSON file ({exc})") from None
    if not rows:
        raise SystemExit(f"plot_track_bench: error: {path} holds no clip")
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--markdown", type=Path, default=Path("docs/benchmarks.md"))
    parser.add_argument("--out", type=Path, default=Path("docs/img/tracking_synth_idf1.png"))
    parser.add_argument("--sections", nargs="*", default=list(DEFAULT_SECTIONS),
                        help="section headings (their start) to read")
    parser.add_argument("--target", type=float, default=0.9)
    parser.add_argument("--colour-by", choices=("seed", "hidden"), default=None,
                        help="one colour per seed (default for the markdown tables), or by whether a dancer starts "
                        "hidden (tables since session 14; default for --per-clip-json)")
    parser.add_argument("--per-clip-json", type=Path, nargs="+", metavar="JSON",
                        help="plot these per-clip score files (hindsight_runs.py score / bench_track.py "
                        "--per-clip-json) instead of the markdown tables")
    parser.add_argument("--title", help="the plot's title (default: counts of the clips, below the target and with "
                        "switches)")
    parser.add_argument("--held-out", default="97,101,113,127,131,137,139,151,163,173",
                        help="seeds rendered after the tracker's rules were written (marked in the legend)")
    args = parser.parse_args(argv)
    if args.per_clip_json:
        rows = [r for path in args.per_clip_json for r in read_json_rows(path)]
        args.colour_by = args.colour_by or "hidden"  # hundreds of seeds: one colour each would say nothing
    else:
        if not args.markdown.is_file():
            raise SystemExit(f"plot_track_bench: error: {args.markdown} not found")
        text = args.markdown.read_text()
        rows = [r for heading in args.sections for r in read_rows(text, heading)]
        args.colour_by = args.colour_by or "seed"

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hdvr.io.atomic import atomic_path

    clips = sorted({(r["clip"], r["genre"], r["dancers"]) for r in rows})
    seeds = sorted({r["seed"] for r in rows})
    held_out = {int(v) for v in args.held_out.split(",") if v.strip()}
    fig, ax = plt.subplots(figsize=(10.5, 4.2))
    loose_labelled = False
    if args.colour_by == "hidden" and any(r["hidden"] is None for r in rows):
        raise SystemExit("plot_track_bench: error: --colour-by hidden needs tables with the 'starts hidden' "
                         "column, or hidden_starts in every clip of the per-clip JSON")
    hidden_labelled = set()
    for k, seed in enumerate(seeds):
        mine = [r for r in rows if r["seed"] == seed]
        xs = [clips.index((r["clip"], r["genre"], r["dancers"])) + (k - (len(seeds) - 1) / 2) * (0.8 / len(seeds))
              for r in mine]
        if args.colour_by == "hidden":
            for x, r in zip(xs, mine):
                kind = "a dancer starts hidden" if r["hidden"] else "all dancers start visible"
                ax.scatter([x], [r["idf1"]], s=22, zorder=3, color="tab:orange" if r["hidden"] else "tab:blue",
                           marker="^" if r["hidden"] else "o", label=None if kind in hidden_labelled else kind)
                hidden_labelled.add(kind)
        else:  # 10 colours, then the same colours with another marker: more than 10 seeds stay distinguishable
            ax.scatter(xs, [r["idf1"] for r in mine], s=28, zorder=3, color=plt.cm.tab10(k % 10),
                       marker="o^sD"[(k // 10) % 4],
                       label=f"seed {seed}" + (" (held out)" if seed in held_out else ""))
        for x, r in zip(xs, mine):
            if r["idf1_loose"] is not None and (r["idf1"] < args.target or r["switches"]):  # loss from box extent
                ax.plot([x, x], [r["idf1"], r["idf1_loose"]], color="grey", linewidth=0.8, zorder=2)
                ax.scatter([x], [r["idf1_loose"]], s=28, marker="_", color="grey", zorder=2,
                           label="same clip at IoU 0.4" if not loose_labelled else None)
                loose_labelled = True
            if r["switches"]:
                ax.scatter([x], [r["idf1"]], s=140, facecolors="none", edgecolors="red", linewidths=1.5, zorder=4)
                ax.annotate(f"{r['switches']} sw", (x, r["idf1"]), textcoords="offset points", xytext=(6, -10),
                            fontsize=8, color="red")
    ax.axhline(args.target, color="grey", linestyle="--", linewidth=1)
    ax.text(len(clips) - 0.5, args.target + 0.004, f"target {args.target:g}", ha="right", va="bottom", fontsize=8,
            color="grey")
    ax.set_xticks(range(len(clips)), [f"{g.replace('_', '-')}\n{n} dancers" for _, g, n in clips], fontsize=8)
    ax.set_ylabel("IDF1 (amodal boxes, IoU 0.5)")
    low = min(r["idf1"] for r in rows)
    ax.set_ylim(min(0.75, low - 0.03), 1.01)
    below = sum(r["idf1"] < args.target for r in rows)
    switched = sum(r["switches"] > 0 for r in rows)
    counts = f"{len(rows)} clips, {below} below {args.target:g}, {switched} with identity switches (red rings)"
    ax.set_title(f"{args.title}: {counts}" if args.title else f"Tracking on hdvr.synth clips: {counts}", fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: labels[i].startswith("same clip"))  # the tick's entry last
    ax.legend([handles[i] for i in order], [labels[i] for i in order], fontsize=8, loc="upper left",
              bbox_to_anchor=(1.01, 1.0))  # outside: no dot hidden
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(args.out) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    print(f"wrote {args.out} ({len(rows)} clips)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
