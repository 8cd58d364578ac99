"""Training and inference for :class:`hdvr.lifter.model.TemporalLifter`.

Checkpoints are plain ``torch.save`` dicts of tensors and primitives (``state_dict``, ``config``, ``meta``) and
are loaded with ``torch.load(..., weights_only=True)``. Training is deterministic for a seed on the CPU; on a GPU
the window order and flips are the same, the arithmetic (TF32 / bf16 kernels) is not bit-exact.
"""

from __future__ import annotations

import os
import time
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np
import torch

from hdvr.errors import HDVRError
from hdvr.io.atomic import atomic_path
from hdvr.lifter import losses
from hdvr.lifter.data import LiftingClip, WindowBatcher, mirror
from hdvr.lifter.model import LifterConfig, TemporalLifter
from hdvr.progress import progress


@dataclass
class TrainConfig:
    """Optimisation settings and the weights of Algorithm 4*'s loss terms."""

    epochs: int = 40
    # windows per step: the lifter needs many steps more than large ones (docs/benchmarks.md, "Lifter", session 43:
    # on the CPU a step of 32 windows costs half one of 64, and 45 minutes at 32 ended 1 mm better)
    batch_size: int = 32
    out_frames: int = 16
    window_stride: int = 2  # frames between training window starts
    learning_rate: float = 1e-3
    lr_decay: float = 0.95  # per epoch
    weight_reprojection: float = 1.0
    weight_fit: float = 1.0
    weight_temporal_3d: float = 0.1
    weight_temporal_2d: float = 0.1
    weight_supervised: float = 1.0
    flip: bool = True
    seed: int = 0
    device: str = "auto"
    # bf16 autocast on a CUDA device (ignored on the CPU). Off: on an H100 the full-size lifter trained 1.7x slower
    # with it than in float32 (TF32 convolutions), on the same loss curve (docs/benchmarks.md, "Lifter", session 43)
    mixed_precision: bool = False
    max_seconds: float | None = None  # stop after the epoch that passes this much training time (None: no limit)
    history: list = field(default_factory=list)


def pick_device(name: str = "auto") -> torch.device:
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    return torch.device(name)


#: Unit scalings so the terms are comparable: normalised image units^2 -> px^2 at f = 1000 px; m^2 -> cm^2.
PX2 = 1e6
CM2 = 1e4


def loss_terms(pred: torch.Tensor, batch: dict, cfg: TrainConfig) -> dict[str, torch.Tensor]:
    """Each weighted term of the loss for a batch (predictions (B, L, 25, 3) camera metres)."""
    terms = {
        "reprojection": cfg.weight_reprojection * PX2 * losses.reprojection_loss(pred, batch["keypoints2d"],
                                                                                batch["confidence"]),
        "fit": cfg.weight_fit * CM2 * losses.fit_consistency_loss(pred, batch["fit3d"]),
        "temporal_3d": cfg.weight_temporal_3d * CM2 * losses.temporal_3d_loss(pred),
        "temporal_2d": cfg.weight_temporal_2d * PX2 * losses.temporal_2d_loss(pred),
    }
    has = batch["has_labels"]
    if bool(has.any()):
        terms["supervised"] = cfg.weight_supervised * CM2 * losses.fit_consistency_loss(pred[has],
                                                                                        batch["labels3d"][has])
    return terms


