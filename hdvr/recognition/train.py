"""Training of the movement LSTMs, prediction with the movement and genre LSTMs, one checkpoint file for all models.

Movement labels are a per-frame multi-hot matrix (T, N_labels) over the global label ids of the taxonomy
(154 for HDVR's vocabulary); ``part_label_ids`` says which ids belong to each body part. Checkpoints are
``torch.save`` dicts of tensors and primitives, loaded with ``weights_only=True``. The genre LSTM is trained by
:func:`hdvr.recognition.genre_data.train_genre` (the one genre training loop, which trains the shipped checkpoint).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import torch
from torch import nn

from hdvr.errors import HDVRError
from hdvr.io.atomic import atomic_path
from hdvr.progress import progress
from hdvr.recognition.features import part_features
from hdvr.recognition.models import GenreLSTM, MovementLSTM


@dataclass
class RecognitionTrainConfig:
    """Settings of :func:`train_movement_models` (the genre LSTM has its own, the arguments of
    :func:`hdvr.recognition.genre_data.train_genre`)."""

    epochs: int = 30
    window: int = 64  # frames per training sequence
    batch_size: int = 32
    learning_rate: float = 2e-3
    hidden: int = 128
    layers: int = 2
    seed: int = 0
    device: str = "cpu"


@dataclass
class LabelledClip:
    """One dancer's clip: BODY_25 3D keypoints (T, 25, 3) metres, frame rate, multi-hot labels (T, N), genre."""

    keypoints3d: np.ndarray
    fps: float
    labels: np.ndarray
    genre: int | None = None
    up_axis: str = "z"


