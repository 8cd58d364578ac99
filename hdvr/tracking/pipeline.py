"""Video -> per-dancer tracks and 2D keypoints (Algorithms 1* and 2* together), streaming in constant memory.

Outputs in ``out_dir``:

- ``dancer_<i>.npz``: the 2D keypoint file of dancer i (BODY_25, :mod:`hdvr.io.keypoints2d` format), the input
  of ``hdvr fit3d``;
- ``tracks.mot.txt`` (MOT challenge text) and ``tracks.json``: boxes per frame and dancer;
- ``overlay.mp4``: H.264 video with boxes, ids and skeletons (unless disabled);
- ``timeline.png``: each dancer's status and found keypoints over the frames, with the corrections and swaps
  (unless disabled; :mod:`hdvr.tracking.timeline`).

Frames are decoded and tracked one at a time; only small per-frame arrays (boxes and keypoints) are kept. Once
all frames are tracked, the stretches in which a dancer was hidden behind others are filled with hindsight (or held
where it was last seen when it was not seen again), the boxes widened to the keypoints chosen for their dancers (and
lowered to a full pose's head where they reach far above it) and smoothed over time (:mod:`hdvr.tracking.hindsight`),
and the overlay is drawn in a second pass over the video with the final boxes. If decoding or anything else stops
the run early, the outputs for the frames done so far are written before the error is raised.
"""

from __future__ import annotations

import itertools
import os
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from hdvr.errors import HDVRError
from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
from hdvr.layouts import BODY25_NAMES
from hdvr.pose2d.base import PersonPose, PoseDetector
from hdvr.pose2d.cache import CachingDetector, detector_signature, load_detections, save_detections, video_signature
from hdvr.pose2d.draw import draw_overlay
from hdvr.pose2d.selection import PoseSelector
from hdvr.progress import progress
from hdvr.tracking.appearance import box_iou, box_overlap
from hdvr.tracking.boxes import check_boxes_in_frame, write_mot, write_tracks_json
from hdvr.tracking.amodal import load_refiner
from hdvr.tracking.hindsight import HindsightSettings, apply_hindsight
from hdvr.tracking.multi import OCCLUDED, OUT, TRACKED, FrameResult, MultiDancerTracker, MultiTrackerConfig
from hdvr.tracking.state import BODY_CORE_ASPECT, HIDDEN, body_core
from hdvr.tracking.timeline import draw_tracks_timeline
from hdvr.video import VideoReader, VideoWriter


@dataclass
class TrackRun:
    """What a run produced (arrays cover the frames processed)."""

    boxes: np.ndarray  # (T, N, 4) x, y, w, h px
    status: list  # T tuples of N: "tracked" (seen), "occluded" (hidden behind others: box predicted, or filled with
    # hindsight), "hidden" (started hidden behind another, not come out yet), "out" (of the frame), "absent" (not
    # started yet)
    confidence: np.ndarray  # (T, N)
    keypoints: np.ndarray  # (T, N, 25, 3) BODY_25 x_px, y_px, confidence
    detected: np.ndarray  # (T,) bool: the detector ran on this frame
    fps: float
    size: tuple[int, int]
    outputs: list[Path] = field(default_factory=list)
    seconds: float = 0.0  # wall clock
    cpu_seconds: float = 0.0  # CPU time of this process (all threads) during the run
    stage_seconds: dict = field(default_factory=dict)  # decode, detect, track, select, overlay (the overlay video
    # and the timeline picture)
    hidden_starts: list = field(default_factory=list)  # (frame, dancer, dancer in front) per dancer whose start box
    # lies mostly behind another dancer's (MultiDancerTracker.hiding_dancer): its colours are not its own; also per
    # correction that puts a dancer straight behind another (it waits behind it from there), and per wait the tracker
    # handed over to another dancer in front (``MultiTrackerConfig.adrift_hands_over_waiting``)
    filled: np.ndarray | None = None  # (T, N) bool: box filled with hindsight
    # (:func:`hdvr.tracking.hindsight.fill_occluded`)
    detections_reused: int = 0  # frames whose people came from the detections cache (track_video's
    # ``detections_cache``) instead of the detector
    stopped_behind: np.ndarray | None = None  # (T, N) bool: occluded, its predicted box stopped behind the dancers
    # in front (``DancerTrack.stopped_behind``); hindsight keeps such a stretch's online boxes
    returned_behind: np.ndarray | None = None  # (T, N) bool: waiting behind another since its start and put back
    # behind it from the empty floor (``DancerTrack.returned_behind``) on or before this frame; hindsight does not
    # pull such a wait back towards the start place (:func:`hdvr.tracking.hindsight.keep_start_place`)


@dataclass(frozen=True)
class DancerStart:
    """Where tracking of a dancer begins: 0-based frame and (x, y, w, h) px box in it."""

    frame: int
    box: tuple[float, float, float, float]


@dataclass(frozen=True)
class BoxCorrection:
    """A user's correction: in 0-based ``frame``, dancer ``dancer`` (0-based, as numbered in the outputs) is at
    ``box`` = (x, y, w, h) px, or (``box`` None) is the person the detector finds at ``point`` = (x, y) px in that
    frame (:func:`person_at`). Its tracker restarts there (:meth:`MultiDancerTracker.correct`) and the box is
    written as given (or as found)."""

    frame: int
    dancer: int
    box: tuple[float, float, float, float] | None
    point: tuple[float, float] | None = None


@dataclass(frozen=True)
class IdentitySwap:
    """A user's identity swap: from 0-based ``frame`` on, dancers ``first`` and ``second`` (ids as numbered in the
    outputs) exchange ids, where the overlay shows each box on the other dancer after a crossing. Only the ids
    written change: each tracker keeps following the person it followed, with that person's memories."""

    frame: int
    first: int
    second: int


