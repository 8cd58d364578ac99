"""Keypoint layouts and converters.

BODY_25 (OpenPose order) is the canonical layout of HDVR: the digital dancer has one site per BODY_25 keypoint,
2D keypoint files and 3D results use it. Other layouts convert to and from it:

- COCO-17 (most 2D detectors, YOLO-pose, RTMPose): ``neck`` = midpoint of the shoulders and ``mid_hip`` = midpoint
  of the hips are derived; toes and heels have no COCO counterpart and stay missing.
- H36M-17 (Human3.6M 3D benchmarks): ``pelvis`` = mid_hip, ``thorax`` = neck, ``spine`` = midpoint of pelvis and
  thorax, ``neck_nose`` = nose, ``head`` = midpoint of the ears (approximation of the head-top marker).
- CMU BVH (the salsa and Indian mocap in ``../shared/data``): see :data:`CMU_BVH_TO_BODY25` and
  :func:`hdvr.io.bvh.body25_from_bvh` for derived points.

All converters work on arrays shaped ``(..., J, C)`` for any trailing channel count C (2D pixels with confidence,
or 3D metres): a derived point is the mean of its sources, and is missing (NaN, confidence 0) if any source is.

:data:`EVAL_JOINTS` is the one joint subset that every 3D metric in HDVR uses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hdvr.errors import HDVRError

BODY25_NAMES: tuple[str, ...] = (
    "nose", "neck",
    "right_shoulder", "right_elbow", "right_wrist",
    "left_shoulder", "left_elbow", "left_wrist",
    "mid_hip",
    "right_hip", "right_knee", "right_ankle",
    "left_hip", "left_knee", "left_ankle",
    "right_eye", "left_eye", "right_ear", "left_ear",
    "left_big_toe", "left_small_toe", "left_heel",
    "right_big_toe", "right_small_toe", "right_heel",
)

COCO17_NAMES: tuple[str, ...] = (
    "nose", "left_eye", "right_eye", "left_ear", "right_ear",
    "left_shoulder", "right_shoulder", "left_elbow", "right_elbow",
    "left_wrist", "right_wrist", "left_hip", "right_hip",
    "left_knee", "right_knee", "left_ankle", "right_ankle",
)

H36M17_NAMES: tuple[str, ...] = (
    "pelvis", "right_hip", "right_knee", "right_ankle",
    "left_hip", "left_knee", "left_ankle",
    "spine", "thorax", "neck_nose", "head",
    "left_shoulder", "left_elbow", "left_wrist",
    "right_shoulder", "right_elbow", "right_wrist",
)

#: Bones of BODY_25 as (parent, child) name pairs, for drawing skeletons.
BODY25_BONES: tuple[tuple[str, str], ...] = (
    ("neck", "nose"), ("nose", "right_eye"), ("nose", "left_eye"), ("right_eye", "right_ear"),
    ("left_eye", "left_ear"),
    ("neck", "right_shoulder"), ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"),
    ("neck", "left_shoulder"), ("left_shoulder", "left_elbow"), ("left_elbow", "left_wrist"),
    ("neck", "mid_hip"), ("mid_hip", "right_hip"), ("right_hip", "right_knee"), ("right_knee", "right_ankle"),
    ("mid_hip", "left_hip"), ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
    ("right_ankle", "right_heel"), ("right_ankle", "right_big_toe"), ("right_big_toe", "right_small_toe"),
    ("left_ankle", "left_heel"), ("left_ankle", "left_big_toe"), ("left_big_toe", "left_small_toe"),
)

#: The evaluation subset used by every 3D metric (MPJPE, P-MPJPE, ...): joints that every layout and the
#: mocap define the same way. ``neck`` is the midpoint of the shoulders everywhere, ``mid_hip`` of the hips.
EVAL_JOINTS: tuple[str, ...] = (
    "neck", "mid_hip",
    "right_shoulder", "right_elbow", "right_wrist",
    "left_shoulder", "left_elbow", "left_wrist",
    "right_hip", "right_knee", "right_ankle",
    "left_hip", "left_knee", "left_ankle",
)

#: Root joint for root-relative metrics (MPJPE protocol 1) in BODY_25.
ROOT_JOINT = "mid_hip"


@dataclass(frozen=True)
class Layout:
    """A named keypoint layout: ``names`` in storage order."""

    name: str
    names: tuple[str, ...]

    def index(self, joint: str) -> int:
        try:
            return self.names.index(joint)
        except ValueError:
            raise HDVRError(f"unknown joint name {joint!r} for layout {self.name}") from None

    def indices(self, joints) -> np.ndarray:
        return np.array([self.index(j) for j in joints], dtype=np.int64)


BODY25 = Layout("body25", BODY25_NAMES)
COCO17 = Layout("coco17", COCO17_NAMES)
H36M17 = Layout("h36m17", H36M17_NAMES)
LAYOUTS: dict[str, Layout] = {layout.name: layout for layout in (BODY25, COCO17, H36M17)}

#: For each BODY_25 joint, the COCO-17 joints whose mean gives it (empty: no counterpart).
_BODY25_FROM_COCO17: dict[str, tuple[str, ...]] = {
    **{n: (n,) for n in COCO17_NAMES},
    "neck": ("left_shoulder", "right_shoulder"),
    "mid_hip": ("left_hip", "right_hip"),
}

_H36M17_FROM_BODY25: dict[str, tuple[str, ...]] = {
    "pelvis": ("mid_hip",),
    "right_hip": ("right_hip",), "right_knee": ("right_knee",), "right_ankle": ("right_ankle",),
    "left_hip": ("left_hip",), "left_knee": ("left_knee",), "left_ankle": ("left_ankle",),
    "spine": ("mid_hip", "neck"),
    "thorax": ("neck",),
    "neck_nose": ("nose",),
    "head": ("left_ear", "right_ear"),
    "left_shoulder": ("left_shoulder",), "left_elbow": ("left_elbow",), "left_wrist": ("left_wrist",),
    "right_shoulder": ("right_shoulder",), "right_elbow": ("right_elbow",), "right_wrist": ("right_wrist",),
}

_BODY25_FROM_H36M17: dict[str, tuple[str, ...]] = {
    "mid_hip": ("pelvis",), "neck": ("thorax",), "nose": ("neck_nose",),
    **{n: (n,) for n in H36M17_NAMES if n in BODY25_NAMES},
}


def _mean_of_sources(src: np.ndarray, src_layout: Layout, dst_layout: Layout,
                     recipe: dict[str, tuple[str, ...]], has_confidence: bool) -> np.ndarray:
    """Build ``dst`` (..., J_dst, C) where each joint is the mean of its recipe's source joints."""
    src = np.asarray(src, dtype=np.float64)
    if src.ndim < 2 or src.shape[-2] != len(src_layout.names):
        raise HDVRError(f"expected keypoints shaped (..., {len(src_layout.names)}, C) for layout "
                        f"{src_layout.name}, got {src.shape}")
    out = np.full(src.shape[:-2] + (len(dst_layout.names), src.shape[-1]), np.nan)
    if has_confidence:
        out[..., -1] = 0.0
    for j, name in enumerate(dst_layout.names):
        sources = recipe.get(name, ())
        if not sources:
            continue
        idx = src_layout.indices(sources)
        picked = src[..., idx, :]
        if has_confidence:
            xy = picked[..., :-1].mean(axis=-2)
            conf = picked[..., -1].min(axis=-1)
            missing = np.isnan(xy).any(axis=-1) | (conf <= 0)
            xy[missing] = np.nan
            conf = np.where(missing, 0.0, conf)
            out[..., j, :-1] = xy
            out[..., j, -1] = conf
        else:
            out[..., j, :] = picked.mean(axis=-2)
    return out


