"""A dancer's box adapted to the person detection on it (part of Algorithm 1*, :mod:`hdvr.tracking.multi`).

Only a detection that can be one dancer alone counts (:meth:`DetectionAdaptation._single_person`: plausible height
and width, body core clear of the other dancers). The box of a clear dancer adapts its size and centre to it
(:meth:`DetectionAdaptation._adapt_box`), keeping what the detector cannot see: feet and sides hidden behind a dancer
in front (:meth:`DetectionAdaptation._feet_hidden`, :meth:`DetectionAdaptation._sides_hidden`). A dancer in front of
one waiting hidden adapts only its height, or narrows; a box is trimmed to the foreground where it holds none
(:meth:`DetectionAdaptation._trim_to_foreground`). The foreground mask (colours rare in the background around the
dancers) is built here too, for these rules and for :mod:`hdvr.tracking.extent`.

:class:`DetectionAdaptation` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`: it reads the tracker's
``config`` (:class:`hdvr.tracking.config.MultiTrackerConfig`), ``dancers`` (:class:`hdvr.tracking.state.DancerTrack`),
``frame_index`` and the tracker's geometry and histogram methods. Boxes are (x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import numpy as np

from hdvr.tracking.appearance import box_inside, box_iou, box_overlap, clip_box, foreground_mask
from hdvr.tracking.geometry import height_within
from hdvr.tracking.state import OUT, TRACKED, DancerTrack, box_at, box_centre, stands_in_front


class DetectionAdaptation:
    """Dancers' boxes adapted to their detections, and the foreground mask (mixin of the tracker)."""

    def _single_person(self, d: DancerTrack, detection, max_height_change: float | None = None,
                       height: float | None = None) -> bool:
        """Whether ``detection`` can be dancer ``d`` alone: its body core overlaps no other dancer's, its height
        is within ``max_height_change`` (default: the config's) of ``d``'s box height, or of ``height`` px if given
        (a box around two people is neither), and it is at most ``max_person_width`` x the box height wide (a
        person's arm span is about their stature; the detector sometimes returns a box across the whole frame)."""
        c = self.config
        return self._person_sized(d, detection, max_height_change, height) and \
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

    def _alone_at_implied_height(self, d: DancerTrack, detection) -> bool:
        """As :meth:`_single_person`, but with ``detection``'s height (px) compared with the detection height that
        ``d``'s box implies: its height over the learned height ratio of box to detection (``size_ratio``; the box
        itself while none is learned). A box that grew too tall about its dancer is then still told to be hers."""
        ratio = float(d.size_ratio[1]) if d.size_ratio is not None else 1.0
        return self._single_person(d, detection, height=d.box[3] / ratio)

    def _person_sized(self, d: DancerTrack, detection, max_height_change: float | None = None,
                      height: float | None = None) -> bool:
        """Whether ``detection`` (x, y, w, h px) has the size of dancer ``d`` alone: its height within
        ``max_height_change`` (default: the config's) of ``d``'s box height (or of ``height`` px, if given), its
        width at most ``max_person_width`` x the box height (the size tests of :meth:`_single_person` and
        :meth:`_beside_partner`)."""
        c = self.config
        change = max_height_change or c.max_height_change
        reference = d.box if height is None else (0.0, 0.0, 0.0, height)
        return height_within(detection, reference, change) and detection[2] <= c.max_person_width * d.box[3]

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

    def _adapt_height(self, d: DancerTrack, detection, weight: float | None = None) -> None:
        """The height of dancer ``d``'s box moves ``weight`` (default ``box_adaptation``) of the way towards that of
        ``detection`` (times
        the dancer's learned height ratio of box to detection, ``size_ratio``); the box keeps its bottom (the feet)
        and width (the detection's width holds an arm out towards a partner). The bottom is kept in this frame only:
        the box's offset from the tracker's centre is left as it was, so from the next frame on the box lies about
        the tracker's centre again and half of the height change shows at its bottom. Keeping the bottom through
        the offset was measured in session 69 and not kept (docs/benchmarks.md "session 69")."""
        a = self.config.box_adaptation if weight is None else weight
        ratio = d.size_ratio[1] if d.size_ratio is not None else 1.0
        height = (1 - a) * d.box[3] + a * ratio * float(detection[3])
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
