"""Dancers leaving and re-entering the frame (part of Algorithm 1*, :mod:`hdvr.tracking.multi`).

A dancer whose box leaves the frame (walked out past its side, or cut by it on the detector's find) is *out*: no
box, nothing tracked, until it comes back, on a detection whose height and colours fit it, or without one on the
strip at the left or right edge it left by, when that strip matches its memory clearly better than the empty edge
did (:meth:`FrameEdges._reenter_at_edge`).

:class:`FrameEdges` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's
``config`` (:class:`hdvr.tracking.config.MultiTrackerConfig`), ``dancers`` (:class:`hdvr.tracking.state.DancerTrack`),
``frame_index`` and the tracker's geometry and histogram methods. Boxes are (x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import box_overlap
from hdvr.tracking.geometry import height_within
from hdvr.tracking.state import OUT, TRACKED, DancerTrack


class FrameEdges:
    """Dancers walking out of the frame and back in (mixin of the tracker)."""

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
