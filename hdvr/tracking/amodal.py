"""Amodal box refinement: a small learned correction from a seen dancer's box to the box of its whole body.

The boxes the tracker writes (:mod:`hdvr.tracking.multi`, then :mod:`hdvr.tracking.hindsight`) follow what shows of a
dancer: its tracked box, the detector's person box, its chosen keypoints and the foreground. The ground truth of
multi-object tracking counts the whole (amodal) body, also the arm behind a partner and the leg the detector left out.
Where a dancer overlaps others the two differ by amounts that hand-set rules could not get right on average (mirroring
the visible arm onto the hidden side made 21,479 of 30,173 boxes worse: docs/benchmarks.md "session 52"), but that
follow from the configuration: which keypoints were found where in the box, and where the other dancers' boxes lie.

:class:`AmodalBoxRefiner` is the mean of three two-layer perceptrons, trained by ``scripts/train_amodal_boxes.py``
(:func:`train_refiner`) on hdvr synth clips, whose ground truth is amodal, and on their mirror images
(:func:`mirror_rows`); it maps the :func:`amodal_features` of a dancer in one frame to the four edge offsets of its
whole-body box (:func:`edge_targets`). :func:`refine_boxes` applies it to the boxes of dancers seen
(status ``tracked``) as the last step of :func:`hdvr.tracking.hindsight.apply_hindsight`; the other dancers' boxes
(occluded, waiting hidden) are guesses of another kind and are left as they are (refining them too lost clips).

Data contract (feature version :data:`FEATURE_VERSION`), per (frame, dancer), in units of the dancer's box height h
(px / px, so the same at any video size and position):

- ``[0:3]`` status one-hot: ``tracked``, ``occluded``, ``hidden``;
- ``[3]`` box aspect w / h;
- ``[4:29]`` x of each BODY_25 keypoint minus the box centre's x, / h; ``[29:54]`` its y minus the box top, / h;
  ``[54:79]`` 1 where the keypoint is given (confidence > 0), else 0 (and 0 in the two slots before);
- ``[79:97]`` the three other dancers whose boxes overlap this one most (by IoU; zeros where fewer): for each, its
  box centre's x minus this box's centre x, its top minus this top, its width and its height (all / h), 1 if it
  stands in front (its box bottom lower in the image, :func:`hdvr.tracking.state.stands_in_front`), and the IoU.

Targets (:func:`edge_targets`): the whole-body box's left, top, right and bottom edge minus this box's, / h.

Boxes are (x, y, w, h) pixels, top-left origin; arrays indexed (frame, dancer).
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import BODY25_NAMES
from hdvr.tracking.state import HIDDEN, OCCLUDED, TRACKED

FEATURE_VERSION = 1
STATUSES = (TRACKED, OCCLUDED, HIDDEN)  # one-hot order of the status features
NUM_KEYPOINTS = 25  # BODY_25
NUM_NEIGHBOURS = 3
NEIGHBOUR_FEATURES = 6
NUM_FEATURES = len(STATUSES) + 1 + 3 * NUM_KEYPOINTS + NUM_NEIGHBOURS * NEIGHBOUR_FEATURES
TARGET_CLIP = 1.0  # training targets are clipped to +-1 box height (a box off by more is on the wrong person)
DEFAULT_WEIGHTS = Path(__file__).resolve().parent.parent / "data" / "amodal_boxes.pt"


def _pair_iou(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """IoU of (..., 4) boxes ``a`` and ``b`` elementwise, broadcast (0 where either is empty). Written here because
    :func:`hdvr.tracking.evaluation.iou_matrix` pairs every box of one frame with every box of another, and the
    features need all frames at once."""
    ix = np.clip(np.minimum(a[..., 0] + a[..., 2], b[..., 0] + b[..., 2]) - np.maximum(a[..., 0], b[..., 0]), 0, None)
    iy = np.clip(np.minimum(a[..., 1] + a[..., 3], b[..., 1] + b[..., 3]) - np.maximum(a[..., 1], b[..., 1]), 0, None)
    inter = ix * iy
    union = a[..., 2] * a[..., 3] + b[..., 2] * b[..., 3] - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0.0)


def amodal_features(boxes: np.ndarray, status, keypoints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Features (T, N, :data:`NUM_FEATURES`) float32 of each dancer in each frame (module docstring's layout) from
    ``boxes`` (T, N, 4) px, ``status`` (T, N) strings and ``keypoints`` (T, N, 25, 3) px + confidence, and the (T, N)
    bool mask of those that have them: a status in :data:`STATUSES` and a finite box of positive size."""
    boxes = np.asarray(boxes, float)
    keypoints = np.asarray(keypoints, float)
    status = np.asarray(status)
    if boxes.ndim != 3 or boxes.shape[2] != 4:
        raise HDVRError(f"expected (T, N, 4) boxes, got {boxes.shape}")
    T, N = boxes.shape[:2]
    if status.shape != (T, N) or keypoints.shape != (T, N, NUM_KEYPOINTS, 3):
        raise HDVRError(f"expected (T, N) status and (T, N, {NUM_KEYPOINTS}, 3) keypoints for {T} frames of {N} "
                        f"dancers, got {status.shape} and {keypoints.shape}")
    features = np.zeros((T, N, NUM_FEATURES), np.float32)
    usable = np.isfinite(boxes).all(axis=2) & (np.nan_to_num(boxes[..., 2]) > 0) & (np.nan_to_num(boxes[..., 3]) > 0)
    usable &= np.isin(status, STATUSES)
    for i, name in enumerate(STATUSES):
        features[..., i] = status == name
    safe = np.where(usable[..., None], boxes, [0.0, 0.0, 1.0, 1.0])
    x, y, w, h = np.moveaxis(safe, -1, 0)
    centre = x + w / 2
    features[..., 3] = w / h
    given = (keypoints[..., 2] > 0) & np.isfinite(keypoints[..., :2]).all(axis=3)
    k = len(STATUSES) + 1
    features[..., k:k + NUM_KEYPOINTS] = np.where(given, (np.nan_to_num(keypoints[..., 0]) - centre[..., None])
                                                  / h[..., None], 0.0)
    features[..., k + NUM_KEYPOINTS:k + 2 * NUM_KEYPOINTS] = np.where(
        given, (np.nan_to_num(keypoints[..., 1]) - y[..., None]) / h[..., None], 0.0)
    features[..., k + 2 * NUM_KEYPOINTS:k + 3 * NUM_KEYPOINTS] = given
    start = k + 3 * NUM_KEYPOINTS
    for d in range(N):
        others = [e for e in range(N) if e != d]
        if not others:
            break
        other = safe[:, others]  # (T, N-1, 4)
        iou = np.where(usable[:, others], _pair_iou(safe[:, d:d + 1], other), -1.0)  # -1: no box
        rank = np.argsort(-iou, axis=1, kind="stable")[:, :NUM_NEIGHBOURS]
        for slot in range(rank.shape[1]):
            o = other[np.arange(T), rank[:, slot]]
            o_iou = iou[np.arange(T), rank[:, slot]]
            there = o_iou >= 0
            values = np.stack([(o[:, 0] + o[:, 2] / 2 - centre[:, d]) / h[:, d], (o[:, 1] - y[:, d]) / h[:, d],
                               o[:, 2] / h[:, d], o[:, 3] / h[:, d],
                               o[:, 1] + o[:, 3] > y[:, d] + h[:, d],  # stands_in_front with margin 0
                               o_iou], axis=1)
            j = start + slot * NEIGHBOUR_FEATURES
            features[:, d, j:j + NEIGHBOUR_FEATURES] = np.where(there[:, None], values, 0.0)
    features[~usable] = 0.0
    return features, usable


