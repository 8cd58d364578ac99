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

A dancer whose box leaves the frame is *out* (no box) until it comes back: on a detection, or without one on the
strip at the left or right edge it left by, when that strip matches its memory clearly better than the empty edge
did (:meth:`MultiDancerTracker._reenter_at_edge`).

Dancers may start later than the first frame (:meth:`MultiDancerTracker.add_dancer`).

Boxes are (x, y, w, h) pixels, top-left corner; velocities px/frame; frames are 0-based indices.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy.optimize import linear_sum_assignment

from hdvr.tracking.appearance import (box_inside, box_iou, box_overlap, clip_box, colour_bins, colour_histogram,
                                      foreground_mask, histogram_similarity)
from hdvr.tracking.extent import ReportedExtent
from hdvr.tracking.ldes import LDESConfig, LDESTracker
from hdvr.tracking.state import (BODY_CORE_ASPECT, OCCLUDED, OUT, TRACKED, DancerTrack, FrameResult, body_core,
                                 box_at, box_centre, covered_fraction, stands_in_front)

#: fraction of a dancer's box height left out at its top and at its bottom in the dancers' colour histograms
HISTOGRAM_END_SHRINK = 0.15
#: covers of an occluded dancer's predicted boxes within this of the best are as well hidden
#: (``MultiTrackerConfig.hold_uncovered_prediction``: it stops at the middle of those boxes)
COVER_TIE = 0.05


HIDDEN_SIDES_MODES = ("off", "tracked", "written")  # ``MultiTrackerConfig.keep_hidden_sides``


