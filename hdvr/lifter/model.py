"""Dilated temporal convolution lifter.

Input: (B, T_in, 25, 3) = BODY_25 keypoints in normalised camera coordinates ``((u - c_x) / f, (v - c_y) / f)``
plus confidence (0 where missing; coordinates zeroed there). Normalising by the intrinsics makes the network
independent of image size and focal length, so one model serves every camera.

Output: (B, T_out, 25, 3) keypoints in the camera frame, metres (x right, y down, z forward), with
``T_out = T_in - receptive_field + 1``. The network predicts a root-relative pose (mid_hip at the origin) and,
from a separate head, the root's normalised image position and log depth; the two are combined into absolute
camera-frame positions so that the reprojection loss of Algorithm 4* applies.

Architecture (as published for VideoPose3D, Pavllo et al. 2019; implemented here from the description): a
width-w convolution, then blocks of (dilated width-w convolution, 1x1 convolution), each with normalisation
(GroupNorm by default, see :func:`_norm`), ReLU,
dropout and a residual connection whose input is centre-cropped to the block's output length. Dilations are
w^1, w^2, ..., so the receptive field is w^(blocks+1) (243 for w = 3 and 4 blocks).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import torch
from torch import nn

NUM_JOINTS = 25
ROOT_INDEX = 8  # BODY_25 mid_hip
INITIAL_DEPTH_M = 4.0
MIN_DEPTH_M = 0.1


@dataclass
class LifterConfig:
    """Hyper-parameters; ``filter_widths`` (3, 3, 3, 3, 3) gives receptive field 243 frames."""

    filter_widths: tuple[int, ...] = (3, 3, 3, 3, 3)
    channels: int = 1024
    dropout: float = 0.25
    num_joints: int = NUM_JOINTS
    norm: str = "group"  # "group" (GroupNorm, 8 groups), "batch" (as published) or "none"

    @property
    def receptive_field(self) -> int:
        rf = 1
        for w in self.filter_widths:
            rf *= w
        return rf

    def to_dict(self) -> dict:
        d = asdict(self)
        d["filter_widths"] = list(self.filter_widths)
        return d

    @classmethod
    def from_dict(cls, d: dict) -> "LifterConfig":
        return cls(filter_widths=tuple(int(w) for w in d["filter_widths"]), channels=int(d["channels"]),
                   dropout=float(d["dropout"]), num_joints=int(d.get("num_joints", NUM_JOINTS)),
                   norm=str(d.get("norm", "group")))


def _norm(kind: str, channels: int) -> nn.Module:
    """Normalisation layer. GroupNorm is the default: batch norm's running averages, taken over windows of many
    clips and cameras, mismatch a single clip at inference (measured: a toy lifter that converged with GroupNorm
    or none diverged at evaluation with batch norm)."""
    if kind == "group":
        return nn.GroupNorm(8, channels)
    if kind == "batch":
        return nn.BatchNorm1d(channels, momentum=0.1)
    if kind == "none":
        return nn.Identity()
    raise ValueError(f"unknown normalisation {kind!r}")


class _Trunk(nn.Module):
    def __init__(self, in_channels: int, out_channels: int, cfg: LifterConfig):
        super().__init__()
        c = cfg.channels
        self.expand = nn.Conv1d(in_channels, c, cfg.filter_widths[0], bias=False)
        self.expand_bn = _norm(cfg.norm, c)
        self.dilated = nn.ModuleList()
        self.dilated_bn = nn.ModuleList()
        self.pointwise = nn.ModuleList()
        self.pointwise_bn = nn.ModuleList()
        self.crops: list[int] = []
        dilation = cfg.filter_widths[0]
        for w in cfg.filter_widths[1:]:
            self.crops.append((w - 1) * dilation // 2)
            self.dilated.append(nn.Conv1d(c, c, w, dilation=dilation, bias=False))
            self.dilated_bn.append(_norm(cfg.norm, c))
            self.pointwise.append(nn.Conv1d(c, c, 1, bias=False))
            self.pointwise_bn.append(_norm(cfg.norm, c))
            dilation *= w
        self.drop = nn.Dropout(cfg.dropout)
        self.relu = nn.ReLU(inplace=True)
        self.head = nn.Conv1d(c, out_channels, 1)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # x: (B, C_in, T)
        x = self.drop(self.relu(self.expand_bn(self.expand(x))))
        for crop, conv, bn, pw, pw_bn in zip(self.crops, self.dilated, self.dilated_bn, self.pointwise,
                                             self.pointwise_bn):
            residual = x[:, :, crop:x.shape[2] - crop]
            x = self.drop(self.relu(bn(conv(x))))
            x = residual + self.drop(self.relu(pw_bn(pw(x))))
        return self.head(x)


class TemporalLifter(nn.Module):
    """Maps (B, T_in, J, 3) normalised 2D + confidence to (B, T_out, J, 3) camera-frame metres."""

    def __init__(self, cfg: LifterConfig | None = None):
        super().__init__()
        self.cfg = cfg or LifterConfig()
        j = self.cfg.num_joints
        self.pose = _Trunk(3 * j, 3 * j, self.cfg)
        self.root = _Trunk(3 * j, 3, self.cfg)
        with torch.no_grad():
            # Zero-initialised output layers: the network starts from every joint at the root, 4 m in front of
            # the camera (a typical filming distance), instead of poses metres wide (measured: with default
            # initialisation the residual stream's scale made the first poses ~7 m off and training stalled).
            for head in (self.pose.head, self.root.head):
                head.weight.zero_()
                head.bias.zero_()
            inverse_softplus = float(np.log(np.expm1(INITIAL_DEPTH_M - MIN_DEPTH_M)))
            self.root.head.bias.copy_(torch.tensor([0.0, 0.0, inverse_softplus]))

    @property
    def receptive_field(self) -> int:
        return self.cfg.receptive_field

    def forward(self, keypoints: torch.Tensor) -> torch.Tensor:
        b, t, j, c = keypoints.shape
        if j != self.cfg.num_joints or c != 3:
            raise ValueError(f"expected (B, T, {self.cfg.num_joints}, 3) input, got {tuple(keypoints.shape)}")
        if t < self.receptive_field:
            raise ValueError(f"need at least {self.receptive_field} input frames, got {t}")
        x = keypoints.reshape(b, t, j * c).transpose(1, 2)
        rel = self.pose(x).transpose(1, 2).reshape(b, -1, j, 3)
        rel = rel - rel[:, :, ROOT_INDEX:ROOT_INDEX + 1]
        r = self.root(x).transpose(1, 2)  # (B, T_out, 3): u, v (normalised), log depth
        # softplus keeps a gradient everywhere (a hard clamp froze samples whose depth left the clamp range)
        depth = MIN_DEPTH_M + nn.functional.softplus(r[..., 2:3])
        root = torch.cat([r[..., :2] * depth, depth], dim=-1)
        return rel + root[:, :, None, :]
