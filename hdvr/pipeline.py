"""The whole hierarchy on one video: tracks -> 2D poses -> 3D fit -> movements (``hdvr run``, ``hdvr demo``).

Outputs in ``out_dir`` (every file written atomically; a dancer whose stage fails keeps what came before):

- ``overlay.mp4``, ``timeline.png``, ``tracks.mot.txt``, ``tracks.json``, ``dancer_<i>.npz``: tracking and 2D poses
  (:mod:`hdvr.tracking`); ``detections.npz``: the detector's people per frame, reused by a run on the same video
  into the same folder (:mod:`hdvr.pose2d.cache`)
- ``dancer_<i>.result3d.npz``: the fitted digital dancer (:mod:`hdvr.fitting`, 3D result contract)
- ``dancer_<i>.bvh``: the fitted motion for Blender (Y up, centimetres)
- ``dancer_<i>.labels.json`` and ``dancer_<i>.score.png``: body-part movements and their score (:mod:`hdvr.movements`)
- ``dancer_<i>.3d.mp4``: the fitted dancer rendered by MuJoCo (optional)
- ``summary.json``: per dancer, coverage, fit figures, the most frequent movement per part (``movements``), the
  movements that take most of the clip other than keeping still (``active_movements``: ``[label, fraction of
  frames]``, at most 4) and the genre; the video's genre (keys below)

Genre (the paper's step 5, :mod:`hdvr.recognition.genre`): the genre LSTM of a recogniser checkpoint (default: the
one shipped in ``hdvr/data/recognisers.pt``) reads each fitted dancer's movement labels. ``summary.json`` keys:

- per dancer ``genre``: ``{"top": name, "probabilities": {name: p}}`` over the nine genres (``{}`` when the dancer
  was not fitted or genre recognition is off/unavailable);
- top level ``genre``: ``{"available": true, "top": name, "probabilities": {name: p}, "dancers": n,
  "recogniser": path}`` with the mean of the dancers' probabilities, or ``{"available": false, "reason": text}``.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.atomic import write_text_atomic
from hdvr.recognition.genre import PIPELINE_SMOOTHING_S

#: A dancer needs 2D keypoints on at least this fraction of frames to be fitted in 3D.
MIN_POSE_COVERAGE = 0.2


@dataclass
class DancerOutputs:
    index: int
    keypoints2d: Path
    pose_coverage: float
    result3d: Path | None = None
    bvh: Path | None = None
    labels: Path | None = None
    score: Path | None = None
    render: Path | None = None
    fit: dict = field(default_factory=dict)
    movements: dict = field(default_factory=dict)
    active_movements: list = field(default_factory=list)
    genre: dict = field(default_factory=dict)
    skipped: str | None = None


@dataclass
class PipelineResult:
    out_dir: Path
    fps: float
    frames: int
    dancers: list[DancerOutputs]
    track_seconds: float
    genre: dict = field(default_factory=lambda: {"available": False, "reason": "genre recognition is off"})

    def summary(self) -> dict:
        return {"frames": self.frames, "fps": self.fps, "track_seconds": self.track_seconds, "genre": self.genre,
                "dancers": [{k: (str(v) if isinstance(v, Path) else v) for k, v in d.__dict__.items()}
                            for d in self.dancers]}


def load_genre_recogniser(recogniser="default"):
    """-> (GenreRecogniser or None, reason when None). ``"default"``: the shipped checkpoint, whose absence or
    damage only turns genre off (with the reason); ``None``/``False``: off; a path: that checkpoint, and a
    missing or unreadable one is an :class:`HDVRError`."""
    from hdvr.recognition.genre import GenreRecogniser

    if recogniser is None or recogniser is False:
        return None, "genre recognition is off"
    if isinstance(recogniser, GenreRecogniser):
        return recogniser, None
    if isinstance(recogniser, str) and recogniser == "default":
        try:
            return GenreRecogniser.load(), None
        except HDVRError as exc:
            return None, str(exc)
    return GenreRecogniser.load(recogniser), None


def video_genre(dancers: list[DancerOutputs], recogniser, reason: str | None) -> dict:
    """The video's genre: the mean of the dancers' genre probabilities (see the module docstring for keys)."""
    if recogniser is None:
        return {"available": False, "reason": reason or "genre recognition is off"}
    probs = [[d.genre["probabilities"][g] for g in recogniser.genres] for d in dancers if d.genre]
    if not probs:
        return {"available": False, "reason": "no dancer was fitted in 3D"}
    mean = np.mean(probs, axis=0)
    return {"available": True, **recogniser.as_dict(mean / mean.sum()), "dancers": len(probs),
            "recogniser": recogniser.source}


WEAK_DETECTION_THRESHOLD = 0.2  # ONNX detectors: people scoring 0.2-0.3 are weak finds (PersonPose.weak)


def make_detector(name: str = "yolo11n", size: int = 480, pose_model: str | None = None,
                  openpose_json: str | None = None, threads: int | None = None,
                  weak_threshold: float | None = WEAK_DETECTION_THRESHOLD, flip_test: bool = False):
    """The 2D pose detector by name: yolo11n (default, offline weights), onnx, openpose or none. ONNX detectors
    report people scoring from ``weak_threshold`` up to their sure threshold (0.3) as weak finds (None: none), and
    with ``flip_test`` look at the mirrored frame too (:class:`hdvr.pose2d.onnx_pose.OnnxPoseDetector`)."""
    kind = name.lower()
    if kind == "none":
        return None
    if kind == "openpose":
        if not openpose_json:
            raise HDVRError("--detector openpose needs --openpose-json FOLDER")
        from hdvr.pose2d.openpose_json import OpenPoseJsonDetector

        return OpenPoseJsonDetector(openpose_json)
    from hdvr.pose2d.onnx_pose import OnnxPoseDetector

    if kind == "onnx" or pose_model:
        if not pose_model:
            raise HDVRError("--detector onnx needs --pose-model MODEL.onnx")
        return OnnxPoseDetector(pose_model, input_size=size, threads=threads, weak_threshold=weak_threshold,
                                flip_test=flip_test)
    if kind == "yolo11n":
        from hdvr.pose2d.models import default_pose_model

        return OnnxPoseDetector(default_pose_model(), input_size=size, threads=threads,
                                weak_threshold=weak_threshold, flip_test=flip_test)
    raise HDVRError(f"unknown detector {name!r}: use yolo11n, onnx, openpose or none")


def dominant_movements(labels) -> dict[str, str]:
    """For each body part, the label it carries most often (``labels``: hdvr.movements Labels)."""
    out = {}
    segments = labels.segments()
    for part in labels.taxonomy.part_names:
        frames: dict[str, int] = {}
        for seg in segments:
            if seg["part"] == part:
                frames[seg["label"]] = frames.get(seg["label"], 0) + int(seg["end"]) - int(seg["start"])
        if frames:
            out[part] = max(frames, key=frames.get)
    return out


def active_movements(labels, top: int = 4) -> list[tuple[str, float]]:
    """The ``top`` labels other than keeping still, a relaxed foot and unknown that the dancer's body parts carry on
    most frames, each with the fraction of the clip's frames it covers, most frequent first (``labels``:
    hdvr.movements Labels): what a dancer does, where :func:`dominant_movements` mostly reads "Keeping Still"."""
    ids = np.asarray(labels.ids)
    if ids.size == 0:
        return []
    names = labels.taxonomy.labels
    counts = np.bincount(ids.astype(np.int64).ravel(), minlength=len(names))

    def at_rest(label) -> bool:
        return label.kind in ("still", "unknown") or (label.kind == "state" and label.condition == "relaxed")

    ranked = [int(i) for i in np.argsort(-counts, kind="stable") if counts[i] > 0 and not at_rest(names[int(i)])]
    return [(names[i].name, round(float(counts[i]) / ids.shape[0], 3)) for i in ranked[:top]]


def analyse_keypoints(kp_path: Path, out_dir: Path, index: int, fit_settings=None, render_size=None,
                      smoothing_s: float = PIPELINE_SMOOTHING_S, genre_recogniser=None) -> DancerOutputs:
    """3D fit, BVH, movement labels and score (and optionally a render) for one dancer's 2D keypoint file; with a
    :class:`~hdvr.recognition.genre.GenreRecogniser` also the dancer's genre probabilities."""
    from hdvr.fitting.sequence import fit_keypoints
    from hdvr.io.bvh import write_dancer_bvh
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.io.result3d import save_result3d
    from hdvr.movements.labeller import MovementLabeller
    from hdvr.movements.score import draw_score
    from hdvr.skeleton import Skeleton

    kp = load_keypoints2d(kp_path, require_visible=False)
    coverage = float((kp.keypoints[..., 2] > 0).any(axis=1).mean())
    dancer = DancerOutputs(index, kp_path, coverage)
    if coverage < MIN_POSE_COVERAGE:
        dancer.skipped = f"2D pose found on {100 * coverage:.0f}% of frames (< {100 * MIN_POSE_COVERAGE:.0f}%)"
        return dancer
    stem = out_dir / f"dancer_{index}"
    result, report = fit_keypoints(kp, fit_settings)
    dancer.result3d = stem.with_suffix(".result3d.npz")
    save_result3d(dancer.result3d, result)
    dancer.fit = {"frames_per_second": round(report.frames_per_second, 1),
                  "focal_px": round(float(np.median(result.focal)), 1),
                  "median_reprojection_px": round(float(np.nanmedian(result.reprojection_error_px)), 2),
                  "bone_lengths_m": [round(float(b), 3) for b in result.bone_lengths]}
    skeleton = Skeleton()
    skeleton.set_bone_lengths(result.bone_lengths)
    dancer.bvh = stem.with_suffix(".bvh")
    write_dancer_bvh(dancer.bvh, skeleton, result.qpos, result.fps)
    world = skeleton.keypoints(result.qpos)
    labels = MovementLabeller(smoothing_s=smoothing_s).label(world, result.fps, (0.0, 0.0, 1.0))
    dancer.labels = stem.with_suffix(".labels.json")
    write_text_atomic(dancer.labels, json.dumps({"source": str(dancer.result3d), "fps": result.fps,
                                                  "frames": int(world.shape[0]), "segments": labels.segments()},
                                                 indent=1))
    dancer.score = stem.with_suffix(".score.png")
    draw_score(labels, dancer.score, title=f"dancer {index}: movements (fitted 3D)")
    dancer.movements = dominant_movements(labels)
    dancer.active_movements = active_movements(labels)
    if genre_recogniser is not None:
        dancer.genre = genre_recogniser.as_dict(genre_recogniser.predict_labels(labels.multi_hot(), result.fps))
    if render_size:
        dancer.render = stem.with_suffix(".3d.mp4")
        render_motion(skeleton, result.qpos, dancer.render, result.fps, render_size)
    return dancer


