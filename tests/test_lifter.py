"""The lifter: receptive field, shapes, loss terms, flip augmentation, training reduces error, checkpoints."""

import numpy as np
import pytest
import torch

from hdvr.camera import orbit_camera, project
from hdvr.errors import HDVRError
from hdvr.lifter import losses
from hdvr.lifter.data import FLIP_INDEX, LiftingClip, WindowBatcher, normalise_keypoints
from hdvr.lifter.model import LifterConfig, TemporalLifter, solve_root_translation
from hdvr.lifter.train import TrainConfig, lift_sequence, load_checkpoint, save_checkpoint, train_lifter
from hdvr.layouts import BODY25_NAMES
from hdvr.skeleton import Skeleton

SMALL = LifterConfig(filter_widths=(3, 3), channels=64, dropout=0.0, root="learned")


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


def test_window_batcher_padding_and_flip():
    clip = _toy_clips()
    other = _toy_clips(seed=1, frames=50)
    data = WindowBatcher([clip, other], receptive_field=27, out_frames=8, flip=False, stride=2)
    assert len(data) == 60 + 25
    first = data.gather(torch.tensor([0]), torch.tensor([False]))
    assert first["inputs"].shape == (1, 27 + 7, 25, 3) and first["fit3d"].shape == (1, 8, 25, 3)
    np.testing.assert_allclose(first["inputs"][0, :14], np.repeat(clip.inputs[:1], 14, 0))  # padded: first frame
    np.testing.assert_allclose(first["inputs"][0, 13:], clip.inputs[:21])
    np.testing.assert_allclose(first["fit3d"][0], clip.fit3d[:8])
    # the second clip's last window is padded with its own last frame, never the first clip's frames
    last = data.gather(torch.tensor([len(data) - 1]), torch.tensor([False]))
    np.testing.assert_allclose(last["inputs"][0, 13:], other.inputs[[48, 49] + [49] * 19])
    np.testing.assert_allclose(last["keypoints2d"][0], other.inputs[[48, 49] + [49] * 6, :, :2])
    assert not bool(last["has_labels"][0])
    # a mirrored window: x negated, left and right exchanged, 2D and 3D still consistent
    mirrored = data.gather(torch.tensor([0]), torch.tensor([True]))
    np.testing.assert_allclose(mirrored["fit3d"][0, :, FLIP_INDEX, 0], -first["fit3d"][0, :, :, 0])
    np.testing.assert_allclose(mirrored["inputs"][0, :, FLIP_INDEX, 2], first["inputs"][0, :, :, 2])
    np.testing.assert_allclose(losses.project_normalised(mirrored["fit3d"]), mirrored["keypoints2d"], atol=1e-5)
    # an epoch visits every window once; order and flips depend on (seed, epoch) only
    flipping = WindowBatcher([clip, other], receptive_field=27, out_frames=8, flip=True, seed=3)
    order, flips = flipping.order(0)
    assert sorted(order.tolist()) == list(range(len(data))) and 0 < int(flips.sum()) < len(data)
    assert torch.equal(order, flipping.order(0)[0]) and not torch.equal(order, flipping.order(1)[0])
    batches = list(flipping.batches(0, batch_size=16))
    assert len(batches) == len(data) // 16 and all(b["inputs"].shape[0] == 16 for b in batches)
    assert len(list(flipping.batches(0, batch_size=16, drop_last=False))) == len(data) // 16 + 1


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


def _write_toy_pair(folder, frames: int) -> None:
    """A toy clip's 2D keypoints (pixels, 1280x720) and its 3D fit, as ``kp.npz`` and ``fit.npz`` in ``folder``."""
    from hdvr.io.keypoints2d import Keypoints2D, save_keypoints2d
    from hdvr.io.result3d import Result3D, save_result3d

    clip = _toy_clips(1, frames=frames)
    px = clip.inputs.copy()
    px[..., :2] = px[..., :2] * 1000.0 + np.array([640, 360])
    save_keypoints2d(folder / "kp.npz", Keypoints2D(px, BODY25_NAMES, 30.0, (1280, 720)))
    q = np.zeros((frames, 41))
    q[:, 3] = 1
    save_result3d(folder / "fit.npz", Result3D(clip.fit3d, q, 1000.0, (640, 360), np.ones(9), np.zeros(frames)))


def test_lift_cli_train_and_apply(tmp_path):
    from hdvr.cli import main
    from hdvr.io.result3d import load_result3d

    _write_toy_pair(tmp_path, 60)
    assert main(["lift", "train", "--pair", str(tmp_path / "kp.npz"), str(tmp_path / "fit.npz"),
                 "--out", str(tmp_path / "m.pt"), "--epochs", "2", "--small", "--device", "cpu",
                 "--batch-size", "32", "--max-minutes", "5"]) == 0
    assert main(["lift", "apply", str(tmp_path / "kp.npz"), "--fit", str(tmp_path / "fit.npz"),
                 "--model", str(tmp_path / "m.pt"), "--out", str(tmp_path / "lifted.npz")]) == 0
    out = load_result3d(tmp_path / "lifted.npz")
    assert out.keypoints3d.shape == (60, 25, 3) and out.meta["keypoints3d_source"] == "lifter"
    assert main(["lift", "apply", str(tmp_path / "kp.npz"), "--fit", str(tmp_path / "fit.npz"), "--flip-test",
                 "--model", str(tmp_path / "m.pt"), "--out", str(tmp_path / "flipped.npz")]) == 0
    flipped = load_result3d(tmp_path / "flipped.npz").keypoints3d
    assert flipped.shape == (60, 25, 3) and not np.allclose(flipped, out.keypoints3d)


