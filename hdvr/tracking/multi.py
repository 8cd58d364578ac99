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
each dancer's own tracking, adaptation to its detection, failure tests, occlusion and relocation; its parameters are
:class:`hdvr.tracking.config.MultiTrackerConfig` (imported here too); the mixins :mod:`hdvr.tracking.groups`
(overlapping dancers adapted together), :mod:`hdvr.tracking.emergence` (dancers waiting hidden coming out),
:mod:`hdvr.tracking.reidentification` (steps 4 and 6: occluded and lost dancers found again) and
:mod:`hdvr.tracking.extent` (the reported box) add the rest; :mod:`hdvr.tracking.geometry` has the box helpers.

A dancer whose box leaves the frame is *out* (no box) until it comes back: on a detection, or without one on the
strip at the left or right edge it left by, when that strip matches its memory clearly better than the empty edge
did (:meth:`MultiDancerTracker._reenter_at_edge`).

Dancers may start later than the first frame (:meth:`MultiDancerTracker.add_dancer`).

Boxes are (x, y, w, h) pixels, top-left corner; velocities px/frame; frames are 0-based indices.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import (box_inside, box_iou, box_overlap, clip_box, colour_histogram, foreground_mask,
                                      histogram_similarity)
from hdvr.tracking.config import MultiTrackerConfig  # noqa: F401  (part of this module's interface)
from hdvr.tracking.emergence import Emergence
from hdvr.tracking.extent import ReportedExtent
from hdvr.tracking.geometry import angle_between, box_behind, height_within, offset_behind, shifted
from hdvr.tracking.groups import GroupAdaptation
from hdvr.tracking.ldes import LDESTracker
from hdvr.tracking.reidentification import Reidentification
from hdvr.tracking.state import (OCCLUDED, OUT, TRACKED, DancerTrack, FrameResult, body_core, box_at, box_centre,
                                 covered_fraction, stands_in_front)

#: fraction of a dancer's box height left out at its top and at its bottom in the dancers' colour histograms
HISTOGRAM_END_SHRINK = 0.15
#: covers of an occluded dancer's predicted boxes within this of the best are as well hidden
#: (``MultiTrackerConfig.hold_uncovered_prediction``: it stops at the middle of those boxes)
COVER_TIE = 0.05