def _windows(length: int, window: int) -> list[tuple[int, int]]:
    if length <= window:
        return [(0, length)]
    starts = list(range(0, length - window + 1, window // 2))
    if starts[-1] != length - window:
        starts.append(length - window)
    return [(s, s + window) for s in starts]


def _stack(items: list[np.ndarray], window: int) -> np.ndarray:
    out = np.zeros((len(items), window) + items[0].shape[1:], dtype=np.float32)
    for i, a in enumerate(items):
        out[i, :len(a)] = a
    return out


def train_movement_models(clips: list[LabelledClip], part_label_ids: dict[str, list[int]],
                          cfg: RecognitionTrainConfig | None = None) -> dict[str, MovementLSTM]:
    """Train one :class:`MovementLSTM` per part on windows of the clips (BCE over the part's labels)."""
    cfg = cfg or RecognitionTrainConfig()
    if not clips:
        raise HDVRError("no labelled clips to train on")
    torch.manual_seed(cfg.seed)
    rng = np.random.default_rng(cfg.seed)
    feats = [part_features(c.keypoints3d, c.fps, c.up_axis) for c in clips]
    models = {}
    for part, ids in progress(part_label_ids.items(), desc="training movement LSTMs", unit="part"):
        xs, ys = [], []
        for f, clip in zip(feats, clips):
            for s, e in _windows(clip.labels.shape[0], cfg.window):
                xs.append(f[part][s:e])
                ys.append(clip.labels[s:e, ids].astype(np.float32))
        x, y = _stack(xs, cfg.window), _stack(ys, cfg.window)
        mask = _stack([np.ones(len(a), np.float32) for a in xs], cfg.window)
        model = MovementLSTM(x.shape[-1], len(ids), cfg.hidden, cfg.layers).to(cfg.device)
        opt = torch.optim.Adam(model.parameters(), lr=cfg.learning_rate)
        pos = y.reshape(-1, len(ids)).mean(0)
        pos_weight = torch.tensor(np.clip((1 - pos) / np.maximum(pos, 1e-3), 1.0, 20.0), dtype=torch.float32)
        bce = nn.BCEWithLogitsLoss(reduction="none", pos_weight=pos_weight.to(cfg.device))
        tx, ty, tm = (torch.from_numpy(a).to(cfg.device) for a in (x, y, mask))
        for _ in range(cfg.epochs):
            order = rng.permutation(len(x))
            for b in range(0, len(order), cfg.batch_size):
                sel = torch.from_numpy(order[b:b + cfg.batch_size])
                loss = (bce(model(tx[sel]), ty[sel]).mean(-1) * tm[sel]).sum() / tm[sel].sum().clamp(min=1)
                opt.zero_grad(set_to_none=True)
                loss.backward()
                opt.step()
        models[part] = model.eval().cpu()
    return models


@torch.no_grad()
def predict_movements(models: dict[str, MovementLSTM], part_label_ids: dict[str, list[int]],
                      keypoints3d: np.ndarray, fps: float, num_labels: int, up_axis: str = "z") -> np.ndarray:
    """Per-frame label probabilities (T, num_labels) for one clip."""
    feats = part_features(keypoints3d, fps, up_axis)
    out = np.zeros((keypoints3d.shape[0], num_labels), dtype=np.float32)
    for part, model in models.items():
        logits = model(torch.from_numpy(feats[part])[None])[0]
        out[:, part_label_ids[part]] = torch.sigmoid(logits).numpy()
    return out


@torch.no_grad()
def predict_genre(model: GenreLSTM, label_probs: np.ndarray, window: int = 64) -> np.ndarray:
    """Genre probabilities (G,) for a clip's per-frame labels ``label_probs`` (T, N): the mean of the softmax over
    its ``window``-frame windows (half overlapping; a clip shorter than ``window`` is one window)."""
    wins = [label_probs[s:e] for s, e in _windows(label_probs.shape[0], window)]
    x = torch.from_numpy(_stack(wins, min(window, label_probs.shape[0])))
    return torch.softmax(model(x), dim=-1).mean(0).numpy()


def save_recognisers(path: str | os.PathLike, movement: dict[str, MovementLSTM], genre: GenreLSTM | None,
                     part_label_ids: dict[str, list[int]], meta: dict | None = None) -> None:
    """One checkpoint for all recognisers (atomic)."""
    payload = {
        "movement": {p: m.state_dict() for p, m in movement.items()},
        "movement_shapes": {p: [m.lstm.input_size, m.head.out_features, m.lstm.hidden_size, m.lstm.num_layers]
                            for p, m in movement.items()},
        "part_label_ids": {p: list(map(int, ids)) for p, ids in part_label_ids.items()},
        "genre": genre.state_dict() if genre is not None else {},
        "genre_shape": ([genre.lstm.input_size, genre.head.out_features, genre.lstm.hidden_size,
                         genre.lstm.num_layers] if genre is not None else []),
        "meta": meta or {},
    }
    with atomic_path(path) as tmp:
        torch.save(payload, tmp)


def load_recognisers(path: str | os.PathLike):
    """-> (movement models, genre model or None, part_label_ids, meta); ``weights_only=True``."""
    if not os.path.isfile(path):
        raise HDVRError(f"recogniser checkpoint not found: {path}")
    try:
        payload = torch.load(path, map_location="cpu", weights_only=True)
        if not isinstance(payload, dict):
            raise TypeError(f"a {type(payload).__name__}, not a dict")
        movement = {}
        for part, (fin, nl, hid, layers) in payload["movement_shapes"].items():
            m = MovementLSTM(fin, nl, hid, layers)
            m.load_state_dict(payload["movement"][part])
            movement[part] = m.eval()
        genre = None
        if payload["genre_shape"]:
            nin, ng, hid, layers = payload["genre_shape"]
            genre = GenreLSTM(nin, ng, hid, layers)
            genre.load_state_dict(payload["genre"])
            genre.eval()
        part_label_ids, meta = dict(payload["part_label_ids"]), dict(payload["meta"])
    except Exception as exc:  # torch raises many kinds (UnpicklingError, zip errors, shape mismatches)
        raise HDVRError(f"cannot read recogniser checkpoint {path}: not a valid HDVR checkpoint "
                        f"({type(exc).__name__})") from None
    return movement, genre, part_label_ids, meta
