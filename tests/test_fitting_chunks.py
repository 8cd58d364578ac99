"""Chunked fitting: spans, seams, worker processes, and a chunked fit on real mocap that is the same for any number
of workers."""

import numpy as np
import pytest

from hdvr.fitting.chunks import CHUNK_OVERLAP, chunk_spans, run_chunks, seam_frame
from hdvr.fitting.presets import FitSettings
from hdvr.fitting.sequence import fit_keypoints
from hdvr.metrics import evaluate


def test_chunk_spans_cover_the_clip_with_overlap():
    assert chunk_spans(1000, 900) == [chunk_spans(1000, 900)[0]] and chunk_spans(1000, 900)[0].stop == 1000
    spans = chunk_spans(2000, 900)
    assert [c.nominal_start for c in spans] == [0, 900]  # the 200-frame remainder joins the last chunk
    assert spans[-1].stop == 2000 and spans[1].start == 900 - CHUNK_OVERLAP
    spans = chunk_spans(3000, 900, overlap=10)
    assert [(c.start, c.nominal_start, c.stop) for c in spans] == [(0, 0, 900), (890, 900, 1800), (1790, 1800, 3000)]
    assert chunk_spans(50, 0) == [chunk_spans(50, 0)[0]] and chunk_spans(50, 0)[0].stop == 50
    assert [(c.start, c.nominal_start, c.stop) for c in chunk_spans(20, 8)] == [(0, 0, 8), (4, 8, 16), (12, 16, 20)]


def test_seam_is_where_the_chunks_agree():
    rng = np.random.default_rng(0)
    left = rng.normal(size=(20, 25, 3))
    right = left + rng.normal(scale=0.1, size=left.shape)  # the chunks disagree ...
    right[14] = left[14] + np.array([2.0, 0.0, 0.0])  # ... except at frame 14, a pure translation of the pose
    right[4] = left[4]  # agreement in the first half of the overlap is not taken (the later chunk is settling)
    assert seam_frame(left, right, first=100) == 114


def _square(i, tick):
    tick(i + 1)
    return i * i


def test_run_chunks_in_processes_matches_in_order():
    seen = []
    assert run_chunks(_square, 5, workers=2, on_progress=seen.append) == [0, 1, 4, 9, 16]
    assert sorted(seen) == [1, 2, 3, 4, 5]
    assert run_chunks(_square, 3, workers=1) == [0, 1, 4]


@pytest.fixture(scope="module")
def salsa_clip(salsa_view):
    return salsa_view("02", 30, 130, 60.0)


def test_chunked_fit_is_the_same_for_any_worker_count(salsa_clip):
    kp, gt = salsa_clip
    base = dict(focal=1500.0, chunk_frames=40, refine_sweeps=1, max_iter=5)
    one, _ = fit_keypoints(kp, FitSettings(workers=1, **base))
    two, _ = fit_keypoints(kp, FitSettings(workers=2, **base))
    assert np.array_equal(one.keypoints3d, two.keypoints3d)
    scores = evaluate(one.keypoints3d, gt)
    assert scores["p_mpjpe_mm"] < 130, scores
    # no seam jump: the largest frame-to-frame root-relative keypoint step stays a dancer's, not a flip's
    rel = one.keypoints3d - one.keypoints3d[:, 8:9]
    steps = np.linalg.norm(np.diff(rel, axis=0), axis=-1).max(axis=1)
    assert steps.max() < 0.5, steps.max()