class MultiDancerTracker(GroupAdaptation, Emergence, Reidentification, ReportedExtent):
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

    def _travel(self, d: DancerTrack, frame_index: int) -> np.ndarray:
        """How far (px) occluded dancer ``d`` is taken to have moved from its last clear box by ``frame_index``:
        :meth:`prediction_velocity` x its stored velocity x the frames since; with ``detector_velocity_if_found``,
        ``prediction_velocity`` for a dancer the detector did not find on the last detector frame it was clear.
        Up or down the image the frames since count as if the velocity faded (``vertical_prediction_frames``: after
        t frames, tau x (1 - exp(-t / tau)) frames' worth, at most tau)."""
        fraction = self.prediction_velocity
        if self.config.detector_velocity_if_found and not self._detector_found(d):
            fraction = self.config.prediction_velocity
        elapsed = float(frame_index - d.stored_frame)
        steps = np.array([elapsed, elapsed])  # frames' worth of its stored velocity, horizontally and vertically
        fade = self.config.vertical_prediction_frames
        if fade > 0 and elapsed > 0:
            steps[1] = fade * (1.0 - np.exp(-elapsed / fade))
        return fraction * d.stored_velocity * steps

    @staticmethod
    def _detector_found(d: DancerTrack) -> bool:
        """Whether the detector found a person on dancer ``d``'s box on the last detector frame it was clear (so
        it will find it where it comes out from behind others)."""
        return d.missed == 0 and d.detected_clear_at >= 0

    @property
    def prediction_velocity(self) -> float:
        """The fraction of its stored velocity an occluded dancer is predicted with: the config's
        ``detector_prediction_velocity`` once detections were given (a detector runs), else its
        ``prediction_velocity``; :meth:`_travel` keeps ``prediction_velocity`` for a dancer the detector did not
        find (``detector_velocity_if_found``)."""
        c = self.config
        if self.given_detections and c.detector_prediction_velocity is not None:
            return c.detector_prediction_velocity
        return c.prediction_velocity

    def _predicted_box(self, d: DancerTrack, frame_index: int):
        return shifted(d.stored_box, self._travel(d, frame_index))

    def _predict_overlap_end(self, d: DancerTrack, others: list[DancerTrack], now: int) -> int:
        """First frame after ``now`` at which ``d``'s predicted box overlaps none of ``others``' predicted boxes
        (each moving on with its stored velocity)."""
        c = self.config
        for t in range(now + 1, now + c.max_occlusion_frames):
            mine = self._predicted_box(d, t)
            if all(self._bodies_overlap(mine, self._predicted_box(o, t) if o.status == OCCLUDED
                               else shifted(o.box, o.stored_velocity * (t - now))) <= c.overlap_threshold
                   for o in others):
                return t + c.overlap_margin_frames
        return now + c.max_occlusion_frames

    def _cone_candidates(self, d: DancerTrack, detections) -> tuple[list, list]:
        """Where occluded dancer ``d`` may be found again, as (patches, detections), (x, y, w, h) px: patches of the
        stored box size along the stored motion direction (a disc about the prediction when barely moving), and the
        ``detections`` in that cone. For a dancer whose prediction stopped behind the dancers in front
        (``stopped_behind``) the patches lie on the way to where it stopped, and the detections are those in either
        cone (a detector's find where the dancer would have walked on is no guess)."""
        travel = self._travel(d, self.frame_index)
        patches, found = self._cone(d, travel, detections)
        if d.stopped_behind:
            patches, stopped = self._cone(d, box_centre(d.box) - box_centre(d.stored_box), detections)
            found += [det for det in stopped if det not in found]
        return patches, found

    def _cone(self, d: DancerTrack, travel: np.ndarray, detections) -> tuple[list, list]:
        """The cone search of :meth:`_cone_candidates` for a ``travel`` (px) from the centre of ``d``'s stored box."""
        c = self.config
        origin = box_centre(d.stored_box)
        dist = float(np.linalg.norm(travel))
        w, h = d.stored_box[2], d.stored_box[3]
        centres = []
        if dist > c.min_search_radius * h:
            heading = np.arctan2(travel[1], travel[0])
            half = np.radians(c.cone_half_angle_deg)
            for r in c.cone_radii:
                for a in np.linspace(-half, half, c.cone_angles):
                    centres.append(origin + r * dist * np.array([np.cos(heading + a), np.sin(heading + a)]))
        else:  # barely moving: a disc around the prediction
            rad = c.min_search_radius * h
            centres.append(origin + travel)
            for k in range(8):
                a = 2 * np.pi * k / 8
                for r in (0.5 * rad, rad):
                    centres.append(origin + travel + r * np.array([np.cos(a), np.sin(a)]))
        patches = [(float(x - w / 2), float(y - h / 2), w, h) for x, y in centres]
        found = []
        for det in detections or []:
            centre = np.array([det[0] + det[2] / 2, det[1] + det[3] / 2])
            off = centre - origin
            if dist > c.min_search_radius * h:
                inside = (angle_between(off, travel) <= 2 * c.cone_half_angle_deg
                          and 0.4 * dist <= np.linalg.norm(off) <= 1.8 * dist + 0.5 * w)
            else:
                inside = np.linalg.norm(off - travel) <= 2 * c.min_search_radius * h
            if inside:
                found.append(tuple(float(v) for v in det))
        return patches, found

    # --------------------------------------------------------------------- step
    def step(self, frame: np.ndarray, detections=None, weak_detections=None) -> FrameResult:
        """Track all dancers into the next frame. ``detections``: optional person boxes (x, y, w, h) px in this
        frame, used as extra relocation candidates; ``weak_detections``: boxes the detector is less sure of, used
        only to update dancers followed (``MultiTrackerConfig.weak_detections``)."""
        c = self.config
        # weak detections come second: for a dancer followed that no sure detection updates (as in ByteTrack)
        weak = list(weak_detections) if detections is not None and weak_detections and c.weak_detections else []
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
        if detections is not None and c.group_scale:
            self._scale_groups(group, detections, weak)
        if detections is not None and c.group_reshape_after:
            self._reshape_in_group(group, detections)
        if c.emerge_hidden_starts:  # sure finds first, then weak ones (also on a frame without a sure one)
            front_histograms = {}  # shared by both calls: the colours of the boxes of the dancers in front
            if detections:
                self._emerge(frame, detections, front_histograms)
            if weak:
                self._emerge(frame, weak, front_histograms)
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

    def _back_behind_front(self, frame, d: DancerTrack, t: int) -> bool:
        """With ``waiting_empty_behind``: whether occluded dancer ``d``, still waiting behind the dancer it started
        behind, was put back behind him in frame ``t`` because its box lay clear of everyone on the floor or wall;
        if so its last box is its place behind him (at ``wait_offset``), and its prediction starts there, still."""
        c = self.config
        if not c.waiting_empty_behind or d.hidden_behind is None or d.wait_offset is None:
            return False
        front = self.dancers[d.hidden_behind]
        if front.status != TRACKED or not self._clear_of_others(d, d.box) or \
                self._shows_someone(frame, d, [d.box])[0]:
            return False
        d.stored_box = box_behind(d.box, front.box, d.wait_offset)
        d.stored_frame, d.stored_velocity = t, np.zeros(2)
        d.box = d.stored_box
        d.returned_behind = True
        return True

    def _occlude(self, d: DancerTrack, front: list[DancerTrack], behind_stranger: bool = False) -> None:
        """Dancer ``d`` is hidden behind the dancers ``front`` from this frame on: its box is predicted from its
        last clear one (with the size of its box now, ``occluded_keeps_size``), and it is looked for again from the
        predicted end of the overlap. ``behind_stranger``: hidden behind a person nobody tracks
        (``stranger_in_front``), whose path, and so the end of the overlap, is unknown: it is looked for by
        re-identification only, until ``max_occlusion_frames`` have passed."""
        t = self.frame_index
        d.status = OCCLUDED
        d.occluded_since = t
        d.stopped_behind, d.cover_path, d.behind_stranger = False, [], behind_stranger
        if self.config.occluded_keeps_size:
            cx, cy = box_centre(d.stored_box)
            d.stored_box = (cx - d.box[2] / 2, cy - d.box[3] / 2, d.box[2], d.box[3])
        d.occlusion_end = t + self.config.max_occlusion_frames if behind_stranger \
            else self._predict_overlap_end(d, front, t)
        d.box = self._predicted_box(d, t)
        d.confidence = 0.0

    def _leaves_frame(self, d: DancerTrack, frame, t: int) -> bool:
        """Whether dancer ``d``, whose box is partly out of the frame, has left it: its box is less than
        ``out_fraction`` inside, or its last clear box moved on with its stored velocity is and the box no longer
        matches its stored histogram (``failure_histogram``: the tracker stuck at the edge on the background,
        while a dancer who turns back at the edge is still seen there)."""
        c = self.config
        if self._inside_fraction(d.box) < c.out_fraction:
            return True
        if self._inside_fraction(self._predicted_box(d, t)) >= c.out_fraction:
            return False
        return self._memory_match(d, frame) < c.failure_histogram

    def _set_out(self, d: DancerTrack, side: str | None = None) -> None:
        """Dancer ``d`` has left the frame: no box until it is re-identified (:meth:`_reenter`,
        :meth:`_reenter_at_edge`). The edge it left by is ``side``, by default where its box overflows the frame
        most."""
        d.status, d.confidence, d.missed, d.detected_at_edge = OUT, 0.0, 0, None
        d.out_unseen = False
        x, _, w, _ = d.box
        left, right = -x, x + w - self.frame_size[0]
        d.exit_side = side or (("left" if left > right else "right") if max(left, right) > 0 else None)
        d.edge_empty_score = 1.0

    def _cut_by_edge(self, detections) -> str | None:
        """"left" or "right" when every one of ``detections`` (x, y, w, h px) reaches that side of the frame
        (within ``exit_edge_px``): the person is partly out of the frame there; else None."""
        c, width = self.config, self.frame_size[0]
        if all(det[0] <= c.exit_edge_px for det in detections):
            return "left"
        if all(det[0] + det[2] >= width - c.exit_edge_px for det in detections):
            return "right"
        return None

    def _walked_out(self, frame, d: DancerTrack) -> bool:
        """Whether clear dancer ``d`` has walked out of the frame although its box is still in it: the last
        detection on its box was cut by the left or right edge, none has held it for ``exit_missed_detections``
        detector frames, and its box is background (fewer than ``exit_max_foreground`` of its columns hold
        foreground: :meth:`_foreground_columns`). A dancer walking out slowly is detected by the part still in,
        its box adapts to those narrowing detections, and when nothing is left the tracker stays on the
        background at the edge, which its colour memory (learned with background around it) may still match
        (0.75 on the real two-people video). The foreground test keeps a dancer who is still there but missed by
        the detector."""
        if d.detected_at_edge is None or d.missed < self.config.exit_missed_detections:
            return False
        fraction = self._foreground_columns(frame, d)
        return fraction is not None and fraction < self.config.exit_max_foreground

    def _edge_strip(self, d: DancerTrack) -> tuple[float, float, float, float]:
        """The strip (px) at the edge dancer ``d`` left by where it would show first when it comes back: the
        height and vertical place of its last clear box, ``edge_strip`` x its width wide."""
        _, y, w, h = d.stored_box
        sw = self.config.edge_strip * w
        x = 0.0 if d.exit_side == "left" else self.frame_size[0] - sw
        return (x, y, sw, h)

    def _reenter_at_edge(self, frame) -> None:
        """Dancers out of the frame that left by the left or right edge are re-identified there without a
        detection. The strip of :meth:`_edge_strip` is a candidate when it is clear of every tracked dancer and its
        histogram matches the dancer's memory by ``reid_margin`` better than the emptiest view of that strip
        since the dancer left (a thin dancer's strip is mostly background, which may match its memory too); the
        candidates are matched by :meth:`_histogram_matches` against the memories of every dancer not seen now.
        The box (the last clear size, inside the frame at that edge: a tracker started on a box partly outside
        stays there) is taken and the tracker restarts there with no velocity."""
        c = self.config
        out = [d for d in self.dancers if d.status == OUT and d.exit_side is not None]
        if not c.edge_reentry or not out:
            return
        tracked = [o.box for o in self.dancers if o.status == TRACKED]
        unseen = [o for o in self.dancers if o.status != TRACKED]
        candidates = []
        for d in out:
            strip = self._edge_strip(d)
            score = self._memory_match(d, frame, strip)
            empty = d.edge_empty_score
            d.edge_empty_score = min(empty, score)
            if score >= empty + c.reid_margin and all(box_overlap(strip, self._core(o)) <= c.overlap_threshold
                                                      for o in tracked):
                candidates.append((d, [strip]))
        for d, strip, score in self._histogram_matches(frame, candidates, unseen):
            w, h = d.stored_box[2:]
            box = (0.0 if d.exit_side == "left" else self.frame_size[0] - w, strip[1], w, h)
            self._back_in_frame(d, frame, box, score)

    def _reenter(self, frame, detections) -> None:
        """Dancers out of the frame who come back are re-identified on person detections (without one, at the
        edge they left by: :meth:`_reenter_at_edge`). Candidates: the detections that no tracked dancer takes
        (:meth:`_claimed`; a dancer comes back at the edge, or anywhere after a tracker pushed off the frame) and
        whose height is within ``max_height_change`` of the dancer's last clear box, matched by
        :meth:`_histogram_matches` against every dancer not seen now (occluded or out). The dancer's tracker
        restarts there, with no velocity."""
        c = self.config
        out = [d for d in self.dancers if d.status == OUT]
        if not out or not detections:
            return
        dets = [tuple(float(v) for v in det) for det in detections]
        claimed = self._claimed(dets)
        free = [det for k, det in enumerate(dets) if k not in claimed]
        unseen = [o for o in self.dancers if o.status != TRACKED]
        # a box of another height is a hand or a leg reaching into the frame
        candidates = [(d, [box for box in free
                           if height_within(box, d.stored_box, c.max_height_change)])
                      for d in out]
        for d, box, score in self._histogram_matches(frame, candidates, unseen):
            self._back_in_frame(d, frame, box, score)

    def _back_in_frame(self, d: DancerTrack, frame, box, score: float) -> None:
        """Dancer ``d``, out of the frame, is back at ``box``: taken there, its tracker restarted, no velocity."""
        self._take(d, box, score)
        d.tracker.init(frame, self._core(box))
        d.stored_velocity = np.zeros(2)

    def _histogram_matches(self, frame, candidates, rivals, box_rivals=None,
                           histograms: dict | None = None) -> list[tuple[DancerTrack, tuple, float]]:
        """One-to-one matches of dancers to candidate boxes (px) by colour histogram, best first:
        ``candidates`` is a list of (dancer, boxes). A box is taken for its dancer when its histogram correlates
        with the dancer's memory at least ``reid_similarity`` and better by ``reid_margin`` than with the memory of
        every other dancer in ``rivals`` (and in ``box_rivals[box]``, dancers that box stands beside; and, with
        ``hidden_front_rival``, the dancer hiding a dancer that still waits to come out from behind it; over a
        dancer that still waits behind the dancer matched, by ``reid_waiting_margin`` only), and when it
        is clear of the boxes taken before (the dancer in front of a group shows whole and is taken first). Returns
        (dancer, box, similarity) triples. ``histograms``: colour histograms of boxes already computed, by box
        tuple; each box's is computed once, whatever the number of dancers it is a candidate for."""
        c = self.config
        histograms = {} if histograms is None else histograms
        options = []
        for d, boxes in candidates:
            for box in boxes:
                hist = self._cached_histogram(frame, histograms, tuple(float(v) for v in box), box)
                score = histogram_similarity(hist, d.stored_histogram)
                if score >= c.reid_similarity:
                    options.append((score, d.dancer_id, box, hist))
        matches: list[tuple[DancerTrack, tuple, float]] = []
        for score, i, box, hist in sorted(options, key=lambda o: -o[0]):
            d = self.dancers[i]
            if any(m[0] is d for m in matches) or any(self._bodies_overlap(box, m[1]) > c.overlap_threshold
                                                      for m in matches):
                continue
            extra = list((box_rivals or {}).get(tuple(box), []))
            if c.hidden_front_rival and d.hidden_behind is not None:  # its memory shows the dancer in front
                extra.append(self.dancers[d.hidden_behind])
            if any(histogram_similarity(hist, o.stored_histogram) >
                   score - (c.reid_waiting_margin if o.hidden_behind == d.dancer_id else c.reid_margin)
                   for o in list(rivals) + extra if o is not d):
                continue
            matches.append((d, box, score))
        return matches

    def _jump_to_detection(self, d: DancerTrack, frame, detections, on_background: bool | None = None) -> bool:
        """A dancer whose box has held no detected person for a while moves to a detected person nearby that
        nobody else tracks, if that person's histogram matches the stored one clearly better than the box does
        (the tracker drifted off, e.g. in a jump). After ``long_lost_detections`` detector frames without a person
        on its box, the box's own match no longer counts (a box left on a static background keeps matching a
        memory learned there), unless the box still shows someone (``lost_max_foreground``): the person is taken if
        it matches this dancer's memory at least ``relocate_min_similarity`` and better by ``reid_margin`` than the
        memory of every other dancer not held by a detection of its own (one that is cannot be this person). With
        ``jump_rivals``, at any time, it must also match by ``reid_margin`` better than the memory of every other
        dancer showing its own colours (a person that looks like another dancer is that dancer, lost too, not this
        one). ``on_background``: whether the box shows less than ``lost_max_foreground`` foreground, if the caller
        measured it already. Returns whether it moved."""
        c = self.config
        # a box that still shows someone (``lost_max_foreground``) is on a dancer the detector misses (a thin one far
        # back), not on the background: its own match counts however long no person was detected on it
        long_lost = d.missed >= c.long_lost_detections and (c.lost_max_foreground <= 0 or (
            on_background if on_background is not None
            else not self._shows_someone(frame, d, [d.box], c.lost_max_foreground)[0]))
        current = self._memory_match(d, frame)
        others = [o for o in self.dancers if o is not d]
        # dancers the person must match worse (by reid_margin) than this one: when long lost, those not held by a
        # detection of their own; with jump_rivals, every one showing its own colours
        rivals = [o for o in others if (long_lost and not (o.status == TRACKED and o.missed == 0))
                  or (c.jump_rivals and o.hidden_behind is None)]
        best, best_score = None, c.relocate_min_similarity if long_lost else max(current + 0.1,
                                                                                  c.relocate_min_similarity)
        for det in detections:
            if any(box_iou(det, o.box) > 0.3 for o in others) or not self._single_person(d, det):
                continue
            off = np.array([det[0] + det[2] / 2, det[1] + det[3] / 2]) - d.center
            if np.linalg.norm(off) > c.lost_search_heights * d.box[3]:
                continue
            hist = self._histogram(frame, det)
            score = histogram_similarity(hist, d.stored_histogram)
            if any(histogram_similarity(hist, o.stored_histogram) > score - c.reid_margin for o in rivals):
                continue
            if score > best_score:
                best, best_score = tuple(float(v) for v in det), score
        if best is None:
            return False
        self._restart(d, frame, best, best_score)
        if long_lost:
            d.recovering_until = self.frame_index + c.recovery_frames
        return True

    def _restart(self, d: DancerTrack, frame, box, score: float) -> None:
        """Restart dancer ``d``'s tracker on ``box`` (its filter learned whatever it drifted onto)."""
        d.offset = np.zeros(2)
        d.tracker.init(frame, self._core(box))
        d.box, d.missed, d.confidence = tuple(float(v) for v in box), 0, float(np.clip(score, 0, 1))
        d.detected_at_edge, d.lost_on_background, d.behind_stranger = None, False, False
        d.hidden_aspect, d.hidden_sides = None, (False, False)
        d.centers, d.clear_track = [d.body_center], []
        d.stored_box, d.stored_frame = d.box, self.frame_index
        if self.config.restart_hands_over_waiting:
            self._hand_over_waiting(d)

    def _restart_on_stuck(self, d: DancerTrack, frame, detection) -> None:
        """Dancer ``d``, clear of the others, has had ``detection`` (x, y, w, h px), one person alone, on its box for
        ``stuck_persist`` detector frames in a row without being able to adapt to it (too far off): its box moves
        onto it (centred there, at the dancer's box-to-detection size, :meth:`_box_size`) and its tracker restarts
        there. Its colour memory and stored velocity are kept (no re-identification happens; :meth:`_restart`
        touches neither)."""
        self._restart_on_detection(d, frame, detection)
        d.stuck, d.adapted_at = 0, self.frame_index

    def _restart_on_detection(self, d: DancerTrack, frame, detection) -> None:
        """Dancer ``d``'s box moves onto ``detection`` (x, y, w, h px: centred there, at the dancer's box-to-detection
        size, :meth:`_detected_size`) and its tracker restarts there (:meth:`_restart`)."""
        w, h = self._detected_size(d, detection)
        cx, cy = box_centre(detection)
        self._restart(d, frame, (cx - w / 2, cy - h / 2, float(w), float(h)), d.confidence)

    def _single_person(self, d: DancerTrack, detection, max_height_change: float | None = None) -> bool:
        """Whether ``detection`` can be dancer ``d`` alone: its body core overlaps no other dancer's, its height
        is within ``max_height_change`` (default: the config's) of ``d``'s box height (a box around two people is
        neither), and it is at most ``max_person_width`` x that height wide (a person's arm span is about their
        stature; the detector sometimes returns a box across the whole frame)."""
        c = self.config
        return self._person_sized(d, detection, max_height_change) and \
            all(self._bodies_overlap(detection, o.box) <= c.overlap_threshold for o in self.dancers
                if o is not d and not self._clear_of_waiting(d, o))

    def _follow_front_feet(self, d: DancerTrack, frame, detections) -> bool:
        """With ``front_follows_feet``, dancer ``d``, with a dancer waiting straight behind it, restarts on the
        person detected on its box (overlap > 0.3) whose feet are lowest, when two or more are: the one in front is
        nearest the camera. People count if their height is within ``reid_height_change`` of ``d``'s box (a box
        around two people reaches lowest too) and no other dancer followed holds them (IoU >= 0.5). Only if ``d``'s
        box has slid off that person (IoU < 0.5), e.g. its tracker, which learned both dancers from the start,
        follows the one behind as they part; and with ``front_feet_max_off`` only if that person's centre lies
        within that x the box's width of the box's columns. Returns whether it restarted."""
        c = self.config
        if c.front_follows_feet <= 0:
            return False
        others = [o.box for o in self.dancers if o is not d and o.status == TRACKED and o.hidden_behind is None]
        people = [tuple(float(v) for v in det) for det in detections
                  if box_overlap(d.box, det) > 0.3 and self._person_sized(d, det, c.reid_height_change)
                  and all(box_iou(det, o) < 0.5 for o in others)]
        if len(people) < 2:
            return False
        people.sort(key=lambda b: b[1] + b[3], reverse=True)
        front, second = people[0], people[1]
        if front[1] + front[3] - (second[1] + second[3]) < c.front_follows_feet * d.box[3] or \
                box_iou(d.box, front) >= 0.5:
            return False
        if c.front_feet_max_off is not None:
            centre_x = box_centre(front)[0]
            off = max(d.box[0] - centre_x, centre_x - (d.box[0] + d.box[2]), 0.0)
            if off > c.front_feet_max_off * d.box[2]:
                return False
        self._restart_on_detection(d, frame, front)
        return True

    def _clear_of_waiting(self, d: DancerTrack, o: DancerTrack) -> bool:
        """With ``front_of_waiting_clear``, whether dancer ``d`` counts as clear of dancer ``o``, which overlaps it:
        ``o`` still waits hidden behind ``d`` since its start, straight behind it (``hidden_start_overlap``)."""
        c = self.config
        return c.front_of_waiting_clear and o.hidden_behind == d.dancer_id and \
            self._straight_in_front(d, o, c.hidden_start_overlap)

    def _person_sized(self, d: DancerTrack, detection, max_height_change: float | None = None) -> bool:
        """Whether ``detection`` (x, y, w, h px) has the size of dancer ``d`` alone: its height within
        ``max_height_change`` (default: the config's) of ``d``'s box height, its width at most ``max_person_width``
        x that height (the size tests of :meth:`_single_person` and :meth:`_beside_partner`)."""
        c = self.config
        change = max_height_change or c.max_height_change
        return height_within(detection, d.box, change) and detection[2] <= c.max_person_width * d.box[3]

    def _beside_partner(self, d: DancerTrack, detection, detections) -> bool:
        """Whether ``detection`` (x, y, w, h px), refused as dancer ``d`` alone because its body core overlaps
        another dancer's (:meth:`_single_person`), is still ``d``'s: its height is within ``max_height_change`` of
        ``d``'s box and it is at most ``max_person_width`` x that height wide, neither it nor the box reaches the
        frame's top or bottom (a dancer cut by the frame), and it overlaps the core of at least one dancer, every one
        of them tracked, clear of ``d`` (cores apart), not standing in front of ``d`` (the detection then shows all
        of ``d``), and holding a detection of its own (another one that fits its box by ``group_min_score``:
        :meth:`_fit_score`). A dancer beside a partner, an arm out towards her, not a box around both (which would
        leave the partner without a detection of her own)."""
        c, height = self.config, self.frame_size[1]
        if not self._person_sized(d, detection) or min(detection[1], d.box[1]) <= c.exit_edge_px or \
                max(detection[1] + detection[3], d.box[1] + d.box[3]) >= height - c.exit_edge_px:
            return False  # a dancer cut by the frame's top or bottom: the detection does not give her height
        partners = [o for o in self.dancers if o is not d and o.status != OUT
                    and self._bodies_overlap(detection, o.box) > c.overlap_threshold]
        return bool(partners) and all(
            o.status == TRACKED and self._bodies_overlap(d.box, o.box) <= c.overlap_threshold
            and not stands_in_front(o.box, d.box, c.pixel_front)
            and any(tuple(other) != tuple(detection) and self._fit_score(o.box, other) >= c.group_min_score
                    for other in detections)
            for o in partners)

    def _adapt_height(self, d: DancerTrack, detection) -> None:
        """The height of dancer ``d``'s box moves ``box_adaptation`` of the way towards that of ``detection`` (times
        the dancer's learned height ratio of box to detection, ``size_ratio``); the box keeps its bottom (the feet)
        and width (the detection's width holds an arm out towards a partner). The bottom is kept in this frame only:
        the box's offset from the tracker's centre is left as it was, so from the next frame on the box lies about
        the tracker's centre again and half of the height change shows at its bottom. Keeping the bottom through
        the offset was measured in session 69 and not kept (docs/benchmarks.md "session 69")."""
        c = self.config
        ratio = d.size_ratio[1] if d.size_ratio is not None else 1.0
        height = (1 - c.box_adaptation) * d.box[3] + c.box_adaptation * ratio * float(detection[3])
        x, y, w, h = d.box
        d.box = (x, y + h - height, w, height)

    def _narrow_front(self, d: DancerTrack, detection) -> None:
        """Dancer ``d``'s box, in front of dancers waiting behind it, narrows ``box_adaptation`` of the way towards
        ``detection`` (x, y, w, h px; its width as :meth:`_box_size` makes it) where that is narrower, its centre
        moving as far towards the detection's: limbs of the dancers behind can widen its detection, not narrow it
        (seed 2635 tango: a start box with spread arms stayed 145 px wide while the dancer, arms in, was 70)."""
        c = self.config
        a = c.box_adaptation
        width = float(self._detected_size(d, detection)[0])
        x, y, w, h = d.box
        if width >= w:
            return
        new_w = (1 - a) * w + a * width
        shift = a * (float(detection[0]) + float(detection[2]) / 2 - (x + w / 2))
        offset_x = float(np.clip(d.offset[0] + shift, -c.max_box_offset * new_w, c.max_box_offset * new_w))
        centre = x + w / 2 + offset_x - d.offset[0]
        d.offset = np.array([offset_x, d.offset[1]])
        d.box = (centre - new_w / 2, y, new_w, h)

    def _trim_to_foreground(self, d: DancerTrack, frame) -> None:
        """Narrow clear dancer ``d``'s box where a side shows no foreground: each side whose columns hold fewer than
        ``foreground_trim`` x the box height foreground pixels (:meth:`_foreground`) moves
        ``foreground_trim_weight`` of the way in to the outermost column that holds more (plus half the start box's
        width margin, :meth:`_box_size`), the box centre's offset from the tracker's following (where that is more
        than ``max_box_offset`` x the width, the tracker restarts on the new box). Foreground columns count only in
        the run (gaps up to ``pixel_gap``) nearest the tracker's centre. A side is left as it is where it lies
        outside the frame or where a column to be cut lies in another dancer's box (that foreground is not told
        apart); the box is left alone where less than ``foreground_trim_min_fill`` of it is foreground (a dancer
        dressed like the background), and is never narrower than ``foreground_trim_min_aspect`` x its height. Only
        ever narrows: spread arms widen the box through the detections, and the reported extent
        (:mod:`hdvr.tracking.extent`) reaches them between those."""
        c = self.config
        fg = self._foreground(frame)
        width, height = frame.shape[1], frame.shape[0]
        x, y, w, h = d.box
        r = clip_box(d.box, (width, height))
        if fg is None or r is None or w <= 0 or h <= 0:
            return
        x0, y0, x1, y1 = r
        counts = fg[y0:y1, x0:x1].sum(axis=0)
        if counts.sum() < c.foreground_trim_min_fill * w * h:
            return
        filled = np.flatnonzero(counts >= max(2.0, c.foreground_trim * h))
        if not len(filled):
            return
        # the run of filled columns (gaps up to ``pixel_gap``) nearest the tracker's centre: specks of background
        # colours missing from the sample around the dancers lie apart from it
        runs = np.split(filled, np.flatnonzero(np.diff(filled) > c.pixel_gap + 1) + 1)
        centre_column = float(d.tracker.center[0]) - x0
        filled = min(runs, key=lambda run: 0.0 if run[0] <= centre_column <= run[-1] else
                     min(abs(run[0] - centre_column), abs(run[-1] - centre_column)))
        blocked = self._columns_of_others(d, x0, x1, (width, height))
        # a start box with a margin around the body keeps it (half the width margin of :meth:`_box_size` a side)
        pad = 0.0
        if c.width_margin and d.size_ratio is not None and d.ratio_aspect is not None:
            pad = max(0.0, 0.5 * (d.size_ratio[0] - 1.0) * d.ratio_aspect * h / d.size_ratio[1])
        a = c.foreground_trim_weight
        left, right = x, x + w
        inner_left, inner_right = x0 + filled[0] - pad, x0 + filled[-1] + 1 + pad
        if x >= 0 and inner_left > x and not blocked[:filled[0]].any():
            left = x + a * (inner_left - x)
        if x + w <= width and inner_right < x + w and not blocked[filled[-1] + 1:].any():
            right = x + w - a * (x + w - inner_right)
        new_w = right - left
        if new_w >= w or new_w < c.foreground_trim_min_aspect * h:
            return
        d.box = (left, y, new_w, h)
        offset_x = d.offset[0] + (left + right - 2 * x - w) / 2
        if abs(offset_x) <= c.max_box_offset * new_w:
            d.offset = np.array([offset_x, d.offset[1]])
        else:  # the tracker follows a point off the figure (a start box far wider on one side): restart it there
            d.offset = np.zeros(2)
            d.tracker.init(frame, self._core(d.box))

    def _containment(self, detection, box) -> float:
        """How much of ``detection`` lies inside dancer box ``box`` (both x, y, w, h px), in [0, 1]: with
        ``adapt_containment_columns`` the fraction of its width inside the box's columns, 0 unless at least half of
        its height lies within the box's rows (a standing person rising out of the low box of a floor move); else
        the fraction of its area inside the box."""
        if not self.config.adapt_containment_columns:
            return box_inside(detection, box)
        x, y, w, h = (float(v) for v in detection)
        if w <= 0 or h <= 0:
            return 0.0
        rows = min(y + h, box[1] + box[3]) - max(y, box[1])
        if rows < 0.5 * h:
            return 0.0
        return max(0.0, min(x + w, box[0] + box[2]) - max(x, box[0])) / w

    def _empty_around(self, frame, d: DancerTrack, detection) -> bool:
        """Whether the columns of dancer ``d``'s box beside ``detection`` (x, y, w, h px) are background (fewer than
        ``adapt_max_foreground`` of them hold foreground: :meth:`_foreground_columns`). A box left wide after a
        dancer got up from the floor is empty there; one around spread arms the detector left out is not (thin
        arms fill few pixels but many columns)."""
        fraction = self._foreground_columns(frame, d, skip=detection)
        return fraction is not None and fraction < self.config.adapt_max_foreground

    def _foreground(self, frame) -> np.ndarray | None:
        """Foreground mask of ``frame`` (:func:`hdvr.tracking.appearance.foreground_mask`), the background sampled
        around the tracked boxes of the dancers in the frame (not the reported ones: a reported box grown onto
        background would take that background out of the sample and make it foreground, and grow further).
        Computed once per frame and set of boxes (several tests of a frame may ask for it)."""
        boxes = tuple(d.box for d in self.dancers if d.status != OUT)
        cached = self._foreground_cache  # (frame, boxes, mask): the frame itself is held, so it is that very array
        if cached is None or cached[0] is not frame or cached[1] != boxes:
            cached = (frame, boxes, self._foreground_around(frame, list(boxes)))
            self._foreground_cache = cached
        return cached[2]

    def _foreground_around(self, frame, boxes) -> np.ndarray | None:
        """Foreground mask of ``frame`` with the background sampled around ``boxes`` (x, y, w, h px), with the
        tracker's settings (``pixel_margin``, ``pixel_opening``, ``pixel_ring_common``, ``pixel_arm_margin`` at rows
        ``pixel_band``): :func:`hdvr.tracking.appearance.foreground_mask`."""
        c = self.config
        return foreground_mask(frame, boxes, margin=c.pixel_margin, opening=c.pixel_opening,
                               ring_common=c.pixel_ring_common, arm_rows=c.pixel_band, arm_margin=c.pixel_arm_margin)

    def _foreground_columns(self, frame, d: DancerTrack, skip=None) -> float | None:
        """Fraction of the columns of dancer ``d``'s box that hold max(3, ``pixel_min_thickness`` x the box height)
        foreground pixels (:func:`hdvr.tracking.appearance.foreground_mask`). Columns inside other dancers' boxes
        (their foreground is theirs) and inside ``skip`` (x, y, w, h px) do not count. None when no column is left
        or the background cannot be told."""
        c = self.config
        box = d.box
        fg = self._foreground(frame)
        size = (frame.shape[1], frame.shape[0])
        r = clip_box(box, size)
        if fg is None or r is None:
            return None
        x0, y0, x1, y1 = r
        counts = fg[y0:y1, x0:x1].sum(axis=0)
        counted = ~self._columns_of_others(d, x0, x1, size, [skip] if skip is not None else [])
        if not counted.any():
            return None
        needed = max(3.0, c.pixel_min_thickness * box[3])
        return float((counts[counted] >= needed).mean())

    def _columns_of_others(self, d: DancerTrack, x0: int, x1: int, size, extra=(), below: float | None = None
                           ) -> np.ndarray:
        """bool mask of the frame columns ``x0`` to ``x1`` (px, exclusive) that lie in the box of a dancer in the
        frame other than ``d`` (with ``below``, only of a dancer whose box reaches lower than that row, px) or in
        one of the boxes ``extra`` (x, y, w, h px); ``size``: the frame's (width, height) px."""
        inside = np.zeros(x1 - x0, bool)
        others = [o.box for o in self.dancers if o.status != OUT and o is not d and
                  (below is None or o.box[1] + o.box[3] > below)]
        for b in [clip_box(b, size) for b in others + list(extra)]:
            if b is not None:
                inside[max(0, b[0] - x0):max(0, b[2] - x0)] = True
        return inside

    def _adapt_box(self, d: DancerTrack, frame, detection, weight: float | None = None, retrack: bool = True) -> None:
        """Move the box of a clear dancer part of the way (``box_adaptation``) towards the one person detected on
        it: size (times the ratio of the dancer's box to the first detection on it, so the initial box's
        convention is kept) and offset of the box centre from the tracker's centre (at most ``max_box_offset`` x
        the box size). When the box height has drifted by more than ``retrack_scale`` from the tracker's template, the
        tracker restarts on the new box (if ``retrack``; without it, the box-to-detection size ratio is not learned
        either: used for dancers overlapping others). ``weight``: that of the detection (default
        ``box_adaptation``)."""
        c = self.config
        a = c.box_adaptation if weight is None else weight
        self._note_hidden_sides(d, detection)
        detection = self._hidden_parts(d, detection, as_detection=True)
        detection = self._feet_in_foreground(d, frame, detection)
        centre = np.asarray(d.tracker.center, float)
        detected = np.array(detection[2:], float)
        # keep the convention of the initial box (e.g. a margin around the body), learned from a clear dancer's
        # detections (``late_ratio_samples`` 0: only from a detection in the start frame)
        if retrack and c.late_ratio_samples and (d.size_ratio is None or d.ratio_samples):
            self._learn_late_ratio(d, detected)
        size = (1 - a) * np.array(d.box[2:]) + a * self._detected_size(d, detection)
        d.offset = np.clip((1 - a) * d.offset + a * (box_centre(detection) - centre), -c.max_box_offset * size,
                           c.max_box_offset * size)
        d.box = box_at(centre + d.offset, (0.0, 0.0, float(size[0]), float(size[1])))
        if retrack and abs(np.log(size[1] / d.tracker.base_size[1])) > np.log(c.retrack_scale):
            d.offset = np.zeros(2)
            d.tracker.init(frame, self._core(d.box))

    def _learn_late_ratio(self, d: DancerTrack, detected: np.ndarray) -> None:
        """Dancer ``d``'s ratio of box to detection (``detected``: its (w, h) px), learned after its start frame:
        the first clear detection fixes the reference box (the box then, as given at the start or correction), and
        each further one up to ``late_ratio_samples`` within ``late_ratio_frames`` of it adds its ratio to that
        box; the ratio is the median of those taken (:meth:`_size_ratio` limits)."""
        c = self.config
        if d.size_ratio is None:
            d.ratio_box, d.ratio_since, d.ratio_samples = np.array(d.box[2:], float), self.frame_index, []
            d.ratio_aspect = None  # a margin is taken only from a detection in the start box's own frame
        elif self.frame_index - d.ratio_since > c.late_ratio_frames:
            d.ratio_samples = []  # the dancer may have changed its posture since: the ratio stays as learned
            return
        d.ratio_samples.append(self._size_ratio(d.ratio_box, detected))
        d.size_ratio = np.median(np.array(d.ratio_samples), axis=0)
        if len(d.ratio_samples) >= c.late_ratio_samples:
            d.ratio_samples = []

    def _feet_hidden(self, d: DancerTrack, detection):
        """``detection`` (x, y, w, h px) of dancer ``d``, with its bottom moved down to that of ``d``'s box when it
        ends higher on the body of a dancer standing in front of ``d`` (box bottom ``pixel_front`` x the height
        lower in the image): the detector sees only the part above, and the amodal box keeps the hidden legs.
        Unchanged with ``keep_hidden_feet`` off."""
        c = self.config
        if not c.keep_hidden_feet:
            return detection
        x, y, w, h = (float(v) for v in detection)
        bottom, cx = y + h, x + w / 2
        box_bottom = d.box[1] + d.box[3]
        if bottom >= box_bottom:
            return detection
        for o in self.dancers:
            if o is d or o.status == OUT:
                continue
            ox, oy, ow, oh = o.box
            if stands_in_front(o.box, d.box, c.pixel_front) and ox <= cx <= ox + ow and oy <= bottom <= oy + oh:
                return (x, y, w, box_bottom - y)
        return detection

    def _sides_hidden(self, d: DancerTrack, detection, as_detection: bool = False):
        """``detection`` (x, y, w, h px) of dancer ``d``, widened to the width of ``d``'s box when it is narrower
        and a side of it ends on the body of a dancer standing in front of ``d`` (:meth:`_front_cut_sides`): the
        detector sees only the part beside him, and the amodal box keeps the part behind. The other side stays
        where it was seen; when both sides end on dancers in front, the box is centred on the detection.
        ``as_detection``: widened instead to the detection width that :meth:`_box_size` (not cut by the frame's
        edge) turns into the box's width (for :meth:`_adapt_box`, which applies the dancer's box-to-detection ratio;
        the box would otherwise grow by that ratio at every adaptation). Unchanged unless ``keep_hidden_sides`` is
        "tracked"."""
        if self.config.keep_hidden_sides != "tracked":
            return detection
        x, y, w, h = (float(v) for v in detection)
        width = float(d.box[2])
        if as_detection:  # invert _box_size, linear in the detection's width: box width = slope x width + offset
            offset = self._box_size(d, (0.0, h))[0]
            width = (width - offset) / (self._box_size(d, (1.0, h))[0] - offset)
        if not w < width:
            return detection
        left, right = self._front_cut_sides(d, detection)
        if left and right:
            return (x + w / 2 - width / 2, y, width, h)
        if right:
            return (x, y, width, h)
        if left:
            return (x + w - width, y, width, h)
        return detection

    def _front_cut_sides(self, d: DancerTrack, detection) -> tuple[bool, bool]:
        """Whether the left and the right side of ``detection`` (x, y, w, h px) of dancer ``d`` end on the body of a
        dancer standing in front of ``d`` (:func:`stands_in_front` with ``pixel_front``): that side inside his box's
        columns, the detection's middle row inside his rows."""
        x, y, w, h = (float(v) for v in detection)
        middle = y + h / 2
        columns = [(o.box[0], o.box[0] + o.box[2]) for o in self.dancers if o is not d and o.status != OUT and
                   stands_in_front(o.box, d.box, self.config.pixel_front) and o.box[1] <= middle <= o.box[1] + o.box[3]]
        return tuple(any(x0 < edge < x1 for x0, x1 in columns) for edge in (x, x + w))

    def _note_hidden_sides(self, d: DancerTrack, detection, as_box: bool = False) -> None:
        """With ``keep_hidden_sides`` "written", note on dancer ``d`` (before its box adapts to, or is taken at,
        ``detection``, x, y, w, h px) which sides of the detection end on a dancer in front (:meth:`_front_cut_sides`)
        when the box it makes (:meth:`_box_size`; ``as_box``: the detection itself, as :meth:`_take` takes it) is
        narrower than ``d``'s box, or than the width noted at the first such cut; the width is noted as an aspect
        (width / height of the box then) so that it follows the box's height. A detection not cut so, or as wide,
        clears the note. The written box then reaches that width behind the dancer in front
        (:meth:`ReportedExtent._hidden_sides_reach`); the tracked box follows the part seen."""
        if self.config.keep_hidden_sides != "written":
            return
        x, y, w, h = (float(v) for v in detection)
        width = d.hidden_aspect * d.box[3] if d.hidden_aspect is not None else float(d.box[2])
        made = w if as_box else self._box_size(d, (w, h))[0]
        sides = self._front_cut_sides(d, detection) if made < width else (False, False)
        if not any(sides):
            d.hidden_aspect, d.hidden_sides = None, (False, False)
            return
        if d.hidden_aspect is None:
            d.hidden_aspect = float(d.box[2]) / float(d.box[3])
        d.hidden_sides = sides

    def _hidden_parts(self, d: DancerTrack, detection, as_detection: bool = False):
        """``detection`` with the parts a dancer in front hides made good: :meth:`_sides_hidden` (with
        ``as_detection``), then :meth:`_feet_hidden`."""
        return self._feet_hidden(d, self._sides_hidden(d, detection, as_detection))

    def _feet_in_foreground(self, d: DancerTrack, frame, detection):
        """``detection`` (x, y, w, h px) of clear dancer ``d``, with its bottom moved down to where the foreground
        (:meth:`_foreground`) below it ends, when it runs on down from there: the detector left out legs whose
        colours are rare in the background (seed 2915 hip-hop: yellow chequered trousers, detections 90-150 px
        tall on a dancer 245 px tall). Rows are counted in the middle half of the detection's columns, less those
        in another dancer's box reaching below the detection (that foreground may be theirs); a row counts when
        ``foreground_feet_rows`` of them hold foreground, and the run may break for ``pixel_gap`` rows. The bottom
        moves at most ``foreground_feet`` x the detection's height, or down to the box's bottom if that is lower.
        Unchanged with ``foreground_feet`` None."""
        c = self.config
        if c.foreground_feet is None:
            return detection
        fg = self._foreground(frame)
        if fg is None:
            return detection
        x, y, w, h = (float(v) for v in detection)
        height, width = fg.shape
        x0, x1 = max(0, int(round(x + w / 4))), min(width, int(round(x + 3 * w / 4)))
        top = max(0, int(round(y + h)))
        bottom_row = min(height, int(round(max(y + h + c.foreground_feet * h, d.box[1] + d.box[3]))))
        if x1 - x0 < 4 or bottom_row <= top:
            return detection
        counted = ~self._columns_of_others(d, x0, x1, (width, height), below=top)
        if counted.sum() < 0.5 * (x1 - x0):
            return detection
        filled = fg[top:bottom_row, x0:x1][:, counted].sum(axis=1) >= c.foreground_feet_rows * counted.sum()
        last, gap = -1, 0  # the last row of the run from the detection's bottom
        for row, full in enumerate(filled):
            gap = 0 if full else gap + 1
            if gap > c.pixel_gap:
                break
            if full:
                last = row
        return detection if last < 0 else (x, y, w, h + float(last + 1))

    def _clear_velocity(self, d: DancerTrack) -> np.ndarray:
        """Dancer ``d``'s velocity (px/frame) fitted on its clear track (:meth:`_fit_velocity`), at most
        ``max_speed`` box heights per frame, and up or down the image at most ``max_vertical_speed``."""
        c = self.config
        v = self._fit_velocity(d.clear_track, c.max_speed * d.box[3])
        if c.max_vertical_speed > 0:
            limit = c.max_vertical_speed * d.box[3]
            v[1] = float(np.clip(v[1], -limit, limit))
        return v

    @staticmethod
    def _fit_velocity(track, max_speed: float = np.inf) -> np.ndarray:
        """Least-squares velocity (px/frame) through (frame, centre) samples, at most ``max_speed`` px/frame;
        zero with fewer than 2."""
        if len(track) < 2:
            return np.zeros(2)
        f = np.array([ft for ft, _ in track], float)
        p = np.array([pt for _, pt in track], float)
        f -= f.mean()
        v = (f[:, None] * (p - p.mean(axis=0))).sum(axis=0) / (f ** 2).sum()
        speed = float(np.linalg.norm(v))
        return v * (max_speed / speed) if speed > max_speed else v

    def _failed(self, d: DancerTrack, frame, overlapping: list[int], boxes) -> bool:
        c = self.config
        similarity = self._memory_match(d, frame)
        stored_speed = float(np.linalg.norm(d.stored_velocity))
        if len(d.centers) > c.motion_window and not self._in_front_of_all(d, overlapping):  # a full window since
            # (re)start, and someone there could have taken its tracker (``front_keeps_motion``)
            steps = len(d.centers) - 1
            motion = d.recent_motion
            moved = float(np.linalg.norm(motion)) * steps
            if stored_speed >= c.min_speed:
                if moved >= c.min_motion_px and angle_between(motion, d.stored_velocity) > c.failure_angle_deg:
                    return True
                expected = stored_speed * steps
                if expected >= c.min_motion_px and (moved < 0.3 * expected or moved > 2.5 * expected + 2 * steps):
                    return True
            elif moved > c.min_motion_px + 0.05 * d.box[3] and not self._couple_in_hold(d, overlapping) and (
                    not c.still_needs_follower or self._moves_with(motion, overlapping)
                    or similarity < c.still_histogram):
                return True  # a still dancer that suddenly moves off with an overlapping one, or onto another look
        if d.tracker.confidence < c.failure_psr:
            return True
        if similarity < c.failure_histogram:
            return True
        # two trackers on the same person: the one that matches its memory worse has failed
        for j in overlapping:
            o = self.dancers[j]
            if o.status == TRACKED and self._on_same_person(d, o):
                if c.waiting_yields and o.hidden_behind == d.dancer_id:
                    continue  # o still waits hidden behind d: d is the dancer seen there (o yields in its own test)
                if c.waiting_yields and d.hidden_behind == o.dancer_id:
                    return True
                other_similarity = self._memory_match(o, frame)
                if similarity < other_similarity:
                    return True
        return False

    def _on_same_person(self, d: DancerTrack, o: DancerTrack) -> bool:
        """Whether the boxes of dancers ``d`` and ``o`` may be on one person: IoU above ``same_person_iou``, or
        (``same_person_inside``) ``d``'s box that much inside ``o``'s, the two of about one height, while a person of
        ``d``'s height that no tracked dancer takes has been seen on ``same_person_stray`` detector frames in a row
        (someone the tracking accounts for nowhere; without one, a box inside another's is a couple in hold)."""
        c = self.config
        if box_iou(d.box, o.box) > c.same_person_iou:
            return True
        return c.same_person_inside is not None and box_inside(d.box, o.box) >= c.same_person_inside \
            and height_within(d.box, o.box, c.same_person_height) \
            and any(n >= c.same_person_stray and self._height_fits(d, det, c.same_person_height)
                    for det, n in self.unclaimed)

    def _stranger_in_front(self, frame, d: DancerTrack, detection, detections) -> bool:
        """With ``stranger_in_front``, whether ``detection`` (x, y, w, h px), the one person on clear dancer ``d``'s
        box, is someone nobody tracks standing in front of it: at least ``stranger_height`` x as tall as its box, its
        bottom at least ``stranger_lower`` x that height lower in the image, its colours matching ``d``'s memory less
        than ``stranger_in_front``, no other tracked dancer taking it in the assignment of this frame's
        ``detections`` (:meth:`_claims`; a dancer beside ``d`` whose detection reaches over ``d``'s box), and no
        other dancer's box, waiting or occluded ones' included, on it (IoU ``stranger_accounted`` or more): a
        person the tracking places nowhere."""
        c = self.config
        if c.stranger_in_front is None or d.stored_histogram is None:
            return False
        if detection[3] < c.stranger_height * d.box[3] or not stands_in_front(detection, d.box, c.stranger_lower):
            return False
        hist = self._histogram(frame, detection)
        if hist is None or histogram_similarity(hist, d.stored_histogram) >= c.stranger_in_front:
            return False
        if any(o is not d and o.status != OUT and box_iou(o.box, detection) >= c.stranger_accounted
               for o in self.dancers):
            return False
        dets = [tuple(float(v) for v in det) for det in detections]
        detection = tuple(float(v) for v in detection)
        if detection not in dets:  # a weak detection (``weak_detections``): assigned along with the sure ones
            dets.append(detection)
        k = dets.index(detection)
        return all(taken != k or i == d.dancer_id for i, taken in self._claims(dets).items())

    def _in_front_of_all(self, d: DancerTrack, overlapping: list[int]) -> bool:
        """With ``front_keeps_motion``, whether dancer ``d`` stands in front of every dancer it overlaps (indices
        ``overlapping``, at least one): box bottom lower by ``pixel_front`` x the height, or (``waiting_counts_behind``)
        that dancer waits hidden behind ``d`` since its start."""
        c = self.config
        return c.front_keeps_motion and bool(overlapping) and all(
            stands_in_front(d.box, self.dancers[j].box, c.pixel_front)
            or (c.waiting_counts_behind and self.dancers[j].hidden_behind == d.dancer_id) for j in overlapping)

    def _couple_in_hold(self, d: DancerTrack, overlapping: list[int]) -> bool:
        """Whether ``d`` and the dancers it overlaps (indices ``overlapping``) are a couple in hold
        (``couple_moves_together``): ``d`` started overlapping exactly one dancer, overlaps no other now, and has
        never been clear long enough to measure a velocity. Its lack of a stored velocity then says nothing about
        whether it stood still, and moving with its partner is no sign of a tracker dragged along."""
        return (self.config.couple_moves_together and not d.velocity_measured and len(d.start_partners) == 1
                and set(overlapping) <= d.start_partners)  # indices are dancer ids

    def _moves_with(self, motion: np.ndarray, overlapping: list[int]) -> bool:
        """Whether ``motion`` (px/frame) is that of one of the dancers ``overlapping`` (indices): within
        ``follower_angle_deg`` of its direction and ``follower_speed_ratio`` of its speed. A tracked dancer's motion
        is measured over its recent centres, an occluded one's is its stored velocity."""
        c = self.config
        speed = float(np.linalg.norm(motion))
        for j in overlapping:
            o = self.dancers[j]
            theirs = o.recent_motion if o.status == TRACKED and len(o.centers) > 1 else o.stored_velocity
            their_speed = float(np.linalg.norm(theirs))
            if their_speed < 1e-6 or speed < 1e-6:
                continue
            if angle_between(motion, theirs) <= c.follower_angle_deg and \
                    1 / c.follower_speed_ratio <= speed / their_speed <= c.follower_speed_ratio:
                return True
        return False

    def _own_box_stays(self, d: DancerTrack, own) -> bool:
        """Whether occluded dancer ``d``'s own tracker's box ``own`` (x, y, w, h px) has its bottom within
        ``own_box_max_shift`` x ``d``'s box height of the bottom of ``d``'s box (always, with the test off); never
        for a dancer lost on the background (``lost_on_background``: its tracker is what drifted there) or hidden
        behind a person nobody tracks (``behind_stranger``: its box shows that person)."""
        c = self.config
        if d.lost_on_background or d.behind_stranger or (not c.waiting_own_box and d.hidden_behind is not None):
            return False
        speed = float(np.linalg.norm(d.stored_velocity))
        if c.own_box_max_back is not None and speed >= c.min_speed:
            ahead = float(np.dot(box_centre(own) - box_centre(d.box), d.stored_velocity / speed))
            if ahead < -c.own_box_max_back * d.box[2]:
                return False
        limit = c.own_box_max_shift
        if limit is None:
            return True
        return abs((own[1] + own[3]) - (d.box[1] + d.box[3])) <= limit * d.box[3]

    def _height_fits(self, d: DancerTrack, detection, factor: float | None = None) -> bool:
        """Whether ``detection`` (x, y, w, h px), its bottom made good where a dancer in front hides the legs
        (:meth:`_feet_hidden`), is within ``factor`` (default ``reid_height_change``) of dancer ``d``'s box height: a
        candidate of re-identification and relocation."""
        factor = self.config.reid_height_change if factor is None else factor
        return height_within(self._feet_hidden(d, detection), d.box, factor)

    def _relocate(self, d: DancerTrack, frame, detections, force: bool, extra=()) -> None:
        """Occluded dancer ``d`` is taken again on the candidate (x, y, w, h px) whose colours match its memory
        best: the cone's patches that show someone (:meth:`_cone_candidates`, :meth:`_shows_someone`), the
        ``detections`` in the cone within ``reid_height_change`` of its box height (``relocate_height_change``) and
        ``extra`` (its own tracker's box); none that is another tracked dancer's (IoU > 0.5). Below
        ``relocate_min_similarity`` it stays occluded, unless ``force``."""
        c = self.config
        patches, found = self._cone_candidates(d, detections)
        if c.relocate_height_change:  # as in re-identification: a detection of another height is someone else
            found = [det for det in found if self._height_fits(d, det)]
        if c.relocate_holder_cores:  # a box around another dancer (and the hidden one) is not the hidden one's
            found = [det for det in found if not self._around_a_pile(d, det, c.relocate_holder_cores)]
        # the cone's patches are guesses, and those on background are no candidates; the dancer's own tracker
        # (``extra``) and the detections saw something there
        if not c.relocate_patches:
            patches = []
        candidates = [b for b, shows in zip(patches, self._shows_someone(frame, d, patches)) if shows] + found + \
            [tuple(b) for b in extra]
        others = [o.box for o in self.dancers if o is not d and o.status == TRACKED]
        best, best_score = None, -np.inf
        for box in candidates:
            if max((box_iou(box, o) for o in others), default=0.0) > 0.5:
                continue  # that patch is another dancer's
            score = self._memory_match(d, frame, box)
            if score > best_score:
                best, best_score = box, score
        if best is None or (best_score < c.relocate_min_similarity and not force):
            return  # stay occluded; try again next frame
        self._take(d, best, best_score, seen_part=best in found)

    def _covered_fraction(self, d: DancerTrack, box) -> float:
        """The fraction of the body core of ``box`` (x, y, w, h px) inside the body cores of the tracked dancers
        but ``d`` (those in front that may hide it; :func:`hdvr.tracking.state.covered_fraction`)."""
        return covered_fraction(box, [o.box for o in self.dancers if o is not d and o.status == TRACKED],
                                self.config.core_aspect)

    def _clear_of_others(self, d: DancerTrack, box) -> bool:
        """Whether ``box`` (x, y, w, h px) overlaps the body core of no dancer in the frame but ``d``."""
        return all(self._bodies_overlap(box, o.box) <= self.config.overlap_threshold
                   for o in self.dancers if o is not d and o.status != OUT)

    @staticmethod
    def _wider_than(box, d: DancerTrack, factor: float, min_aspect: float = 0.0) -> bool:
        """Whether ``box`` (x, y, w, h px) is more than ``factor`` x as wide for its height as dancer ``d``'s box,
        counted at least ``min_aspect`` wide for its height: then it is a part of a dancer that YOLO drew as a person
        (e.g. an upper body with spread arms), not ``d``."""
        return box[2] / box[3] > factor * max(d.box[2] / d.box[3], min_aspect)

    def _shows_someone(self, frame, d: DancerTrack, boxes, min_foreground: float | None = None) -> list[bool]:
        """For each of ``boxes`` (x, y, w, h px) where dancer ``d`` might be: whether at least ``min_foreground``
        (default ``patch_min_foreground``) of its pixels outside the boxes of the other dancers in the frame (their
        foreground is theirs) are foreground. A patch of floor or wall is not a dancer however its colours match
        one's memory (hdvr synth seed 503 ballet: a dancer hidden behind another stopped, its predicted box moved on
        and was taken again on the wall beside them, similarity 0.68). The background colours are sampled outside
        the dancers' boxes and ``boxes`` (:func:`hdvr.tracking.appearance.foreground_mask`: a dancer standing there
        would otherwise count as background). True where the background cannot be told or nothing of a box is
        left."""
        c = self.config
        min_foreground = c.patch_min_foreground if min_foreground is None else min_foreground
        if min_foreground <= 0 or not boxes:
            return [True] * len(boxes)
        others = [o.box for o in self.dancers if o is not d and o.status != OUT]
        fg = self._foreground_around(frame, others + [d.box] + [tuple(b) for b in boxes])
        size = (frame.shape[1], frame.shape[0])
        others_clipped = [b for b in (clip_box(o, size) for o in others) if b is not None]
        shows = []
        for box in boxes:
            r = clip_box(box, size)
            if fg is None or r is None:
                shows.append(True)
                continue
            x0, y0, x1, y1 = r
            counted = np.ones((y1 - y0, x1 - x0), bool)
            for b in others_clipped:
                counted[max(0, b[1] - y0):max(0, b[3] - y0), max(0, b[0] - x0):max(0, b[2] - x0)] = False
            shows.append(not counted.any() or float(fg[y0:y1, x0:x1][counted].mean()) >= min_foreground)
        return shows

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
