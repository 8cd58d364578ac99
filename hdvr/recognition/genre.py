"""Genre recognition as ``hdvr run`` uses it: movement labels of fitted 3D -> genre probabilities.

The genre LSTM (:class:`hdvr.recognition.models.GenreLSTM`, the paper's step 5) reads the per-frame movement labels
of all 16 body parts, as the multi-hot matrix (T, 154) of :meth:`hdvr.movements.labeller.Labels.multi_hot` that the
pipeline computes on the fitted dancer. Before the LSTM the labels are resampled to :data:`GENRE_FPS` (the mean of
the multi-hot rows falling in each output frame), so videos of any frame rate feed it the same time scale; a clip is
cut into windows of ``window`` frames (half overlapping) and its genre probabilities are the mean softmax over them.

The shipped checkpoint ``hdvr/data/recognisers.pt`` is written by ``scripts/train_recognisers.py`` (synthetic
choreographies of the nine genres, labels from noisy 3D; see docs/recognition.md). Checkpoints are read with
``torch.load(..., weights_only=True)`` only.

:func:`perturb_motion` is the augmentation that makes the model see labels as the pipeline produces them: fitted
3D is off by slowly drifting joint-angle errors (0.2-0.3 rad RMS measured on the demo clip), a little frame-to-frame
jitter, a wandering root and slightly wrong bone lengths.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError

#: Frame rate of the label sequences the genre LSTM reads.
GENRE_FPS = 15.0
#: Window of the genre LSTM in frames at :data:`GENRE_FPS` (4 s).
GENRE_WINDOW = 60
#: The labeller smoothing ``hdvr run`` uses on fitted 3D (hdvr.pipeline.analyse_keypoints).
PIPELINE_SMOOTHING_S = 0.2


def default_checkpoint() -> Path:
    """The checkpoint shipped with the package (may be absent in a source tree that never trained one)."""
    return Path(__file__).resolve().parents[1] / "data" / "recognisers.pt"


def resample_labels(multi_hot: np.ndarray, fps: float, target_fps: float = GENRE_FPS) -> np.ndarray:
    """(T, N) per-frame labels at ``fps`` -> (T', N) float32 at ``target_fps``: each output frame is the mean of the
    input frames whose times fall in it (nearest input frame when upsampling)."""
    x = np.asarray(multi_hot, dtype=np.float32)
    if x.ndim != 2 or x.shape[0] == 0:
        raise HDVRError(f"movement labels must be (T, N) with T >= 1, got shape {x.shape}")
    if not np.isfinite(fps) or fps <= 0:
        raise HDVRError(f"fps must be positive, got {fps}")
    T = x.shape[0]
    n_out = max(1, int(round(T * target_fps / fps)))
    bins = np.minimum((np.arange(T) * target_fps / fps).astype(np.int64), n_out - 1)
    sums = np.zeros((n_out, x.shape[1]), dtype=np.float64)
    np.add.at(sums, bins, x)
    counts = np.bincount(bins, minlength=n_out).astype(np.float64)
    empty = counts == 0
    if empty.any():  # upsampling: take the nearest input frame
        src = np.minimum(np.round(np.flatnonzero(empty) * fps / target_fps).astype(np.int64), T - 1)
        sums[empty] = x[src]
        counts[empty] = 1.0
    return (sums / counts[:, None]).astype(np.float32)


def movement_multi_hot(keypoints_world: np.ndarray, fps: float, labeller=None) -> np.ndarray:
    """(T, 25, 3) world keypoints (z up) -> (T, 154) bool labels, exactly as the pipeline labels fitted 3D."""
    from hdvr.movements.labeller import MovementLabeller

    labeller = labeller or MovementLabeller(smoothing_s=PIPELINE_SMOOTHING_S)
    return labeller.label(keypoints_world, fps, (0.0, 0.0, 1.0)).multi_hot()


def _smooth_noise(rng: np.random.Generator, shape, window: int) -> np.ndarray:
    """Gaussian noise low-passed by a moving average of ``window`` frames, rescaled to unit RMS."""
    from scipy.ndimage import uniform_filter1d

    n = rng.standard_normal(shape)
    if window > 1:
        n = uniform_filter1d(n, window, axis=0, mode="reflect")
        n /= max(float(n.std()), 1e-9)
    return n


def perturb_motion(qpos: np.ndarray, skeleton, rng: np.random.Generator, fps: float, level: float = 1.0
                   ) -> np.ndarray:
    """World keypoints (T, 25, 3) of ``qpos`` (T, 41) disturbed like a 3D fit of that motion; ``skeleton`` carries
    the dancer's bone lengths (its bones are changed for the call and restored).

    ``level`` scales every error (0: exact). At level 1 the hinge errors are a per-hinge bias (RMS 0.08 rad), a drift
    over about a second (RMS 0.18 rad, per-hinge scale log-normal), jitter over a few frames (RMS 0.07 rad); the
    root wanders by about 8 cm and tilts by about 3 degrees; bone lengths are off by up to 5 %.
    """
    q = np.array(qpos, dtype=np.float64, copy=True)
    T = q.shape[0]
    hinges = q.shape[1] - 7
    if level > 0:
        scale = level * np.exp(0.5 * rng.standard_normal(hinges))  # some hinges are far worse than others
        drift_w = max(3, int(rng.uniform(0.5, 1.5) * fps))
        jitter_w = max(1, int(rng.uniform(0.05, 0.2) * fps))
        q[:, 7:] += scale * (0.08 * rng.standard_normal(hinges)
                             + 0.18 * _smooth_noise(rng, (T, hinges), drift_w)
                             + 0.07 * _smooth_noise(rng, (T, hinges), jitter_w))
        q[:, :3] += level * 0.08 * _smooth_noise(rng, (T, 3), drift_w) * np.array([1.0, 1.0, 0.3])
        # a small tilt of the root: rotate its quaternion by a random drifting axis-angle
        tilt = level * 0.05 * _smooth_noise(rng, (T, 2), drift_w)
        half = 0.5 * np.linalg.norm(tilt, axis=1, keepdims=True)
        axis = np.concatenate([tilt, np.zeros((T, 1))], axis=1) / np.maximum(2 * half, 1e-9)
        dq = np.concatenate([np.cos(half), np.sin(half) * axis], axis=1)
        w1, v1 = dq[:, :1], dq[:, 1:]
        w2, v2 = q[:, 3:4], q[:, 4:7]
        q[:, 3:7] = np.concatenate([w1 * w2 - (v1 * v2).sum(1, keepdims=True),
                                    w1 * v2 + w2 * v1 + np.cross(v1, v2)], axis=1)
    bones = skeleton.bone_lengths
    if level > 0:
        skeleton.set_bone_lengths(bones * (1.0 + np.clip(level * 0.03 * rng.standard_normal(bones.shape),
                                                         -0.05, 0.05)))
    try:
        return skeleton.keypoints(skeleton.clamp(q))
    finally:
        skeleton.set_bone_lengths(bones)


class GenreRecogniser:
    """The genre LSTM of a recogniser checkpoint, with the genre names and time scale it was trained with."""

    def __init__(self, model, genres: list[str], fps: float = GENRE_FPS, window: int = GENRE_WINDOW,
                 source: str = "", meta: dict | None = None):
        self.model = model
        self.genres = list(genres)
        self.fps = float(fps)
        self.window = int(window)
        self.source = source
        self.meta = meta or {}

    @classmethod
    def load(cls, path: str | os.PathLike | None = None) -> GenreRecogniser:
        """Read a checkpoint (default: the shipped one); one-line :class:`HDVRError` when missing, corrupt or
        without a genre model."""
        from hdvr.recognition.train import load_recognisers

        path = Path(path) if path is not None else default_checkpoint()
        _, genre, _, meta = load_recognisers(path)
        if genre is None:
            raise HDVRError(f"recogniser checkpoint {path} has no genre model")
        genres = meta.get("genres")
        if not isinstance(genres, list) or len(genres) != genre.head.out_features:
            raise HDVRError(f"recogniser checkpoint {path} does not name its {genre.head.out_features} genres")
        return cls(genre, genres, float(meta.get("genre_fps", GENRE_FPS)), int(meta.get("genre_window",
                                                                                          GENRE_WINDOW)),
                   str(path), meta)

    def predict_labels(self, multi_hot: np.ndarray, fps: float) -> np.ndarray:
        """(T, 154) per-frame movement labels at ``fps`` -> genre probabilities (G,) summing to 1."""
        import torch

        from hdvr.recognition.train import predict_genre

        x = resample_labels(multi_hot, fps, self.fps)
        if x.shape[1] != self.model.lstm.input_size:
            raise HDVRError(f"the genre model reads {self.model.lstm.input_size} movement labels, got {x.shape[1]}")
        with torch.inference_mode():
            probs = predict_genre(self.model, x, self.window).astype(np.float64)
        return probs / probs.sum()

    def predict_keypoints(self, keypoints_world: np.ndarray, fps: float) -> np.ndarray:
        """World keypoints (T, 25, 3), z up -> genre probabilities (G,), labelling them as the pipeline does."""
        return self.predict_labels(movement_multi_hot(keypoints_world, fps), fps)

    def as_dict(self, probs: np.ndarray) -> dict:
        """``{"top": name, "probabilities": {name: p}}`` (rounded to 4 decimals) for JSON."""
        probs = np.asarray(probs, dtype=np.float64)
        return {"top": self.genres[int(np.argmax(probs))],
                "probabilities": {g: round(float(p), 4) for g, p in zip(self.genres, probs)}}
