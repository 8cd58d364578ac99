"""State of Algorithm 1*: one dancer's track, one frame's result, and the box helpers the tracker's modules share.

Boxes are (x, y, w, h) pixels, top-left corner; velocities px/frame; frames are 0-based indices.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hdvr.tracking.appearance import box_overlap, colour_histogram, histogram_similarity
from hdvr.tracking.ldes import LDESTracker

TRACKED, OCCLUDED, OUT = "tracked", "occluded", "out"
HIDDEN = "hidden"  # written (not a tracker state) for a dancer that waits hidden behind another since its start


@dataclass
class DancerTrack:
    """State of one dancer in Algorithm 1*."""

    dancer_id: int
    tracker: LDESTracker
    box: tuple[float, float, float, float]
    status: str = TRACKED
    stored_histogram: np.ndarray | None = None
    stored_velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    stored_box: tuple[float, float, float, float] | None = None  # last box seen clear of others (from the frame
    # it is occluded on, with the size its box had then: ``MultiTrackerConfig.occluded_keeps_size``)
    stored_frame: int = 0  # frame of stored_box
    occlusion_end: int = -1  # predicted frame where the overlap ends
    occluded_since: int = -1
    centers: list = field(default_factory=list)  # recent centres (px), newest last
    missed: int = 0  # detector frames in a row in which no person was detected on this dancer's box
    clear_track: list = field(default_factory=list)  # (frame, centre) of recent frames clear of others
    confidence: float = 1.0
    offset: np.ndarray = field(default_factory=lambda: np.zeros(2))  # box centre - tracker centre, px
    recovering_until: int = -1  # frame until which a dancer recovered after being long lost follows detections
    size_ratio: np.ndarray | None = None  # (w, h) of the dancer's box / of the detector's box on it
    ratio_samples: list = field(default_factory=list)  # ratios taken so far while the ratio is learned after the
    # start frame (:meth:`hdvr.tracking.multi.MultiDancerTracker._learn_late_ratio`); empty once it is learned
    ratio_box: np.ndarray | None = None  # (w, h) px of the box those ratios are taken against
    ratio_aspect: float | None = None  # width over height of the detection in the start (or correction) frame that
    # ``size_ratio`` was learned from; None when it was learned later (no width margin then: ``width_margin``)
    ratio_since: int = -1  # frame of the first of them
    start_frame: int = 0  # frame in which tracking of this dancer began
    exit_side: str | None = None  # "left" or "right": the frame edge the dancer left by (None: another or none)
    growth: np.ndarray = field(default_factory=lambda: np.zeros(4))  # px the reported box extends beyond ``box``
    # on the left, top, right and bottom (:meth:`hdvr.tracking.extent.ReportedExtent.extend_to_poses`)
    hidden_aspect: float | None = None  # width / height of its box when a detection on it first ended, on a side, on
    # a dancer in front (``MultiTrackerConfig.keep_hidden_sides`` "written"); None when the last one did not
    hidden_sides: tuple[bool, bool] = (False, False)  # which sides (left, right) of that detection did
    last_status: str = TRACKED  # status in the frame before
    adapted_at: int = -1  # last frame in which the box adapted to a detection while clear
    stuck: int = 0  # detector frames in a row in which the one person on its clear box was too far off to adapt it
    edge_empty_score: float = 1.0  # lowest histogram similarity of the edge strip to the memory since it left
    detected_at_edge: str | None = None  # "left" or "right": the last detection on the box was cut by that edge
    detected_clear_at: int = -1  # last detector frame in which a person was detected on its box while it was clear
    found_streak: int = 0  # detector frames in a row, while clear, with a person detected on its box
    stopped_behind: bool = False  # occluded, its predicted box was stopped behind the dancers in front
    # (``MultiTrackerConfig.hold_uncovered_prediction``) and stays there until it is found again
    returned_behind: bool = False  # waiting behind another since its start, occluded, and put back behind that
    # dancer at least once because its box lay clear of everyone on the floor or wall
    # (``MultiTrackerConfig.waiting_empty_behind``): the place it was left at showed nobody
    out_unseen: bool = False  # out of the frame because its predicted box left it while occluded (not seen leaving)
    lost_candidate: tuple | None = None  # while occluded long: the box (px) the whole-frame search last found it at
    # (:meth:`hdvr.tracking.multi.MultiDancerTracker._search_lost`), and on how many searches in a row there
    lost_streak: int = 0
    behind_stranger: bool = False  # occluded behind a person nobody tracks (``MultiTrackerConfig.stranger_in_front``):
    # that person's path is unknown, so the dancer is looked for by re-identification, not relocated when its box
    # lies clear of the dancers followed
    lost_on_background: bool = False  # occluded because its tracker drifted onto the background (its box held
    # no person nor foreground: ``MultiTrackerConfig.lost_max_foreground``); until it is taken again, its own
    # tracker's box is no candidate
    cover_path: list = field(default_factory=list)  # while occluded: (fraction of its core covered, predicted box px)
    # of the predicted boxes within ``hdvr.tracking.multi.COVER_TIE`` of the best cover so far
    # detections half beside the dancers in front that a dancer waiting behind them could come out on
    # (``MultiTrackerConfig.emerge_beside_persist``), as (box px, detector frames in a row one lay there):
    beside_now: list = field(default_factory=list)  # in its latest detector frame, ``beside_frame``
    beside_before: list = field(default_factory=list)  # in the detector frame before that
    beside_frame: int = -1
    hidden_behind: int | None = None  # id of the dancer it started mostly hidden behind: its stored colours are
    # that dancer's until it comes out (:meth:`hdvr.tracking.multi.MultiDancerTracker._emerge`); then None
    wait_offset: tuple[float, float] | None = None  # while ``hidden_behind``: where its box stood when it began to
    # wait, relative to that dancer's box: (centre x, bottom y) offsets in its own box heights (positive: right, down)
    start_partners: frozenset = frozenset()  # ids of the dancers whose body core overlapped this one's when either
    # started (:meth:`hdvr.tracking.multi.MultiDancerTracker.add_dancer`); exactly one: a couple in hold
    # (:meth:`hdvr.tracking.multi.MultiDancerTracker._couple_in_hold`)
    velocity_measured: bool = False  # its clear track has spanned ``min_velocity_span`` frames at least once
    group_reference: tuple[float, float, bool] | None = None  # (height of its detection, of its box) px when its
    # group's scale was first measured, and whether that detection was one shared by the group
    # (:meth:`hdvr.tracking.multi.MultiDancerTracker._scale_groups`); None while clear
    reshape_streak: int = 0  # detector frames in a row in which its detection showed an upright person while its
    # box had a floor shape and it overlapped others (:meth:`hdvr.tracking.multi.MultiDancerTracker._reshape_in_group`)

    @property
    def body_center(self) -> np.ndarray:
        """Centre (px) of the tracker's body core: motion is measured on it (the box centre also moves when the
        box adapts to a detection)."""
        return np.asarray(self.tracker.center, float)

    @property
    def recent_motion(self) -> np.ndarray:
        """Mean motion (px/frame) of the body core over the recent centres ``centers``; zero with fewer than 2."""
        if len(self.centers) < 2:
            return np.zeros(2)
        return (self.centers[-1] - self.centers[0]) / (len(self.centers) - 1)

    @property
    def center(self) -> np.ndarray:
        x, y, w, h = self.box
        return np.array([x + w / 2, y + h / 2])

    def memory_match(self, frame_bgr: np.ndarray, box=None, shrink: float | tuple[float, float] = 0.15) -> float:
        """How well the colours inside ``box`` (x, y, w, h px; default the dancer's own box, shrunk by ``shrink`` as
        :func:`hdvr.tracking.appearance.colour_histogram` does) of a BGR frame match the dancer's stored histogram:
        correlation in [-1, 1], -1 where either histogram is missing."""
        return histogram_similarity(colour_histogram(frame_bgr, self.box if box is None else box, shrink),
                                    self.stored_histogram)


@dataclass(frozen=True)
class FrameResult:
    """Boxes of all dancers in one frame."""

    frame_index: int
    boxes: np.ndarray  # (N, 4) float: x, y, w, h px
    status: tuple[str, ...]  # per dancer: "tracked", "occluded" (box predicted, not seen) or "out" (of the frame)
    confidence: np.ndarray  # (N,) float in [0, 1]


def box_at(centre, box) -> tuple[float, float, float, float]:
    """A box of ``box``'s size centred at ``centre`` (px)."""
    return (float(centre[0]) - box[2] / 2, float(centre[1]) - box[3] / 2, box[2], box[3])


