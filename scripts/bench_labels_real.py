#!/usr/bin/env python3
"""How far the movement labels of a 3D fit agree with the labels of the real motion: CMU salsa and Indian mocap
seen by random virtual cameras, fitted with no 3D data, both labelled by the pipeline's labeller.

What a dance researcher reading ``hdvr run``'s ``dancer_<i>.labels.json`` wants to know: on real dance, how often
does a body part carry the label it would carry if the dancer had been motion-captured? For each take of
../shared/data (or ``--gt-npz``, as written by ``scripts/bench_lifter.py --write-gt-npz``) and each of
``--cameras-salsa`` / ``--cameras-indian`` random views (the cameras of scripts/bench_fit_views.py, numbered from
100, 3 px Gaussian noise on all 25 BODY_25 keypoints), the 2D is fitted with the default settings
(``hdvr.fitting.sequence.fit_keypoints``, focal estimated), the fitted dancer's world keypoints are labelled as
``hdvr run`` labels them (:data:`hdvr.recognition.genre.PIPELINE_SMOOTHING_S`, or each of ``--smoothing``) and
compared part by part with the labels of the mocap's own keypoints (the labeller's mocap default smoothing).

Figures (per style, over all views' frames): per-part agreement (the fraction of frames on which the part
carries the same label; one label per part and frame, so this is the part's micro F1), the same within 0.2 s (a
frame agrees when the fit gives its part the mocap's label at most 0.2 s earlier or later) and per-part macro F1
(the F1 of each label the mocap shows, averaged), and the same for a "chance" baseline that gives every frame each
part's most frequent mocap label. ``--figure``: agreement per part and style as a bar chart (a black mark: within
0.2 s); ``--score-figure``: the two scores (mocap above, fit below) of one view.

    python3 scripts/bench_labels_real.py --fits-cache /tmp/label_fits.npz --out labels_real.json \\
        --figure docs/img/labels_real.png --score-figure docs/img/labels_real_score.png
    python3 scripts/bench_labels_real.py --fits-cache /tmp/label_fits.npz --smoothing 0.1,0.2,0.3,0.5

The fits are the slow part (minutes per take); ``--fits-cache`` keeps them for further runs with other labelling
settings (a cache made with other views or noise is refused).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import zlib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("HDVR_NO_PROGRESS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

import bench_lifter  # noqa: E402
from bench_fit_views import FIRST_CAMERA, style_of  # noqa: E402

FPS = 30.0
TOLERANCE_S = 0.2  # "within": a label put this much early or late still agrees


def fit_view(job) -> dict:
    """Worker: fit one (take, camera) view; returns the fitted dancer's world keypoints (T, 25, 3) m, z up."""
    name, camera, world, noise_px, max_frames = job
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.keypoints2d import Keypoints2D
    from hdvr.layouts import BODY25_NAMES
    from hdvr.skeleton import Skeleton

    world = world[:max_frames] if max_frames else world
    kp, _, _ = bench_lifter.make_view(world, zlib.crc32(f"{name}/{camera}".encode()), noise_px)
    start = time.perf_counter()
    result, _ = fit_keypoints(Keypoints2D(kp, BODY25_NAMES, FPS, bench_lifter.IMAGE))
    skeleton = Skeleton()
    skeleton.set_bone_lengths(result.bone_lengths)
    return {"name": name, "camera": camera, "fit_world": skeleton.keypoints(result.qpos).astype(np.float32),
            "seconds": time.perf_counter() - start}


def cache_key(jobs) -> str:
    return json.dumps([[name, camera, noise, frames] for name, camera, _, noise, frames in jobs])


def load_cache(path: Path, key: str) -> list[dict] | None:
    if not path.is_file():
        return None
    data = np.load(path)
    if str(data["key"]) != key:
        raise SystemExit(f"bench_labels_real: {path} holds fits of other views or noise; remove it or name another")
    names = [str(n) for n in data["names"]]
    return [{"name": n, "camera": int(data[f"{i}/camera"]), "fit_world": data[f"{i}/fit_world"],
             "seconds": float(data[f"{i}/seconds"])} for i, n in enumerate(names)]