def find_dancers(video: str | os.PathLike, detector: PoseDetector, num_dancers: int, seconds: float = 3.0,
                 every: int = 3, min_iou: float = 0.3) -> list[DancerStart]:
    """The ``num_dancers`` people seen most often in the first ``seconds`` of ``video`` (detector on every
    ``every``-th frame; detections linked frame to frame by box overlap), each with its first detection.
    Ids are ordered by first appearance, then left to right."""
    reader = VideoReader(video)
    limit = max(1, int(round(seconds * reader.info.fps)))
    tracks: list[dict] = []
    for k, frame in enumerate(itertools.islice(reader, limit)):
        if k % every:
            continue
        used = set()
        for p in detector.detect(frame, k):
            if p.weak:  # a dancer to follow is found surely
                continue
            best, best_iou = None, min_iou
            for ti, tr in enumerate(tracks):
                if ti in used or k - tr["last_frame"] > 3 * every:
                    continue
                iou = box_iou(tr["box"], p.box)
                if iou > best_iou:
                    best, best_iou = ti, iou
            if best is None:
                tracks.append({"box": p.box, "last_frame": k, "count": 1, "score": p.score,
                               "start": DancerStart(k, tuple(float(v) for v in p.box))})
                used.add(len(tracks) - 1)
            else:
                tr = tracks[best]
                tr.update(box=p.box, last_frame=k, count=tr["count"] + 1, score=tr["score"] + p.score)
                used.add(best)
    reader.close()
    if not tracks:
        raise HDVRError(f"no person found in the first {seconds:g} s of {video}; give the dancers' boxes with "
                        f"--boxes")
    tracks.sort(key=lambda tr: (-tr["count"], -tr["score"]))
    chosen = tracks[:num_dancers]
    if len(chosen) < num_dancers:
        print(f"hdvr: warning: asked for {num_dancers} dancers, found {len(chosen)} people in the first "
              f"{seconds:g} s", file=sys.stderr)
    chosen.sort(key=lambda tr: (tr["start"].frame, tr["start"].box[0]))
    return [tr["start"] for tr in chosen]


def person_at(people, point) -> tuple[float, float, float, float] | None:
    """The box (x, y, w, h px) of the person among ``people`` (:class:`PersonPose`) that a user pointed at with
    ``point`` = (x, y) px: of those whose box holds the point, the one with a found keypoint nearest to it (in a
    stack the boxes of several people hold it; the keypoints tell whose body it is on), then the smaller box. None
    if no box holds it."""
    x, y = point
    best, best_key = None, None
    for p in people:
        bx, by, bw, bh = p.box
        if not (bx <= x <= bx + bw and by <= y <= by + bh):
            continue
        kp = np.asarray(p.keypoints, float)
        found = kp[(kp[:, 2] > 0) & np.isfinite(kp[:, :2]).all(axis=1), :2]
        distance = float(np.hypot(*(found - (x, y)).T).min()) if len(found) else np.inf
        key = (distance, bw * bh)
        if best_key is None or key < best_key:
            best, best_key = tuple(float(v) for v in p.box), key
    return best


def _check_dancer_at(where: str, dancer: int, frame: int, starts: list[DancerStart], num_frames: int | None) -> None:
    """Raise :class:`HDVRError` (message starting with ``where``) unless ``dancer`` exists and has started by
    ``frame`` (``starts`` sorted by frame, as the dancers are numbered) and ``frame`` is within the video's
    ``num_frames`` (None: unknown)."""
    if not 0 <= dancer < len(starts):
        raise HDVRError(f"{where}: no dancer {dancer} (dancers are numbered 0 to {len(starts) - 1})")
    if frame < starts[dancer].frame:
        raise HDVRError(f"{where}: dancer {dancer} starts only at frame {starts[dancer].frame}")
    if num_frames is not None and frame >= num_frames:
        raise HDVRError(f"{where}: the video has {num_frames} frames (counted from 0)")


def check_corrections(corrections: list[BoxCorrection], starts: list[DancerStart], num_frames: int | None,
                      size: tuple[int, int], has_detector: bool = True) -> None:
    """Raise :class:`HDVRError` for a correction of a dancer that does not exist or has not started by its frame,
    one past the video's ``num_frames`` (None: unknown), one dancer given twice in a frame, a box (or point)
    outside a frame of ``size`` = (w, h) px, or a point without a detector to find the person there
    (``has_detector``). ``starts``: sorted by frame, as the dancers are numbered."""
    seen = set()
    for c in corrections:
        if (c.box is None) == (c.point is None):
            raise HDVRError(f"correction of dancer {c.dancer} at frame {c.frame}: give a box or a point, not "
                            f"{'both' if c.box is not None else 'neither'}")
        if c.point is not None:
            if not has_detector:
                raise HDVRError(f"correction of dancer {c.dancer} at frame {c.frame}: a point needs a detector to "
                                f"find the person there; give the box x,y,w,h")
            if not (0 <= c.point[0] < size[0] and 0 <= c.point[1] < size[1]):
                raise HDVRError(f"correction of dancer {c.dancer} at frame {c.frame}: point ({c.point[0]:g}, "
                                f"{c.point[1]:g}) lies outside the {size[0]}x{size[1]} frame")
        _check_dancer_at(f"correction at frame {c.frame}", c.dancer, c.frame, starts, num_frames)
        if (c.frame, c.dancer) in seen:
            raise HDVRError(f"dancer {c.dancer} is corrected twice at frame {c.frame}")
        seen.add((c.frame, c.dancer))
        try:
            if c.box is not None:
                check_boxes_in_frame([c.box], size)
        except HDVRError as exc:
            raise HDVRError(f"correction of dancer {c.dancer} at frame {c.frame}: {exc}") from None


