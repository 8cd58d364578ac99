"""Dancers waiting hidden behind others coming out (part of Algorithm 1*, :mod:`hdvr.tracking.multi`).

A dancer that starts mostly hidden behind another (``hidden_behind``) has no colours of its own yet: it cannot be
re-identified by its histogram. :class:`Emergence` lets it take a detection that comes out from behind the dancer
it waits behind: one no other dancer takes, of a plausible height, and unlike the dancer in front (or, when the
front dancer leaves, the one it leaves behind). It also keeps the claims of tracked dancers on the frame's
detections (:meth:`Emergence._claimed`, :meth:`Emergence._claims`), which re-identification asks too.

:class:`Emergence` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's ``config``
(:class:`hdvr.tracking.config.MultiTrackerConfig`, the ``emerge_*`` fields), ``dancers``
(:class:`hdvr.tracking.state.DancerTrack`) and the tracker's histogram and geometry methods. Boxes are (x, y, w, h)
pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import box_iou, histogram_similarity
from hdvr.tracking.geometry import chain_length, height_misfit, height_within
from hdvr.tracking.state import OCCLUDED, OUT, TRACKED, DancerTrack, box_centre


class Emergence:
    """Dancers that started hidden behind another take the detection that comes out from behind (mixin)."""

    def _emerge(self, frame, detections, front_histograms: dict | None = None) -> None:
        """Dancers that started mostly hidden (``hidden_behind``) take a detection that comes out from behind:
        one that no other dancer takes (one assignment on :meth:`_fit_score` of the detections to the tracked
        dancers not waiting so), whose body core overlaps no other dancer's (``overlap_threshold``), whose centre
        lies within ``emerge_distance`` box heights of the dancer's box centre, whose height is within
        ``max_height_change`` of the box's, whose width / height is at most ``emerge_max_aspect`` x the box's,
        counted at least ``emerge_min_aspect`` (a wider one is a part of a dancer drawn as a person), and whose
        colours match the hiding dancer's memory less than ``reid_similarity`` (or, ``emerge_relative``, by
        ``reid_margin`` less than the hiding dancer's box does now) and that does not plainly show another dancer
        whose colours are known (:meth:`_shows_known_dancer`); the nearest such detection; with
        ``emerge_front_first`` the dancers waiting behind a dancer followed choose before those waiting behind a
        dancer who waits too. The dancer's box moves there (unless it already overlaps it by IoU 0.5, or more;
        keeping its height when the detection is shorter, ``emerge_keeps_height``), and it learns its
        colours from it, replacing those of the dancer in front: it no longer waits. With ``emerge_beside_persist``
        N, a detection whose body core overlaps other dancers' less than ``emerge_beside_overlap`` counts too, when
        its colours match each of their memories less than ``emerge_beside_similarity`` and such a detection lay on it
        on each of the N - 1 detector frames before (``DancerTrack.beside_now`` / ``beside_before``; detector frames
        as :meth:`_count_detector_frame` counts them); with ``emerge_own_margin`` m, so does one on the dancer's own
        box (IoU >= 0.5) however much it overlaps the others, when its colours match the front dancer's memory by m
        less than his box does now. With ``emerge_height_yield`` a dancer leaves a detection to another waiting dancer
        of its height who may take it (:meth:`_fits_other_waiting`); with ``emerge_front_leaves`` a dancer in front
        whose box stayed on the dancer waiting behind it moves to the detection of him beside them, and she comes
        out (:meth:`_front_leaves`). ``front_histograms``: a dict of the colour histograms of the
        front dancers' boxes, by (dancer id, box), shared by the calls of a frame."""
        c = self.config
        front_histograms = {} if front_histograms is None else front_histograms
        waiting = self.waiting()
        if not waiting:
            return
        if c.emerge_front_first:  # those hidden by one dancer before those hidden by a dancer who waits too
            waiting.sort(key=lambda d: self.dancers[d.hidden_behind].hidden_behind is not None)
        dets = [tuple(float(v) for v in det) for det in detections]
        holders = [o for o in self.dancers if o.status == TRACKED and o.hidden_behind is None]
        held = {holders[i].dancer_id: k for i, k in self._fit_assignment([o.box for o in holders], dets)[1]} \
            if holders else {}
        taken = set(held.values())
        histograms = {}  # detection index -> its colour histogram, computed once for all waiting dancers
        for d in waiting:
            if c.emerge_beside_persist and d.beside_frame != self.frame_index:  # a new detector frame
                # what lay beside it counts only if it was seen on the detector frame just before this one
                d.beside_before = d.beside_now if d.beside_frame == self.previous_detector_frame else []
                d.beside_now, d.beside_frame = [], self.frame_index
        for d in waiting:
            front = self.dancers[d.hidden_behind]
            unlike_front, front_now = self._front_likeness(frame, front, front_histograms)
            if c.emerge_front_leaves > 0 and front.hidden_behind is None and front.dancer_id in held and \
                    self._front_leaves(frame, d, front, dets, held[front.dancer_id], taken, histograms,
                                       unlike_front):
                continue
            centre = np.asarray(box_centre(d.box))
            best, best_distance = None, c.emerge_distance * d.box[3]
            for k, det in enumerate(dets):
                if k in taken:
                    continue
                distance = float(np.linalg.norm(np.asarray(box_centre(det)) - centre))
                if distance > best_distance:
                    continue
                hist = self._emerges_on(frame, d, k, det, unlike_front, front_now, histograms)
                if hist is None or (c.emerge_height_yield > 0 and self._fits_other_waiting(
                        frame, d, k, det, waiting, histograms, front_histograms)):
                    continue
                best, best_distance = (k, hist), distance
            if best is None:
                continue
            k, hist = best
            taken.add(k)
            if box_iou(d.box, dets[k]) < 0.5 or d.status != TRACKED:  # the box is elsewhere: move it there
                det = dets[k]
                if c.emerge_keeps_height and det[3] < d.box[3]:
                    det = (det[0], det[1], det[2], d.box[3])  # the detector sees the part not hidden yet
                self._take(d, det, 1.0)
                d.tracker.init(frame, self._core(d.box))
            d.stored_histogram, d.hidden_behind = hist, None

    def _front_likeness(self, frame, front: DancerTrack, front_histograms: dict) -> tuple[float, float | None]:
        """(unlike_front, front_now) for a dancer waiting behind ``front``: the match of the front dancer's memory
        below which a detection does not look like him (``reid_similarity``, or with ``emerge_relative`` up to
        ``reid_margin`` less than his box matches it now), and that match of his box now (None if not known).
        ``front_histograms``: the colour histograms of the front dancers' boxes, by (dancer id, box)."""
        c = self.config
        unlike_front, front_now = c.reid_similarity, None
        if c.emerge_relative and front.status == TRACKED:
            front_hist = self._cached_histogram(frame, front_histograms, (front.dancer_id, tuple(front.box)), front.box)
            if front_hist is not None:
                front_now = histogram_similarity(front_hist, front.stored_histogram)
                unlike_front = max(unlike_front, front_now - c.reid_margin)
        return unlike_front, front_now

    def _emerges_on(self, frame, d: DancerTrack, k: int, det, unlike_front: float, front_now: float | None,
                    histograms: dict, record: bool = True):
        """The colour histogram of detection ``det`` (index ``k``; x, y, w, h px) if waiting dancer ``d`` may come
        out on it by the tests of :meth:`_emerge` but distance and being taken; else None. ``unlike_front``,
        ``front_now``: :meth:`_front_likeness` of its front dancer; ``histograms``: detection index -> histogram,
        shared. A detection beside others is counted on ``d.beside_now`` (``record``; not when asked on another's
        behalf)."""
        c = self.config
        front = self.dancers[d.hidden_behind]
        if not height_within(det, d.box, c.max_height_change) \
                or self._wider_than(det, d, c.emerge_max_aspect, c.emerge_min_aspect):
            return None
        fit = box_iou(det, d.box)
        overlaps = [(o, self._bodies_overlap(det, o.box)) for o in self.dancers
                    if o is not d and o.status != OUT and not (
                        c.emerge_past_waiting and o.hidden_behind is not None
                        and o.dancer_id != d.hidden_behind and box_iou(det, o.box) < fit)]
        if c.emerge_past_unlike_occluded:
            overlaps = [(o, v) for o, v in overlaps
                        if v <= c.overlap_threshold or not self._plainly_not(frame, o, k, det, histograms)]
        overlapped = [o for o, v in overlaps if v > c.overlap_threshold]
        half_beside = bool(overlapped) and max(v for _, v in overlaps) < c.emerge_beside_overlap
        own = bool(c.emerge_own_margin) and c.emerge_beside_persist and fit >= 0.5 and front_now is not None
        if overlapped and not own and (not c.emerge_beside_persist or not half_beside):
            return None
        hist = self._cached_histogram(frame, histograms, k, det)
        if hist is None:
            return None
        like_front = histogram_similarity(hist, front.stored_histogram)
        if like_front >= unlike_front or self._shows_known_dancer(hist, front, det):
            return None
        if overlapped:  # beside others: unlike each of them, and there on the detector frames before
            beside = half_beside and not any(
                o.stored_histogram is not None and histogram_similarity(hist, o.stored_histogram)
                >= c.emerge_beside_similarity for o in overlapped)
            # or on its own box, far less like the dancer in front than his own box is now
            on_own = own and like_front < front_now - c.emerge_own_margin
            if not (beside or on_own):
                return None
            count = chain_length(d.beside_before, det)
            if record:
                d.beside_now.append((det, count))
            if count < c.emerge_beside_persist:
                return None
        return hist

    def _cached_histogram(self, frame, histograms: dict, key, box):
        """The colour histogram of ``box`` (x, y, w, h px) in ``frame`` (:meth:`_histogram`; None where it cannot be
        told), kept in ``histograms`` under ``key`` (a detection index or a box tuple) and computed only once."""
        if key not in histograms:
            histograms[key] = self._histogram(frame, box)
        return histograms[key]

    def _plainly_not(self, frame, o: DancerTrack, k: int, det, histograms: dict) -> bool:
        """Whether dancer ``o``, occluded and not waiting (its box a prediction), plainly is not the person of
        detection ``det`` (index ``k``; x, y, w, h px): the detection's colours match its memory less than
        ``emerge_beside_similarity``. ``histograms``: detection index -> histogram, shared."""
        if o.status != OCCLUDED or o.hidden_behind is not None or o.stored_histogram is None:
            return False
        hist = self._cached_histogram(frame, histograms, k, det)
        return hist is not None and \
            histogram_similarity(hist, o.stored_histogram) < self.config.emerge_beside_similarity

    def _front_leaves(self, frame, d: DancerTrack, front: DancerTrack, dets: list, k_held: int, taken: set,
                      histograms: dict, like_front_min: float) -> bool:
        """With ``emerge_front_leaves``: whether dancer ``front``, holding detection ``k_held`` that lies on the box
        of dancer ``d`` waiting behind it, walked out of their stack onto another of ``dets`` (see the option); if
        so, ``front`` is moved there and ``d`` comes out on the held detection (both then in ``taken``).
        ``like_front_min``: the least match of the front dancer's memory that looks like him (``unlike_front`` of
        :meth:`_front_likeness`, at least ``reid_similarity``)."""
        c = self.config
        held = dets[k_held]
        if box_iou(held, d.box) < 0.5 or front.stored_histogram is None:
            return False
        front_centre = np.asarray(box_centre(front.box))
        best = None
        for k, det in enumerate(dets):
            if k in taken or float(np.linalg.norm(np.asarray(box_centre(det)) - front_centre)) > \
                    c.emerge_distance * front.box[3]:
                continue
            # his box fits this detection better than the held one, hers the held one better than this
            gain = height_misfit(held, front.box) - height_misfit(det, front.box) + \
                height_misfit(det, d.box) - height_misfit(held, d.box)
            if gain <= c.emerge_front_leaves or self._bodies_overlap(det, held) > c.overlap_threshold or any(
                    self._bodies_overlap(det, o.box) > c.overlap_threshold
                    for o in self.dancers if o is not front and o.status != OUT):
                continue  # beside the waiting dancer and everyone else (his own box may still lie on her)
            hist = self._cached_histogram(frame, histograms, k, det)
            like_front = histogram_similarity(hist, front.stored_histogram) if hist is not None else -np.inf
            if like_front < like_front_min:
                continue
            if best is None or gain > best[1]:
                best = (k, gain, like_front)
        if best is None:
            return False
        k, _, like_front = best
        self._take(front, dets[k], like_front)
        front.tracker.init(frame, self._core(front.box))
        if d.status != TRACKED:  # as :meth:`_emerge` places a dancer coming out
            self._take(d, held, 1.0)
            d.tracker.init(frame, self._core(d.box))
        own = self._cached_histogram(frame, histograms, k_held, held)
        own = own if own is not None else self._histogram(frame, d.box)
        if own is not None:
            d.stored_histogram = own
        d.hidden_behind = None
        taken.add(k)
        return True

    def _fits_other_waiting(self, frame, d: DancerTrack, k: int, det, waiting: list[DancerTrack], histograms: dict,
                            front_histograms: dict) -> bool:
        """With ``emerge_height_yield`` m, whether detection ``det`` (index ``k``; x, y, w, h px) fits another of the
        ``waiting`` dancers than ``d`` better by height, its box height closer to the detection's by more than m in
        |log(detection height / box height)|, and that dancer, still waiting, may come out on it too: within its
        ``emerge_distance``, and by the tests of :meth:`_emerges_on`."""
        c = self.config
        mine = height_misfit(det, d.box)
        centre = np.asarray(box_centre(det))
        for e in waiting:
            if e is d or e.hidden_behind is None or height_misfit(det, e.box) + c.emerge_height_yield >= mine \
                    or float(np.linalg.norm(centre - np.asarray(box_centre(e.box)))) > c.emerge_distance * e.box[3]:
                continue
            unlike_front, front_now = self._front_likeness(frame, self.dancers[e.hidden_behind], front_histograms)
            if self._emerges_on(frame, e, k, det, unlike_front, front_now, histograms, record=False) is not None:
                return True
        return False

    def _shows_known_dancer(self, hist, front: DancerTrack, detection=None) -> bool:
        """With ``emerge_yields_to_known``, whether a detection with colour histogram ``hist`` shows a dancer other
        than ``front`` whose colours are known (not out, not waiting since its start): its memory matches at least
        ``reid_similarity`` and by ``reid_margin`` more than every other such dancer's. With ``emerge_known_height``
        and the ``detection`` (x, y, w, h px) given, only dancers whose box height fits it (:meth:`_height_fits`)
        count, besides ``front``: a dancer that could not take the person is not the one it shows."""
        c = self.config
        if not c.emerge_yields_to_known:
            return False
        scores = sorted(((histogram_similarity(hist, o.stored_histogram), o.dancer_id) for o in self.dancers
                         if o.status != OUT and o.hidden_behind is None and o.stored_histogram is not None
                         and (not c.emerge_known_height or detection is None or o is front
                              or self._height_fits(o, detection))),
                        reverse=True)
        if not scores or scores[0][0] < c.reid_similarity or scores[0][1] == front.dancer_id:
            return False
        return len(scores) < 2 or scores[0][0] - scores[1][0] >= c.reid_margin

    def _claimed(self, detections) -> set[int]:
        """Indices of the detections that tracked dancers take in one assignment (Hungarian on
        :meth:`_fit_score`, at least ``group_min_score``)."""
        return set(self._claims(detections).values())

    def _claims(self, detections) -> dict[int, int]:
        """Tracked dancer id -> index of the detection it takes in one assignment (Hungarian on
        :meth:`_fit_score`, at least ``group_min_score``)."""
        tracked = [o for o in self.dancers if o.status == TRACKED]
        if not tracked or not detections:
            return {}
        _, pairs = self._fit_assignment([o.box for o in tracked], detections)
        return {tracked[i].dancer_id: k for i, k in pairs}
