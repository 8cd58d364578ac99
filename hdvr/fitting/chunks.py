"""Long clips in parallel: overlapping chunks fitted in worker processes and stitched where they agree.

After the per-dancer calibration (one bone set, one focal) the windowed fit and its refinement only couple
neighbouring frames, so a long clip is cut into chunks of ``chunk_frames`` frames; chunk k > 0 starts
``CHUNK_OVERLAP`` frames early. Each chunk is fitted (windows + refinement) on its own, from a fresh start; two
neighbouring chunks are joined at the frame of their overlap where their root-relative keypoints agree best, and a
short refinement around the seam (in the caller) removes what is left of the step.

The cut depends only on the clip length and ``chunk_frames``, never on the number of worker processes: the result
is the same for any ``workers`` setting (workers only decide how many chunks run at once). Workers are forked
processes (they inherit the dancer model); where ``fork`` is unavailable the chunks run one after the other.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
from dataclasses import dataclass
from typing import Callable

import numpy as np

CHUNK_OVERLAP = 30  # frames two neighbouring chunks share (1 s at 30 fps)


@dataclass(frozen=True)
class Chunk:
    """Frames ``[start, stop)`` fitted together; ``[start, nominal_start)`` is shared with the previous chunk and
    the stitched result switches to this chunk at the seam frame inside it (:func:`seam_frame`)."""

    start: int
    stop: int
    nominal_start: int  # where the chunk would start without the overlap


def chunk_spans(num_frames: int, chunk_frames: int, overlap: int = CHUNK_OVERLAP) -> list[Chunk]:
    """Chunks covering ``num_frames`` frames: nominal length ``chunk_frames``, the last one absorbing a remainder
    shorter than half a chunk; every chunk after the first starts ``overlap`` frames (at most half a chunk) before
    its nominal start."""
    if chunk_frames <= 0 or num_frames <= chunk_frames + chunk_frames // 2:
        return [Chunk(0, num_frames, 0)]
    overlap = min(overlap, chunk_frames // 2)
    starts = list(range(0, num_frames, chunk_frames))
    if num_frames - starts[-1] < chunk_frames // 2:
        starts.pop()
    stops = starts[1:] + [num_frames]
    return [Chunk(max(0, s - overlap) if k else 0, e, s) for k, (s, e) in enumerate(zip(starts, stops))]


def seam_frame(left_kp: np.ndarray, right_kp: np.ndarray, first: int) -> int:
    """Index (absolute frame) in an overlap where two chunks' solutions agree best.

    ``left_kp``/``right_kp``: (M, 25, 3) keypoints (metres, camera frame) of the same M frames, starting at frame
    ``first``, from the earlier and the later chunk. Agreement is the mean distance of root-relative keypoints; the
    later half of the overlap is preferred on ties (the later chunk has settled after its fresh start).
    """
    rel_l = left_kp - left_kp[:, 8:9]
    rel_r = right_kp - right_kp[:, 8:9]
    dist = np.linalg.norm(rel_l - rel_r, axis=-1).mean(axis=1)
    half = len(dist) // 2
    k = half + int(np.argmin(dist[half:])) if len(dist) > 1 else 0
    return first + k


def run_chunks(work: Callable[[int, Callable[[int], None]], object], count: int, workers: int,
               on_progress: Callable[[int], None] | None = None) -> list:
    """``[work(i, tick) for i in range(count)]``, run in up to ``workers`` forked processes.

    ``work`` is called in the child as ``work(index, tick)``; ``tick(k)`` reports k more frames done and reaches
    ``on_progress`` in the parent. Results come back in index order. With one worker (or no ``fork``), runs here.
    """
    report = on_progress or (lambda k: None)
    if workers <= 1 or count <= 1 or "fork" not in multiprocessing.get_all_start_methods():
        return [work(i, report) for i in range(count)]
    ctx = multiprocessing.get_context("fork")
    queue = ctx.SimpleQueue()
    _FORKED["work"], _FORKED["queue"] = work, queue

    def drain():
        while True:
            item = queue.get()
            if item is None:
                return
            report(item)

    reader = threading.Thread(target=drain, daemon=True)
    reader.start()
    try:
        with ctx.Pool(processes=min(workers, count)) as pool:
            results = pool.map(_run_forked, range(count), chunksize=1)
    finally:
        queue.put(None)
        reader.join(timeout=5)
        _FORKED.clear()
    return results


_FORKED: dict = {}  # the work function and progress queue, inherited by forked workers


def _run_forked(index: int):
    os.environ["HDVR_NO_PROGRESS"] = "1"  # the parent draws the one progress bar
    queue = _FORKED["queue"]
    return _FORKED["work"](index, lambda k: queue.put(int(k)))