def check_swaps(swaps: list[IdentitySwap], starts: list[DancerStart], num_frames: int | None) -> None:
    """Raise :class:`HDVRError` for a swap of a dancer with itself, of one that does not exist or has not started
    by its frame, or one past the video's ``num_frames`` (None: unknown). ``starts``: sorted by frame."""
    for s in swaps:
        where = f"swap of dancers {s.first} and {s.second} at frame {s.frame}"
        if s.first == s.second:
            raise HDVRError(f"{where}: a dancer cannot swap with itself")
        for i in (s.first, s.second):
            _check_dancer_at(where, i, s.frame, starts, num_frames)


def _pad(result: FrameResult, n: int) -> FrameResult:
    """``result`` with rows for dancers not started yet (NaN box, status "absent")."""
    k = len(result.status)
    if k == n:
        return result
    boxes = np.full((n, 4), np.nan)
    boxes[:k] = result.boxes
    conf = np.zeros(n)
    conf[:k] = result.confidence
    return FrameResult(result.frame_index, boxes, tuple(result.status) + ("absent",) * (n - k), conf)


def _reported_status(result: FrameResult, tracker: MultiDancerTracker) -> tuple[str, ...]:
    """The status written for each dancer: the tracker's, except "hidden" for a dancer that started hidden behind
    another and waits to come out (its box is held on that dancer; the tracker counts it as followed)."""
    waiting = {d.dancer_id for d in tracker.waiting()}
    return tuple(HIDDEN if i in waiting else s for i, s in enumerate(result.status))


def fill_between_detections(keypoints: np.ndarray, detected: np.ndarray, max_gap: int) -> np.ndarray:
    """Keypoints (T, N, J, 3) of frames where the detector did not run: linear interpolation between the nearest
    detector frames before and after (when both have the joint and are at most ``max_gap`` frames apart);
    otherwise missing. Confidence is the smaller of the two."""
    out = keypoints.copy()
    det_idx = np.flatnonzero(detected)
    if len(det_idx) < 2:
        return out
    for t in np.flatnonzero(~detected):
        k = np.searchsorted(det_idx, t)
        if k == 0 or k >= len(det_idx):
            continue
        a, b = det_idx[k - 1], det_idx[k]
        if b - a > max_gap:
            continue
        w = (t - a) / (b - a)
        ka, kb = keypoints[a], keypoints[b]
        ok = (ka[..., 2] > 0) & (kb[..., 2] > 0)
        out[t, ..., :2] = np.where(ok[..., None], (1 - w) * ka[..., :2] + w * kb[..., :2], np.nan)
        out[t, ..., 2] = np.where(ok, np.minimum(ka[..., 2], kb[..., 2]), 0.0)
    return out


def zoom_detections(detector: PoseDetector, frame: np.ndarray, frame_index: int, boxes, people: list,
                    clear_of=(), side: float = 2.5, core_aspect: float = BODY_CORE_ASPECT,
                    overlap: float = 0.05) -> list:
    """People found by running ``detector`` again on square crops of ``frame`` about ``boxes`` ((x, y, w, h) px;
    side ``side`` x the box height, clipped to the frame), in frame pixels. The detector sees each crop at its
    input size (``track_video`` gives it :data:`ZOOM_INPUT_SIZE`), so a small dancer beside another, which it misses
    in the whole frame, is larger there
    (hdvr synth seed 308 ballet: a dancer 75 px tall that walked out from behind another, missed in the whole
    frame at 480 and 640 px input, found in the crop with score 0.78). Left out: a person that one of ``people``
    or one found before already covers (IoU > 0.5), one cut by a side of the crop that is not the frame's (a part
    of someone), and one whose body core (``core_aspect`` x its height wide) overlaps that of a box of
    ``clear_of`` by more than ``overlap`` (intersection / smaller): such a box, a part of a group, is the kind that
    is taken for the wrong dancer, and a dancer coming out from behind another is sought clear of the others
    (:meth:`hdvr.tracking.multi.MultiDancerTracker._emerge`). A weak find (:class:`PersonPose` ``weak``) counts
    as sure here: the crop is searched only where a waiting dancer is expected."""
    height, width = frame.shape[:2]
    found: list = []
    for x, y, w, h in boxes:
        cx, cy, half = x + w / 2, y + h / 2, side * h / 2
        x0, y0 = int(max(0, cx - half)), int(max(0, cy - half))
        x1, y1 = int(min(width, cx + half)), int(min(height, cy + half))
        if x1 - x0 < 32 or y1 - y0 < 32:
            continue
        for p in crop_detections(detector, frame, frame_index, (x0, y0, x1, y1)):
            core = body_core(p.box, core_aspect)
            if any(box_iou(p.box, q.box) > 0.5 for q in list(people) + found) or \
                    any(box_overlap(core, body_core(o, core_aspect)) > overlap for o in clear_of):
                continue
            found.append(replace(p, weak=False))
    return found


def crop_detections(detector: PoseDetector, frame: np.ndarray, frame_index: int, crop) -> list:
    """The people ``detector`` finds on the crop ``crop`` (x0, y0, x1, y1 px) of ``frame``, box and keypoints in
    frame pixels, weak finds weak; left out: a person cut by a side of the crop that is not the frame's (a part of
    someone)."""
    height, width = frame.shape[:2]
    x0, y0, x1, y1 = crop
    found: list = []
    for p in detector.detect(np.ascontiguousarray(frame[y0:y1, x0:x1]), frame_index):
        bx, by, bw, bh = p.box
        if ((bx <= 2 and x0 > 0) or (by <= 2 and y0 > 0) or (bx + bw >= x1 - x0 - 2 and x1 < width)
                or (by + bh >= y1 - y0 - 2 and y1 < height)):
            continue
        kp = np.array(p.keypoints, np.float32, copy=True)
        kp[:, 0] += x0
        kp[:, 1] += y0
        found.append(PersonPose(kp, (bx + x0, by + y0, bw, bh), p.score, p.joint_names, weak=p.weak))
    return found


