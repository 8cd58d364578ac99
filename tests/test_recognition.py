"""Movement and genre LSTMs learn toy problems; features are invariant to position, heading and size."""

import numpy as np
import pytest

from hdvr.recognition.features import PART_JOINTS, body_frame, part_features
from hdvr.recognition.genre_data import GenreSequence, train_genre
from hdvr.recognition.train import (LabelledClip, RecognitionTrainConfig, load_recognisers, predict_genre,
                                    predict_movements, save_recognisers, train_movement_models)
from hdvr.skeleton import Skeleton


pytestmark = pytest.mark.usefixtures("one_torch_thread")


def _arm_clip(seed: int, frames: int = 200, fps: float = 30.0):
    """The left arm raising and lowering at random times; labels 0 = moving up, 1 = moving down."""
    sk = Skeleton()
    rng = np.random.default_rng(seed)
    phase = np.cumsum(rng.uniform(0.02, 0.12, frames))
    angle = 0.9 + 0.8 * np.sin(phase)
    q = np.repeat(sk.rest_qpos()[None], frames, axis=0)
    q[:, 7 + 8] = angle  # left shoulder abduction
    kp = sk.keypoints(q)
    d = np.gradient(angle)
    labels = np.stack([d > 0.01, d < -0.01], axis=1).astype(np.float32)
    return LabelledClip(kp, fps, labels)


def test_features_invariant_to_placement_heading_and_size():
    kp = _arm_clip(0, 20).keypoints3d
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    moved = 1.3 * kp @ rot.T + np.array([2.0, -1.0, 0.0])
    np.testing.assert_allclose(body_frame(moved), body_frame(kp), atol=1e-9)
    f = part_features(kp, 30.0)
    assert set(f) == set(PART_JOINTS) and len(PART_JOINTS) == 16
    assert f["left_upper_arm"].shape == (20, 3 * 6)


def test_movement_and_genre_lstms_learn_and_round_trip(tmp_path):
    cfg = RecognitionTrainConfig(epochs=40, window=48, hidden=32, layers=1, batch_size=8)
    ids = {"left_upper_arm": [0, 1]}
    models = train_movement_models([_arm_clip(s) for s in range(4)], ids, cfg)
    test = _arm_clip(9)
    probs = predict_movements(models, ids, test.keypoints3d, test.fps, num_labels=2)
    pred = probs > 0.5
    truth = test.labels > 0.5
    f1 = 2 * (pred & truth).sum() / (pred.sum() + truth.sum())
    assert f1 > 0.85, f1

    # the genre LSTM (the shipped model's training loop): 3 toy genres, each a rhythm on its own label
    rng = np.random.default_rng(0)

    def toy_labels(g):
        seq = rng.uniform(0, 0.3, (96, 5)).astype(np.float32)
        seq[:, g] += 0.6 * (np.sin(np.arange(96) * (0.2 + 0.3 * g)) > 0)  # genre-specific rhythm
        return seq

    seqs = [GenreSequence(toy_labels(g), g, clip=6 * g + i, dancer=0, level=0.0) for g in range(3) for i in range(6)]
    genre, history = train_genre(seqs, 3, epochs=80, hidden=32, layers=1, window=48, batch_size=8,
                                 crops_per_sequence=3, seed=0, log=None)
    assert len(history) == 80 and history[-1]["loss"] < 0.5 * history[0]["loss"], history[::20]
    held_out = [toy_labels(g) for g in range(3)]
    for g, seq in enumerate(held_out):
        assert predict_genre(genre, seq, 48).argmax() == g

    save_recognisers(tmp_path / "rec.pt", models, genre, ids, {"taxonomy": "toy"})
    m2, g2, ids2, meta = load_recognisers(tmp_path / "rec.pt")
    assert ids2 == ids and meta == {"taxonomy": "toy"}
    np.testing.assert_allclose(predict_movements(m2, ids2, test.keypoints3d, test.fps, 2), probs, atol=1e-6)
    for seq in held_out:
        np.testing.assert_allclose(predict_genre(g2, seq, 48), predict_genre(genre, seq, 48), atol=1e-6)