@dataclass(frozen=True)
class MultiTrackerConfig:
    """Parameters of Algorithm 1* (defaults tuned on the procedural crossing clips)."""

    # dancers: a tight search window and a strong colour term keep thin limbs from losing to a textured
    # background; dancers turn in depth, not in the image plane, so in-plane rotation is not estimated
    ldes: LDESConfig = field(default_factory=lambda: LDESConfig(padding=0.6, colour_weight=0.5,
                                                                estimate_rotation=False, estimate_scale=False))
    overlap_threshold: float = 0.05  # intersection / smaller core area above which two dancers overlap
    core_aspect: float = BODY_CORE_ASPECT  # overlaps are tested on body cores at most this x the box height wide
    velocity_window: int = 30  # clear frames over which the stored velocity is fitted (least squares)
    min_velocity_span: int = 1  # a clear track spanning fewer frames (one position, e.g. the first clear frame
    # after a re-identification) gives no velocity: the stored one is kept, not replaced by zero
    prediction_velocity: float = 1.0  # fraction of the stored velocity with which an occluded dancer's box is
    # predicted and its cone search aimed (once a detector runs: ``detector_prediction_velocity``, where set); the
    # failure test keeps the whole. Below 1 the tracker alone loses a crossing of procedural figures moving on at
    # constant speed (test_three_dancers_cross_without_identity_switch: measured at 0.5 and 0, session 55)
    detector_prediction_velocity: float | None = None  # ... the same once a detector runs (detections given to
    # :meth:`MultiDancerTracker.add_dancer` or :meth:`MultiDancerTracker.step`); None: ``prediction_velocity``
    # throughout. A detector finds a dancer that walked on out of hiding, while a dancer standing still behind a
    # partner is looked for far from where it is at full velocity (hdvr synth D 2705 ballet 0.898 -> 0.969, 2714
    # ballet 0.823 -> 0.981 at 0.5). An option, off: docs/benchmarks.md "session 56"
    detector_velocity_if_found: bool = True  # ... and only for a dancer on whose clear box the detector found a
    # person on the last detector frame before it was hidden (the detector sees it, so it will find it again where
    # it comes out); one it did not find is predicted with ``prediction_velocity``. Session 56, YOLO on every 3rd
    # frame, 0.5 against 1: hdvr synth sets D, F, G (120 clips each) and a fresh H (60) 7 + 7 + 5 + 0 -> 5 + 7 + 5 +
    # 0 failing, none newly failing; procedural crossings with the detector (36 clips of 2-4 stick figures) 11 -> 11
    # failing, switches 12 -> 15; but procedural groups of 6 (6 clips) get 4 more switches (seed 3 0.99 -> 0.86).
    # For every dancer alike (this off): as many failing on D-H, procedural crossings 11 -> 13 failing
    max_speed: float = 0.06  # x box height per frame: the stored velocity is capped there (a dancer crossing the
    # frame runs at about 0.03)
    histogram_smoothing: float = 0.1  # weight of the newest histogram in the stored one
    histogram_side_shrink: float = 0.15  # the colour histograms of dancers' boxes (memories and candidates) leave
    # out this fraction of the box's width on the left and on the right (and ``HISTOGRAM_END_SHRINK`` of its height
    # at the top and at the bottom). 0.25, the middle half, where the body is, measured in session 54 on three sets
    # of 120 hdvr synth clips: docs/benchmarks.md; it fails two procedural tests of tests/test_tracking_multi.py
    failure_angle_deg: float = 60.0  # turn of the motion direction that counts as a tracking failure
    min_speed: float = 0.7  # px/frame: below this the direction is not trusted (histogram test only)
    failure_histogram: float = 0.5  # similarity to the stored histogram below this = failure while overlapped
    failure_psr: float = 2.5  # correlation-filter peak-to-sidelobe ratio below this = failure while overlapped
    motion_window: int = 4  # frames over which the current motion is measured
    min_motion_px: float = 4.0  # displacement over the motion window below which its direction is not trusted
    still_needs_follower: bool = True  # a dancer without a stored velocity that moves off fails only when it moves
    # like a dancer it overlaps (its tracker dragged along: :meth:`_moves_with`)
    follower_angle_deg: float = 45.0  # ... within this angle of that dancer's motion
    follower_speed_ratio: float = 2.0  # ... and within this factor of its speed
    still_histogram: float = 0.7  # ... or when its box matches its stored histogram less than this: it moves off
    # onto another look (dragged by a dancer whose own tracker is lost, so whose motion is unknown; seed 137 ballet
    # of hdvr synth: a still dancer's tracker went off with the dancer passing in front, IDF1 0.883 -> 0.985)
    couple_moves_together: bool = True  # ... except for a dancer never seen clear that started overlapping exactly
    # one other dancer and moves with it alone: a couple in hold, whose partners move together from the first frame
    # on (:meth:`MultiDancerTracker._couple_in_hold`). Cached synthetic clips: seeds 201-212 and 151-199 mean IDF1
    # 0.9585 -> 0.9621, switches 15 -> 14 (seed 201 tango 0.575 -> 0.875); seeds 7-139 the same mean, 2 -> 3
    # switches (seed 97 hip-hop quartet); groups of 6-8 0.9279 -> 0.9278; held-out seeds 301-312 (benchmark) 10 -> 11
    # below 0.9 (seed 302 flamenco 0.950 -> 0.894)
    front_keeps_motion: bool = True  # no motion test (direction, stall, jump, a still dancer moving off) for a dancer
    # standing in front of every dancer it overlaps (box bottom lower by ``pixel_front`` x the height): it is the one
    # seen there, and a turn or a stop is its own dance, not an overlap taking its tracker off it (hdvr synth seed
    # 2202 hip-hop: the front dancer of four stopped walking left, was taken for occluded while fully seen, never
    # re-identified, and lost its identity to the dancer behind: IDF1 0.871 with a switch -> 0.979). Its correlation
    # peak, its histogram and the same-person test still apply. 504 synthetic clips: failing 18 -> 17, switches 8 ->
    # 7, 8 clips up, 5 down (2210 hip-hop 0.919 -> 0.783: a waiting dancer's box a few px off its amodal truth);
    # only where the front dancer moves like none it overlaps (a dragged tracker moves with the dancer dragging it):
    # 18 failing. Measured worse in session 17 on the code then (seed 208 tango), which no longer changes
    waiting_counts_behind: bool = True  # ... and a dancer waiting hidden behind it since its start counts as
    # behind it whatever their boxes' bottoms: the waiting box is a guess (its start box, moved with the front
    # dancer's), not a place the dancer was seen standing. Seed 2844 tango (session 71): the woman waiting behind
    # the man stepped out to his side; her guessed box's bottom came level with his, he no longer counted as in
    # front, turned, failed the direction test while fully seen (colours 0.99 of his memory), and stood predicted
    # as occluded for 62 frames, his prediction on her detection so that she could not come out (IDF1 0.762 ->
    # 0.938). Its correlation peak, histogram and same-person tests still apply. 295 clips with a hidden start: failing
    # 17 -> 16, switches 10 -> 9; 2712 tango 0.875 -> 0.842 (failing before), 2902 hip-hop 0.956 -> 0.927
    same_person_iou: float = 0.5  # two tracked boxes overlapping more than this (IoU) may be on the same person:
    # the one matching its own memory worse has failed
    same_person_inside: float | None = 0.9  # ... and so may a tracked box lying at least this much (its area's
    # share) inside another's, of a height within ``same_person_height`` of it, while a person of its height that no
    # tracked dancer takes has been seen on ``same_person_stray`` detector frames in a row (``unclaimed``): a box that
    # drifted onto a dancer as tall in front of it is narrower than that dancer's, and the IoU stays below 0.5 (seed
    # 2962 hip-hop: 0.48 for 85 frames, the dancer clear beside the group, taken by nobody; 0.792 -> 0.971). The
    # untaken person is what tells a drifted box from a couple in hold, one box inside the other's: without that
    # test, 0.9 broke 3047 ballet and made 3044 tango 1.000 -> 0.946. None: off. Session 82, the 1,443 clips of
    # sessions 80-81: failing 39 -> 38, 2 clips changed (2951 tango 0.954 -> 0.946); a fresh set of 150: 4 -> 4, none
    # changed (docs/benchmarks.md "Session 82")
    same_person_stray: int = 3
    same_person_height: float = 1.25
    stranger_in_front: float | None = 0.4  # a dancer clear of the others whose one detection is someone else walking
    # in front of it is hidden behind that person, not that person: the detection's colours match the dancer's memory
    # less than this, it is at least ``stranger_height`` x as tall as the dancer's box, and its bottom lies at least
    # ``stranger_lower`` x that height lower (nearer the camera). The dancer is then occluded (memory and velocity
    # kept) instead of adapting its box to the person and learning its colours; a dancer waiting hidden behind
    # another may come out on that detection (:meth:`MultiDancerTracker._stranger_in_front`). Seed 3048 flamenco: a
    # small dancer standing still was walked over by one 1.25 x her height who had waited behind the dancer in front
    # (colours 0.24 of hers); her box grew onto him and followed him, and the waiting dancer never came out. The
    # person's path is unknown: the dancer is found again by re-identification on a detection
    # (``DancerTrack.behind_stranger``), not on its own tracker's box nor relocated to the patches about it (they
    # show him). Only for a person the tracking places nowhere: no other tracked dancer takes the detection and no
    # other dancer's box (waiting or occluded ones' too) lies on it at IoU ``stranger_accounted`` or more; without
    # that, 3009 ballet was broken (a waiting dancer's box lay on the person: 0.979 -> 0.931 with a switch) and 2952
    # ballet lowered (the detection was a tracked neighbour's). Session 83, the 1,593 clips of sessions 80-82: failing
    # 42 -> 41, 3048 flamenco 0.692 with 2 switches -> 1.000, no other clip changed (docs/benchmarks.md "Session 83").
    # None: off
    stranger_height: float = 1.15
    stranger_lower: float = 0.1
    stranger_accounted: float = 0.3
    waiting_yields: bool = True  # ... except that a dancer still waiting hidden behind the other (``hidden_behind``)
    # fails, whatever the match: its memory is the start box, which shows the dancer in front, so the two match
    # their memories alike and the test would toss a coin, and the dancer in front is the one the video shows.
    # Cached synthetic clips (against the test by the match): seeds 201-212 and 151-199 mean IDF1 0.9769 -> 0.9771
    # (seed 173 hip-hop trio 0.828 -> 0.978, seed 208 ballet 0.994 -> 0.867); seeds 301-312 0.9650 ->
    # 0.9699, 9 -> 8 below 0.9 (seed 312 tango 0.592 -> 0.946: the visible dancer had failed in frame 1 and stood
    # still while the waiting one took its place); groups of 6-8 0.9468 -> 0.9515, 5 -> 1 switches; seeds 7-139 the
    # same. Exempting both dancers instead: 0.9710, 10 below, 4 switches (seed 181 tango 1.000 -> 0.750)
    cone_half_angle_deg: float = 12.0  # the cone's half angle about the predicted travel. Dancers on a floor seen
    # from the side keep their level while they cross, and at 100 px of travel 25 degrees reached 50 px above and
    # below it: procedural troupe of 8 seed 3, tracker alone, a dancer taken again on a patch 56 px above its figure
    # (session 62). 25 -> 12: groups failing runs 8 -> 7 of 24, switches 11 -> 8; crossings seeds 0-11 all pass
    # still; rendered D, F, G, H failing 6 + 3 + 2 + 0 -> 5 + 3 + 2 + 0 (D 2704 ballet 0.848 -> 0.975), mean IDF1
    # D 0.9872 -> 0.9882, F 0.9915 -> 0.9914, G and H the same
    cone_radii: tuple[float, ...] = (0.7, 0.85, 1.0, 1.15, 1.3)  # x the predicted travel distance
    cone_angles: int = 5  # directions sampled across the cone
    min_search_radius: float = 0.25  # x box height: search radius around the prediction when barely moving
    relocate_min_similarity: float = 0.3  # a candidate must correlate at least this well to be taken
    relocate_holder_cores: int = 1  # with > 0, relocation takes no detection that holds the body cores of this many
    # other dancers or more (:meth:`MultiDancerTracker._around_a_pile`; 0: no such test): a box around the dancer in
    # front and the hidden one is not the hidden one's (hdvr synth D 2719 ballet: a 174 x 164 px box taken by a dancer
    # of 57 x 132). Session 60, with ``own_box_max_back``: D, F, G, H failing 12 -> 10 (docs/benchmarks.md)
    relocate_patches: bool = True  # the cone search's patches are relocation candidates (Algorithm 1*); False, an
    # ablation: only the detections in the cone and the dancer's own tracker's box are (session 55, sets D and F of
    # 120 hdvr synth clips each: failing clips 7 -> 7 on each, mean IDF1 -0.0007 and -0.0003;
    # scripts/ablate_tracking.py)
    patch_min_foreground: float = 0.15  # a patch of the cone search takes an occluded dancer only if at least
    # this fraction of its pixels are foreground (:meth:`MultiDancerTracker._shows_someone`; 0 = any patch)
    hold_empty_prediction: bool = True  # an occluded dancer's predicted box stays where it was when it would move
    # clear of every other dancer onto background (fewer than ``patch_min_foreground`` of its pixels foreground).
    # With both (session 23), cached synthetic clips: seeds 201-912 mean IDF1 0.9771 either way, 41 -> 40 below 0.9,
    # 16 -> 13 switches; seeds 1201-1212 (fresh) 0.9646 -> 0.9676, 6 -> 5 switches (seed 1208 ballet 0.660 -> 0.871);
    # seeds 1101-1112 unchanged. Testing the dancer's own tracker's box too: seed 1102 hip-hop 0.917 -> 0.692
    hold_uncovered_prediction: float = 0.6  # once a detector runs, an occluded dancer whose predicted box was at
    # least this much hidden (fraction of its body core inside the body cores of the dancers followed in front)
    # stops when it would come out from behind them (below this), if the detector found it on the last detector
    # frames it was clear (``hold_found_streak`` in a row): a dancer the detector sees that walked out would have
    # been found, so it stopped behind them (a stick figure YOLO finds now and then is not held: procedural groups of
    # 6, seed 3, 0.99 -> 0.85 with 2 switches when one found on its last clear detector frame was). Its box goes back
    # to the middle of the stretch of its path hidden best (cover within ``COVER_TIE`` of the best) and stays
    # (``DancerTrack.stopped_behind``); the cone search's patches look on the way there, its detections in both
    # cones; hindsight keeps such a stretch's online boxes (``HindsightSettings.keep_stopped``). 0: off. The
    # tracker alone, which finds a dancer that walked on only on cone patches, keeps Algorithm 1*'s prediction.
    # Session 57, YOLO on every 3rd frame: hdvr synth sets D, F, G, H 7 + 7 + 5 + 0 -> 6 + 5 + 5 + 0 failing (D 2705
    # ballet 0.898 -> 1.000, F 2755 0.829 -> 1.000, 2758 0.871 -> 1.000), none newly failing; procedural crossings
    # with the detector switches 12 -> 11, failing 11 -> 11; groups of 6 and 8 as before
    hold_found_streak: int = 3  # ... detector frames in a row, while clear, on which a person lay on its box
    hold_unseen_prediction: bool = False  # ... or, for a dancer the detector was not finding so steadily, if the
    # part of its predicted box outside the other dancers' boxes shows no one (``_shows_someone``): the floor or wall
    # shows where it would have come out (hdvr synth seed 3053 ballet: a dancer walking in a clump, found on one
    # detector frame in a row, stopped behind another; her box ran on 45 px and stayed half over the empty floor).
    # Off: measured in session 77, 44 of 1,247 hdvr synth clips failing either way, 2 up and 5 down
    reid_similarity: float = 0.6  # before the predicted end of an overlap, a clear candidate needs this much
    reid_margin: float = 0.2  # ... and this much more than with any other occluded dancer's memory
    reid_radius_growth: float = 0.03  # x box height per frame: the re-identification radius (``2 x
    # min_search_radius`` box heights about the predicted and last clear positions) grows by this for each frame since
    # the dancer was last seen clear, up to ``reid_radius_cap`` box heights: behind the dancers in front it may walk
    # elsewhere than predicted, at up to about 0.9 of its height a second (a brisk walk) at 30 frames a second. Seed
    # 2922 flamenco (session 71): a dancer walked 170 px left behind a large dancer in front while her prediction
    # stood still; seen alone again, colours 1.00 of her memory, she was 150-170 px from it, outside the radius of
    # 100, and stayed occluded for 37 frames (IDF1 0.897 -> 0.911); no other of 491 clips rendered again changed.
    # 0: a fixed radius
    reid_radius_cap: float = 1.0  # ... x box height: the most the radius grows to
    reid_beside_held: bool = True  # a detection that overlaps tracked dancers may re-identify an occluded dancer
    # when each of them holds a detection of its own (:meth:`_reidentify`)
    reid_held_overlap: float = 0.5  # ... whose body core this one overlaps less than this (intersection / smaller)
    reid_beside_unheld: bool = True  # ... or tracked dancers without a detection whose memory it matches worse
    reid_unheld_height: float = 1.3  # ... if its height is within this factor of the occluded dancer's box
    reid_unheld_aspect: float = 2.0  # ... and its width / height at most this factor of the occluded dancer's box's
    # (a wider box there is a part of that dancer drawn apart, e.g. its upper body with spread arms)
    reid_unheld_rival_height: float | None = 1.3  # ... and at most this factor taller than each such dancer's box:
    # a box around that dancer and another figure beside it is taller than it (procedural crossings with the
    # detector, 4 figures, seed 10: a figure re-identified on a box 1.47 x its neighbour's height, 1.24 x its own,
    # kept that box's size to the end, IDF1 0.86 -> 0.95; hdvr synth D, F, G, H: no run changed). None: off
    reid_pile_cores: int | None = 2  # re-identification takes no detection that holds the body cores of this many
    # other dancers in the frame (their boxes, occluded ones' predicted boxes, each ``reid_pile_inside`` inside it):
    # a box around a pile of figures, not one of them coming out (procedural crossings with the detector: 3 figures
    # seed 7, all three occluded in a pile, one re-identified on YOLO's box around it, 0.88 -> 1.00; 4 figures seed
    # 3 0.87 -> 0.92; hdvr synth D, F, G, H and the groups of 6 and 8: no run changed). None: off
    reid_pile_inside: float = 0.9  # ... the fraction of such a core inside the detection
    reid_height_change: float = 1.25  # re-identification takes no detection this much taller or shorter than the
    # dancer's box, its bottom made good where a dancer in front hides it (:meth:`_feet_hidden`). A box about a
    # dancer's head and spread arms, a third of its height, took hdvr synth seed 901 swing's dancer in front for the
    # rest of the clip (IDF1 0.750 -> 1.000 with 2.0). Session 28, 2.0 -> 1.25: a dancer occluded for a frame or
    # two was taken again on a detection 0.72-0.77 x her height, the dancer behind's upper body (seed 707 hip-hop
    # 0.539 -> 0.731) or a floor shape (1512 hip-hop 0.810 -> 0.967); 936 clips 0.9763 -> 0.9767 (docs/benchmarks.md)
    relocate_height_change: bool = True  # relocation, too, takes no detection ``reid_height_change`` x taller or
    # shorter than the dancer's box (bottom made good behind a dancer in front). Session 28: seed 807 hip-hop, a
    # dancer relocated onto a 347 x 253 px box around two dancers while her box was 275 x 355 (0.878 -> 0.908; no
    # other clip of 936 changed)
    weak_detections: bool = True  # weak finds (:class:`hdvr.pose2d.base.PersonPose` ``weak``: scored between the
    # detector's weak and sure thresholds, mostly people partly hidden by another) update the boxes of dancers
    # followed, clear or in a group, and let a dancer that starts hidden come out; they never find a lost or occluded
    # dancer again (re-identification, relocation, re-entry, jumps: there they cost switches, see docs/tracking.md)
    reid_from_holder: bool = True  # a detection a tracked dancer holds goes to an occluded dancer whose memory it
    # matches at least ``reid_similarity`` and by ``reid_margin`` better than the holder's, if it stands in front of
    # the holder (bottom ``pixel_front`` lower): the holder's box shows the occluded dancer, come out in front of
    # it, and the holder is occluded from then on (:meth:`_reidentify`, :meth:`_handed_over`).
    # hdvr synth seed 503 ballet: a dancer at the back took the colours of the dancer walking out in front of it,
    # which was never re-identified; IDF1 0.633 -> 0.723 (seed 308 flamenco 0.883 -> 0.983)
    reid_holder_covered: float = 0.9  # ... and if it spans this much of the width of the holder's body core (the
    # holder is hidden behind it, not beside it; seed 609 ballet, 0.78 of it: 0.940 -> 0.727 with 2 switches)
    reid_past_waiting: bool = True  # an occluded dancer may be re-identified on a detection that a dancer waiting
    # behind it since its start (``hidden_behind``) takes, and beside or over such a dancer's body core: that dancer
    # shows nothing of its own, the person seen there is the one it waits behind (hdvr synth seed 3038 hip-hop: a
    # dancer occluded in a floor move stood up clear of everyone but the dancer hidden behind her, whose box took her
    # detection; her box was predicted on for 100 frames)
    own_box_max_shift: float | None = 0.15  # an occluded dancer's own tracker's box (running without learning) is a
    # candidate of re-identification and relocation only if its bottom lies within this x the dancer's box height of
    # the bottom of the dancer's box (held or predicted): a hidden dancer's feet stay on the floor, and a tracker
    # that drifts up or down off it follows something else (:meth:`_own_box_stays`). None: no such test. Session 48
    # (seed 212 hip-hop: a waiting dancer's box 47 px up behind crouching dancers, held there 100 frames; IDF1 0.602
    # -> 0.867): 504 synthetic clips failing 22 -> 20, mean IDF1 0.9854 -> 0.9863, switches 14 -> 8, 6 clips up, 2
    # down (2308 hip-hop 0.879 with 6 switches -> 0.925 with none, 2506 ballet 0.871 -> 1.000)
    own_box_max_back: float | None = 0.5  # ... and only if its centre lies at most this x the dancer's box width
    # behind the centre of the dancer's box along its stored velocity (a moving dancer; the cone of Algorithm 1*
    # lies ahead): a tracker that slid back onto the dancer in front follows that dancer's limbs (D 2719 ballet: 44
    # px behind, similarity 0.42; F 2752 ballet: 56 px behind, on the front dancer's arm). None: no such test
    waiting_back_behind: bool = True  # a dancer still waiting behind another since its start (``hidden_behind``)
    # whose tracker drifted onto the floor or wall (``lost_max_foreground``) is held behind that dancer, where it
    # stood relative to him when it began to wait (``DancerTrack.wait_offset``), not where the drift left it: nothing
    # showed it come out (hdvr synth seed 2804 ballet)
    waiting_empty_behind: bool = True  # an occluded dancer still waiting behind another since its start
    # (``hidden_behind``) whose box lies clear of the others' body cores and shows nobody (``_shows_someone``: the
    # floor or wall) while that dancer is followed goes back behind him, where it stood relative to him when it
    # began to wait (``DancerTrack.wait_offset``), and is predicted on from there: had it stayed there it would be
    # seen; it went on behind him (``DancerTrack.returned_behind``; hindsight then does not pull the wait back to the
    # start place). hdvr synth seed 2907 ballet: the dancer behind, occluded, stood predicted on the empty floor for
    # 75 frames while the dancer in front walked on with her (0.781 -> 0.998). Session 75: the 434 clips with a hidden
    # start of seeds 2701-3040 failing 29 -> 28, 2 clips up, none down (docs/benchmarks.md "Session 75")
    waiting_own_box: bool = False  # an occluded dancer still waiting hidden behind another since its start
    # (``hidden_behind``) has its own tracker's box as a candidate of re-identification and relocation
    # (:meth:`MultiDancerTracker._own_box_stays`). Off: not, its tracker having learned its start box, which showed
    # mostly the dancer in front; that box is no sighting of it (hdvr synth G 2762 hip-hop 0.953 -> 0.972; the
    # other 213 clips with a hidden start of D, F, G, H and seeds 2801-2880 unchanged, session 66)
    emerge_hidden_starts: bool = True  # a dancer started mostly hidden (``hidden_start_overlap``) takes the first
    # detection that comes out clear of every other dancer, that no other dancer takes and that does not look like
    # the dancer hiding it (:meth:`MultiDancerTracker._emerge`)
    emerge_relative: bool = True  # ... or that looks like it by ``reid_margin`` less than that dancer's own box
    # does: a person dressed partly alike is someone else (seed 504 flamenco: the dancer behind wore the front
    # dancer's colours in other places, 0.61-0.78 match; IDF1 0.728 -> 0.975)
    emerge_yields_to_known: bool = True  # ... nor that shows another dancer whose colours are known (not one
    # waiting so): its memory matches at least ``reid_similarity`` and by ``reid_margin`` more than every other
    # such dancer's (:meth:`MultiDancerTracker._shows_known_dancer`). The waiting dancer's colours are unknown; a
    # person who plainly is someone else is left to that dancer. A dancer waiting behind another since its start
    # took a dancer who had walked behind the same one and came out on the far side (her memory 0.92, the others
    # at most 0.43) while her box stayed behind, and kept her all clip (seed 2305 ballet)
    emerge_known_height: bool = True  # ... and only to a dancer that could take it: its box's height within
    # ``reid_height_change`` of the person's (:meth:`MultiDancerTracker._height_fits`). Seed 2826 ballet: the waiting
    # dancer walked out clear, detected for 40 frames at 117 px, and an occluded dancer 171 px tall whose colours
    # matched 0.62-0.72 kept her from it (0.842 -> 0.875). Session 66, on the 239 clips with a hidden start of D-H and
    # seeds 2801-2900: no clip passes or fails otherwise; 2831 hip-hop 0.933 -> 0.990, F 2743 flamenco 1.000 -> 0.972
    emerge_keeps_height: bool = True  # a dancer coming out on a detection shorter than its box keeps the box's
    # height (the detector sees the part already out; seed 705 tango, a couple in hold: 0.533 -> 0.812)
    emerge_beside_persist: int = 3  # with N > 0, a waiting dancer may also come out on a detection whose body core
    # overlaps other dancers' cores by less than ``emerge_beside_overlap`` (a dancer half beside the one in front),
    # when its colours match each of those dancers' memories less than ``emerge_beside_similarity`` and a detection
    # passing the same tests lay on it (IoU >= 0.5) on each of the N - 1 detector frames before (a person that
    # stays there, not a limb or a floor shape seen once; 0: off). Detector frames, whatever ``--detect-every``: a
    # detector frame without such a detection starts the count again. 219 hdvr synth clips with a hidden start: 8
    # up, none down (seed 1302 flamenco 0.861 -> 0.889, 802 ballet loses its switch); fresh seeds 2101-2312
    # unchanged. Without the persistence (session 31) fresh clips gained 4 switches; with 2 frames 9 up, 2 down
    emerge_beside_overlap: float = 0.5
    emerge_beside_similarity: float = 0.3
    emerge_distance: float = 1.0  # x the box height: how far from the dancer's box centre that detection may be
    emerge_max_aspect: float = 2.0  # ... and its width / height at most this factor of the dancer's box's: a wider
    # one is a part of a dancer that YOLO drew as a person, e.g. the spread arm of the dancer in front (seed 1308
    # hip-hop; cached synthetic clips: 8 of 864 up, none down, 4 switches fewer; docs/tracking.md, session 26)
    emerge_own_margin: float = 0.35  # with m > 0, also on a detection on its own box (IoU >= 0.5) that overlaps others,
    # when its colours match the front dancer's memory by m less than his box does now, on ``emerge_beside_persist``
    # detector frames in a row (seed 2665 hip-hop: the dancer behind, seen on her own box for 90 frames, never came
    # out). Session 51: fresh clips (seeds 2601-2640) failing 10 -> 9, (2641-2680) 6 -> 5, tuned 16 -> 15; 0.2: 10, 5,
    # 16 (docs/benchmarks.md "session 51"). Session 50's version with the plain colour test of coming out: 36 -> 37
    emerge_past_waiting: bool = True  # ... another dancer still waiting so (not the one hiding this one) does not
    # stand in the way of that detection when it fits the detection less well (IoU) than this one's box: its box is a
    # guess where it may be, not a sighting (hdvr synth seed 2624 hip-hop: two dancers started behind the same one, who
    # walked away; the first, seen whole and detected for 90 frames, never came out because the second's box, still
    # at the start, lay on her). The dancer hiding this one still stands in the way when it waits itself (a stack of
    # three: seed 2507 flamenco, the dancer at the back took the middle one's detection, 0.967 -> 0.800)
    emerge_past_unlike_occluded: bool = True  # ... nor does a dancer occluded (not waiting) whose memory the
    # detection's colours match less than ``emerge_beside_similarity``: its box is a prediction from its velocity, and
    # the person there is plainly not it. Session 72: hdvr synth seed 2844 hip-hop, the waiting dancer stepped out
    # beside the one in front as he was predicted for four frames, and came out 15 frames later (0.887 -> 0.963); the
    # other 294 clips with a hidden start unchanged (docs/benchmarks.md "Session 72")
    emerge_front_first: bool = True  # a person coming out is offered first to the dancers waiting behind a dancer
    # followed, then to those waiting behind a dancer who waits too (a chain: that one is hidden by two, the first by
    # one); before, in the order of the dancers' numbers (hdvr synth G 2766 ballet: dancer 1, behind dancer 2 behind
    # dancer 3, took dancer 2 as she came out, 5 switches)
    emerge_height_yield: float = 0.1  # with m > 0, a waiting dancer leaves a detection to another dancer waiting so
    # whose box height fits it better by more than m (|log(detection height / box height)|) and who may come out on
    # it too (within its ``emerge_distance``, by the tests of :meth:`MultiDancerTracker._emerges_on`): of two dancers
    # waiting near one person coming out, the one of its size is the one it shows (0: off). Session 70: hdvr synth
    # seed 2906 flamenco, a stack of three, the middle dancer (185 px) took the one at the back (123 px) as she came
    # out: 0.606 with a switch -> 0.972
    emerge_front_leaves: float = 0.05  # with m > 0, a dancer in front walking out of the stack it forms with a dancer
    # waiting behind it since its start, whose own box stayed on the waiting one: when the detection given to it lies
    # on the waiting dancer's box (IoU >= 0.5) and an untaken detection within ``emerge_distance`` of its box, clear
    # of the body cores of the held detection and of the other dancers (the waiting one's too), looks like it (its
    # memory matched at least ``reid_similarity`` and by at most ``reid_margin`` less than its box now) and fits the
    # two heights the other way round (the front dancer's box height closer to it, the waiting dancer's closer to the
    # held detection, together by more than m in |log(height ratio)|), the front dancer moves to that detection and
    # the waiting one comes out on the held one (:meth:`MultiDancerTracker._front_leaves`; 0: off). Session 70: hdvr
    # synth seed 2870 ballet, his box stayed on her as he walked away, and another dancer later took him: 0.658 with
    # a switch -> 0.948
    emerge_min_aspect: float = 0.3  # ``emerge_max_aspect`` counts a waiting dancer's box as at least this wide for its
    # height (a start box seen side-on, 0.27, made a dancer turning to the camera as she came out "too wide")
    hidden_front_rival: bool = True  # while such a dancer waits, the dancer hiding it is one more rival when it is
    # re-identified (its memory shows that dancer: a patch of it would match). Cached synthetic clips: seeds 201-212
    # and 151-199 mean IDF1 0.9578 -> 0.9585, identity switches 23 -> 15; seeds 7-139 and groups of 6-8 unchanged
    reid_waiting_margin: float = 0.1  # ... but over a dancer still waiting hidden behind the dancer re-identified,
    # by this margin only: its memory is mostly that dancer's colours (seed 804 hip-hop: 0.83-0.89 against 0.96-0.98,
    # and the dancer in front stayed occluded to the end, IDF1 0.747 -> 0.972). Cached synthetic clips (936): 4 up,
    # none down, 0.9767 -> 0.9771; not counting it as a rival at all took a dancer in front on the waiting one (0.90
    # against 0.85, seed 802 hip-hop 0.861 -> 0.839; docs/tracking.md, session 29)
    hidden_start_overlap: float = 0.5  # a dancer whose body core is this much (intersection / smaller) inside the
    # core of a dancer in front when it starts is started hidden (:meth:`hiding_dancer`; the CLI warns)
    start_seen_iou: float = 0.0  # with a value > 0 (0.6 measured), such a dancer does not wait when the detector
    # finds it in its start frame (:meth:`MultiDancerTracker._seen_at_start`): one detection on its start box (IoU at
    # least this, and ``start_seen_margin`` more than with any other dancer's box), of its height
    # (``max_height_change``) and at most ``start_seen_aspect`` x as wide for its height, whose colours outside the
    # front dancer's body core match that dancer's memory less than ``reid_similarity``: it is seen and learns those
    # colours. Off: 219 hdvr synth clips with a hidden start, YOLO11n-pose: failing 35 -> 34 (fresh seeds: no
    # change), but with a detector that finds partly hidden dancers (the clips' ground truth) 22 -> 29; a dancer let
    # out while mostly behind her partner is occluded at once and her predicted box stays behind while the couple
    # moves on (seed 612 tango 1.000 -> 0.667; docs/tracking.md, session 35)
    start_seen_margin: float = 0.2
    start_seen_aspect: float = 1.5  # a wider box is a box around the dancer and someone beside (seed 309 hip-hop)
    orphan_persist: int = 2  # with N > 0, an occluded dancer (not one waiting since its start) that neither
    # re-identification nor relocation finds takes a *stray person*: a sure detection that no tracked dancer takes,
    # clear of every tracked dancer's body core and within ``reid_height_change`` of the dancer's box height, that
    # lay there (IoU >= 0.5 with the one before) on N detector frames in a row, if its colours match the dancer's
    # memory at least ``reid_similarity`` and by ``reid_margin`` better than any other occluded dancer's; wherever
    # it is (:meth:`MultiDancerTracker._take_stray`). A dancer that came out from behind another on the side away
    # from its stored motion stayed occluded in its old place while the detector found it clear of everyone for
    # 60 frames (seed 2110 flamenco). 0: off. 3 until session 47; 2 (with ``stray_adrift``), 504 synthetic clips:
    # failing 24 -> 23, switches 16 -> 14 (302 flamenco 0.922 with 2 switches -> 0.939 with none; 2310 ballet,
    # failing already, 0.873 -> 0.852)
    stray_adrift: bool = True  # ... and so does a tracked dancer whose memory a person no tracked dancer takes,
    # seen so on as many detector frames in a row (clear of the tracked dancers' cores or not) matches by
    # ``stray_adrift_margin`` better than its box does now (its box stayed behind in a group while the dancer came
    # out elsewhere), at least ``reid_similarity`` and by ``reid_margin`` better than the memory of any other dancer
    # whose colours are known; its tracker restarts there (seed 2305 ballet: a dancer's box stayed by the dancer she
    # had walked behind, for 75 frames, matching her memory 0.75 against the person's 0.83-0.90; 0.642 -> 0.863.
    # Seed 302 flamenco, the person inside the wide box of the dancer she had passed: 0.850 with 4 switches -> 0.922
    # with 2. Session 47, 504 synthetic clips: 3 changed, failing 24 -> 24, mean IDF1 0.9843 -> 0.9849)
    stray_adrift_margin: float = 0.05
    stray_adrift_height_change: float | None = 1.35  # ... and within this of the tracked dancer's box height (None:
    # ``reid_height_change``). A dancer whose box was never seen clear has no detection ratio yet, and its box holds
    # the whole body where the detector draws a little less: hdvr synth seed 3016 ballet, the dancer in front walked
    # out of a stack of three, her box (220 px) stayed on it, and the person she was (173 px, 1.27 x shorter; colours
    # 0.90-0.98 against her box's 0.74) was left for 80 frames
    adrift_hands_over_waiting: bool = True  # ... and the dancers still waiting behind it since their start, left
    # clear of its new box, wait behind the dancer followed straight in front of them from then on
    # (:meth:`MultiDancerTracker._hand_over_waiting`; hdvr track starts a new wait there, which hindsight keeps to):
    # they stood behind the stack its box had stayed on, not behind the dancer who walked out of it (seed 3016
    # ballet: hindsight took the dancer at the back 35 px along after the one walking out, IoU 0.83 -> 0.04)
    restart_hands_over_waiting: bool = False  # so at every restart of a dancer's tracker on another box
    # (:meth:`MultiDancerTracker._restart`: a jump to a detection, a box stuck off its dancer, a recovery, a
    # correction), not only the stray person's. Off: in session 77 it changed no clip among the 474 hdvr synth
    # clips with a hidden start; ``hdvr track`` records hand-overs made in a step as new hidden starts, not one made
    # at a user's correction
    front_of_waiting_clear: bool = True  # a dancer whose body core overlaps only dancers waiting straight behind it
    # since their start (``hidden_start_overlap``) counts as clear: its memory is stored, and its box's height (not
    # its width: the detection may hold their limbs beside it) adapts to the one detection on it. Before, such a
    # dancer was in a group and kept its box: a couple walking away, one hidden behind the other all along, kept the
    # front box 327 px tall while the dancer shrank to 245 (seed 2505 swing). Session 46, 504 synthetic clips:
    # failing 25 -> 24, mean IDF1 0.9839 -> 0.9843, 17 up, 13 down (2108 hip-hop 0.765 -> 0.977, 2210 hip-hop 0.808
    # -> 0.925; 2209 hip-hop 0.983 -> 0.856, and 309 hip-hop, failing already, 1 -> 2 switches). Adapting the whole
    # box: 27 -> 28 (2105 hip-hop: the detection held the spread arms of the dancer behind, the box doubled its width)
    front_narrows: bool = True  # ... and its box narrows (width and centre, by ``box_adaptation``) to that
    # detection where the detection is narrower: limbs of the dancers behind can only widen it
    # (:meth:`MultiDancerTracker._narrow_front`). Seed 2635 tango: a start box with spread arms stayed 145 px wide
    # while the dancer, arms in, was 70, and the dancer waiting behind took her detection (0.633 -> 0.983). Session
    # 51, with hindsight's 30-frame walk: fresh clips (seeds 2601-2640) failing 12 -> 10, (2641-2680) 6 -> 6, tuned
    # 15 -> 16 (docs/benchmarks.md "session 51")
    front_follows_feet: float = 0.05  # with > 0, a dancer with a dancer waiting straight behind it, when two or
    # more people of its height are detected on its box, restarts on the one whose feet are lowest (nearest the
    # camera: the one in front) if its box has slid off that one (IoU < 0.5) and its feet are this x its box height
    # below every other's (:meth:`MultiDancerTracker._follow_front_feet`). Session 66, with ``front_feet_max_off``:
    # 0.02 mended seed 2870 ballet (the two parted with their feet 3-5 px apart; 0.658 -> 0.940) but broke fresh
    # seed 2907 flamenco (0.981 -> 0.756 with a switch); 0.01 also D 2719 hip-hop (0.964 -> 0.933)
    front_feet_max_off: float | None = 0.5  # ... and only if that person's centre lies within this x the dancer's
    # box width of its box's columns (None: no such test): a third dancer's wide detection, an arm spread onto the
    # box, is not the dancer in front (hdvr synth seed 2819 hip-hop: the front dancer restarted on the person beside
    # it, 34 px beyond its box, and followed her for 85 frames; 0.823 -> 1.000, session 66)
    lost_search_after: int = 15  # with N > 0, a dancer occluded for N frames (not one waiting since its start) is
    # looked for over the whole frame every ``lost_search_every`` frames, with or without a detector
    # (:meth:`MultiDancerTracker._search_lost`): windows of its box's size where the pixels' colours are most its own
    # (a back-projection of its memory against the frame's colours, outside the tracked dancers' boxes:
    # :func:`likely_windows`, at least ``lost_search_min_share`` on average), clear of every tracked dancer's body
    # core, at most ``lost_search_max_inside`` inside a tracked dancer's box and showing foreground; taken when one's
    # colours match its memory at least ``reid_similarity`` and by ``reid_margin`` better than any other known
    # dancer's, near the same place on ``lost_search_persist`` searches in a row. In a dense group a dancer comes out
    # where neither its stored motion nor the detector (which misses textured figures) leads, and its box stayed in
    # the group to the clip's end (procedural troupe of 8, seed 1: a figure standing alone for 60 frames).
    # Session 61: procedural groups of 8, median IDF1 0.81 -> 0.90 (tracker alone), 0.76 -> 0.89 (with the
    # detector), switches over the 24 group runs 24 -> 10; crossings all pass still; rendered sets D, F, G, H: one
    # clip changed (D 2716 flamenco, failing already, 0.753 -> 0.736). 8 frames: 12 switches, 30: 16
    lost_search_out: bool = True  # ... and so is a dancer whose predicted box left the frame while it was occluded
    # (``out_unseen``: it may have turned back behind the others). Session 61, groups: failing runs 10 -> 9,
    # switches 10 -> 10 (8 figures alone median IDF1 0.906 -> 0.92); crossings and rendered sets D, F, G, H unchanged
    lost_search_every: int = 3
    lost_search_min_share: float = 0.6  # 0.5: 13 switches on the groups, 0.7: 17
    lost_search_persist: int = 2
    lost_search_max_inside: float = 0.25  # (a dancer partly hidden beside a group shows a strip of its colours there)
    max_occlusion_frames: int = 150  # after this many frames occluded, relocate to the best candidate anyway
    overlap_margin_frames: int = 2  # relocation starts this many frames after the predicted end of the overlap
    adapt_min_iou: float = 0.4  # a detection adapts a dancer's box only if it overlaps it this much (IoU)
    adapt_min_containment: float = 0.9  # ... or lies this much inside it (intersection / detection area): the
    # dancer got up from the floor, and its wide box holds the standing person
    adapt_containment_columns: bool = True  # ... the containment counted in columns (of the detection's width, the
    # part inside the box's columns), with at least half of its height within the box's rows: a dancer who got up
    # from a floor move has a wide, low box that the standing detection sticks out of at the top (seed 2203 hip-hop
    # quartet: a box 2.6 x the dancer's width for 90 frames; docs/tracking.md, session 45)
    adapt_max_foreground: float = 0.2  # ... and its columns beside the detection are background (at most this
    # fraction with a limb's worth of foreground: :meth:`_empty_around`)
    max_height_change: float = 1.6  # a detection this much taller or shorter than a dancer's box is not it
    foreground_trim: float = 0.01  # with > 0, on each detector frame a clear dancer's box side whose columns
    # hold fewer foreground pixels than this x the box height moves ``foreground_trim_weight`` of the way in to the
    # outermost column that holds more (:meth:`MultiDancerTracker._trim_to_foreground`): the detector finds a thin
    # figure mostly with its arms out, or boxes it wide beside a partner, and the box kept that width between
    # finds (procedural crossing, 2 figures seed 9: 180 px around an 88 px figure)
    foreground_trim_min_fill: float = 0.15  # ... only where at least this fraction of the box is foreground (the
    # dancer stands out from the background there)
    foreground_trim_min_aspect: float = 0.2  # ... and never narrower than this x the box height
    foreground_trim_weight: float = 1.0  # ... moving this much of the way in per detector frame
    adapt_beside_partner: bool = True  # a clear dancer whose one detection is refused as hers alone only because its
    # body core overlaps a partner's beside her (tracked, clear of her, not in front, holding a detection of her
    # own) adapts her box's height to it, keeping its bottom and width (:meth:`MultiDancerTracker._beside_partner`).
    # Cached synthetic clips: seed 1207 swing 0.808 -> 0.975, 13 others within 0.021 (docs/tracking.md, session 27)
    jump_rivals: bool = True  # a lost dancer jumps to a detected person only if it matches its memory by
    # ``reid_margin`` better than every other dancer's (:meth:`MultiDancerTracker._jump_to_detection`); without, a
    # dancer at the back of hdvr synth seed 406 ballet jumped onto a lost dancer passing in front (2 switches)
    keep_hidden_feet: bool = True  # a detection ending on the body of a dancer in front keeps the box's bottom
    # when the box adapts to it (:meth:`MultiDancerTracker._feet_hidden`)
    keep_hidden_sides: str = "written"  # ... and a detection narrower than the box whose side ends on the body of
    # a dancer in front keeps the box's width, from its other side: a partner in hold behind the dancer in front
    # shows her head and one shoulder (hdvr synth seed 2951 tango: the box of the dancer behind took a detection
    # 67 px wide, 0.53 of her width, for the whole clip). "written": only the written box reaches behind him, the
    # tracked box follows the part seen (:meth:`MultiDancerTracker._note_hidden_sides`,
    # :meth:`ReportedExtent._hidden_sides_reach`; session 80: 2951 tango 0.721 -> 0.954, 2773 swing 0.738 -> 0.963
    # and two flamenco trios mended, 3085 tango broken, 0.938 -> 0.854: a partner who turns narrow while hidden).
    # "tracked": the tracked box keeps it (:meth:`MultiDancerTracker._sides_hidden`; over 1,397 hdvr synth clips
    # 48 -> 49 failing, 5 mended and 6 broken: the wider box overlaps the dancer in front and the tracker then holds
    # the partner as occluded, seed 2921 tango 1.000 -> 0.688; session 79). "off": neither
    foreground_feet: float | None = 0.6  # a clear dancer's detection whose bottom ends above foreground that runs
    # on down in its columns (legs the detector left out: patterned trousers) ends where that run ends, at most
    # this x the detection's height lower, or down to the box's bottom (None: off;
    # :meth:`MultiDancerTracker._feet_in_foreground`; docs/tracking.md, session 67)
    foreground_feet_rows: float = 0.25  # ... a row counts when this fraction of the detection's middle half holds
    # foreground (columns in other dancers' boxes left out); the run may break for ``pixel_gap`` rows
    feet_of_detections_only: bool = True  # ... a detection only: a dancer taken again on a patch of its own box
    # size (cone search, its own tracker) keeps the patch as it is; a patch a little up the motion direction grew
    # by that much each time (seed 304 ballet: 134 -> 185 px in two relocations, then 2 identity switches)
    max_vertical_speed: float = 0.005  # x box height per frame: the stored velocity's vertical part is capped
    # there (0: only ``max_speed``). Dancers on a floor seen from the side move up or down the image only by walking
    # towards or away from the camera: in the rendered hdvr synth sets D, F, G the ground-truth boxes' centres move
    # 0.0007 box heights per frame (median over 15 frames; 99th percentile 0.0056). A tracker taken again on a
    # patch off its figure jumps back to it over the next frames, and those clear frames gave a hidden figure a
    # vertical velocity of 5.7-10.9 px/frame (procedural groups of 8, boxes 192 px: 0.03-0.06) that carried its
    # predicted box 100-270 px off (session 63). 0.005: groups failing runs 7 -> 5 of 24, switches 8 -> 4;
    # crossings seeds 0-11 unchanged; rendered D, F, G, H the same 10 of 420 failing, D 2716 flamenco switches 2
    # -> 0; 0.01: groups 7 failing, 5 switches; 0.0025: groups 4 failing, but D 2704 ballet 0.975 -> 0.848 (a far
    # dancer hidden for most of the clip, whose vertical motion is real) and D 2716 back to 2 switches
    vertical_prediction_frames: float = 60.0  # with tau > 0, an occluded dancer's predicted box moves up or down
    # the image as if its stored vertical velocity faded with this time constant (frames): tau x (1 - exp(-t / tau))
    # frames' worth after t frames, never more than tau frames' worth; sideways it moves on at its stored velocity.
    # Dancers move about a floor seen from the side: they cross sideways for long, while the image's vertical
    # motion comes from walking towards or away from the camera, slowly, and over a few clear frames also from the
    # tracker bobbing with the steps and arms. The vertical velocity measured so carried a hidden figure's box 60-100
    # px below or above it over a long occlusion (procedural crossing, 4 figures seed 14 with the detector, a seed
    # never tuned on: a figure walking level predicted 1.1 px/frame downwards for 90 frames, IDF1 0.89 -> 0.98).
    # Session 62: crossings seeds 12-23 (held out) failing 1 -> 0 of 72, seeds 0-11 all pass still; groups of 6 and
    # 8 failing runs 9 -> 8 of 24 (switches 10 -> 11); rendered sets D, F, G, H failing 10 -> 11 of 420 (D 2704
    # ballet, a far dancer hidden for 80 frames, 0.919 -> 0.848), mean IDF1 down 0.0001-0.0006 each: in hdvr synth's
    # 3D dances the vertical motion is partly real. tau 20: groups 7 failing, rendered 12; fading sideways too (tau
    # 60) 15 group runs failing (figures do walk on behind others). 0: Algorithm 1*'s linear prediction
    occluded_keeps_size: bool = True  # an occluded dancer's predicted box has the size its box had when it was
    # hidden, not that of its last clear box (a couple in hold is never clear: seed 803 tango had shrunk by a third
    # walking away; IDF1 0.671 with 2 switches -> 0.996 with none)
    box_adaptation: float = 0.3  # per confirming detection, weight of the detected box in a clear dancer's box
    max_box_offset: float = 0.25  # box centre at most this x its size from the tracker's centre
    max_person_width: float = 2.0  # a detection wider than this x a dancer's box height is not that dancer alone
    max_size_ratio: float = 1.4  # the initial box is at most this much wider or narrower than the detector's
    max_height_ratio: float = 1.3  # ... and at most this much taller or shorter: a first detection that leaves the
    # legs out would keep the box that much too tall all along (the box follows its detections times this ratio).
    # The ground truth's height over YOLO11n-pose's for dancers seen whole: median 1.09, 99th percentile 1.26. hdvr
    # synth, 936 clips: 16 up, 2 down, failing 52 -> 51 (1506 hip-hop 0.890 -> 0.904, 310 flamenco 0.950 -> 1.000;
    # 711 ballet 0.967 -> 0.929); fresh seeds 2501-2512: 2 up, none down
    late_ratio_samples: int = 0  # with N > 0, a ratio learned after the start frame (no detection on the start
    # box then, or a stack) is the median of N clear detections' ratios to the box the first one was taken against,
    # taken within ``late_ratio_frames`` of it; 0: no ratio is learned after the start frame, and the box of such a
    # dancer follows its detections as they are (the detector's convention). A moving dancer's first detection
    # makes a poor ratio: one that left the legs out kept the box up to 1.3 x too tall all clip (seed 2402 swing:
    # 192 px against a 259 px box, 1.16 x the dancer's height). Session 46, 1 -> 0: 504 synthetic clips failing
    # 27 -> 25, mean IDF1 0.9836 -> 0.9839, 20 up, 13 down (2402 swing 0.887 -> 0.996, 309 ballet 0.829 -> 0.971,
    # 2412 hip-hop loses its switch; 2308 swing 0.954 -> 0.883, three more swing clips 1.000 -> 0.93-0.95). 3 in
    # session 45: 360 clips 4 up, 3 down; 144 clips 2 up, 2 down (docs/benchmarks.md, sessions 45 and 46)
    late_ratio_frames: int = 12
    width_margin: bool = True  # the box's width follows its detections plus a margin (the start box's width
    # beyond the detection on it in its start frame, in detection heights), not times a ratio: spread arms widen a
    # detection by a limb, and a ratio of 1.4 learned from a narrow standing detection made them 1.4 x as wide. Only
    # from a detection in the start frame (a ratio learned later, from a moving dancer, makes a poor margin), and not
    # for a detection cut by the frame's edge. hdvr synth, session 44's generator: 360 clips 0.9836 -> 0.9852,
    # failing 19 -> 17, none broken (44 up, 9 down); 144 clips 0.9780 -> 0.9786, 11 failing both (14 up, 5 down);
    # docs/benchmarks.md, session 45
    start_ratio_alone: bool = True  # the initial box's ratio to the detector's is learned at the start only for a
    # dancer whose body core overlaps no other dancer's then (in a stack the detection on it may be the other's);
    # otherwise from its first detection while clear
    retrack_scale: float = 1.25  # box height this factor off the tracker's template: the tracker restarts
    max_missed_detections: int = 3  # detector frames in a row without a person on a clear dancer's box = lost
    long_lost_detections: int = 8  # detector frames in a row without a person on a clear dancer's box = long lost
    lost_max_foreground: float = 0.1  # with > 0, a clear dancer without a person on its box for
    # ``max_missed_detections`` detector frames that no detection could take back (:meth:`_jump_to_detection`), and
    # whose box holds fewer than this fraction of foreground pixels (:meth:`_shows_someone`), is lost on the
    # background: it is occluded there (:meth:`_occlude`) and looked for like a dancer hidden behind others
    recovery_frames: int = 30  # frames after such a recovery in which the box restarts on any detection on it
    recovery_height_change: float = 2.5  # ... whose height is within this factor of the box's
    stuck_persist: int = 3  # with N > 0, a clear dancer whose box holds one person alone (on the box: matched, so never
    # counted missed) that lies too far off to adapt it (IoU <= ``adapt_min_iou``) and reaches out of the box's
    # columns (containment at most ``adapt_min_containment``: a person inside a wide box is the dancer with its arms
    # left out) on N of its clear detector frames in a row (frames it overlaps others neither count nor break the
    # run; a detector frame on which it is clear without such a person does) restarts on that person
    # (:meth:`MultiDancerTracker._restart_on_stuck`): a box left behind by a floor move or a turn keeps half the
    # person and is never found lost (hdvr synth seed 2622 hip-hop: a dancer got up from the floor, her box stayed low
    # and 50 px aside for 45 frames with her detection on it each detector frame). Without the containment test it
    # also fired on detections inside wide boxes (seeds 2109 swing 0.994 -> 0.939, 2511 ballet 1.000 -> 0.975)
    lost_search_heights: float = 3.0  # a lost dancer is searched among detections this many box heights away
    adapt_in_groups: bool = False  # boxes of overlapping dancers adapt to detections assigned unambiguously
    # (:meth:`MultiDancerTracker._adapt_in_group`). Off: on the synthetic clips of hdvr.synth it raised mean IDF1
    # on seed 7 (0.911 -> 0.926) but lowered it on held-out seeds 11 (0.939 -> 0.917) and 23 (0.989 -> 0.970)
    group_min_score: float = 0.55  # a detection adapts an overlapping dancer's box only if it fits it this well
    # (mean of the IoU and the IoU of the vertical extents: spread arms change the width, not the height)
    group_margin: float = 0.15  # ... and fits every other dancer by this much less
    group_adaptation: float = 0.5  # per such detection, weight of the detected box in the dancer's box
    group_scale: bool = True  # the boxes of a group of overlapping dancers scale together as their detections
    # grow or shrink alike (a couple walking towards or away from the camera: :meth:`MultiDancerTracker._scale_groups`).
    # Cached synthetic clips: seeds 131-139 mean IDF1 0.961 -> 0.978 (seed 137 tango 0.688 -> 1.000, its switch
    # gone); seeds 7-127 0.9735 -> 0.9728 (seed 101 flamenco 0.900 -> 0.897); groups of 6-8 0.9205 -> 0.9212
    group_scale_agreement: float = 1.15  # ... when the dancers' scale changes are within this factor of each other
    group_scale_adaptation: float = 0.3  # ... by this fraction of the (log) change per detector frame
    group_scale_front: bool = True  # ... and a lone dancer whose overlapping dancers all wait hidden behind it since
    # their start (``hidden_behind``) scales the same way with its own detection (a couple walking towards the camera,
    # one hidden behind the other all along)
    group_scale_shared: bool = True  # ... or, when the detector draws one person box over the whole group (a couple
    # in hold), as that box grows or shrinks (:meth:`MultiDancerTracker._shared_detection`). Cached synthetic clips:
    # seeds 201-212 and 151-199 mean IDF1 0.9740 -> 0.9753 (seed 201 tango 0.867 -> 1.000), switches unchanged;
    # seeds 7-139 0.9854 -> 0.9855; groups of 6-8 0.9461 -> 0.9456
    group_shared_inside: float = 0.6  # ... which holds at least this fraction of each dancer's body core
    group_reshape_after: int = 2  # a dancer in a group, in front of every dancer it overlaps, whose box has a floor
    # shape while its unambiguous detection has shown an upright person on this many detector frames in a row takes
    # that detection's aspect at its box's height (:meth:`MultiDancerTracker._reshape_in_group`); 0: off. Cached
    # synthetic clips: 1 of 936 changes (seed 1512 hip-hop 0.642 -> 0.810; docs/tracking.md, session 27)
    group_reshape_min_aspect: float = 1.0  # ... "floor shape": the box at least this wide for its height
    group_reshape_aspect: float = 1.3  # ... "upright": the detection's width / height this factor below the box's
    pose_extent: bool = True  # the reported box of a dancer extends to the box of the pose Algorithm 2* chose for
    # it where that reaches further (spread arms), when the choice is clear (:meth:`MultiDancerTracker.extend_to_poses`)
    pose_margin: float = 0.2  # ... the pose's selection score better by this for the dancer than for any other
    pose_max_height: float = 1.2  # ... the pose's box at most this much taller than the dancer's box
    pose_stack_overlap: float = 0.7  # ... and no dancer without a pose of its own stands straight behind or in front
    # (body cores overlapping more than this, intersection / smaller): a limb beside them may be either's
    pose_adaptation: float = 0.5  # ... by this fraction of the way per detector frame
    waiting_not_rival: bool = True  # a dancer still waiting hidden behind another (``hidden_behind``) is no rival
    # in the selection margin of that dancer's pose (:meth:`MultiDancerTracker.not_pose_rivals`): its memory is
    # that dancer's colours (cached synthetic clips: see docs/tracking.md, session 18)
    waiting_yields_pose: bool = True  # a dancer still waiting hidden behind another cannot take a pose that fits
    # that dancer's box about as well as its own (:meth:`MultiDancerTracker.pose_yields`,
    # ``SelectionConfig.yield_iou_margin``): its memory is the front dancer's colours, so Algorithm 2*'s histogram
    # cannot tell them apart (session 40, docs/tracking.md)
    correction_waits_behind: bool = True  # a dancer a user corrects onto a box straight behind another dancer
    # (:meth:`MultiDancerTracker.correct`) waits hidden behind it from there, as a dancer that starts so does
    # (``hidden_start_overlap``): its box follows that dancer's until it comes out
    group_shrink: float = 0.33  # in a group (body core overlapping another dancer's) the growth goes back at this
    # fraction of that rate: the detector's and the foreground's evidence of a limb flickers there from frame to
    # frame (a skeleton that reaches out in one frame and not in the next), and one frame without it says little.
    # 1 shrinks as fast as it grows. Cached synthetic clips (against 1): seeds 201-212 and 151-199 mean IDF1 0.9753
    # -> 0.9769, below 0.9 8 -> 7, switches 6 -> 2; seeds 7-139 0.9855 -> 0.9865, 2 -> 1 below, 4 -> 2 switches;
    # groups of 6-8 0.9456 -> 0.9468, 7 -> 5 switches (0.5 and 0.2: 0.9764 and 0.9764 on the first set)
    pixel_extent: bool = True  # ... and sideways as far as foreground pixels (colours rare in the background
    # around the dancers) run on from the box at arm height (:meth:`MultiDancerTracker._pixel_reach`)
    pixel_band: tuple[float, float] = (0.05, 0.6)  # rows searched for arms, x the box height from its top
    pixel_max_reach: float = 0.6  # at most this x the box height beyond each side
    pixel_follow_reach: float = 1.2  # x the box height: a run still going at ``pixel_max_reach`` is followed this
    # far to see where it ends (on the body of a dancer beside: nothing, as for a shorter run)
    pixel_gap: int = 3  # px: the run of foreground columns may break for this many columns
    pixel_min_thickness: float = 0.025  # x the box height: foreground pixels a column needs (an arm; the
    # blended pixels along the edge of a floor are thinner)
    pixel_front: float = 0.05  # x the box height: a dancer whose box bottom is this much lower stands in front
    pixel_opening: int = 3  # px: foreground thinner than this is removed (morphological opening)
    pixel_margin: tuple[float, float] = (0.3, 0.3)  # the background is sampled outside the dancers' boxes widened
    # by this x their height sideways and up and down
    pixel_ring_common: float | None = 0.02  # ... and a colour this common (fraction of the pixels) in the ring
    # between the boxes and the widened boxes, and in the ring on both sides of some box, is background too: the
    # floor where the widened boxes cover all of it (:func:`hdvr.tracking.appearance.foreground_mask`'s
    # ``ring_common``; an arm out into the ring is a small part of it, a person no one follows standing beside a
    # dancer shows on one side only). None: off. Seed 2984 hip-hop: 37 % of a frame foreground without it, 19 % with
    # it, 0.883 -> 0.997. Over 1,397 hdvr synth clips 49 -> 48 failing, 4 clips up, 1 down by 0.002 (session 79; in
    # session 78 the same without the both-sides test, left off for the person beside). At margin 0.45 (a spread
    # arm's reach): 49 -> 50 (docs/benchmarks.md "Session 78")
    pixel_arm_margin: float | None = 0.45  # ... and at arm height (``pixel_band``) this x their height sideways
    # (shoulder to fingertip is about 0.45 of the stature): a spread arm's hand and forearm reach past
    # ``pixel_margin``, their colour (skin) was background in the sample, and the arm seemed to end at the sleeve
    # (:func:`hdvr.tracking.appearance.foreground_mask`'s ``arm_margin``; hdvr synth seed 3136 tango). None: off
    pixel_max_fill: float = 0.4  # a column more than this full of foreground (of the band's rows) is no arm: a
    # body beside the box, or background whose colour the sample around the dancers lacks; the run stops there
    pixel_full_in_box: bool = True  # ... and where that column lies in the box of a dancer standing level or in
    # front, that side gets nothing: the run crossed that dancer's arm to its body (seed 502 flamenco)
    pixel_unexplained_limb: bool = True  # a run that reaches the body core of a dancer level or in front is this
    # dancer's limb as far as that body when that dancer's clearly chosen pose (``pose_margin``) draws no limb on the
    # run's columns and rows (else that side gets nothing: the limb may be that dancer's; seed 310 flamenco)
    pixel_unexplained_own: bool = True  # ... and, where this dancer's own pose is chosen clearly, that pose draws a
    # limb there: a limb that neither skeleton draws (the detector leaves spread arms out) is either's (seed 405 tango)
    pixel_front_limb: bool = True  # a run from a tracked dancer's side is the arm of a dancer overlapping its box,
    # level or in front, crossing it when that dancer's clearly chosen pose draws a limb there or its reported box
    # reaches as far (and this dancer's own clear pose, if any, draws none): that side gets nothing
    # (:meth:`MultiDancerTracker._not_front_limbs`; seed 2865 hip-hop)
    front_limb_root: float | None = 0.05  # ... and so is a run whose first columns beside the box hold foreground
    # within this x the box height of that dancer's shoulder row (``shoulder_row`` down its box) and hardly any
    # within it of this dancer's, the two rows at least twice this apart: an arm leaves the body at its shoulder,
    # and the detector drew the front dancer's spread arm in (seed 2966 hip-hop, with ``pixel_arm_margin``). Not
    # applied to the GrabCut extent (measured: 2784 ballet mended, 2739 hip-hop broken). None: off
    shoulder_row: float = 0.2  # x a box's height from its top: about where a standing dancer's shoulders are
    stacked_extent: bool = True  # a dancer hidden straight behind another reaches as far as foreground runs on
    # from the front dancer's box beyond that dancer's own skeleton (:meth:`MultiDancerTracker._stacked_reach`)
    stacked_tolerance: float = 0.1  # x the front dancer's height: a shorter run is no limb
    stacked_max_reach: float = 0.45  # x the hidden dancer's box height: the most its arm reaches beyond its box
    # (shoulder to fingertip is about 0.45 of the stature); a longer limb is not its own
    stacked_arm_out: float = 0.05  # x the front dancer's height: its arm reaching or pointing further out to a side
    # makes a limb on that side possibly its own
    front_extent: bool = True  # ... and the dancer in front of such a pair as far as foreground runs on from its
    # box on a side its own skeleton reaches or points to (:meth:`MultiDancerTracker._front_reach`)
    front_own_band: bool = True  # ... that run scanned at the front dancer's own arm height (``pixel_band`` of its
    # box), not at the hidden dancer's (sessions 11-17; a shorter dancer further back has its arms lower in the
    # image, and the front dancer's arms then fell outside the rows scanned)
    grabcut_extent: bool = True  # ... and a dancer in a group as far as its own GrabCut segment (OpenCV's colour
    # segmentation, seeded from the skeletons) runs on from its box (:meth:`MultiDancerTracker._grabcut_reach`):
    # the foreground alone cannot tell whose limb crosses another dancer's body
    grabcut_widen: float = 0.8  # x the box height: the segmented crop reaches this far beyond each side of the box
    grabcut_scale: float = 0.5  # the crop is segmented at this scale (1.0: about 3x the time)
    grabcut_iterations: int = 3  # GrabCut iterations (colour models re-fitted and cut again)
    grabcut_seed_thickness: float = 0.03  # x the box height: skeletons (or body strips) drawn as seeds
    grabcut_rows: tuple[float, float] = (0.0, 1.0)  # rows of the segment scanned, x the box height from its top
    hold_hidden_extent: bool = True  # the reported box of a dancer hidden behind another keeps its extent (its
    # limbs cannot be seen to come in: :meth:`MultiDancerTracker._hidden_behind`). Cached synthetic clips: seeds
    # 7-127 mean IDF1 0.970 -> 0.974 (4 -> 3 below 0.9), groups of 6-8 0.915 -> 0.921 (14 -> 11 switches); 131-139 same
    hold_within_cover: bool = True  # ... but only as far as the reported boxes of the dancers overlapping it reach
    # beyond its box: a limb beyond them would be seen (:meth:`ReportedExtent._covered_reach`). Without it, the arm of
    # the dancer in front that the front dancer's skeleton left out, once taken for the hidden dancer's, stayed on its
    # box for the rest of the clip (hdvr synth seed 2505 swing couple: 76 px held from frame 30 to the end, IDF1 0.733
    # -> 0.929). 504 hdvr synth clips: failing 20 -> 18, 10 clips up, 1 down (docs/benchmarks.md "session 49")
    hidden_min_aspect: float = 0.5  # the written box of a hidden dancer (occluded, or tracked with a dancer in
    # front whose body core overlaps its own by more than ``hidden_widen_overlap``) is at least this x its height
    # wide, but no wider than the dancers overlapping it (:meth:`MultiDancerTracker._widen_hidden`): its limbs are
    # unseen, and the tracked box is the arms-down body (amodal ground truth of hdvr synth: median aspect 0.46;
    # occluded dancers' boxes were 0.32). 0 switches it off. Cached synthetic clips: seeds 201-212 and 151-199 mean
    # IDF1 0.9621 -> 0.9740, below 0.9 13 -> 9, switches 14 -> 6; seeds 7-139 0.9792 -> 0.9854, 4 -> 2 below, 3 -> 4
    # switches; groups of 6-8 0.9278 -> 0.9461, 10 -> 7 switches (0.45 and 0.55: 0.9733 and 0.9731, 9 and 12
    # switches on the first set)
    hidden_widen_overlap: float = 0.3  # intersection / smaller body core (0.7, ``pose_stack_overlap``: 0.9708)
    out_fraction: float = 0.35  # a box with less than this fraction of its area in the frame is out of it
    edge_reentry: bool = True  # a dancer who left on the left or right is re-identified on a strip at that edge
    # whose histogram matches its memory (:meth:`_reenter_at_edge`); works without a detector
    edge_strip: float = 0.5  # width of that strip, x the dancer's box width
    exit_missed_detections: int = 2  # a clear dancer whose last detection was cut by the left or right edge is
    # out after this many detector frames in a row without a person on its box (:meth:`_walked_out`) ...
    exit_max_foreground: float = 0.2  # ... when at most this fraction of its box's columns hold foreground
    exit_edge_px: float = 2.0  # px: a detection this close to the frame's side is cut by it
    learn_inside: float = 0.9  # the tracker learns only while at least this fraction of its box is in the frame

    def __post_init__(self) -> None:
        if self.keep_hidden_sides not in HIDDEN_SIDES_MODES:
            raise ValueError(f"keep_hidden_sides must be one of {', '.join(HIDDEN_SIDES_MODES)}, "
                             f"got {self.keep_hidden_sides!r}")


