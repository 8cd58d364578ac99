"""Synthetic training and evaluation data for the genre LSTM, its training loop and its scores.

A sequence is one dancer of one synthetic clip (:func:`hdvr.synth.groundtruth.generate_motion`, deterministic by
(seed, clip index)): the movement labels the pipeline's labeller gives its 3D motion, exact or disturbed like a 3D
fit (:func:`hdvr.recognition.genre.perturb_motion`), resampled to :data:`GENRE_FPS`. :func:`fitted_sequences`
goes through the real 3D fit instead: the clip's 2D keypoints (the 19 BODY_25 joints a COCO-17 detector such as
YOLO11n-pose gives, its 17 plus neck and mid-hip, feet missing, with pixel noise) are fitted with
:func:`hdvr.fitting.sequence.fit_keypoints` and the fitted dancer is labelled, as in ``hdvr run`` minus tracking
and 2D detection.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass

import numpy as np

from hdvr.errors import HDVRError
from hdvr.progress import progress
from hdvr.recognition.genre import (GENRE_FPS, GENRE_WINDOW, PIPELINE_SMOOTHING_S, movement_multi_hot,
                                    perturb_motion, resample_labels)


@dataclass
class GenreSequence:
    """One dancer's labels (T, 154) float32 at :data:`GENRE_FPS` (any (T, N) for :func:`train_genre`); genre index;
    where it came from."""

    labels: np.ndarray
    genre: int
    clip: int
    dancer: int
    level: float  # perturbation level (0 exact); -1 for labels of a real 3D fit


def _genre_setup(genres):
    from hdvr.synth.genres import GENRES, parse_genres

    names = parse_genres(genres) if isinstance(genres, str) or genres is None else tuple(genres)
    return names, [GENRES.index(g) if g in GENRES else -1 for g in names]


def synthetic_sequences(seed: int, clips: int, seconds: float = 8.0, dancers: tuple[int, int] = (1, 2),
                        levels: tuple[float, ...] = (0.0,), random_levels: int = 0,
                        level_range: tuple[float, float] = (0.2, 1.2), genres=None, fps: float = 30.0,
                        desc: str = "synthetic clips") -> list[GenreSequence]:
    """Label sequences of ``clips`` synthetic clips of seed ``seed`` (genres cycle over the clips): per dancer one
    sequence for each of ``levels`` and ``random_levels`` more with a level drawn uniformly in ``level_range``."""
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.skeleton import Skeleton
    from hdvr.synth.genres import GENRES
    from hdvr.synth.groundtruth import clip_spec, generate_motion

    names, _ = _genre_setup(genres)
    labeller = MovementLabeller(smoothing_s=PIPELINE_SMOOTHING_S)
    scratch = Skeleton()
    out = []
    for i in progress(range(clips), desc=desc, unit="clip"):
        spec = clip_spec(i, seed, names, dancers, seconds, fps)
        motion, _ = generate_motion(spec)
        rng = np.random.default_rng([seed, i, 77])
        for k, dancer in enumerate(motion):
            scratch.set_bone_lengths(dancer.bones)
            todo = list(levels) + [float(rng.uniform(*level_range)) for _ in range(random_levels)]
            for level in todo:
                kp = dancer.keypoints if level == 0 else perturb_motion(dancer.qpos, scratch, rng, fps, level)
                hot = movement_multi_hot(kp, fps, labeller)
                out.append(GenreSequence(resample_labels(hot, fps), GENRES.index(spec.genre), i, k, float(level)))
    return out


def fitted_sequences(seed: int, clips: int, seconds: float = 6.0, dancers: tuple[int, int] = (1, 1),
                     noise_px: float = 3.0, genres=None, fps: float = 30.0, first_clip: int = 0,
                     desc: str = "fitted clips") -> list[GenreSequence]:
    """Label sequences of clips ``first_clip..first_clip+clips-1`` of seed ``seed`` through the real 3D fit of
    their 2D keypoints (the 19 joints of a COCO-17 detector, Gaussian noise of ``noise_px`` pixels); see the module
    docstring."""
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.layouts import BODY25_NAMES
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.skeleton import Skeleton
    from hdvr.synth.genres import GENRES
    from hdvr.synth.groundtruth import clip_spec, make_clip

    names, _ = _genre_setup(genres)
    labeller = MovementLabeller(smoothing_s=PIPELINE_SMOOTHING_S)
    detected = np.array([not n.endswith(("toe", "heel")) for n in BODY25_NAMES])  # BODY_25 from COCO-17: no feet
    out = []
    with tempfile.TemporaryDirectory(prefix="hdvr-genre-") as tmp:
        for i in progress(range(first_clip, first_clip + clips), desc=desc, unit="clip"):
            spec = clip_spec(i, seed, names, dancers, seconds, fps)
            make_clip(tmp, spec, render=False)
            rng = np.random.default_rng([seed, i, 78])
            for k in range(spec.n_dancers):
                kp2 = load_keypoints2d(f"{tmp}/{spec.name}/dancer_{k}.keypoints2d.npz", require_visible=False)
                arr = kp2.keypoints.copy()
                arr[:, ~detected, 2] = 0.0
                arr[..., :2] += rng.normal(0.0, noise_px, arr[..., :2].shape)
                kp2.keypoints = arr
                kp2.__post_init__()
                if (arr[..., 2] > 0).any(axis=1).mean() < 0.2:
                    continue  # as the pipeline: too little of the dancer in view to fit
                result, _ = fit_keypoints(kp2)
                sk = Skeleton()
                sk.set_bone_lengths(result.bone_lengths)
                world = sk.keypoints(result.qpos)
                hot = movement_multi_hot(world, result.fps, labeller)
                out.append(GenreSequence(resample_labels(hot, result.fps), GENRES.index(spec.genre), i, k, -1.0))
    return out


def train_genre(sequences: list[GenreSequence], num_genres: int, epochs: int = 40, hidden: int = 128,
                layers: int = 1, window: int = GENRE_WINDOW, batch_size: int = 64, learning_rate: float = 3e-3,
                crops_per_sequence: int = 1, seed: int = 0, validation: list[GenreSequence] | None = None,
                input_dropout: float = 0.0, weight_decay: float = 0.0, log=print):
    """Train :class:`~hdvr.recognition.models.GenreLSTM` (the one genre training loop; it trains the shipped model).

    ``sequences``: per-frame labels ``labels`` (T, N) float32 (N = 154 for HDVR's labeller; the same N for all;
    at :data:`GENRE_FPS` for the shipped model) with T >= ``window``, and a genre index in ``0..num_genres-1``.
    Each epoch draws ``crops_per_sequence`` random ``window``-frame crops per sequence (new crops every epoch),
    in shuffled batches of ``batch_size`` crops; cross-entropy of the last step's logits, AdamW (``weight_decay``)
    with a one-cycle schedule peaking at ``learning_rate``, gradient norm clipped at 5. ``input_dropout`` zeroes
    that fraction of the crops' label entries (so the model cannot lean on any single label). ``hidden`` and
    ``layers`` size the LSTM. ``validation`` sequences, if given, are scored each epoch with :func:`evaluate`
    (whole sequences, ``window``-frame windows). ``log`` gets one line per epoch (None: silent). Deterministic for
    a ``seed`` (torch and NumPy generators seeded here; one torch thread).

    Returns (model in eval mode, history: per-epoch dicts ``epoch``, ``loss`` (mean cross-entropy over the
    epoch's crops), ``train_window_accuracy`` and, with ``validation``, ``validation_accuracy``)."""
    import torch
    from torch import nn

    from hdvr.recognition.models import GenreLSTM

    if not sequences:
        raise HDVRError("no genre sequences to train on")
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    lengths = np.array([s.labels.shape[0] for s in sequences])
    if (lengths < window).any():
        raise HDVRError(f"genre training needs sequences of at least {window} frames, shortest is {lengths.min()}")
    data = [torch.from_numpy(np.ascontiguousarray(s.labels)) for s in sequences]
    y_all = torch.tensor([s.genre for s in sequences])
    model = GenreLSTM(sequences[0].labels.shape[1], num_genres, hidden, layers)
    opt = torch.optim.AdamW(model.parameters(), lr=learning_rate, weight_decay=weight_decay)
    steps = epochs * int(np.ceil(len(sequences) * crops_per_sequence / batch_size))
    sched = torch.optim.lr_scheduler.OneCycleLR(opt, learning_rate, total_steps=steps, pct_start=0.1)
    ce = nn.CrossEntropyLoss()
    history = []
    for epoch in progress(range(epochs), desc="training genre LSTM", unit="epoch"):
        model.train()
        idx = np.repeat(np.arange(len(sequences)), crops_per_sequence)
        rng.shuffle(idx)
        starts = (rng.random(len(idx)) * (lengths[idx] - window + 1)).astype(np.int64)
        total, correct, seen = 0.0, 0, 0
        for b in range(0, len(idx), batch_size):
            sel, st = idx[b:b + batch_size], starts[b:b + batch_size]
            x = torch.stack([data[i][s:s + window] for i, s in zip(sel, st)])
            y = y_all[sel]
            if input_dropout > 0:
                x = x * (torch.rand(x.shape) >= input_dropout)
            logits = model(x)
            loss = ce(logits, y)
            opt.zero_grad(set_to_none=True)
            loss.backward()
            nn.utils.clip_grad_norm_(model.parameters(), 5.0)
            opt.step()
            sched.step()
            total += float(loss.detach()) * len(sel)
            correct += int((logits.argmax(-1) == y).sum())
            seen += len(sel)
        row = {"epoch": epoch + 1, "loss": round(total / seen, 4), "train_window_accuracy": round(correct / seen, 4)}
        if validation:
            row["validation_accuracy"] = round(evaluate(model.eval(), validation, num_genres, window)["accuracy"],
                                               4)
        history.append(row)
        if log:
            log("  " + ", ".join(f"{k} {v}" for k, v in row.items()))
    return model.eval(), history


def predict_sequences(model, sequences: list[GenreSequence], window: int = GENRE_WINDOW) -> np.ndarray:
    """(N, G) genre probabilities of whole sequences (mean softmax over their half-overlapping windows)."""
    import torch

    from hdvr.recognition.train import predict_genre

    with torch.inference_mode():
        return np.stack([predict_genre(model, s.labels, window) for s in sequences]) if sequences else \
            np.zeros((0, model.head.out_features))


def evaluate(model, sequences: list[GenreSequence], num_genres: int, window: int = GENRE_WINDOW) -> dict:
    """Accuracy, per-genre accuracy (recall) and confusion matrix (rows truth, columns prediction) of whole
    sequences."""
    if not sequences:
        raise HDVRError("no sequences to evaluate")
    probs = predict_sequences(model, sequences, window)
    pred = probs.argmax(-1)
    truth = np.array([s.genre for s in sequences])
    conf = np.zeros((num_genres, num_genres), dtype=np.int64)
    np.add.at(conf, (truth, pred), 1)
    per = conf.diagonal() / np.maximum(conf.sum(1), 1)
    return {"accuracy": float((pred == truth).mean()), "sequences": len(sequences),
            "per_genre_accuracy": [round(float(a), 4) for a in per], "confusion": conf.tolist()}