def edge_targets(boxes: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """(..., 4) offsets of the ``truth`` box's left, top, right and bottom edges from those of ``boxes`` (both
    (..., 4) (x, y, w, h) px), in the box heights of ``boxes``; NaN where either is absent."""
    b = np.asarray(boxes, float)
    g = np.asarray(truth, float)
    h = b[..., 3]
    return np.stack([(g[..., 0] - b[..., 0]) / h, (g[..., 1] - b[..., 1]) / h,
                     (g[..., 0] + g[..., 2] - b[..., 0] - b[..., 2]) / h,
                     (g[..., 1] + g[..., 3] - b[..., 1] - b[..., 3]) / h], axis=-1)


def apply_edges(boxes: np.ndarray, edges: np.ndarray, min_size: float = 2.0) -> np.ndarray:
    """``boxes`` (..., 4) px with each edge moved by ``edges`` (..., 4) box heights (:func:`edge_targets`' order);
    width and height at least ``min_size`` px."""
    b = np.asarray(boxes, float)
    h = b[..., 3:4]
    x0 = b[..., 0:1] + edges[..., 0:1] * h
    y0 = b[..., 1:2] + edges[..., 1:2] * h
    x1 = b[..., 0:1] + b[..., 2:3] + edges[..., 2:3] * h
    y1 = b[..., 1:2] + b[..., 3:4] + edges[..., 3:4] * h
    return np.concatenate([x0, y0, np.maximum(x1 - x0, min_size), np.maximum(y1 - y0, min_size)], axis=-1)


def _mirrored_joints() -> np.ndarray:
    """Index of each BODY_25 joint's mirror image (left and right exchanged; the centre line kept)."""
    names = list(BODY25_NAMES)
    swap = {"left_": "right_", "right_": "left_"}
    return np.array([names.index(next((n.replace(a, b, 1) for a, b in swap.items() if n.startswith(a)), n))
                     for n in names])


def mirror_rows(features: np.ndarray, targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (M, :data:`NUM_FEATURES`) ``features`` and (M, 4) ``targets`` of the same dancers seen in the mirrored
    video: keypoint x offsets and neighbours' centre offsets negated, left and right joints exchanged, the left and
    right edge offsets exchanged and negated (a training augmentation: the world has no preferred side)."""
    x = np.array(features, np.float32, copy=True)
    y = np.array(targets, np.float32, copy=True)
    joints = _mirrored_joints()
    k = len(STATUSES) + 1
    x[:, k:k + NUM_KEYPOINTS] = -x[:, k:k + NUM_KEYPOINTS][:, joints]
    for block in (1, 2):
        part = slice(k + block * NUM_KEYPOINTS, k + (block + 1) * NUM_KEYPOINTS)
        x[:, part] = x[:, part][:, joints]
    start = k + 3 * NUM_KEYPOINTS
    x[:, start:start + NUM_NEIGHBOURS * NEIGHBOUR_FEATURES:NEIGHBOUR_FEATURES] *= -1
    y[:, [0, 2]] = -np.asarray(targets, np.float32)[:, [2, 0]]
    return x, y


def build_network(hidden: int, dropout: float):
    """The refiner's network: :data:`NUM_FEATURES` -> ``hidden`` -> ``hidden`` -> 4 edges, ReLU, dropout after each
    hidden layer (training only)."""
    import torch

    return torch.nn.Sequential(
        torch.nn.Linear(NUM_FEATURES, hidden), torch.nn.ReLU(), torch.nn.Dropout(dropout),
        torch.nn.Linear(hidden, hidden), torch.nn.ReLU(), torch.nn.Dropout(dropout),
        torch.nn.Linear(hidden, 4))


class AmodalBoxRefiner:
    """A trained refiner: :meth:`edges` predicts the whole-body box's edge offsets from :func:`amodal_features`, the
    mean of an ensemble of small networks trained from different seeds (one network's count of failing clips moved
    by 1-2 in 240 from seed to seed; docs/benchmarks.md "session 52").

    ``payload``: the dict :func:`train_refiner` returns and ``scripts/train_amodal_boxes.py`` saves (``members``: the
    networks' state dicts, ``hidden``, ``dropout``, ``feature_version``, and what it was trained on)."""

    def __init__(self, payload: dict):
        import torch

        if int(payload.get("feature_version", -1)) != FEATURE_VERSION:
            raise HDVRError(f"amodal box weights are for feature version {payload.get('feature_version')}, this "
                            f"hdvr computes version {FEATURE_VERSION}: train them again "
                            "(scripts/train_amodal_boxes.py)")
        self.payload = payload
        self.networks = []
        for state in payload["members"]:
            network = build_network(int(payload["hidden"]), float(payload["dropout"]))
            network.load_state_dict(state)
            self.networks.append(network.eval())
        if not self.networks:
            raise HDVRError("amodal box weights hold no network")
        self._torch = torch

    @classmethod
    def load(cls, path: str | os.PathLike = DEFAULT_WEIGHTS) -> AmodalBoxRefiner:
        """Weights saved by ``scripts/train_amodal_boxes.py`` (``torch.load(..., weights_only=True)``)."""
        import torch

        path = Path(path)
        if not path.is_file():
            raise HDVRError(f"amodal box weights not found: {path}")
        try:
            payload = torch.load(path, map_location="cpu", weights_only=True)
        except Exception as error:  # a truncated or foreign file
            raise HDVRError(f"cannot read amodal box weights {path}: {error}") from None
        if not isinstance(payload, dict) or "members" not in payload:
            raise HDVRError(f"{path} holds no amodal box weights (no members)")
        return cls(payload)

    def edges(self, features: np.ndarray) -> np.ndarray:
        """(M, 4) predicted edge offsets, box heights, for (M, :data:`NUM_FEATURES`) features."""
        features = np.asarray(features, np.float32)
        if features.ndim != 2 or features.shape[1] != NUM_FEATURES:
            raise HDVRError(f"expected (M, {NUM_FEATURES}) amodal features, got {features.shape}")
        if not len(features):
            return np.zeros((0, 4))
        x = self._torch.from_numpy(features)
        with self._torch.no_grad():
            return np.mean([network(x).numpy() for network in self.networks], axis=0).astype(float)


@functools.lru_cache(maxsize=4)
def _cached_refiner(path: str) -> AmodalBoxRefiner:
    return AmodalBoxRefiner.load(path)


def load_refiner(path: str | os.PathLike | None = None) -> AmodalBoxRefiner:
    """The refiner of the weights at ``path`` (None or "": the shipped ones), loaded once per path and process."""
    return _cached_refiner(str(Path(path).resolve()) if path else str(DEFAULT_WEIGHTS))


def refine_boxes(boxes: np.ndarray, status, keypoints: np.ndarray, refiner: AmodalBoxRefiner | None = None,
                 statuses=(TRACKED,), weights: str | os.PathLike | None = None) -> np.ndarray:
    """``boxes`` (T, N, 4) px with the box of each dancer whose status is in ``statuses`` (default: seen) moved to
    the whole-body box ``refiner`` predicts (default: the weights at ``weights``, :func:`load_refiner`, loaded only
    when a box is to be moved). Other boxes, and rows without a box, are kept; the input is not changed. A run
    without a single keypoint (tracked with no pose detector) is returned as it is: the refiner learned from runs
    with one, and a box alone says too little. Frames of a run with poses where a dancer has none are refined
    (they are about 8 % of the frames seen, and leaving them out lost a clip of 120 fresh ones: docs/benchmarks.md
    "session 52")."""
    boxes = np.asarray(boxes, float)
    if not (np.asarray(keypoints, float)[..., 2] > 0).any():
        return boxes.copy()
    features, usable = amodal_features(boxes, status, keypoints)
    chosen = usable & np.isin(np.asarray(status), statuses)
    out = boxes.copy()
    if chosen.any():
        refiner = refiner or load_refiner(weights)
        out[chosen] = apply_edges(boxes[chosen], refiner.edges(features[chosen]))
    return out


def _train_network(x, y, hidden: int, dropout: float, epochs: int, batch: int, learning_rate: float,
                   weight_decay: float, seed: int, progress=None):
    """One network trained on tensors ``x``, ``y`` (see :func:`train_refiner`); returns its state dict."""
    import torch

    generator = torch.Generator().manual_seed(seed)
    torch.manual_seed(seed)
    network = build_network(hidden, dropout)
    optimiser = torch.optim.Adam(network.parameters(), learning_rate, weight_decay=weight_decay)
    network.train()
    for epoch in range(epochs):
        order = torch.randperm(len(x), generator=generator)
        total = 0.0
        for i in range(0, len(x), batch):
            rows = order[i:i + batch]
            loss = torch.nn.functional.smooth_l1_loss(network(x[rows]), y[rows], beta=0.05)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            total += loss.item() * len(rows)
        if progress is not None:
            progress(epoch, total / len(x))
    return {k: v.detach().clone() for k, v in network.state_dict().items()}


def train_refiner(features: np.ndarray, targets: np.ndarray, hidden: int = 64, dropout: float = 0.2,
                  epochs: int = 10, members: int = 3, mirror: bool = True, batch: int = 512,
                  learning_rate: float = 1e-3, weight_decay: float = 1e-5, seed: int = 0, progress=None) -> dict:
    """Train a refiner of ``members`` networks (seeds ``seed``, ``seed`` + 1, ...) on (M, :data:`NUM_FEATURES`)
    ``features`` and (M, 4) ``targets`` (:func:`edge_targets`, clipped to +-:data:`TARGET_CLIP`), with ``mirror``
    their mirror images too (:func:`mirror_rows`), with Adam and a smooth L1 loss (beta 0.05 box heights), on the
    CPU, deterministically for ``seed``. ``progress(member, epoch, loss)`` is called after each epoch. Returns the
    payload :class:`AmodalBoxRefiner` takes. The networks are small and regularised: with 128 units, no dropout and
    30 epochs one fitted the clips it was trained on and lost clips it was not; the mirror images raised the mean
    IDF1 and HOTA of clips it was not trained on (docs/benchmarks.md "session 52")."""
    import torch

    features = np.asarray(features, np.float32)
    targets = np.clip(np.asarray(targets, np.float32), -TARGET_CLIP, TARGET_CLIP)
    if features.ndim != 2 or features.shape[1] != NUM_FEATURES or targets.shape != (len(features), 4):
        raise HDVRError(f"expected (M, {NUM_FEATURES}) features and (M, 4) targets, got {features.shape} and "
                        f"{targets.shape}")
    if not len(features) or not np.isfinite(features).all() or not np.isfinite(targets).all():
        raise HDVRError("amodal box training needs finite features and targets, at least one row")
    if members < 1:
        raise HDVRError(f"members must be >= 1, got {members}")
    if mirror:
        mirrored = mirror_rows(features, targets)
        features, targets = np.concatenate([features, mirrored[0]]), np.concatenate([targets, mirrored[1]])
    x, y = torch.from_numpy(features), torch.from_numpy(targets)
    states = []
    for m in range(members):
        report = None if progress is None else (lambda epoch, loss, m=m: progress(m, epoch, loss))
        states.append(_train_network(x, y, hidden, dropout, epochs, batch, learning_rate, weight_decay, seed + m,
                                     report))
    return {"members": states, "hidden": hidden, "dropout": dropout, "feature_version": FEATURE_VERSION,
            "epochs": epochs, "seed": seed, "weight_decay": weight_decay, "mirror": mirror, "rows": len(features)}
