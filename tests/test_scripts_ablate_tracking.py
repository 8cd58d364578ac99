"""scripts/ablate_tracking.py: the variants are valid settings, and offline variants are scored on kept runs into a
table, JSON and a plot."""

import json

import numpy as np
import pytest
from script_loader import load_script

from test_scripts_hindsight_runs import _clip_with_truth, _kept_run


def test_every_variant_names_real_settings():
    script = load_script("ablate_tracking")
    bench = load_script("bench_track")
    hindsight = load_script("hindsight_runs")
    assert len({v.name for v in script.VARIANTS}) == len(script.VARIANTS)
    for v in script.VARIANTS:
        bench.parse_tracker_config(v.tracker)  # SystemExit on a field MultiTrackerConfig does not have
        hindsight.parse_settings(list(v.hindsight_settings))
    assert script.VARIANTS_BY_NAME["no_cone_patches"].online and not script.VARIANTS_BY_NAME["no_hindsight"].online
    assert [v.name for v in script.parse_variants("no_zoom,full")] == ["full", "no_zoom"]
    with pytest.raises(SystemExit, match="unknown variant.*no_such"):
        script.parse_variants("no_such")


def test_offline_variants_are_scored_on_the_kept_full_runs(tmp_path, capsys):
    script = load_script("ablate_tracking")
    runs = tmp_path / "work" / "runs-full"
    runs.mkdir(parents=True)
    for index in range(6):  # every clip of seed 7 kept, so that nothing is tracked
        truth = _kept_run(runs, f"7_{index}")
        _clip_with_truth(tmp_path / "clips", truth, index=index)
    out_md, out_json, plot = tmp_path / "a.md", tmp_path / "a.json", tmp_path / "a.png"
    assert script.main(["--clips-dir", str(tmp_path / "clips"), "--seeds", "7", "--work", str(tmp_path / "work"),
                        "--variants", "no_hindsight,no_amodal_boxes", "--procs", "1", "--out-md", str(out_md),
                        "--out-json", str(out_json), "--plot", str(plot)]) == 0
    result = json.loads(out_json.read_text())
    full, raw = result["summaries"]["full"], result["summaries"]["no_hindsight"]
    assert full["clips"] == 6 and full["mean_idf1"] == 1.0 and full["failing"] == 0
    # the kept boxes leave the occluded dancer behind where hindsight fills the stretch
    assert raw["mean_idf1"] < 1.0 and raw["down"] == 6 and raw["up"] == 0
    assert result["summaries"]["no_amodal_boxes"]["mean_idf1"] == 1.0  # no keypoints: the refiner leaves it be
    table = out_md.read_text()
    assert table in capsys.readouterr().out  # printed too
    assert table.count("\n") == 5 and "| `full` |" in table and "6 / 0" not in table and "0 / 6" in table
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_seeds_are_a_one_line_error(tmp_path):
    script = load_script("ablate_tracking")
    with pytest.raises(SystemExit, match="--seeds takes comma-separated integers"):
        script.main(["--clips-dir", str(tmp_path), "--seeds", "7,x", "--work", str(tmp_path / "w")])
