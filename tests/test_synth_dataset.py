import numpy as np
import pytest
import torch

from hdvr.errors import HDVRError
from hdvr.synth.dataset import SynthDanceDataset
from hdvr.synth.groundtruth import clip_spec, make_clip, write_index


@pytest.fixture(scope="module")
def dataset_root(tmp_path_factory):
    root = tmp_path_factory.mktemp("synth")
    for i in range(3):
        make_clip(root, clip_spec(i, 0, ("waltz", "tap", "hip_hop"), (1, 2), 2.0), render=False)
    write_index(root)
    return root


def test_windows_and_fields(dataset_root):
    ds = SynthDanceDataset(dataset_root, window=20, stride=10)
    assert len(ds) > 0
    item = ds[0]
    assert item["keypoints2d"].shape == (20, 25, 2) and item["labels"].dtype == torch.int64
    assert item["labels"].shape == (20, 16) and int(item["labels"].max()) < 154
    assert item["genre"].item() in range(9)
    loader = torch.utils.data.DataLoader(ds, batch_size=4)
    batch = next(iter(loader))
    assert batch["keypoints3d_camera"].shape == (4, 20, 25, 3)


def test_splits_and_errors(dataset_root, tmp_path):
    train = SynthDanceDataset(dataset_root, window=20, split="train")
    assert {c for c, _, _ in train.items} == {"clip_00000", "clip_00001", "clip_00002"}
    assert len(SynthDanceDataset(dataset_root, window=20, split="val")) == 0
    with pytest.raises(HDVRError, match="index"):
        SynthDanceDataset(tmp_path)
    with pytest.raises(HDVRError, match="split"):
        SynthDanceDataset(dataset_root, split="dev")
