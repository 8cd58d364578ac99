"""scripts/hindsight_runs.py: kept runs scored with hindsight settings, the settings parsed, bad input; and one real
clip tracked, kept and scored as the benchmark scores it."""

import json
import numpy as np
import pytest
from script_loader import load_script

from hdvr.tracking.hindsight import HindsightSettings


def _kept_run(folder, name="7_0"):
    """A kept run of two dancers over 12 frames: dancer 0 seen throughout, dancer 1 occluded on frames 4-7 with a
    box left where it was; its ground truth moves steadily right, 5 px a frame."""
    frames = 12
    truth = np.zeros((frames, 2, 4))
    truth[:, 0] = [100, 50, 40, 100]
    truth[:, 1] = np.stack([200 + 5 * np.arange(frames), np.full(frames, 60.0), np.full(frames, 40.0),
                            np.full(frames, 100.0)], axis=1)
    boxes = truth.copy()
    boxes[4:8, 1] = truth[3, 1]
    status = np.array([["tracked", "occluded" if 4 <= t < 8 else "tracked"] for t in range(frames)])
    keypoints = np.full((frames, 2, 25, 3), np.nan)
    keypoints[..., 2] = 0
    np.savez(folder / f"{name}.npz", boxes=boxes, status=status, keypoints=keypoints, order=np.array([0, 1]),
             hidden_starts=np.zeros((0, 3), int), width=640.0)
    return truth


def _clip_with_truth(clips_dir, truth, seed=7, index=0):
    clip = clips_dir / f"synth-{seed}" / f"clip_{index:05d}"
    clip.mkdir(parents=True)
    frames, n = truth.shape[:2]
    np.savez(clip / "gt.npz", boxes=np.transpose(truth, (1, 0, 2)), keypoints2d=np.zeros((n, frames, 25, 2)),
             visibility=np.full((n, frames, 25), 2))
    return clip


def _kept_clip(tmp_path):
    """The script, the runs folder holding :func:`_kept_run` (7_0) with its clip's truth under ``tmp_path/clips``,
    the truth (T, N, 4) px and the run as :func:`load_run` reads it."""
    script = load_script("hindsight_runs")
    runs = tmp_path / "runs"
    runs.mkdir()
    truth = _kept_run(runs)
    _clip_with_truth(tmp_path / "clips", truth)
    return script, runs, truth, script.load_run(runs / "7_0.npz")


def test_a_kept_run_scores_with_hindsight_filling_the_occluded_stretch(tmp_path, capsys):
    script, runs, truth, run = _kept_clip(tmp_path)
    out = tmp_path / "scores.json"
    assert script.main(["score", "--clips-dir", str(tmp_path / "clips"), "--runs", str(runs),
                        "--per-clip-json", str(out)]) == 0
    scores = json.loads(out.read_text())
    assert scores["hindsight"]["keypoint_reach"] == HindsightSettings().keypoint_reach
    clip = scores["clips"]["7:0:0.3"]
    assert clip["idf1"] == 1.0 and clip["id_switches"] == 0  # the filled stretch follows the dancer
    assert "1 clips, mean IDF1 1.0000" in capsys.readouterr().out
    # without hindsight the held box falls behind the moving dancer: the kept boxes themselves score lower
    from hdvr.tracking.evaluation import evaluate_tracking
    assert evaluate_tracking(truth, run["boxes"]).idf1 < 1.0


