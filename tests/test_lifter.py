"""The lifter: receptive field, shapes, loss terms, flip augmentation, training reduces error, checkpoints."""

import numpy as np
import pytest
import torch

from hdvr.camera import orbit_camera, project
from hdvr.errors import HDVRError
from hdvr.lifter import losses
from hdvr.lifter.data import FLIP_INDEX, LiftingClip, WindowDataset, normalise_keypoints
from hdvr.lifter.model import LifterConfig, TemporalLifter
from hdvr.lifter.train import TrainConfig, lift_sequence, load_checkpoint, save_checkpoint, train_lifter
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import Skeleton

SMALL = LifterConfig(filter_widths=(3, 3), channels=64, dropout=0.0)


pytestmark = pytest.mark.usefixtures("one_torch_thread")


def test_receptive_field_and_shapes():
    assert LifterConfig().receptive_field == 243
    model = TemporalLifter(SMALL).eval()
    out = model(torch.zeros(2, 9 + 9, 25, 3))
    assert out.shape == (2, 10, 25, 3)
    assert torch.all(out[..., 2] > 0)  # in front of the camera
    with pytest.raises(ValueError):
        model(torch.zeros(1, 5, 25, 3))


def test_flip_index_swaps_sides():
    assert BODY25_NAMES[FLIP_INDEX[BODY25_NAMES.index("left_wrist")]] == "right_wrist"
    assert BODY25_NAMES[FLIP_INDEX[BODY25_NAMES.index("nose")]] == "nose"
    assert sorted(FLIP_INDEX) == list(range(25))


def test_loss_terms_vanish_on_consistent_data():
    p = torch.rand(2, 5, 25, 3) + torch.tensor([0.0, 0.0, 3.0])
    kp = losses.project_normalised(p)
    conf = torch.ones(2, 5, 25)
    assert losses.reprojection_loss(p, kp, conf) == pytest.approx(0.0, abs=1e-12)
    assert losses.fit_consistency_loss(p, p) == 0.0
    still = p[:, :1].repeat(1, 5, 1, 1)
    assert losses.temporal_3d_loss(still) == 0.0 and losses.temporal_2d_loss(still) == 0.0
    # a missing keypoint (confidence 0) does not count
    kp2 = kp.clone()
    kp2[0, 0, 3] += 5.0
    conf[0, 0, 3] = 0.0
    assert losses.reprojection_loss(p, kp2, conf) == pytest.approx(0.0, abs=1e-12)


def _toy_clips(seed=0, frames=120):
    """The dancer waving its arms, seen by a camera 4 m away: 2D inputs and exact 3D (as the 'fit')."""
    sk = Skeleton()
    rng = np.random.default_rng(seed)
    t = np.arange(frames) / 30.0
    q = np.repeat(sk.rest_qpos()[None], frames, axis=0)
    for row, amp, freq in ((8, 0.8, 0.5), (14, 0.8, 0.7), (11, -0.8, 1.0), (23, 0.5, 0.3)):
        q[:, 7 + row] = np.clip(q[:, 7 + row] + amp * (0.5 - 0.5 * np.cos(2 * np.pi * freq * t + rng.uniform())),
                                sk.lower[row], sk.upper[row])
    world = sk.keypoints(q)
    cam = orbit_camera(4.0, rng.uniform(-60, 60), 5.0, target=(0, 0, 0.8))
    p3 = cam.to_camera(world)
    px = project(p3, 1000.0, (640, 360))
    kp = np.concatenate([px, np.ones(px.shape[:2] + (1,))], -1)
    return LiftingClip(normalise_keypoints(kp, 1000.0, (640, 360)), p3.astype(np.float32))


def test_window_dataset_padding_and_flip():
    clip = _toy_clips()
    ds = WindowDataset([clip], receptive_field=27, out_frames=8, flip=False)
    item = ds[0]
    assert item["inputs"].shape == (27 + 7, 25, 3) and item["fit3d"].shape == (8, 25, 3)
    np.testing.assert_allclose(item["inputs"][0], clip.inputs[0])  # padded with the first frame
    flipped = WindowDataset([clip], receptive_field=27, out_frames=8, flip=True, seed=3)
    items = [flipped[i] for i in range(len(flipped))]
    assert any(not torch.allclose(a["fit3d"], ds[i]["fit3d"]) for i, a in enumerate(items))
    # flipping keeps 2D and 3D consistent: projection of the flipped 3D equals the flipped 2D
    for a in items:
        np.testing.assert_allclose(losses.project_normalised(a["fit3d"]), a["keypoints2d"], atol=1e-5)


def test_training_reduces_error_and_checkpoint_round_trip(tmp_path):
    clips = [_toy_clips(s) for s in range(3)]
    test = _toy_clips(7)
    model0 = TemporalLifter(SMALL)
    before = np.linalg.norm(lift_sequence(model0, test.inputs) - test.fit3d, axis=-1).mean()
    cfg = TrainConfig(epochs=30, batch_size=16, out_frames=4, device="cpu", seed=0, lr_decay=0.98)
    model, history = train_lifter(clips, SMALL, cfg)
    after = np.linalg.norm(lift_sequence(model, test.inputs) - test.fit3d, axis=-1).mean()
    assert history[-1]["fit"] < history[0]["fit"]
    assert after < 0.5 * before and after < 0.25, (before, after)
    save_checkpoint(tmp_path / "lifter.pt", model, {"note": "toy"})
    loaded, meta = load_checkpoint(tmp_path / "lifter.pt")
    assert meta == {"note": "toy"}
    np.testing.assert_allclose(lift_sequence(loaded, test.inputs), lift_sequence(model, test.inputs), atol=1e-5)
    with pytest.raises(HDVRError):
        load_checkpoint(tmp_path / "missing.pt")


def test_lift_cli_train_and_apply(tmp_path):
    from hdvr.cli import main
    from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
    from hdvr.io.result3d import Result3D, load_result3d, save_result3d

    clip = _toy_clips(1, frames=60)
    px = clip.inputs.copy()
    px[..., :2] = px[..., :2] * 1000.0 + np.array([640, 360])
    save_keypoints2d(tmp_path / "kp.npz", Keypoints2D(px, BODY25_NAMES, 30.0, (1280, 720)))
    q = np.zeros((60, 41))
    q[:, 3] = 1
    save_result3d(tmp_path / "fit.npz", Result3D(clip.fit3d, q, 1000.0, (640, 360), np.ones(9), np.zeros(60)))
    assert main(["lift", "train", "--pair", str(tmp_path / "kp.npz"), str(tmp_path / "fit.npz"),
                 "--out", str(tmp_path / "m.pt"), "--epochs", "2", "--small", "--device", "cpu"]) == 0
    assert main(["lift", "apply", str(tmp_path / "kp.npz"), "--fit", str(tmp_path / "fit.npz"),
                 "--model", str(tmp_path / "m.pt"), "--out", str(tmp_path / "lifted.npz")]) == 0
    out = load_result3d(tmp_path / "lifted.npz")
    assert out.keypoints3d.shape == (60, 25, 3) and out.meta["keypoints3d_source"] == "lifter"