def train_lifter(clips: list[LiftingClip], model_cfg: LifterConfig | None = None,
                 cfg: TrainConfig | None = None,
                 on_epoch: Callable[[dict], None] | None = None) -> tuple[TemporalLifter, list[dict]]:
    """Train a lifter on ``clips``; returns the model (eval mode, on the CPU) and the per-epoch history (mean of
    each weighted loss term, training seconds so far), each entry also passed to ``on_epoch`` as it ends."""
    cfg = cfg or TrainConfig()
    torch.manual_seed(cfg.seed)
    device = pick_device(cfg.device)
    model = TemporalLifter(model_cfg).to(device)
    data = WindowBatcher(clips, model.receptive_field, cfg.out_frames, cfg.flip, cfg.seed, cfg.window_stride,
                         device=device)
    opt = torch.optim.Adam(model.parameters(), lr=cfg.learning_rate, amsgrad=True)
    sched = torch.optim.lr_scheduler.ExponentialLR(opt, cfg.lr_decay)
    autocast = torch.autocast(device.type, dtype=torch.bfloat16,
                              enabled=cfg.mixed_precision and device.type == "cuda")
    history = []
    start = time.perf_counter()
    for epoch in progress(range(cfg.epochs), desc="training lifter", unit="epoch"):
        model.train()
        sums: dict[str, torch.Tensor] = {}
        batches = 0
        for batch in data.batches(epoch, cfg.batch_size):
            with autocast:
                pred = model(batch["inputs"])
            terms = loss_terms(pred.float(), batch, cfg)
            loss = sum(terms.values())
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
            for k, v in terms.items():  # summed on the device: no synchronisation per step
                sums[k] = sums.get(k, 0.0) + v.detach()
            batches += 1
        sched.step()
        seconds = time.perf_counter() - start
        history.append({"epoch": epoch, **{k: float(v) / max(batches, 1) for k, v in sums.items()},
                        "seconds": seconds})
        if on_epoch is not None:
            on_epoch(history[-1])
        if cfg.max_seconds is not None and seconds > cfg.max_seconds:
            break
    model.eval()
    return model.cpu(), history


@torch.no_grad()
def lift_sequence(model: TemporalLifter, inputs: np.ndarray, chunk: int = 2048,
                  flip_test: bool = False) -> np.ndarray:
    """Lift a whole clip: ``inputs`` (T, 25, 3) normalised 2D + confidence -> (T, 25, 3) camera metres.

    The clip is padded by repeating its first and last frames so every frame gets a prediction. ``flip_test``
    also lifts the mirrored clip and averages its prediction, mirrored back, with the clip's (as VideoPose3D's
    test-time augmentation; twice the work).
    """
    if inputs.ndim != 3 or inputs.shape[1:] != (25, 3) or inputs.shape[0] == 0:
        raise HDVRError(f"lifter input must be (T>0, 25, 3), got {inputs.shape}")
    if flip_test:
        return 0.5 * (lift_sequence(model, inputs, chunk) + mirror(lift_sequence(model, mirror(inputs), chunk)))
    model.eval()
    device = next(model.parameters()).device
    rf = model.receptive_field
    pad = (rf - 1) // 2
    t = inputs.shape[0]
    idx = np.clip(np.arange(-pad, t + pad), 0, t - 1)
    padded = torch.from_numpy(np.ascontiguousarray(inputs[idx], dtype=np.float32))
    out = []
    for s in range(0, t, chunk):
        n = min(chunk, t - s)
        window = padded[s:s + n + rf - 1][None].to(device)
        out.append(model(window)[0].cpu().numpy())
    return np.concatenate(out, axis=0)


def save_checkpoint(path: str | os.PathLike, model: TemporalLifter, meta: dict | None = None) -> None:
    """Write the model's weights, config and ``meta`` (primitives only) atomically."""
    payload = {"state_dict": model.state_dict(), "config": model.cfg.to_dict(), "meta": meta or {}}
    with atomic_path(path) as tmp:
        torch.save(payload, tmp)


def load_checkpoint(path: str | os.PathLike, device: str = "cpu") -> tuple[TemporalLifter, dict]:
    """Load a lifter saved by :func:`save_checkpoint` (``weights_only=True``)."""
    if not os.path.isfile(path):
        raise HDVRError(f"lifter checkpoint not found: {path}")
    try:
        payload = torch.load(path, map_location=device, weights_only=True)
        model = TemporalLifter(LifterConfig.from_dict(payload["config"]))
        model.load_state_dict(payload["state_dict"])
    except (RuntimeError, KeyError, ValueError, EOFError) as exc:
        raise HDVRError(f"cannot read lifter checkpoint {path}: {type(exc).__name__}") from None
    model.eval()
    return model, payload.get("meta", {})


def train_config_dict(cfg: TrainConfig) -> dict:
    d = asdict(cfg)
    d.pop("history", None)
    return d
