"""``hdvr synth``: generate a synthetic dance dataset (rendered videos + full ground truth).

Deterministic for a seed (clip i depends only on (seed, i) and the options), resumable (clips whose meta.json
matches are skipped), parallel over clips (``--workers``), with a progress bar over clips.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from hdvr.errors import HDVRError
from hdvr.progress import progress


def _parse_range(text: str) -> tuple[int, int]:
    try:
        parts = [int(p) for p in text.split("-")]
    except ValueError:
        raise HDVRError(f"--dancers must be N or MIN-MAX (e.g. 1-4), got {text!r}") from None
    lo, hi = (parts[0], parts[0]) if len(parts) == 1 else (parts[0], parts[1]) if len(parts) == 2 else (0, -1)
    if not 1 <= lo <= hi <= 4:
        raise HDVRError(f"--dancers must lie within 1-4 with MIN <= MAX, got {text!r}")
    return lo, hi


def _parse_size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise HDVRError(f"--size must be WIDTHxHEIGHT (e.g. 640x480), got {text!r}") from None
    if w < 64 or h < 64 or w % 2 or h % 2:
        raise HDVRError(f"--size must be even and at least 64x64 (H.264), got {text!r}")
    return w, h


def _one_clip(out: str, spec, render: bool) -> dict:
    os.environ.setdefault("MUJOCO_GL", "egl")
    from hdvr.synth.groundtruth import make_clip

    return make_clip(out, spec, render=render)


def _one_mocap_clip(out: str, spec, paths: list[str], render: bool) -> dict:
    os.environ.setdefault("MUJOCO_GL", "egl")
    from hdvr.synth.groundtruth import make_clip, mocap_motion

    return make_clip(out, spec, render=render, motion=mocap_motion(spec, paths))


def mocap_groups(folder: str | os.PathLike) -> list[list[str]]:
    """BVH takes grouped into scenes: files ``{subject}_{take}*.bvh`` with the same take and different subjects
    dance together (CMU salsa: 60_01 lead + 61_01 follow share one world frame); sorted by take."""
    folder = Path(folder)
    if not folder.is_dir():
        raise HDVRError(f"mocap folder not found: {folder}")
    groups: dict[str, list[str]] = {}
    for path in sorted(folder.glob("*.bvh")):
        subject, _, take = path.stem.partition("_")
        groups.setdefault(take or subject, []).append(str(path))
    if not groups:
        raise HDVRError(f"no .bvh files in {folder}")
    return [groups[k][:4] for k in sorted(groups)]


def run_synth(out: str | os.PathLike, clips: int, genres: str | None = None, dancers: str = "1-4",
              seconds: float = 10.0, seed: int = 0, render: bool = True, workers: int = 1, fps: float = 30.0,
              size: str = "640x480", mocap: str | None = None, mocap_clips: int | None = None) -> dict:
    """Generate (or complete) a dataset; returns the index dict (see :func:`hdvr.synth.groundtruth.write_index`)."""
    from hdvr.synth.genres import parse_genres
    from hdvr.synth.groundtruth import clip_spec, is_done, write_index

    if clips < 0 or clips == 0 and not mocap:
        raise HDVRError(f"--clips must be at least 1 (or 0 with --mocap), got {clips}")
    if not 0.5 <= seconds <= 600:
        raise HDVRError(f"--seconds must be between 0.5 and 600, got {seconds}")
    if not 5 <= fps <= 120:
        raise HDVRError(f"--fps must be between 5 and 120, got {fps}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    genre_list = parse_genres(genres)
    lo_hi = _parse_range(dancers)
    wh = _parse_size(size)
    jobs = [(_one_clip, (str(out), clip_spec(i, seed, genre_list, lo_hi, seconds, fps, wh), render))
            for i in range(clips)]
    if mocap:
        from hdvr.synth.groundtruth import ClipSpec

        groups = mocap_groups(mocap)
        count = len(groups) if mocap_clips is None else mocap_clips
        for k in range(count):  # cycle over the takes; each clip starts at its own random time
            group = groups[k % len(groups)]
            spec = ClipSpec(k, seed, "salsa", len(group), float(seconds), fps, wh, prefix="mocap")
            jobs.append((_one_mocap_clip, (str(out), spec, group, render)))
    todo = [(fn, a) for fn, a in jobs if not is_done(out, a[1], render)]
    bar = progress(total=len(jobs), desc="synth", unit="clip", initial=len(jobs) - len(todo))
    try:
        if workers <= 1 or len(todo) <= 1:
            for fn, a in todo:
                fn(*a)
                bar.update(1)
        else:
            import multiprocessing as mp

            with ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context("spawn")) as pool:
                futures = [pool.submit(fn, *a) for fn, a in todo]
                for fut in as_completed(futures):
                    fut.result()
                    bar.update(1)
    finally:
        bar.close()
        index = write_index(out)  # what finished is indexed even when interrupted
    return index


def register(subparsers) -> None:
    p = subparsers.add_parser("synth", help="generate synthetic dance clips with full ground truth",
                              description="Generate synthetic dance clips of the nine genres: choreographies on "
                                          "the digital dancer, rendered multi-dancer videos (H.264) and ground "
                                          "truth (2D/3D keypoints with visibility, boxes, MOT tracks, qpos, "
                                          "camera, movement labels, genre). Finished clips are kept and skipped.")
    p.add_argument("--out", required=True, help="output folder (one clip_XXXXX/ folder per clip, index.json)")
    p.add_argument("--clips", type=int, default=9, help="number of clips (genres cycle over the clips)")
    p.add_argument("--genres", default="all", help="comma-separated genres or 'all' (ballet, belly_dance, "
                                                   "flamenco, hip_hop, rumba, swing, tango, tap, waltz)")
    p.add_argument("--dancers", default="1-4", help="dancers per clip, N or MIN-MAX within 1-4 (partner dances "
                                                    "get couples)")
    p.add_argument("--seconds", type=float, default=10.0, help="clip length in seconds")
    p.add_argument("--seed", type=int, default=0, help="random seed: same seed and options -> same clips")
    p.add_argument("--no-render", action="store_true", help="motion and ground truth only: no video, occlusion "
                                                            "not computed")
    p.add_argument("--workers", type=int, default=1, help="clips generated in parallel (processes)")
    p.add_argument("--fps", type=float, default=30.0, help="frames per second")
    p.add_argument("--size", default="640x480", help="video size WIDTHxHEIGHT")
    p.add_argument("--mocap", help="folder of BVH takes to mix in (CMU skeleton; files {subject}_{take}*.bvh with "
                                   "the same take dance together, e.g. ../shared/data/cmu-salsa): retargeted to the "
                                   "dancer, rendered like the synthetic clips as mocap_XXXXX/, genre 'salsa'")
    p.add_argument("--mocap-clips", type=int, default=None, help="number of mocap clips (default: one per take)")
    p.set_defaults(func=lambda a: _main(a))


def _main(args) -> int:
    index = run_synth(args.out, args.clips, args.genres, args.dancers, args.seconds, args.seed,
                      not args.no_render, args.workers, args.fps, args.size, args.mocap, args.mocap_clips)
    print(f"{len(index['clips'])} clips in {args.out} (index.json)")
    return 0
