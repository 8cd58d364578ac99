"""scripts/plot_track_bench.py: reads the synthetic tracking tables of the benchmark markdown and plots them."""

import importlib.util
import json
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "plot_track_bench.py"

MARKDOWN = """# Benchmarks

### Synthetic dancers with keypoints, seeds 7, 11 and 23 (session 9, final code)

| seed | clip | dancers | detector threshold | IDF1 | MOTA | HOTA | ID switches | pose per dancer |
|---|---|---|---|---|---|---|---|---|
| 7 | clip_00000 tango | 2 | 0.3 | 1.000 | 1.000 | 0.742 | 0 | 1.00 / 1.00 |
| 7 | clip_00005 ballet | 4 | 0.3 | 0.846 | -0.121 | 0.645 | 2 | 0.95 / 1.00 / 0.00 / 0.30 |

### Synthetic dancers, held-out seeds 97, 101, 113 and 127 (re-run)

| seed | clip | dancers | detector threshold | IDF1 | MOTA | HOTA | ID switches | pose per dancer |
|---|---|---|---|---|---|---|---|---|
| 97 | clip_00003 flamenco | 3 | 0.3 | 0.828 | 0.656 | 0.698 | 0 | 0.20 / 1.00 / 1.00 |

### Synthetic dancers, seeds 7-139 (session 12)

| seed | clip | dancers | detector threshold | IDF1 | MOTA | HOTA | ID switches | pose per dancer | IDF1 / switches at IoU 0.4 |
|---|---|---|---|---|---|---|---|---|---|
| 127 | clip_00000 tango | 2 | 0.3 | 0.800 | 0.600 | 0.600 | 0 | 1.00 / 1.00 | 1.000 / 0 |

### Something else

| 5 | clip_00001 swing | 2 | 0.3 | 0.100 | 0.100 | 0.100 | 9 | not read |
"""


def load_script():
    spec = importlib.util.spec_from_file_location("plot_track_bench", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_rows_are_read_from_the_named_section_only():
    module = load_script()
    rows = module.read_rows(MARKDOWN, "### Synthetic dancers with keypoints, seeds 7")
    assert [(r["seed"], r["genre"], r["dancers"], r["idf1"], r["switches"]) for r in rows] == \
        [(7, "tango", 2, 1.0, 0), (7, "ballet", 4, 0.846, 2)]


def test_the_idf1_at_iou_04_is_read_where_the_table_has_it():
    module = load_script()
    [row] = module.read_rows(MARKDOWN, "### Synthetic dancers, seeds 7-139 (session 12)")
    assert (row["seed"], row["idf1"], row["idf1_loose"]) == (127, 0.8, 1.0)
    assert all(r["idf1_loose"] is None for r in module.read_rows(MARKDOWN, "### Synthetic dancers with keypoints"))


def test_plot_is_written(tmp_path):
    module = load_script()
    markdown = tmp_path / "bench.md"
    markdown.write_text(MARKDOWN)
    out = tmp_path / "img" / "idf1.png"
    sections = ["### Synthetic dancers with keypoints, seeds 7", "### Synthetic dancers, held-out seeds",
                "### Synthetic dancers, seeds 7-139 (session 12)"]
    assert module.main(["--markdown", str(markdown), "--out", str(out), "--sections", *sections]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in out.parent.iterdir() if p.name.startswith(".")]  # no temporary file left


def test_missing_section_is_a_one_line_error(tmp_path):
    module = load_script()
    markdown = tmp_path / "bench.md"
    markdown.write_text("# Benchmarks\n")
    with pytest.raises(SystemExit, match="no section"):
        module.main(["--markdown", str(markdown), "--out", str(tmp_path / "x.png")])


PER_CLIP = {"hindsight": {}, "clips": {
    "2801:0:0.3": {"genre": "tango", "dancers": 2, "idf1": 1.0, "id_switches": 0, "hidden_starts": 0, "mota": 1.0,
                   "hota": 0.88, "idf1_iou04": 1.0, "id_switches_iou04": 0},
    "2839:5:0.3": {"genre": "ballet", "dancers": 4, "idf1": 0.621, "id_switches": 3, "hidden_starts": 1,
                   "mota": 0.4, "hota": 0.5, "idf1_iou04": 0.771, "id_switches_iou04": 4},
    "2840:2:0.3": {"genre": "hip_hop", "dancers": 3, "idf1": 0.95, "id_switches": 0}}}  # older files: fewer keys


def test_per_clip_json_rows_are_read_as_the_tables_rows(tmp_path):
    module = load_script()
    path = tmp_path / "run.json"
    path.write_text(json.dumps(PER_CLIP))
    rows = module.read_json_rows(path)
    assert [(r["seed"], r["clip"], r["genre"], r["dancers"], r["idf1"], r["switches"], r["idf1_loose"], r["hidden"])
            for r in rows] == [(2801, "clip_00000", "tango", 2, 1.0, 0, 1.0, 0),
                               (2839, "clip_00005", "ballet", 4, 0.621, 3, 0.771, 1),
                               (2840, "clip_00002", "hip_hop", 3, 0.95, 0, None, None)]


def test_a_per_clip_json_is_plotted_by_hidden_starts_and_bad_files_are_one_line_errors(tmp_path):
    module = load_script()
    clips = dict(PER_CLIP["clips"])
    del clips["2840:2:0.3"]  # colouring by hidden starts needs the column in every clip
    path = tmp_path / "run.json"
    path.write_text(json.dumps({"clips": clips}))
    out = tmp_path / "img" / "fresh.png"
    assert module.main(["--per-clip-json", str(path), "--out", str(out), "--title", "Fresh clips"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(SystemExit, match="not a per-clip JSON file"):
        module.main(["--per-clip-json", str(bad), "--out", str(out)])
    bad.write_text(json.dumps({"clips": {}}))
    with pytest.raises(SystemExit, match="holds no clip"):
        module.main(["--per-clip-json", str(bad), "--out", str(out)])
    old = tmp_path / "old.json"  # one clip without hidden_starts
    old.write_text(json.dumps(PER_CLIP))
    with pytest.raises(SystemExit, match="hidden_starts in every clip"):
        module.main(["--per-clip-json", str(path), str(old), "--out", str(out)])