#: margin (x the group's width and height) added on each side of the union of the dancers' boxes to make the crop
#: about a group (:func:`group_zoom_detections`)
GROUP_ZOOM_MARGIN = 0.15
#: the crop about a group is searched only when it is at most this fraction of the frame's width and of its height:
#: a larger one would show the dancers hardly larger than the whole frame does
GROUP_ZOOM_MAX_FRACTION = 0.8


def group_crop(boxes, frame_size: tuple[int, int], margin: float = GROUP_ZOOM_MARGIN,
               max_fraction: float = GROUP_ZOOM_MAX_FRACTION) -> tuple[int, int, int, int] | None:
    """The crop (x0, y0, x1, y1 px, clipped to the frame of ``frame_size`` (width, height)) about the union of
    ``boxes`` ((x, y, w, h) px), widened by ``margin`` x its width and height on each side; None when there are no
    boxes or the crop is larger than ``max_fraction`` of the frame's width or height."""
    boxes = np.asarray([b for b in boxes if np.isfinite(b).all()], float).reshape(-1, 4)
    if not len(boxes):
        return None
    width, height = frame_size
    x0, y0 = boxes[:, 0].min(), boxes[:, 1].min()
    x1, y1 = (boxes[:, 0] + boxes[:, 2]).max(), (boxes[:, 1] + boxes[:, 3]).max()
    mx, my = margin * (x1 - x0), margin * (y1 - y0)
    x0, y0 = int(max(0.0, x0 - mx)), int(max(0.0, y0 - my))
    x1, y1 = int(min(width, x1 + mx)), int(min(height, y1 + my))
    if x1 - x0 < 32 or y1 - y0 < 32 or x1 - x0 > max_fraction * width or y1 - y0 > max_fraction * height:
        return None
    return x0, y0, x1, y1


def group_zoom_detections(detector: PoseDetector, frame: np.ndarray, frame_index: int, crop, people: list) -> list:
    """People found by running ``detector`` again on the crop ``crop`` (x0, y0, x1, y1 px, :func:`group_crop`) of
    ``frame`` about a group of dancers, in frame pixels: at the detector's input size the dancers are larger there
    than in the whole frame, and the detector finds some it missed (a small dancer beside a tall one, a dancer half
    behind another; hdvr synth clips of 3-4 dancers, session 89: of 722 dancer-frames at least half visible, the
    whole frame at 480 px found 507, whole frame and crop together 607). Left out: a person that one of ``people``
    (the whole frame's) already covers (IoU > 0.5), and one cut by a side of the crop that is not the frame's (a
    part of someone; :func:`crop_detections`). Every find comes back weak (:class:`PersonPose` ``weak``): zoomed
    in, the detector also draws parts of dancers as people (session 89: 275 of the 695 finds it added on 41 clips
    matched no dancer), so a find here only updates a dancer followed (``MultiDancerTracker.step``'s
    ``zoomed_detections``) and may be chosen as a pose (Algorithm 2*), never finds a lost dancer again, and lets a
    dancer waiting hidden come out only when as tall as her box (``MultiTrackerConfig.zoomed_emerge_height``)."""
    found: list = []
    for p in crop_detections(detector, frame, frame_index, crop):
        if not any(box_iou(p.box, q.box) > 0.5 for q in list(people) + found):
            found.append(replace(p, weak=True))
    return found


def in_a_group(dancers, overlap_threshold: float = 0.0) -> bool:
    """Whether any two of ``dancers`` (:class:`hdvr.tracking.state.DancerTrack`, not out of the frame) have boxes
    that overlap (intersection over the smaller box above ``overlap_threshold``), or any is occluded or waits
    hidden behind another: the frames on which the detector is asked again about the group
    (``track_video(zoom_group=True)``)."""
    present = [d for d in dancers if d.status != OUT]
    if any(d.status == OCCLUDED or d.hidden_behind is not None for d in present):
        return True
    return any(box_overlap(a.box, b.box) > overlap_threshold
               for i, a in enumerate(present) for b in present[i + 1:])


#: side of the square crop (x the box height) about a dancer seen that no whole-frame person lies on, in which the
#: detector looks for its pose again (:func:`unposed_dancers`; session 53 measured 1.5, 2.0 and 2.5: docs/benchmarks.md)
UNPOSED_ZOOM_SIDE = 2.0
#: detector frames a dancer is not looked for again, zoomed in, after a crop about it gave it no pose (a figure the
#: detector cannot see at all, such as a stick figure, would otherwise cost a crop on every detector frame)
UNPOSED_RETRY_AFTER = 4
#: network input size (longer side, px) of the detector on the crops about single dancers (:func:`zoom_detections`),
#: where the detector allows it (``at_input_size``). A crop 2 x a dancer's height shows it 160 px tall at 320 px,
#: larger than the whole frame at 480 px shows any dancer under 210 px; at 320 a crop costs 0.44 of one at 480
#: (session 54, 120 hdvr synth clips: 7 failing with either; speed benchmark 16.3 -> 18.6 frames/s:
#: docs/benchmarks.md)
ZOOM_INPUT_SIZE = 320


def unposed_dancers(dancers, people, min_iou: float = 0.3) -> list[int]:
    """Indices of the ``dancers`` (:class:`hdvr.tracking.state.DancerTrack`) seen now (status ``tracked``, not waiting
    hidden behind another) on whose tracked box (x, y, w, h px) no person of ``people`` (:class:`PersonPose`,
    whole-frame detections) lies at IoU ``min_iou`` or more: dancers in plain view that the detector missed in the
    whole frame (an unusual pose, such as a leg kicked high, or a small dancer), whose pose a crop about them may
    still give."""
    return [i for i, d in enumerate(dancers)
            if d.status == TRACKED and d.hidden_behind is None
            and not any(box_iou(d.box, p.box) >= min_iou for p in people)]


