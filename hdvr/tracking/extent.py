"""The *reported* extent of each dancer's box: how far beyond its tracked box a dancer's limbs reach.

Algorithm 1* tracks a dancer's body (:mod:`hdvr.tracking.multi`); while it overlaps others its tracked box keeps
the size it had when clear, so spread arms or a raised leg fall outside it. After Algorithm 2* has chosen each
dancer's pose on a detector frame, :meth:`ReportedExtent.extend_to_poses` grows the box that is written (not the
one that is tracked) on each side as far as the evidence reaches: the clearly chosen pose, foreground pixels at arm
height, the limb beside a front dancer that its skeleton does not explain (for the dancer hidden behind it, and
for the dancer in front where its own arm reaches or points there), and the dancer's own GrabCut segment. A hidden
dancer's written box is also at least ``hidden_min_aspect`` x its height wide within the dancers hiding it
(:meth:`ReportedExtent._widen_hidden`). The tracking itself (overlaps, histograms, failure tests, relocation)
never uses these extents.

:class:`ReportedExtent` is a mixin of :class:`hdvr.tracking.multi.MultiDancerTracker`; it reads the tracker's
``config`` (:class:`hdvr.tracking.multi.MultiTrackerConfig`: the ``pose_*``, ``pixel_*``, ``stacked_*``,
``front_extent``, ``grabcut_*``, ``hold_hidden_extent`` and ``keep_hidden_sides`` fields), ``dancers``
(:class:`hdvr.tracking.state.DancerTrack`, whose ``growth`` it sets), ``frame_index``, ``result()`` and the body-core
geometry ``_core``, ``_bodies_overlap``, ``_overlapping``, ``_fit_score`` and ``_foreground``.

Boxes are (x, y, w, h) pixels, top-left corner.
"""

from __future__ import annotations

import cv2
import numpy as np

from hdvr.pose2d.selection import skeleton_mask
from hdvr.tracking.appearance import box_overlap
from hdvr.tracking.state import (OCCLUDED, OUT, TRACKED, DancerTrack, FrameResult, box_at, box_centre,
                                 stands_in_front, straight_in_front)


def _draws_limb(keypoints25: np.ndarray, strip, frame_size) -> bool:
    """Whether the skeleton of BODY_25 ``keypoints25`` draws a limb inside ``strip`` (x, y, w, h px) of a frame of
    ``frame_size`` (width, height) px (:func:`hdvr.pose2d.selection.skeleton_mask`)."""
    mask = skeleton_mask(keypoints25, strip, frame_size)
    return mask is not None and bool(mask.any())


def _beyond(box, front_box, run: float, side: int) -> float:
    """How far (px) a foreground ``run`` (px) beside ``front_box`` on ``side`` (0 left, 1 right) reaches beyond
    ``box`` on that side (negative: it ends inside it); boxes x, y, w, h px."""
    if side == 0:
        return box[0] - (front_box[0] - run)
    return front_box[0] + front_box[2] + run - box[0] - box[2]