def write_cache(path: Path, key: str, views: list[dict]) -> None:
    from hdvr.io.atomic import save_npz_atomic

    arrays = {"key": np.array(key), "names": np.array([v["name"] for v in views])}
    for i, v in enumerate(views):
        arrays.update({f"{i}/camera": np.array(v["camera"]), f"{i}/fit_world": v["fit_world"],
                       f"{i}/seconds": np.array(v["seconds"])})
    save_npz_atomic(path, **arrays)


def majority_labels(reference: np.ndarray) -> np.ndarray:
    """Each part's most frequent label on every frame (T, 16): what agreement a labeller gets by knowing only how
    often each label occurs."""
    out = np.empty_like(reference)
    for p in range(reference.shape[1]):
        values, counts = np.unique(reference[:, p], return_counts=True)
        out[:, p] = values[np.argmax(counts)]
    return out


def agreement_within(reference: np.ndarray, predicted: np.ndarray, frames: int) -> np.ndarray:
    """(16,) per part: the fraction of frames whose reference label the prediction carries within ``frames``
    frames either way (a label put a little early or late still agrees)."""
    hit = reference == predicted
    for shift in range(1, frames + 1):
        hit[shift:] |= reference[shift:] == predicted[:-shift]
        hit[:-shift] |= reference[:-shift] == predicted[shift:]
    return hit.mean(axis=0)


def agreement(reference: np.ndarray, predicted: np.ndarray, tolerance_frames: int = round(TOLERANCE_S * FPS)) -> dict:
    """{per_part_agreement, per_part_macro_f1, per_part_agreement_within, mean_agreement, mean_macro_f1,
    mean_agreement_within} of two (T, 16) label-id arrays; "within": a label within ``tolerance_frames``
    (:func:`agreement_within`)."""
    from hdvr.movements.taxonomy import load_taxonomy
    from hdvr.synth.evaluate import f_scores

    s = f_scores(reference, predicted)
    within = agreement_within(reference, predicted, tolerance_frames)
    return {"per_part_agreement": s["per_part_micro_f1"], "per_part_macro_f1": s["per_part_macro_f1"],
            "per_part_agreement_within": {p.name: float(within[p.index]) for p in load_taxonomy().parts},
            "mean_agreement": float(np.mean(list(s["per_part_micro_f1"].values()))),
            "mean_macro_f1": float(np.nanmean(list(s["per_part_macro_f1"].values()))),
            "mean_agreement_within": float(within.mean())}


def label_ids(keypoints: np.ndarray, smoothing_s: float | None) -> np.ndarray:
    from hdvr.movements.labeller import MovementLabeller

    return MovementLabeller(smoothing_s=smoothing_s).label(keypoints, FPS, (0.0, 0.0, 1.0)).ids


def reference_labels(gt: dict, views: list[dict]) -> list[np.ndarray]:
    """Per view, the labels (T, 16) of the mocap's own keypoints over the fitted frames (the labeller's default)."""
    return [label_ids(gt[v["name"]][:len(v["fit_world"])], None) for v in views]


def score_views(views: list[dict], references: list[np.ndarray], smoothing_s: float) -> dict:
    """{style: {views, frames, fit: agreement(...), majority: agreement(...)}} over the views' frames pooled;
    ``references``: :func:`reference_labels` of the views."""
    by_style: dict[str, tuple[list, list, list]] = {}
    for v, ref in zip(views, references):
        fit = label_ids(v["fit_world"], smoothing_s)
        refs, fits, majors = by_style.setdefault(style_of(v["name"]), ([], [], []))
        refs.append(ref)
        fits.append(fit)
        majors.append(majority_labels(ref))
    out = {}
    for style, (refs, fits, majors) in sorted(by_style.items()):
        ref = np.concatenate(refs)
        out[style] = {"views": len(refs), "frames": int(ref.shape[0]),
                      "fit": agreement(ref, np.concatenate(fits)),
                      "majority": agreement(ref, np.concatenate(majors))}
    return out


