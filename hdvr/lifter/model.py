"""Dilated temporal convolution lifter.

Input: (B, T_in, 25, 3) = BODY_25 keypoints in normalised camera coordinates ``((u - c_x) / f, (v - c_y) / f)``
plus confidence (0 where missing; coordinates zeroed there). Normalising by the intrinsics makes the network
independent of image size and focal length, so one model serves every camera.

Output: (B, T_out, 25, 3) keypoints in the camera frame, metres (x right, y down, z forward), with
``T_out = T_in - receptive_field + 1``. The network predicts a root-relative pose (mid_hip at the origin);
the root's position is solved in closed form as the translation that best reprojects that pose onto the input 2D
(:func:`solve_root_translation`; or, with ``LifterConfig.root = "learned"``, predicted by a second network as
normalised image position and depth). The two are combined into absolute camera-frame positions so that the
reprojection loss of Algorithm 4* applies. Solving the root leaves the network only the pose to learn, and it
learns far faster (docs/benchmarks.md, "Lifter", session 43: after 8 CPU minutes on the CMU benchmark, P-MPJPE
84 mm on unseen takes against 131 mm with a learned root, MPJPE 99 against 326 mm).

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
    # where the root is: "solved" (:func:`solve_root_translation`, the default) or "learned" (a second trunk
    # predicts its image position and depth, as in sessions 1-42; checkpoints without the key are such)
    root: str = "solved"
    # the pose network sees each frame's 2D about its root and scaled to unit size (:func:`centred_inputs`);
    # False: the normalised camera coordinates as given (checkpoints without the key)
    centre_inputs: bool = True

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
                   norm=str(d.get("norm", "group")), root=str(d.get("root", "learned")),
                   centre_inputs=bool(d.get("centre_inputs", False)))


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
        # The output layer always in float32: under bf16 autocast (GPU training) a depth of 4 m would come out in
        # steps of 16 mm.
        with torch.autocast(x.device.type, enabled=False):
            return self.head(x.float())


def centred_inputs(keypoints: torch.Tensor) -> torch.Tensor:
    """(B, T, J, 3) normalised 2D + confidence -> (B, T, 3 J + 2) features per frame.

    Each frame's 2D about its root (mid_hip, or the confidence-weighted mean of its keypoints where the hip is
    missing), divided by its size (the weighted RMS distance from the root), with the confidences; then the root's
    normalised image position (its viewing ray, which turns the pose seen). A pose then looks the same to the
    network wherever it stands in the picture and however far away: size and place are left to the root's solve.
    Missing keypoints stay zero.
    """
    conf = keypoints[..., 2].clamp(min=0.0)
    xy = keypoints[..., :2]
    total = conf.sum(-1, keepdim=True)
    mean = (conf[..., None] * xy).sum(-2) / total.clamp(min=1e-6)
    hip_seen = conf[..., ROOT_INDEX:ROOT_INDEX + 1] > 0
    root = torch.where(hip_seen, xy[..., ROOT_INDEX, :], mean)  # (B, T, 2)
    rel = (xy - root[..., None, :]) * (conf[..., None] > 0)
    size = ((conf * (rel ** 2).sum(-1)).sum(-1, keepdim=True) / total.clamp(min=1e-6)).sqrt().clamp(min=1e-3)
    features = torch.cat([rel / size[..., None], conf[..., None]], dim=-1)
    return torch.cat([features.flatten(-2), root * (total > 0)], dim=-1)


def solve_root_translation(relative: torch.Tensor, keypoints2d: torch.Tensor, weight: torch.Tensor,
                           prior_weight: float = 1e-6) -> torch.Tensor:
    """The camera-frame translation T (B, T, 3), metres, that best places a root-relative pose on the 2D.

    ``relative`` (B, T, J, 3) metres, ``keypoints2d`` (B, T, J, 2) normalised camera coordinates, ``weight``
    (B, T, J) confidences. Minimises sum_j w_j |(X_j + T)_xy - p_j (X_j + T)_z|^2, the numerator of
    :func:`hdvr.lifter.losses.reprojection_loss`, which is linear in T: a 3x3 system per frame. A weak pull
    (``prior_weight`` per unit of summed confidence; depth is the ill-conditioned direction, its curvature is
    about 1e-2 per unit) towards 4 m straight ahead keeps frames with no keypoints defined. Depth is kept at
    :data:`MIN_DEPTH_M` or more.
    """
    w = weight.clamp(min=0.0)
    u, v = keypoints2d[..., 0], keypoints2d[..., 1]
    x, y, z = relative[..., 0], relative[..., 1], relative[..., 2]
    sw, su, sv = w.sum(-1), (w * u).sum(-1), (w * v).sum(-1)
    suv = (w * (u * u + v * v)).sum(-1)
    bx, by = u * z - x, v * z - y  # per joint: T_x - u T_z = bx, T_y - v T_z = by
    rhs = torch.stack([(w * bx).sum(-1), (w * by).sum(-1), -(w * (u * bx + v * by)).sum(-1)], dim=-1)
    zero = torch.zeros_like(sw)
    normal = torch.stack([torch.stack([sw, zero, -su], -1), torch.stack([zero, sw, -sv], -1),
                          torch.stack([-su, -sv, suv], -1)], dim=-2)
    lam = (prior_weight * (sw.detach() + 1.0))[..., None]
    normal = normal + lam[..., None] * torch.eye(3, dtype=normal.dtype, device=normal.device)
    rhs = rhs + lam * torch.tensor([0.0, 0.0, INITIAL_DEPTH_M], dtype=rhs.dtype, device=rhs.device)
    t = torch.linalg.solve(normal, rhs.unsqueeze(-1)).squeeze(-1)
    return torch.cat([t[..., :2], t[..., 2:].clamp(min=MIN_DEPTH_M)], dim=-1)


class TemporalLifter(nn.Module):
    """Maps (B, T_in, J, 3) normalised 2D + confidence to (B, T_out, J, 3) camera-frame metres."""

    def __init__(self, cfg: LifterConfig | None = None):
        super().__init__()
        self.cfg = cfg or LifterConfig()
        j = self.cfg.num_joints
        if self.cfg.root not in ("learned", "solved"):
            raise ValueError(f"unknown root {self.cfg.root!r}: learned or solved")
        self.pose = _Trunk(3 * j + (2 if self.cfg.centre_inputs else 0), 3 * j, self.cfg)
        self.root = _Trunk(3 * j, 3, self.cfg) if self.cfg.root == "learned" else None
        with torch.no_grad():
            # Zero-initialised output layers: the network starts from every joint at the root, 4 m in front of
            # the camera (a typical filming distance), instead of poses metres wide (measured: with default
            # initialisation the residual stream's scale made the first poses ~7 m off and training stalled).
            for head in (self.pose.head,) + ((self.root.head,) if self.root is not None else ()):
                head.weight.zero_()
                head.bias.zero_()
            if self.root is not None:
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
        pose_in = centred_inputs(keypoints).transpose(1, 2) if self.cfg.centre_inputs else x
        rel = self.pose(pose_in).transpose(1, 2).reshape(b, -1, j, 3)
        rel = rel - rel[:, :, ROOT_INDEX:ROOT_INDEX + 1]
        if self.root is None:
            pad = (self.receptive_field - 1) // 2
            centre = keypoints[:, pad:pad + rel.shape[1]].float()
            with torch.autocast(keypoints.device.type, enabled=False):
                return rel + solve_root_translation(rel, centre[..., :2], centre[..., 2])[:, :, None, :]
        r = self.root(x).transpose(1, 2)  # (B, T_out, 3): u, v (normalised), log depth
        # softplus keeps a gradient everywhere (a hard clamp froze samples whose depth left the clamp range)
        depth = MIN_DEPTH_M + nn.functional.softplus(r[..., 2:3])
        root = torch.cat([r[..., :2] * depth, depth], dim=-1)
        return rel + root[:, :, None, :]
