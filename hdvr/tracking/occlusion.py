"""Tracking failures, occlusion, prediction and cone relocation (steps 2, 3 and 5 of Algorithm 1*).

While a dancer overlaps others its tracker does not learn; a *tracking failure* shows as a sudden change of motion
(:meth:`OcclusionHandling._failed`: direction turned, a stall or a jump, or a box that moves like a dancer it
overlaps) or a histogram that no longer matches. The dancer is then *occluded* (:meth:`OcclusionHandling._occlude`):
its box moves on with the velocity fitted on its clear track (:meth:`OcclusionHandling._clear_velocity`), the frame
where the overlap ends is predicted (:meth:`OcclusionHandling._predict_overlap_end`), and from then on it is
*relocated* (:meth:`OcclusionHandling._relocate`) to the candidate in a cone along its motion
(:meth:`OcclusionHandling._cone`) whose histogram correlates best with the stored one.

:class:`OcclusionHandling` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's
``config`` (:class:`hdvr.tracking.config.MultiTrackerConfig`), ``dancers`` (:class:`hdvr.tracking.state.DancerTrack`),
``frame_index`` and the tracker's geometry and histogram methods. Boxes are (x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import box_inside, box_iou, clip_box, histogram_similarity
from hdvr.tracking.geometry import angle_between, box_behind, height_within, shifted
from hdvr.tracking.state import OCCLUDED, OUT, TRACKED, DancerTrack, box_centre, covered_fraction, stands_in_front


class OcclusionHandling:
    """Failure tests, occlusion, overlap-end prediction and cone relocation (mixin of the tracker)."""

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