def agreement_figure(path: Path, scores: dict, smoothing_s: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hdvr.io.atomic import atomic_path
    from hdvr.movements.taxonomy import load_taxonomy

    parts = [p.name for p in load_taxonomy().parts]
    styles = list(scores)
    fig, ax = plt.subplots(figsize=(12, 4.2))
    width = 0.8 / (2 * len(styles))
    x = np.arange(len(parts))
    colours = {"salsa": ("#d95f02", "#fdd0a2"), "indian": ("#1b9e77", "#b2dfd2")}
    for k, style in enumerate(styles):
        fit = [scores[style]["fit"]["per_part_agreement"][p] for p in parts]
        major = [scores[style]["majority"]["per_part_agreement"][p] for p in parts]
        strong, pale = colours.get(style, ("#555555", "#cccccc"))
        within = [scores[style]["fit"]["per_part_agreement_within"][p] for p in parts]
        fit_x = x + (2 * k) * width - 0.4 + width / 2
        summary = scores[style]["fit"]
        ax.bar(fit_x, fit, width, color=strong,
               label=f"{style}: fit ({scores[style]['views']} views, mean {summary['mean_agreement']:.2f}; "
                     f"within {TOLERANCE_S:g} s {summary['mean_agreement_within']:.2f})")
        ax.scatter(fit_x, within, marker="_", s=60, color="black", zorder=3,
                   label=f"fit, the label within {TOLERANCE_S:g} s" if k == 0 else None)
        ax.bar(fit_x + width, major, width, color=pale,
               label=f"{style}: most frequent label (mean {scores[style]['majority']['mean_agreement']:.2f})")
    ax.set_xticks(x, [p.replace("_", " ") for p in parts], rotation=40, ha="right", fontsize=8)
    ax.set_ylim(0, 1)
    ax.set_ylabel("frames with the mocap's label")
    ax.set_title(f"Movement labels of the 3D fit against the labels of the mocap (3 px noise, labels smoothed "
                 f"{smoothing_s:g} s)", fontsize=10)
    ax.legend(fontsize=7, ncol=2, loc="upper left")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)


def score_figure(path: Path, gt: dict, view: dict, smoothing_s: float, seconds: float = 8.0) -> None:
    """Mocap score above, fit score below, of the first ``seconds`` of one view, in one picture."""
    import tempfile

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt

    from hdvr.io.atomic import atomic_path
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.movements.score import draw_score

    world = gt[view["name"]][:len(view["fit_world"])]
    with tempfile.TemporaryDirectory() as tmp_dir:
        top, bottom = Path(tmp_dir) / "mocap.png", Path(tmp_dir) / "fit.png"
        draw_score(MovementLabeller().label(world, FPS), top, title=f"{view['name']}: labels of the mocap",
                   end_s=seconds)
        draw_score(MovementLabeller(smoothing_s=smoothing_s).label(view["fit_world"], FPS), bottom,
                   title=f"{view['name']}, camera {view['camera']}: labels of the 3D fit of its 2D (3 px noise)",
                   end_s=seconds)
        images = [mpimg.imread(top), mpimg.imread(bottom)]
    fig, axes = plt.subplots(2, 1, figsize=(images[0].shape[1] / 110, (images[0].shape[0] + images[1].shape[0]) / 110))
    for ax, im in zip(axes, images):
        ax.imshow(im)
        ax.axis("off")
    fig.subplots_adjust(0, 0, 1, 1, 0, 0)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)


