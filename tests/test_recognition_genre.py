"""Genre recognition as shipped: the checkpoint loads safely, recognises held-out synthetic dancers well above
chance, resamples any frame rate, and a missing or damaged checkpoint is a one-line error (or 'unavailable')."""

import numpy as np
import pytest
import torch

from hdvr.cli import main
from hdvr.errors import HDVRError
from hdvr.pipeline import analyse_video, load_genre_recogniser, video_genre
from hdvr.recognition.genre import GenreRecogniser, default_checkpoint, perturb_motion, resample_labels
from hdvr.recognition.genre_data import evaluate, synthetic_sequences
from hdvr.synth.genres import GENRES

pytestmark = pytest.mark.usefixtures("one_torch_thread")

#: Measured on these 45 clips (seed 4242, five per genre, 6 s, 1-2 dancers: 76 dancers) with the shipped
#: checkpoint, exact 3D; the assertion keeps a margin. Chance is 1/9 = 11 %.
HELD_OUT_SEED, HELD_OUT_CLIPS = 4242, 45
MEASURED_ACCURACY = 0.474  # 36 of 76 dancers
MIN_ACCURACY = 0.33


@pytest.fixture(scope="module")
def recogniser():
    if not default_checkpoint().is_file():
        pytest.fail(f"the shipped checkpoint {default_checkpoint()} is missing (scripts/train_recognisers.py)")
    return GenreRecogniser.load()


def test_shipped_checkpoint_is_plain_tensors_and_predicts_probabilities(recogniser):
    payload = torch.load(default_checkpoint(), map_location="cpu", weights_only=True)
    assert set(payload) >= {"genre", "genre_shape", "meta"} and payload["meta"]["genres"] == list(GENRES)
    assert default_checkpoint().stat().st_size < 3_000_000
    rng = np.random.default_rng(0)
    labels = rng.random((95, 154)) < 0.1
    probs = recogniser.predict_labels(labels, fps=25.0)
    assert probs.shape == (9,) and np.all(probs >= 0) and probs.sum() == pytest.approx(1.0, abs=1e-6)
    d = recogniser.as_dict(probs)
    assert d["top"] in GENRES and set(d["probabilities"]) == set(GENRES)


def test_held_out_synthetic_dancers_are_recognised_well_above_chance(recogniser):
    seqs = synthetic_sequences(HELD_OUT_SEED, HELD_OUT_CLIPS, 6.0, levels=(0.0,))
    res = evaluate(recogniser.model, seqs, len(GENRES), recogniser.window)
    assert res["sequences"] >= HELD_OUT_CLIPS
    assert res["accuracy"] >= MIN_ACCURACY, (MEASURED_ACCURACY, res)


def test_resampling_keeps_time_and_label_mass():
    x = np.zeros((60, 3), dtype=bool)
    x[:30, 0] = True
    x[30:, 1] = True
    down = resample_labels(x, 30.0, 15.0)
    assert down.shape == (30, 3)
    np.testing.assert_allclose(down[:15, 0], 1.0)
    np.testing.assert_allclose(down[15:, 1], 1.0)
    up = resample_labels(x, 10.0, 15.0)
    assert up.shape == (90, 3) and up[:45, 0].all() and up[45:, 1].all()
    np.testing.assert_allclose(resample_labels(x, 15.0, 15.0), x.astype(np.float32))
    with pytest.raises(HDVRError, match="fps"):
        resample_labels(x, 0.0)


