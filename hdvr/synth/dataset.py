"""PyTorch Dataset over a synthetic dataset folder (``hdvr synth --out DIR``).

An item is one dancer's window of ``window`` frames (stride ``stride``) from one clip. Fixed keys of an item
(tensors; W = window):

- ``keypoints2d`` float32 (W, 25, 2) pixels (NaN behind the camera); ``visibility`` int64 (W, 25) (2 visible,
  1 occluded, 0 outside); ``keypoints3d_camera`` / ``keypoints3d_world`` float32 (W, 25, 3) metres;
  ``qpos`` float32 (W, 41); ``boxes`` float32 (W, 4) x, y, w, h pixels (NaN when out of view);
  ``labels`` int64 (W, 16) global movement label ids; ``genre`` int64 () index in :data:`GENRES`;
  ``focal`` float32 (W,) px, ``principal_point`` float32 (2,), ``image_size`` int64 (2,);
  ``clip`` str, ``dancer`` int, ``start`` int (first frame);
- with ``frames=True`` also ``frames`` uint8 (W, H, Wd, 3) RGB decoded from the clip's video.

``split``: ``"train"`` / ``"val"`` / ``"test"`` by clip index (index mod 10: 0-7 train, 8 val, 9 test), or None.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np
import torch
from torch.utils.data import Dataset

from hdvr.errors import HDVRError
from hdvr.io.npz import open_npz
from hdvr.synth.genres import GENRES
from hdvr.synth.groundtruth import GT_KEYS

SPLITS = {"train": range(0, 8), "val": (8,), "test": (9,)}


@lru_cache(maxsize=8)
def _load_gt(path: str) -> dict:
    data = open_npz(path, GT_KEYS, "synthetic ground-truth")
    return {k: data[k] for k in GT_KEYS}


class SynthDanceDataset(Dataset):
    """Windows of one dancer's ground truth from synthetic clips (see module docstring)."""

    def __init__(self, root: str | Path, window: int = 64, stride: int | None = None, split: str | None = None,
                 frames: bool = False):
        self.root = Path(root)
        index_path = self.root / "index.json"
        if not index_path.is_file():
            raise HDVRError(f"no synthetic dataset index at {index_path} (run `hdvr synth --out {self.root}`)")
        try:
            index = json.loads(index_path.read_text())
        except json.JSONDecodeError:
            raise HDVRError(f"corrupt dataset index {index_path}") from None
        if split is not None and split not in SPLITS:
            raise HDVRError(f"split must be one of {sorted(SPLITS)} or None, got {split!r}")
        if window < 1:
            raise HDVRError(f"window must be at least 1 frame, got {window}")
        self.window = int(window)
        self.stride = int(stride or window)
        self.frames = frames
        self.items: list[tuple[str, int, int]] = []
        for clip in index["clips"]:
            idx = int(clip["clip"].split("_")[-1])
            if split is not None and idx % 10 not in SPLITS[split]:
                continue
            if frames and not clip.get("rendered"):
                continue
            T = int(clip["frames"])
            if T < self.window:
                continue
            for dancer in range(int(clip["n_dancers"])):
                for start in range(0, T - self.window + 1, self.stride):
                    self.items.append((clip["clip"], dancer, start))

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, i: int) -> dict:
        clip, dancer, start = self.items[i]
        gt = _load_gt(str(self.root / clip / "gt.npz"))
        w = slice(start, start + self.window)
        item = {
            "keypoints2d": torch.from_numpy(np.ascontiguousarray(gt["keypoints2d"][dancer, w], dtype=np.float32)),
            "visibility": torch.from_numpy(gt["visibility"][dancer, w].astype(np.int64)),
            "keypoints3d_camera": torch.from_numpy(np.ascontiguousarray(gt["keypoints3d_camera"][dancer, w],
                                                                        dtype=np.float32)),
            "keypoints3d_world": torch.from_numpy(np.ascontiguousarray(gt["keypoints3d_world"][dancer, w],
                                                                       dtype=np.float32)),
            "qpos": torch.from_numpy(gt["qpos"][dancer, w].astype(np.float32)),
            "boxes": torch.from_numpy(gt["boxes"][dancer, w].astype(np.float32)),
            "labels": torch.from_numpy(gt["labels"][dancer, w].astype(np.int64)),
            "genre": torch.tensor(int(gt["genre_index"]), dtype=torch.int64),
            "focal": torch.from_numpy(gt["focal"][w].astype(np.float32)),
            "principal_point": torch.from_numpy(gt["principal_point"].astype(np.float32)),
            "image_size": torch.from_numpy(gt["image_size"].astype(np.int64)),
            "clip": clip, "dancer": dancer, "start": start,
        }
        if self.frames:
            item["frames"] = torch.from_numpy(read_frames(self.root / clip / "video.mp4", start, self.window))
        return item

    @property
    def genres(self) -> tuple[str, ...]:
        return GENRES


def read_frames(path: Path, start: int, count: int) -> np.ndarray:
    """RGB frames [start, start + count) of a video, (count, H, W, 3) uint8 (OpenCV decodes H.264)."""
    import cv2

    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise HDVRError(f"cannot open video {path}")
    try:
        cap.set(cv2.CAP_PROP_POS_FRAMES, start)
        out = []
        for _ in range(count):
            ok, frame = cap.read()
            if not ok:
                raise HDVRError(f"video {path} ends before frame {start + len(out)}")
            out.append(cv2.cvtColor(frame, cv2.COLOR_BGR2RGB))
    finally:
        cap.release()
    return np.stack(out)
