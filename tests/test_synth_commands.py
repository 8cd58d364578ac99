import json

import pytest

from hdvr.cli import main


def test_synth_command_resumes_and_indexes(tmp_path, capsys):
    out = tmp_path / "ds"
    assert main(["synth", "--out", str(out), "--clips", "2", "--dancers", "1-2", "--seconds", "1", "--seed", "4",
                 "--no-render"]) == 0
    first = (out / "clip_00001" / "gt.npz").stat().st_mtime_ns
    assert main(["synth", "--out", str(out), "--clips", "3", "--dancers", "1-2", "--seconds", "1", "--seed", "4",
                 "--no-render"]) == 0
    assert (out / "clip_00001" / "gt.npz").stat().st_mtime_ns == first  # finished clips are not redone
    index = json.loads((out / "index.json").read_text())
    assert [c["clip"] for c in index["clips"]] == ["clip_00000", "clip_00001", "clip_00002"]


@pytest.mark.parametrize("args, message", [
    (["--clips", "0"], "--clips"), (["--dancers", "2-9"], "--dancers"), (["--genres", "polka"], "unknown genre"),
    (["--size", "641x480"], "--size"), (["--seconds", "0"], "--seconds")])
def test_synth_bad_options(tmp_path, capsys, args, message):
    assert main(["synth", "--out", str(tmp_path)] + args) == 2
    assert message in capsys.readouterr().err


def test_label_command_on_synthetic_gt(tmp_path, capsys):
    out = tmp_path / "ds"
    main(["synth", "--out", str(out), "--clips", "1", "--dancers", "1", "--seconds", "2", "--no-render"])
    labels, score = tmp_path / "labels.json", tmp_path / "score.png"
    assert main(["label", str(out / "clip_00000" / "gt.npz"), "--out", str(labels), "--score", str(score)]) == 0
    doc = json.loads(labels.read_text())
    assert doc["frames"] == 60 and {s["part"] for s in doc["segments"]} >= {"head", "left_foot"}
    assert score.stat().st_size > 10_000
    assert main(["label", str(tmp_path / "missing.bvh"), "--out", str(labels)]) == 2


@pytest.mark.shared_data
def test_label_command_on_salsa(shared_data, tmp_path):
    labels = tmp_path / "salsa.json"
    assert main(["label", str(shared_data / "cmu-salsa" / "60_02_scaled.bvh"), "--out", str(labels)]) == 0
    doc = json.loads(labels.read_text())
    assert doc["fps"] == 30.0 and len(doc["segments"]) > 100


def test_label_command_on_a_3d_result(tmp_path):
    import numpy as np

    from hdvr.io.result3d import Result3D, save_result3d
    from hdvr.synth.choreography import ChoreographyGenerator

    chor = ChoreographyGenerator().generate("belly_dance", 3, np.random.default_rng(1))
    T = chor.qpos.shape[0]
    result = Result3D(keypoints3d=chor.keypoints, qpos=chor.qpos, focal=np.full(T, 500.0),
                      principal_point=np.tile([320.0, 240.0], (T, 1)),
                      bone_lengths=ChoreographyGenerator().sk.bone_lengths, reprojection_error_px=np.zeros(T))
    save_result3d(tmp_path / "fit.npz", result)
    out = tmp_path / "labels.json"
    assert main(["label", str(tmp_path / "fit.npz"), "--out", str(out), "--smoothing", "0.1"]) == 0
    segs = json.loads(out.read_text())["segments"]
    from hdvr.movements.labeller import MovementLabeller
    expected = MovementLabeller().label(chor.keypoints, 30.0).segments()
    assert [(s["part"], s["label"], s["start"]) for s in segs] == [(s["part"], s["label"], s["start"]) for s in expected]