def test_lift_train_takes_32_windows_per_step_on_the_cpu_and_64_on_a_gpu(tmp_path):
    """Without --batch-size: 32 on the CPU (recorded in the checkpoint), 64 on a GPU (measured best on each)."""
    from hdvr.cli import main
    from hdvr.commands.lift import default_batch_size
    from hdvr.lifter.train import load_checkpoint

    assert default_batch_size("cpu") == 32 and default_batch_size("cuda") == 64 and default_batch_size("cuda:1") == 64
    _write_toy_pair(tmp_path, 80)
    assert main(["lift", "train", "--pair", str(tmp_path / "kp.npz"), str(tmp_path / "fit.npz"),
                 "--out", str(tmp_path / "m.pt"), "--epochs", "1", "--small", "--device", "cpu"]) == 0
    assert load_checkpoint(tmp_path / "m.pt")[1]["train"]["batch_size"] == 32


def test_solved_root_translation_places_the_pose_on_the_2d():
    gen = torch.Generator().manual_seed(0)
    rel = 0.3 * torch.randn(2, 4, 25, 3, generator=gen)
    rel = rel - rel[:, :, 8:9]
    truth = torch.tensor([0.4, -0.3, 5.5])
    kp = losses.project_normalised(rel + truth)
    weight = torch.ones(2, 4, 25)
    np.testing.assert_allclose(solve_root_translation(rel, kp, weight), truth.expand(2, 4, 3), atol=1e-3)
    # joints without confidence do not count, however wrong their 2D
    weight[..., :10] = 0.0
    wrong = kp.clone()
    wrong[..., :10, :] += 0.5
    np.testing.assert_allclose(solve_root_translation(rel, wrong, weight), truth.expand(2, 4, 3), atol=1e-3)
    # a frame with no keypoints stands 4 m straight ahead
    np.testing.assert_allclose(solve_root_translation(rel, kp, torch.zeros(2, 4, 25)), [[[0.0, 0.0, 4.0]] * 4] * 2)
    # the translation is differentiable in the pose: the loss can shape the pose through it
    rel.requires_grad_(True)
    solve_root_translation(rel, kp, torch.ones(2, 4, 25))[..., 2].sum().backward()
    assert torch.isfinite(rel.grad).all() and rel.grad.abs().sum() > 0


def test_lifter_with_solved_root_learns_and_round_trips(tmp_path):
    solved = LifterConfig(filter_widths=(3, 3), channels=64, dropout=0.0)
    assert solved.root == "solved"  # the default
    model = TemporalLifter(solved)
    assert model.root is None and sum(p.numel() for p in model.parameters()) < sum(
        p.numel() for p in TemporalLifter(SMALL).parameters())
    clips = [_toy_clips(s) for s in range(3)]
    test = _toy_clips(7)
    before = np.linalg.norm(lift_sequence(model, test.inputs) - test.fit3d, axis=-1).mean()
    cfg = TrainConfig(epochs=20, batch_size=16, out_frames=4, device="cpu", seed=0, lr_decay=0.98)
    model, history = train_lifter(clips, solved, cfg)
    lifted = lift_sequence(model, test.inputs)
    after = np.linalg.norm(lifted - test.fit3d, axis=-1).mean()
    assert after < 0.5 * before and after < 0.1, (before, after)
    # the root is where the lifted pose reprojects best onto the input 2D
    reprojection = losses.project_normalised(torch.from_numpy(lifted)) - torch.from_numpy(test.inputs[..., :2])
    assert float(reprojection.abs().mean()) < 0.01
    save_checkpoint(tmp_path / "solved.pt", model)
    loaded, _ = load_checkpoint(tmp_path / "solved.pt")
    assert loaded.cfg.root == "solved"
    np.testing.assert_allclose(lift_sequence(loaded, test.inputs), lifted, atol=1e-5)
    with pytest.raises(ValueError):
        TemporalLifter(LifterConfig(root="guessed"))


def test_training_stops_at_its_time_limit_and_reports_each_epoch():
    seen = []
    cfg = TrainConfig(epochs=5, batch_size=16, out_frames=4, device="cpu", max_seconds=0.0)
    _, history = train_lifter([_toy_clips(frames=40)], SMALL, cfg, on_epoch=seen.append)
    assert len(history) == 1 and seen == history  # the first epoch passes 0 s: training stops after it
    assert {"reprojection", "fit", "temporal_3d", "temporal_2d", "seconds"} <= set(history[0])


def test_flip_test_is_mirror_symmetric():
    from hdvr.lifter.data import mirror

    model = TemporalLifter(LifterConfig(filter_widths=(3, 3), channels=64))
    torch.nn.init.normal_(model.pose.head.weight, std=0.05)  # an untrained, asymmetric network
    clip = _toy_clips(frames=30)
    plain = lift_sequence(model, clip.inputs)
    assert not np.allclose(mirror(lift_sequence(model, mirror(clip.inputs))), plain, atol=1e-3)
    both = lift_sequence(model, clip.inputs, flip_test=True)
    np.testing.assert_allclose(lift_sequence(model, mirror(clip.inputs), flip_test=True), mirror(both), atol=1e-5)
    np.testing.assert_allclose(mirror(mirror(clip.inputs)), clip.inputs)
