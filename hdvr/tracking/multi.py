"""Algorithm 1* of the paper: N dancers tracked through mutual occlusion.

Each dancer has its own LDES-style tracker (:mod:`hdvr.tracking.ldes`), run on the dancer's *body core* (the
central strip of its box, at most ``core_aspect`` x its height wide); overlaps between dancers are tested on the
cores too, so spread arms do not count. Per frame:

1. every dancer that is being tracked is moved by its tracker; while it overlaps no other dancer its colour
   histogram and velocity are stored (the appearance and motion memory), and its tracker learns;
2. while it overlaps another dancer the tracker does not learn; a *tracking failure* shows as a sudden change of
   motion (direction turned by more than ``failure_angle_deg``, a stall or a jump; a dancer with no stored
   velocity, e.g. one that has overlapped others since it started, fails by moving off only when it moves like a
   dancer it overlaps or its box no longer looks much like it: its tracker is being dragged along; no motion test
   for a dancer standing in front of every dancer it overlaps, ``front_keeps_motion``) or as a histogram that no
   longer matches the stored one;
3. on a failure the dancer is *occluded*: its box moves on with the stored velocity, and the frame where the
   overlap will end is predicted from the stored velocities of the dancers involved;
4. occluded dancers that show clearly again (own tracker or a detection clear of every tracked dancer, matching
   the memory well and better than any other occluded dancer's) are re-identified at once, best matches first;
5. from the predicted end of the overlap on, the dancer is *relocated*: candidate patches (the stored box size)
   are laid out in a cone along the stored motion direction, plus any person detections inside the cone; the
   candidate whose histogram correlates best with the stored one takes the dancer, and tracking resumes there;
6. an occluded dancer that neither finds takes a *stray person* wherever it is: a detection that no tracked dancer
   takes, clear of all of them, seen on several detector frames in a row, whose colours match its memory
   (:meth:`MultiDancerTracker._take_stray`).

When person detections are given (``step(frame, detections)``), only those that can be one dancer alone count
(body core clear of the other dancers, plausible height; a dancer that others wait straight behind since their
start, hidden, counts as clear of them, but its box adapts only its height). The box of a clear dancer adapts its
size and centre to the one detection on it; the boxes of dancers overlapping one another scale together when their
detections grow or shrink alike (:meth:`MultiDancerTracker._scale_groups`). A clear dancer whose box has held no
detected person for ``max_missed_detections`` detector frames in a row may have lost its dancer (e.g. in a jump):
if a detected person nearby, tracked by no one, matches its stored histogram clearly better than its box does (and
better than any other dancer's, ``jump_rivals``), the dancer moves there and its tracker restarts; after
``long_lost_detections`` such frames the box's own match no longer counts (unless the box still shows someone,
``lost_max_foreground``), and the recovered box follows the detections for ``recovery_frames``. When no detected
person takes it back and its box shows (almost) no foreground, its tracker drifted onto the background: the dancer
is lost there and looked for like an occluded one.
Its stored histogram is only updated on frames where no detection is missing on its box.

After Algorithm 2* has chosen each dancer's pose on a detector frame, the *reported* box may reach beyond the
tracked one (spread arms, a raised leg): :mod:`hdvr.tracking.extent` (a mixin of this tracker). The tracking itself
does not use these extents.

The tracker is one class built from one module per concept: this module holds the per-frame loop (:meth:`step`),
starting, correcting and histogram memory; its parameters are :class:`hdvr.tracking.config.MultiTrackerConfig`
(imported here too); mixins add the rest: :mod:`hdvr.tracking.adaptation` (a box adapted to its detection, the
foreground mask), :mod:`hdvr.tracking.occlusion` (steps 2, 3 and 5: failure tests, occlusion, prediction, cone
relocation), :mod:`hdvr.tracking.groups` (overlapping dancers adapted together), :mod:`hdvr.tracking.emergence`
(dancers waiting hidden coming out), :mod:`hdvr.tracking.reidentification` (steps 4 and 6, lost dancers found
again), :mod:`hdvr.tracking.edges` (leaving and re-entering the frame) and :mod:`hdvr.tracking.extent` (the
reported box); :mod:`hdvr.tracking.geometry` has the box helpers.

A dancer whose box leaves the frame is *out* (no box) until it comes back: on a detection, or without one on the
strip at the left or right edge it left by, when that strip matches its memory clearly better than the empty edge
did (:meth:`MultiDancerTracker._reenter_at_edge`).

Dancers may start later than the first frame (:meth:`MultiDancerTracker.add_dancer`).

Boxes are (x, y, w, h) pixels, top-left corner; velocities px/frame; frames are 0-based indices.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.adaptation import DetectionAdaptation
from hdvr.tracking.appearance import box_iou, box_overlap, clip_box, colour_histogram, histogram_similarity
from hdvr.tracking.config import MultiTrackerConfig
from hdvr.tracking.edges import FrameEdges
from hdvr.tracking.emergence import Emergence
from hdvr.tracking.extent import ReportedExtent
from hdvr.tracking.geometry import box_behind, height_within, offset_behind
from hdvr.tracking.groups import GroupAdaptation
from hdvr.tracking.ldes import LDESTracker
from hdvr.tracking.occlusion import OcclusionHandling
from hdvr.tracking.reidentification import Reidentification
from hdvr.tracking.state import OCCLUDED, OUT, TRACKED, DancerTrack, FrameResult, body_core, box_at

#: fraction of a dancer's box height left out at its top and at its bottom in the dancers' colour histograms
HISTOGRAM_END_SHRINK = 0.15
#: covers of an occluded dancer's predicted boxes within this of the best are as well hidden
#: (``MultiTrackerConfig.hold_uncovered_prediction``: it stops at the middle of those boxes)
COVER_TIE = 0.05


class MultiDancerTracker(DetectionAdaptation, OcclusionHandling, GroupAdaptation, Emergence, Reidentification,
                         FrameEdges, ReportedExtent):
    """Track N dancers from their boxes in the first frame. Call :meth:`step` with each following frame."""

    def __init__(self, frame: np.ndarray, boxes, config: MultiTrackerConfig | None = None):
        self.config = config or MultiTrackerConfig()
        self.frame_size = (frame.shape[1], frame.shape[0])
        self.frame_index = 0
        # the latest frame with detections (sure, weak or none found) and the one before it (-1: none yet)
        self.detector_frame, self.previous_detector_frame = -1, -1
        self.given_detections = False  # a detector runs: detections (found or not) were given in some frame
        self.dancers: list[DancerTrack] = []
        self._foreground_cache = None  # :meth:`_foreground`
        self.strays: list[tuple[tuple, int]] = []  # :meth:`_stray_people`: (box px, detector frames in a row)
        self.unclaimed: list[tuple[tuple, int]] = []  # ... the same for every detection no tracked dancer takes
        for b in boxes:
            self.add_dancer(frame, b)

    def add_dancer(self, frame: np.ndarray, box, detections=None) -> int:
        """Start tracking a dancer at ``box`` = (x, y, w, h) px in ``frame`` (the current frame); returns its id.
        ``detections``: person boxes in this frame; the one on ``box`` (IoU > 0.5) gives the ratio of the
        dancer's box to the detector's, kept when the box size adapts to later detections. With
        ``start_ratio_alone``, not for a box whose body core overlaps another dancer's (nor for that dancer, if it
        started in this frame too): the ratio is then learned from the first detection while clear."""
        b = tuple(float(v) for v in box)
        self.given_detections |= detections is not None
        tracker = LDESTracker(frame, self._core(b), self.config.ldes)
        d = DancerTrack(len(self.dancers), tracker, b, stored_box=b, stored_frame=self.frame_index,
                        start_frame=self.frame_index)
        d.stored_histogram = self._histogram(frame, b)
        partners = [o for o in self.dancers if o.status != OUT
                    and self._bodies_overlap(b, o.box) > self.config.overlap_threshold]
        d.start_partners = frozenset(o.dancer_id for o in partners)
        for o in partners:  # symmetric: a dancer starting on one already tracked is its partner too
            o.start_partners = o.start_partners | {d.dancer_id}
        stacked = partners if self.config.start_ratio_alone else []
        for o in stacked:  # started in this frame beside this one: neither's start detection is certain
            if o.start_frame == self.frame_index:
                o.size_ratio = None
        # in a stack the ratio is learned later, from a detection while clear (:meth:`_adapt_box`)
        if not stacked:
            d.size_ratio, d.ratio_aspect = self._ratio_to_detection(b, detections)
        d.centers.append(d.body_center)
        for o in self.dancers:  # the new dancer behind one, or one started in this frame behind the new one
            if o.status == OUT:
                continue
            if d.hidden_behind is None and self._straight_in_front(o, d, self.config.hidden_start_overlap):
                d.hidden_behind = o.dancer_id
            if o.hidden_behind is None and o.start_frame == self.frame_index and \
                    self._straight_in_front(d, o, self.config.hidden_start_overlap):
                o.hidden_behind = d.dancer_id
        everyone = self.dancers + [d]
        for o in everyone:  # where each dancer that began to wait here stands behind its front dancer
            if o.hidden_behind is not None and o.start_frame == self.frame_index:
                o.wait_offset = offset_behind(o.box, everyone[o.hidden_behind].box)
        if self.config.start_seen_iou and detections:
            for o in everyone:  # the new dancer, or one started in this frame that the new one hides
                if o.hidden_behind is not None and o.start_frame == self.frame_index:
                    self._seen_at_start(frame, o, everyone, detections)
        self.dancers.append(d)
        return d.dancer_id

    def correct(self, frame: np.ndarray, i: int, box, detections=None) -> None:
        """A user's correction: dancer ``i`` is at ``box`` = (x, y, w, h) px in ``frame`` (the current frame,
        already stepped). Its tracker restarts there, seen (``tracked``), as at a start: its velocity and box growth
        forgotten (they may be another dancer's); with ``correction_waits_behind``, a box straight behind another
        dancer waits hidden behind that dancer (:meth:`hiding_dancer`), else it no longer waits behind anyone and
        learns its colours again from the box outside the body cores of the dancers it overlaps (kept where nothing
        of the box is left). ``detections``: person boxes in this frame; one on the box (IoU > 0.5) gives the ratio
        of the dancer's box to the detector's, as at a start. The other dancers are left as they are: after an
        identity switch, correct each dancer involved."""
        if not 0 <= i < len(self.dancers):
            raise IndexError(f"no dancer {i}: {len(self.dancers)} started")
        d = self.dancers[i]
        b = tuple(float(v) for v in box)
        self.given_detections |= detections is not None
        self._restart(d, frame, b, 1.0)
        d.status = d.last_status = TRACKED
        d.hidden_behind, d.returned_behind = None, False  # a wait behind another starting here is a new one
        d.occlusion_end = d.occluded_since = d.recovering_until = -1
        d.stored_velocity, d.velocity_measured = np.zeros(2), False
        d.growth = np.zeros(4)
        d.exit_side, d.edge_empty_score = None, 1.0
        d.beside_now, d.beside_before, d.beside_frame = [], [], -1
        d.group_reference, d.reshape_streak = None, 0
        d.adapted_at = self.frame_index
        others = [o for o in self.dancers if o is not d and o.status != OUT
                  and self._bodies_overlap(b, o.box) > self.config.overlap_threshold]
        if self.config.correction_waits_behind:  # as at a start (:meth:`add_dancer`)
            front = [o for o in others if o.hidden_behind is None
                     and self._straight_in_front(o, d, self.config.hidden_start_overlap)]
            if front:
                d.hidden_behind = front[0].dancer_id
                d.wait_offset = offset_behind(d.box, front[0].box)
        # colours of the dancers overlapping it left out (a dancer that waits keeps those of its whole box, as at a
        # start: its emergence tests expect the front dancer's)
        mask = self._outside_cores(frame, others) if others and d.hidden_behind is None else None
        hist = self._histogram(frame, b, mask)
        if hist is not None:
            d.stored_histogram = hist
        # over others the ratio is learned again from a detection while clear (:meth:`_adapt_box`)
        d.size_ratio, d.ratio_aspect = (None, None) if others else self._ratio_to_detection(b, detections)
        d.ratio_samples = []  # a ratio being learned was the uncorrected box's

    def _ratio_to_detection(self, box, detections) -> tuple[np.ndarray | None, float | None]:
        """:meth:`_size_ratio` of ``box`` to the one of ``detections`` ((x, y, w, h) px) on it (IoU > 0.5, the
        best) and that detection's width over its height, or (None, None) where none is."""
        ious = [box_iou(box, det) for det in detections or []]
        if not ious or max(ious) <= 0.5:
            return None, None
        det = np.array(detections[int(np.argmax(ious))][2:], float)
        return self._size_ratio(np.array(box[2:]), det), float(det[0] / det[1])

    def _box_size(self, d: DancerTrack, detected, cut: bool = False) -> np.ndarray:
        """(w, h) px of dancer ``d``'s box for a detection of size ``detected`` (w, h px): times its learned ratio
        (``size_ratio``; 1 while none), or with ``width_margin`` the width plus the start box's margin beyond its
        detection's width, in detection heights. ``cut``: the detection is cut by the frame's left or right edge
        (its width is not the dancer's): times the ratio."""
        detected = np.asarray(detected, float)
        if d.size_ratio is None:
            return detected.copy()
        size = d.size_ratio * detected
        if self.config.width_margin and d.ratio_aspect is not None and not cut:
            size[0] = detected[0] + (d.size_ratio[0] - 1.0) * d.ratio_aspect * detected[1]
        return size

    def _detected_size(self, d: DancerTrack, detection) -> np.ndarray:
        """(w, h) px of dancer ``d``'s box for ``detection`` (x, y, w, h px): :meth:`_box_size`, the detection cut by
        the frame's left or right edge or not (:meth:`_cut_by_edge`)."""
        return self._box_size(d, detection[2:], self._cut_by_edge([detection]) is not None)

    def _outside_cores(self, frame, dancers: list[DancerTrack]) -> np.ndarray:
        """uint8 mask of ``frame``: 255 except on the body cores of ``dancers`` (0), to take a histogram of what
        lies outside them."""
        mask = np.full(frame.shape[:2], 255, np.uint8)
        for o in dancers:
            core = clip_box(self._core(o.box), (frame.shape[1], frame.shape[0]))
            if core is not None:
                x0, y0, x1, y1 = core
                mask[y0:y1, x0:x1] = 0
        return mask

    def _seen_at_start(self, frame, d: DancerTrack, everyone: list[DancerTrack], detections) -> None:
        """Dancer ``d``, starting mostly behind dancer ``d.hidden_behind``, does not wait to come out when one of
        ``detections`` ((x, y, w, h) px) shows it at its start (``start_seen_iou``): it learns its colours from its
        start box outside the front dancer's body core. ``everyone``: all dancers started, ``d`` included."""
        c = self.config
        front = everyone[d.hidden_behind]

        def shows_d(det) -> bool:
            iou = box_iou(d.box, det)
            return (iou >= c.start_seen_iou and height_within(det, d.box, c.max_height_change)
                    and not self._wider_than(det, d, c.start_seen_aspect)
                    and all(box_iou(o.box, det) <= iou - c.start_seen_margin for o in everyone if o is not d))

        if sum(shows_d(det) for det in detections) != 1:
            return
        hist = self._histogram(frame, d.box, self._outside_cores(frame, [front]))
        if hist is not None and histogram_similarity(hist, front.stored_histogram) < c.reid_similarity:
            d.hidden_behind, d.stored_histogram = None, hist

    def hiding_dancer(self, i: int) -> int | None:
        """The id of the dancer that dancer ``i`` started mostly hidden behind (standing in front of it,
        :meth:`_straight_in_front`, its body core covering more than ``hidden_start_overlap`` of ``i``'s), while
        ``i`` still waits to come out from behind it (``hidden_behind``, :meth:`_emerge`); else None. Asked right
        after :meth:`add_dancer`: Algorithm 1* stores the histogram of the start box, which then shows the dancer
        in front, and ``i`` may be taken for it."""
        return self.dancers[i].hidden_behind

    def waiting_behind(self) -> np.ndarray:
        """(N, N) bool, True at [i, j] where dancer j, in the frame, still waits hidden behind dancer i since its
        start (``hidden_behind``)."""
        out = np.zeros((len(self.dancers),) * 2, bool)
        for d in self.waiting():
            out[d.hidden_behind, d.dancer_id] = True
        return out

    def not_pose_rivals(self) -> np.ndarray:
        """:meth:`waiting_behind` with ``waiting_not_rival`` (else all False): j's colours are then i's, so j
        matching a pose says nothing against its being i's, and j is left out of i's selection margin
        (:class:`hdvr.pose2d.selection.PoseSelector`)."""
        return self.waiting_behind() & self.config.waiting_not_rival

    def pose_yields(self) -> np.ndarray:
        """:meth:`waiting_behind` with ``waiting_yields_pose`` (else all False): j gives way to i for a pose that
        fits i's box about as well as its own (:class:`hdvr.pose2d.selection.PoseSelector`, ``yields``)."""
        return self.waiting_behind() & self.config.waiting_yields_pose

    def waiting(self) -> list[DancerTrack]:
        """Dancers in the frame that started mostly hidden behind another and have not come out yet
        (``hidden_behind``)."""
        return [d for d in self.dancers if d.hidden_behind is not None and d.status != OUT]

    @property
    def _histogram_shrink(self) -> tuple[float, float]:
        """(left and right, top and bottom) fractions of a box left out of the colour histograms of dancers."""
        return self.config.histogram_side_shrink, HISTOGRAM_END_SHRINK

    def _histogram(self, frame, box, mask=None):
        """Colour histogram of ``box`` (x, y, w, h px) as the dancers' memories are made
        (:func:`hdvr.tracking.appearance.colour_histogram` with :attr:`_histogram_shrink`, within ``mask``)."""
        return colour_histogram(frame, box, self._histogram_shrink, mask)

    def _memory_match(self, d: DancerTrack, frame, box=None) -> float:
        """:meth:`DancerTrack.memory_match` of dancer ``d`` (on ``box``, default its own), its histogram made as
        the memories are (:meth:`_histogram`)."""
        return d.memory_match(frame, box, self._histogram_shrink)

    def looks_like_a_followed_dancer(self, frame, box) -> bool:
        """Whether the colours in ``box`` ((x, y, w, h) px) match at least ``reid_similarity`` the memory of a
        dancer in the frame that shows its own colours (one not waiting behind another: a waiting dancer's memory
        shows the dancer in front). A person found by zooming in about a waiting dancer that does is most likely
        that dancer, whose box has slipped off it, not the waiting one coming out (hdvr synth: 0.69-0.92 on three
        such finds in seeds 7, 11 and 97, 0.23-0.34 on the two that were the waiting dancer)."""
        hist = self._histogram(frame, box)
        return hist is not None and any(
            histogram_similarity(hist, d.stored_histogram) >= self.config.reid_similarity
            for d in self.dancers if d.hidden_behind is None and d.status != OUT and d.stored_histogram is not None)

    def result(self, widen_hidden: bool = True) -> FrameResult:
        """Boxes of this frame, clipped to the frame (px); NaN for dancers out of the frame. ``widen_hidden``: the
        boxes of hidden dancers at their amodal width (:meth:`_widen_hidden`), as written; off, the boxes Algorithm
        2* selects poses by."""
        if not self.dancers:
            return FrameResult(self.frame_index, np.zeros((0, 4)), (), np.zeros(0))
        boxes = np.array([self._reported(d) if d.status != OUT else (np.nan,) * 4 for d in self.dancers], float)
        if widen_hidden and self.config.hidden_min_aspect > 0:
            boxes = self._widen_hidden(boxes)
        boxes = np.array([self._clipped(b) if np.isfinite(b).all() else b for b in boxes], float)
        return FrameResult(self.frame_index, boxes, tuple(d.status for d in self.dancers),
                           np.array([d.confidence if d.status != OUT else 0.0 for d in self.dancers], float))

    def _clipped(self, box) -> tuple[float, float, float, float]:
        """The part of ``box`` inside the frame (px); the box itself if nothing of it is inside."""
        w, h = self.frame_size
        x0, y0 = max(box[0], 0.0), max(box[1], 0.0)
        x1, y1 = min(box[0] + box[2], float(w)), min(box[1] + box[3], float(h))
        if x1 - x0 < 1 or y1 - y0 < 1:
            return tuple(float(v) for v in box)
        return (x0, y0, x1 - x0, y1 - y0)

    def _inside_fraction(self, box) -> float:
        """Fraction of ``box``'s area inside the frame."""
        w, h = self.frame_size
        ix = max(0.0, min(box[0] + box[2], w) - max(box[0], 0.0))
        iy = max(0.0, min(box[1] + box[3], h) - max(box[1], 0.0))
        return ix * iy / (box[2] * box[3]) if box[2] * box[3] > 0 else 0.0

    # ------------------------------------------------------------------ helpers
    def _core(self, box):
        """The body core of a box: centred, at most ``core_aspect`` x its height wide (spread arms left out)."""
        return body_core(box, self.config.core_aspect)

    def _bodies_overlap(self, a, b) -> float:
        return box_overlap(self._core(a), self._core(b))

    def _overlapping(self, i: int, boxes) -> list[int]:
        """Indices of the dancers (in the frame) whose body core in ``boxes`` overlaps dancer ``i``'s."""
        return [j for j in range(len(boxes)) if j != i and self.dancers[j].status != OUT
                and self._bodies_overlap(boxes[i], boxes[j]) > self.config.overlap_threshold]

    def _boxes_now(self, dancers: list[DancerTrack]) -> list:
        """Where each of ``dancers`` is in this frame, (x, y, w, h px): its box if tracked, else its predicted box."""
        return [d.box if d.status == TRACKED else self._predicted_box(d, self.frame_index) for d in dancers]

    # --------------------------------------------------------------------- step
    def step(self, frame: np.ndarray, detections=None, weak_detections=None, zoomed_detections=None) -> FrameResult:
        """Track all dancers into the next frame. ``detections``: optional person boxes (x, y, w, h) px in this
        frame, used as extra relocation candidates; ``weak_detections``: boxes the detector is less sure of, used
        only to update dancers followed and to let a dancer that starts hidden come out
        (``MultiTrackerConfig.weak_detections``); ``zoomed_detections``: boxes found on a crop about a group of
        dancers (:func:`hdvr.tracking.pipeline.group_zoom_detections`), used as weak ones, but to let a dancer that
        starts hidden come out only when as tall as her box (``MultiTrackerConfig.zoomed_emerge_height``): zoomed
        in, the detector also draws parts of people, and a sliver of a dancer peeking out from behind another would
        become her whole box."""
        c = self.config
        # weak detections come second: for a dancer followed that no sure detection updates (as in ByteTrack)
        use_weak = detections is not None and c.weak_detections
        emerging = list(weak_detections) if use_weak and weak_detections else []
        zoomed = list(zoomed_detections) if use_weak and zoomed_detections else []
        waiting = [d.box for d in self.dancers if d.hidden_behind is not None]  # boxes as of the frame before
        whole = [z for z in zoomed if any(box_overlap(z, w) > 0.5 and z[3] >= c.zoomed_emerge_height * w[3]
                                          for w in waiting)]
        emerging += whole
        weak = emerging + [z for z in zoomed if z not in whole]
        self.frame_index += 1
        t = self.frame_index
        if detections is not None:
            self._count_detector_frame()
            self.given_detections = True
        prev_boxes = [d.box for d in self.dancers]
        # 1. move tracked dancers; learn only those that were clear of the others
        for i, d in enumerate(self.dancers):
            if d.status != TRACKED:
                continue
            # partly out of the frame the tracker does not learn either (a dancer walking out would leave it with a
            # template of the background there)
            clear = not self._overlapping(i, prev_boxes) and self._inside_fraction(d.box) >= c.learn_inside
            state = d.tracker.update(frame, learn=clear)
            d.box = box_at(np.asarray(state.center) + d.offset, d.box)
            d.confidence = float(np.clip(state.confidence / 20.0, 0, 1))
            d.centers = (d.centers + [d.body_center])[-(c.motion_window + 1):]
        boxes = [d.box for d in self.dancers]
        # 2. memory update or failure test
        group = []  # tracked dancers overlapping others
        for i, d in enumerate(self.dancers):
            if d.status != TRACKED:
                continue
            overlapping = self._overlapping(i, self._boxes_now(self.dancers))
            # dancers waiting hidden straight behind it since their start show nothing of theirs
            alone = [j for j in overlapping if not self._clear_of_waiting(d, self.dancers[j])]
            fronting, overlapping = len(alone) < len(overlapping), alone
            if not overlapping and detections is not None:
                def on_box(det, box=d.box) -> bool:
                    return box_overlap(box, det) > 0.5 and box_iou(box, det) > 0.2

                matches = [det for det in detections if on_box(det)] or [det for det in weak if on_box(det)]
                if len(matches) == 1 and self._stranger_in_front(frame, d, matches[0], detections):
                    self._occlude(d, [], behind_stranger=True)
                    continue
                d.missed = 0 if matches else d.missed + 1
                d.found_streak = d.found_streak + 1 if matches else 0
                if matches:
                    d.detected_at_edge = self._cut_by_edge(matches)
                    d.detected_clear_at = t
                elif self._walked_out(frame, d):
                    self._set_out(d, d.detected_at_edge)
                    continue
                stuck = False
                if fronting and self._follow_front_feet(d, frame, detections):
                    d.adapted_at = t  # two people part on its box: it follows the one in front
                elif len(matches) == 1 and t <= d.recovering_until and \
                        self._single_person(d, matches[0], c.recovery_height_change):
                    # just recovered, moving fast and changing shape (e.g. a flip): follow the detector
                    self._restart(d, frame, matches[0], d.confidence)
                elif len(matches) == 1 and (box_iou(d.box, matches[0]) > c.adapt_min_iou or
                                            (self._containment(matches[0], d.box) > c.adapt_min_containment
                                             and self._empty_around(frame, d, matches[0]))) and \
                        self._single_person(d, matches[0]):
                    if fronting:  # its detection may hold limbs of the dancers behind it beside it: height only
                        self._adapt_height(d, matches[0])
                        if c.front_narrows:
                            self._narrow_front(d, matches[0])
                    else:
                        self._adapt_box(d, frame, matches[0])
                    d.adapted_at = t
                elif c.adapt_beside_partner and len(matches) == 1 and \
                        box_iou(d.box, matches[0]) > c.adapt_min_iou and \
                        self._beside_partner(d, matches[0], detections):
                    self._adapt_height(d, matches[0])
                elif c.adapt_height_inside and len(matches) == 1 and not fronting and \
                        self._containment(matches[0], d.box) > c.adapt_min_containment and \
                        self._alone_at_implied_height(d, matches[0]):
                    self._adapt_height(d, matches[0])  # a box grown too tall about it: the height follows
                    d.adapted_at = t
                else:  # a person on the box reaching out of its columns: the box lies off it
                    stuck = len(matches) == 1 and not fronting and self._single_person(d, matches[0]) and \
                        self._containment(matches[0], d.box) <= c.adapt_min_containment
                d.stuck = d.stuck + 1 if stuck else 0
                if c.foreground_trim > 0 and not fronting:
                    self._trim_to_foreground(d, frame)
                if c.stuck_persist and d.stuck >= c.stuck_persist:
                    self._restart_on_stuck(d, frame, matches[0])
                # a box missed that long and showing (almost) no foreground lies on the floor or wall
                on_background = c.lost_max_foreground > 0 and d.missed >= c.max_missed_detections and \
                    not self._shows_someone(frame, d, [d.box], c.lost_max_foreground)[0]
                if d.missed >= c.max_missed_detections and detections and self._jump_to_detection(
                        d, frame, detections, on_background):
                    continue
                if on_background:
                    # its tracker drifted onto the floor or wall: the dancer is elsewhere, and the motion measured
                    # there is the drift's
                    d.stored_velocity = np.zeros(2)
                    front = self.dancers[d.hidden_behind] if d.hidden_behind is not None else None
                    if c.waiting_back_behind and front is not None and front.status != OUT \
                            and d.wait_offset is not None:
                        # never seen, it never came out: it still stands behind the dancer it waits behind
                        d.stored_box = box_behind(d.box, front.box, d.wait_offset)
                    self._occlude(d, [])
                    d.lost_on_background = True
                    continue
            if self._inside_fraction(d.box) < c.learn_inside:  # partly out of the frame: memory kept from before
                if self._leaves_frame(d, frame, t):
                    self._set_out(d)
                continue
            if not overlapping:
                d.clear_track = [(f, p) for f, p in d.clear_track if f >= t - c.velocity_window] + [(t, d.body_center)]
                if d.clear_track[-1][0] - d.clear_track[0][0] >= c.min_velocity_span:
                    d.velocity_measured = True
                    d.stored_velocity = self._clear_velocity(d)
                hist = self._histogram(frame, d.box) if d.missed == 0 else None
                if hist is not None:
                    d.stored_histogram = hist if d.stored_histogram is None else \
                        (1 - c.histogram_smoothing) * d.stored_histogram + c.histogram_smoothing * hist
                d.stored_box, d.stored_frame = d.box, t
                continue
            if self._failed(d, frame, overlapping, boxes):
                self._occlude(d, [self.dancers[j] for j in overlapping])
            else:
                group.append(d)
        if detections is not None and c.adapt_in_groups:
            self._adapt_in_group(frame, group, detections, weak)
        elif detections is not None and c.group_front_adapts is not None:
            self._adapt_front_in_group(frame, group, detections, weak)
        if detections is not None and c.group_scale:
            self._scale_groups(group, detections, weak)
        if detections is not None and c.group_reshape_after:
            self._reshape_in_group(group, detections)
        if c.emerge_hidden_starts:  # sure finds first, then weak ones (also on a frame without a sure one)
            front_histograms = {}  # shared by both calls: the colours of the boxes of the dancers in front
            if detections:
                self._emerge(frame, detections, front_histograms)
            if emerging:
                self._emerge(frame, emerging, front_histograms)
        # 3-4. occluded dancers: predict; re-identify any that show clearly again; relocate from the predicted
        # end of the overlap on
        occluded = [d for d in self.dancers if d.status == OCCLUDED]
        own_boxes = []
        for d in occluded:
            # the dancer's own tracker keeps running without learning: where it ends up is one more candidate
            own_boxes.append(box_at(np.asarray(d.tracker.update(frame, learn=False).center) + d.offset, d.box))
            predicted = self._predicted_box(d, t)
            if self._back_behind_front(frame, d, t):
                continue
            if c.hold_empty_prediction and self._clear_of_others(d, predicted) and \
                    not self._shows_someone(frame, d, [predicted])[0]:
                continue  # nobody there: the dancer is still behind the others
            found_steadily = d.found_streak >= c.hold_found_streak
            if c.hold_uncovered_prediction > 0 and self.given_detections and \
                    (found_steadily or c.hold_unseen_prediction):
                if d.stopped_behind:
                    continue
                cover = self._covered_fraction(d, predicted)
                best = max((v for v, _ in d.cover_path), default=0.0)
                if cover < c.hold_uncovered_prediction <= best:
                    if found_steadily or not self._shows_someone(frame, d, [predicted])[0]:
                        # it would come out from behind the dancers in front unseen: it stopped where its predicted
                        # path was hidden best (the middle of the best-hidden stretch)
                        hidden = np.array([b for v, b in d.cover_path if v >= best - COVER_TIE], dtype=float)
                        d.box = tuple(float(v) for v in hidden.mean(axis=0))
                        d.stopped_behind = True
                        continue
                    d.cover_path, best = [], 0.0  # it comes out where someone shows: predicted on from here
                # only the boxes near the best cover so far are kept (the list stays short however long it hides)
                if cover >= best - COVER_TIE:
                    d.cover_path = [(v, b) for v, b in d.cover_path if v >= max(best, cover) - COVER_TIE]
                    d.cover_path.append((cover, tuple(predicted)))
            d.box = predicted
        self._reidentify(frame, occluded, own_boxes, detections)
        for d, own in zip(occluded, own_boxes):
            if d.status != OCCLUDED:
                continue
            if self._inside_fraction(d.box) < c.out_fraction:  # moved out of the frame behind the others
                self._set_out(d)
                d.out_unseen = True  # by its prediction: it may have turned back behind them
                continue
            clear_now = not d.behind_stranger and (self._clear_of_others(d, d.box) or self._clear_of_others(d, own))
            if t >= d.occlusion_end or clear_now:
                self._relocate(d, frame, detections, force=t - d.occluded_since >= c.max_occlusion_frames,
                               extra=[own] if self._own_box_stays(d, own) else [])
        if detections is not None and c.orphan_persist:
            self._take_stray(frame, detections)
        if c.lost_search_after:
            self._search_lost(frame)
        # 5. dancers out of the frame: re-identified when they come back
        self._reenter(frame, detections)
        self._reenter_at_edge(frame)
        for d in self.dancers:  # a box taken elsewhere or out of the frame starts without growth
            if d.status == OUT or d.status != d.last_status:
                d.growth = np.zeros(4)
            d.last_status = d.status
        return self.result()

    def _size_ratio(self, box_size: np.ndarray, detected: np.ndarray) -> np.ndarray:
        """(2,) width and height of a dancer's box (``box_size`` px) over those of the detection on it
        (``detected`` px), within ``max_size_ratio`` (``max_height_ratio`` for the height) either way."""
        c = self.config
        limit = np.array([c.max_size_ratio, c.max_height_ratio])
        return np.clip(box_size / detected, 1 / limit, limit)

    def _count_detector_frame(self) -> None:
        """The detector ran on this frame (``detections`` given to :meth:`step`, found or not): it becomes
        ``detector_frame``, and the one before ``previous_detector_frame``. Rules that need a detection on several
        detector frames in a row count these, not frames, so that they mean the same at any ``--detect-every``."""
        if self.detector_frame != self.frame_index:
            self.previous_detector_frame, self.detector_frame = self.detector_frame, self.frame_index

    def _take(self, d: DancerTrack, box, score: float, seen_part: bool = True) -> None:
        """Dancer ``d`` is seen again at ``box`` (histogram similarity ``score``): tracking resumes there.
        ``seen_part``: ``box`` is a detection, showing only what is not hidden (:meth:`_feet_hidden`); False for
        a patch of the dancer's own box size (``feet_of_detections_only``)."""
        if seen_part:
            self._note_hidden_sides(d, box, as_box=True)
        if seen_part or not self.config.feet_of_detections_only:
            box = self._hidden_parts(d, box)
        d.tracker.center = (box[0] + box[2] / 2, box[1] + box[3] / 2)
        d.offset = np.zeros(2)
        d.box = tuple(float(v) for v in box)
        d.status = TRACKED
        d.missed, d.detected_at_edge = 0, None
        d.lost_on_background = d.behind_stranger = False
        d.lost_candidate, d.lost_streak = None, 0  # a later search starts afresh
        d.confidence = float(np.clip(score, 0, 1))
        d.centers = [d.body_center]
        d.clear_track = []
        d.stored_box, d.stored_frame = d.box, self.frame_index