def main(argv=None) -> int:
    from hdvr.recognition.genre import PIPELINE_SMOOTHING_S

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cameras-salsa", type=int, default=1, help="views per salsa take")
    ap.add_argument("--cameras-indian", type=int, default=4, help="views per Indian take")
    ap.add_argument("--noise-px", type=float, default=3.0)
    ap.add_argument("--max-frames", type=int, default=0, help="truncate takes (0: whole takes)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--gt-npz", default=None, help="pre-converted mocap (scripts/bench_lifter.py --write-gt-npz)")
    ap.add_argument("--fits-cache", default=None, help="NPZ keeping the fits for further runs")
    ap.add_argument("--smoothing", default=str(PIPELINE_SMOOTHING_S),
                    help="comma-separated smoothing (s) of the fitted keypoints before labelling; the first is the "
                         "one drawn")
    ap.add_argument("--out", default=None, help="write the figures per smoothing here (JSON)")
    ap.add_argument("--figure", default=None, help="agreement per part and style (PNG)")
    ap.add_argument("--score-figure", default=None, help="mocap and fit scores of the first view (PNG)")
    args = ap.parse_args(argv)
    try:
        smoothings = [float(s) for s in args.smoothing.split(",")]
    except ValueError:
        ap.error(f"--smoothing takes comma-separated seconds, got {args.smoothing!r}")
    gt = bench_lifter.load_gt(args.gt_npz)
    if not gt:
        print("bench_labels_real: no mocap found (../shared/data or --gt-npz)", file=sys.stderr)
        return 2
    cams = {"salsa": args.cameras_salsa, "indian": args.cameras_indian}
    jobs = [(name, FIRST_CAMERA + c, world, args.noise_px, args.max_frames)
            for name, world in gt.items() for c in range(cams[style_of(name)])]
    if not jobs:
        print("bench_labels_real: no views asked for", file=sys.stderr)
        return 2
    key = cache_key(jobs)
    cache = Path(args.fits_cache) if args.fits_cache else None
    views = load_cache(cache, key) if cache else None
    start = time.perf_counter()
    if views is None:
        print(f"fitting {len(jobs)} views with {args.workers} workers ...", flush=True)
        with ProcessPoolExecutor(args.workers) as pool:
            views = []
            for v in pool.map(fit_view, jobs):
                views.append(v)
                print(f"  {v['name']} camera {v['camera']}: {len(v['fit_world'])} frames in {v['seconds']:.0f} s",
                      flush=True)
        if cache:
            write_cache(cache, key, views)
    report = {"noise_px": args.noise_px, "views": [[v["name"], v["camera"]] for v in views], "by_smoothing": {}}
    references = reference_labels(gt, views)  # the same for every smoothing of the fit
    for s in smoothings:
        scores = score_views(views, references, s)
        report["by_smoothing"][f"{s:g}"] = scores
        for style, sc in scores.items():
            print(f"smoothing {s:g} s, {style} ({sc['views']} views, {sc['frames']} frames): agreement "
                  f"{sc['fit']['mean_agreement']:.3f} (most frequent label {sc['majority']['mean_agreement']:.3f}), "
                  f"within 0.2 s {sc['fit']['mean_agreement_within']:.3f} "
                  f"({sc['majority']['mean_agreement_within']:.3f}), macro F1 {sc['fit']['mean_macro_f1']:.3f} "
                  f"({sc['majority']['mean_macro_f1']:.3f})")
    report["seconds"] = time.perf_counter() - start
    if args.out:
        from hdvr.io.atomic import write_text_atomic

        write_text_atomic(Path(args.out), json.dumps(report, indent=1))
    if args.figure:
        agreement_figure(Path(args.figure), report["by_smoothing"][f"{smoothings[0]:g}"], smoothings[0])
    if args.score_figure:
        score_figure(Path(args.score_figure), gt, views[0], smoothings[0])
    print(f"{len(views)} views in {report['seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