def _angle_between(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    if na < 1e-9 or nb < 1e-9:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(np.dot(a, b) / (na * nb), -1.0, 1.0))))


def _chain_length(before, box) -> int:
    """Detector frames in a row on which a person lay at ``box`` (x, y, w, h px), this one included: 1 + the count
    of the chain of the detector frame before (``before``: (box, count) pairs) on which it lies (IoU >= 0.5)."""
    return 1 + max([n for b, n in before if box_iou(b, box) >= 0.5], default=0)


def _height_within(box, reference, factor: float) -> bool:
    """Whether (x, y, w, h px) ``box`` is at most ``factor`` x taller or shorter than ``reference``."""
    return 1 / factor <= box[3] / reference[3] <= factor


def _height_misfit(box, reference) -> float:
    """|log(height ratio)| of two (x, y, w, h px) boxes: 0 for the same height, as much for twice as for half."""
    return abs(float(np.log(box[3] / reference[3])))


def likely_windows(weights: np.ndarray, window, min_mean: float, count: int = 3,
                   step: int = 4) -> list[np.ndarray]:
    """Centres (x, y) px of up to ``count`` windows of ``window`` = (width, height) px whose mean of ``weights``
    (an image, e.g. a back-projected colour histogram) is highest and at least ``min_mean``, best first, no two
    closer than a window's size. Computed on the image shrunk ``step`` times (a box filter: one pass whatever the
    window); a window is not scored beyond the image's border (counted as 0 there)."""
    height, width = weights.shape
    small = cv2.resize(weights.astype(np.float32), (max(1, width // step), max(1, height // step)),
                       interpolation=cv2.INTER_AREA)
    kw, kh = max(1, int(round(window[0] / step))), max(1, int(round(window[1] / step)))
    mean = cv2.boxFilter(small, -1, (kw, kh), normalize=True, borderType=cv2.BORDER_CONSTANT)
    centres = []
    for _ in range(count):
        i, j = np.unravel_index(int(np.argmax(mean)), mean.shape)
        if mean[i, j] < min_mean:
            break
        centres.append(np.array([(j + 0.5) * width / small.shape[1], (i + 0.5) * height / small.shape[0]]))
        mean[max(0, i - kh):i + kh + 1, max(0, j - kw):j + kw + 1] = -1.0
    return centres


def _offset_behind(box, front) -> tuple[float, float]:
    """Where (x, y, w, h) px ``box`` stands relative to the box ``front`` of the dancer it waits behind: the offsets
    of its centre x and its bottom from ``front``'s, in ``box`` heights (positive: right, down)."""
    x, y, w, h = box
    fx, fy, fw, fh = front
    return (x + w / 2 - fx - fw / 2) / h, (y + h - fy - fh) / h


def _box_behind(box, front, offset) -> tuple[float, float, float, float]:
    """``box`` (x, y, w, h px; its size kept) placed at ``offset`` (:func:`_offset_behind`) from the box ``front``."""
    _, _, w, h = box
    fx, fy, fw, fh = front
    cx, bottom = fx + fw / 2 + offset[0] * h, fy + fh + offset[1] * h
    return (cx - w / 2, bottom - h, w, h)


def _shift(box, d) -> tuple[float, float, float, float]:
    return (box[0] + float(d[0]), box[1] + float(d[1]), box[2], box[3])


class MultiDancerTracker(ReportedExtent):
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
                o.wait_offset = _offset_behind(o.box, everyone[o.hidden_behind].box)
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
                d.wait_offset = _offset_behind(d.box, front[0].box)
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
            return (iou >= c.start_seen_iou and _height_within(det, d.box, c.max_height_change)
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
        return _shift(d.stored_box, self._travel(d, frame_index))

    def _predict_overlap_end(self, d: DancerTrack, others: list[DancerTrack], now: int) -> int:
        """First frame after ``now`` at which ``d``'s predicted box overlaps none of ``others``' predicted boxes
        (each moving on with its stored velocity)."""
        c = self.config
        for t in range(now + 1, now + c.max_occlusion_frames):
            mine = self._predicted_box(d, t)
            if all(self._bodies_overlap(mine, self._predicted_box(o, t) if o.status == OCCLUDED
                               else _shift(o.box, o.stored_velocity * (t - now))) <= c.overlap_threshold
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
                inside = (_angle_between(off, travel) <= 2 * c.cone_half_angle_deg
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
                        d.stored_box = _box_behind(d.box, front.box, d.wait_offset)
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
        d.stored_box = _box_behind(d.box, front.box, d.wait_offset)
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
                           if _height_within(box, d.stored_box, c.max_height_change)])
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
        return _height_within(detection, d.box, change) and detection[2] <= c.max_person_width * d.box[3]

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
            if det is not None and _height_within(det, d.box, c.max_height_change):
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
                _height_within(det, d.box, c.max_height_change)
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
                if moved >= c.min_motion_px and _angle_between(motion, d.stored_velocity) > c.failure_angle_deg:
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
            and _height_within(d.box, o.box, c.same_person_height) \
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
            if _angle_between(motion, theirs) <= c.follower_angle_deg and \
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
        return _height_within(self._feet_hidden(d, detection), d.box, factor)

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
        if not _height_within(det, d.box, c.max_height_change) \
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
            count = _chain_length(d.beside_before, det)
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
            gain = _height_misfit(held, front.box) - _height_misfit(det, front.box) + \
                _height_misfit(det, d.box) - _height_misfit(held, d.box)
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
        mine = _height_misfit(det, d.box)
        centre = np.asarray(box_centre(det))
        for e in waiting:
            if e is d or e.hidden_behind is None or _height_misfit(det, e.box) + c.emerge_height_yield >= mine \
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
                     or (_height_within(box, d.box, c.reid_unheld_height)
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
        which it lies (:func:`_chain_length`; ``strays`` keeps each one's count of detector frames in a row).
        Returns those seen on ``orphan_persist`` detector frames in a row, this one included."""
        c = self.config
        dets = [tuple(float(v) for v in det) for det in detections]
        claimed = set(self._claims(dets).values())
        tracked = [o for o in self.dancers if o.status == TRACKED]
        unclaimed = [det for k, det in enumerate(dets) if k not in claimed]
        stray = [det for det in unclaimed if all(self._bodies_overlap(det, o.box) <= c.overlap_threshold
                                                 for o in tracked)]
        self.unclaimed = [(det, _chain_length(self.unclaimed, det)) for det in unclaimed]
        self.strays = [(det, _chain_length(self.strays, det)) for det in stray]
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
                o.wait_offset = _offset_behind(o.box, front.box)

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