def track_video(video: str | os.PathLike, out_dir: str | os.PathLike, detector: PoseDetector | None = None,
                boxes=None, num_dancers: int | None = None, detect_every: int = 1, overlay: bool = True,
                max_frames: int | None = None, config: MultiTrackerConfig | None = None,
                init_seconds: float = 3.0, write: bool = True, starts: list[DancerStart] | None = None,
                zoom_hidden: bool = True, zoom_unposed: bool = True, zoom_group: bool = True,
                zoom_input_size: int | None = ZOOM_INPUT_SIZE,
                hindsight: bool = True, amodal_boxes: bool = True,
                amodal_weights: str | os.PathLike | None = None, follow_partner: bool = True,
                corrections: list[BoxCorrection] | None = None,
                swaps: list[IdentitySwap] | None = None, timeline: bool = True,
                detections_cache: str | os.PathLike | None = None) -> TrackRun:
    """Track the dancers of ``video`` and estimate their 2D poses; write the outputs to ``out_dir``.

    ``boxes``: initial (x, y, w, h) px boxes in the first frame, or None to find ``num_dancers`` people with the
    detector in the first ``init_seconds`` of the video (each starts where it is first seen); ``starts`` gives the
    start frames and boxes directly instead (dancers are numbered in the order they start). ``detect_every``: run
    the detector on every k-th frame only, and on the last frame where the video's length (or ``max_frames``) is
    known (keypoints in between are interpolated). ``detector`` None: boxes only,
    no keypoints. ``zoom_hidden``: on detector frames, while a dancer that started hidden behind another waits to
    come out, the detector also runs on a crop about its box (:func:`zoom_detections`; not for detectors with
    ``supports_crops`` False, such as precomputed OpenPose output). ``zoom_unposed``: on detector frames, a dancer
    seen that no whole-frame person lies on (:func:`unposed_dancers`) is looked for again on a crop about its box
    (``UNPOSED_ZOOM_SIDE`` x its height), and what is found there is offered to Algorithm 2* with the frame's people
    (its pose only: the tracker does not adapt its box to these finds); a dancer whose crop gave it no pose is not
    looked for so again on the next ``UNPOSED_RETRY_AFTER`` detector frames. ``zoom_group`` (on by default since
    session 90: docs/benchmarks.md "Session 90"): on detector frames on which dancers' boxes overlap, or a dancer is
    occluded or waits hidden (:func:`in_a_group`), the detector (not one with ``supports_crops`` False) also runs, at
    its own input size, on a crop about the union of the dancers' boxes (:func:`group_crop`, when that is at most
    ``GROUP_ZOOM_MAX_FRACTION`` of the frame), and the people it finds there that the whole frame missed join the
    frame's weak finds (:func:`group_zoom_detections`): they update dancers followed and may be chosen as poses,
    never find a lost dancer again, and let a waiting one come out only when as tall as her box
    (``MultiTrackerConfig.zoomed_emerge_height``). ``zoom_input_size``: the
    detector's input size (px) on the crops about single dancers, where it can change it (``at_input_size``; None:
    its own). ``hindsight``: once all frames are tracked, fill the boxes of each stretch in which a dancer was
    occluded between where it was seen before and after (:func:`hdvr.tracking.hindsight.fill_occluded`; a
    stretch not seen after it holds the box where the dancer was last seen,
    :func:`hdvr.tracking.hindsight.hold_last_seen`, unless the tracker stopped it behind the dancers in front:
    ``TrackRun.stopped_behind``), widen each box to enclose its dancer's keypoints
    (:func:`hdvr.tracking.hindsight.enclose_keypoints`), lower the top of a box that reaches far above a full pose
    (:func:`hdvr.tracking.hindsight.trim_above_pose`) and smooth the boxes over time
    (:func:`hdvr.tracking.hindsight.smooth_boxes`), all in :func:`hdvr.tracking.hindsight.apply_hindsight`; off, the
    boxes are those of the online tracker. ``amodal_boxes`` (with ``hindsight``): last, move each seen dancer's box
    to the whole body that the learned refiner predicts (:func:`hdvr.tracking.amodal.refine_boxes`), with the
    weights at ``amodal_weights`` (None: the shipped ones; read before tracking starts). ``follow_partner`` (with
    ``hindsight``): in a video of two dancers, carry a partner hidden behind the other (waiting since her start, or
    occluded after being seen) with his box (:func:`hdvr.tracking.hindsight.follow_partner_in_hold`; off for two
    dancers who do not dance in hold).
    ``timeline``:
    also draw ``timeline.png``, each dancer's status, found
    keypoints, corrections and swaps over the frames (:func:`hdvr.tracking.timeline.draw_tracks_timeline`).
    ``detections_cache``: an NPZ file (:mod:`hdvr.pose2d.cache`) from which the detector's people are taken for the
    frames it holds, if it was written for this video and detector settings, and to which those of this run are
    written (with ``write``); the outputs are the same as without it.
    """
    started = time.perf_counter()
    cpu_started = time.process_time()
    if detect_every < 1:
        raise HDVRError(f"--detect-every must be >= 1, got {detect_every}")
    if hindsight and amodal_boxes and amodal_weights:
        load_refiner(amodal_weights)  # a missing or foreign file stops here, not after the whole video
    reader = VideoReader(video)
    info = reader.info
    cache_signature = None
    if detector is not None and detections_cache is not None:
        detector_key = detector_signature(detector)
        if detector_key is not None:
            cache_signature = {"video": video_signature(video, info.size), "detector": detector_key}
            detector = CachingDetector(detector, info.size, load_detections(detections_cache, cache_signature))
    # the last frame to be tracked, where known: the detector runs there too (below), and no start may lie after it
    last = info.num_frames - 1 if info.num_frames else None
    if max_frames:
        last = max_frames - 1 if last is None else min(last, max_frames - 1)
    if starts is not None:
        starts = sorted(starts, key=lambda s: s.frame)  # dancers are numbered in the order they start
        for i, s in enumerate(starts):
            if s.frame < 0:
                raise HDVRError(f"dancer {i} starts at frame {s.frame}: frames are counted from 0")
            if last is not None and s.frame > last:
                raise HDVRError(f"dancer {i} starts at frame {s.frame}, after the last frame tracked ({last})")
    elif boxes is None:
        if detector is None:
            raise HDVRError("give the dancers' boxes (--boxes) or a detector to find them (--dancers N)")
        if not num_dancers or num_dancers < 1:
            raise HDVRError("give --boxes or --dancers N (N >= 1)")
        if max_frames:
            init_seconds = min(init_seconds, max_frames / info.fps)
        starts = find_dancers(video, detector, num_dancers, seconds=init_seconds)
    else:
        starts = [DancerStart(0, tuple(float(v) for v in b)) for b in boxes]
    check_boxes_in_frame([s.box for s in starts], info.size)
    boxes = [s.box for s in starts]
    if not boxes:
        raise HDVRError("no dancer to track")
    corrections = sorted(corrections or [], key=lambda c: c.frame)
    check_corrections(corrections, starts, info.num_frames or None, info.size, has_detector=detector is not None)
    swaps = sorted(swaps or [], key=lambda s: s.frame)
    check_swaps(swaps, starts, info.num_frames or None)
    order = list(range(len(starts)))  # order[j]: the tracker's index of the dancer written as id j (swaps)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    n = len(boxes)
    selector = PoseSelector(n)
    crops = getattr(detector, "supports_crops", True)  # precomputed poses (OpenPose JSON) cannot look again zoomed in
    zoom_hidden, zoom_unposed, zoom_group = zoom_hidden and crops, zoom_unposed and crops, zoom_group and crops
    crop_detector = detector  # the detector on crops about single dancers: smaller input where it allows
    if crops and zoom_input_size and hasattr(detector, "at_input_size"):
        crop_detector = detector.at_input_size(zoom_input_size)
    zoom_retry: dict[int, int] = {}  # tracker index -> first frame to look for it zoomed in again (zoom_unposed)
    all_boxes, all_status, all_conf, all_kp, detected, all_stopped, all_returned = [], [], [], [], [], [], []
    stage = dict.fromkeys(("decode", "detect", "track", "select", "overlay"), 0.0)
    tracker = None
    hidden_starts = []
    failure: BaseException | None = None
    total = last + 1 if info.num_frames else None  # frames to track, for the progress bar (None: unknown)
    frames = iter(reader)
    bar = progress(total=total, desc="track", unit="frame")
    try:
        t = 0
        tic = time.perf_counter()
        for frame in frames:
            stage["decode"] += time.perf_counter() - tic
            # every k-th frame, and the last: the frames after the last k-th one are then interpolated like all
            # others, not left without keypoints (a container that misreports its length only loses that)
            run_detector = detector is not None and (t % detect_every == 0 or t == last)
            people, weak, group_finds = [], [], []
            if run_detector:
                tic = time.perf_counter()
                people = detector.detect(frame, t)
                if zoom_group and tracker is not None and len(tracker.dancers) > 1 and in_a_group(tracker.dancers):
                    crop = group_crop([d.box for d in tracker.dancers if d.status != OUT], info.size)
                    if crop is not None:  # all weak; kept apart from the whole frame's weak finds for the tracker
                        group_finds = group_zoom_detections(detector, frame, t, crop, people)
                weak = [p for p in people if p.weak]  # only for updating dancers followed (see MultiTrackerConfig)
                people = [p for p in people if not p.weak]
                if zoom_hidden and tracker is not None:
                    # a dancer that started hidden and still waits to come out is looked for again, zoomed in; a
                    # find with the colours of a dancer already followed is that dancer, not the waiting one
                    waiting = tracker.waiting()
                    if waiting:
                        others = [d.box for d in tracker.dancers if d.hidden_behind is None and d.status != OUT]
                        finds = zoom_detections(
                            crop_detector, frame, t, [d.box for d in waiting], people, clear_of=others,
                            core_aspect=tracker.config.core_aspect, overlap=tracker.config.overlap_threshold)
                        people = people + [p for p in finds if not tracker.looks_like_a_followed_dancer(frame, p.box)]
                stage["detect"] += time.perf_counter() - tic
            tic = time.perf_counter()
            stepped, handed = None, []
            if tracker is None:
                tracker = MultiDancerTracker(frame, [], config)
            else:
                fronts = [d.hidden_behind for d in tracker.dancers]
                stepped = tracker.step(frame, detections=[p.box for p in people] if run_detector else None,
                                       weak_detections=[p.box for p in weak] if run_detector else None,
                                       zoomed_detections=[p.box for p in group_finds] if run_detector else None)
                # waits handed over to another dancer in front (the one in front walked out of their stack)
                handed = [(k, d.hidden_behind) for k, d in enumerate(tracker.dancers[:len(fronts)])
                          if None not in (d.hidden_behind, fronts[k]) and d.hidden_behind != fronts[k]]
            weak = weak + group_finds  # from here on (poses, corrections) the crop's finds are weak ones like others
            new_ids = [tracker.add_dancer(frame, s.box, [p.box for p in people] if run_detector else None)
                       for s in starts if s.frame == t]
            for swap in swaps:
                if swap.frame == t:
                    order[swap.first], order[swap.second] = order[swap.second], order[swap.first]
            written_id = {k: j for j, k in enumerate(order)}
            for k, front in handed:  # a new wait, which hindsight keeps to as to one from a start
                hidden_starts.append((t, written_id[k], written_id[front]))
            for k in new_ids:
                front = tracker.hiding_dancer(k)
                if front is not None:
                    i, front = written_id[k], written_id[front]  # swapped in its start frame: not its index
                    hidden_starts.append((t, i, front))
                    print(f"hdvr: warning: dancer {i} starts mostly hidden behind dancer {front} (frame {t}): its "
                          f"colours are unknown until it comes out clear of the others, and it may be taken for "
                          f"dancer {front}; check it in the overlay video, and if it is, give it its box in a frame "
                          f"where it is seen clearly (--correct {i}@FRAME:x,y,w,h)", file=sys.stderr)
            corrected = [c for c in corrections if c.frame == t]
            if any(c.point is not None for c in corrected):
                found = people + weak if run_detector else detector.detect(frame, t)  # pointed at: whose box?
                for k, c in enumerate(corrections):
                    if c.frame == t and c.point is not None:
                        box = person_at(found, c.point)
                        if box is None:
                            raise HDVRError(f"correction of dancer {c.dancer} at frame {t}: nobody detected at "
                                            f"({c.point[0]:g}, {c.point[1]:g}); give the box x,y,w,h instead")
                        corrections[k] = replace(c, box=box)
                corrected = [c for c in corrections if c.frame == t]
            for c in corrected:
                tracker.correct(frame, order[c.dancer], c.box, [p.box for p in people] if run_detector else None)
                front = tracker.hiding_dancer(order[c.dancer])
                if front is not None:  # waits behind it again: hindsight keeps it near this offset from it
                    hidden_starts.append((t, c.dancer, written_id[front]))
            # the frame's result from step() holds unless dancers were added or corrected after it
            result = _pad(stepped if stepped is not None and not new_ids and not corrected else tracker.result(), n)
            stage["track"] += time.perf_counter() - tic
            kp = np.full((n, 25, 3), np.nan, np.float32)
            kp[..., 2] = 0
            if run_detector:
                tic = time.perf_counter()
                # poses are chosen by the tracked extent, not by the amodal width guessed for hidden dancers
                not_rivals = np.zeros((n, n), bool)  # padded like the boxes: dancers not started yet are no one's
                k = len(tracker.dancers)
                not_rivals[:k, :k] = tracker.not_pose_rivals()
                yields = np.zeros((n, n), bool)
                yields[:k, :k] = tracker.pose_yields()
                # a dancer seen that no whole-frame person lies on is looked for again, zoomed in, for its pose only
                # (the tracker does not adapt to these finds); after a crop that gave it no pose, not for a while
                zoom_tic = time.perf_counter()  # the detector's time, counted as such
                unposed = [i for i in unposed_dancers(tracker.dancers, people + weak) if t >= zoom_retry.get(i, 0)] \
                    if zoom_unposed else []
                zoomed = zoom_detections(crop_detector, frame, t, [tracker.dancers[i].box for i in unposed],
                                         people + weak, side=UNPOSED_ZOOM_SIDE) if unposed else []
                zoom_seconds = time.perf_counter() - zoom_tic
                stage["detect"] += zoom_seconds
                chosen = selector.select(frame, _pad(tracker.result(widen_hidden=False), n).boxes,
                                         people + weak + zoomed, not_rivals, yields)
                for i, pose in enumerate(chosen):
                    if pose is not None:
                        kp[i] = pose.body25()
                for i in unposed:  # tracker index = selector index
                    if not any(chosen[i] is p for p in zoomed):
                        zoom_retry[i] = t + (UNPOSED_RETRY_AFTER + 1) * detect_every
                if tracker is not None:  # reported boxes reach as far as the poses clearly chosen for them
                    k = len(tracker.dancers)
                    result = _pad(tracker.extend_to_poses(frame, chosen[:k], selector.margins[:k]), n)
                stage["select"] += time.perf_counter() - tic - zoom_seconds
            status = _reported_status(result, tracker)
            all_boxes.append(result.boxes[order])  # rows by written id
            all_status.append(tuple(status[k] for k in order))
            all_conf.append(result.confidence[order])
            stopped = np.zeros(n, bool)  # predicted boxes stopped behind the dancers in front (hindsight keeps them)
            if tracker is not None:
                stopped[:len(tracker.dancers)] = [d.status == OCCLUDED and d.stopped_behind for d in tracker.dancers]
            all_stopped.append(stopped[order])
            returned = np.zeros(n, bool)  # waiting dancers put back behind the dancer in front from the empty floor
            if tracker is not None:
                returned[:len(tracker.dancers)] = [d.hidden_behind is not None and d.returned_behind
                                                   for d in tracker.dancers]
            all_returned.append(returned[order])
            all_kp.append(kp[order])
            detected.append(run_detector)
            t += 1
            bar.update(1)
            if max_frames and t >= max_frames:
                break
            tic = time.perf_counter()
    except (HDVRError, KeyboardInterrupt) as exc:
        failure = exc
    finally:
        bar.close()
    done = min(len(all_boxes), len(all_status), len(all_conf), len(all_kp), len(detected),  # an interrupt may
               len(all_stopped), len(all_returned))  # land mid-frame
    del all_boxes[done:], all_status[done:], all_conf[done:], all_kp[done:], detected[done:], all_stopped[done:]
    del all_returned[done:]
    if not all_boxes:
        if failure is not None:
            raise failure
        raise HDVRError(f"video {video} has no decodable frame")
    run = TrackRun(np.array(all_boxes, float), all_status, np.array(all_conf, float), np.array(all_kp, np.float32),
                   np.array(detected, bool), info.fps, info.size, hidden_starts=hidden_starts,
                   stopped_behind=np.array(all_stopped, bool).reshape(done, n),
                   returned_behind=np.array(all_returned, bool).reshape(done, n))
    run.keypoints = fill_between_detections(run.keypoints, run.detected, detect_every)
    run.filled = np.zeros(run.boxes.shape[:2], bool)
    if hindsight:
        run.boxes, run.filled = apply_hindsight(run.boxes, run.status, run.keypoints, frame_width=info.size[0],
                                                hidden_starts=hidden_starts, stopped_behind=run.stopped_behind,
                                                returned_behind=run.returned_behind,
                                                settings=HindsightSettings(amodal_boxes=amodal_boxes,
                                                                           amodal_weights=str(amodal_weights or ""),
                                                                           follow_partner=follow_partner))
    for c in corrections:  # written as the user gave them (or as found where the user pointed)
        if c.frame < len(run.boxes) and c.box is not None:
            run.boxes[c.frame, c.dancer] = c.box
            run.filled[c.frame, c.dancer] = False
    if write:
        run.outputs += write_outputs(out, run, extra={
            "source": str(video), "detect_every": detect_every, "detector": getattr(detector, "name", None),
            "hindsight": hindsight, "amodal_boxes": hindsight and amodal_boxes,
            "amodal_weights": str(amodal_weights) if hindsight and amodal_boxes and amodal_weights else None,
            "follow_partner": hindsight and follow_partner,
            "starts": [{"frame": st.frame, "box": [float(v) for v in st.box]} for st in starts],
            "hidden_starts": [{"frame": f, "dancer": i, "behind": j} for f, i, j in hidden_starts],
            "corrections": [{"frame": c.frame, "dancer": c.dancer,
                             "box": None if c.box is None else [float(v) for v in c.box],
                             **({} if c.point is None else {"point": [float(v) for v in c.point]})}
                            for c in corrections],
            "swaps": [{"frame": s.frame, "dancers": [s.first, s.second]} for s in swaps]})
        if cache_signature is not None:
            run.outputs.append(save_detections(detections_cache, cache_signature, detector.all_found()))
            run.detections_reused = detector.reused
        if timeline and len(run.boxes):
            tic = time.perf_counter()
            run.outputs.append(draw_tracks_timeline(
                out / "timeline.png", run.status, run.keypoints, run.fps,
                corrections=[(c.frame, c.dancer) for c in corrections if c.frame < len(run.boxes)],
                swaps=[(s.frame, s.first, s.second) for s in swaps if s.frame < len(run.boxes)],
                hidden_starts=hidden_starts, title=f"Tracks of {Path(video).name}"))
            stage["overlay"] += time.perf_counter() - tic  # the pictures: overlay video and timeline
    if overlay and write:  # after the files that matter most
        if isinstance(failure, KeyboardInterrupt):  # stopped by the user: no second pass over the video, and no
            (out / "overlay.mp4").unlink(missing_ok=True)  # overlay of an earlier run beside these tracks
        else:
            tic = time.perf_counter()
            try:
                run.outputs.append(write_overlay(video, out / "overlay.mp4", run))
            except HDVRError as exc:
                raise (failure or HDVRError(f"{exc}; the other outputs were written to {out}")) from exc
            stage["overlay"] += time.perf_counter() - tic
    run.seconds = time.perf_counter() - started
    run.cpu_seconds = time.process_time() - cpu_started
    run.stage_seconds = stage
    if failure is not None:
        raise failure
    if reader.error:
        raise HDVRError(f"{reader.error}; outputs for the {len(all_boxes)} frames decoded were written to {out}")
    return run


