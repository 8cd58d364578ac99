"""scripts/train_amodal_boxes.py: weights trained on kept runs and written atomically, each set cross-validated on
weights trained on the others, weights scored on other clips, bad input."""

import json

import numpy as np
import pytest
from script_loader import load_script

from hdvr.tracking.amodal import AmodalBoxRefiner


def _set(root, seed, frames=12):
    """Kept runs of two clips (seed ``seed``, indices 0 and 1) of two dancers seen throughout, with a pose each, and
    their ground truth: the whole body 10 % wider on each side than the box tracked."""
    clips, runs = root / "clips", root / "runs"
    runs.mkdir(parents=True)
    for index in (0, 1):
        boxes = np.zeros((frames, 2, 4))
        boxes[:, 0] = np.stack([100 + 3 * np.arange(frames), np.full(frames, 50.0), np.full(frames, 40.0),
                                np.full(frames, 100.0)], axis=1)
        boxes[:, 1] = [300 + 20 * index, 60, 40, 100]
        truth = boxes.copy()
        truth[..., 0] -= 10
        truth[..., 2] += 20
        keypoints = np.zeros((frames, 2, 25, 3))
        keypoints[..., 0] = boxes[..., None, 0] + 20
        keypoints[..., 1] = boxes[..., None, 1] + np.linspace(5, 95, 25)
        keypoints[..., :15, 2] = 0.9
        status = np.full((frames, 2), "tracked")
        np.savez(runs / f"{seed}_{index}.npz", boxes=boxes, status=status, keypoints=keypoints, order=np.array([0, 1]),
                 hidden_starts=np.zeros((0, 3), int), width=640.0)
        clip = clips / f"synth-{seed}" / f"clip_{index:05d}"
        clip.mkdir(parents=True)
        np.savez(clip / "gt.npz", boxes=np.transpose(truth, (1, 0, 2)), keypoints2d=np.zeros((2, frames, 25, 2)),
                 visibility=np.full((2, frames, 25), 2))
    return f"{clips}:{runs}"


def test_train_cross_validate_and_score(tmp_path, capsys):
    script = load_script("train_amodal_boxes")
    first, second = _set(tmp_path / "a", 7), _set(tmp_path / "b", 8)
    small = ["--hidden", "16", "--epochs", "300", "--members", "2", "--dropout", "0"]
    out = tmp_path / "weights" / "amodal.pt"
    assert script.main(["train", "--data", first, "--data", second, "--out", str(out)] + small) == 0
    refiner = AmodalBoxRefiner.load(out)
    assert len(refiner.networks) == 2 and refiner.payload["hidden"] == 16 and refiner.payload["rows"] == 2 * 4 * 2 * 12
    assert refiner.payload["mirror"] is True  # the rows and their mirror images
    assert [s.split(" (")[1] for s in refiner.payload["trained_on"]] == ["2 clips)", "2 clips)"]
    assert not list(out.parent.glob("*.tmp"))  # written atomically, nothing left beside it
    printed = capsys.readouterr().out
    assert "training on 96 dancer-frames of 4 clips and their mirror images" in printed and "network 2/2 epoch 300/300" in printed
    report = tmp_path / "cv.json"
    assert script.main(["cross-validate", "--data", first, "--data", second, "--json", str(report)] + small) == 0
    summaries = json.loads(report.read_text())["summaries"]
    assert [s["set"] for s in summaries] == [first, second]
    assert all(s["clips"] == 2 and s["failing_before"] == s["failing_after"] == 0 for s in summaries)
    # the boxes tracked are narrower than the truth; weights trained on the other set widen them
    assert all(s["hota_before"] + 0.1 < s["hota_after"] for s in summaries)
    assert script.main(["score", "--weights", str(out), "--data", first]) == 0
    assert "2 clips, failing 0 -> 0" in capsys.readouterr().out


def test_bad_input_is_a_one_line_error(tmp_path):
    script = load_script("train_amodal_boxes")
    with pytest.raises(SystemExit, match="need CLIPS:RUNS folders"):
        script.main(["train", "--data", f"{tmp_path}/none:{tmp_path}/none", "--out", str(tmp_path / "w.pt")])
    (tmp_path / "clips").mkdir()
    (tmp_path / "runs").mkdir()
    with pytest.raises(SystemExit, match="no kept runs"):
        script.main(["train", "--data", f"{tmp_path}/clips:{tmp_path}/runs"])
    data = _set(tmp_path / "a", 7)
    with pytest.raises(SystemExit, match="train needs --out"):
        script.main(["train", "--data", data])
    with pytest.raises(SystemExit, match="two --data sets"):
        script.main(["cross-validate", "--data", data])
    (tmp_path / "a" / "clips" / "synth-7" / "clip_00001" / "gt.npz").unlink()
    with pytest.raises(SystemExit, match="no ground truth for run 7_1.npz"):
        script.main(["train", "--data", data, "--out", str(tmp_path / "w.pt")])