def test_the_stretches_where_a_box_lies_off_its_dancer_are_listed(tmp_path, capsys):
    """``weak_stretches`` lists the frames where a written box lies below IoU 0.5 with its own dancer's truth: the
    held box of the kept run falls behind from frame 6 (IoU 0.45, 0.33); hindsight fills the stretch and none is
    left. The ``stretches`` command prints them per clip."""
    script, runs, truth, run = _kept_clip(tmp_path)
    found = script.weak_stretches(run["boxes"], truth, run["order"], run["status"])
    assert [(s["dancer"], s["truth"], s["start"], s["end"], s["statuses"], s["on_truth"]) for s in found] == \
        [(1, 1, 6, 8, ["occluded"], None)]
    assert found[0]["median_iou"] == pytest.approx((25 / 55 + 20 / 60) / 2)
    # the truth's dancers swapped in the order: each box lies on the other's truth, wholly off its own
    swapped = script.weak_stretches(run["boxes"], truth[:, ::-1], run["order"], run["status"])
    assert [(s["dancer"], s["start"], s["end"], s["on_truth"]) for s in swapped] == [(0, 0, 12, 1), (1, 0, 12, 0)]
    clips, runs_arg = ["--clips-dir", str(tmp_path / "clips")], ["--runs", str(runs)]
    assert script.main(["stretches", *clips, *runs_arg, "--online"]) == 0
    out = capsys.readouterr().out
    assert "7_0 tango: IDF1" in out and "dancer 1 (truth 1) frames 6-7: IoU 0.39 (occluded)" in out
    assert script.main(["stretches", *clips, *runs_arg, "--keys", "7_0"]) == 0
    assert "frames" not in capsys.readouterr().out  # hindsight filled the stretch
    with pytest.raises(SystemExit, match="no kept run for 8_1"):
        script.main(["stretches", *clips, *runs_arg, "--keys", "7_0,8_1"])


def test_the_frames_hindsight_moves_off_and_onto_their_dancer_are_counted_per_status(tmp_path, capsys):
    """``hindsight_moves`` counts, per status, the dancer-frames whose box hindsight moved from IoU >= 0.5 with its
    own truth to below (off) and back (on): the kept run's held box lies below 0.5 on frames 6-7 and hindsight's
    filled stretch puts it back (2 occluded frames on); a written box pushed 30 px aside on frames 0-2 of the seen
    dancer is off on each, but frame 1 has no truth and is not counted: 2 tracked frames off. The ``harm`` command
    prints the counts, and no clip when none moved off."""
    script, runs, truth, run = _kept_clip(tmp_path)
    written = script.written_boxes(run, HindsightSettings())
    assert script.hindsight_moves(run["boxes"], written, truth, run["order"], run["status"]) == \
        {"occluded": (0, 2), "tracked": (0, 0)}
    pushed = written.copy()
    pushed[:3, 0, 0] += 30  # IoU 10/70 of a 40 px wide box
    no_truth = truth.copy()
    no_truth[1] = np.nan
    assert script.hindsight_moves(run["boxes"], pushed, no_truth, run["order"], run["status"]) == \
        {"occluded": (0, 2), "tracked": (2, 0)}
    assert script.main(["harm", "--clips-dir", str(tmp_path / "clips"), "--runs", str(runs)]) == 0
    out = capsys.readouterr().out
    assert "occluded: 0 off, 2 on" in out and "tracked: 0 off, 0 on" in out
    assert "clips whose boxes" not in out  # none moved off


