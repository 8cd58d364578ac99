"""Pictures of where the tracker falls short, for docs/tracking.md ("Limits").

Renders held-out hdvr.synth clips (deterministic by seed), tracks them as ``scripts/bench_track.py --sections synth``
does (ground-truth start boxes, YOLO11n-pose at 480 px on every 3rd frame) and draws chosen frames: each dancer's
amodal ground-truth box thin, its tracked box thick in the same colour, with the IoU between them; the detector's
person boxes of that frame in white. Writes one JPEG per (seed, clip, frame) into docs/img, for the cases of
``BEFORE_AFTER`` one picture with the frame tracked without a rule (left) and with it (right), and for those of
``HINDSIGHT`` one with the online tracker's boxes (left) and the boxes written, occluded stretches filled with
hindsight (right), for those of ``KEYPOINT_REACH`` one with the boxes filled and smoothed (left) and widened to
the dancers' keypoints before the smoothing (right), for those of ``HEAD_REACH`` one with the boxes widened
(left) and lowered to a full pose's head (right), and for those of ``START_OFFSET`` one with the boxes before
(left) and after (right) a dancer waiting hidden behind another is moved towards her start offset, as written, for
those of ``AMODAL`` one with the boxes written without (left) and with (right) the learned whole-body refiner, for
those of ``DEPTH`` one with the boxes written without (left) and with (right) a waiting dancer's box scaled with her
feet against the horizon (``HindsightSettings.scale_with_depth``), for those of ``PARTNER`` one with the boxes
written without (left) and with (right) a couple's hidden partner carried with the dancer in front
(``HindsightSettings.follow_partner``), and
for those of ``CORRECTION`` one with the boxes as tracked (left) and after the first correction of the simulated user
of ``scripts/bench_corrections.py`` (right), at the frame after it where the corrected dancer's box gains most, and
for those of ``PROCEDURAL_HOLD`` a procedural crossing clip of ``bench_track.py --sections identity`` with a figure
held where it went behind (left, ``HindsightSettings.hold_min_cover`` 0) and as written (right), and for those of
``PROCEDURAL_TRIM`` one tracked without (left) and with (right) ``MultiTrackerConfig.foreground_trim``, and for
those of ``PROCEDURAL_LOST`` a procedural troupe clip (``--sections troupe``) tracked without (left) and with (right)
the whole-frame search for dancers lost for long (``MultiTrackerConfig.lost_search_after``), and for those of
``PROCEDURAL_VERTICAL`` a procedural crossing tracked without (left) and with (right) the fading vertical prediction
(``MultiTrackerConfig.vertical_prediction_frames``), and for those of ``PROCEDURAL_VERTICAL_CAP`` a procedural troupe
tracked without (left) and with (right) the cap on a clear dancer's stored vertical velocity
(``MultiTrackerConfig.max_vertical_speed``).

    MUJOCO_GL=egl python3 scripts/make_tracking_docs.py
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench_track, also where this file is loaded as a module

#: (seed, clip index, genre, dancers, frame, what it shows)
CASES = (
    (113, 5, "ballet", 4, 60, "dancer 1 straight behind dancer 2: its spread arms and raised leg lie behind dancer 2, "
                              "its box keeps the arms-down width"),
    (97, 5, "ballet", 4, 57, "a clump of three: no pose is chosen for dancer 2 (narrow box), and the predicted box of "
                             "dancer 3, hidden behind them, matches dancer 2's ground truth better"),
)
#: (seed, clip index, genre, dancers, frame, MultiTrackerConfig field switched off on the left, picture name)
BEFORE_AFTER = (
    (113, 5, "ballet", 4, 60, "hidden_min_aspect", "tracking_amodal_s113_ballet_060.jpg"),
    (2505, 1, "swing", 2, 66, "hold_within_cover", "tracking_hold_within_cover_s2505_swing_066.jpg"),
    (2202, 4, "hip_hop", 4, 100, "front_keeps_motion", "tracking_front_keeps_motion_s2202_hip_hop_100.jpg"),
    (2622, 2, "hip_hop", 3, 90, "stuck_persist", "tracking_stuck_persist_s2622_hip_hop_090.jpg"),
    (2624, 2, "hip_hop", 3, 60, "emerge_past_waiting", "tracking_emerge_past_waiting_s2624_hip_hop_060.jpg"),
    (2635, 0, "tango", 2, 60, "front_narrows", "tracking_front_narrows_s2635_tango_060.jpg"),
    (2665, 2, "hip_hop", 3, 8, "emerge_own_margin", "tracking_emerge_own_margin_s2665_hip_hop_008.jpg"),
    (2741, 5, "ballet", 4, 45, "lost_max_foreground", "tracking_lost_max_foreground_s2741_ballet_045.jpg"),
    (2762, 5, "ballet", 4, 30, "front_follows_feet", "tracking_front_follows_feet_s2762_ballet_030.jpg"),
    (2819, 4, "hip_hop", 4, 60, "front_feet_max_off", "tracking_front_feet_max_off_s2819_hip_hop_060.jpg"),
    (2915, 2, "hip_hop", 3, 108, "foreground_feet", "tracking_foreground_feet_s2915_hip_hop_108.jpg"),
    (2865, 2, "hip_hop", 3, 27, "pixel_front_limb", "tracking_pixel_front_limb_s2865_hip_hop_027.jpg"),
    (2804, 5, "ballet", 4, 45, "waiting_back_behind", "tracking_waiting_back_behind_s2804_ballet_045.jpg"),
    (2907, 5, "ballet", 4, 60, "waiting_empty_behind", "tracking_waiting_empty_behind_s2907_ballet_060.jpg"),
    (2870, 5, "ballet", 4, 27, "emerge_front_leaves", "tracking_emerge_front_leaves_s2870_ballet_027.jpg"),
    (2906, 3, "flamenco", 3, 45, "emerge_height_yield", "tracking_emerge_height_yield_s2906_flamenco_045.jpg"),
    (2844, 0, "tango", 2, 54, "waiting_counts_behind", "tracking_waiting_counts_behind_s2844_tango_054.jpg"),
    (2922, 3, "flamenco", 3, 81, "reid_radius_growth", "tracking_reid_radius_growth_s2922_flamenco_081.jpg"),
    (2844, 4, "hip_hop", 4, 95, "emerge_past_unlike_occluded",
     "tracking_emerge_past_unlike_occluded_s2844_hip_hop_095.jpg"),
    (3016, 5, "ballet", 4, 60, "stray_adrift_height_change", "tracking_stray_adrift_height_s3016_ballet_060.jpg"),
    (3038, 4, "hip_hop", 4, 40, "reid_past_waiting", "tracking_reid_past_waiting_s3038_hip_hop_040.jpg"),
    (3081, 4, "hip_hop", 4, 55, "front_long_run", "tracking_front_long_run_s3081_hip_hop_055.jpg"),
)
#: (figures, seed, frame, picture name): a procedural crossing clip (``bench_track.py --sections identity``) where a
#: figure that walked on behind another is held where it went behind without ``HindsightSettings.hold_min_cover``
PROCEDURAL_HOLD = (
    (3, 2, 110, "tracking_hold_min_cover_crossing3_s2_110.jpg"),
)
#: (figures, seed, frame, picture name): a procedural crossing clip with the detector where a thin figure's box kept
#: the width of a detection with spread arms (or of a sloppy one beside a partner) without
#: ``MultiTrackerConfig.foreground_trim``
PROCEDURAL_TRIM = (
    (2, 9, 63, "tracking_foreground_trim_crossing2_s9_063.jpg"),
)
#: (figures, seed, frame, picture name): a procedural troupe clip (``bench_track.py --sections troupe``) with the
#: detector where a figure stands alone while its box, lost in the group, stays there without
#: ``MultiTrackerConfig.lost_search_after``
PROCEDURAL_LOST = (
    (8, 1, 86, "tracking_lost_search_troupe8_s1_086.jpg"),
)
#: (figures, seed, frame, picture name): a procedural crossing clip of a held-out seed with the detector where a
#: figure walking level, hidden for long, is predicted sinking below itself without
#: ``MultiTrackerConfig.vertical_prediction_frames``
PROCEDURAL_VERTICAL = (
    (4, 14, 80, "tracking_vertical_prediction_crossing4_s14_080.jpg"),
)
#: (figures, seed, frame, picture name): a procedural troupe clip with the detector where a figure's tracker,
#: taken again on a patch off its figure, jumped back to it and gave the figure a vertical velocity that carries its
#: hidden box far below it without ``MultiTrackerConfig.max_vertical_speed``
PROCEDURAL_VERTICAL_CAP = (
    (8, 1, 100, "tracking_vertical_cap_troupe8_s1_100.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame inside an occluded stretch filled with hindsight
HINDSIGHT = (
    (1412, 5, "ballet", 4, 89, "tracking_hindsight_s1412_ballet_089.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a box is widened to its dancer's keypoints
KEYPOINT_REACH = (
    (701, 5, "ballet", 4, 93, "tracking_keypoint_reach_s701_ballet_093.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a box is lowered to its dancer's head
HEAD_REACH = (
    (309, 2, "hip_hop", 3, 96, "tracking_head_reach_s309_hip_hop_096.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a dancer waits hidden behind another
START_OFFSET = (
    (906, 2, "hip_hop", 3, 44, "tracking_start_offset_s906_hip_hop_044.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where the learned refiner moves the seen dancers'
#: boxes to their whole body (a clip of seeds 2681-2700, which it was not trained on)
AMODAL = (
    (2694, 5, "ballet", 4, 54, "tracking_amodal_boxes_s2694_ballet_054.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a couple has come nearer the camera and
#: the dancer hidden behind the front one all along is scaled with her feet (``scale_with_depth``; session 74, a clip
#: of the fresh set of seeds 2941-2965)
DEPTH = (
    (2960, 0, "tango", 2, 64, "tracking_depth_scale_s2960_tango_064.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a couple's partner waiting hidden behind the
#: dancer in front has opened her arms with his, and one where a partner occluded behind him after being seen is
#: carried with him (``follow_partner``; session 81, clips of the fresh set F and of seeds 2701-2823)
PARTNER = (
    (3049, 0, "tango", 2, 100, "tracking_partner_in_hold_s3049_tango_100.jpg"),
    (2733, 0, "tango", 2, 90, "tracking_partner_occluded_s2733_tango_090.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a frame where a dancer in plain view that the whole
#: frame's detection misses (a leg kicked high) gets its pose from a crop about it (``zoom_unposed``; session 53)
UNPOSED = (
    (2685, 4, "hip_hop", 4, 45, "tracking_zoom_unposed_s2685_hip_hop_045.jpg"),
)
#: (seed, clip index, genre, dancers, frame, picture name): a dancer the whole frame's detection misses beside the
#: others, found on the crop about the group (``zoom_group``; session 89, on by default since session 90): seed 2721
#: hip-hop, the small dancer lost without it from frame 18 on
GROUP_ZOOM = (
    (2721, 4, "hip_hop", 4, 30, "tracking_zoom_group_s2721_hip_hop_030.jpg"),
)
#: (seed, clip index, genre, dancers, picture name): a clip one correction mends
CORRECTION = (
    (1412, 2, "hip_hop", 3, "tracking_correction_s1412_hip_hop.jpg"),
)
#: (seed, clip index, genre, dancers, picture name): a clip drawn by hdvr evaluate tracks --plot (two switches)
EVALUATION = [(1509, 4, "hip_hop", 4, "tracking_evaluation_s1509_hip_hop.png")]
#: (--only value, cases, the two of :func:`_hindsight_steps_case`'s boxes drawn, their titles, the step shown)
STEP_PICTURES = (
    ("keypoints", KEYPOINT_REACH, slice(0, 2), ("filled and smoothed", "widened to the keypoints too"), "widening"),
    ("head", HEAD_REACH, slice(1, 3), ("widened to the keypoints", "lowered to the head's reach too"), "lowering"),
    ("start-offset", START_OFFSET, slice(2, 4), ("before the start offset", "towards the start offset (as written)"),
     "start offset"),
)
#: (--only value, cases, the HindsightSettings field drawn off (left) and on (right), their titles, what it is)
HINDSIGHT_SETTING_PICTURES = (
    ("amodal", AMODAL, "amodal_boxes", ("--no-amodal-boxes", "whole-body boxes (as written)"), "the amodal refiner"),
    ("depth", DEPTH, "scale_with_depth",
     ("her start size (scale_with_depth off)", "scaled with her feet (as written)"), "scale_with_depth"),
    ("partner", PARTNER, "follow_partner",
     ("her own box (follow_partner off)", "carried with his (as written)"), "follow_partner"),
)
#: (--only value, cases, the track_video crop option drawn off (left) and on (right), their titles, what it is,
#: other track_video options of both runs: the zoom about unposed dancers is drawn without the crop about the group,
#: which finds the kicking dancer's pose too since session 90)
ZOOM_PICTURES = (
    ("unposed", UNPOSED, "zoom_unposed", ("no zoom for dancers in view", "pose found zoomed in"),
     "the zoom about dancers in view without a detection", {"zoom_group": False}),
    ("group-zoom", GROUP_ZOOM, "zoom_group",
     ("no crop about the group (--no-zoom-group)", "crop about the group (as written)"), "the crop about the group",
     {}),
)
COLOURS = [(0, 0, 255), (0, 190, 0), (255, 60, 0), (0, 200, 220)]  # BGR


def draw_case(frame: np.ndarray, gt: np.ndarray, tracked: np.ndarray, detections, crop_margin: int = 40,
              crop_boxes=None):
    """Frame with ground-truth (thin) and tracked (thick) boxes, IoU labels, detections in white; cropped around
    the boxes (and ``crop_boxes`` (K, 4) px, if given: to crop two pictures alike)."""
    import cv2

    from hdvr.tracking.appearance import box_iou

    img = frame.copy()  # BGR, as decoded
    labels = []  # written in a strip above the picture: stacked dancers' labels would cover each other
    for det in detections:
        x, y, w, h = (int(round(v)) for v in det.box)
        cv2.rectangle(img, (x, y), (x + w, y + h), (255, 255, 255), 1)
    for i in range(gt.shape[0]):
        colour = COLOURS[i % len(COLOURS)]
        if np.isfinite(gt[i]).all():
            x, y, w, h = (int(round(v)) for v in gt[i])
            cv2.rectangle(img, (x, y), (x + w, y + h), colour, 1)
        if np.isfinite(tracked[i]).all():
            x, y, w, h = (int(round(v)) for v in tracked[i])
            cv2.rectangle(img, (x, y), (x + w, y + h), colour, 3)
            iou = box_iou(gt[i], tracked[i]) if np.isfinite(gt[i]).all() else 0.0
            labels.append((f"dancer {i}: IoU {iou:.2f}", colour))
    boxes = [gt, tracked] + ([np.asarray(crop_boxes, float)] if crop_boxes is not None else [])
    boxes = np.concatenate([b[np.isfinite(b).all(axis=1)] for b in boxes])
    x0 = max(0, int(boxes[:, 0].min()) - crop_margin)
    y0 = max(0, int(boxes[:, 1].min()) - crop_margin)
    x1 = min(img.shape[1], int((boxes[:, 0] + boxes[:, 2]).max()) + crop_margin)
    y1 = min(img.shape[0], int((boxes[:, 1] + boxes[:, 3]).max()) + crop_margin)
    crop = img[y0:y1, x0:x1]
    picture = cv2.resize(crop, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST)
    picture = cv2.copyMakeBorder(picture, 30, 0, 0, 0, cv2.BORDER_CONSTANT, value=(40, 40, 40))
    x = 8
    for text, colour in labels:
        cv2.putText(picture, text, (x, 21), cv2.FONT_HERSHEY_SIMPLEX, 0.5, colour, 2)
        x += cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 2)[0][0] + 18
    return picture


def _render_case(tmp: Path, seed: int, index: int, genre: str, n: int):
    """Render clip ``index`` of ``seed``: (gt (T, N, 4) boxes in the clip's order, start of each dancer in the order
    track_video numbers them, that order, path of the video)."""
    from bench_track import _starts_from_truth  # the starts the benchmark gives

    from hdvr.synth.groundtruth import ClipSpec, make_clip

    spec = ClipSpec(index, seed, genre, n, 4.0)
    make_clip(tmp, spec, render=True)
    clip = tmp / spec.name
    with np.load(clip / "gt.npz") as g:
        gt = np.transpose(g["boxes"], (1, 0, 2)).astype(float)
    order, starts = _starts_from_truth(gt)
    return gt, starts, order, clip / "video.mp4"


def _track_case(tmp: Path, detector, seed: int, index: int, genre: str, n: int, configs, hindsight=None):
    """Render clip ``index`` of ``seed`` and track it once per config (and per ``hindsight`` flag, zipped with
    ``configs``; default on); returns (gt (T, N, 4), tracked boxes per config (T, N, 4), path of the video),
    dancers in the clip's order."""
    from hdvr.tracking.pipeline import track_video

    gt, starts, order, video = _render_case(tmp, seed, index, genre, n)
    tracked = []
    for config, filled in zip(configs, hindsight or [True] * len(configs)):
        run = track_video(video, tmp / "out", detector=detector, starts=starts, detect_every=3,
                          overlay=False, write=False, config=config, hindsight=filled)
        tracked.append(run.boxes[:, np.argsort(order)])
    return gt, tracked, video