def write_overlay(video: str | os.PathLike, path: Path, run: TrackRun) -> Path:
    """Draw ``run``'s boxes, ids and keypoints (as written to the keypoint files) and each frame's number (for
    ``--correct``) on the frames of ``video`` it covers and encode them to H.264 ``path``: a second pass over the
    video, so that the overlay shows the boxes filled with hindsight. Frames that cannot be decoded end the overlay
    early; the frames drawn are kept."""
    frames = run.boxes.shape[0]
    bar = progress(total=frames, desc="overlay", unit="frame")
    try:
        with VideoReader(video) as reader, VideoWriter(path, run.fps, run.size) as writer:
            for t, frame in enumerate(itertools.islice(reader, frames)):
                writer.write(draw_overlay(frame, run.boxes[t], run.status[t], run.keypoints[t], frame_index=t))
                bar.update(1)
    finally:
        bar.close()
    return path


def write_outputs(out: Path, run: TrackRun, extra: dict | None = None) -> list[Path]:
    """Write the per-dancer keypoint NPZ files, MOT text and JSON tracks (all atomically)."""
    paths = []
    for i in range(run.boxes.shape[1]):
        path = out / f"dancer_{i}.npz"
        save_keypoints2d(path, Keypoints2D(run.keypoints[:, i], BODY25_NAMES, run.fps, run.size))
        paths.append(path)
    write_mot(out / "tracks.mot.txt", run.boxes, run.confidence)
    extra = dict(extra or {})
    if run.filled is not None:
        extra["filled_with_hindsight"] = [[int(t) for t in np.flatnonzero(run.filled[:, i])]
                                          for i in range(run.boxes.shape[1])]
    write_tracks_json(out / "tracks.json", run.boxes, run.status, run.fps, run.size, run.confidence, extra)
    paths += [out / "tracks.mot.txt", out / "tracks.json"]
    return paths


def tracked_fraction(run: TrackRun) -> np.ndarray:
    """(N,) fraction of frames in which each dancer was seen (status "tracked": not predicted or filled through an
    occlusion, nor waiting hidden behind another since its start)."""
    return np.array([[s[i] == TRACKED for s in run.status] for i in range(run.boxes.shape[1])]).mean(axis=1)