def convert(keypoints: np.ndarray, src: str | Layout, dst: str | Layout, has_confidence: bool) -> np.ndarray:
    """Convert keypoints between layouts.

    ``keypoints`` is ``(..., J_src, C)``; if ``has_confidence`` the last channel is a confidence in [0, 1]
    (a derived point takes the minimum of its sources), otherwise all channels are coordinates.
    Joints without a counterpart are NaN (confidence 0).
    """
    src_l = LAYOUTS[src] if isinstance(src, str) else src
    dst_l = LAYOUTS[dst] if isinstance(dst, str) else dst
    if src_l == dst_l:
        return np.asarray(keypoints, dtype=np.float64).copy()
    recipes = {
        ("coco17", "body25"): _BODY25_FROM_COCO17,
        ("body25", "h36m17"): _H36M17_FROM_BODY25,
        ("h36m17", "body25"): _BODY25_FROM_H36M17,
    }
    if (src_l.name, dst_l.name) == ("body25", "coco17"):
        recipe = {n: (n,) for n in COCO17_NAMES}
    elif (src_l.name, dst_l.name) in recipes:
        recipe = recipes[(src_l.name, dst_l.name)]
    elif (src_l.name, dst_l.name) == ("coco17", "h36m17"):
        return convert(convert(keypoints, src_l, BODY25, has_confidence), BODY25, dst_l, has_confidence)
    else:
        raise HDVRError(f"no converter from layout {src_l.name} to {dst_l.name}")
    return _mean_of_sources(keypoints, src_l, dst_l, recipe, has_confidence)


def guess_layout(joint_names) -> Layout:
    """The layout whose names equal ``joint_names`` (in order), else :class:`HDVRError`."""
    names = tuple(str(n) for n in joint_names)
    for layout in LAYOUTS.values():
        if names == layout.names:
            return layout
    unknown = [n for n in names if n not in BODY25_NAMES and n not in COCO17_NAMES and n not in H36M17_NAMES]
    detail = f"unknown joint names {unknown[:5]}" if unknown else "names in an unexpected order"
    raise HDVRError(f"joint names match no known layout (body25, coco17, h36m17): {detail}")


def eval_indices(layout: Layout = BODY25) -> np.ndarray:
    """Indices of :data:`EVAL_JOINTS` in ``layout``."""
    return layout.indices(EVAL_JOINTS)
