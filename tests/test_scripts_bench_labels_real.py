"""scripts/bench_labels_real.py: the agreement measures, and a run on a tiny stand-in for the mocap (synthetic
dancers as 'salsa' and 'indian' takes) that keeps its fits in a cache and draws its figures."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

SCRIPTS = Path(__file__).resolve().parents[1] / "scripts"
sys.path.insert(0, str(SCRIPTS))

import bench_labels_real  # noqa: E402


def test_majority_labels_give_each_part_its_most_frequent_label():
    ref = np.array([[1, 7], [1, 8], [2, 8], [1, 8]], dtype=np.int16)
    major = bench_labels_real.majority_labels(ref)
    assert (major[:, 0] == 1).all() and (major[:, 1] == 8).all()


def test_agreement_is_the_fraction_of_frames_with_the_same_label():
    from hdvr.movements.taxonomy import load_taxonomy

    tax = load_taxonomy()
    ids = np.array([[p.labels[0].id for p in tax.parts]] * 4, dtype=np.int16)
    same = bench_labels_real.agreement(ids, ids)
    assert same["mean_agreement"] == 1.0 and same["mean_macro_f1"] == 1.0
    other = ids.copy()
    other[:1, 0] = tax.parts[0].labels[1].id  # one frame of the first part differs
    scores = bench_labels_real.agreement(ids, other)
    assert scores["per_part_agreement"][tax.parts[0].name] == 0.75
    assert scores["mean_agreement"] == (15 + 0.75) / 16


def test_run_fits_once_labels_and_draws(tmp_path, mocap_standin):
    gt = mocap_standin(40)
    cache, out = tmp_path / "fits.npz", tmp_path / "labels.json"
    base = [sys.executable, str(SCRIPTS / "bench_labels_real.py"), "--gt-npz", str(gt), "--cameras-salsa", "1",
            "--cameras-indian", "1", "--workers", "1", "--fits-cache", str(cache)]
    run = subprocess.run(base + ["--out", str(out), "--figure", str(tmp_path / "bars.png"),
                                 "--score-figure", str(tmp_path / "score.png")],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "fitting 2 views" in run.stdout and cache.is_file()
    report = json.loads(out.read_text())
    scores = report["by_smoothing"]["0.2"]
    assert set(scores) == {"salsa", "indian"}
    for style in scores.values():
        assert style["views"] == 1 and style["frames"] == 40
        assert all(0 <= a <= 1 for a in style["fit"]["per_part_agreement"].values())
        assert len(style["majority"]["per_part_agreement"]) == 16
    assert (tmp_path / "bars.png").stat().st_size > 10_000 and (tmp_path / "score.png").stat().st_size > 10_000
    # again with other smoothing: the fits come from the cache, and the figures are the same for the same setting
    again = subprocess.run(base + ["--smoothing", "0.2,0.5", "--out", str(tmp_path / "again.json")],
                           capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert "fitting" not in again.stdout
    report2 = json.loads((tmp_path / "again.json").read_text())
    assert report2["by_smoothing"]["0.2"] == scores and "0.5" in report2["by_smoothing"]
    # a cache of other views is refused with one line
    other = subprocess.run(base[:6] + ["--cameras-indian", "2", "--workers", "1", "--fits-cache", str(cache)],
                           capture_output=True, text=True, timeout=300)
    assert other.returncode != 0 and "other views" in other.stderr and "Traceback" not in other.stderr


def test_agreement_within_counts_a_label_put_a_little_late():
    ref = np.array([[1], [1], [2], [2], [2], [3], [3]])
    late = np.array([[1], [1], [1], [2], [2], [2], [3]])  # every change one frame late
    assert bench_labels_real.agreement_within(ref, late, 0)[0] == 5 / 7
    assert bench_labels_real.agreement_within(ref, late, 1)[0] == 1.0
    assert bench_labels_real.agreement_within(ref, np.full_like(ref, 9), 3)[0] == 0.0
