"""Parameters of Algorithm 1* (:class:`MultiTrackerConfig`), the multi-dancer tracker of
:mod:`hdvr.tracking.multi`, with the reason and the measurement behind each default in the comment beside it.

Distances are pixels (px) unless a comment gives them in box heights ("x the box height"); speeds px/frame; frame
counts are video frames, "detector frames" those on which the person detector ran.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdvr.tracking.ldes import LDESConfig
from hdvr.tracking.state import BODY_CORE_ASPECT

HIDDEN_SIDES_MODES = ("off", "tracked", "written")  # ``MultiTrackerConfig.keep_hidden_sides``
#: what of a box in front of a group follows its detection (``MultiTrackerConfig.group_front_parts``)
GROUP_FRONT_PARTS = ("box", "centre", "vertical", "height")


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
    # dancer again (re-identification, relocation, re-entry, jumps: there they cost switches, see docs/tracking.md).
    # The finds of the crop about a group (``step``'s ``zoomed_detections``, session 90) are used as weak ones, but
    # let a dancer that starts hidden come out only as ``zoomed_emerge_height`` allows. False: neither kind is used
    zoomed_emerge_height: float = 0.9  # a find of the crop about a group lets a dancer waiting hidden come out only
    # if it lies on her box (intersection over the smaller box above 0.5) and is at least this fraction of its
    # height: a whole dancer, not a sliver of one peeking out from behind the dancer in front, which the detector,
    # zoomed in, also draws as a person (hdvr synth seed 3123 flamenco: a find 19 x 94 px on her 141 px tall box, she
    # came out on it and kept a box that narrow, IDF1 1.000 -> 0.769). Session 90, on session 88's 41 failing clips
    # and 600 random ones: no such find (infinity) 43 -> 38 failing, 0.9 -> 36, none broken (docs/benchmarks.md)
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
    adapt_height_inside: bool = False  # a clear dancer whose one detection lies inside its box (containment
    # above ``adapt_min_containment``) but fits it too loosely to adapt it (IoU at most ``adapt_min_iou``, columns
    # beside it not empty: a limb out there) adapts its box's height to it, keeping its bottom and width, when the
    # detection is hers alone at the height her box implies (:meth:`MultiDancerTracker._alone_at_implied_height`:
    # the box height over the learned ``size_ratio``). Without it a box grown too tall stays so: its height is
    # compared with the detection's raw, more than ``max_height_change`` apart (hdvr synth seed 2723 tango: one
    # detection 13 % taller grew the box to 367 px, 1.66 x the detections after it). Session 91 (docs/benchmarks.md
    # "Session 91"), with OpenCV 5.0.0.93, on the 36 clips failing in session 90 and 198 random 3-4 dancer clips: 4
    # changed, none mended or broken, 2723 tango 0.679 -> 0.733 but with 2 switches where it had none (with OpenCV
    # 5.1 it had taken 2 switches out of that clip). Off: it adds switches on the one failing clip it changes
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
    group_front_adapts: float | None = None  # with ``adapt_in_groups`` off, the box of a dancer standing in front
    # of every dancer it overlaps (box bottom ``group_front_margin`` x their height lower) follows its unambiguous
    # detection with this weight (:meth:`MultiDancerTracker._adapt_front_in_group`): all of it is seen. None: off.
    # Session 88, for a couple in hold whose front dancer's tracker drifts up towards the partner behind (3070 tango
    # 0.654 -> 1.000, 3100 tango 0.637 -> 0.683): at 0.5, all 1,743 clips of sessions 80-83 tracked again, 41 -> 48
    # failing, 13 mended and 20 broken, runs of 749 changed. Broken: a front dancer taking a detection that lies
    # over the group behind it (3031 ballet 1.000 -> 0.700), a box too low counted as in front (2964 hip-hop), a
    # box narrowed to a detection without the spread arms (2791 tango 1.000 -> 0.754). Not kept
    group_front_margin: float = 0.05  # 0.15: of the 33 clips 0.05 mended or broke, 10 mended and 14 broken
    group_front_parts: str = "box"  # what of its box follows: "box" (size and centre), "centre" (the centre),
    # "vertical" (the centre's height in the image and the box height), "height" (the height, its bottom kept, as in
    # front of dancers waiting behind it). Session 88, on the 114 clips of sets N and M whose runs "box" changed:
    # 6 -> 8 failing ("centre"), 6 -> 9 ("vertical"); on the 33 clips "box" mended or broke, "height" mended 2 (3070
    # tango, 3105 ballet) and broke 7 (2791 tango 1.000 -> 0.792, 3095 tango 0.912 -> 0.817)
    group_front_after: int = 0  # ... only from this many frames after the box was last placed for sure (clear of
    # the others, started or re-identified: ``stored_frame``); its tracker, learning nothing in the group, drifts
    # with time. Session 88, on the 33 clips: 30 mended 7 and broke 10 (3070 tango no longer mended), 60 mended none
    group_front_aspect: float | None = None  # ... not to a detection narrower for its height than this x the box
    # (it may leave out spread arms the box holds); None: whatever its shape. Session 88, on the 33 clips: 0.9
    # mended 8 and broke 15 (2791 tango no longer broken, 3070 tango no longer mended)
    group_front_max_iou: float | None = None  # ... only to a detection overlapping the box less than this (IoU): a
    # box off its dancer, not one a little off its detection; None: any. Session 88, on the 33 clips: 0.7 mended 6
    # (3070 tango among them) and broke 12
    group_front_match: float | None = None  # ... only while its detection matches its stored colours this much
    # better than its box does (its tracker drifted off it); None: whatever the colours. Session 88, on the 33
    # clips: 0.0 mended 2 and broke 8, 0.05 mended 1 (3105 ballet) and broke 1 (3031 ballet)
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
    front_long_run: float | None = 0.4  # x the hidden dancer's box height: a run beside a stacked pair reaching
    # further than this beyond the hidden dancer's box is not its arm but the front dancer's, drawn without it by the
    # detector (seed 3063 swing): the front dancer's box takes it on a side its skeleton does not reach too, and the
    # hidden dancer's does not (:meth:`MultiDancerTracker._too_long_for`; session 87: 0.45, 0.4, 0.35 mend 1, 2, 2 of
    # the 44 failing clips, none worse; 0.4, about an arm's length less the shoulder's inset, on all 1,743: see
    # docs/benchmarks.md "Session 87"); None: off
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
        if self.group_front_parts not in GROUP_FRONT_PARTS:
            raise ValueError(f"group_front_parts must be one of {', '.join(GROUP_FRONT_PARTS)}, "
                             f"got {self.group_front_parts!r}")
