"""Occluded and lost dancers found again (steps 4 and 6 of Algorithm 1*, :mod:`hdvr.tracking.multi`).

:class:`Reidentification` re-identifies occluded dancers that show clearly again before the predicted end of their
overlap (own tracker's box or a detection clear of every tracked dancer, whose colour histogram matches the stored
one well and better than any other occluded dancer's, best matches first), lets an occluded dancer that nothing
found take a *stray person* (a detection no tracked dancer takes, seen on several detector frames in a row, whose
colours match its memory), hands a dancer waiting hidden over to the dancer it now stands behind, and searches the
whole frame for dancers lost on the background. A clear dancer whose box has held no detected person for
``max_missed_detections`` detector frames (lost in a jump, say) moves to a person nearby that no one tracks when its
colours match clearly better there (:meth:`Reidentification._jump_to_detection`), and its tracker restarts.

:class:`Reidentification` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's
``config`` (:class:`hdvr.tracking.config.MultiTrackerConfig`, the ``reid_*``, ``stray_*`` and ``lost_*`` fields),
``dancers`` (:class:`hdvr.tracking.state.DancerTrack`) and the tracker's histogram and geometry methods. Boxes are
(x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import box_inside, box_iou, clip_box, colour_bins, histogram_similarity
from hdvr.tracking.geometry import chain_length, height_within, likely_windows, offset_behind
from hdvr.tracking.state import OCCLUDED, OUT, TRACKED, DancerTrack, box_at, box_centre, stands_in_front


class Reidentification:
    """Occluded dancers re-identified, stray people taken, waiting dancers handed over, lost ones searched (mixin)."""

    def _reidentify(self, frame, occluded: list[DancerTrack], own_boxes: list, detections) -> None:
        """Occluded dancers that show clearly again take their place before the predicted end of the overlap.

        Candidates of each occluded dancer are its own tracker's box and the detections near its predicted or its
        last clear position (within :meth:`_reid_radius` box heights, growing with the frames since it was last
        seen clear) that no tracked dancer takes
        (:meth:`_claims`), within ``reid_height_change`` of its box height (bottom made good behind a dancer in
        front), if clear of every tracked dancer's body core. A detection may also overlap tracked
        dancers that each hold a detection of their own in that assignment, if its body core overlaps the
        core of theirs less than ``reid_held_overlap`` (``reid_beside_held``): then it is a second person beside
        them, not them nor a box around them (a dancer in front of a partner's spread arm; taking any detection
        that overlaps a tracked dancer cost IDF1 0.15-0.2 on procedural 4-dancer clips with the detector).
        With ``reid_beside_unheld``, a detection may also overlap (less than ``reid_held_overlap`` of the core)
        tracked dancers that hold no detection, e.g. one hidden behind a third dancer, when its height is within
        ``reid_unheld_height`` of the occluded dancer's box and its width / height at most ``reid_unheld_aspect`` x
        the box's (a wider one is a part of such a dancer that YOLO drew apart); those dancers' memories are then
        rivals too: the detection must match the occluded dancer's memory by ``reid_margin`` better than theirs,
        and (``reid_unheld_rival_height``) it may be at most that factor taller than each of them (a box around such
        a dancer and a figure beside it is taller). No detection that holds the body cores of ``reid_pile_cores``
        other dancers (:meth:`_around_a_pile`: a box around a pile of figures) re-identifies anyone.
        With ``reid_from_holder``, a detection that a tracked dancer takes is a candidate too when it stands in
        front of that dancer, covering its body core's width, and its colours match an occluded dancer's memory at
        least ``reid_similarity`` and by ``reid_margin`` better than the holder's (:meth:`_handed_over`; the holder
        is then one more rival); if the occluded dancer takes it, the holder, whose box showed that dancer in front
        of it, is occluded (:meth:`_occlude`) and forgets the size ratio it may have learned from the detection.
        Matched by :meth:`_histogram_matches` against the other occluded dancers' memories."""
        c = self.config
        if not occluded:
            return
        tracked = [o for o in self.dancers if o.status == TRACKED]
        dets = [tuple(float(v) for v in det) for det in detections or []]
        claims = self._claims(dets)
        handed = self._handed_over(frame, occluded, dets, claims) if c.reid_from_holder else {}
        claims = {i: k for i, k in claims.items() if dets[k] not in handed}
        free = [det for k, det in enumerate(dets) if k not in claims.values()]

        box_rivals: dict[tuple, list[DancerTrack]] = {}

        def clear(box, is_detection: bool, waiting=()) -> bool:
            # clear of every tracked dancer's body core (but those ``waiting`` behind the dancer looked for), or (a
            # detection) of every one that holds a detection of its own that this one does not mostly overlap (a box
            # around both, or a part of it), or of every one without a detection whose core it overlaps less than
            # half: then that dancer is one more rival
            rivals = []
            for o in tracked:
                if self._bodies_overlap(box, o.box) <= c.overlap_threshold or o.dancer_id in waiting:
                    continue
                if is_detection and handed.get(tuple(box)) is o:
                    rivals.append(o)
                    continue
                if is_detection and c.reid_beside_held and o.dancer_id in claims:
                    if self._bodies_overlap(box, dets[claims[o.dancer_id]]) < c.reid_held_overlap:
                        continue
                    return False
                if is_detection and c.reid_beside_unheld and o.dancer_id not in claims and \
                        o.stored_histogram is not None and self._bodies_overlap(box, o.box) < c.reid_held_overlap \
                        and (c.reid_unheld_rival_height is None or box[3] <= c.reid_unheld_rival_height * o.box[3]):
                    rivals.append(o)
                    continue
                return False
            if rivals:
                box_rivals[tuple(box)] = rivals
            return True

        candidates = []
        for d, own in zip(occluded, own_boxes):
            radius = d.box[3] * self._reid_radius(d)
            # the dancers waiting behind it show nothing of their own: their detections and cores are its
            waiting = {o.dancer_id for o in tracked if o.hidden_behind == d.dancer_id} if c.reid_past_waiting \
                else set()
            seen = free + [dets[k] for i, k in claims.items() if i in waiting]
            near = [det for det in seen if min(np.linalg.norm(box_centre(det) - d.center),
                                               np.linalg.norm(box_centre(det) - box_centre(d.stored_box))) <= radius]
            boxes = [box for box in near if clear(box, True, waiting)]
            # beside a dancer without a detection, a box of about the dancer's height only (YOLO's box around two
            # figures, or a figure and its shadow, is taller), and not much wider for its height (a part of the
            # dancer without a detection, e.g. its upper body with spread arms)
            boxes = [box for box in boxes if tuple(box) not in box_rivals
                     or (height_within(box, d.box, c.reid_unheld_height)
                         and not self._wider_than(box, d, c.reid_unheld_aspect))]
            boxes = [box for box in boxes if self._height_fits(d, box)]
            if c.reid_pile_cores:
                boxes = [box for box in boxes if not self._around_a_pile(d, box)]
            candidates.append((d, boxes + ([own] if clear(own, False) and self._own_box_stays(d, own) else [])))
        for d, box, score in self._histogram_matches(frame, candidates, occluded, box_rivals):
            self._take(d, box, score, seen_part=tuple(box) in dets)
            holder = handed.get(tuple(box))
            if holder is not None and holder.status == TRACKED:
                holder.size_ratio = None  # perhaps learned from that detection
                self._occlude(holder, [d])

    def _reid_radius(self, d: DancerTrack) -> float:
        """The re-identification radius of occluded dancer ``d``, in its box heights: ``2 x min_search_radius``,
        grown by ``reid_radius_growth`` for each frame since it was last seen clear, up to ``reid_radius_cap``."""
        c = self.config
        base = 2 * c.min_search_radius
        if c.reid_radius_growth <= 0:
            return base
        return min(max(base, c.reid_radius_cap), base + c.reid_radius_growth * (self.frame_index - d.stored_frame))

    def _around_a_pile(self, d: DancerTrack, box, cores: int | None = None) -> bool:
        """Whether ``box`` (x, y, w, h px) holds the body cores of ``cores`` (default ``reid_pile_cores``) or more
        dancers in the frame but ``d`` (each at least ``reid_pile_inside`` inside it; occluded ones at their
        predicted boxes)."""
        c = self.config
        others = [o for o in self.dancers if o is not d and o.status != OUT]
        held = sum(box_inside(self._core(b), box) >= c.reid_pile_inside for b in self._boxes_now(others))
        return held >= (c.reid_pile_cores if cores is None else cores)

    def _stray_people(self, detections) -> list[tuple[float, float, float, float]]:
        """Sure ``detections`` (x, y, w, h px) of this detector frame that no tracked dancer takes
        (:meth:`_claims`) and whose body core overlaps no tracked dancer's (``overlap_threshold``): people the
        tracking accounts for nowhere. Each continues the chain of a stray person of the detector frame before on
        which it lies (:func:`chain_length`; ``strays`` keeps each one's count of detector frames in a row).
        Returns those seen on ``orphan_persist`` detector frames in a row, this one included."""
        c = self.config
        dets = [tuple(float(v) for v in det) for det in detections]
        claimed = set(self._claims(dets).values())
        tracked = [o for o in self.dancers if o.status == TRACKED]
        unclaimed = [det for k, det in enumerate(dets) if k not in claimed]
        stray = [det for det in unclaimed if all(self._bodies_overlap(det, o.box) <= c.overlap_threshold
                                                 for o in tracked)]
        self.unclaimed = [(det, chain_length(self.unclaimed, det)) for det in unclaimed]
        self.strays = [(det, chain_length(self.strays, det)) for det in stray]
        return [det for det, n in self.strays if n >= c.orphan_persist]

    def _take_stray(self, frame, detections) -> None:
        """Occluded dancers (not those waiting since their start, ``hidden_behind``) take stray people
        (:meth:`_stray_people`) of about their height (:meth:`_height_fits`) wherever these are, matched by
        :meth:`_histogram_matches` against the other occluded dancers' memories (``orphan_persist``). Where the
        dancer came out from behind the others is not always where its stored motion led: a person the tracking
        accounts for nowhere, seen on several detector frames, and looking like the one dancer it has lost, is
        that dancer. With ``stray_adrift``, tracked dancers then take the people left that no tracked dancer takes
        and that were seen on as many detector frames in a row (clear of the tracked dancers or not: the box of the
        dancer it came out from behind may hold it), whose colours match their memory better
        (``stray_adrift_margin``) than their box does now, against every known dancer's memory."""
        c = self.config
        strays = self._stray_people(detections)  # on every detector frame: the chains must not break
        occluded = [d for d in self.dancers if d.status == OCCLUDED and d.hidden_behind is None]
        taken = []
        if strays and occluded:
            candidates = [(d, [det for det in strays if self._height_fits(d, det)]) for d in occluded]
            for d, box, score in self._histogram_matches(frame, candidates, occluded):
                self._take(d, box, score, seen_part=True)
                taken.append(box)
                self._forget_person(box)
        # with stray_adrift, any person no tracked dancer takes, seen so long, even on a tracked dancer's body
        people = [det for det, n in self.unclaimed if n >= c.orphan_persist and det not in taken]
        if not c.stray_adrift or not people:
            return
        # tracked dancers whose colours a stray person shows better than their box does: the box may have stayed
        # behind (in a group) while the dancer came out elsewhere; rivals: every dancer whose colours are known
        known = [d for d in self.dancers if d.status != OUT and d.hidden_behind is None
                 and d.stored_histogram is not None]
        histograms = {det: self._histogram(frame, det) for det in people}  # shared with _histogram_matches
        candidates = []
        for d in [o for o in known if o.status == TRACKED]:
            current = self._memory_match(d, frame)
            candidates.append((d, [det for det in people if self._height_fits(d, det, c.stray_adrift_height_change)
                                   and histogram_similarity(histograms[det], d.stored_histogram)
                                   >= current + c.stray_adrift_margin]))
        for d, box, score in self._histogram_matches(frame, candidates, known, histograms=histograms):
            self._restart(d, frame, self._hidden_parts(d, box), score)
            self._forget_person(box)
            if c.adrift_hands_over_waiting:
                self._hand_over_waiting(d)

    def _hand_over_waiting(self, d: DancerTrack) -> None:
        """Dancers still waiting behind dancer ``d`` since their start (``hidden_behind``) whose body core
        no longer overlaps ``d``'s box now that it was taken elsewhere, wait from now on behind the dancer followed
        that stands straight in front of them (:meth:`_straight_in_front` with ``hidden_start_overlap``; the one
        whose body core overlaps theirs most), at their offset from it now: ``d``'s box had stayed on that dancer,
        and so had theirs. One with no such dancer in front is left as it was."""
        c = self.config
        for o in self.dancers:
            if o.hidden_behind != d.dancer_id or o.status == OUT or \
                    self._bodies_overlap(o.box, d.box) > c.overlap_threshold:
                continue
            fronts = [f for f in self.dancers if f is not o and f is not d and f.status == TRACKED
                      and f.hidden_behind is None and self._straight_in_front(f, o, c.hidden_start_overlap)]
            if fronts:
                front = max(fronts, key=lambda f: self._bodies_overlap(f.box, o.box))
                o.hidden_behind, o.returned_behind = front.dancer_id, False
                o.wait_offset = offset_behind(o.box, front.box)

    def _search_lost(self, frame) -> None:
        """Dancers occluded for ``lost_search_after`` frames (and, with ``lost_search_out``, those whose prediction
        left the frame while occluded: ``out_unseen``) are looked for over the whole frame (every
        ``lost_search_every`` frames of their occlusion): :func:`likely_windows` of a back-projection of each one's
        memory against the colours of the frame (outside the tracked dancers' boxes), clear of every tracked dancer's
        body core, mostly in the frame and showing foreground (:meth:`_shows_someone`), matched one to one by
        :meth:`_histogram_matches` against the memories of all known dancers. A dancer found near the same place
        (IoU >= 0.3) on ``lost_search_persist`` searches in a row is taken there (a patch of its box's size)."""
        c = self.config
        t = self.frame_index
        searched = [d for d in self.dancers if d.status == OCCLUDED
                    or (c.lost_search_out and d.status == OUT and d.out_unseen)]
        lost = [d for d in searched if d.hidden_behind is None and d.stored_histogram is not None
                and t - d.occluded_since >= c.lost_search_after
                and (t - d.occluded_since - c.lost_search_after) % c.lost_search_every == 0]
        if not lost:
            return
        bins = colour_bins(frame)
        frame_share = np.bincount(bins.ravel(), minlength=len(lost[0].stored_histogram)) / bins.size
        tracked = [o.box for o in self.dancers if o.status == TRACKED]
        size = (frame.shape[1], frame.shape[0])
        outside_tracked = np.ones(bins.shape, np.float32)
        for r in (clip_box(b, size) for b in tracked):
            if r is not None:
                outside_tracked[r[1]:r[3], r[0]:r[2]] = 0.0
        side, end = self._histogram_shrink
        candidates = []
        for d in lost:
            memory = d.stored_histogram.astype(np.float64)
            # the share of each colour that is this dancer's rather than the frame's at large, per pixel
            own_share = (memory / np.maximum(memory + frame_share, 1e-9)).astype(np.float32)
            window = (d.box[2] * (1 - 2 * side), d.box[3] * (1 - 2 * end))
            centres = likely_windows(own_share[bins] * outside_tracked, window, c.lost_search_min_share)
            boxes = [box_at(p, d.box) for p in centres]
            boxes = [b for b in boxes if self._inside_fraction(b) >= c.learn_inside
                     and all(self._bodies_overlap(b, o) <= c.overlap_threshold
                             and box_inside(b, o) <= c.lost_search_max_inside for o in tracked)]
            candidates.append((d, [b for b, shows in zip(boxes, self._shows_someone(frame, d, boxes)) if shows]))
        known = [o for o in self.dancers if (o.status != OUT or o in lost) and o.hidden_behind is None
                 and o.stored_histogram is not None]
        found = {d.dancer_id: (box, score) for d, box, score in self._histogram_matches(frame, candidates, known)}
        for d in lost:
            box, score = found.get(d.dancer_id, (None, 0.0))
            if box is None:
                d.lost_candidate, d.lost_streak = None, 0
                continue
            again = d.lost_candidate is not None and box_iou(box, d.lost_candidate) >= 0.3
            d.lost_streak = d.lost_streak + 1 if again else 1
            d.lost_candidate = box
            if d.lost_streak >= c.lost_search_persist:
                if d.status == OUT:
                    self._back_in_frame(d, frame, box, score)
                else:
                    self._take(d, box, score, seen_part=False)

    def _forget_person(self, box) -> None:
        """A stray person taken by a dancer at ``box`` starts no chain of the next detector frame
        (``strays``, ``unclaimed``)."""
        self.strays = [(det, n) for det, n in self.strays if det != box]
        self.unclaimed = [(det, n) for det, n in self.unclaimed if det != box]

    def _handed_over(self, frame, occluded: list[DancerTrack], dets: list, claims: dict[int, int]) -> dict:
        """Detections (x, y, w, h px) that the tracked dancers in ``claims`` (dancer id -> index into ``dets``)
        take but that show an occluded dancer standing in front of the holder: their colours match its memory at
        least ``reid_similarity`` and by ``reid_margin`` better than the holder's memory, their bottom is
        ``pixel_front`` x the holder's height lower in the image than the holder's box, and they span
        ``reid_holder_covered`` of the width of the holder's body core. Detection -> holder.
        Dancers whose memory is not their own yet (``hidden_behind``) neither hold nor are looked for so."""
        c = self.config
        looked_for = [d for d in occluded if d.hidden_behind is None and d.stored_histogram is not None]
        handed = {}
        if not looked_for:
            return handed
        for i, k in claims.items():
            holder = self.dancers[i]
            if holder.hidden_behind is not None or holder.stored_histogram is None:
                continue
            if not stands_in_front(dets[k], holder.box, c.pixel_front):
                continue  # not in front of the holder: the holder's outline, partly covered by someone passing
            x, _, w, _ = dets[k]
            cx, _, cw, _ = self._core(holder.box)
            if min(cx + cw, x + w) - max(cx, x) < c.reid_holder_covered * cw:
                continue  # the holder shows beside the person: not hidden behind it
            hist = self._histogram(frame, dets[k])
            if hist is None:
                continue
            own = histogram_similarity(hist, holder.stored_histogram)
            if any(histogram_similarity(hist, d.stored_histogram) >= max(c.reid_similarity, own + c.reid_margin)
                   for d in looked_for):
                handed[dets[k]] = holder
        return handed

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