def _hindsight_steps_case(tmp: Path, detector, seed: int, index: int, genre: str, n: int):
    """Render and track clip ``index`` of ``seed`` once; returns (gt, [boxes filled (or held) and smoothed, also
    widened to the keypoints, also lowered to a full pose's head (:func:`hdvr.tracking.hindsight.apply_hindsight`
    without the hidden starts), as written (a dancer waiting hidden moved towards her start offset too)], path of
    the video), dancers in the clip's order."""
    from hdvr.tracking.hindsight import (HindsightSettings, apply_hindsight, enclose_keypoints, fill_occluded,
                                         hold_last_seen, keep_start_offset, smooth_boxes, start_offsets)
    from hdvr.tracking.pipeline import track_video

    gt, starts, order, video = _render_case(tmp, seed, index, genre, n)
    run = track_video(video, tmp / "out", detector=detector, starts=starts, detect_every=3, overlay=False,
                      write=False, hindsight=False)
    filled, mask = fill_occluded(run.boxes, run.status)
    filled, _ = hold_last_seen(filled, run.status, mask, stopped=run.stopped_behind)
    widened, _ = enclose_keypoints(filled, run.status, run.keypoints, frame_width=run.size[0])
    lowered, _ = apply_hindsight(run.boxes, run.status, run.keypoints, frame_width=run.size[0],
                                 settings=HindsightSettings(amodal_boxes=False), stopped_behind=run.stopped_behind)
    written = keep_start_offset(lowered, run.status, start_offsets(run.boxes, run.hidden_starts))  # the last step
    steps = [smooth_boxes(filled, run.status), smooth_boxes(widened, run.status), lowered, written]
    return gt, [b[:, np.argsort(order)] for b in steps], video


