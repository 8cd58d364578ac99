import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import plot_lifter_runs  # noqa: E402


def _report(path: Path, fit_terms: list[float], salsa: float, flip: bool = False) -> Path:
    """A bench_lifter.py report with the keys the plot reads: 800 training frames, a window every 2, batch 100."""
    rows = [{"split": "test_salsa", "method": plot_lifter_runs.FIT, "p_mpjpe_mm": 47.0},
            {"split": "test_salsa", "method": "lifter (trained on the fit)", "p_mpjpe_mm": salsa},
            {"split": "test_indian", "method": "lifter (trained on the fit)", "p_mpjpe_mm": 2 * salsa}]
    if flip:
        rows.append({"split": "test_salsa", "method": "lifter, flip test", "p_mpjpe_mm": salsa - 1})
    path.write_text(json.dumps({"train": {"window_stride": 2, "batch_size": 100}, "train_frames": 800,
                                "history": [{"epoch": e, "fit": f} for e, f in enumerate(fit_terms)],
                                "rows": rows}))
    return path


def test_runs_are_read_with_their_steps_and_scores_and_the_plot_is_written(tmp_path):
    plain = _report(tmp_path / "plain.json", [900.0, 500.0], 60.0)
    flipped = _report(tmp_path / "flipped.json", [800.0, 400.0, 300.0], 55.0, flip=True)
    run = plot_lifter_runs.load_run(f"{flipped}:CPU, centred")
    assert run["label"] == "CPU, centred" and run["steps_per_epoch"] == 4  # 800 / 2 windows, 100 a step
    assert plot_lifter_runs.load_run(str(plain))["label"] == "plain"
    assert plot_lifter_runs.lifter_method(run["report"]) == "lifter, flip test"
    assert plot_lifter_runs.score(run["report"], "test_salsa", "lifter, flip test") == 54.0
    assert plot_lifter_runs.score(run["report"], "test_indian", "lifter, flip test") is None
    out = tmp_path / "img" / "runs.png"
    out.parent.mkdir()
    assert plot_lifter_runs.main([str(plain), f"{flipped}:flipped", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_file_that_is_no_report_is_refused_in_one_line(tmp_path):
    (tmp_path / "other.json").write_text(json.dumps({"clips": {}}))
    with pytest.raises(SystemExit, match="not a readable bench_lifter.py report"):
        plot_lifter_runs.load_run(str(tmp_path / "other.json"))
    with pytest.raises(SystemExit, match="not a readable"):
        plot_lifter_runs.load_run(str(tmp_path / "missing.json"))