def test_a_picture_draws_each_written_box_over_its_truth(tmp_path, capsys):
    """``draw_run_frames`` tiles the frames asked two a row, each written box in its dancer's colour and each truth
    box thin in green; the ``picture`` command draws them from the clip's video (after hindsight, or ``--online``)
    into a PNG, and says so; frames outside the run, a bad list and an unknown run are one-line errors."""
    import cv2

    from hdvr.pose2d.draw import dancer_colour
    from hdvr.video import VideoWriter

    script, runs, truth, run = _kept_clip(tmp_path)
    frames = {t: np.zeros((200, 320, 3), np.uint8) for t in (5, 2, 7)}
    image = script.draw_run_frames(frames, run["boxes"], truth, run["order"], run["status"], title="7_0")
    assert image.shape == (400, 640, 3)  # frames 2, 5 | 7, blank
    # frame 2 (top left): dancer 1's box (200+10, 60, 40, 100) in its colour, its truth beneath it in green
    assert tuple(image[60 + 50, 210]) == dancer_colour(1)
    assert tuple(image[60 + 50, 100]) == dancer_colour(0)
    assert tuple(image[50 + 50, 100]) == dancer_colour(0)  # dancer 0's box lies exactly on its truth
    # frame 7 (bottom left): dancer 1's held box (at frame 3's place, x 215) drawn apart from its truth (x 235)
    assert tuple(image[200 + 60 + 50, 215]) == dancer_colour(1)
    assert tuple(image[200 + 60 + 50, 235]) == script.TRUTH_COLOUR
    assert not image[200:, 320:].any()  # the tile after the last frame is left blank
    with pytest.raises(ValueError, match="no frames"):
        script.draw_run_frames({}, run["boxes"], truth, run["order"], run["status"])
    clip = tmp_path / "clips" / "synth-7" / "clip_00000"
    with VideoWriter(clip / "video.mp4", fps=30, size=(320, 200)) as writer:
        for _ in range(12):
            writer.write(np.full((200, 320, 3), 90, np.uint8))
    out = tmp_path / "pictures" / "7_0.png"
    args = ["picture", "--clips-dir", str(tmp_path / "clips"), "--runs", str(runs), "--key", "7_0"]
    assert script.main([*args, "--frames", "7,2", "--out", str(out), "--online"]) == 0
    assert "frames 2,7 of 7_0" in capsys.readouterr().out
    drawn = cv2.imread(str(out))
    assert drawn.shape == (200, 640, 3)
    assert np.abs(drawn[60 + 50, 320 + 215].astype(int) - dancer_colour(1)).max() < 60  # online: the held box
    for bad, message in ((["--frames", "12", "--out", str(out)], "must lie in 0-11"),
                         (["--frames", "a,b", "--out", str(out)], "comma-separated frame numbers"),
                         (["--frames", "1", "--out", str(tmp_path / "x.gif")], "must end in .png or .jpg")):
        with pytest.raises(SystemExit, match=message):
            script.main([*args, *bad])
    with pytest.raises(SystemExit, match="no kept run for 8_1"):
        script.main(["picture", "--clips-dir", str(tmp_path / "clips"), "--runs", str(runs), "--key", "8_1",
                     "--frames", "1", "--out", str(out)])


def test_settings_are_parsed_with_clear_errors():
    script = load_script("hindsight_runs")
    s = script.parse_settings(["keypoint_reach=0.1", "smooth_window=13"])
    assert s == HindsightSettings(keypoint_reach=0.1, smooth_window=13) and isinstance(s.smooth_window, int)
    with pytest.raises(SystemExit, match="unknown setting 'reach'"):
        script.parse_settings(["reach=0.1"])
    with pytest.raises(SystemExit, match="needs a number"):
        script.parse_settings(["keypoint_reach=wide"])
    assert script.parse_settings(["amodal_boxes=false"]) == HindsightSettings(amodal_boxes=False)
    assert script.parse_settings(["amodal_boxes=True"]).amodal_boxes is True
    assert script.parse_settings(["amodal_weights=own.pt"]).amodal_weights == "own.pt"
    with pytest.raises(SystemExit, match="needs true or false"):
        script.parse_settings(["amodal_boxes=maybe"])


def test_failing_and_summary_count_the_issue_target():
    """The script reports with compare_track_runs' ``failing`` and ``summary``, so both read the same counts."""
    script = load_script("hindsight_runs")
    ok = {"idf1": 0.95, "id_switches": 0, "hota": 0.8, "idf1_iou04": 0.97, "id_switches_iou04": 0}
    switched = dict(ok, id_switches=1)
    low = dict(ok, idf1=0.85, idf1_iou04=0.92)
    assert [script.failing(r) for r in (ok, switched, low)] == [False, True, True]
    assert script.failing(low, "idf1_iou04", "id_switches_iou04") is False
    rows = {"a": ok, "b": switched, "c": low}
    line = script.summary(rows, rows)
    assert "3 clips" in line and "2 failing" in line and "1 below 0.9" in line and "1 switches on 1 clips" in line


