"""Hindsight once a whole video is tracked: occluded stretches filled (or held where the dancer was last seen),
boxes widened to their keypoints (and lowered where they reach far above a full pose), boxes smoothed over time, and
the box of a dancer waiting hidden behind another kept partly at its start offset from that dancer, its feet near
where the front dancer's say they are and its size following its feet.

Algorithm 1* runs online, but ``hdvr track`` writes its outputs only at the end, so eleven offline steps can use the
frames after each one, as offline multi-object trackers do (ByteTrack's and StrongSORT's linear interpolation of the
missing frames of a track, StrongSORT's smoothing of the boxes):

:func:`fill_occluded`: while a dancer is hidden behind others (status ``occluded``) its box is a prediction from its
last clear box and velocity. Where the dancer was seen again is known by the end, so each such stretch is filled
by linear interpolation (box centre and size) between its box on the last frame it was seen before and on the
first frame it was seen again. A dancer hidden behind a partner moves on while unseen, where its predicted box
either stands still or runs on with a stale velocity (hdvr synth seed 1210 swing couple: IDF1 0.762 -> 0.887).
A re-identification is trusted as the end of a stretch only when the dancer then stays seen for
``min_seen_after`` frames in a row (or to the end of the video): a dancer taken for one frame on the wrong person
and lost again would drag the whole filled stretch there (hdvr synth seed 505 hip-hop trio, frame 107). A
re-identification on the wrong dancer that lasts drags it all the same: hindsight repeats the tracker's identity
decisions, it does not make them. Not filled: a stretch with no seen frame after it (hidden to the end, or out of
the frame), one after an exit from the frame, and a dancer that waits hidden behind another since its start
(status ``hidden``), which :func:`fill_hidden_until_seen` handles last.

:func:`hold_last_seen`: a stretch that :func:`fill_occluded` leaves unfilled because nothing trusted was seen after
it (the dancer stays hidden to the end of the video, or is lost again at once) keeps the box of the frame the dancer
was last seen, instead of the online prediction, which starts from its last box clear of the others (frames
earlier, while it still moved freely) and runs on with the velocity it had then: a dancer that stays hidden behind
others has mostly stopped there (it would show again had it moved on). 936 hdvr synth clips: clips below IDF1 0.9
or with a switch 51 -> 45, mean 0.9807 -> 0.9814; hdvr synth seed 712 hip-hop quartet 0.840 -> 0.983
(docs/benchmarks.md "session 33"). A stretch in which the online tracker stopped the dancer's predicted box behind
the dancers in front (``stopped``: it ran on only while hidden, then stayed where the dancer was hidden best;
``MultiTrackerConfig.hold_uncovered_prediction``) keeps its online boxes (session 57). So does a stretch in some
frame of which the place the dancer was last seen lies open to view (``min_cover``, 0.5: less than half its body
core behind the body cores of the dancers followed): the dancer would have been seen there, so it walked on, and the
online prediction says where (session 59: the procedural crossings of ``scripts/bench_track.py --sections
identity``, figures that walk on behind another and are never found again, failing 17 -> 5 of 72 and identity
switches 11 -> 2, tracker alone and with the detector; hdvr synth sets D, F, G, H unchanged but for one clip, 1.000
-> 0.992).

:func:`enclose_keypoints`: each box of a dancer seen (``tracked``) is widened, left and right, to enclose the
keypoints written for it (those of the pose Algorithm 2* chose, interpolated between detector frames), plus
``reach`` x the box height for the body beyond its outermost joints (the hand beyond the wrist, the foot beyond the
ankle, the limb's own thickness; a hand alone is about 0.1 of a person's height). While a dancer overlaps others its
tracked box keeps the size it had when clear, and the detector's person box often leaves out a spread arm or a
raised leg that its keypoints show, so the written box would miss part of the written skeleton. Only a pose that
fits the box counts: its torso (neck, shoulders, hips) lies between the box's sides and all its keypoints within the
box's height, give or take ``height_margin`` (Algorithm 2* sometimes gives a dancer behind another the pose of the
one in front: hdvr synth seed 809 hip-hop quartet, a small dancer's box would have doubled its width to the pose of
the tall dancer in front: IDF1 0.944 -> 0.823 without the test). Only keypoints of confidence ``min_confidence`` or
more count, and only when ``min_keypoints`` of them do. Boxes only grow, and only sideways: a dancer's height is
what the tracker and the detector follow best, and widening it to the keypoints too added identity switches (936
hdvr synth clips: clips below IDF1 0.9 or with a switch 63 -> 54, mean 0.9784 -> 0.9801; docs/benchmarks.md "session
32").

:func:`trim_above_pose`: a box of a dancer seen whose pose shows nearly all of COCO-17's joints, all inside the box,
is lowered where its top reaches more than ``reach`` x its height above the pose's highest keypoint (the head's
top above the face keypoints, or the fingers above a raised wrist), keeping its bottom. A box's size follows its
detections times the ratio of the start box to the first detection on the dancer; when that detection left the
legs out, the box stays that much too tall all along (hdvr synth seed 309 hip-hop trio: a box 1.3 x the dancer's
height, lowered on 101 frames by a median 0.09 of it, to 1.18 x; frames missed 21 -> 4, IDF1 0.936 -> 0.981; seed 302
flamenco, a box 1.2 x the dancer's height: its 2 identity switches go). 936 hdvr synth clips: mean IDF1 0.9801 ->
0.9805, switches 19 -> 17, HOTA 0.7791 -> 0.7810 (52 clips up, 6 down; docs/benchmarks.md "session 33").

:func:`smooth_boxes`: the box centre and size of each run of frames with a box (``tracked`` or ``occluded``) are
averaged over a centred window of ``window`` frames: the tracker and the detector each move a box by a few pixels
from frame to frame where the dancer moves smoothly (936 hdvr synth clips, after the filling: clips below IDF1 0.9
or with a switch 67 -> 62 with 9 frames; docs/benchmarks.md "session 31").

:func:`keep_start_offset`: a dancer whose start box lies mostly behind another dancer's waits hidden there (status
``hidden``) until it comes out clear, and its tracker follows what its box shows, the dancer in front, so its box
drifts to his place. Dancers that stand one behind the other mostly keep their places in the formation, so where
the box was against the front dancer's at the start says where the hidden dancer still is. Each such box is moved
sideways ``weight`` of the way from where the tracker has it (against the front dancer's box) to its start offset.
The two guesses are each right on some clips and wrong on others: holding the start offset outright loses to the
tracker's box (219 hdvr synth clips with a hidden start: 35 -> 47 failing, IDF1 below 0.9 or a switch), a quarter of
the way towards it wins (35 -> 27; weights 0.1-0.35 gave 27-30; 83 fresh clips with a hidden start 16 -> 14;
moving the bottom edge as well: 29 and 12; docs/benchmarks.md "session 37").

:func:`keep_feet_behind_front`: the box of such a waiting dancer is also moved up or down, where needed, so that its
bottom lies within ``tolerance`` (0.2 since session 73) x its height of its start bottom moved by as much as the front
dancer's bottom moved since the start: dancers standing one behind the other stay so in depth, and the waiting dancer's
own tracker, which follows the dancer in front, can slide off the stack (hdvr synth seed 2112 hip-hop: 160 px down) or
stay behind while the pair comes nearer the camera (seed 310 tango: 54 px too high, IDF1 0.858 -> 0.950). Only a clamp:
boxes within the tolerance keep their place (moving every box by the front dancer's bottom, wholly or in part, lost more
clips than it mended; 504 hdvr synth clips with the clamp: 5 up, none down; docs/benchmarks.md "session 49").

:func:`scale_with_depth`: that moves her feet down the image as a couple comes nearer the camera (or up as it goes
away), but her tracker keeps the size she had at the start, and a dancer nearer the camera looks larger in proportion
to her feet's distance below the horizon (:mod:`hdvr.tracking.ground`). So where the boxes of the dancers seen show a
horizon (some dancer's feet range over 0.1 of its height up and down the image), each waiting dancer's box is given
her start height times the ratio of her feet's distances below the horizon now and at her start, its width scaled
alike, its bottom and centre kept; unless her start box against that horizon makes her more than 1.5 times taller or
shorter than the dancers seen (the horizon was fitted to a jittering box bottom). Session 74: 497 hdvr synth clips
failing 21 -> 20 (10 up, 1 down; seed 2809 tango 0.833 -> 0.988), 150 fresh clips 9 -> 6 (2960 tango 0.708 ->
0.988, 2963 swing 0.842 -> 1.000), two more sets of 150 held out 4 -> 4 and 2 -> 2 (6 up, 1 down; docs/benchmarks.md
"Session 74").

:func:`fill_hidden_until_seen`: once a dancer that waited hidden behind another since its start is seen (status
``tracked`` right after the wait), the boxes of its last ``walk_frames`` (30) frames, as the steps above left them,
are replaced by a straight line (centre and size) from the box before them to the box it was first seen at, as
:func:`fill_occluded` does for an occluded stretch: it walked from behind the dancer in front to there, while its
tracker followed the dancer in front. Session 49 drew the line over the whole wait, from the start box: 504 hdvr synth
clips 10 clips up, 4 down, failing 16 -> 15 (seed 2407 flamenco: the dancer behind walked out at frame 21 and was
first taken at frame 56; 0.892 -> 1.000). But a dancer hidden behind another mostly stays there (it would show had it
moved off) and walks out late: a dancer that stood still behind the one in front until frame 85 and was first seen
at frame 105 had its box 25 px aside by frame 50 on the whole-wait line (seed 2642 hip-hop, with ``front_narrows``).
Session 51, the line over the last 30 frames only: 240 fresh clips (seeds 2601-2640) failing 13 -> 12, 240 more
(2641-2680) 8 -> 6, the 504 tuned 15 -> 15; 10 clips up, 3 down (2651 swing 0.867 -> 0.975; 2407 flamenco 1.000 ->
0.908). (Measured on 936 clips in session 31, before the start offset and the feet: 0.9451 -> 0.9446 on the clips
with a hidden start.)

:func:`keep_start_place`: a wait never followed by a sighting (the dancer stays hidden to the end, or is next
occluded or out of the frame) has no such end to draw a line to; its boxes are moved sideways ``weight`` (0.5) of the
way towards where the dancer started, as :func:`hold_last_seen` holds an occluded dancer where it was last seen: a
dancer that stays hidden behind others all along has mostly stayed where it was (it would show had it moved out),
while its own tracker drifts with the dancers in front. Session 50: 504 hdvr synth clips failing 15 -> 15 (17 clips
up, 9 down; 202 ballet 0.842 -> 0.908), and 240 fresh clips (seeds 2601-2640, never tuned on) 18 -> 15 (10 up, 9
down; 2633 hip-hop 0.800 with 2 switches -> 0.994 with none); weights 0.35 and 0.65 gave 16 each there, the whole way
18 (and 17 on the 504); every wait, also those later seen, 17 on the 504. On a second fresh set scored once at the end
(seeds 2641-2680) it loses a little: 8 -> 8 failing, 1 clip up, 5 down (one of them a clip whose tracks were already
swapped); over all 984 clips failing 41 -> 38 (docs/benchmarks.md "session 50").

Then :func:`hdvr.tracking.amodal.refine_boxes` moves the box of each dancer seen to the whole (amodal) body that a
small network learned from hdvr synth clips predicts from the box, its keypoints and the other dancers' boxes
(``HindsightSettings.amodal_boxes``; session 52: on clips it was not trained on, 15 + 9 + 5 -> 13 + 6 + 5 failing
over three sets, HOTA up 0.04 on each; docs/tracking.md "Whole-body boxes").

Last, :func:`follow_partner_in_hold`: in a video of two dancers, a partner hidden behind the other dances in hold with
him (tango, swing, salsa): as the couple comes nearer she grows with him, and as he opens his arms so does she, while
her own tracker keeps her start size (or holds her last box seen) and the steps above move only her place. So on each
frame where his pose shows at least ``PARTNER_FRONT_JOINTS`` (13) of the 17 COCO-17 joints (his box, refined, is then
his whole body), her box is his box mapped as his box mapped onto hers at a frame where both were known: her height
and her offsets from his centre and bottom scaled with his height, her width his width times hers over his then. A
partner waiting hidden since her start is mapped from her start box, on the frames where her own pose shows fewer than
``MIN_KEYPOINTS`` keypoints (her own pose, when the detector finds it, is better evidence: 2887 swing), and where it
shows more, with its torso 0.1 of her height or more from his (``PARTNER_TORSO_APART``: her own pose, not his given to
her), her box is moved sideways onto her torso (3004 tango 0.883 -> 0.912; in every clip with a hidden start, groups
too, it lost more than it mended: 2720 ballet and 2771 hip-hop gained switches); a partner occluded after being seen,
while he is seen, from the frame she was last seen, blended linearly towards the mapping from the frame she is seen
again where there is one. In a group the dancer in front spreads his arms on his own (session 79: a waiting dancer's
width following the front dancer's in every clip, 49 -> 63 failing), so only couples. Session 81, on 1,141 hdvr synth
clips tracked by session 80's code: 35 -> 27 failing, 10 mended (3004 tango, 3049 tango 0.704 -> 0.975, 3064 tango
0.642 -> 0.938, 3007 tango 0.604 -> 1.000, 2938 swing 0.600 -> 1.000, 2733 tango 0.700 -> 1.000 occluded, 3085 tango
0.854 with a switch -> 0.917 occluded, 2721 swing, 3062 tango, 3024 tango) and 2 broken, where his box itself misses
his spread arms or his height (3063 swing 0.988 -> 0.979 with a switch, 2950 tango 0.958 -> 0.954 with a switch); 302
more clips without a couple hidden unchanged. For the waits 12 joints gave the same as 13, 14 one fewer mended and one
fewer broken, 15 (``MIN_FULL_POSE``: his face is mostly turned from the camera, 3 of its 5 points unseen) left most
frames as they were, 35 -> 36 (docs/benchmarks.md "Session 81"). Session 87: his height, by which she scales, is
the median over ``PARTNER_SCALE_WINDOW`` (8) frames on each side of the heights of his boxes around his whole pose:
his box loses his raised arms on some frames, and she shrank with it (the two clips broken above mended; 1,743 clips
44 -> 42 failing).

Boxes are (x, y, w, h) pixels, top-left origin; arrays are indexed (frame, dancer).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from hdvr.io.keypoints2d import BODY25_NAMES
from hdvr.tracking.amodal import refine_boxes
from hdvr.tracking.ground import HORIZON_MIN_SPREAD, depth_scale, fit_horizon, height_ratio
from hdvr.tracking.state import BODY_CORE_ASPECT, HIDDEN, OCCLUDED, TRACKED, covered_fraction

#: frames in a row a dancer must be seen after a stretch occluded for the stretch to be filled towards it
#: (chosen on 936 hdvr synth clips: 3 and 5 frames gave 67 and 68 clips below IDF1 0.9 or with a switch, 72 without
#: hindsight; docs/benchmarks.md "session 31")
MIN_SEEN_AFTER = 3
#: the fraction of the body core of the box where a dancer was last seen that must lie behind the body cores of the
#: dancers followed in every frame of an occluded stretch for :func:`hold_last_seen` to hold it there (session 59;
#: 0.4, 0.5 and 0.6 gave the same 5 of 72 procedural crossings failing, 17 without; on hdvr synth sets D, F, G, H
#: 0.5 moved one clip, 0.6 two: docs/benchmarks.md "session 59")
HOLD_MIN_COVER = 0.5
#: the share of the box last seen in a held stretch, the rest the online prediction (:func:`hold_last_seen`; session
#: 72, on 497 hdvr synth clips tracked with session 72's tracker: 1.0 (held, sessions 33-71) 22 failing, 0.75 21 with
#: no clip newly failing (D 2714 ballet 0.840 -> 0.981), 0.5 and 0.25 21 with one newly failing; docs/benchmarks.md
#: "session 72")
HOLD_WEIGHT = 0.75
#: how far a dancer's body reaches beyond its outermost keypoint, in box heights (:func:`enclose_keypoints`). Measured
#: (``scripts/measure_keypoint_reach.py``): on dancers of hdvr synth clips seen whole, the ground-truth box's sides lie
#: beyond YOLO11n-pose's outermost keypoints by a median 0.08 of its height (quartiles 0.07 and 0.11; 10,739
#: dancer-frames of the 144 clips of seeds 201-212 and 301-312). Sessions 32-47 used 0.06, an estimate; 504 synthetic
#: clips: failing 23 -> 22, mean IDF1 0.9849 -> 0.9854, HOTA 0.7934 -> 0.7953 (docs/benchmarks.md "session 48")
KEYPOINT_REACH = 0.08
#: keypoint confidence from which a keypoint widens its dancer's box
MIN_KEYPOINT_CONFIDENCE = 0.3
#: keypoints of that confidence a dancer needs in a frame for its box to be widened to them
MIN_KEYPOINTS = 5
#: of the 17 COCO-17 joints, how many a pose must show (confidence ``MIN_KEYPOINT_CONFIDENCE``) to lower a box's top
MIN_FULL_POSE = 15
#: of the 17 COCO-17 joints, how many the dancer in front must show for a couple's hidden partner to follow his box
#: (:func:`follow_partner_in_hold`, measured on the waits alone; session 81: 12 and 13 gave 30 failing clips of
#: 1,141, 35 without the step; 14 30 as well, with one fewer mended and one fewer broken; 15 36; no test of his pose
#: 32; docs/benchmarks.md "Session 81")
PARTNER_FRONT_JOINTS = 13
#: how far apart (in her box heights) the torso centres of a couple's waiting partner and of the dancer in front
#: must lie for her pose to count as her own (:func:`follow_partner_in_hold`; Algorithm 2* may give her his pose;
#: session 81, the only value tried: in 3004 tango her keypoints lie a median 44 px, 0.2 of her height, from his)
PARTNER_TORSO_APART = 0.1
#: frames on each side over which the height of the dancer in front, by which a couple's hidden partner scales, is
#: a median (:func:`follow_partner_in_hold`; 0: each frame's own height). Session 87, on session 84's runs of 1,743
#: clips: 44 -> 42 failing (2950 tango, 3063 swing mended), HOTA level; 15 also 42 and 30 43 (measured with every
#: frame's height in the median, before it kept to frames with his whole pose); docs/benchmarks.md "Session 87"
PARTNER_SCALE_WINDOW = 8
#: how far (in box heights) above or below its box a keypoint may lie for the pose to count as the dancer's
POSE_HEIGHT_MARGIN = 0.1
#: how far a dancer reaches above its highest keypoint (the top of the head above the face keypoints, the fingers
#: above a wrist), in box heights (:func:`trim_above_pose`). On 10,000 frames of fully seen dancers of hdvr synth clips
#: the ground truth reaches above YOLO11n-pose's highest keypoint by 0.07 of its height (median), 0.11 (95th
#: percentile), 0.13 (99th); 0.10, 0.12 and 0.13 were tried (docs/benchmarks.md "session 33")
HEAD_REACH = 0.12
#: BODY_25 indices of the 17 joints of COCO-17 (face, arms, hips, knees, ankles), those every pose detector gives: a
#: pose that shows nearly all of them (:func:`trim_above_pose`) shows the dancer's highest point
_FULL_POSE = [BODY25_NAMES.index(name) for name in (
    "nose", "right_eye", "left_eye", "right_ear", "left_ear", "right_shoulder", "left_shoulder", "right_elbow",
    "left_elbow", "right_wrist", "left_wrist", "right_hip", "left_hip", "right_knee", "left_knee", "right_ankle",
    "left_ankle")]
#: BODY_25 indices of the torso keypoints, whose mean must lie between a box's sides for its pose to widen it
_TORSO = [BODY25_NAMES.index(name) for name in ("neck", "right_shoulder", "left_shoulder", "mid_hip", "right_hip",
                                                 "left_hip")]
#: frames of the centred moving average of :func:`smooth_boxes` (0.3 s at 30 frames/s; chosen on the 936 clips:
#: 7, 9, 13 and 17 frames gave 65, 62, 61 and 62 clips failing, 9 the fewest switches, 18)
SMOOTH_WINDOW = 9
#: how far a hidden dancer's box moves from the tracker's place towards its start offset from the dancer in front
#: (:func:`keep_start_offset`; chosen on the 219 hdvr synth clips with a hidden start of seeds 201-912 and 1101-1512)
START_OFFSET_WEIGHT = 0.25
#: how far (in its box heights) a waiting dancer's feet may lie from where its start says they are
#: (:func:`keep_feet_behind_front`). 504 hdvr synth clips: 0.25 5 clips up, none down (failing 17 -> 16); 0.2 7 up,
#: 2 down; 0.3 3 up and 0.4 1 up, none down, 16 failing each (docs/benchmarks.md "session 49"). Scored again in
#: session 73 on 497 clips tracked with session 72's tracker: 0.2 6 clips up (2809 tango loses its switch), none down,
#: 21 failing as with 0.25; 0.15 the same counts; 0.1 and 0.35 23 failing (docs/benchmarks.md "session 73")
HIDDEN_FEET_TOLERANCE = 0.2
#: the least and most a waiting dancer's box is scaled from its start size as its feet move down or up the image
#: (:func:`scale_with_depth`): a guard against a wrong horizon, wider than a 4 s dance clip's changes of depth
DEPTH_SCALE_LIMITS = (0.6, 1.6)
#: how many times taller or shorter than the dancers seen a waiting dancer's start box may make her, against the
#: horizon, for her box to be scaled (:func:`scale_with_depth`): a horizon fitted just above the feet of a dancer whose
#: box bottom jitters puts a waiting dancer's feet a few px below it, a giant (hdvr synth seed 2982 flamenco: 4.2 x the
#: ratios of the dancers seen, IDF1 0.944 -> 0.836 without the check; 1.3 and 1.5 gave the same on 797 clips)
DEPTH_STATURE_FACTOR = 1.5
#: how far a waiting dancer's boxes move towards the straight line from its start box to where it was first seen
#: (:func:`fill_hidden_until_seen`; 1: onto it, 0: not at all)
HIDDEN_FILL_WEIGHT = 1.0
#: frames before its first sighting in which a waiting dancer is taken to walk out from behind the dancer in front
#: (:func:`fill_hidden_until_seen`; 1 s at 30 frames/s). Chosen in session 51 on 240 + 240 fresh and 504 tuned hdvr
#: synth clips: 20, 30, 40 and 60 frames gave 12 + 6 + 15 failing each (45: 13 + 6 + 15), against 13 + 8 + 15 for a
#: line over the whole wait; 30: 10 clips up, 3 down
HIDDEN_WALK_FRAMES = 30
#: how far the boxes of a wait never followed by a sighting move sideways towards the dancer's start place
#: (:func:`keep_start_place`; chosen in session 50 on 504 tuned and 240 fresh hdvr synth clips: 0.35, 0.5, 0.65, 0.8
#: and 1 gave 15+16, 15+15, 15+16, 15+16 and 17+18 failing)
START_PLACE_WEIGHT = 0.5


def _runs(mask) -> list[tuple[int, int]]:
    """(first, last) index, inclusive, of each run of True in the (T,) bool ``mask``."""
    edges = np.flatnonzero(np.diff(np.r_[0, np.asarray(mask).astype(np.int8), 0]))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


def occluded_stretches(status) -> list[tuple[int, int]]:
    """(first, last) frame, inclusive, of each run of ``occluded`` in ``status`` (T,) strings."""
    return _runs(np.asarray(status) == OCCLUDED)


def _checked(boxes, status, **counts) -> tuple[np.ndarray, np.ndarray]:
    """``boxes`` as a (T, N, 4) float array and ``status`` as a (T, N) object array; ValueError for other shapes and
    for any of ``counts`` (name=value) below 1."""
    boxes = np.asarray(boxes, float)
    if boxes.ndim != 3 or boxes.shape[2] != 4:
        raise ValueError(f"boxes must be (T, N, 4), got {boxes.shape}")
    for name, value in counts.items():
        if value < 1:
            raise ValueError(f"{name} must be >= 1, got {value}")
    return boxes, np.asarray([tuple(s) for s in status], dtype=object).reshape(boxes.shape[:2])


def _checked_start_boxes(boxes: np.ndarray, start_boxes) -> np.ndarray:
    """``start_boxes`` as a float array shaped like ``boxes`` (T, N, 4) px, ``boxes`` itself when None; ValueError
    for another shape."""
    start_boxes = boxes if start_boxes is None else np.asarray(start_boxes, float)
    if start_boxes.shape != boxes.shape:
        raise ValueError(f"start_boxes must be {boxes.shape} like boxes, got {start_boxes.shape}")
    return start_boxes


def _checked_mask(boxes: np.ndarray, mask, name: str) -> np.ndarray | None:
    """A (T, N) bool ``mask`` for ``boxes`` (T, N, 4), as an array (None stays None: an optional mask not given); a
    clear error naming it (``name``) for another shape."""
    if mask is None:
        return None
    mask = np.asarray(mask, bool)
    if mask.shape != boxes.shape[:2]:
        raise ValueError(f"{name} must be (T, N) for boxes {boxes.shape}, got {mask.shape}")
    return mask


def _checked_keypoints(keypoints, boxes: np.ndarray) -> np.ndarray:
    """``keypoints`` as a (T, N, 25, 3) BODY_25 float array for (T, N, 4) ``boxes``; ValueError for other shapes."""
    keypoints = np.asarray(keypoints, float)
    if keypoints.shape != boxes.shape[:2] + (len(BODY25_NAMES), 3):
        raise ValueError(f"keypoints must be (T, N, 25, 3) BODY_25 for boxes {boxes.shape}, got {keypoints.shape}")
    return keypoints


def _confident(keypoints: np.ndarray, min_confidence: float) -> np.ndarray:
    """(...) bool: which of the (..., 3) ``keypoints`` (x px, y px, confidence) are known and of confidence
    ``min_confidence`` or more."""
    return (keypoints[..., 2] >= min_confidence) & np.isfinite(keypoints[..., :2]).all(axis=-1)


def interpolate_boxes(start, end, steps: int) -> np.ndarray:
    """(steps, 4) boxes strictly between (x, y, w, h) px boxes ``start`` and ``end``, evenly spaced in time:
    centre and size are interpolated linearly (so a box that grows does not also drift)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    w = np.arange(1, steps + 1)[:, None] / (steps + 1)
    centre = (1 - w) * (start[:2] + start[2:] / 2) + w * (end[:2] + end[2:] / 2)
    size = (1 - w) * start[2:] + w * end[2:]
    return np.concatenate([centre - size / 2, size], axis=1)


