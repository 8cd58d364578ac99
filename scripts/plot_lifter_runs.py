"""Plot lifter benchmark runs: how fast each learns, and where it ends against the fit it learns from.

Reads the JSON reports that ``scripts/bench_lifter.py --out F.json`` writes and draws two panels:

- left: the fit-consistency term of Algorithm 4*'s loss (cm^2 per joint, the distance to the fit's 3D poses) per
  optimisation step (epochs x windows per epoch / batch size), log scale;
- right: P-MPJPE (mm, median over views) on the unseen salsa takes and the Indian takes, one bar pair per run,
  with the fit's own score as a dashed line.

    python3 scripts/plot_lifter_runs.py RUN.json[:LABEL] ... --out docs/img/lifter_runs.png
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

FIT = "fit (Algorithm 3* + refinement)"


def load_run(spec: str) -> dict:
    """One report, labelled by the text after ':' (default: the file's stem)."""
    path, _, label = spec.partition(":")
    try:
        report = json.loads(Path(path).read_text())
        train, _ = report["train"], report["history"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SystemExit(f"plot_lifter_runs: error: {path} is not a readable bench_lifter.py report "
                         f"({type(exc).__name__}: {exc})") from None
    windows = report["train_frames"] / train["window_stride"]  # one window every window_stride frames of a clip
    steps_per_epoch = max(1, int(windows // train["batch_size"]))
    return {"label": label or Path(path).stem, "report": report, "steps_per_epoch": steps_per_epoch}


def score(report: dict, split: str, method: str, key: str = "p_mpjpe_mm") -> float | None:
    for row in report["rows"]:
        if row["split"] == split and row["method"] == method:
            return row[key]
    return None


def lifter_method(report: dict) -> str:
    """The flip-tested lifter's rows where the run has them, else the plain lifter's."""
    methods = {row["method"] for row in report["rows"]}
    return "lifter, flip test" if "lifter, flip test" in methods else "lifter (trained on the fit)"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="bench_lifter.py JSON reports, each optionally :LABEL")
    parser.add_argument("--out", required=True, help="picture to write (.png)")
    args = parser.parse_args(argv)
    runs = [load_run(spec) for spec in args.runs]

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (curves, bars) = plt.subplots(1, 2, figsize=(13, 5.4), gridspec_kw={"width_ratios": [1.3, 1]})
    for run in runs:
        history = run["report"]["history"]
        steps = [(h["epoch"] + 1) * run["steps_per_epoch"] for h in history]
        curves.plot(steps, [h["fit"] for h in history], label=run["label"])
    curves.set_yscale("log")
    curves.set_xlabel("optimisation steps")
    curves.set_ylabel("distance to the fit (cm$^2$ per joint)")
    curves.set_title("learning")
    curves.grid(True, which="both", alpha=0.3)
    curves.legend(fontsize=8)

    width = 0.38
    for i, run in enumerate(runs):
        report = run["report"]
        method = lifter_method(report)
        for j, (split, colour) in enumerate((("test_salsa", "tab:blue"), ("test_indian", "tab:orange"))):
            value = score(report, split, method)
            if value is not None:
                bars.bar(i + (j - 0.5) * width, value, width, color=colour,
                         label=("unseen salsa takes", "Indian takes")[j] if i == 0 else None)
    fit_salsa = score(runs[0]["report"], "test_salsa", FIT)
    fit_indian = score(runs[0]["report"], "test_indian", FIT)
    for value, colour, name in ((fit_salsa, "tab:blue", "the fit, salsa"), (fit_indian, "tab:orange",
                                                                          "the fit, Indian")):
        if value is not None:
            bars.axhline(value, color=colour, linestyle="--", linewidth=1, label=f"{name} ({value:.0f} mm)")
    bars.set_xticks(range(len(runs)), [run["label"] for run in runs], rotation=20, ha="right", fontsize=8)
    bars.set_ylabel("P-MPJPE (mm, median over views)")
    bars.set_title("lifter on unseen takes (flip test where scored)")
    bars.legend(fontsize=8)
    bars.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from hdvr.io.atomic import atomic_path

    with atomic_path(args.out) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(args.out).suffix.lstrip(".") or "png")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
