"""Shared fixtures. Tests that need ../shared/data skip with a reason when it is absent (a user's clone)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HDVR_NO_PROGRESS", "1")

REPO_ROOT = Path(__file__).resolve().parents[1]
SHARED_DATA = Path(os.environ.get("HDVR_SHARED_DATA", REPO_ROOT.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """Path to ../shared/data (real mocap and videos); skips the test when it is not there."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"real data folder {SHARED_DATA} is absent (it ships beside the repo only for developers/CI)")
    return SHARED_DATA


@pytest.fixture
def one_torch_thread():
    """Tiny torch models train faster on one thread than on two contended ones (measured 6 s vs 20 s)."""
    import torch

    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


@pytest.fixture(scope="session")
def salsa_view(shared_data):
    """``view(take, start, stop, azimuth_deg)`` -> (Keypoints2D, camera-frame mocap (T, 25, 3) m): a CMU salsa
    lead-dancer clip (30 fps) seen by a 1920x1080 camera, focal 1500 px, 5 m away, 10 deg elevation."""
    import numpy as np

    from hdvr.camera import orbit_camera, project
    from hdvr.io.bvh import load_mocap_body25
    from hdvr.io.keypoints2d import Keypoints2D
    from hdvr.layouts import BODY25_NAMES

    def view(take: str, start: int, stop: int, azimuth_deg: float):
        pos, _ = load_mocap_body25(shared_data / "cmu-salsa" / f"60_{take}_scaled.bvh", fps=30)
        clip = pos[start:stop]
        cam = orbit_camera(5.0, azimuth_deg, 10.0, target=(*clip[:, 8, :2].mean(axis=0), 1.0))
        gt = cam.to_camera(clip)
        uv = project(gt, 1500.0, (960.0, 540.0))
        kp = Keypoints2D(np.concatenate([uv, np.ones(uv.shape[:2] + (1,))], axis=-1), BODY25_NAMES, 30.0,
                         (1920, 1080))
        return kp, gt

    return view


@pytest.fixture
def mocap_standin(tmp_path):
    """``standin(frames)`` -> path of a ``--gt-npz`` file (as ``scripts/bench_lifter.py --write-gt-npz`` writes)
    that holds two synthetic dancers as the takes '60_01' (rumba, a salsa take) and 'indian_04' (ballet), each
    ``frames`` long (30 fps, world metres, z up): for the mocap benchmarks' tests without ../shared."""
    import numpy as np

    from hdvr.synth.choreography import ChoreographyGenerator

    def standin(frames: int) -> Path:
        gen = ChoreographyGenerator()
        seconds = frames / 30.0 + 0.5
        takes = {"60_01": gen.generate("rumba", seconds, np.random.default_rng(1)).keypoints,
                 "indian_04": gen.generate("ballet", seconds, np.random.default_rng(2)).keypoints}
        path = tmp_path / "gt.npz"
        np.savez(path, **{k: v[:frames].astype(np.float32) for k, v in takes.items()})
        return path

    return standin