def fill_occluded(boxes: np.ndarray, status, min_seen_after: int = MIN_SEEN_AFTER,
                  max_frames: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Fill with hindsight the boxes of the stretches in which each dancer was occluded (module docstring), with
    ``max_frames`` only those of at most that many frames (None, the default: any length).

    Session 87 measured a cap, as offline trackers cap the gaps they interpolate (StrongSORT's linear interpolation:
    20 frames): hidden for long, a dancer may turn back, and the line between its ends then lies off it (3060 hip-hop, a
    dancer hidden over frames 4-45: 0.890 -> 0.933 at 40). On the 1,743 hdvr synth clips' runs 40 frames gave 41 ->
    40 failing (9 up, 5 down), 30 39 and 20 39 (19 down); but a figure that walks steadily behind others for longer
    is best on the line, and the procedural crossing of ``scripts/make_tracking_docs.py --only procedural-vertical``
    (seed 14, figure 3 hidden from frame 28) fell to IoU 0.24 at frame 80 with 40. Not kept.

    ``boxes`` (T, N, 4) px, NaN where a dancer is absent or out of the frame; ``status`` T sequences of N strings
    (``tracked``, ``occluded``, ``hidden``, ``out``, ``absent``). Returns the new boxes and a (T, N) bool mask of the
    frames filled. The input is not changed.
    """
    boxes, status = _checked(boxes, status, min_seen_after=min_seen_after)
    out = boxes.copy()
    filled = np.zeros(boxes.shape[:2], bool)
    num_frames = boxes.shape[0]
    for i in range(boxes.shape[1]):
        seen = status[:, i] == TRACKED
        for first, last in occluded_stretches(status[:, i]):
            before, after = first - 1, last + 1
            if before < 0 or not seen[before] or after >= num_frames or \
                    not seen[after:after + min_seen_after].all():  # not seen before, or lost again (or never seen)
                continue
            if max_frames is not None and after - first > max_frames:
                continue
            ends = boxes[[before, after], i]
            if not np.isfinite(ends).all() or (ends[:, 2:] <= 0).any():
                continue
            out[first:after, i] = interpolate_boxes(ends[0], ends[1], after - first)
            filled[first:after, i] = True
    return out, filled


def hold_last_seen(boxes: np.ndarray, status, filled: np.ndarray, weight: float = 1.0,
                   stopped: np.ndarray | None = None,
                   min_cover: float = HOLD_MIN_COVER) -> tuple[np.ndarray, np.ndarray]:
    """Hold the box where each dancer was last seen through each ``occluded`` stretch that starts right after a frame
    it was seen (``tracked``) and that :func:`fill_occluded` did not fill (``filled``, its (T, N) mask); module
    docstring. ``boxes`` (T, N, 4) px, NaN where absent or out (those frames stay so). ``weight``: the held box is
    ``weight`` x the box last seen + (1 - ``weight``) x the online prediction of that frame (1: held;
    :func:`apply_hindsight` gives ``HOLD_WEIGHT``, 0.75, since session 72: docs/benchmarks.md). ``stopped``: optional
    (T, N) bool, the frames in which the online tracker had stopped the dancer's predicted box behind the dancers in
    front (``TrackRun.stopped_behind``); a stretch with any such frame keeps its online boxes (they ran on only while
    hidden). ``min_cover``: so does a stretch in any frame of which less than this fraction of the body core of the
    box last seen lies inside the body cores of the other dancers seen (``tracked``) then (:func:`covered_fraction`):
    that place lay open to view, so the dancer was not there; 0: off. Returns the new boxes and a (T, N) bool mask of
    the frames held. The input is not changed."""
    boxes, status = _checked(boxes, status)
    filled = _checked_mask(boxes, np.asarray(filled, bool), "filled")  # required: None is a wrong shape too
    stopped = _checked_mask(boxes, stopped, "stopped")
    out = boxes.copy()
    held = np.zeros(boxes.shape[:2], bool)
    for i in range(boxes.shape[1]):
        for first, last in occluded_stretches(status[:, i]):
            seen = boxes[first - 1, i] if first > 0 else None
            if seen is None or status[first - 1, i] != TRACKED or filled[first, i] or not np.isfinite(seen).all():
                continue
            if stopped is not None and stopped[first:last + 1, i].any():
                continue  # the tracker kept it behind the dancers in front: its online boxes say where
            stretch = np.arange(first, last + 1)
            stretch = stretch[np.isfinite(boxes[stretch, i]).all(axis=1)]
            others = [j for j in range(boxes.shape[1]) if j != i]
            if min_cover > 0 and any(
                    covered_fraction(seen, [boxes[t, j] for j in others if status[t, j] == TRACKED],
                                     BODY_CORE_ASPECT) < min_cover for t in stretch):
                continue  # where it was last seen lies open to view in some frame: it is not there
            out[stretch, i] = weight * seen + (1.0 - weight) * boxes[stretch, i]
            held[stretch, i] = True
    return out, held


def enclose_keypoints(boxes: np.ndarray, status, keypoints: np.ndarray, reach: float = KEYPOINT_REACH,
                      min_confidence: float = MIN_KEYPOINT_CONFIDENCE, min_keypoints: int = MIN_KEYPOINTS,
                      height_margin: float = POSE_HEIGHT_MARGIN,
                      frame_width: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``boxes`` (T, N, 4) px widened to enclose each dancer's BODY_25 ``keypoints`` (T, N, 25, 3: x px, y px,
    confidence; NaN where missing), with ``reach`` x the box height beyond the outermost ones (module docstring), in
    frames where the dancer is ``tracked`` and its pose fits its box: the mean of its torso keypoints (neck,
    shoulders, hips) lies between the box's left and right sides, and all its keypoints lie within the box's height,
    give or take ``height_margin`` x that height. No wider than the frame, given its width in px. Returns the new
    boxes and a (T, N) bool mask of the boxes widened. The input is not changed."""
    boxes, status = _checked(boxes, status, min_keypoints=min_keypoints)
    keypoints = _checked_keypoints(keypoints, boxes)
    if reach < 0 or height_margin < 0:
        raise ValueError(f"reach and height_margin must be >= 0, got {reach} and {height_margin}")
    confident = _confident(keypoints, min_confidence)
    x = np.where(confident, keypoints[..., 0], np.nan)
    y = np.where(confident, keypoints[..., 1], np.nan)
    left, top, width, height = np.moveaxis(boxes, -1, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows (no keypoint): those are not used anyway
        torso = np.nanmean(x[..., _TORSO], axis=-1)
        lowest, highest = np.nanmax(y, axis=-1), np.nanmin(y, axis=-1)
        new_left = np.fmin(left, np.nanmin(x, axis=-1) - reach * height)
        new_right = np.fmax(left + width, np.nanmax(x, axis=-1) + reach * height)
    with np.errstate(invalid="ignore"):  # NaN boxes and keypoints compare False: not widened
        fits = (left <= torso) & (torso <= left + width) & (highest >= top - height_margin * height) \
            & (lowest <= top + height + height_margin * height)
    if frame_width is not None:  # clipped like the tracker's own boxes, but never cut below them
        new_left = np.minimum(np.maximum(new_left, 0.0), left)
        new_right = np.maximum(np.minimum(new_right, float(frame_width)), left + width)
    widened = fits & (confident.sum(axis=-1) >= min_keypoints) & (status == TRACKED) \
        & ((new_left < left) | (new_right > left + width))
    out = boxes.copy()
    out[..., 0] = np.where(widened, new_left, left)
    out[..., 2] = np.where(widened, new_right - new_left, width)
    return out, widened


def trim_above_pose(boxes: np.ndarray, status, keypoints: np.ndarray, reach: float = HEAD_REACH,
                    min_confidence: float = MIN_KEYPOINT_CONFIDENCE,
                    min_joints: int = MIN_FULL_POSE) -> tuple[np.ndarray, np.ndarray]:
    """``boxes`` (T, N, 4) px whose top lies more than ``reach`` x the box height above the highest of the dancer's
    BODY_25 ``keypoints`` (T, N, 25, 3: x px, y px, confidence; NaN where missing) lowered to that, keeping the
    bottom (module docstring), in frames where the dancer is ``tracked``, shows at least ``min_joints`` of the 17
    COCO-17 joints with confidence ``min_confidence`` or more (so that its highest keypoint is its face or a raised
    hand) and all of these lie between the box's sides (the pose is the dancer's; run after
    :func:`enclose_keypoints`). Never below half the box's height. Returns the new boxes and a (T, N) bool mask of
    the boxes lowered. The input is not changed."""
    boxes, status = _checked(boxes, status, min_joints=min_joints)
    keypoints = _checked_keypoints(keypoints, boxes)
    if reach < 0:
        raise ValueError(f"reach must be >= 0, got {reach}")
    joints = keypoints[:, :, _FULL_POSE]
    confident = _confident(joints, min_confidence)
    left, top, width, height = np.moveaxis(boxes, -1, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows (no keypoint): those are not used anyway
        highest = np.nanmin(np.where(confident, joints[..., 1], np.nan), axis=-1)
        leftmost = np.nanmin(np.where(confident, joints[..., 0], np.nan), axis=-1)
        rightmost = np.nanmax(np.where(confident, joints[..., 0], np.nan), axis=-1)
    new_top = highest - reach * height
    bottom = top + height
    with np.errstate(invalid="ignore"):  # NaN boxes and keypoints compare False: not lowered
        lowered = (status == TRACKED) & (confident.sum(axis=-1) >= min_joints) & (leftmost >= left) \
            & (rightmost <= left + width) & (new_top > top) & (bottom - new_top >= 0.5 * height)
    out = boxes.copy()
    out[..., 1] = np.where(lowered, new_top, top)
    out[..., 3] = np.where(lowered, bottom - new_top, height)
    return out, lowered


def smooth_boxes(boxes: np.ndarray, status, window: int = SMOOTH_WINDOW) -> np.ndarray:
    """``boxes`` (T, N, 4) px with the centre and size of each dancer's boxes averaged over ``window`` frames
    centred on each frame (the ends of a run padded with its first and last box), within each run of frames with
    a box and status ``tracked`` or ``occluded``; runs shorter than ``window`` and other frames are kept. A
    box inside the frame stays inside it (its corners are averages of boxes inside it). The input is not changed."""
    boxes, status = _checked(boxes, status, window=window)
    out = boxes.copy()
    for i in range(boxes.shape[1]):
        has_box = np.isfinite(boxes[:, i]).all(axis=1) & np.isin(status[:, i], (TRACKED, OCCLUDED))
        for first, last in _runs(has_box):
            run = slice(first, last + 1)
            if last + 1 - first < window:
                continue
            centre = boxes[run, i, :2] + boxes[run, i, 2:] / 2
            size = uniform_filter1d(boxes[run, i, 2:], window, axis=0, mode="nearest")
            centre = uniform_filter1d(centre, window, axis=0, mode="nearest")
            out[run, i] = np.concatenate([centre - size / 2, size], axis=1)
    return out


def _sideways_offset(own: np.ndarray, other: np.ndarray) -> np.ndarray:
    """Horizontal offset of the centres of boxes ``own`` from those of ``other`` (..., 4) px, in ``own``'s box
    heights (positive: to the right in the image)."""
    return (own[..., 0] + own[..., 2] / 2 - other[..., 0] - other[..., 2] / 2) / own[..., 3]


def start_offsets(boxes: np.ndarray, hidden_starts) -> dict[tuple[int, int], tuple[int, float]]:
    """For each start of a dancer hidden behind another (``hidden_starts``: (frame, dancer, dancer in front)
    triples; a user's correction that puts a dancer behind another is such a start too), keyed by (dancer, frame):
    the dancer in front and the horizontal offset of its box centre from that dancer's box centre in ``boxes``
    (T, N, 4) px at that frame, in its own box heights (positive: to the right in the image)."""
    boxes = np.asarray(boxes, float)
    out = {}
    for frame, dancer, front in hidden_starts:
        own, other = boxes[frame, dancer], boxes[frame, front]
        if np.isfinite(own).all() and np.isfinite(other).all() and own[3] > 0:
            out[(int(dancer), int(frame))] = (int(front), float(_sideways_offset(own, other)))
    return out


def _start_spans(starts, num_frames: int) -> dict[tuple[int, int], int]:
    """For each (dancer, frame) start of ``starts`` (a dict keyed so, or a set of such pairs), the frame its span
    ends (exclusive): the dancer's next start, or ``num_frames``."""
    keys = sorted(starts)
    return {(dancer, first): next((f for d, f in keys[k + 1:] if d == dancer), num_frames)
            for k, (dancer, first) in enumerate(keys)}


def _wait_end(status: np.ndarray, dancer: int, first: int) -> int:
    """The first frame from ``first`` on where ``dancer`` no longer waits hidden (status ``hidden``) in ``status``
    (T, N), or T: the frame its wait ends."""
    after = np.flatnonzero(status[first:, dancer] != HIDDEN)
    return first + int(after[0]) if len(after) else len(status)


def _waiting_frames(boxes: np.ndarray, status: np.ndarray, dancer: int, front: int, first: int,
                    end: int) -> np.ndarray:
    """Frames in [first, end) where ``dancer`` waits hidden (status ``hidden``) and both its box and the box of the
    dancer in front, ``front``, are known (``boxes`` (T, N, 4) px, ``status`` (T, N))."""
    frames = np.arange(first, end)
    known = np.isfinite(boxes[frames, dancer]).all(axis=1) & np.isfinite(boxes[frames, front]).all(axis=1)
    return frames[(status[frames, dancer] == HIDDEN) & known]


def keep_start_offset(boxes: np.ndarray, status, offsets: dict[tuple[int, int], tuple[int, float]],
                      weight: float = START_OFFSET_WEIGHT) -> np.ndarray:
    """``boxes`` (T, N, 4) px with each dancer of ``offsets`` (:func:`start_offsets`) moved sideways, on the frames
    where it waits hidden (status ``hidden``) and both its box and its front dancer's are known, ``weight`` of the way
    from its offset from the front dancer's box to the offset of its latest start (module docstring). Size and
    height are kept. The input is not changed."""
    boxes, status = _checked(boxes, status)
    if not 0 <= weight <= 1:
        raise ValueError(f"weight must be in [0, 1], got {weight}")
    out = boxes.copy()
    for (dancer, first), end in _start_spans(offsets, len(boxes)).items():
        front, offset = offsets[(dancer, first)]
        frames = _waiting_frames(boxes, status, dancer, front, first, end)
        frames = frames[boxes[frames, dancer, 3] > 0]
        own = boxes[frames, dancer]
        now = _sideways_offset(own, boxes[frames, front])
        out[frames, dancer, 0] = own[:, 0] + weight * (offset - now) * own[:, 3]
    return out


def start_feet(boxes: np.ndarray, hidden_starts) -> dict[tuple[int, int], tuple[int, float, float]]:
    """For each start of a dancer hidden behind another (``hidden_starts``: (frame, dancer, dancer in front)
    triples), keyed by (dancer, frame): the dancer in front, and the bottoms (y px) of the dancer's and the front
    dancer's boxes in ``boxes`` (T, N, 4) px at that frame: where their feet were."""
    boxes = np.asarray(boxes, float)
    out = {}
    for frame, dancer, front in hidden_starts:
        own, other = boxes[frame, dancer], boxes[frame, front]
        if np.isfinite(own).all() and np.isfinite(other).all():
            out[(int(dancer), int(frame))] = (int(front), float(own[1] + own[3]), float(other[1] + other[3]))
    return out


def keep_feet_behind_front(boxes: np.ndarray, status, feet: dict[tuple[int, int], tuple[int, float, float]],
                           tolerance: float = HIDDEN_FEET_TOLERANCE) -> np.ndarray:
    """``boxes`` (T, N, 4) px with the box of each dancer of ``feet`` (:func:`start_feet`) moved up or down, on the
    frames where it waits hidden (status ``hidden``) and both its box and its front dancer's are known, until its
    bottom lies within ``tolerance`` x its height of its start bottom moved by as much as the front dancer's bottom
    moved since the start. The dancer waiting behind stays on the floor behind the one in front, as far in depth
    as he goes, while its own tracker follows what its box shows, the dancer in front, and can slide off it (hdvr
    synth seed 2112 hip-hop: 160 px down; seed 310 tango, a couple walking towards the camera: the dancer behind
    left 54 px too high, IDF1 0.858 -> 0.950). Size and sideways place are kept; ``inf`` leaves every box as it is.
    The input is not changed."""
    boxes, status = _checked(boxes, status)
    if not tolerance >= 0:
        raise ValueError(f"tolerance must be >= 0, got {tolerance}")
    out = boxes.copy()
    for (dancer, first), end in _start_spans(feet, len(boxes)).items():
        front, own_bottom, front_bottom = feet[(dancer, first)]
        frames = _waiting_frames(boxes, status, dancer, front, first, end)
        own, other = boxes[frames, dancer], boxes[frames, front]
        expected = own_bottom + (other[:, 1] + other[:, 3] - front_bottom)
        limit = tolerance * own[:, 3]
        bottom = np.clip(own[:, 1] + own[:, 3], expected - limit, expected + limit)
        out[frames, dancer, 1] = bottom - own[:, 3]
    return out


def scale_with_depth(boxes: np.ndarray, status, feet: dict[tuple[int, int], tuple[int, float, float]],
                     horizon: float, start_boxes: np.ndarray | None = None,
                     limits: tuple[float, float] = DEPTH_SCALE_LIMITS, seen_ratio: float = np.nan,
                     stature_factor: float = DEPTH_STATURE_FACTOR) -> np.ndarray:
    """``boxes`` (T, N, 4) px with the box of each dancer of ``feet`` (:func:`start_feet`), on the frames where it waits
    hidden (status ``hidden``) and both its box and its front dancer's are known, given the height of its start box
    (in ``start_boxes``, default ``boxes``) times :func:`hdvr.tracking.ground.depth_scale` of its bottom against its
    start bottom for the horizon row ``horizon`` px (:func:`hdvr.tracking.ground.fit_horizon`), clipped to
    ``limits``; its width scaled alike, its bottom and centre kept. A couple that comes nearer the camera brings the
    dancer hidden behind nearer too, and :func:`keep_feet_behind_front` has moved her feet down with his, while her
    own tracker kept the size she had at the start (module docstring). ``seen_ratio``: the box height per px of feet
    below the horizon of the dancers seen (:func:`hdvr.tracking.ground.height_ratio`); a waiting dancer whose start box
    gives a ratio more than ``stature_factor`` times larger or smaller is left as it is (the horizon and her start
    disagree); NaN: no such check. A horizon at ``-inf`` and frames whose bottom lies above the horizon change
    nothing; the input is not changed."""
    boxes, status = _checked(boxes, status)
    start_boxes = _checked_start_boxes(boxes, start_boxes)
    if not 0 < limits[0] <= 1 <= limits[1]:
        raise ValueError(f"limits must be (low, high) with 0 < low <= 1 <= high, got {limits}")
    if not stature_factor >= 1:
        raise ValueError(f"stature_factor must be >= 1, got {stature_factor}")
    out = boxes.copy()
    if not np.isfinite(horizon):
        return out
    for (dancer, first), end in _start_spans(feet, len(boxes)).items():
        front, own_bottom, _ = feet[(dancer, first)]
        start_height = start_boxes[first, dancer, 3]
        own_ratio = start_height / (own_bottom - horizon) if own_bottom > horizon else np.inf
        if np.isfinite(seen_ratio) and not 1 / stature_factor <= own_ratio / seen_ratio <= stature_factor:
            continue
        frames = _waiting_frames(boxes, status, dancer, front, first, end)
        own = boxes[frames, dancer]
        bottom = own[:, 1] + own[:, 3]
        scale = np.clip(depth_scale(bottom, own_bottom, horizon), *limits)
        keep = np.isfinite(scale) & (own[:, 3] > 0)
        frames, own, bottom, scale = frames[keep], own[keep], bottom[keep], scale[keep]
        height = start_height * scale
        width = own[:, 2] * height / own[:, 3]
        out[frames, dancer] = np.stack([own[:, 0] + (own[:, 2] - width) / 2, bottom - height, width, height], axis=1)
    return out


def fill_hidden_until_seen(boxes: np.ndarray, status, hidden_starts, weight: float = HIDDEN_FILL_WEIGHT,
                           walk_frames: int = HIDDEN_WALK_FRAMES) -> np.ndarray:
    """``boxes`` (T, N, 4) px with each wait of ``hidden_starts`` ((frame, dancer, dancer in front) triples) that ends
    with the dancer seen (status ``hidden`` from the start frame on, then ``tracked``) walking out over its last
    ``walk_frames`` frames: those move ``weight`` of the way onto the straight line (centre and size,
    :func:`interpolate_boxes`) from its box ``walk_frames`` + 1 frames before the first frame seen (the start frame's
    in a shorter wait, or where that box is unknown) to the box of the first frame seen; the frames before keep their
    boxes (module docstring). ``walk_frames`` at least as long as the wait: one line from the start box over all of
    it. Frames without a box stay so; the input is not changed."""
    boxes, status = _checked(boxes, status)
    if not 0 <= weight <= 1:
        raise ValueError(f"weight must be in [0, 1], got {weight}")
    if walk_frames < 1:
        raise ValueError(f"walk_frames must be >= 1, got {walk_frames}")
    out = boxes.copy()
    for first, dancer, _ in hidden_starts:
        seen = _wait_end(status, dancer, first)
        if seen >= len(boxes) or status[seen, dancer] != TRACKED or seen - first < 2:
            continue
        since = max(first, seen - walk_frames - 1)  # it stood behind the front dancer until then
        if not np.isfinite(boxes[since, dancer]).all():
            since = first
        ends = boxes[[since, seen], dancer]
        if not np.isfinite(ends).all():
            continue
        line = interpolate_boxes(ends[0], ends[1], seen - since - 1)
        frames = np.arange(since + 1, seen)
        known = np.isfinite(boxes[frames, dancer]).all(axis=1)
        out[frames[known], dancer] = (1 - weight) * boxes[frames[known], dancer] + weight * line[known]
    return out


def keep_start_place(boxes: np.ndarray, status, hidden_starts, weight: float = START_PLACE_WEIGHT,
                     start_boxes: np.ndarray | None = None, returned: np.ndarray | None = None) -> np.ndarray:
    """``boxes`` (T, N, 4) px with the boxes of each wait of ``hidden_starts`` ((frame, dancer, dancer in front)
    triples) that is never followed by a sighting (the dancer is still ``hidden`` at the end of the video, or its
    wait ends with any status but ``tracked``) moved sideways ``weight`` of the way from their centre to the centre
    of its start box (module docstring); a wait that a later start of the same dancer (a user's correction behind
    another dancer) cuts short is left as it is. ``start_boxes`` (T, N, 4) px: where the start boxes are read (default
    ``boxes``; :func:`apply_hindsight` gives the online boxes). A wait that ends seen is left to
    :func:`fill_hidden_until_seen`, and so is, as the online tracker has it, a wait in some frame of which
    ``returned`` ((T, N) bool, ``TrackRun.returned_behind``) says the online tracker found the dancer's box on the
    empty floor and put it back behind the dancer in front (``MultiTrackerConfig.waiting_empty_behind``): the
    place it was left at showed nobody, so it had not stayed there. Size, height and frames without a box are kept;
    the input is not changed."""
    boxes, status = _checked(boxes, status)
    if not 0 <= weight <= 1:
        raise ValueError(f"weight must be in [0, 1], got {weight}")
    start_boxes = _checked_start_boxes(boxes, start_boxes)
    returned = _checked_mask(boxes, returned, "returned")
    out = boxes.copy()
    spans = _start_spans({(int(d), int(f)) for f, d, _ in hidden_starts}, len(boxes))
    for first, dancer, _ in hidden_starts if weight > 0 else ():  # 0: off, the boxes exactly as they were
        end = _wait_end(status, dancer, first)
        if spans[(int(dancer), int(first))] < end:  # hidden again from a later start (a correction): its own place
            continue
        start = start_boxes[first, dancer]
        if (end < len(boxes) and status[end, dancer] == TRACKED) or not np.isfinite(start).all():
            continue
        if returned is not None and returned[first:end, dancer].any():  # its place seen empty: it went on
            continue
        frames = np.arange(first + 1, end)
        frames = frames[np.isfinite(boxes[frames, dancer]).all(axis=1)]
        centre = boxes[frames, dancer, 0] + boxes[frames, dancer, 2] / 2
        target = start[0] + start[2] / 2
        out[frames, dancer, 0] = (1 - weight) * centre + weight * target - boxes[frames, dancer, 2] / 2
    return out


def _carried(his: np.ndarray, his_then: np.ndarray, own_then: np.ndarray, width_ratio: float,
             scale: np.ndarray) -> np.ndarray:
    """(F, 4) px boxes of a partner carried with the dancer in front: his boxes ``his`` (F, 4) px mapped as his box
    ``his_then`` mapped onto hers, ``own_then`` (both (4,) px): her height and her offsets from his centre and bottom
    times ``scale`` (F,) (his height over his height then), her width his width times ``width_ratio``."""
    centre = his[:, 0] + his[:, 2] / 2 + (own_then[0] + own_then[2] / 2 - his_then[0] - his_then[2] / 2) * scale
    bottom = his[:, 1] + his[:, 3] + (own_then[1] + own_then[3] - his_then[1] - his_then[3]) * scale
    height = own_then[3] * scale
    width = his[:, 2] * width_ratio
    return np.stack([centre - width / 2, bottom - height, width, height], axis=1)


def _running_median(values: np.ndarray, half: int) -> np.ndarray:
    """(T, ...) median of ``values`` over the frames within ``half`` of each (NaN ignored; NaN where all are);
    ``values`` itself for ``half`` 0."""
    if half <= 0:
        return values
    pad = np.full((half,) + values.shape[1:], np.nan)
    windows = np.lib.stride_tricks.sliding_window_view(np.concatenate([pad, values, pad]), 2 * half + 1, axis=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN window stays NaN
        return np.nanmedian(windows, axis=-1)


def _torso_centre(keypoints: np.ndarray, min_confidence: float) -> np.ndarray:
    """(F,) mean x px of the torso keypoints (neck, shoulders, hips) of confidence ``min_confidence`` or more of
    each of the (F, 25, 3) BODY_25 ``keypoints``; NaN where fewer than two are."""
    torso = keypoints[:, _TORSO]
    sure = _confident(torso, min_confidence)
    count = sure.sum(axis=1)
    total = np.where(sure, torso[..., 0], 0.0).sum(axis=1)
    return np.where(count >= 2, total / np.maximum(count, 1), np.nan)


def follow_partner_in_hold(boxes: np.ndarray, status, hidden_starts, keypoints: np.ndarray,
                           min_confidence: float = MIN_KEYPOINT_CONFIDENCE, front_joints: int = PARTNER_FRONT_JOINTS,
                           own_keypoints: int = MIN_KEYPOINTS,
                           torso_apart: float = PARTNER_TORSO_APART,
                           scale_window: int = PARTNER_SCALE_WINDOW) -> np.ndarray:
    """``boxes`` (T, N, 4) px of a video of exactly two dancers (N == 2: a couple) with the box of a partner hidden
    behind the other carried along with his (module docstring), on the frames where the dancer in front shows at
    least ``front_joints`` of the 17 COCO-17 joints (BODY_25 ``keypoints`` (T, N, 25, 3): x px, y px, confidence;
    confidence ``min_confidence`` or more):

    - a partner waiting hidden since her start (``hidden_starts``: (frame, dancer, dancer in front) triples; status
      ``hidden``) and showing fewer than ``own_keypoints`` keypoints of her own: his box mapped as his box at her
      start mapped onto her start box (:func:`_carried`), her width his width times her start width over his;
      where she shows ``own_keypoints`` or more and her torso's centre lies ``torso_apart`` x her box height or
      more from his (a pose of her own, not his given to her), her box is moved sideways onto her torso instead,
      whatever his pose shows;
    - a partner occluded after being seen (a stretch of status ``occluded`` right after a ``tracked`` frame) while
      he is ``tracked``: his box mapped as his box on the frame she was last seen mapped onto hers then, her width
      his width times hers over his then; where she is seen again right after the stretch, blended linearly
      towards the mapping of that frame's boxes.

    His height, by which her box scales, is the median of his box heights over the ``scale_window`` frames on each
    side on which his pose shows ``front_joints`` joints (his box is his whole body there; 0: each frame's own, as
    on frames with no such frame near): his box, even refined, loses his raised arms or a bent knee on some frames
    (2950 tango: 275 px around a dancer of 357 with raised arms), and she did not shrink with them.

    Other frames, clips of any other number of dancers and the input are not changed."""
    boxes, status = _checked(boxes, status, front_joints=front_joints, own_keypoints=own_keypoints)
    if scale_window < 0:
        raise ValueError(f"scale_window must be >= 0, got {scale_window}")
    keypoints = _checked_keypoints(keypoints, boxes)
    out = boxes.copy()
    if boxes.shape[1] != 2:
        return out
    front_seen = _confident(keypoints[:, :, _FULL_POSE], min_confidence).sum(axis=-1)
    whole = np.where(front_seen >= front_joints, boxes[:, :, 3], np.nan)  # heights of boxes around a whole body
    heights = _running_median(whole, scale_window)  # (T, 2) px
    heights = np.where(np.isfinite(heights), heights, boxes[:, :, 3])
    own_seen = _confident(keypoints, min_confidence).sum(axis=-1)
    for first, dancer, front in hidden_starts:
        his_start, own_start = boxes[first, front], boxes[first, dancer]
        if not (np.isfinite(his_start).all() and np.isfinite(own_start).all() and (his_start[2:] > 0).all()):
            continue
        waiting = _waiting_frames(boxes, status, dancer, front, first, _wait_end(status, dancer, first))
        frames = waiting[(front_seen[waiting, front] >= front_joints) & (own_seen[waiting, dancer] < own_keypoints)]
        out[frames, dancer] = _carried(boxes[frames, front], his_start, own_start, own_start[2] / his_start[2],
                                       heights[frames, front] / heights[first, front])
        posed = waiting[own_seen[waiting, dancer] >= own_keypoints]
        centre = _torso_centre(keypoints[posed, dancer], min_confidence)
        with np.errstate(invalid="ignore"):  # his torso unseen (NaN): hers is her own
            given = np.abs(centre - _torso_centre(keypoints[posed, front], min_confidence)) \
                < torso_apart * boxes[posed, dancer, 3]  # the front dancer's pose given to her
        own = np.isfinite(centre) & ~given
        out[posed[own], dancer, 0] = centre[own] - boxes[posed[own], dancer, 2] / 2
    def seen(t: int, dancer: int) -> bool:  # the dancer is seen on frame t and both boxes are known there
        return 0 <= t < len(boxes) and status[t, dancer] == TRACKED and np.isfinite(boxes[t]).all() \
            and (boxes[t, :, 2:] > 0).all()

    for dancer, front in ((0, 1), (1, 0)):
        for begin, end in occluded_stretches(status[:, dancer]):
            frames = np.arange(begin, end + 1)
            frames = frames[(status[frames, front] == TRACKED) & np.isfinite(boxes[frames, front]).all(axis=1)
                            & (front_seen[frames, front] >= front_joints)]
            if not len(frames) or not seen(begin - 1, dancer):
                continue
            ends = [begin - 1, end + 1] if seen(end + 1, dancer) else [begin - 1]
            carried = [_carried(boxes[frames, front], boxes[t, front], boxes[t, dancer],
                                boxes[t, dancer, 2] / boxes[t, front, 2], heights[frames, front] / heights[t, front])
                       for t in ends]
            if len(ends) == 2:
                weight = ((frames - (begin - 1)) / (end + 2 - begin))[:, None]
                carried = [(1 - weight) * carried[0] + weight * carried[1]]
            out[frames, dancer] = carried[0]
    return out


@dataclass(frozen=True)
class HindsightSettings:
    """The settings of :func:`apply_hindsight`'s steps, the module's defaults unless given (for measuring others on runs
    already tracked, ``scripts/hindsight_runs.py``). ``keypoint_reach`` and ``head_reach`` in box heights,
    ``smooth_window``, ``min_seen_after`` and ``hidden_walk_frames`` in frames, ``start_offset_weight``,
    ``hidden_fill_weight`` and ``start_place_weight`` fractions, ``hidden_feet_tolerance`` in box heights (``inf``:
    off). ``hold_weight``: the share of the box last seen in a held stretch (:func:`hold_last_seen`), the rest the
    online prediction; ``keep_stopped``: a stretch in which the online tracker stopped the dancer behind the dancers in
    front keeps its online boxes (:func:`hold_last_seen`'s ``stopped``), and so does one in which the place last seen
    lies open to view (``hold_min_cover``, :func:`hold_last_seen`'s ``min_cover``); ``keep_returned``: a wait in
    which the online tracker put the dancer back behind the dancer in front from the empty floor keeps its online
    boxes (:func:`keep_start_place`'s ``returned``). ``scale_with_depth``: scale waiting
    dancers' boxes with their feet (:func:`scale_with_depth`), with a horizon fitted only where some dancer's feet range
    over ``horizon_min_spread`` of its height, and ``depth_stature_factor`` its check of the waiting dancer's start
    against the horizon. ``amodal_boxes``: :func:`hdvr.tracking.amodal.refine_boxes`, with the weights at
    ``amodal_weights`` ("": the shipped ones). ``follow_partner``: end with :func:`follow_partner_in_hold`, its
    ``front_joints`` ``partner_front_joints`` and its ``scale_window`` ``partner_scale_window`` (frames).
    ``max_fill_frames``: :func:`fill_occluded`'s ``max_frames`` (None: stretches of any length filled)."""

    min_seen_after: int = MIN_SEEN_AFTER
    keypoint_reach: float = KEYPOINT_REACH
    head_reach: float = HEAD_REACH
    smooth_window: int = SMOOTH_WINDOW
    start_offset_weight: float = START_OFFSET_WEIGHT
    hidden_feet_tolerance: float = HIDDEN_FEET_TOLERANCE
    hidden_fill_weight: float = HIDDEN_FILL_WEIGHT
    hidden_walk_frames: int = HIDDEN_WALK_FRAMES
    start_place_weight: float = START_PLACE_WEIGHT
    hold_weight: float = HOLD_WEIGHT
    keep_stopped: bool = True
    keep_returned: bool = True
    hold_min_cover: float = HOLD_MIN_COVER
    amodal_boxes: bool = True
    amodal_weights: str = ""
    scale_with_depth: bool = True
    horizon_min_spread: float = HORIZON_MIN_SPREAD
    depth_stature_factor: float = DEPTH_STATURE_FACTOR
    follow_partner: bool = True
    partner_front_joints: int = PARTNER_FRONT_JOINTS
    partner_scale_window: int = PARTNER_SCALE_WINDOW
    max_fill_frames: int | None = None


def apply_hindsight(boxes: np.ndarray, status, keypoints: np.ndarray, frame_width: float | None = None,
                    hidden_starts=(), settings: HindsightSettings | None = None,
                    stopped_behind: np.ndarray | None = None,
                    returned_behind: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The boxes ``hdvr track`` writes, from the online tracker's ``boxes`` (T, N, 4) px, ``status``, the
    ``keypoints`` (T, N, 25, 3) written for each dancer and the dancers that start hidden behind another
    (``hidden_starts``: (frame, dancer, dancer in front) triples): :func:`fill_occluded`, :func:`hold_last_seen`,
    :func:`enclose_keypoints` (no wider than ``frame_width`` px), :func:`trim_above_pose`, :func:`smooth_boxes`,
    :func:`keep_start_offset` (with the start offsets of the online boxes), :func:`keep_feet_behind_front` (with
    their start feet), :func:`scale_with_depth` (against the horizon and the height ratio that the boxes of the
    dancers seen show by then: :func:`hdvr.tracking.ground.fit_horizon`, :func:`hdvr.tracking.ground.height_ratio`),
    :func:`fill_hidden_until_seen`, :func:`keep_start_place` (towards the online start boxes),
    :func:`hdvr.tracking.amodal.refine_boxes` (seen dancers' boxes to their whole body) and
    :func:`follow_partner_in_hold` (a couple's hidden partner carried with the dancer in front), in that order, with
    ``settings`` (default: :class:`HindsightSettings`, the module's); ``stopped_behind``: optional (T, N) bool, the
    frames in which the online tracker had stopped a dancer behind the dancers in front (``TrackRun.stopped_behind``);
    ``returned_behind``: optional (T, N) bool, the frames by which it had put a waiting dancer back behind the dancer
    in front from the empty floor (``TrackRun.returned_behind``; :func:`keep_start_place` leaves such a wait).
    Returns the boxes and the (T, N) bool mask of the frames filled."""
    s = settings or HindsightSettings()
    online = np.asarray(boxes, float)
    offsets, feet = start_offsets(online, hidden_starts), start_feet(online, hidden_starts)
    boxes, filled = fill_occluded(boxes, status, min_seen_after=s.min_seen_after, max_frames=s.max_fill_frames)
    boxes = hold_last_seen(boxes, status, filled, weight=s.hold_weight,
                           stopped=stopped_behind if s.keep_stopped else None, min_cover=s.hold_min_cover)[0]
    boxes = enclose_keypoints(boxes, status, keypoints, reach=s.keypoint_reach, frame_width=frame_width)[0]
    boxes = trim_above_pose(boxes, status, keypoints, reach=s.head_reach)[0]
    boxes = smooth_boxes(boxes, status, window=s.smooth_window)
    boxes = keep_start_offset(boxes, status, offsets, weight=s.start_offset_weight)
    boxes = keep_feet_behind_front(boxes, status, feet, tolerance=s.hidden_feet_tolerance)
    if s.scale_with_depth:
        horizon = fit_horizon(boxes, status, min_spread=s.horizon_min_spread)
        boxes = scale_with_depth(boxes, status, feet, horizon, start_boxes=online,
                                 seen_ratio=height_ratio(boxes, status, horizon), stature_factor=s.depth_stature_factor)
    boxes = fill_hidden_until_seen(boxes, status, hidden_starts, weight=s.hidden_fill_weight,
                                   walk_frames=s.hidden_walk_frames)
    boxes = keep_start_place(boxes, status, hidden_starts, weight=s.start_place_weight, start_boxes=online,
                             returned=returned_behind if s.keep_returned else None)
    if s.amodal_boxes:
        boxes = refine_boxes(boxes, status, keypoints, weights=s.amodal_weights)
    if s.follow_partner:
        boxes = follow_partner_in_hold(boxes, status, hidden_starts, keypoints, front_joints=s.partner_front_joints,
                                       scale_window=s.partner_scale_window)
    return boxes, filled