def _write_hindsight_setting(path: Path, tmp: Path, detector, case, field: str, frame_index: int, titles) -> None:
    """JPEG ``path``: frame ``frame_index`` of ``case`` ((seed, clip index, genre, dancers)), tracked once as the
    benchmark does, its boxes written by hindsight with the boolean ``HindsightSettings`` field ``field`` off (left)
    and on (right), under ``titles``."""
    from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight
    from hdvr.tracking.pipeline import track_video

    gt, starts, order, video = _render_case(tmp, *case)
    run = track_video(video, tmp / "out", detector=detector, starts=starts, detect_every=3, overlay=False,
                      write=False, hindsight=False)
    tracked = [apply_hindsight(run.boxes, run.status, run.keypoints, frame_width=run.size[0],
                               hidden_starts=run.hidden_starts, stopped_behind=run.stopped_behind,
                               returned_behind=run.returned_behind,
                               settings=HindsightSettings(**{field: on}))[0][:, np.argsort(order)]
               for on in (False, True)]
    _write_two_runs(path, video, detector, frame_index, gt, tracked, titles)


def _frame_and_detections(video: Path, detector, frame_index: int):
    """Frame ``frame_index`` of ``video`` and the detector's persons on the detector frame the tracker used last."""
    from hdvr.video import VideoReader

    detector_frame = frame_index - frame_index % 3
    frames = {k: f for k, f in enumerate(VideoReader(video)) if k in (frame_index, detector_frame)}
    return frames[frame_index], detector.detect(frames[detector_frame], detector_frame)