def test_perturbation_is_deterministic_and_scales_with_level():
    from hdvr.skeleton import Skeleton
    from hdvr.synth.groundtruth import clip_spec, generate_motion

    dancer = generate_motion(clip_spec(0, 3, ("tango",), (1, 1), 2.0))[0][0]
    sk = Skeleton()
    sk.set_bone_lengths(dancer.bones)
    exact = perturb_motion(dancer.qpos, sk, np.random.default_rng(1), 30.0, 0.0)
    np.testing.assert_allclose(exact, dancer.keypoints, atol=1e-6)
    a = perturb_motion(dancer.qpos, sk, np.random.default_rng(1), 30.0, 0.5)
    b = perturb_motion(dancer.qpos, sk, np.random.default_rng(1), 30.0, 0.5)
    c = perturb_motion(dancer.qpos, sk, np.random.default_rng(1), 30.0, 1.0)
    np.testing.assert_array_equal(a, b)
    err = [np.linalg.norm(k - dancer.keypoints, axis=-1).mean() for k in (a, c)]
    assert 0.02 < err[0] < err[1] < 0.5
    np.testing.assert_allclose(sk.bone_lengths, dancer.bones)  # restored


def test_missing_or_corrupt_checkpoint_is_a_one_line_error(tmp_path, capsys):
    missing = tmp_path / "nothing.pt"
    with pytest.raises(HDVRError, match="not found"):
        GenreRecogniser.load(missing)
    corrupt = tmp_path / "corrupt.pt"
    corrupt.write_bytes(b"this is not a checkpoint" * 10)
    with pytest.raises(HDVRError, match="cannot read recogniser checkpoint") as info:
        GenreRecogniser.load(corrupt)
    assert "\n" not in str(info.value)
    tensor_only = tmp_path / "tensor.pt"
    torch.save(torch.zeros(3), tensor_only)
    with pytest.raises(HDVRError, match="cannot read recogniser checkpoint"):
        GenreRecogniser.load(tensor_only)
    # an explicit bad checkpoint fails before any video work; the CLI prints one line and exits 2
    with pytest.raises(HDVRError):
        analyse_video(tmp_path / "no-video.mp4", tmp_path / "out", recogniser=corrupt)
    assert main(["run", str(tmp_path / "no-video.mp4"), "--out", str(tmp_path / "out"), "--dancers", "1",
                 "--detector", "none", "--recogniser", str(missing)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hdvr: error:") and "recogniser checkpoint not found" in err and "\n" not in err


def test_absent_default_checkpoint_turns_genre_off_with_a_reason(monkeypatch, tmp_path):
    import hdvr.recognition.genre as genre

    monkeypatch.setattr(genre, "default_checkpoint", lambda: tmp_path / "absent.pt")
    model, reason = load_genre_recogniser("default")
    assert model is None and "not found" in reason
    assert video_genre([], model, reason) == {"available": False, "reason": reason}
    assert load_genre_recogniser(None) == (None, "genre recognition is off")


@pytest.mark.slow
def test_training_script_is_deterministic_and_writes_a_loadable_checkpoint(tmp_path):
    import importlib.util
    import json
    from pathlib import Path

    script = Path(__file__).resolve().parents[1] / "scripts" / "train_recognisers.py"
    spec = importlib.util.spec_from_file_location("train_recognisers", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for run in ("a", "b"):
        assert module.main(["--train-clips", "18", "--eval-clips", "9", "--fitted-clips", "1", "--epochs", "2",
                            "--seconds", "5", "--out", str(tmp_path / f"{run}.pt"),
                            "--report", str(tmp_path / f"{run}.json"), "--figure", str(tmp_path / f"{run}.png")]) == 0
    a = torch.load(tmp_path / "a.pt", weights_only=True)
    b = torch.load(tmp_path / "b.pt", weights_only=True)
    assert all(torch.equal(a["genre"][k], b["genre"][k]) for k in a["genre"])
    report = json.loads((tmp_path / "a.json").read_text())
    assert set(report["results"]) == {"held_out_exact_3d", "held_out_disturbed_3d", "held_out_fitted_3d"}
    assert np.array(report["results"]["held_out_exact_3d"]["confusion"]).shape == (9, 9)
    assert GenreRecogniser.load(tmp_path / "a.pt").genres == list(GENRES)
