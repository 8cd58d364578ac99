import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import plot_detector_bound  # noqa: E402


def _run(path: Path, threshold: str, scores: dict) -> Path:
    """A bench_track --per-clip-json file with clips "seed:index:threshold" -> (idf1, switches, hidden starts)."""
    clips = {f"{key}:{threshold}": {"genre": "tango", "dancers": 2, "idf1": idf1, "id_switches": switches,
                                    "hidden_starts": hidden, "fewest_frames_shown": 10}
             for key, (idf1, switches, hidden) in scores.items()}
    path.write_text(json.dumps({"tracker_config": "", "hindsight": True, "clips": clips}))
    return path


def test_runs_are_matched_by_clip_whatever_their_threshold_and_the_plot_is_written(tmp_path, capsys):
    yolo = _run(tmp_path / "yolo.json", "0.3", {"7:0": (0.80, 0, 1), "7:1": (1.0, 1, 0), "7:2": (0.95, 0, 0)})
    truth = _run(tmp_path / "truth.json", "0", {"7:0": (0.99, 0, 1), "7:1": (1.0, 0, 0), "8:0": (0.5, 0, 0)})
    label, clips = plot_detector_bound.load_run(f"perfect={truth}")
    assert label == "perfect" and set(clips) == {"7:0", "7:1", "8:0"}
    assert [plot_detector_bound.fails(clips[k]) for k in ("7:0", "7:1", "8:0")] == [False, False, True]
    out = tmp_path / "img" / "bound.png"
    assert plot_detector_bound.main(["--run", f"YOLO={yolo}", "--run", f"perfect={truth}", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and not list(out.parent.glob("*.tmp.png"))


def test_bad_runs_are_refused_with_a_clear_message(tmp_path):
    yolo = _run(tmp_path / "yolo.json", "0.3", {"7:0": (0.8, 0, 1)})
    other = _run(tmp_path / "other.json", "0", {"9:0": (0.8, 0, 1)})
    with pytest.raises(SystemExit, match="LABEL=FILE"):
        plot_detector_bound.load_run(str(yolo))
    with pytest.raises(SystemExit, match="at least two"):
        plot_detector_bound.main(["--run", f"YOLO={yolo}"])
    with pytest.raises(SystemExit, match="no clip in both"):
        plot_detector_bound.main(["--run", f"YOLO={yolo}", "--run", f"perfect={other}", "--out",
                                  str(tmp_path / "x.png")])
    (tmp_path / "bad.json").write_text("{}")
    with pytest.raises(SystemExit, match="not a bench_track"):
        plot_detector_bound.load_run(f"x={tmp_path / 'bad.json'}")
