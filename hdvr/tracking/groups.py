"""Dancers that overlap one another, adapted together (part of Algorithm 1*, :mod:`hdvr.tracking.multi`).

While dancers overlap, no detection can be trusted to be one dancer alone. :class:`GroupAdaptation` assigns the
frame's person detections to all dancers at once (one assignment on :meth:`GroupAdaptation._fit_score`) and lets a
dancer take only the detection it fits unambiguously; the boxes of a group of overlapping dancers scale together
when their detections grow or shrink alike (a couple walking towards or away from the camera), and change their
shape only on a detection that is clearly theirs. With ``group_front_adapts`` (off by default: measured in session
88, it broke more clips than it mended) the box of a dancer in front of every dancer it overlaps follows its
detection.

:class:`GroupAdaptation` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's
``config`` (:class:`hdvr.tracking.config.MultiTrackerConfig`, the ``group_*`` fields), ``dancers``
(:class:`hdvr.tracking.state.DancerTrack`) and the tracker's geometry (``_core``, ``_bodies_overlap``,
``_boxes_now``, ``_box_size``, ``_single_person``, ...). Boxes are (x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from hdvr.tracking.appearance import box_inside, box_iou
from hdvr.tracking.geometry import height_within
from hdvr.tracking.state import OCCLUDED, OUT, DancerTrack, box_at, box_centre, stands_in_front


class GroupAdaptation:
    """Detections assigned to overlapping dancers, and their boxes scaled together (mixin of the tracker)."""

    @staticmethod
    def _fit_score(box, det) -> float:
        """How well detection ``det`` fits dancer box ``box`` (both (x, y, w, h) px), in [0, 1]: the mean of their
        IoU and of the IoU of their vertical extents (spread arms change a dancer's width, hardly its height and
        vertical position); 0 unless the detection covers the box's centre line."""
        cx = box[0] + box[2] / 2
        if not det[0] <= cx <= det[0] + det[2]:
            return 0.0
        inter = min(box[1] + box[3], det[1] + det[3]) - max(box[1], det[1])
        union = max(box[1] + box[3], det[1] + det[3]) - min(box[1], det[1])
        y_iou = max(0.0, inter) / union if union > 0 else 0.0
        return 0.5 * (box_iou(box, det) + y_iou)

    def _in_front_of_group(self, d: DancerTrack, boxes) -> bool:
        """Whether dancer ``d`` stands in front of every dancer it overlaps (its box bottom ``group_front_margin`` x
        their height lower; at least one); ``boxes``: every dancer's box now (:meth:`_boxes_now`)."""
        overlapping = self._overlapping(self.dancers.index(d), boxes)
        margin = self.config.group_front_margin
        return bool(overlapping) and all(stands_in_front(d.box, boxes[j], margin) for j in overlapping)

    def _adapt_front_in_group(self, frame, group: list[DancerTrack], detections, weak=()) -> None:
        """With ``group_front_adapts``: the dancers of ``group`` standing in front of every dancer they overlap
        (:meth:`_in_front_of_group`) are seen whole; each box follows the detection assigned to it unambiguously
        (:meth:`_unambiguous_detections`, height within ``max_height_change`` of the box's) with weight
        ``group_front_adapts``: its size and centre, its centre only, its centre's height and the box's height, or
        its height with its bottom kept (``group_front_parts``); with ``group_front_match``, only while the
        detection matches the dancer's stored colours that much better than its box does; with
        ``group_front_after``, only that many frames after the box was last placed for sure; with
        ``group_front_aspect``, not to a detection that much narrower for its height than the box; with
        ``group_front_max_iou``, only to a detection overlapping the box less than that. The tracker is not
        restarted. Off by default: measured in session 88 (docs/benchmarks.md), more clips broken than mended."""
        c = self.config
        boxes = self._boxes_now(self.dancers)
        front = [d for d in group if self._in_front_of_group(d, boxes)]
        if not front or not (detections or weak):
            return
        assigned = self._unambiguous_detections(detections, weak)
        for d in front:
            det = assigned.get(d.dancer_id)
            if det is None or not height_within(det, d.box, c.max_height_change) or \
                    self.frame_index - d.stored_frame < c.group_front_after:
                continue
            if c.group_front_aspect is not None and det[2] / det[3] < c.group_front_aspect * d.box[2] / d.box[3]:
                continue
            if c.group_front_max_iou is not None and box_iou(d.box, det) >= c.group_front_max_iou:
                continue
            if c.group_front_match is not None and \
                    self._memory_match(d, frame, det) < self._memory_match(d, frame) + c.group_front_match:
                continue
            if c.group_front_parts == "box":
                self._adapt_box(d, frame, det, c.group_front_adapts, retrack=False)
            elif c.group_front_parts == "height":  # as in front of dancers waiting behind it: its bottom kept
                self._adapt_height(d, det, c.group_front_adapts)
            else:
                self._follow_centre(d, det, c.group_front_adapts, vertical=c.group_front_parts == "vertical")

    def _follow_centre(self, d: DancerTrack, detection, weight: float, vertical: bool) -> None:
        """The centre of dancer ``d``'s box moves ``weight`` of the way towards that of ``detection`` (x, y, w, h
        px) through its offset from the tracker's centre (at most ``max_box_offset`` x the box size), its size kept;
        ``vertical``: only the centre's height, and the box's height moves as far towards the detection's (times
        the dancer's learned ratio, :meth:`_detected_size`)."""
        c = self.config
        centre = np.asarray(d.tracker.center, float)
        size = np.array(d.box[2:], float)
        if vertical:
            size[1] = (1 - weight) * size[1] + weight * float(self._detected_size(d, detection)[1])
        offset = (1 - weight) * d.offset + weight * (box_centre(detection) - centre)
        if vertical:
            offset[0] = d.offset[0]
        d.offset = np.clip(offset, -c.max_box_offset * size, c.max_box_offset * size)
        d.box = box_at(centre + d.offset, (0.0, 0.0, float(size[0]), float(size[1])))

    def _adapt_in_group(self, frame, group: list[DancerTrack], detections, weak=()) -> None:
        """Boxes of tracked dancers that overlap others adapt to detections that can be assigned to them
        unambiguously (:meth:`_unambiguous_detections`) and whose height is within ``max_height_change`` of the
        box's. The box moves ``group_adaptation`` of the way towards it (size and offset from the tracker's centre,
        as for a clear dancer); the tracker is not restarted (its template would take in the dancers around)."""
        c = self.config
        if not group or not (detections or weak):
            return
        assigned = self._unambiguous_detections(detections, weak)
        for d in group:
            det = assigned.get(d.dancer_id)
            if det is not None and height_within(det, d.box, c.max_height_change):
                self._adapt_box(d, frame, det, c.group_adaptation, retrack=False)

    def _unambiguous_detections(self, detections, weak=()) -> dict[int, tuple[float, float, float, float]]:
        """Dancer id -> the detection (x, y, w, h px) assigned to it unambiguously: one assignment (Hungarian, on
        :meth:`_fit_score`) of ``detections`` to all dancers in the frame (occluded ones at their predicted boxes);
        a dancer takes its detection when the fit is at least ``group_min_score`` and better by ``group_margin``
        than that of every other dancer. The same with ``weak`` detections then gives those dancers still without
        one theirs."""
        assigned = self._unambiguous_assignment(detections)
        if weak:
            for dancer_id, det in self._unambiguous_assignment(weak).items():
                assigned.setdefault(dancer_id, det)
        return assigned

    def _unambiguous_assignment(self, detections) -> dict[int, tuple[float, float, float, float]]:
        """One round of :meth:`_unambiguous_detections`, on ``detections`` alone."""
        c = self.config
        dets = [tuple(float(v) for v in det) for det in detections]
        live = [d for d in self.dancers if d.status != OUT]
        if not dets or not live:
            return {}
        boxes = self._boxes_now(live)
        score, pairs = self._fit_assignment(boxes, dets)
        assigned = {}
        for i, k in pairs:
            others = np.delete(score[:, k], i)
            if not (others.size and others.max() > score[i, k] - c.group_margin):
                assigned[live[i].dancer_id] = dets[k]
        return assigned

    def _fit_assignment(self, boxes, dets) -> tuple[np.ndarray, list[tuple[int, int]]]:
        """One assignment (Hungarian) of detections ``dets`` to dancer ``boxes`` (both (x, y, w, h) px) on
        :meth:`_fit_score`: the score matrix (boxes x detections) and the (box, detection) index pairs whose fit
        is at least ``group_min_score``."""
        score = np.array([[self._fit_score(b, det) for det in dets] for b in boxes])
        pairs = [(int(i), int(k)) for i, k in zip(*linear_sum_assignment(-score))
                 if score[i, k] >= self.config.group_min_score]
        return score, pairs

    def _groups(self, dancers: list[DancerTrack]) -> list[list[DancerTrack]]:
        """``dancers`` split into groups: connected by body cores that overlap (``overlap_threshold``)."""
        c, left, groups = self.config, list(dancers), []
        while left:
            group, todo = [], [left.pop(0)]
            while todo:
                d = todo.pop()
                group.append(d)
                joined = [o for o in left if self._bodies_overlap(d.box, o.box) > c.overlap_threshold]
                left = [o for o in left if o not in joined]
                todo += joined
            groups.append(group)
        return groups

    def _scale_groups(self, group: list[DancerTrack], detections, weak=()) -> None:
        """The boxes of tracked dancers overlapping one another (``group``) grow or shrink with their detections.

        A dancer's box keeps its size while it overlaps others (it adapts to detections only while clear), so a
        couple that dances towards or away from the camera without parting keeps boxes of the size it had when it
        met (seed 137 tango of ``hdvr synth``: ground truth 249 -> 173 px tall, boxes 249 px). Per group of
        overlapping dancers (:meth:`_groups`) with no occluded dancer among them and each holding a detection
        unambiguously (:meth:`_unambiguous_detections`): the first such frame records each dancer's detected and
        box heights (``group_reference``); later, each dancer's scale change is its detection's height change
        since then relative to its box's, and when these agree within ``group_scale_agreement`` (a detection cut
        by the dancer in front changes alone) and their geometric mean is within ``max_height_change``, every box
        is scaled about its centre by ``group_scale_adaptation`` of that mean (in log). Relative changes, not
        sizes: a box of a dancer that met others keeps its size convention (e.g. the margin of the initial box),
        whatever the detector draws. The tracker's template is not changed. The reference is dropped while the
        dancer is clear of others. With ``group_scale_shared``, a group whose dancers do not each hold a detection
        but share one person box (:meth:`_shared_detection`: the detector drew a couple in hold as one person)
        takes that box's height as every member's detected height; a change between shared and own detections
        starts a new reference. With ``group_scale_front``, a lone dancer whose overlapping dancers are all occluded
        behind it (box bottom ``pixel_front`` x their height lower), each waiting there since its start
        (``hidden_behind``), is such a group on its own, with its own unambiguous detection: a couple walking
        towards the camera with one hidden behind the other all along kept the front box's size (seed 1203 swing)."""
        c = self.config
        for d in self.dancers:
            if d not in group:
                d.group_reference = None
        if len(group) < (1 if c.group_scale_front else 2) or not (detections or weak):
            return
        assigned = self._unambiguous_detections(detections, weak)
        for members in self._groups(group):
            hidden = [o for o in self.dancers if o.status == OCCLUDED
                      and any(self._bodies_overlap(o.box, m.box) > c.overlap_threshold for m in members)]
            # a dancer in front of dancers waiting hidden behind it since their start scales alone
            front = c.group_scale_front and len(members) == 1 and hidden and members[0].dancer_id in assigned \
                and all(o.hidden_behind is not None and stands_in_front(members[0].box, o.box, c.pixel_front)
                        for o in hidden)
            if not front and (len(members) < 2 or hidden):
                continue
            heights = {m.dancer_id: assigned[m.dancer_id][3] for m in members if m.dancer_id in assigned}
            shared = len(heights) < len(members)
            if shared:  # one person box over the whole group (a couple in hold seen as one): its height for all
                det = self._shared_detection(members, detections) if c.group_scale_shared else None
                if det is None:
                    continue
                heights = {m.dancer_id: det[3] for m in members}
            if any(m.group_reference is None or m.group_reference[2] != shared for m in members):
                for m in members:
                    m.group_reference = (heights[m.dancer_id], m.box[3], shared)
                continue
            change = np.array([heights[m.dancer_id] / m.group_reference[0] * m.group_reference[1] / m.box[3]
                               for m in members])
            if change.max() / change.min() > c.group_scale_agreement:
                continue
            log_change = float(np.log(change).mean())
            if abs(log_change) > np.log(c.max_height_change):
                continue
            factor = float(np.exp(c.group_scale_adaptation * log_change))
            for m in members:
                m.box = box_at(box_centre(m.box), (0.0, 0.0, m.box[2] * factor, m.box[3] * factor))

    def _reshape_in_group(self, group: list[DancerTrack], detections) -> None:
        """A dancer of ``group`` (tracked, overlapping others) whose box has a floor shape (at least
        ``group_reshape_min_aspect`` x its height wide) while its unambiguous sure detection
        (:meth:`_unambiguous_assignment`) shows an upright person (width / height ``group_reshape_aspect`` below the
        box's) on ``group_reshape_after`` detector frames in a row, and which stands in front of every dancer it
        overlaps (the detection shows all of it), takes the detection's aspect at its box's height, centred on the
        detection. Group scaling keeps a box's aspect, so a box that took a floor shape (a dancer down, or two
        dancers drawn as one person) kept it for as long as the dancer overlapped others (seed 1512 hip-hop)."""
        c = self.config
        for d in self.dancers:
            if d not in group:
                d.reshape_streak = 0
        if not group:
            return
        assigned = self._unambiguous_assignment(detections)
        boxes = self._boxes_now(self.dancers)
        for d in group:
            det = assigned.get(d.dancer_id)
            box_aspect = d.box[2] / d.box[3]
            upright = det is not None and box_aspect >= c.group_reshape_min_aspect and \
                box_aspect / (det[2] / det[3]) > c.group_reshape_aspect and \
                height_within(det, d.box, c.max_height_change)
            in_front = all(stands_in_front(d.box, self.dancers[j].box, c.pixel_front)
                           for j in self._overlapping(self.dancers.index(d), boxes))
            d.reshape_streak = d.reshape_streak + 1 if upright and in_front else 0
            if d.reshape_streak >= c.group_reshape_after:
                width = d.box[3] * det[2] / det[3]
                d.box = (det[0] + det[2] / 2 - width / 2, d.box[1], width, d.box[3])
                d.offset = box_centre(d.box) - np.asarray(d.tracker.center, float)
                d.reshape_streak = 0

    def _shared_detection(self, members: list[DancerTrack], detections):
        """The one detection (x, y, w, h px) that holds the body cores of all ``members`` (each at least
        ``group_shared_inside`` inside it) when no other detection overlaps any of those cores (intersection / core
        more than ``overlap_threshold``); else None."""
        c = self.config
        cores = [self._core(m.box) for m in members]
        touching = [det for det in detections if any(box_inside(core, det) > c.overlap_threshold for core in cores)]
        if len(touching) != 1 or any(box_inside(core, touching[0]) < c.group_shared_inside for core in cores):
            return None
        return tuple(float(v) for v in touching[0])
