"""``hdvr evaluate``: score tracks, 2D keypoints and 3D poses against a user's ground truth.

``hdvr evaluate tracks``: MOTA, IDF1, HOTA, identity switches, recall and precision (:mod:`hdvr.tracking.evaluation`,
computed by ``trackeval``) of tracked boxes against ground-truth boxes. Either side is MOT challenge text
(``frame,id,x,y,w,h,...``, 1-based frame and id, pixels: what ``hdvr track`` writes as ``tracks.mot.txt`` and what
annotation tools export; in ground truth, rows whose 7th column, the consider flag, is 0 are ignored boxes and
left out), an ``hdvr track`` output folder, or (ground truth only) an ``hdvr synth`` clip's ``gt.npz`` or its
folder. Ids need not correspond: the metrics find the best association themselves.

``hdvr evaluate keypoints``: PCK@alpha (a joint is right within alpha x the torso diameter of the truth) of a 2D
keypoint NPZ (``hdvr track``'s ``dancer_<i>.npz``) against a ground-truth one in the same format; joints the truth
lacks do not count, joints the prediction lacks count as wrong.

``hdvr evaluate pose3d``: MPJPE, P-MPJPE, N-MPJPE, velocity and acceleration errors (mm, VideoPose3D's definitions,
:mod:`hdvr.metrics`, on :data:`hdvr.layouts.EVAL_JOINTS`, root-relative) of a 3D result NPZ (``hdvr fit3d``,
``hdvr lift apply``, ``hdvr run``) against an ``hdvr synth`` clip's ``gt.npz`` (camera-frame keypoints of one
dancer) or another 3D result, frame by frame; frames either side lacks (:func:`hdvr.metrics.scored_frames`) are
left out and counted.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError


def load_boxes(path: str | Path, ground_truth: bool) -> np.ndarray:
    """(T, N, 4) boxes x, y, w, h px (NaN where absent) from MOT text, an ``hdvr track`` output folder (its
    ``tracks.mot.txt``), or an ``hdvr synth`` ``gt.npz`` / clip folder. ``ground_truth``: MOT rows marked ignored
    are left out (:func:`hdvr.tracking.boxes.read_mot`); it also names the side in errors."""
    from hdvr.tracking.boxes import read_mot

    what = "ground-truth" if ground_truth else "tracks"
    p = Path(path)
    if p.is_dir():
        if (p / "tracks.mot.txt").is_file():
            p = p / "tracks.mot.txt"
        elif (p / "gt.npz").is_file():
            p = p / "gt.npz"
        else:
            raise HDVRError(f"{what} folder {p} has neither tracks.mot.txt (hdvr track) nor gt.npz (hdvr synth)")
    if not p.is_file():
        raise HDVRError(f"{what} file not found: {p}")
    if p.suffix.lower() == ".npz":
        from hdvr.io.npz import open_npz

        boxes = np.asarray(open_npz(p, ("boxes",), f"{what} boxes")["boxes"], float)
        if boxes.ndim != 3 or boxes.shape[-1] != 4:
            raise HDVRError(f"{p}: 'boxes' must be (dancers, frames, 4), got {boxes.shape}")
        return np.transpose(boxes, (1, 0, 2))
    return read_mot(p, ground_truth=ground_truth)


def _pad_frames(boxes: np.ndarray, frames: int) -> np.ndarray:
    if boxes.shape[0] >= frames:
        return boxes
    return np.concatenate([boxes, np.full((frames - boxes.shape[0],) + boxes.shape[1:], np.nan)])


def score_tracks(gt_path, tracks_path, iou_threshold: float = 0.5) -> dict:
    """Tracking scores (:meth:`hdvr.tracking.evaluation.TrackingScores.as_dict`) of ``tracks_path`` against
    ``gt_path`` (see :func:`load_boxes`), over the frames of the longer of the two."""
    from hdvr.tracking.evaluation import evaluate_tracking

    if not 0 < iou_threshold < 1:
        raise HDVRError(f"--iou must be between 0 and 1, got {iou_threshold}")
    gt = load_boxes(gt_path, ground_truth=True)
    tracks = load_boxes(tracks_path, ground_truth=False)
    frames = max(gt.shape[0], tracks.shape[0])
    scores = evaluate_tracking(_pad_frames(gt, frames), _pad_frames(tracks, frames), iou_threshold)
    return dict(scores.as_dict(), gt_ids=int(gt.shape[1]), tracked_ids=int(tracks.shape[1]))


def score_keypoints(gt_path, predicted_path, alpha: float = 0.2, detector_joints: bool = False) -> dict:
    """PCK@``alpha`` of the 2D keypoint NPZ ``predicted_path`` against ``gt_path`` (both BODY_25-convertible, same
    frame count), overall and per joint. ``detector_joints``: score only the 19 BODY_25 joints a COCO-17 detector
    gives (no feet)."""
    from hdvr.io.keypoints2d import load_keypoints2d
    from hdvr.layouts import BODY25_NAMES, COCO17_NAMES
    from hdvr.tracking.evaluation import body25_joints_of, pck

    if not 0 < alpha <= 1:
        raise HDVRError(f"--alpha must be in (0, 1], got {alpha}")
    truth = load_keypoints2d(gt_path).to_body25()
    predicted = load_keypoints2d(predicted_path, require_visible=False).to_body25()
    if truth.num_frames != predicted.num_frames:
        raise HDVRError(f"{predicted_path} has {predicted.num_frames} frames, the ground truth {gt_path} "
                        f"{truth.num_frames}: score keypoints of the same video")
    joints = body25_joints_of(COCO17_NAMES) if detector_joints else np.arange(len(BODY25_NAMES))
    per_joint = {BODY25_NAMES[j]: pck(predicted.keypoints, truth.keypoints, alpha, joints=[int(j)]) for j in joints}
    return {"alpha": alpha, "pck": pck(predicted.keypoints, truth.keypoints, alpha, joints=joints),
            "frames": truth.num_frames,
            "per_joint": {k: v for k, v in per_joint.items() if np.isfinite(v)}}


def load_pose3d(path, dancer: int, what: str) -> np.ndarray:
    """(T, 25, 3) BODY_25 camera-frame keypoints, metres, from an ``hdvr synth`` ``gt.npz`` (``keypoints3d_camera``
    of ``dancer``) or a 3D result NPZ (``keypoints3d``). ``what`` names the side in errors."""
    from hdvr.io.npz import open_npz

    p = Path(path)
    with open_npz(p, (), what) as data:
        kp = np.asarray(data["keypoints3d_camera"], float) if "keypoints3d_camera" in data.files else None
    if kp is None:  # not a synth gt.npz: a 3D result, read and checked as such
        from hdvr.io.result3d import load_result3d

        return np.asarray(load_result3d(p).keypoints3d, float)
    if kp.ndim != 4 or kp.shape[2:] != (25, 3):
        raise HDVRError(f"{p}: 'keypoints3d_camera' must be (dancers, frames, 25, 3), got {kp.shape}")
    if not 0 <= dancer < kp.shape[0]:
        raise HDVRError(f"{p} has {kp.shape[0]} dancers; --dancer {dancer} does not exist")
    return kp[dancer]


def score_pose3d(gt_path, predicted_path, dancer: int = 0) -> dict:
    """3D metrics (mm, :func:`hdvr.metrics.evaluate`) of the 3D result ``predicted_path`` against ``gt_path``
    (:func:`load_pose3d`) on the frames both have (:func:`hdvr.metrics.scored_frames`); ``frames`` scored and
    ``frames_left_out``."""
    from hdvr.metrics import evaluate, scored_frames

    truth = load_pose3d(gt_path, dancer, "ground-truth 3D")
    predicted = load_pose3d(predicted_path, 0, "3D result")
    if truth.shape[0] != predicted.shape[0]:
        raise HDVRError(f"{predicted_path} has {predicted.shape[0]} frames, the ground truth {gt_path} "
                        f"{truth.shape[0]}: score 3D poses of the same video")
    scored = scored_frames(predicted, truth)
    if not scored.any():
        raise HDVRError(f"no frame has a full pose in both {gt_path} and {predicted_path}")
    scores = {k: round(v, 2) for k, v in evaluate(predicted, truth).items()}
    return dict(scores, frames=int(scored.sum()), frames_left_out=int((~scored).sum()))


def register(subparsers) -> None:
    p = subparsers.add_parser("evaluate", help="score tracks (MOTA, IDF1, HOTA), 2D keypoints (PCK) or 3D poses "
                                               "(MPJPE) against ground truth",
                              description="Score hdvr's outputs against your own ground truth.")
    sub = p.add_subparsers(dest="what", metavar="WHAT")
    t = sub.add_parser("tracks", help="MOTA, IDF1, HOTA, identity switches of tracked boxes",
                       description="Tracked boxes against ground-truth boxes (MOT text, an hdvr track folder, or "
                                   "an hdvr synth gt.npz / clip folder); metrics by trackeval.")
    t.add_argument("--gt", required=True, help="ground-truth boxes: MOT text, hdvr synth gt.npz or clip folder")
    t.add_argument("--tracks", required=True, help="tracked boxes: MOT text or an hdvr track output folder")
    t.add_argument("--iou", type=float, default=0.5, help="IoU at which a box matches, for MOTA and IDF1 "
                                                          "(HOTA averages over 0.05-0.95)")
    t.add_argument("--json", help="also write the scores to this JSON file")
    t.add_argument("--plot", help="also draw which track lies on each true dancer, frame by frame (PNG or JPEG): "
                                  "identity switches and misses show as changes of colour")
    t.set_defaults(func=_tracks)
    k = sub.add_parser("keypoints", help="PCK of a dancer's 2D keypoints",
                       description="PCK@alpha of a 2D keypoint NPZ (hdvr track's dancer_<i>.npz) against a "
                                   "ground-truth NPZ in the same format, overall and per joint.")
    k.add_argument("--gt", required=True, help="ground-truth 2D keypoint NPZ")
    k.add_argument("--pred", required=True, help="predicted 2D keypoint NPZ")
    k.add_argument("--alpha", type=float, default=0.2, help="threshold as a fraction of the torso diameter")
    k.add_argument("--detector-joints", action="store_true",
                   help="score only the 19 joints a COCO-17 detector gives (no feet)")
    k.add_argument("--json", help="also write the scores to this JSON file")
    k.set_defaults(func=_keypoints)
    d = sub.add_parser("pose3d", help="MPJPE, P-MPJPE of a fitted or lifted 3D pose",
                       description="MPJPE, P-MPJPE, N-MPJPE, velocity and acceleration errors (mm, root-relative, "
                                   "VideoPose3D's definitions) of a 3D result NPZ against an hdvr synth gt.npz or "
                                   "another 3D result of the same frames.")
    d.add_argument("--gt", required=True, help="hdvr synth gt.npz or a 3D result NPZ")
    d.add_argument("--pred", required=True, help="3D result NPZ (hdvr fit3d, lift apply, run)")
    d.add_argument("--dancer", type=int, default=0, help="dancer index in a synthetic gt.npz")
    d.add_argument("--json", help="also write the scores to this JSON file")
    d.set_defaults(func=_pose3d)
    p.set_defaults(func=lambda args: p.print_help() or 0)


def _write_json(path, doc: dict) -> None:
    from hdvr.io.atomic import write_text_atomic

    write_text_atomic(path, json.dumps(doc, indent=1))


def _tracks(args) -> int:
    from hdvr.io import PICTURE_SUFFIXES

    if args.plot and Path(args.plot).suffix.lower() not in PICTURE_SUFFIXES:  # before the scoring, not after
        raise HDVRError(f"--plot {args.plot}: give a .png or .jpg file name")
    s = score_tracks(args.gt, args.tracks, args.iou)
    print(f"MOTA {s['MOTA']:.3f}  IDF1 {s['IDF1']:.3f}  HOTA {s['HOTA']:.3f}  identity switches {s['IDSW']}  "
          f"recall {s['recall']:.3f}  precision {s['precision']:.3f}  ({s['frames']} frames, {s['gt_ids']} "
          f"ground-truth ids, {s['tracked_ids']} tracked; IoU {args.iou:g})")
    if args.json:
        _write_json(args.json, s)
    if args.plot:
        print(f"wrote {plot_tracks(args.gt, args.tracks, args.plot, args.iou, s)}")
    return 0


def plot_tracks(gt_path, tracks_path, path, iou_threshold: float, scores: dict) -> Path:
    """Draw :func:`hdvr.tracking.timeline.draw_truth_timeline` for ``tracks_path`` against ``gt_path`` (see
    :func:`load_boxes`) to ``path`` (PNG or JPEG), titled with ``scores`` (:func:`score_tracks`)."""
    from hdvr.tracking.evaluation import track_on_truth
    from hdvr.tracking.timeline import draw_truth_timeline

    gt = load_boxes(gt_path, ground_truth=True)
    tracks = load_boxes(tracks_path, ground_truth=False)
    frames = max(gt.shape[0], tracks.shape[0])
    owner, best = track_on_truth(_pad_frames(gt, frames), _pad_frames(tracks, frames), iou_threshold)
    fps = _fps_of(tracks_path)
    return draw_truth_timeline(path, owner, best, fps=fps, iou_threshold=iou_threshold,
                               title=f"{Path(tracks_path).name} against {Path(gt_path).name}: IDF1 "
                                     f"{scores['IDF1']:.3f}, MOTA {scores['MOTA']:.3f}, {scores['IDSW']} identity "
                                     f"switches")


def _fps_of(tracks_path) -> float | None:
    """The frame rate an ``hdvr track`` output folder's tracks.json gives, else None (MOT text has none)."""
    from hdvr.tracking.boxes import read_tracks_json

    p = Path(tracks_path)
    if p.is_dir() and (p / "tracks.json").is_file():
        return read_tracks_json(p).fps
    return None


def _keypoints(args) -> int:
    s = score_keypoints(args.gt, args.pred, args.alpha, args.detector_joints)
    worst = sorted(s["per_joint"].items(), key=lambda kv: kv[1])[:3]
    print(f"PCK@{args.alpha:g} {s['pck']:.3f} over {s['frames']} frames; weakest joints: "
          + ", ".join(f"{name} {v:.2f}" for name, v in worst))
    if args.json:
        _write_json(args.json, s)
    return 0


def _pose3d(args) -> int:
    s = score_pose3d(args.gt, args.pred, args.dancer)
    print(f"MPJPE {s['mpjpe_mm']:.1f} mm  P-MPJPE {s['p_mpjpe_mm']:.1f} mm  N-MPJPE {s['n_mpjpe_mm']:.1f} mm  "
          f"velocity {s['mpjve_mm']:.1f} mm/frame  acceleration {s['accel_error_mm']:.1f} mm/frame^2  "
          f"({s['frames']} frames" + (f", {s['frames_left_out']} without a full pose left out)"
                                      if s["frames_left_out"] else ")"))
    if args.json:
        _write_json(args.json, s)
    return 0