def render_motion(skeleton, qpos: np.ndarray, path: Path, fps: float, size=(320, 240)) -> None:
    """Render a fitted motion with MuJoCo, the camera following the dancer, to an H.264 video."""
    import cv2

    from hdvr.render import DancerRenderer
    from hdvr.video import VideoWriter

    renderer = DancerRenderer(skeleton, size[0], size[1], shadows=False)
    try:
        with VideoWriter(path, fps, size) as writer:
            for q in qpos:
                renderer.set_camera(distance=3.2, azimuth=150.0, elevation=-10.0,
                                    lookat=(q[0], q[1], 0.8))
                writer.write(cv2.cvtColor(renderer.render(q), cv2.COLOR_RGB2BGR))
    finally:
        renderer.close()


def analyse_video(video: str | os.PathLike, out_dir: str | os.PathLike, num_dancers: int | None = None,
                  boxes=None, detector=None, detect_every: int = 3, fit_settings=None,
                  render_size: tuple[int, int] | None = None, recogniser="default", starts=None,
                  corrections=None, swaps=None) -> PipelineResult:
    """Run tracking, 2D pose, 3D fit, movement labelling and genre recognition on ``video``; see the module
    docstring. ``starts``, ``corrections``, ``swaps``: as for :func:`hdvr.tracking.pipeline.track_video`.
    ``recogniser``: "default" (the shipped checkpoint; genre is reported unavailable when it is missing), None (no
    genre), a checkpoint path (an error when unreadable) or a loaded GenreRecogniser."""
    from hdvr.progress import progress
    from hdvr.tracking.pipeline import track_video

    genre_model, genre_reason = load_genre_recogniser(recogniser)  # before the slow part: a bad path fails fast
    out = Path(out_dir)
    run = track_video(video, out, detector=detector, boxes=boxes, num_dancers=num_dancers,
                      detect_every=detect_every, starts=starts, corrections=corrections, swaps=swaps,
                      detections_cache=out / "detections.npz")
    dancers = []
    for i in progress(range(run.boxes.shape[1]), desc="3D fit and movements", unit="dancer"):
        kp_path = out / f"dancer_{i}.npz"
        try:
            dancers.append(analyse_keypoints(kp_path, out, i, fit_settings, render_size,
                                             genre_recogniser=genre_model))
        except HDVRError as exc:  # keep the other dancers' results
            dancers.append(DancerOutputs(i, kp_path, 0.0, skipped=str(exc)))
    result = PipelineResult(out, run.fps, int(run.boxes.shape[0]), dancers, run.seconds,
                            video_genre(dancers, genre_model, genre_reason))
    write_text_atomic(out / "summary.json", json.dumps(result.summary(), indent=1))
    return result
