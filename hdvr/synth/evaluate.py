"""The labeller against the generator: per-part and per-label F-scores on generated motion.

The labels the generator's primitives declare (:mod:`hdvr.synth.declare`: from the intents and their planned
trajectories, not from the labeller) are the reference; the labeller sees
only BODY_25 keypoints, here in a random camera frame (``up`` given as the camera-frame vertical), for dancers of
random stature, optionally with Gaussian keypoint noise. One label per part and frame, so the micro F-score of a
part equals its frame accuracy; the macro F-score averages the F-scores of the labels that occur.
"""

from __future__ import annotations

import numpy as np

from hdvr.movements.labeller import MovementLabeller
from hdvr.movements.taxonomy import load_taxonomy
from hdvr.skeleton import Skeleton
from hdvr.synth.choreography import ChoreographyGenerator, foot_metrics
from hdvr.synth.genres import GENRES


def _random_rotation(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def f_scores(reference: np.ndarray, predicted: np.ndarray, n_labels: int = 154) -> dict:
    """Per-part micro F1 and macro F1, per-label F1 and support, from (T, 16) label-id arrays."""
    tax = load_taxonomy()
    per_label, support = {}, {}
    for lab in tax.labels:
        col = tax.part(lab.part).index
        ref, pred = reference[:, col] == lab.id, predicted[:, col] == lab.id
        tp, fp, fn = int((ref & pred).sum()), int((~ref & pred).sum()), int((ref & ~pred).sum())
        support[lab.key] = tp + fn
        per_label[lab.key] = 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else float("nan")
    micro = {p.name: float((reference[:, p.index] == predicted[:, p.index]).mean()) for p in tax.parts}
    macro = {p.name: float(np.nanmean([per_label[lab.key] for lab in p.labels if support[lab.key] > 0]))
             for p in tax.parts}
    return {"per_part_micro_f1": micro, "per_part_macro_f1": macro, "per_label_f1": per_label,
            "support": support}


def evaluate_labeller(seconds: float = 60.0, clips_per_genre: int = 2, seed: int = 0, noise_m: float = 0.0,
                      fps: float = 30.0, genres=GENRES, smoothing_s: float | None = None) -> dict:
    """Generate ``clips_per_genre`` dancers per genre, label their keypoints, compare. Returns fixed keys:
    per_part_micro_f1, per_part_macro_f1, per_label_f1, support, missing_labels, frames, noise_m, smoothing_s,
    joint_limit_violation_rad, foot_penetration_m, foot_skate_max_m_s, foot_skate_all_feet_max_m_s."""
    tax = load_taxonomy()
    labeller = MovementLabeller(tax, smoothing_s=smoothing_s)
    refs, preds = [], []
    worst = {"viol": 0.0, "pen": 0.0, "skate": 0.0, "skate_all": 0.0}
    for gi, genre in enumerate(genres):
        for c in range(clips_per_genre):
            rng = np.random.default_rng([seed, gi, c])
            gen = ChoreographyGenerator(Skeleton(height_m=float(rng.uniform(1.5, 1.9))), fps)
            chor = gen.generate(genre, seconds, rng)
            worst["viol"] = max(worst["viol"], float(gen.sk.limit_violation(chor.qpos).max()))
            feet = foot_metrics(chor.keypoints, chor.airborne, fps, stance=chor.stance)
            worst["pen"] = max(worst["pen"], feet["penetration_m"])
            worst["skate"] = max(worst["skate"], feet["skate_max_m_s"])
            worst["skate_all"] = max(worst["skate_all"], foot_metrics(chor.keypoints, chor.airborne, fps)["skate_max_m_s"])
            rot = _random_rotation(rng)  # a random camera frame
            kp = (chor.keypoints - rng.uniform(-5, 5, 3)) @ rot.T
            if noise_m > 0:
                kp = kp + rng.normal(0, noise_m, kp.shape)
            preds.append(labeller.label(kp, fps, up=rot @ np.array([0.0, 0.0, 1.0])).ids)
            refs.append(chor.labels)
    ref, pred = np.concatenate(refs), np.concatenate(preds)
    out = f_scores(ref, pred)
    present = set(np.unique(ref).tolist())
    out.update({"missing_labels": [lab.key for lab in tax.labels if lab.id not in present], "frames": int(ref.shape[0]),
                "noise_m": noise_m, "smoothing_s": labeller.th["smoothing_s"], "joint_limit_violation_rad": worst["viol"], "foot_penetration_m": worst["pen"],
                "foot_skate_max_m_s": worst["skate"], "foot_skate_all_feet_max_m_s": worst["skate_all"]})
    return out