def box_centre(box) -> np.ndarray:
    """Centre (x, y) px of an (x, y, w, h) box."""
    return np.array([box[0] + box[2] / 2, box[1] + box[3] / 2], float)


#: how wide a dancer's body core is at most, in its box heights (spread arms left out): the default of
#: ``MultiTrackerConfig.core_aspect``, and the one hindsight and the zoomed-in detections test overlaps with
BODY_CORE_ASPECT = 0.3


def body_core(box, aspect: float) -> tuple[float, float, float, float]:
    """The body core of an (x, y, w, h) px box: centred, at most ``aspect`` x its height wide (spread arms left
    out); overlaps between dancers are tested on it."""
    w = min(box[2], aspect * box[3])
    return (box[0] + (box[2] - w) / 2, box[1], w, box[3])


def covered_fraction(box, fronts, aspect: float, samples: int = 12) -> float:
    """The fraction of the body core of ``box`` (x, y, w, h px; :func:`body_core` with ``aspect``) inside the body
    cores of the boxes ``fronts`` (K x 4 px; rows with NaN are left out), sampled on a ``samples`` x 2 ``samples``
    grid; 0 without fronts."""
    fronts = np.asarray(fronts, float).reshape(-1, 4)
    fronts = fronts[np.isfinite(fronts).all(axis=1)]
    if not len(fronts):
        return 0.0
    cores = np.array([body_core(f, aspect) for f in fronts])
    x, y, w, h = body_core(box, aspect)
    xs = x + (np.arange(samples) + 0.5) / samples * w
    ys = y + (np.arange(2 * samples) + 0.5) / (2 * samples) * h
    px, py = (a.ravel()[:, None] for a in np.meshgrid(xs, ys))
    inside = (px >= cores[:, 0]) & (px <= cores[:, 0] + cores[:, 2]) & \
        (py >= cores[:, 1]) & (py <= cores[:, 1] + cores[:, 3])
    return float(inside.any(axis=1).mean())


def stands_in_front(front, behind, margin: float) -> bool:
    """Whether the person in (x, y, w, h) px box ``front`` stands in front of the one in ``behind``: its box bottom
    is ``margin`` x ``behind``'s height lower in the image (the floor rises towards the horizon)."""
    return front[1] + front[3] > behind[1] + behind[3] + margin * behind[3]


def straight_in_front(front, behind, aspect: float, overlap: float, margin: float) -> bool:
    """Whether the person in (x, y, w, h) px box ``front`` stands straight in front of the one in ``behind``: their
    body cores (:func:`body_core` with ``aspect``) overlap by more than ``overlap`` (intersection / smaller) and
    ``front`` stands in front (:func:`stands_in_front` with ``margin``)."""
    return box_overlap(body_core(front, aspect), body_core(behind, aspect)) > overlap and \
        stands_in_front(front, behind, margin)
