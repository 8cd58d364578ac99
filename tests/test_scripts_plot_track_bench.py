"""scripts/plot_track_bench.py: reads the synthetic tracking tables of the benchmark markdown and plots them."""

import importlib.util
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
