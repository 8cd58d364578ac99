"""scripts/compare_track_runs.py, bench_track's --tracker-config and its miss-cause table."""

import json

import pytest
from script_loader import SCRIPTS, load_script


def _run_file(path, clips):
    path.write_text(json.dumps({"tracker_config": "", "clips": clips}))
    return path


def _clip(idf1, switches, genre="ballet"):
    return {"genre": genre, "dancers": 4, "idf1": idf1, "id_switches": switches, "hidden_starts": 0}


def test_changed_clips_and_summaries(tmp_path, capsys):
    compare = load_script("compare_track_runs")
    before = _run_file(tmp_path / "a.json", {"503:5:0.3": _clip(0.633, 0), "308:3:0.3": _clip(0.883, 0, "flamenco"),
                                             "301:4:0.3": _clip(0.885, 1, "hip_hop"), "201:0:0.3": _clip(1.0, 0)})
    after = _run_file(tmp_path / "b.json", {"503:5:0.3": _clip(0.723, 0), "308:3:0.3": _clip(0.8832, 0, "flamenco"),
                                            "301:4:0.3": _clip(0.885, 0, "hip_hop"), "999:0:0.3": _clip(0.5, 3)})
    changed = compare.changed_clips(compare.load_clips(before), compare.load_clips(after))
    assert [k for k, _, _ in changed] == ["503:5:0.3", "301:4:0.3"]  # 308 moved by less than the tolerance
    assert compare.main([str(before), str(after)]) == 0
    out = capsys.readouterr().out
    assert "503:5:0.3 ballet: IDF1 0.633 -> 0.723, switches 0 -> 0" in out
    assert "3 clips, mean IDF1 0.8003, 3 below 0.9, 1 switches on 1 clips, 3 failing\n" in out  # clips both hold


def test_summary_adds_hota_and_the_failing_clips_at_iou_04_when_the_runs_have_them():
    """Runs written since session 47 also hold each clip's HOTA and its IDF1 and switches at IoU 0.4: the summary
    then gives the mean HOTA and the failing clips (IDF1 < 0.9 or a switch) at IoU 0.4 too."""
    compare = load_script("compare_track_runs")
    clips = {"1:0:0.3": {**_clip(0.85, 0), "hota": 0.7, "idf1_iou04": 0.95, "id_switches_iou04": 0},
             "2:0:0.3": {**_clip(1.0, 1), "hota": 0.9, "idf1_iou04": 1.0, "id_switches_iou04": 1}}
    assert compare.summary(clips, list(clips)) == ("2 clips, mean IDF1 0.9250, 1 below 0.9, 1 switches on 1 clips, "
                                                   "2 failing; mean HOTA 0.8000, 1 failing at IoU 0.4")
    del clips["2:0:0.3"]["hota"]  # an older run's clip: no HOTA part
    assert compare.summary(clips, list(clips)).endswith("2 failing")


def test_a_file_that_is_not_a_run_is_a_one_line_error(tmp_path):
    compare = load_script("compare_track_runs")
    bad = tmp_path / "bad.json"
    bad.write_text("[1, 2]")
    with pytest.raises(SystemExit, match="is not a bench_track --per-clip-json file"):
        compare.load_clips(bad)


def test_tracker_config_overrides_take_the_field_types(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPTS))  # bench_track imports its neighbour benchdoc
    bench = load_script("bench_track")
    config = bench.parse_tracker_config("reid_from_holder=false, reid_margin=0.25,max_occlusion_frames=90")
    assert config.reid_from_holder is False and config.reid_margin == 0.25 and config.max_occlusion_frames == 90
    assert bench.parse_tracker_config("") == bench.MultiTrackerConfig()
    # a test that may be None takes a number or none; a plain number field does not take none
    assert bench.parse_tracker_config("own_box_max_shift=none").own_box_max_shift is None
    assert bench.parse_tracker_config("own_box_max_shift=0.3").own_box_max_shift == 0.3
    # a pair of numbers as a:b
    assert bench.parse_tracker_config("pixel_margin=0.45:0.3").pixel_margin == (0.45, 0.3)
    # a mode by its name, one the config knows
    assert bench.parse_tracker_config("keep_hidden_sides=written").keep_hidden_sides == "written"
    for bad in ("no_such_rule=1", "reid_from_holder", "reid_from_holder=maybe", "reid_margin=none",
                "max_occlusion_frames=many", "pixel_margin=0.45", "pixel_margin=0.4:0.3:0.2", "pixel_margin=a:b",
                "keep_hidden_sides=true"):
        with pytest.raises(SystemExit, match="--tracker-config"):
            bench.parse_tracker_config(bad)


def test_miss_cause_table_gives_each_cause_its_share_of_all_dancer_frames(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPTS))
    bench = load_script("bench_track")
    counts = {("visible", "matched"): 6, ("visible", "extent"): 2, ("partly", "other_dancer"): 1,
              ("hidden", "no_box"): 1}
    lines = bench._miss_cause_table(0.3, counts)
    assert "10 dancer-frames" in lines[0]
    rows = {line.split(" | ")[0].strip("| "): line for line in lines if line.startswith("| ") and "---" not in line}
    assert rows["visible"] == "| visible | 8 | 60.00 | 0.00 | 20.00 | 0.00 | 0.00 |"
    assert rows["partly"] == "| partly | 1 | 0.00 | 10.00 | 0.00 | 0.00 | 0.00 |"
    assert rows["hidden"] == "| hidden | 1 | 0.00 | 0.00 | 0.00 | 0.00 | 10.00 |"
    assert bench._miss_cause_table(0.3, {}) == []


def test_synth_section_renders_a_missing_clip_where_it_keeps_it_and_scores_it(monkeypatch, tmp_path):
    """The synth section renders a clip it does not find (here one 1-second swing couple, seed 5) into its
    ``synth-SEED/clip_0000I`` folder (``synth_clip_folder``), tracks it and writes its row and per-clip figures."""
    monkeypatch.syspath_prepend(str(SCRIPTS))
    bench = load_script("bench_track")
    from hdvr.pose2d.models import default_pose_model

    per_clip = {}
    lines = bench.synth_section(bench.TrackingModel(default_pose_model()), tmp_path / "work", seconds=1.0, seeds=(5,),
                                thresholds=(0.3,), clips=(("swing", 2),), clips_dir=tmp_path / "clips",
                                per_clip=per_clip)
    from hdvr.synth.groundtruth import ClipSpec

    clip = bench.synth_clip_folder(tmp_path / "clips", ClipSpec(0, 5, "swing", 2, 1.0))
    assert clip == tmp_path / "clips" / "synth-5" / "clip_00000"
    assert (clip / "gt.npz").is_file() and (clip / "video.mp4").is_file()
    assert any(line.startswith("| 5 | clip_00000 swing | 2 | 0.3 |") for line in lines), lines
    assert set(per_clip) == {"5:0:0.3"} and 0.0 <= per_clip["5:0:0.3"]["idf1"] <= 1.0