def test_the_clips_with_a_hidden_start_are_read_from_a_score_file(tmp_path):
    """``save --hidden-starts-of`` tracks only the clips of an earlier per-clip score file in which a dancer starts
    hidden behind another: a rule for such dancers changes no other clip. Each clip once, in the file's order; a
    file that is missing, not JSON or without ``hidden_starts`` is a one-line error."""
    script = load_script("hindsight_runs")
    row = {"idf1": 1.0, "id_switches": 0, "hota": 0.8}
    scores = {"hindsight": {}, "clips": {"2801:0:0.3": dict(row, hidden_starts=0),
                                         "2801:5:0.3": dict(row, hidden_starts=1),
                                         "2804:5:0.3": dict(row, hidden_starts=2),
                                         "2804:5:0.5": dict(row, hidden_starts=2)}}
    path = tmp_path / "scores.json"
    path.write_text(json.dumps(scores))
    assert script.hidden_start_clips(path) == [(2801, 5), (2804, 5)]
    (tmp_path / "old.json").write_text(json.dumps({"clips": {"2801:0:0.3": row}}))
    (tmp_path / "bad.json").write_text("not json")
    for name in ("old.json", "bad.json", "missing.json"):
        with pytest.raises(SystemExit, match="is no per-clip score file with hidden_starts"):
            script.hidden_start_clips(tmp_path / name)
    with pytest.raises(SystemExit, match="is no per-clip score file"):
        script.main(["save", "--clips-dir", str(tmp_path), "--runs", str(tmp_path / "runs"),
                     "--hidden-starts-of", str(tmp_path / "old.json")])


def test_a_hidden_start_is_told_from_the_truth_s_start_boxes_by_the_tracker_s_test():
    """``starts_hidden``: a dancer whose body core lies mostly inside that of one started then or before, whose box
    bottom is lower (in front), starts hidden; beside him, or in front of him, or started before him, it does not.
    ``save --hidden-starts-only`` picks such clips from their motion alone (seed 2809: its tango, swing and first
    hip-hop clip start a couple one behind the other, the others do not), the 295 of the 1,260 rendered clips of
    docs/benchmarks.md that session 68 had from its score files."""
    script = load_script("hindsight_runs")

    def truth(*boxes_by_frame):  # per dancer, its box from the given start frame on (NaN before)
        frames = 3
        out = np.full((frames, len(boxes_by_frame), 4), np.nan)
        for i, (start, box) in enumerate(boxes_by_frame):
            out[start:, i] = box
        return out

    front, behind = (100.0, 100.0, 60.0, 200.0), (105.0, 80.0, 50.0, 180.0)
    assert script.starts_hidden(truth((0, behind), (0, front)))
    assert script.starts_hidden(truth((1, behind), (0, front)))  # started later, behind one already there
    assert not script.starts_hidden(truth((0, behind), (1, front)))  # the one in front came later: seen before
    assert not script.starts_hidden(truth((0, (300.0, 80.0, 50.0, 180.0)), (0, front)))  # beside him
    assert not script.starts_hidden(truth((0, (105.0, 130.0, 50.0, 180.0)), (0, front)))  # her feet level with his
    assert script.truth_hidden_start_clips([(2809, i) for i in range(6)]) == [(2809, 0), (2809, 1), (2809, 2)]


def test_bad_runs_and_missing_truth_are_one_line_errors(tmp_path):
    script = load_script("hindsight_runs")
    with pytest.raises(SystemExit, match="no kept runs"):
        script.main(["score", "--clips-dir", str(tmp_path), "--runs", str(tmp_path)])
    runs = tmp_path / "runs"
    runs.mkdir()
    _kept_run(runs)
    with pytest.raises(SystemExit, match="no ground truth for run 7_0.npz"):
        script.main(["score", "--clips-dir", str(tmp_path / "none"), "--runs", str(runs)])
    (runs / "7_0.npz").write_bytes(b"not an npz")
    with pytest.raises(SystemExit, match="is not a kept run"):
        script.load_run(runs / "7_0.npz")