def _write_jpeg(path: Path, picture: np.ndarray) -> None:
    import cv2

    from hdvr.io.atomic import atomic_path

    path.parent.mkdir(parents=True, exist_ok=True)
    ok, data = cv2.imencode(".jpg", picture, [cv2.IMWRITE_JPEG_QUALITY, 88])
    if not ok:
        raise SystemExit(f"make_tracking_docs: error: cannot encode {path.name} as JPEG")
    with atomic_path(path) as tmp_path:
        tmp_path.write_bytes(data.tobytes())


def _side_by_side(left: np.ndarray, right: np.ndarray, titles) -> np.ndarray:
    """Two pictures of the same crop side by side, each with a title strip above it."""
    import cv2

    height = max(left.shape[0], right.shape[0])
    panels = []
    for picture, title in zip((left, right), titles):
        picture = cv2.copyMakeBorder(picture, 26, height - picture.shape[0], 0, 6, cv2.BORDER_CONSTANT,
                                     value=(255, 255, 255))
        cv2.putText(picture, title, (8, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.55, (0, 0, 0), 1)
        panels.append(picture)
    return cv2.hconcat(panels)


def _write_two_runs(path: Path, video: Path, detector, frame_index: int, gt: np.ndarray, tracked, titles) -> None:
    """JPEG ``path``: frame ``frame_index`` of ``video`` as two runs ``tracked`` ((T, N, 4) px each) boxed it,
    side by side under ``titles``, both cropped alike."""
    frame, detections = _frame_and_detections(video, detector, frame_index)
    both = np.concatenate([tracked[0][frame_index], tracked[1][frame_index]])
    pictures = [draw_case(frame, gt[frame_index], t[frame_index], detections, crop_boxes=both) for t in tracked]
    _write_jpeg(path, _side_by_side(*pictures, titles))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs/img"))
    parser.add_argument("--only", choices=("limits", "before-after", "hindsight", "keypoints", "head", "start-offset",
                                           "amodal", "depth", "partner", "unposed", "group-zoom", "correction",
                                           "timeline",
                                           "evaluation",
                                           "procedural-hold", "procedural-trim", "procedural-lost",
                                           "procedural-vertical", "procedural-vertical-cap"),
                        default=None,
                        help="write only the limit pictures, the before/after ones, the hindsight ones, the ones "
                             "of boxes widened to the keypoints, the ones of boxes lowered to a full pose's head or "
                             "the ones of a hidden dancer moved towards her start offset, the one of the learned "
                             "whole-body (amodal) boxes, the one of a waiting dancer scaled with her feet, the one "
                             "of a couple's hidden partner carried with the dancer in front, the one "
                             "of a dancer's pose found zoomed in, the one of a dancer found on the crop about the "
                             "group, the one of a "
                             "correction, or "
                             "the timeline and the frame with a pixel grid (hdvr frame) of the corrected clip, or the "
                             "picture of hdvr evaluate tracks --plot, or the procedural crossing held and not held, or "
                             "the one tracked with and without foreground_trim, or the troupe tracked with and "
                             "without the whole-frame search for lost dancers, or the crossing tracked with and "
                             "without the fading vertical prediction, or the troupe tracked with and without the "
                             "cap on the stored vertical velocity")
    parser.add_argument("--fields", default=None, metavar="NAME,...",
                        help="with --only before-after: only the pictures of these MultiTrackerConfig fields")
    args = parser.parse_args(argv)

    from hdvr.commands.evaluate import plot_tracks, score_tracks
    from hdvr.pipeline import make_detector
    from hdvr.tracking.pipeline import track_video

    detector = make_detector("yolo11n", 480, threads=2)  # as hdvr track has it, weak finds included
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for seed, index, genre, n, frame_index, what in CASES if args.only in (None, "limits") else ():
            gt, (tracked,), video = _track_case(tmp, detector, seed, index, genre, n, [None])
            frame, detections = _frame_and_detections(video, detector, frame_index)
            path = args.out / f"tracking_limit_s{seed}_{genre}_{frame_index:03d}.jpg"
            _write_jpeg(path, draw_case(frame, gt[frame_index], tracked[frame_index], detections))
            print(f"wrote {path}: {what}", file=sys.stderr)
        fields = set(args.fields.split(",")) if args.fields else None
        for seed, index, genre, n, frame_index, field, name in BEFORE_AFTER if args.only in (None, "before-after") \
                else ():
            if fields is not None and field not in fields:
                continue
            configs, titles = _field_off_and_default(field)
            gt, tracked, video = _track_case(tmp, detector, seed, index, genre, n, configs)
            path = args.out / name
            _write_two_runs(path, video, detector, frame_index, gt, tracked, titles)
            print(f"wrote {path}: seed {seed} {genre}, frame {frame_index}, {field} off and on", file=sys.stderr)
        for figures, seed, frame_index, name in PROCEDURAL_HOLD if args.only in (None, "procedural-hold") else ():
            path = args.out / name
            _write_procedural_hold(path, tmp, detector, figures, seed, frame_index)
            print(f"wrote {path}: {figures} procedural figures, seed {seed}, frame {frame_index}, without and with "
                  f"hold_min_cover", file=sys.stderr)
        for only, cases, kind, render, field in (
                ("procedural-trim", PROCEDURAL_TRIM, "crossing", _render_crossing, "foreground_trim"),
                ("procedural-lost", PROCEDURAL_LOST, "troupe", _render_troupe, "lost_search_after"),
                ("procedural-vertical", PROCEDURAL_VERTICAL, "crossing", _render_crossing,
                 "vertical_prediction_frames"),
                ("procedural-vertical-cap", PROCEDURAL_VERTICAL_CAP, "troupe", _render_troupe, "max_vertical_speed")):
            for figures, seed, frame_index, name in cases if args.only in (None, only) else ():
                path = args.out / name
                _write_procedural_rule(path, tmp, detector, render(tmp, figures, seed), field, frame_index)
                print(f"wrote {path}: {figures} procedural figures ({kind}), seed {seed}, frame {frame_index}, "
                      f"without and with {field}", file=sys.stderr)
        for seed, index, genre, n, frame_index, name in HINDSIGHT if args.only in (None, "hindsight") else ():
            gt, tracked, video = _track_case(tmp, detector, seed, index, genre, n, [None, None], [False, True])
            path = args.out / name
            _write_two_runs(path, video, detector, frame_index, gt, tracked,
                            ("online (--no-hindsight)", "with hindsight (as written)"))
            print(f"wrote {path}: seed {seed} {genre}, frame {frame_index}, without and with hindsight",
                  file=sys.stderr)
        for only, cases, panels, titles, step in STEP_PICTURES:
            for seed, index, genre, n, frame_index, name in cases if args.only in (None, only) else ():
                gt, tracked, video = _hindsight_steps_case(tmp, detector, seed, index, genre, n)
                path = args.out / name
                _write_two_runs(path, video, detector, frame_index, gt, tracked[panels], titles)
                print(f"wrote {path}: seed {seed} {genre}, frame {frame_index}, without and with the {step}",
                      file=sys.stderr)
        for only, cases, field, titles, what in HINDSIGHT_SETTING_PICTURES:
            for seed, index, genre, n, frame_index, name in cases if args.only in (None, only) else ():
                path = args.out / name
                _write_hindsight_setting(path, tmp, detector, (seed, index, genre, n), field, frame_index, titles)
                print(f"wrote {path}: seed {seed} {genre}, frame {frame_index}, without and with {what}",
                      file=sys.stderr)
        for only, cases, option, titles, what, fixed in ZOOM_PICTURES:
            for seed, index, genre, n, frame_index, name in cases if args.only in (None, only) else ():
                gt, starts, order, video = _render_case(tmp, seed, index, genre, n)
                tracked = [track_video(video, tmp / "out", detector=detector, starts=starts, detect_every=3,
                                       overlay=False, write=False, **{option: on}, **fixed).boxes[:, np.argsort(order)]
                           for on in (False, True)]
                path = args.out / name
                _write_two_runs(path, video, detector, frame_index, gt, tracked, titles)
                print(f"wrote {path}: seed {seed} {genre}, frame {frame_index}, without and with {what}",
                      file=sys.stderr)
        for seed, index, genre, n, name in CORRECTION if args.only in (None, "correction") else ():
            frame_index, (t, dancer) = _write_correction(args.out / name, tmp, detector, seed, index, genre, n)
            print(f"wrote {args.out / name}: seed {seed} {genre}, frame {frame_index}, without and with a correction "
                  f"of dancer {dancer} at frame {t}", file=sys.stderr)
        for seed, index, genre, n, name in EVALUATION if args.only in (None, "evaluation") else ():
            gt, starts, order, video = _render_case(tmp, seed, index, genre, n)
            track_video(video, tmp / "evaluated", detector=detector, starts=starts, detect_every=3, overlay=False)
            scores = score_tracks(video.parent, tmp / "evaluated")
            print(f"wrote {plot_tracks(video.parent, tmp / 'evaluated', args.out / name, 0.5, scores)}: seed {seed} "
                  f"{genre}, IDF1 {scores['IDF1']:.3f}", file=sys.stderr)
        for seed, index, genre, n, name in CORRECTION if args.only in (None, "timeline") else ():
            for path in _write_timeline_and_frame(args.out, tmp, detector, seed, index, genre, n):
                print(f"wrote {path}: seed {seed} {genre}", file=sys.stderr)
    return 0


def _render_crossing(tmp: Path, figures: int, seed: int):
    """The procedural crossing clip of ``figures`` figures and ``seed`` as ``bench_track.py --sections identity``
    renders it (150 frames), written into ``tmp``: (video path, :class:`hdvr.tracking.testclips.ClipTruth`)."""
    from hdvr.tracking.testclips import default_crossing_specs, render_clip

    video = tmp / f"crossing-{figures}-{seed}.mp4"
    return video, render_clip(video, frames=150, specs=default_crossing_specs(num_figures=figures, seed=seed),
                              seed=seed)


def _write_procedural_hold(path: Path, tmp: Path, detector, figures: int, seed: int, frame_index: int):
    """JPEG ``path``: frame ``frame_index`` of the procedural crossing clip of ``figures`` figures and ``seed`` (as
    ``bench_track.py --sections identity`` renders it), tracked as ``hdvr track`` does from the true first boxes, its
    boxes written with hindsight's ``hold_min_cover`` off (left) and as written (right). Returns the ground-truth
    boxes and those two runs' boxes ((T, N, 4) px each)."""
    from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight
    from hdvr.tracking.pipeline import track_video

    video, truth = _render_crossing(tmp, figures, seed)
    run = track_video(video, tmp / "out", detector=detector, boxes=truth.boxes[0], detect_every=3, overlay=False,
                      write=False, hindsight=False)
    tracked = [apply_hindsight(run.boxes, run.status, run.keypoints, frame_width=run.size[0],
                               hidden_starts=run.hidden_starts, stopped_behind=run.stopped_behind,
                               returned_behind=run.returned_behind,
                               settings=HindsightSettings(**settings))[0] for settings in ({"hold_min_cover": 0.0}, {})]
    _write_two_runs(path, video, detector, frame_index, truth.boxes, tracked,
                    ("held where last seen (hold_min_cover 0)", "place open to view: online (as written)"))
    return truth.boxes, tracked


def _render_troupe(tmp: Path, figures: int, seed: int):
    """The procedural troupe clip (two rows) of ``figures`` figures and ``seed`` as ``bench_track.py --sections
    troupe`` renders it (150 frames), written into ``tmp``: (video path, :class:`hdvr.tracking.testclips.ClipTruth`)."""
    from hdvr.tracking.testclips import render_clip, troupe_specs

    video = tmp / f"troupe-{figures}-{seed}.mp4"
    return video, render_clip(video, frames=150, specs=troupe_specs(num_figures=figures, seed=seed), seed=seed)


def _field_off_and_default(field: str):
    """The ``MultiTrackerConfig`` with ``field`` off (None for a test that may be switched off so, such as
    ``front_feet_max_off``; else 0, 0.0 or False) and the default one, and the two pictures' titles: ((off,
    default), (title off, title default))."""
    from dataclasses import replace

    from bench_track import tracker_field_may_be_none

    from hdvr.tracking.multi import MultiTrackerConfig

    default = MultiTrackerConfig()
    off = replace(default, **{field: None if tracker_field_may_be_none(field) else type(getattr(default, field))()})
    return (off, default), (f"{field} off", f"{field} = {getattr(default, field)}")


def _write_procedural_rule(path: Path, tmp: Path, detector, clip, field: str, frame_index: int):
    """JPEG ``path``: frame ``frame_index`` of the procedural ``clip`` ((video path, ground truth) of
    :func:`_render_crossing` or :func:`_render_troupe`), tracked as ``hdvr track`` does from the true first boxes with
    the ``MultiTrackerConfig`` ``field`` off (left: 0) and as by default (right), both as written (hindsight on).
    Returns the ground-truth boxes and those two runs' boxes ((T, N, 4) px each)."""
    from hdvr.tracking.pipeline import track_video

    video, truth = clip
    configs, titles = _field_off_and_default(field)
    tracked = [track_video(video, tmp / "out", detector=detector, boxes=truth.boxes[0], detect_every=3,
                           overlay=False, write=False, config=config).boxes for config in configs]
    _write_two_runs(path, video, detector, frame_index, truth.boxes, tracked, titles)
    return truth.boxes, tracked


def _first_correction_runs(tmp: Path, detector, seed: int, index: int, genre: str, n: int):
    """Clip ``index`` of ``seed`` tracked (outputs in ``tmp/plain``), the simulated user's first corrections
    (:func:`bench_corrections.next_corrections`: (frame, ground-truth dancer, box)) and the clip tracked again with
    them (``tmp/fixed``): (ground truth, start order, video, plain run, fixed run, corrections)."""
    from bench_corrections import next_corrections
    from bench_track import _seen_truth

    from hdvr.tracking.pipeline import BoxCorrection, track_video

    gt, starts, order, video = _render_case(tmp, seed, index, genre, n)
    truth = _seen_truth(video.parent)[1]
    plain = track_video(video, tmp / "plain", detector=detector, starts=starts, detect_every=3, overlay=False)
    fixes, _ = next_corrections(gt, plain.boxes[:, np.argsort(order)], (truth[..., 2] > 0).mean(axis=2))
    if not fixes:
        raise SystemExit(f"seed {seed} {genre}: nothing for the simulated user to correct")
    tracker_id = {j: k for k, j in enumerate(order)}
    fixed = track_video(video, tmp / "fixed", detector=detector, starts=starts, detect_every=3, overlay=False,
                        corrections=[BoxCorrection(f, tracker_id[j], b) for f, j, b in fixes])
    return gt, order, video, plain, fixed, fixes


def _write_timeline_and_frame(out: Path, tmp: Path, detector, seed: int, index: int, genre: str, n: int):
    """What a user works with to correct clip ``index`` of ``seed``: the frame of the simulated user's first
    correction as ``hdvr frame`` draws it from the tracks (pixel grid, boxes, ids), and the ``timeline.png`` of the
    run with that correction (dancers numbered in the order they start, as ``hdvr track`` numbers them)."""
    import shutil

    from hdvr.cli import main as hdvr_main

    _, _, video, _, _, fixes = _first_correction_runs(tmp, detector, seed, index, genre, n)
    t = fixes[0][0]
    frame_path = out / f"tracking_frame_s{seed}_{genre}_{t:03d}.jpg"
    if hdvr_main(["frame", str(video), str(t), "--tracks", str(tmp / "plain"), "--out", str(frame_path)]):
        raise SystemExit("hdvr frame failed")
    timeline_path = out / f"tracking_timeline_s{seed}_{genre}.png"
    shutil.copyfile(tmp / "fixed" / "timeline.png", timeline_path)
    return frame_path, timeline_path


def _write_correction(path: Path, tmp: Path, detector, seed: int, index: int, genre: str, n: int):
    """JPEG ``path``: clip ``index`` of ``seed`` as tracked and after the simulated user's first correction
    (:func:`bench_corrections.next_corrections`), at the frame after it where the corrected dancer's IoU with its
    ground truth gains most. Returns the frame drawn and (frame, ground-truth dancer) of the correction."""
    from hdvr.tracking.appearance import box_iou

    gt, order, video, plain, fixed, fixes = _first_correction_runs(tmp, detector, seed, index, genre, n)
    plain, fixed = plain.boxes[:, np.argsort(order)], fixed.boxes[:, np.argsort(order)]
    t, j = fixes[0][:2]

    def iou(boxes, k):
        return box_iou(boxes[k, j], gt[k, j]) if np.isfinite(boxes[k, j]).all() and np.isfinite(gt[k, j]).all() else 0
    frame_index = max(range(t + 1, len(gt)), key=lambda k: iou(fixed, k) - iou(plain, k))
    frame, detections = _frame_and_detections(video, detector, frame_index)
    both = np.concatenate([plain[frame_index], fixed[frame_index]])
    pictures = [draw_case(frame, gt[frame_index], run[frame_index], detections, crop_boxes=both)
                for run in (plain, fixed)]
    _write_jpeg(path, _side_by_side(*pictures, (f"as tracked, frame {frame_index}",
                                                f"dancer {j} corrected at frame {t}, frame {frame_index}")))
    return frame_index, (t, j)


if __name__ == "__main__":
    raise SystemExit(main())