class ReportedExtent:
    """Growth of the reported boxes beyond the tracked ones (mixin of the multi-dancer tracker)."""

    @staticmethod
    def _reported(d: DancerTrack) -> tuple[float, float, float, float]:
        """The box written for dancer ``d``: its tracked box extended by its growth (:meth:`extend_to_poses`)."""
        gl, gt, gr, gb = d.growth
        x, y, w, h = d.box
        return (x - gl, y - gt, w + gl + gr, h + gt + gb)

    def extend_to_poses(self, frame, poses, margins) -> FrameResult:
        """Box extent from the poses Algorithm 2* chose (called after it, on detector frames).

        ``poses[i]``: the pose (:class:`hdvr.pose2d.base.PersonPose`) chosen for dancer i in ``frame`` (None if
        none); ``margins[i]``: how much better its selection score was for dancer i than for any other dancer.
        A dancer's tracked box keeps its size while it overlaps others, and while clear it adapts only to a
        detection it overlaps well (IoU > ``adapt_min_iou``); a dancer who spreads its arms meanwhile is wider than
        that box. The *reported* box of a tracked or occluded dancer therefore grows on each side where the chosen
        pose's box (scaled by the dancer's box-to-detector size ratio) and its limbs reach beyond the tracked box,
        by ``pose_adaptation`` of the way per detector frame, when:

        - the choice is clear: margin at least ``pose_margin``;
        - the pose's box fits the dancer (:meth:`_fit_score` >= ``group_min_score``) and is at most
          ``pose_max_height`` x as tall (a taller one holds more than this dancer);
        - no other dancer without a pose of its own stands straight behind or in front of this one (body cores
          overlapping more than ``pose_stack_overlap``): YOLO attaches the arm of a dancer behind to the skeleton
          of the one in front, so a limb beside the pair may be either's;
        - the box did not adapt to a detection in this frame anyway (a clear dancer).

        With ``pixel_extent``, a tracked dancer's box also grows sideways as far as foreground pixels run on from it
        at arm height (:meth:`_pixel_reach`; YOLO often draws a dancer without its spread arms, and its keypoints
        then leave them out too), whatever the pose; with ``stacked_extent`` a dancer hidden behind another also
        as far as the limb beside it that the front dancer's skeleton does not explain (:meth:`_stacked_reach`); with
        ``grabcut_extent`` a dancer in a group also as far as its own GrabCut segment runs on from its box
        (:meth:`_grabcut_reach`). Per side, the largest of these extents is approached. ``pose_extent`` off switches
        all off, ``pixel_extent`` off the last three.

        Elsewhere the growth shrinks by that fraction (in a group, by ``group_shrink`` x that fraction: the
        evidence flickers there, and one frame without a limb says little), except (``hold_hidden_extent``) for a
        dancer hidden behind another (:meth:`_hidden_behind`): no evidence can show that its limbs came in, so it
        keeps its extent, with ``hold_within_cover`` only as far as the dancers overlapping it reach beyond its box
        (:meth:`_covered_reach`; a limb beyond them would be seen). The box never shrinks below the tracked box (in a
        group a detection shows the visible part, which the dancer in front may cut), and the growth changes only
        the reported box, not the tracking (overlaps, histograms, failure tests, relocation). Returns the frame's
        result with the reported boxes."""
        c = self.config
        if not c.pose_extent:
            return self.result()
        a = c.pose_adaptation
        size = (frame.shape[1], frame.shape[0])
        fg = self._foreground(frame) if c.pixel_extent else None  # sampled around the tracked boxes
        pairs = list(self._stacked_pairs(fg, poses, margins)) if fg is not None else []  # computed once per frame
        boxes = [d.box for d in self.dancers]
        for i, d in enumerate(self.dancers):
            if d.status == OUT:
                continue
            target = np.zeros(4)
            if fg is not None:
                target[0], target[2] = self._pixel_reach(d, fg, poses, margins)
                if c.stacked_extent:
                    left, right = self._stacked_reach(i, pairs)
                    target[0], target[2] = max(target[0], left), max(target[2], right)
                if c.front_extent:
                    left, right = self._front_reach(i, pairs)
                    target[0], target[2] = max(target[0], left), max(target[2], right)
                if c.grabcut_extent:
                    left, right = self._grabcut_reach(i, frame, fg, poses, margins)
                    target[0], target[2] = max(target[0], left), max(target[2], right)
            pose = poses[i] if i < len(poses) else None
            if pose is not None and self._pose_extends(d, pose, margins[i], poses):
                det = box_at(box_centre(pose.box), (0.0, 0.0, *self._box_size(d, pose.box[2:])))
                x, y, w, h = d.box
                reach = np.maximum(0.0, [x - det[0], y - det[1], det[0] + det[2] - x - w, det[1] + det[3] - y - h])
                strips = [(det[0], det[1], reach[0], det[3]), (det[0], det[1], det[2], reach[1]),
                          (x + w, det[1], reach[2], det[3]), (det[0], y + h, det[2], reach[3])]
                keypoints = pose.body25()
                for side, strip in enumerate(strips):
                    if reach[side] >= 1 and _draws_limb(keypoints, strip, size):  # a limb reaches into the strip
                        target[side] = max(target[side], reach[side])
            if c.hold_hidden_extent and self._hidden_behind(d):
                held = d.growth if not c.hold_within_cover else np.minimum(d.growth, self._covered_reach(d))
                target = np.maximum(target, held)  # nothing can show its limbs are in: they stay out
            rate = np.where(target >= d.growth, a, a * (c.group_shrink if self._overlapping(i, boxes) else 1.0))
            d.growth = (1 - rate) * d.growth + rate * target
            if c.keep_hidden_sides == "written":
                d.growth = np.maximum(d.growth, self._hidden_sides_reach(d))
        return self.result()

    def _hidden_sides_reach(self, d: DancerTrack) -> np.ndarray:
        """How far (px; left, top, right, bottom) dancer ``d``'s written box reaches beyond its tracked box behind the
        dancer in front that cut its detections (``keep_hidden_sides`` "written",
        :meth:`hdvr.tracking.multi.MultiDancerTracker._note_hidden_sides`): to the noted aspect x its height, on the
        side cut (half on each when both were). Zero, and the note cleared, once the box so reached overlaps no
        other dancer's reported box (whether he still stands in front is not asked again: a waiting dancer's box
        keeps the height it had, and its bottom may come level with his)."""
        reach = np.zeros(4)
        if d.hidden_aspect is None:
            return reach
        extra = max(0.0, d.hidden_aspect * d.box[3] - d.box[2])
        left, right = d.hidden_sides
        reach[0] = extra / 2 if left and right else extra if left else 0.0
        reach[2] = extra / 2 if left and right else extra if right else 0.0
        x, y, w, h = d.box
        reached = (x - reach[0], y, w + reach[0] + reach[2], h)
        if not any(o is not d and o.status != OUT and box_overlap(self._reported(o), reached) > 0
                   for o in self.dancers):
            d.hidden_aspect, d.hidden_sides = None, (False, False)
            return np.zeros(4)
        return reach

    def _covered_reach(self, d: DancerTrack) -> np.ndarray:
        """How far (px) the reported boxes of the other dancers overlapping dancer ``d``'s tracked box reach beyond
        it on the left, top, right and bottom (0 where none does): a hidden limb can only stay hidden behind them;
        one reaching further would be seen."""
        x, y, w, h = d.box
        reach = np.zeros(4)
        for o in self.dancers:
            if o is d or o.status == OUT or box_overlap(o.box, d.box) <= 0:
                continue
            ox, oy, ow, oh = self._reported(o)
            reach = np.maximum(reach, [x - ox, y - oy, ox + ow - x - w, oy + oh - y - h])
        return reach

    def _widen_hidden(self, boxes: np.ndarray) -> np.ndarray:
        """Reported ``boxes`` (N, 4) px with each hidden dancer's (:meth:`_hidden_behind` with
        ``hidden_widen_overlap``) widened about its centre to ``hidden_min_aspect`` x its height, but not beyond the
        dancers whose boxes overlap it: a limb reaching further would be seen. Not in a dancer's start frame (its
        box is the one given). Only the boxes written change (``result()``): tracking and pose selection
        (``result(widen_hidden=False)``) do not see the widening."""
        c = self.config
        aspect = c.hidden_min_aspect
        out = boxes.copy()
        for i, d in enumerate(self.dancers):
            x, y, w, h = boxes[i]
            if d.status == OUT or d.start_frame == self.frame_index or aspect * h <= w \
                    or not self._hidden_behind(d, c.hidden_widen_overlap):
                continue
            lo, hi = x, x + w
            for j, b in enumerate(boxes):
                if j != i and np.isfinite(b).all() and box_overlap(boxes[i], b) > 0:
                    lo, hi = min(lo, b[0]), max(hi, b[0] + b[2])
            centre = x + w / 2
            x0, x1 = max(centre - aspect * h / 2, lo), min(centre + aspect * h / 2, hi)
            out[i, 0], out[i, 2] = x0, x1 - x0
        return out

    def _hidden_behind(self, d: DancerTrack, overlap: float | None = None) -> bool:
        """Whether dancer ``d`` is hidden: occluded, or standing straight behind a tracked dancer (body cores
        overlapping more than ``overlap``, intersection / smaller, by default ``pose_stack_overlap``; the other's box
        bottom at least ``pixel_front`` x ``d``'s height lower in the image)."""
        if d.status == OCCLUDED:
            return True
        return any(o is not d and o.status == TRACKED and self._straight_in_front(o, d, overlap) for o in self.dancers)

    def _straight_in_front(self, f: DancerTrack, d: DancerTrack, overlap: float | None = None) -> bool:
        """Whether dancer ``f`` stands straight in front of dancer ``d``: body cores overlapping more than
        ``overlap`` (intersection / smaller; default ``pose_stack_overlap``) and ``f``'s box bottom at least
        ``pixel_front`` x ``d``'s height lower in the image."""
        c = self.config
        overlap = c.pose_stack_overlap if overlap is None else overlap
        return straight_in_front(f.box, d.box, c.core_aspect, overlap, c.pixel_front)

    def _pixel_reach(self, d: DancerTrack, fg: np.ndarray, poses=(), margins=()) -> tuple[float, float]:
        """How far (px) foreground pixels (``fg``: :func:`hdvr.tracking.appearance.foreground_mask`) run on from
        tracked dancer ``d``'s box to the left and to the right at arm height (rows ``pixel_band`` of the box).
        Column by column outwards from the box: a column counts when it holds at least max(3, ``pixel_min_thickness``
        x the box height) foreground pixels, the run may break for ``pixel_gap`` columns, counts up to
        ``pixel_max_reach`` x the box height (a run still going there is followed on to ``pixel_follow_reach`` x
        the height, to see where it ends), and stops at a column more than ``pixel_max_fill`` foreground (a body
        beside the box, or background the sample lacked). Where it reaches another dancer's body core, or such a
        full column inside another dancer's box (``pixel_full_in_box``), it stops, and if that dancer stands level
        with ``d`` or in front (box bottom not ``pixel_front`` x the height higher in the image), that side gets
        nothing: the limb may be that dancer's, reaching towards ``d``; unless (``pixel_unexplained_limb``) the pose
        chosen clearly for that dancer draws no limb on the run (:meth:`_limb_unexplained`) and
        (``pixel_unexplained_own``) ``d``'s own pose, if chosen clearly, does draw one there, ``d`` not being
        hidden behind another (its extent is held): then the run up to that dancer's body core counts. ``poses``,
        ``margins``: the frame's poses chosen by Algorithm 2* and their margins (:meth:`extend_to_poses`). Zero for a
        dancer not seen now or standing straight behind or in front of another (``pose_stack_overlap``).

        Written here as a scan over column counts rather than with ``cv2.connectedComponents``: the dancers' own
        foreground touches (a group is one component), and what is needed is how far the run goes along one row
        band, with the stop rules above."""
        c = self.config
        if d.status != TRACKED:
            return 0.0, 0.0
        others = [o for o in self.dancers if o is not d and o.status != OUT]
        if any(self._bodies_overlap(o.box, d.box) > c.pose_stack_overlap for o in others):
            return 0.0, 0.0
        left, right = self._run_reach(d.box, others, fg, dancer=d, chosen=(poses, margins))
        if c.pixel_front_limb and (left > 0 or right > 0):
            left, right = self._not_front_limbs(d, (left, right), fg, poses, margins)
        return left, right

    def _not_front_limbs(self, d: DancerTrack, reach, fg: np.ndarray, poses, margins) -> tuple[float, float]:
        """``reach`` (px, left and right of tracked dancer ``d``'s box, :meth:`_run_reach`) less each run that is the
        limb of a tracked dancer whose box overlaps ``d``'s and in front of whom ``d`` does not stand
        (:func:`~hdvr.tracking.state.stands_in_front` with ``pixel_front``): that dancer's clearly chosen pose
        (``pose_margin``) draws a limb on the run's columns at ``d``'s arm rows (``pixel_band``), or its reported box
        already reaches as far as the run (its own evidence put its limb there), and ``d``'s own pose, if chosen
        clearly, draws none there; or (``front_limb_root``) the run is rooted at that dancer's shoulder row and not
        at ``d``'s (:meth:`_rooted_at_shoulder`). Such an arm crosses ``d``'s box from the dancer in front and runs
        on beyond it, so the run starts at ``d``'s side without reaching any body core (seed 2865 hip-hop: a dancer
        waiting behind another took his spread arm for hers and her box doubled in width). ``fg``: the frame's
        foreground mask (:meth:`_foreground`)."""
        c = self.config
        shape = fg.shape
        x, y, w, h = d.box
        r0, r1 = y + c.pixel_band[0] * h, y + c.pixel_band[1] * h
        strips = ((x - reach[0], r0, reach[0], r1 - r0), (x + w, r0, reach[1], r1 - r0))
        fronts = self._fronts_of(d)
        out = list(reach)
        for side, strip in enumerate(strips):
            if reach[side] <= 0:
                continue
            end = strip[0] if side == 0 else strip[0] + strip[2]
            theirs = any(self._clearly_draws_limb(o, strip, shape, poses, margins)
                         or self._reaches_past(o, end, side) or self._rooted_at_shoulder(o, d, side, fg)
                         for o in fronts)
            if theirs and not self._clearly_draws_limb(d, strip, shape, poses, margins):
                out[side] = 0.0
        return out[0], out[1]

    def _fronts_of(self, d: DancerTrack) -> list[DancerTrack]:
        """The tracked dancers whose boxes overlap dancer ``d``'s and in front of whom ``d`` does not stand
        (:func:`~hdvr.tracking.state.stands_in_front` with ``pixel_front``): level with it or in front."""
        c = self.config
        return [o for o in self.dancers if o is not d and o.status == TRACKED and box_overlap(o.box, d.box) > 0
                and not stands_in_front(d.box, o.box, c.pixel_front)]

    def _rooted_at_shoulder(self, o: DancerTrack, d: DancerTrack, side: int, fg: np.ndarray) -> bool:
        """Whether the foreground just beside tracked dancer ``d``'s box on ``side`` (0 left, 1 right; its first
        max(3, ``front_limb_root`` x the box height) columns) lies at dancer ``o``'s shoulder row and hardly at
        ``d``'s (``shoulder_row`` down each box; within ``front_limb_root`` x ``d``'s height of it: at least 3 px a
        column on average there, under a quarter of that at ``d``'s, where the edge of its own body may show), the
        two rows at least twice that far apart. An arm leaves its body at the shoulder, so a run rooted at the
        height of ``o``'s shoulders, where ``d`` has none, is ``o``'s arm crossing ``d``'s box (seed 2966 hip-hop: a
        dancer in front spread an arm the detector drew in, level with the chest of a shorter dancer further back).
        False with ``front_limb_root`` None."""
        c = self.config
        if c.front_limb_root is None:
            return False
        x, y, w, h = d.box
        tol = c.front_limb_root * h
        own_row, their_row = y + c.shoulder_row * h, o.box[1] + c.shoulder_row * o.box[3]
        if abs(own_row - their_row) < 2 * tol:
            return False
        depth = max(3, int(round(tol)))
        start = int(np.floor(x)) - depth if side == 0 else int(np.ceil(x + w))
        cols = slice(max(0, start), max(0, start + depth))

        def per_column(row: float) -> float:
            window = fg[max(0, int(row - tol)):max(0, int(np.ceil(row + tol))), cols]
            return float(window.sum(axis=0).mean()) if window.size else 0.0

        theirs = per_column(their_row)
        return theirs >= 3.0 and per_column(own_row) < 0.25 * theirs

    def _clear_pose_draws_limb(self, o: DancerTrack, strip, shape, poses, margins) -> bool | None:
        """Whether the pose chosen clearly for dancer ``o`` on this frame (``poses``, ``margins``:
        :meth:`_clear_pose`; indexed by dancer id) draws a limb in ``strip`` (x, y, w, h px; ``shape``: the frame's
        height, width); None when no pose was chosen clearly for it."""
        j = o.dancer_id
        if not self._clear_pose(j, poses, margins):
            return None
        return _draws_limb(poses[j].body25(), strip, (shape[1], shape[0]))

    def _clearly_draws_limb(self, o: DancerTrack, strip, shape, poses, margins) -> bool:
        """Whether dancer ``o`` has a pose chosen clearly whose skeleton draws a limb in ``strip``
        (:meth:`_clear_pose_draws_limb`)."""
        return self._clear_pose_draws_limb(o, strip, shape, poses, margins) is True

    def _reaches_past(self, o: DancerTrack, end: float, side: int) -> bool:
        """Whether dancer ``o``'s reported box (:meth:`_reported`) reaches at least to column ``end`` (px) on
        ``side`` (0 left, 1 right)."""
        x, _, w, _ = self._reported(o)
        return x <= end if side == 0 else x + w >= end

    def _run_reach(self, box, others, fg: np.ndarray, limb_box=None, own_segment: bool = False,
                   rows=None, dancer: DancerTrack | None = None, chosen=((), ())) -> tuple[float, float]:
        """The column scan of :meth:`_pixel_reach` from the sides of ``box`` (x, y, w, h px), with the body cores
        of dancers ``others`` as stops: how far (px) foreground runs on to the left and to the right of the box.
        Rows, thickness and reach scale with ``limb_box`` (default ``box``): the box of the dancer whose limb is
        sought; ``rows`` (default ``pixel_band``) are the rows scanned, x its height from its top. With
        ``own_segment`` (``fg`` is this dancer's own segment, :meth:`_grabcut_reach`) only the cores of dancers level
        with it stop the run (that side gets nothing): the segmentation has already left out the bodies of those
        behind it and in front of it. ``dancer``: the dancer whose box the run starts from, when the limb sought is
        its own, and ``chosen``: the frame's (poses, margins) from Algorithm 2* (both for the
        ``pixel_unexplained_limb`` and ``pixel_unexplained_own`` tests, which are skipped without ``dancer``)."""
        c = self.config
        x, _, w, _ = box
        _, y, _, h = box if limb_box is None else limb_box
        height, width = fg.shape
        band = c.pixel_band if rows is None else rows
        r0, r1 = int(max(0, y + band[0] * h)), int(min(height, y + band[1] * h))
        if r1 - r0 < 2:
            return 0.0, 0.0
        counts = fg[r0:r1].sum(axis=0)
        # columns of other dancers' body cores at these rows: 1 where this dancer stands in front of that dancer
        # (box bottom lower in the image: its arm may cross the other's body), -1 where behind or level
        cores = np.zeros(width, int)
        level_boxes = np.zeros(width, bool)  # columns of the boxes of dancers level with this one or in front

        def columns(left, span_width) -> slice:
            return slice(max(0, int(left)), max(0, int(np.ceil(left + span_width))))

        owner = np.full(width, -1)  # the index (in ``others``) of the dancer whose body core a column lies in
        for k, o in enumerate(others):
            in_front = y + h > o.box[1] + o.box[3] + c.pixel_front * h  # this dancer stands in front of o
            if not own_segment and not in_front and o.box[1] < r1 and o.box[1] + o.box[3] > r0:
                level_boxes[columns(o.box[0], o.box[2])] = True
            ox, oy, ow, oh = self._core(o.box)
            if oy < r1 and oy + oh > r0:
                span = columns(ox, ow)
                if own_segment and o.box[1] + o.box[3] > y + h + c.pixel_front * h:
                    continue  # o stands in front: its skeleton was a background seed
                cores[span] = np.where(cores[span] < 0, -1, 1 if in_front else -1)
                owner[span] = k
        needed = max(3.0, c.pixel_min_thickness * h)
        full = counts > c.pixel_max_fill * (r1 - r0)
        limit = c.pixel_max_reach * h
        # a run still going at the limit is followed on (not own_segment) to see whether it ends on a dancer's body
        scan = limit if own_segment else max(limit, c.pixel_follow_reach * h)
        reach = []
        for edge, step in ((int(np.floor(x)) - 1, -1), (int(np.ceil(x + w)), 1)):
            last, gap, col = 0, 0, edge
            while 0 <= col < width and abs(col - edge) < scan:
                if full[col]:
                    if c.pixel_full_in_box and level_boxes[col]:
                        last = 0  # the run crossed that dancer's limb to its body
                    break
                if cores[col] > 0 and own_segment:
                    pass  # the limb crosses the body of a dancer behind this one
                elif cores[col] != 0:  # the run reaches another dancer's body: it stops there, and if that dancer
                    # stands in front or level, the limb may be that dancer's, reaching towards this one
                    strip = (min(col, edge), r0, abs(col - edge) + 1, r1 - r0)
                    if cores[col] < 0 and not (
                            c.pixel_unexplained_limb and last and dancer is not None
                            and not self._hidden_behind(dancer)  # its extent is held: no growth on weak evidence
                            and self._limb_unexplained(others[owner[col]], strip, fg.shape, *chosen)
                            and not (c.pixel_unexplained_own
                                     and self._limb_unexplained(dancer, strip, fg.shape, *chosen))):
                        last = 0
                    break
                if counts[col] >= needed:
                    last, gap = min(abs(col - edge) + 1, limit), 0
                else:
                    gap += 1
                    if gap > c.pixel_gap:
                        break
                col += step
            reach.append(float(last))
        return reach[0], reach[1]

    def _limb_unexplained(self, o: DancerTrack, strip, shape, poses, margins) -> bool:
        """Whether dancer ``o`` has a pose chosen clearly on this frame (``poses``, ``margins``:
        :meth:`_clear_pose`) whose skeleton draws no limb in ``strip`` (x, y, w, h px; ``shape``: the frame's height,
        width): foreground there is not its limb (:meth:`_clear_pose_draws_limb`)."""
        return self._clear_pose_draws_limb(o, strip, shape, poses, margins) is False

    def _clear_pose(self, j: int, poses, margins) -> bool:
        """Whether Algorithm 2* chose a pose for dancer ``j`` clearly (selection margin >= ``pose_margin``)."""
        return (j < len(poses) and poses[j] is not None and j < len(margins) and margins[j] is not None
                and margins[j] >= self.config.pose_margin)

    def _stacked_pairs(self, fg: np.ndarray, poses, margins):
        """Dancers standing straight behind one another, with the foreground beside them: yields (d, f, runs,
        own, front_runs) for each dancer d (tracked or occluded, no clear pose of its own) behind a tracked dancer f
        with a clearly chosen pose (margin >= ``pose_margin``) that stands straight in front of it
        (:meth:`_straight_in_front`).
        ``runs``: how far (px) foreground runs on from f's box to the left and right at d's arm height
        (:meth:`_run_reach`); ``front_runs``: the same at f's own arm height (``front_own_band``; else ``runs``).
        ``own``: per side, whether that limb may be f's: f's skeleton reaches beyond its box
        there by more than ``stacked_arm_out`` x f's height, or one of its forearms points out to that side by as
        much (the detector often ends the arm short of the hand)."""
        c = self.config
        for i, d in enumerate(self.dancers):
            if d.status not in (TRACKED, OCCLUDED) or self._clear_pose(i, poses, margins):
                continue
            for j, f in enumerate(self.dancers):
                if f is d or f.status != TRACKED or not self._clear_pose(j, poses, margins):
                    continue
                if not self._straight_in_front(f, d):
                    continue
                fx, fy, fw, fh = f.box
                kp = poses[j].body25()
                seen = kp[:, 2] > 0
                if not seen.any():
                    continue
                others = [o for o in self.dancers if o is not d and o is not f and o.status != OUT]
                runs = self._run_reach(f.box, others, fg, limb_box=d.box)
                front_runs = self._run_reach(f.box, others, fg) if c.front_own_band and c.front_extent else runs
                skel_left = max(0.0, fx - float(np.min(kp[seen, 0])))
                skel_right = max(0.0, float(np.max(kp[seen, 0])) - fx - fw)
                forearms = [kp[w, 0] - kp[e, 0] for e, w in ((3, 4), (6, 7)) if kp[e, 2] > 0 and kp[w, 2] > 0]
                points = c.stacked_arm_out * fh
                own = (skel_left > points or any(v < -points for v in forearms),
                       skel_right > points or any(v > points for v in forearms))
                yield d, f, runs, own, front_runs

    def _stacked_reach(self, i: int, pairs) -> tuple[float, float]:
        """Extent (px, left and right of its box) of dancer ``i`` hidden straight behind another dancer f
        (``pairs``: :meth:`_stacked_pairs`): foreground running on from f's box at arm height further than
        ``stacked_tolerance`` x f's height, on a side where f's own skeleton neither reaches nor points, is a limb
        of a dancer behind f: dancer ``i``'s box reaches as far, unless that is more than ``stacked_max_reach`` x
        its height (shoulder to fingertip; a longer limb is not its own), or more than ``front_long_run`` x it (the
        front dancer takes that limb, :meth:`_front_reach`)."""
        c = self.config
        d = self.dancers[i]
        left = right = 0.0
        for hidden, f, (run_left, run_right), own, _ in pairs:
            if hidden is not d:
                continue
            slack = c.stacked_tolerance * f.box[3]
            longest = c.stacked_max_reach * d.box[3]  # a longer limb cannot be d's
            if c.front_long_run is not None:
                longest = min(longest, c.front_long_run * d.box[3])  # ... and f takes it (:meth:`_front_reach`)
            if run_left > slack and not own[0]:
                reach = _beyond(d.box, f.box, run_left, 0)
                left = max(left, reach if reach <= longest else 0.0)
            if run_right > slack and not own[1]:
                reach = _beyond(d.box, f.box, run_right, 1)
                right = max(right, reach if reach <= longest else 0.0)
        return max(0.0, left), max(0.0, right)

    def _front_reach(self, i: int, pairs) -> tuple[float, float]:
        """Extent (px, left and right of its box) of dancer ``i`` standing straight in front of a dancer without a
        pose (``pairs``: :meth:`_stacked_pairs`; :meth:`_pixel_reach` gives such a pair nothing): on a side where
        ``i``'s own skeleton reaches or points out, the foreground running on from its box at its own arm height
        (``front_runs``) is taken as its arm, up to ``stacked_max_reach`` x its height. With ``front_long_run`` also
        on a side where its skeleton does not reach, when the run there (at the hidden dancer's arm height, as
        :meth:`_stacked_reach` scans it) is longer than ``stacked_tolerance`` x its height and reaches further beyond
        the hidden dancer's box than ``front_long_run`` x that dancer's height (:meth:`_too_long_for`): the limb is
        then not the hidden dancer's but this one's, drawn short or folded in by the detector."""
        c = self.config
        d = self.dancers[i]
        left = right = 0.0
        for hidden, front, runs, own, (run_left, run_right) in pairs:
            if front is not d:
                continue
            longest = c.stacked_max_reach * d.box[3]
            mine = own
            if c.front_long_run is not None:
                mine = (own[0] or self._too_long_for(hidden, d, runs[0], 0),
                        own[1] or self._too_long_for(hidden, d, runs[1], 1))
            left = max(left, min(run_left, longest) if mine[0] else 0.0)
            right = max(right, min(run_right, longest) if mine[1] else 0.0)
        return left, right

    def _too_long_for(self, hidden: DancerTrack, front: DancerTrack, run: float, side: int) -> bool:
        """Whether a foreground ``run`` (px) beside ``front``'s box on ``side`` (0 left, 1 right) is a limb
        (longer than ``stacked_tolerance`` x ``front``'s height) reaching further beyond dancer ``hidden``'s box than
        ``front_long_run`` x its height (about its arm's length: a longer limb is not its own)."""
        c = self.config
        if run <= c.stacked_tolerance * front.box[3]:
            return False
        return _beyond(hidden.box, front.box, run, side) > c.front_long_run * hidden.box[3]

    def _grabcut_reach(self, i: int, frame, fg: np.ndarray, poses, margins) -> tuple[float, float]:
        """Extent (px, left and right of its box) of dancer ``i`` in a group, from its own segment.

        Where a dancer's arm crosses the body of another, the foreground (``fg``) runs on as one region and the
        column scan of :meth:`_pixel_reach` must stop at the other's body. GrabCut (OpenCV's ``cv2.grabCut``: a
        colour model of the dancer and one of everything else, both re-fitted, and a graph cut with a smoothness
        term, seeded from what the tracker knows) separates this dancer's pixels from those of the dancers around
        it, so that its limb can be followed across them; no other per-person segmentation is at hand on the
        frames (the person masks of a pose model gave the front dancer's mask on a hidden dancer's crop).

        Only for a dancer whose body core overlaps another's (a clear dancer is handled by the detections and
        :meth:`_pixel_reach`), tracked, or occluded with a clearly chosen pose (margin >= ``pose_margin``; the middle
        of an occluded dancer's predicted box is mostly the dancer hiding it); and not for one stacked straight
        behind or in front of another (cores overlapping more than ``pose_stack_overlap``) unless both have a
        clearly chosen pose: a body strip seed would be either dancer's, and a limb beside the pair may be either's
        (on a drawn stacked pair the front dancer's segment took the hidden one's arm). On a crop of the frame (the
        box's rows, the box widened by ``grabcut_widen`` x its height on each side) at ``grabcut_scale``,
        ``grabcut_iterations`` iterations, seeded with:

        - sure foreground: the skeleton of the pose chosen for the dancer, or without one a strip down the middle of
          its box (15 % to 85 % of its height), ``grabcut_seed_thickness`` x its height thick, where foreground and
          inside its box (a keypoint beyond the box may lie on another dancer's limb);
        - sure background: pixels ``fg`` marks as background, and the skeletons (strips) of the other dancers that
          stand level with it or in front (box bottom not ``pixel_front`` x its height higher in the image);
        - probably foreground: the other foreground pixels inside its box; probably background: the rest (dancers
          behind it too: its limbs may cross them).

        The part of the segment connected to the sure foreground is scanned like foreground by :meth:`_run_reach`
        over rows ``grabcut_rows`` of the box, passing over the body cores of dancers behind and in front of it.
        The OpenCV random generator is seeded before each cut (its k-means start), so a frame gives one result."""
        c = self.config
        d = self.dancers[i]
        if d.status not in (TRACKED, OCCLUDED) or not self._overlapping(i, [o.box for o in self.dancers]):
            return 0.0, 0.0
        clear = self._clear_pose(i, poses, margins)
        if d.status == OCCLUDED and not clear:
            return 0.0, 0.0  # a body strip down its predicted box would lie on the dancer hiding it
        if any(o is not d and o.status != OUT and self._bodies_overlap(o.box, d.box) > c.pose_stack_overlap
               and not (clear and self._clear_pose(j, poses, margins)) for j, o in enumerate(self.dancers)):
            return 0.0, 0.0
        height, width = fg.shape
        x, y, w, h = d.box
        x0, x1 = int(max(0, x - c.grabcut_widen * h)), int(min(width, np.ceil(x + w + c.grabcut_widen * h)))
        y0, y1 = int(max(0, y)), int(min(height, np.ceil(y + h)))
        if x1 - x0 < 8 or y1 - y0 < 8:
            return 0.0, 0.0

        def seed(j: int) -> np.ndarray:
            """The skeleton of dancer j's chosen pose, or a strip down the middle of its box, on the crop (bool)."""
            o, p = self.dancers[j], poses[j] if j < len(poses) else None
            mask = None if p is None else skeleton_mask(p.body25(), p.box, (width, height), c.grabcut_seed_thickness)
            if mask is None or not mask.any():
                mask = np.zeros((height, width), np.uint8)
                ox, oy, ow, oh = o.box
                half, mid = max(1.0, c.grabcut_seed_thickness * oh / 2), ox + ow / 2
                cv2.rectangle(mask, (int(mid - half), int(oy + 0.15 * oh)), (int(np.ceil(mid + half)),
                                                                             int(oy + 0.85 * oh)), 255, -1)
            return mask[y0:y1, x0:x1] > 0

        f = fg[y0:y1, x0:x1]
        labels = np.full(f.shape, cv2.GC_PR_BGD, np.uint8)
        bx0, bx1 = int(max(0, x - x0)), int(min(x1 - x0, np.ceil(x + w - x0)))
        inside = labels[:, bx0:bx1]
        inside[f[:, bx0:bx1]] = cv2.GC_PR_FGD
        labels[~f] = cv2.GC_BGD
        for j, o in enumerate(self.dancers):
            if o is not d and o.status != OUT and o.box[1] + o.box[3] >= y + h - c.pixel_front * h:
                labels[seed(j) & f] = cv2.GC_BGD  # level or in front: its limbs are not this dancer's
        own = seed(i) & f
        own[:, :bx0] = False  # inside its box only: a keypoint beyond it may lie on another dancer's limb
        own[:, bx1:] = False
        labels[own] = cv2.GC_FGD
        if own.sum() < 5 or not (labels == cv2.GC_BGD).any():
            return 0.0, 0.0
        crop = np.ascontiguousarray(frame[y0:y1, x0:x1])
        s = c.grabcut_scale
        if s != 1.0:
            small = (max(2, int(round((x1 - x0) * s))), max(2, int(round((y1 - y0) * s))))
            crop = cv2.resize(crop, small, interpolation=cv2.INTER_AREA)
            labels = cv2.resize(labels, small, interpolation=cv2.INTER_NEAREST)
            own = cv2.resize(own.astype(np.uint8), small, interpolation=cv2.INTER_AREA) > 0  # keeps thin seeds
            labels[own] = cv2.GC_FGD
        cv2.setRNGSeed(0)  # its k-means start: one result per frame (reseeds OpenCV's generator of this thread)
        try:
            cv2.grabCut(crop, labels, None, np.zeros((1, 65)), np.zeros((1, 65)), c.grabcut_iterations,
                        cv2.GC_INIT_WITH_MASK)
        except cv2.error:  # e.g. no background sample left in the crop
            return 0.0, 0.0
        segment = ((labels == cv2.GC_FGD) | (labels == cv2.GC_PR_FGD)).astype(np.uint8)
        _, parts = cv2.connectedComponents(segment)
        keep = np.unique(parts[own & (segment > 0)])
        keep = keep[keep > 0]
        if not keep.size:
            return 0.0, 0.0
        mine = cv2.resize(np.isin(parts, keep).astype(np.uint8), (x1 - x0, y1 - y0), interpolation=cv2.INTER_NEAREST)
        full = np.zeros((height, width), bool)
        full[y0:y1, x0:x1] = mine > 0
        others = [o for o in self.dancers if o is not d and o.status != OUT]
        return self._run_reach(d.box, others, full, own_segment=True, rows=c.grabcut_rows, dancer=d,
                               chosen=(poses, margins))

    def _pose_extends(self, d: DancerTrack, pose, margin, poses) -> bool:
        """Whether ``pose``, chosen for dancer ``d`` with selection ``margin``, may extend its reported box (the
        conditions of :meth:`extend_to_poses`)."""
        c = self.config
        if margin is None or margin < c.pose_margin or d.adapted_at == self.frame_index:
            return False
        if self._fit_score(d.box, pose.box) < c.group_min_score or \
                not 1 / c.max_height_change <= pose.box[3] / d.box[3] <= c.pose_max_height:
            return False
        return not any(o is not d and o.status != OUT and (j >= len(poses) or poses[j] is None)
                       and self._bodies_overlap(o.box, d.box) > c.pose_stack_overlap
                       for j, o in enumerate(self.dancers))