def test_a_real_clip_kept_and_scored_gives_the_benchmark_s_figures(tmp_path, capsys):
    """One rendered 1-second two-dancer clip (index 1, swing): tracked once with hindsight off by ``save`` and
    scored with the default settings by ``score``, it gives what the benchmark's own tracking, hindsight on, gives."""
    script = load_script("hindsight_runs")
    from bench_track import _seen_truth, _starts_from_truth, default_tracking_detector, track_synth_clip

    from hdvr.tracking.evaluation import evaluate_tracking

    clips, runs, out = tmp_path / "clips", tmp_path / "runs", tmp_path / "scores.json"
    assert script.main(["save", "--clips-dir", str(clips), "--seeds", "5", "--clips", "1", "--runs", str(runs),
                        "--seconds", "1"]) == 0
    assert sorted(p.name for p in runs.glob("*.npz")) == ["5_1.npz"]
    assert script.main(["score", "--clips-dir", str(clips), "--runs", str(runs), "--per-clip-json", str(out)]) == 0
    kept = json.loads(out.read_text())["clips"]["5:1:0.3"]
    clip = script.synth_clip_folder(clips, script.clip_spec(5, 1))
    truth_boxes, _ = _seen_truth(clip)
    order, starts = _starts_from_truth(truth_boxes)
    detector = default_tracking_detector()
    direct = track_synth_clip(clip, tmp_path / "work", detector, starts, hindsight=True)
    expect = evaluate_tracking(truth_boxes, direct.boxes[:, np.argsort(order)])
    assert kept["idf1"] == pytest.approx(expect.idf1) and kept["id_switches"] == expect.id_switches
    assert kept["hota"] == pytest.approx(expect.hota)
    with pytest.raises(SystemExit, match="clip indices are 0-5"):
        script.main(["save", "--clips-dir", str(clips), "--seeds", "5", "--clips", "9", "--runs", str(runs)])
    with pytest.raises(SystemExit, match="SEED_INDEX"):
        script.main(["save", "--clips-dir", str(clips), "--keys", "5-1", "--runs", str(runs)])
    with pytest.raises(SystemExit, match="--seeds .*, --keys or --hidden-starts-of"):
        script.main(["save", "--clips-dir", str(clips), "--runs", str(runs)])
    # with a detections folder: the detector's output is kept there and reused, and the runs are the same
    dets = tmp_path / "dets"
    for kept_runs in (tmp_path / "first", tmp_path / "second"):
        assert script.main(["save", "--clips-dir", str(clips), "--seeds", "5", "--clips", "1", "--runs",
                            str(kept_runs), "--detections", str(dets), "--tracker-config", "pose_extent=true"]) == 0
        assert (dets / "5_1" / "detections.npz").is_file()
        again = script.load_run(kept_runs / "5_1.npz")
        for key, value in script.load_run(runs / "5_1.npz").items():
            np.testing.assert_array_equal(again[key], value)
    # one clip again by its run's name (--keys): the same run
    assert script.main(["save", "--clips-dir", str(clips), "--keys", "5_1", "--runs", str(tmp_path / "third"),
                        "--detections", str(dets)]) == 0
    for key, value in script.load_run(runs / "5_1.npz").items():
        np.testing.assert_array_equal(script.load_run(tmp_path / "third" / "5_1.npz")[key], value)
    with pytest.raises(SystemExit, match="tracker-config"):
        script.main(["save", "--clips-dir", str(clips), "--seeds", "5", "--runs", str(runs),
                     "--tracker-config", "no_such_rule=1"])
